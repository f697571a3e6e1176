"""Sweeps as independent runs, executed by Dask distributed (or in this process).

A :class:`RunDescription` is one run: a scene file, ``--set``-style overrides and an output directory.
It is plain data (JSON-ready through :meth:`RunDescription.to_dict`) and holds the same three things as
a run point of the ``cargo xtask`` studies (scene, ``--set`` overrides) plus where its outputs go, so
one list of descriptions can be run

- here, one after the other: :func:`run_local`;
- on Dask distributed: :func:`run_sweep` with a ``Client`` of a ``LocalCluster``, of a scheduler
  address, or of a dask-jobqueue cluster (SLURM, PBS, ...);
- by the command-line runner: :meth:`RunDescription.cli_args` gives the arguments of ``cosserat`` (or
  of ``cargo xtask run``/``measure-run``, which take the same ``RunArgs``).

Every run returns one row (a dict): the description's label, scene and overrides, the run record's
main fields, and the last row of its probes (columns ``probe.<name>``), so that the rows of a sweep form
one table (:func:`to_csv`, or ``pandas.DataFrame(rows)``).
"""

from __future__ import annotations

import csv
import itertools
import json
import os
from dataclasses import dataclass, field
from typing import Any, Iterable, Mapping, Sequence

#: Run-record fields copied into a sweep's rows.
SUMMARY_COLUMNS = (
    "status",
    "reason",
    "n_steps",
    "n_displacement_dofs",
    "n_rotation_dofs",
    "avg_newton_iterations",
    "max_newton_iterations",
    "n_step_reductions",
    "n_intermediate_levels",
    "wall_seconds",
    "avg_step_ms",
    "peak_memory_mb",
)


def _plain(value: Any) -> Any:
    """NumPy scalars and arrays as Python values: their repr (``np.float64(0.5)``) is no TOML."""
    if hasattr(value, "tolist") and not isinstance(value, (str, bytes)):
        return value.tolist()
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    return value


def _override_text(key: str, value: Any) -> str:
    value = _plain(value)
    if isinstance(value, bool):
        return f"{key}={'true' if value else 'false'}"
    if isinstance(value, str):
        return f"{key}={value}"
    return f"{key}={value!r}"


@dataclass(frozen=True)
class RunDescription:
    """One run of a sweep: ``scene`` (a scene file) with ``overrides`` (``"key=value"`` strings, as
    ``cosserat run --set``), writing into ``out_dir``; ``label`` names the run in the table and
    ``threads`` bounds its threads (1 suits one run per core)."""

    scene: str
    out_dir: str
    overrides: tuple[str, ...] = ()
    label: str = ""
    threads: int | None = 1
    params: tuple[tuple[str, Any], ...] = field(default=())

    def __post_init__(self) -> None:
        # Checked here rather than when the run starts: on a Dask worker a bad description would fail
        # its task, and gathering the sweep would raise and lose every other row.
        for name in ("scene", "out_dir", "label"):
            value = getattr(self, name)
            if not isinstance(value, str):
                raise TypeError(f"RunDescription.{name} must be a str (got {type(value).__name__} {value!r})")
        if not isinstance(self.overrides, tuple):
            raise TypeError(f"RunDescription.overrides must be a tuple of \"key=value\" strings "
                            f"(got {type(self.overrides).__name__})")
        for text in self.overrides:
            _check_override_text(text)
        _check_threads(self.threads)

    @staticmethod
    def of(scene: str | os.PathLike, out_dir: str | os.PathLike, overrides: Mapping[str, Any] | Sequence[str] = (),
           label: str = "", threads: int | None = 1) -> "RunDescription":
        """A description from a dict of overrides (``{"mesh.nx": 8}``) or ``"key=value"`` strings
        (``None``: none)."""
        if overrides is None:
            overrides = ()
        if isinstance(overrides, Mapping):
            params = tuple(overrides.items())
            texts = tuple(_override_text(k, v) for k, v in overrides.items())
        elif isinstance(overrides, (str, bytes)) or not isinstance(overrides, Iterable):
            raise TypeError("overrides must be a dict such as {\"mesh.nx\": 8} or a list of \"key=value\" "
                            f"strings (got {type(overrides).__name__} {overrides!r})")
        else:
            texts = tuple(overrides)
            for text in texts:
                _check_override_text(text)
            params = tuple(tuple(t.split("=", 1)) for t in texts)  # type: ignore[misc]
        return RunDescription(os.fspath(scene), os.fspath(out_dir), texts, label, threads, params)

    def cli_args(self) -> list[str]:
        """The arguments of ``cosserat run`` (or ``cargo xtask run``) for this run."""
        args = ["run", self.scene, "--out", self.out_dir]
        for text in self.overrides:
            args += ["--set", text]
        if self.threads is not None:
            args += ["--threads", str(self.threads)]
        return args

    def to_dict(self) -> dict:
        """The description as JSON-ready data (``scene``, ``overrides``, ``out_dir``, ...)."""
        return {
            "scene": self.scene,
            "out_dir": self.out_dir,
            "overrides": list(self.overrides),
            "label": self.label,
            "threads": self.threads,
        }

    @staticmethod
    def from_dict(data: Mapping[str, Any]) -> "RunDescription":
        """The inverse of :meth:`to_dict`."""
        if not isinstance(data, Mapping):
            raise TypeError(f"a run description must be a dict (got {type(data).__name__} {data!r})")
        missing = [key for key in ("scene", "out_dir") if key not in data]
        if missing:
            raise ValueError(f"a run description needs `scene` and `out_dir`; {data!r} lacks "
                             + " and ".join(f"`{key}`" for key in missing))
        return RunDescription.of(data["scene"], data["out_dir"], list(data.get("overrides", ())),
                                 data.get("label", ""), data.get("threads", 1))

    def run(self) -> dict:
        """Runs the scene (in this process) and returns its row; a scene that cannot be loaded or
        built gives a row with status ``"error"`` and the reason, so that one bad point does not end a
        sweep."""
        from ._cosserat import SceneError, Simulation, SimulationError

        row: dict[str, Any] = {"label": self.label, "scene": self.scene, "out_dir": self.out_dir}
        row.update({f"set.{k}": v for k, v in self.params})
        try:
            sim = Simulation.load(self.scene, overrides=list(self.overrides))
            summary = sim.run(self.out_dir, threads=self.threads)
        except (SceneError, SimulationError) as e:
            row.update({"status": "error", "reason": str(e)})
            return row
        for name in SUMMARY_COLUMNS:
            row[name] = getattr(summary, name)
        row.update(last_probes(os.path.join(self.out_dir, "probes.csv")))
        return row


#: The most threads of one run, as ``Simulation.run`` takes them.
MAX_THREADS = 1024


def _check_override_text(text: Any) -> None:
    if not isinstance(text, str):
        raise TypeError(f"an override must be a \"key=value\" string (got {type(text).__name__} {text!r})")
    key, sep, _ = text.partition("=")
    if not sep or not key.strip():
        raise ValueError(f"override `{text}` is not of the form \"key=value\"")


def _check_threads(threads: Any) -> None:
    if threads is None:
        return
    if isinstance(threads, bool) or not isinstance(threads, int):
        raise TypeError(f"RunDescription.threads must be an int or None (got {type(threads).__name__} {threads!r})")
    if not 1 <= threads <= MAX_THREADS:
        raise ValueError(f"RunDescription.threads must be from 1 to {MAX_THREADS}, or None for all cores "
                         f"(got {threads})")


def last_probes(path: str) -> dict[str, float]:
    """The last row of a run's ``probes.csv`` as ``{"probe.<column>": value}`` (empty if missing)."""
    try:
        with open(path, newline="") as f:
            rows = list(csv.reader(f))
    except OSError:
        return {}
    if len(rows) < 2:
        return {}
    return {f"probe.{name}": float(value) for name, value in zip(rows[0], rows[-1])}


def grid(scene: str | os.PathLike, out_root: str | os.PathLike, threads: int | None = 1,
         **axes: Iterable[Any]) -> list[RunDescription]:
    """The cartesian product of override values as run descriptions, e.g.
    ``grid("scenes/plate.toml", "out/sweep", **{"material.youngs_modulus": [1e6, 1e7], "mesh.nx": [4, 8]})``;
    each run writes into ``out_root/<label>`` with a label made of its values (path separators in them
    become ``_``). Every axis is a non-empty list; a value repeated on an axis raises ``ValueError``, since
    its runs would share a directory."""
    keys = list(axes)
    values_of = [_axis_values(k, axes[k]) for k in keys]
    runs = []
    for values in itertools.product(*values_of):
        overrides = dict(zip(keys, values))
        label = "_".join(f"{k.split('.')[-1]}={_label_text(v)}" for k, v in overrides.items()) or "run"
        runs.append(RunDescription.of(scene, os.path.join(os.fspath(out_root), label), overrides, label, threads))
    check_distinct_out_dirs(runs)
    return runs


def _axis_values(key: str, values: Any) -> list:
    """The values of one axis of a grid: a string would be read as its characters, and an empty axis
    would make an empty sweep."""
    if isinstance(values, (str, bytes)) or not isinstance(values, Iterable):
        raise TypeError(f"grid axis `{key}` must be a list of values (got {type(values).__name__} {values!r})")
    values = list(values)
    if not values:
        raise ValueError(f"grid axis `{key}` has no values")
    return values


def _label_text(value: Any) -> str:
    """A value as part of a label, which names a folder: path separators would nest it elsewhere."""
    text = str(_plain(value))
    for sep in {"/", "\\", os.sep, os.altsep or "/"}:
        text = text.replace(sep, "_")
    return text


def check_distinct_out_dirs(runs: Sequence[RunDescription]) -> None:
    """Raises ``ValueError`` if two runs write into the same directory: the later run's outputs would
    replace the earlier's, and one result would be lost."""
    first: dict[str, int] = {}
    for i, run in enumerate(runs):
        key = os.path.normpath(os.path.abspath(run.out_dir))
        if key in first:
            raise ValueError(
                f"runs {first[key]} and {i} both write into `{run.out_dir}`; give each run its own out_dir "
                "(in a grid: each axis value once)"
            )
        first[key] = i


def _run_one(description: RunDescription) -> dict:
    return description.run()


def run_local(runs: Sequence[RunDescription]) -> list[dict]:
    """Runs the descriptions one after the other in this process; returns their rows in order. Two
    runs with the same ``out_dir`` raise ``ValueError`` before any runs."""
    check_distinct_out_dirs(runs)
    return [d.run() for d in runs]


def run_sweep(runs: Sequence[RunDescription], client: Any = None) -> list[dict]:
    """Runs the descriptions as independent tasks on Dask distributed and gathers their rows, in the
    order of ``runs``.

    ``client`` is a ``distributed.Client`` (of a ``LocalCluster``, a scheduler address or a
    dask-jobqueue cluster); ``None`` uses the current default client. Every worker needs this package
    installed; the scene files and output directories must be on paths the workers share. Two runs with
    the same ``out_dir`` raise ``ValueError`` before any runs.
    """
    check_distinct_out_dirs(runs)
    if client is None:
        from distributed import default_client

        client = default_client()
    # pure=False: a rerun of the same description is a new run, not a cached result.
    futures = client.map(_run_one, list(runs), pure=False, key=[f"cosserat-run-{i}-{d.label}" for i, d in enumerate(runs)])
    return client.gather(futures)


def to_csv(rows: Sequence[Mapping[str, Any]], path: str | os.PathLike) -> None:
    """Writes the rows of a sweep as one CSV table (the union of their columns, in first-seen order)."""
    columns: list[str] = []
    for row in rows:
        columns += [c for c in row if c not in columns]
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=columns)
        writer.writeheader()
        writer.writerows(rows)


def save_descriptions(runs: Sequence[RunDescription], path: str | os.PathLike) -> None:
    """Writes the descriptions as a JSON list (for another process or the command-line runner)."""
    with open(path, "w") as f:
        json.dump([d.to_dict() for d in runs], f, indent=2)


def load_descriptions(path: str | os.PathLike) -> list[RunDescription]:
    """Reads descriptions written by :func:`save_descriptions`."""
    with open(path) as f:
        data = json.load(f)
    if not isinstance(data, list):
        raise ValueError(f"{os.fspath(path)}: expected a JSON list of run descriptions (got {type(data).__name__})")
    return [RunDescription.from_dict(d) for d in data]
