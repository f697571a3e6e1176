"""Outputs from Python are the command-line runner's: the same files, and arrays bit-identical to the
VTU frames it writes."""

import subprocess

import numpy as np
import pytest

import cosserat
from conftest import STRIP, cli_binary, read_vtu_independently


@pytest.fixture(scope="module")
def cli_run(tmp_path_factory):
    binary = cli_binary()
    if binary is None:
        pytest.skip("no `cosserat` binary (build it, or set COSSERAT_BIN)")
    out = tmp_path_factory.mktemp("cli") / "strip"
    args = [binary, "run", str(STRIP), "--out", str(out), "--quiet"]
    for key, value in {"mesh.nx": 8, "mesh.ny": 2, "time.end": 0.05}.items():
        args += ["--set", f"{key}={value}"]
    subprocess.run(args, check=True)
    return out


def test_run_writes_the_files_of_the_cli(cli_run, tmp_path, strip_overrides):
    sim = cosserat.Simulation.load(STRIP, overrides=strip_overrides)
    summary = sim.run(tmp_path / "py")
    assert summary.status == "ok" and summary.n_steps == 5
    cli_files = sorted(p.relative_to(cli_run) for p in cli_run.rglob("*") if p.is_file())
    py_files = sorted(p.relative_to(tmp_path / "py") for p in (tmp_path / "py").rglob("*") if p.is_file())
    assert cli_files == py_files
    assert any(p.suffix == ".vtu" for p in cli_files)
    for rel in cli_files:
        if rel.name == "summary.json":
            continue  # holds wall-clock times and memory
        assert (cli_run / rel).read_bytes() == (tmp_path / "py" / rel).read_bytes(), rel
    import json

    cli_summary = json.loads((cli_run / "summary.json").read_text())
    assert summary.to_dict()["n_steps"] == cli_summary["n_steps"]
    assert summary.to_dict()["hessian_nnz"] == cli_summary["hessian_nnz"]


def test_stepped_arrays_equal_the_cli_frames_bit_for_bit(cli_run, strip_overrides):
    frames = {}
    for path in (cli_run / "frames").glob("*.vtu"):
        time, points, triangles, data = read_vtu_independently(path)
        frames[time] = (points, triangles, data)
    sim = cosserat.Simulation.load(STRIP, overrides=strip_overrides)
    compared = 0
    while True:
        frame = sim.frame()
        assert frame.time == sim.time
        if sim.time in frames:
            points, triangles, data = frames[sim.time]
            assert np.array_equal(frame.points, points)
            assert np.array_equal(frame.triangles, triangles)
            assert set(frame.point_data) == set(data)
            for name, values in data.items():
                assert np.array_equal(frame.point_data[name], values), name
            compared += 1
        if sim.time >= 0.05 - 0.005:
            break
        sim.step()
    assert compared == len(frames) >= 2
    # The package's own reader gives the same arrays.
    last = max(frames)
    path = next(p for p in (cli_run / "frames").glob("*.vtu") if read_vtu_independently(p)[0] == last)
    read = cosserat.read_vtu(path)
    assert np.array_equal(read.points, frames[last][0])
    assert np.array_equal(read.point_data["director3"], frames[last][2]["director3"])
