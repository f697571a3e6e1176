"""Shared helpers of the Python tests: the repository's scenes, the command-line binary, and a VTU
reader written here from the file format (base64 blocks with a UInt64 byte count), independent of the
package's own reader."""

import base64
import os
import shutil
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[3]
SCENES = REPO / "scenes"

#: A short, coarse twisting strip: 5 steps of 10 ms on 8 × 2 quads.
STRIP = SCENES / "twisting_strip.toml"
STRIP_OVERRIDES = {"mesh.nx": 8, "mesh.ny": 2, "time.end": 0.05}


@pytest.fixture
def strip_overrides():
    return dict(STRIP_OVERRIDES)


def cli_binary():
    """The `cosserat` binary: $COSSERAT_BIN (CI sets it, and then it must exist), else the release or
    debug build of this clone, else one on PATH."""
    given = os.environ.get("COSSERAT_BIN")
    if given:
        assert Path(given).is_file(), f"COSSERAT_BIN={given} does not exist"
        return given
    target = Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    for profile in ("release", "debug"):
        candidate = target / profile / "cosserat"
        if candidate.is_file():
            return str(candidate)
    return shutil.which("cosserat")


def _decode(text, dtype):
    raw = base64.b64decode(text.strip())
    n = int(np.frombuffer(raw[:8], dtype="<u8")[0])
    assert n == len(raw) - 8
    return np.frombuffer(raw[8:], dtype=dtype)


def read_vtu_independently(path):
    """time, points, triangles, {name: (n, k) array} of a binary VTU file."""
    root = ET.parse(path).getroot()
    time = float(_decode(root.find("UnstructuredGrid/FieldData/DataArray").text, "<f8")[0])
    piece = root.find("UnstructuredGrid/Piece")
    n_points = int(piece.get("NumberOfPoints"))
    points = _decode(piece.find("Points/DataArray").text, "<f8").reshape(n_points, 3)
    cells = {a.get("Name"): a for a in piece.find("Cells")}
    triangles = _decode(cells["connectivity"].text, "<i8").reshape(-1, 3)
    data = {}
    for array in piece.find("PointData"):
        k = int(array.get("NumberOfComponents"))
        data[array.get("Name")] = _decode(array.text, "<f8").reshape(n_points, k)
    return time, points, triangles, data
