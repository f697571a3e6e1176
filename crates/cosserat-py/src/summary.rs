//! The run record as a Python object with typed attributes.

use cosserat::io::{RunStatus, RunSummary};
use pyo3::prelude::*;

/// The record of a run (also written as `summary.json`): how it ended, its size, its cost.
#[pyclass(name = "RunSummary", module = "cosserat", frozen)]
pub struct PyRunSummary {
    pub(crate) inner: RunSummary,
}

#[pymethods]
impl PyRunSummary {
    /// The scene name.
    #[getter]
    fn scene(&self) -> &str {
        &self.inner.scene
    }
    /// `"ok"`, `"interrupted"` or `"error"`.
    #[getter]
    fn status(&self) -> &'static str {
        match self.inner.status {
            RunStatus::Ok => "ok",
            RunStatus::Interrupted => "interrupted",
            RunStatus::Error => "error",
        }
    }
    /// Why the run stopped early, or `None`.
    #[getter]
    fn reason(&self) -> Option<&str> {
        self.inner.reason.as_deref()
    }
    /// The time (or load factor) where the run stopped early, or `None`.
    #[getter]
    fn stopped_at(&self) -> Option<f64> {
        self.inner.stopped_at
    }
    /// Completed steps (or load levels).
    #[getter]
    fn n_steps(&self) -> usize {
        self.inner.n_steps
    }
    /// Frames written.
    #[getter]
    fn n_frames(&self) -> usize {
        self.inner.n_frames
    }
    /// Displacement degrees of freedom.
    #[getter]
    fn n_displacement_dofs(&self) -> usize {
        self.inner.n_displacement_dofs
    }
    /// Rotation degrees of freedom.
    #[getter]
    fn n_rotation_dofs(&self) -> usize {
        self.inner.n_rotation_dofs
    }
    /// Displacement element, e.g. ``"tri6"``.
    #[getter]
    fn displacement_element(&self) -> String {
        self.inner.displacement_element.clone()
    }
    /// Rotation element, e.g. ``"tri6"`` (``"-"`` for a model without rotations).
    #[getter]
    fn rotation_element(&self) -> String {
        self.inner.rotation_element.clone()
    }
    /// Strain interpolation of the Cosserat shells, e.g. ``"regge_stabilized"`` (``"-"`` without one).
    #[getter]
    fn strain_interpolation(&self) -> String {
        self.inner.strain_interpolation.clone()
    }
    /// Quadrature points per element of the Cosserat shells, e.g. ``"3"`` (``"-"`` without them).
    #[getter]
    fn quadrature_points(&self) -> String {
        self.inner.quadrature_points.clone()
    }
    /// The energy terms of the potential.
    #[getter]
    fn active_terms(&self) -> Vec<String> {
        self.inner.active_terms.clone()
    }
    /// Time step \[s\].
    #[getter]
    fn dt(&self) -> f64 {
        self.inner.dt
    }
    /// Mean Newton iterations per step.
    #[getter]
    fn avg_newton_iterations(&self) -> f64 {
        self.inner.avg_newton_iterations
    }
    /// Most Newton iterations of a step.
    #[getter]
    fn max_newton_iterations(&self) -> usize {
        self.inner.max_newton_iterations
    }
    /// Time-step reductions (retries with a smaller step).
    #[getter]
    fn n_step_reductions(&self) -> usize {
        self.inner.n_step_reductions
    }
    /// Intermediate load levels of a quasi-static run (solved, not written).
    #[getter]
    fn n_intermediate_levels(&self) -> usize {
        self.inner.n_intermediate_levels
    }
    /// Wall-clock time of the run \[s\].
    #[getter]
    fn wall_seconds(&self) -> f64 {
        self.inner.wall_seconds
    }
    /// Mean wall-clock time per step \[ms\].
    #[getter]
    fn avg_step_ms(&self) -> f64 {
        self.inner.avg_step_ms
    }
    /// Peak resident memory of the process \[MB\], where the system tells.
    #[getter]
    fn peak_memory_mb(&self) -> Option<f64> {
        self.inner.peak_memory_mb
    }
    /// Warnings about the scene and the run.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.inner.warnings.clone()
    }

    /// The whole record as `summary.json` holds it (a dict).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let text = serde_json::to_string(&self.inner)
            .map_err(|e| pyo3::exceptions::PyValueError::new_err(format!("the summary as JSON: {e}")))?;
        py.import("json")?.call_method1("loads", (text,))
    }

    fn __repr__(&self) -> String {
        format!(
            "RunSummary(scene={:?}, status={:?}, n_steps={}, avg_newton_iterations={:.2}, wall_seconds={:.3})",
            self.inner.scene,
            self.status(),
            self.inner.n_steps,
            self.inner.avg_newton_iterations,
            self.inner.wall_seconds
        )
    }
}
