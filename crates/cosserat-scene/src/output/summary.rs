//! `summary.json`: what a run was, how long it took and how it ended.
//!
//! [`RunSummary`] mirrors the output contract field by field; the JSON keys are the field names. Element
//! types and energy terms are plain strings here because this file is a report, not an input: the
//! simulator converts its typed choices into names when it fills the summary. Every number is checked
//! before writing, since serde_json would silently write NaN or infinity as `null`.

use std::collections::BTreeMap;
use std::path::Path;

use serde::{Deserialize, Serialize};

use super::OutputError;
use super::atomic::write_atomic;

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RunStatus {
    /// The run reached its end time (`"ok"`).
    Ok,
    /// The run stopped on an error, e.g. a Newton failure at the smallest time step (`"error"`).
    Error,
    /// The run was stopped from outside before its end time (`"interrupted"`).
    Interrupted,
}

/// Axis-aligned bounding box.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BoundingBox {
    /// Componentwise minimum (length units of the scene).
    pub min: [f64; 3],
    /// Componentwise maximum (length units of the scene).
    pub max: [f64; 3],
}

impl BoundingBox {
    /// The bounding box of `points`, `None` if there are none.
    pub fn of_points(points: &[[f64; 3]]) -> Option<Self> {
        let first = *points.first()?;
        Some(points.iter().fold(Self { min: first, max: first }, |mut bbox, p| {
            for k in 0..3 {
                bbox.min[k] = bbox.min[k].min(p[k]);
                bbox.max[k] = bbox.max[k].max(p[k]);
            }
            bbox
        }))
    }
}

/// The step (or load level) a run failed at, with every attempt made.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FailedStep {
    /// Time (or load factor) at the start of the step.
    pub t: f64,
    /// The attempts in order; each after the first halved the time step (or bisected the load step).
    pub attempts: Vec<Attempt>,
    /// Why the step ended without an equilibrium.
    pub reason: String,
}

/// One attempt of a failed step.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Attempt {
    /// Time step of the attempt (load increment for a load level).
    pub dt: f64,
    /// Why Newton failed.
    pub reason: String,
    /// Newton's residual after each iteration (finite values only).
    pub residuals: Vec<f64>,
}

/// Whether the residual tolerance was relative to the load scale or absolute.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ToleranceMode {
    /// A fraction of the step's load scale (its largest external load, reaction or first residual),
    /// never below the residual's round-off floor (`"relative"`).
    Relative,
    /// A residual in force and torque units (`"absolute"`).
    Absolute,
}

/// How the run's Newton solves met their tolerance.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ConvergenceSummary {
    /// Relative or absolute.
    pub tolerance_mode: ToleranceMode,
    /// The scene's tolerance: a fraction of the load scale, or a residual in force (and torque)
    /// units.
    pub tolerance: f64,
    /// The largest residual bound a step used, in force (and torque) units: the absolute tolerance,
    /// or the relative one times the step's load scale, or the round-off floor where that is higher.
    pub max_step_tolerance: f64,
    /// The largest final residual of a step, in force (and torque) units.
    pub max_residual: f64,
    /// The largest final residual of a step over its load scale (steps without any load, reaction or
    /// first residual have none and are left out).
    pub max_relative_residual: f64,
    /// Steps accepted although their residual stayed above the tolerance, because it had stopped
    /// decreasing at the round-off floor with a Newton step below the energy's round-off (a warning).
    pub stagnated_steps: usize,
    /// Newton iterations whose Hessian was not positive definite and was shifted.
    pub shifted_iterations: usize,
}

/// Contents of `DIR/summary.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunSummary {
    /// Name of the scene.
    pub scene: String,
    /// Displacement element type, e.g. `"tri6"`.
    pub displacement_element: String,
    /// Rotation element type, e.g. `"tri3"`.
    pub rotation_element: String,
    /// Number of cells (elements) of the mesh.
    pub n_cells: usize,
    /// Number of displacement degrees of freedom.
    pub n_displacement_dofs: usize,
    /// Number of rotation degrees of freedom.
    pub n_rotation_dofs: usize,
    /// Names of the energy terms of the incremental potential that were active.
    pub active_terms: Vec<String>,
    /// Time step size requested by the scene (time units).
    pub dt: f64,
    /// Number of completed time steps.
    pub n_steps: usize,
    /// Average number of Newton iterations per completed step.
    pub avg_newton_iterations: f64,
    /// Total wall-clock time of the run (s).
    pub wall_seconds: f64,
    /// Average wall-clock time per completed step (ms).
    pub avg_step_ms: f64,
    /// Fraction of the time in steps spent in assembly (0 to 1).
    pub assembly_share: f64,
    /// Fraction of the time in steps spent in linear solves (0 to 1).
    pub linear_solve_share: f64,
    /// Number of time step reductions (dt halvings) after failed steps.
    pub n_step_reductions: usize,
    /// Bounding box of the rest configuration.
    pub rest_bbox: BoundingBox,
    /// How the run ended.
    pub status: RunStatus,
    /// Why the run did not end with `ok` (`null` when it did).
    pub reason: Option<String>,
    /// Simulation time at which the run stopped (`null` if it stopped before the first step).
    pub stopped_at: Option<f64>,
    /// The step that failed, with every attempt (`null` unless a step failed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub failed_step: Option<FailedStep>,
    /// How the Newton solves converged (`null` if no step finished).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub convergence: Option<ConvergenceSummary>,
    /// Experiment-specific numbers, e.g. a measured tip deflection.
    pub extra: BTreeMap<String, serde_json::Value>,
}

impl RunSummary {
    /// The summary of a run that failed before it could report anything else (for instance a scene
    /// that did not validate): counts, times and the bounding box are zero, the element types and the
    /// term list are empty.
    pub fn failed(scene: impl Into<String>, status: RunStatus, reason: impl Into<String>) -> Self {
        Self {
            scene: scene.into(),
            displacement_element: String::new(),
            rotation_element: String::new(),
            n_cells: 0,
            n_displacement_dofs: 0,
            n_rotation_dofs: 0,
            active_terms: Vec::new(),
            dt: 0.0,
            n_steps: 0,
            avg_newton_iterations: 0.0,
            wall_seconds: 0.0,
            avg_step_ms: 0.0,
            assembly_share: 0.0,
            linear_solve_share: 0.0,
            n_step_reductions: 0,
            rest_bbox: BoundingBox {
                min: [0.0; 3],
                max: [0.0; 3],
            },
            status,
            reason: Some(reason.into()),
            stopped_at: None,
            failed_step: None,
            convergence: None,
            extra: BTreeMap::new(),
        }
    }

    /// Checks that every number is finite.
    ///
    /// Values in `extra` need no check: a `serde_json::Value` cannot hold NaN or infinity.
    ///
    /// # Errors
    /// [`OutputError::NonFiniteSummary`] naming the first non-finite field.
    pub fn validate(&self) -> Result<(), OutputError> {
        let scalars = [
            ("dt", self.dt),
            ("avg_newton_iterations", self.avg_newton_iterations),
            ("wall_seconds", self.wall_seconds),
            ("avg_step_ms", self.avg_step_ms),
            ("assembly_share", self.assembly_share),
            ("linear_solve_share", self.linear_solve_share),
        ];
        for (field, value) in scalars {
            if !value.is_finite() {
                return Err(OutputError::NonFiniteSummary {
                    field: field.to_owned(),
                    value,
                });
            }
        }
        for (corner, values) in [("min", self.rest_bbox.min), ("max", self.rest_bbox.max)] {
            if let Some(k) = values.iter().position(|v| !v.is_finite()) {
                return Err(OutputError::NonFiniteSummary {
                    field: format!("rest_bbox.{corner}[{k}]"),
                    value: values[k],
                });
            }
        }
        if let Some(c) = &self.convergence {
            let values = [
                ("convergence.tolerance", c.tolerance),
                ("convergence.max_step_tolerance", c.max_step_tolerance),
                ("convergence.max_residual", c.max_residual),
                ("convergence.max_relative_residual", c.max_relative_residual),
            ];
            if let Some((field, value)) = values.into_iter().find(|(_, v)| !v.is_finite()) {
                return Err(OutputError::NonFiniteSummary {
                    field: field.to_owned(),
                    value,
                });
            }
        }
        if let Some(value) = self.stopped_at.filter(|v| !v.is_finite()) {
            return Err(OutputError::NonFiniteSummary {
                field: "stopped_at".to_owned(),
                value,
            });
        }
        if let Some(step) = &self.failed_step {
            let attempts = step.attempts.iter().enumerate();
            let numbers = std::iter::once(("failed_step.t".to_owned(), step.t)).chain(attempts.flat_map(|(k, a)| {
                let residuals = a.residuals.iter().enumerate();
                std::iter::once((format!("failed_step.attempts[{k}].dt"), a.dt))
                    .chain(residuals.map(move |(i, r)| (format!("failed_step.attempts[{k}].residuals[{i}]"), *r)))
            }));
            for (field, value) in numbers {
                if !value.is_finite() {
                    return Err(OutputError::NonFiniteSummary { field, value });
                }
            }
        }
        Ok(())
    }

    /// The pretty-printed JSON text; `path` is only used in error messages.
    ///
    /// # Errors
    /// The errors of [`RunSummary::validate`], or [`OutputError::Json`].
    pub fn to_json_string(&self, path: &Path) -> Result<String, OutputError> {
        self.validate()?;
        let mut json = serde_json::to_string_pretty(self).map_err(|source| OutputError::Json {
            path: path.to_path_buf(),
            source,
        })?;
        json.push('\n');
        Ok(json)
    }
}

/// Validates `summary` and writes it to `path` atomically as pretty-printed JSON.
///
/// # Errors
/// As [`RunSummary::to_json_string`] (then nothing is written), plus the errors of
/// [`super::atomic::write_atomic`].
pub fn write_summary(path: &Path, summary: &RunSummary) -> Result<(), OutputError> {
    let json = summary.to_json_string(path)?;
    write_atomic(path, json.as_bytes())
}

/// Reads a `summary.json` file.
///
/// # Errors
/// [`OutputError::Io`] if the file cannot be read, [`OutputError::Json`] if it does not hold a summary.
pub fn read_summary(path: &Path) -> Result<RunSummary, OutputError> {
    let text = std::fs::read_to_string(path).map_err(|source| OutputError::Io {
        operation: "read",
        path: path.to_path_buf(),
        source,
    })?;
    serde_json::from_str(&text).map_err(|source| OutputError::Json {
        path: path.to_path_buf(),
        source,
    })
}
