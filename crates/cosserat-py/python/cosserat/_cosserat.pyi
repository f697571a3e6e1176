"""Type stubs of the extension module (re-exported by ``cosserat``)."""

import os
from typing import Any, Callable, Literal, Mapping, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

__version__: str

_Path = Union[str, os.PathLike[str]]
_Overrides = Union[Mapping[str, Any], Sequence[str], None]
_Vec3 = Sequence[float]

class SceneError(ValueError):
    """A scene that cannot be loaded."""

    file: Optional[str]
    """The scene file, or ``None`` for a dict or an override."""
    line: Optional[int]
    """The 1-based line in ``file``, or ``None``."""
    field: Optional[str]
    """The dotted field path (``time.dt``, ``boundary.0.position.stiffness``), or ``None``."""
    override: Optional[str]
    """The ``key=value`` override at fault, or ``None``."""
    reason: str
    """Why the value is rejected."""

class SimulationError(RuntimeError):
    """A scene that cannot be simulated, a target that cannot be set, an output that cannot be written."""

class StepFailed(RuntimeError):
    """A step failed after every allowed reduction; the state is that of the last completed step."""

class StepInfo:
    """What a step (or load level) reports."""

    step: int
    t: float
    end: float
    dt: float
    newton_iterations: int
    residual: float

class RunSummary:
    """The run record (``summary.json``) with typed attributes."""

    @property
    def scene(self) -> str: ...
    @property
    def status(self) -> Literal["ok", "interrupted", "error"]: ...
    @property
    def reason(self) -> Optional[str]: ...
    @property
    def stopped_at(self) -> Optional[float]: ...
    @property
    def n_steps(self) -> int: ...
    @property
    def n_frames(self) -> int: ...
    @property
    def n_displacement_dofs(self) -> int: ...
    @property
    def n_rotation_dofs(self) -> int: ...
    @property
    def displacement_element(self) -> str: ...
    @property
    def rotation_element(self) -> str: ...
    @property
    def strain_interpolation(self) -> str: ...
    @property
    def quadrature_points(self) -> str: ...
    @property
    def active_terms(self) -> list[str]: ...
    @property
    def dt(self) -> float: ...
    @property
    def avg_newton_iterations(self) -> float: ...
    @property
    def max_newton_iterations(self) -> int: ...
    @property
    def n_step_reductions(self) -> int: ...
    @property
    def n_intermediate_levels(self) -> int: ...
    @property
    def wall_seconds(self) -> float: ...
    @property
    def avg_step_ms(self) -> float: ...
    @property
    def peak_memory_mb(self) -> Optional[float]: ...
    @property
    def warnings(self) -> list[str]: ...
    def to_dict(self) -> dict[str, Any]:
        """The whole record as ``summary.json`` holds it."""

class Frame:
    """A triangle surface with point and cell data, as in one ``.vtu`` file of a run."""

    @property
    def time(self) -> float: ...
    @property
    def points(self) -> npt.NDArray[np.float64]:
        """(n, 3)"""
    @property
    def triangles(self) -> npt.NDArray[np.int64]:
        """(m, 3)"""
    @property
    def point_data(self) -> dict[str, npt.NDArray[np.float64]]:
        """``displacement``, ``velocity``, ``director1``..``director3``, ``angular_velocity``: (n, k)."""
    @property
    def cell_data(self) -> dict[str, npt.NDArray[np.float64]]: ...

def read_vtu(path: _Path) -> Frame:
    """Reads a ``.vtu`` file written by a run. Raises the ``OSError`` of the cause
    (``FileNotFoundError``, ``PermissionError``, …) when the file cannot be read, ``ValueError`` when it
    holds no frame."""

class Simulation:
    """A scene ready to run."""

    @staticmethod
    def load(path: _Path, overrides: _Overrides = None) -> "Simulation":
        """Loads a scene file; ``overrides`` like ``cosserat run --set`` (a dict or ``"key=value"``
        strings). Raises ``SceneError`` or ``SimulationError``."""
    @staticmethod
    def from_dict(scene: Mapping[str, Any], base_dir: _Path = ".", overrides: _Overrides = None) -> "Simulation":
        """Builds a scene from a dict of the scene file's structure."""
    @property
    def name(self) -> str: ...
    @property
    def end(self) -> float:
        """The scene's end time (or final load factor)."""
    @property
    def time(self) -> float:
        """The time (or load factor) of the last completed step."""
    @property
    def advice(self) -> list[str]:
        """Warnings about the scene's settings and inputs."""
    @property
    def boundary_names(self) -> list[str]: ...
    @property
    def load_names(self) -> list[str]: ...
    def step(self, threads: Optional[int] = None) -> StepInfo:
        """One time step (dynamic scenes), with the GIL released, on ``threads`` threads (1 to 1024,
        default ``None``: all cores; results do not depend on it). Raises ``StepFailed``."""
    def run_until(self, t: float, threads: Optional[int] = None) -> int:
        """Steps until the time reaches ``t`` (finite, at most ``end``); returns the number of steps,
        0 if the time is there already."""
    def run(
        self,
        out_dir: _Path,
        on_step: Optional[Callable[[StepInfo], Optional[bool]]] = None,
        threads: Optional[int] = None,
    ) -> RunSummary:
        """Runs to the end writing the same files as ``cosserat run --out out_dir``. ``on_step`` may
        set targets; returning ``False`` stops the run. Ctrl-C stops it after the current step and raises
        ``KeyboardInterrupt`` once ``summary.json`` is written. An ``out_dir`` that cannot be created
        raises ``SimulationError`` and leaves the simulation ready to run again."""
    def set_motion(
        self,
        name: str,
        *,
        angle: Optional[float] = None,
        axis: Optional[_Vec3] = None,
        center: _Vec3 = (0.0, 0.0, 0.0),
        translation: _Vec3 = (0.0, 0.0, 0.0),
        rotation: Optional[Sequence[Sequence[float]]] = None,
    ) -> None:
        """Prescribes boundary ``name``'s motion from the next step on: nodes to
        ``R (X - center) + center + translation``, rotations to ``R`` (``rotation``, or ``angle``, default
        0, about ``axis``, default z; not both). Raises ``RuntimeError`` after a run."""
    def reset_motion(self, name: str) -> None:
        """Gives boundary ``name`` back its scene motion. Raises ``RuntimeError`` after a run."""
    def set_load_scale(self, name: str, scale: Optional[float]) -> None:
        """Sets load ``name``'s scale from the next step on (``None``: the scene's). Raises
        ``RuntimeError`` after a run."""
    @property
    def positions(self) -> npt.NDArray[np.float64]:
        """(n, 3) read-only view of the displacement nodes' positions [m]."""
    @property
    def velocities(self) -> npt.NDArray[np.float64]:
        """(n, 3) read-only view [m/s]."""
    @property
    def rest_positions(self) -> npt.NDArray[np.float64]:
        """(n, 3) read-only view [m]."""
    @property
    def displacements(self) -> npt.NDArray[np.float64]:
        """(n, 3) new array ``positions - rest_positions`` [m]."""
    @property
    def quaternions(self) -> npt.NDArray[np.float64]:
        """(n_rot, 4) read-only view, order x, y, z, w."""
    @property
    def directors(self) -> npt.NDArray[np.float64]:
        """(3, n_rot, 3) new array: ``d1, d2, d3 = sim.directors``."""
    @property
    def angular_velocities(self) -> npt.NDArray[np.float64]:
        """(n_rot, 3) read-only view [rad/s]."""
    @property
    def shells(self) -> list[dict[str, Any]]:
        """Per shell: ``name``, ``displacement_nodes``, ``rotation_nodes``, ``displacement_elements``,
        ``rotation_elements`` (shell numbering)."""
    def frame(self) -> Frame:
        """The output frame of the current state, as ``run`` writes it."""
