"""Three-director Cosserat shell simulation from Python.

Load a scene (a TOML file or a dict of the same structure), step it or run it, and read its state as
NumPy arrays::

    import cosserat

    sim = cosserat.Simulation.load("scenes/twisting_strip.toml", overrides={"time.end": 0.1})
    sim.run_until(0.05)
    x = sim.positions            # (n, 3) read-only view, follows the steps
    summary = sim.run("out/strip")  # on a fresh simulation: the same files as `cosserat run`

Sweeps of independent runs (:class:`RunDescription`) go to Dask distributed with
:func:`cosserat.sweep.run_sweep`.
"""

from ._cosserat import (
    Frame,
    RunSummary,
    SceneError,
    Simulation,
    SimulationError,
    StepFailed,
    StepInfo,
    __version__,
    read_vtu,
)
from .sweep import RunDescription, grid

__all__ = [
    "Frame",
    "RunDescription",
    "RunSummary",
    "SceneError",
    "Simulation",
    "SimulationError",
    "StepFailed",
    "StepInfo",
    "__version__",
    "grid",
    "read_vtu",
]
