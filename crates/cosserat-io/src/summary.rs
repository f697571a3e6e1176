//! `summary.json`: the typed record of a run — what it was, how long it took, how it ended.
//!
//! [`RunSummary`] mirrors the output contract field by field; the JSON keys are the field names, and
//! sections that only some runs have (contact, a failed step, a factorisation) are `null` or absent
//! otherwise. Element types, energy terms and laws are plain strings here because this file is a
//! report, not an input: the simulator converts its typed choices into names when it fills the
//! record. Every number is checked before writing, since serde_json would silently write NaN or
//! infinity as `null`.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::OutputError;
use crate::atomic::write_atomic;

/// How a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum RunStatus {
    /// The run reached its end time (`"ok"`).
    #[default]
    Ok,
    /// The run stopped on an error, e.g. a Newton failure at the smallest time step (`"error"`).
    Error,
    /// The run was stopped from outside before its end time (`"interrupted"`).
    Interrupted,
}

/// Axis-aligned bounding box.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
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
pub struct ConvergenceRecord {
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
    /// Newton iterates that would have turned an element inside out, which the line search shortened
    /// (time steps and load levels; docs/time-integration.md, "Inverted elements").
    #[serde(default)]
    pub rejected_iterates: usize,
    /// Halvings of initial guesses (extrapolations, predictions) that would have turned an element
    /// inside out.
    #[serde(default)]
    pub retracted_guesses: usize,
    /// Solves repeated with their iterates free where the check on them blocked the way to a solution.
    #[serde(default)]
    pub free_retries: usize,
}

/// The mechanical model of a run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum ModelRecord {
    /// The three-director Cosserat shell.
    #[default]
    Cosserat,
    /// The Kirchhoff–Love comparison model.
    KirchhoffLove {
        /// The hyperelastic law (`stvk`, `neo_hookean`).
        law: String,
    },
    /// The volumetric micropolar comparison model.
    MicropolarVolume {
        /// Number of tetrahedra.
        n_tetrahedra: usize,
    },
}

/// The linear solves of a run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct LinearSolverRecord {
    /// Numerical factorisations performed (every solve counted, failed attempts included).
    pub factorisations: usize,
    /// The symmetric factor of the last symbolic analysis (direct solvers).
    pub factor: Option<FactorRecord>,
    /// Conjugate-gradient iterations in all (CG solver only).
    pub cg_iterations: Option<usize>,
    /// Conjugate-gradient iterations per Newton iteration (CG solver only).
    pub cg_iterations_per_newton: Option<f64>,
}

/// A sparse symmetric factor and the rate its factorisations ran at.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FactorRecord {
    /// Nonzeros of the factor.
    pub nnz: usize,
    /// Floating-point operations of one numerical factorisation.
    pub flops: f64,
    /// 2 when the two-domain Cholesky factorised the systems, 1 otherwise.
    pub domains: usize,
    /// Wall time of all numerical factorisations \[s\].
    pub seconds: f64,
    /// Achieved rate of the numerical factorisations \[GFLOP/s\] (their own wall time).
    pub gflops_per_s: Option<f64>,
}

/// How the broad-phase queries of a run were answered: from pairs kept within a margin, by a new
/// query of refitted or rebuilt hierarchies, or by an uncached broad phase.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub struct BroadPhaseRecord {
    /// All queries.
    pub queries: usize,
    /// Queries whose motion left the margin, answered by a new query of the hierarchies.
    pub requeries: usize,
    /// Of those, hierarchies built from scratch (the others refitted).
    pub builds: usize,
    /// Queries answered by an uncached broad phase.
    pub uncached: usize,
}

/// Contact over a run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct ContactRecord {
    /// Vertices of the contact mesh (shells and obstacles).
    pub n_vertices: usize,
    /// Triangles of the contact mesh.
    pub n_triangles: usize,
    /// Edges of the contact mesh.
    pub n_edges: usize,
    /// Time in contact energies, gradients and Hessians \[s\].
    pub energy_seconds: f64,
    /// Time in continuous collision detection \[s\].
    pub ccd_seconds: f64,
    /// Time in broad phases \[s\].
    pub broad_phase_seconds: f64,
    /// Share of the steps' time spent in contact (0 to 1).
    pub share_of_step: f64,
    /// Share of the steps' time in contact energies.
    pub energy_share: f64,
    /// Share of the steps' time in CCD.
    pub ccd_share: f64,
    /// Share of the steps' time in broad phases.
    pub broad_phase_share: f64,
    /// Evaluations of the contact term.
    pub n_evaluations: usize,
    /// CCD queries.
    pub n_ccd_queries: usize,
    /// Mean fraction of a Newton step that CCD allows (1 = no step cut short; `null` without any).
    #[serde(default)]
    pub mean_step_fraction: Option<f64>,
    /// Newton steps that CCD cut short (fraction below 1).
    #[serde(default)]
    pub n_step_cuts: usize,
    /// Broad-phase queries (candidate pairs of a motion), and how they were answered.
    #[serde(default)]
    pub broad_phase: BroadPhaseRecord,
    /// Mean number of pairs within the barrier in a committed state.
    pub mean_active_pairs: f64,
    /// Largest number of pairs within the barrier in a committed state.
    pub max_active_pairs: usize,
    /// Smallest gap (distance minus thicknesses) in a committed state \[m\] (`null` without any pair).
    pub min_gap: Option<f64>,
    /// Largest distance of a kinematic obstacle from its scripted place at the end of a step \[m\].
    pub max_obstacle_lag: f64,
    /// The same at the end of the last step \[m\].
    pub final_obstacle_lag: f64,
}

/// Kinetic and elastic energy at the output times.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct EnergyHistory {
    /// Output times.
    pub t: Vec<f64>,
    /// Kinetic energy \[J\].
    pub kinetic: Vec<f64>,
    /// Elastic energy \[J\].
    pub elastic: Vec<f64>,
}

impl EnergyHistory {
    /// Appends one output time; a time with a non-finite energy is left out (JSON has no NaN).
    pub fn push(&mut self, t: f64, kinetic: f64, elastic: f64) {
        if t.is_finite() && kinetic.is_finite() && elastic.is_finite() {
            self.t.push(t);
            self.kinetic.push(kinetic);
            self.elastic.push(elastic);
        }
    }
}

/// Contents of `DIR/summary.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub struct RunSummary {
    /// Name of the scene.
    pub scene: String,
    /// How the run ended.
    pub status: RunStatus,
    /// Why the run did not end with `ok` (`null` when it did).
    pub reason: Option<String>,
    /// Simulation time at which the run stopped (`null` if it completed).
    pub stopped_at: Option<f64>,
    /// The step that failed, with every attempt (`null` unless a step failed).
    pub failed_step: Option<FailedStep>,
    /// The step of the checkpoint this run was resumed from (absent for a run that started from the
    /// beginning); the counts and times of the summary cover the whole run either way.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub resumed_from: Option<usize>,
    /// The mechanical model.
    pub model: ModelRecord,
    /// Displacement element type, e.g. `"tri6"`.
    pub displacement_element: String,
    /// Rotation element type, e.g. `"tri3"` (`"-"` for a model without rotations).
    pub rotation_element: String,
    /// The strain interpolation of the Cosserat shells, e.g. `"regge_stabilized"` (comma-separated when
    /// shells differ; `"-"` for a model without one).
    #[serde(default)]
    pub strain_interpolation: String,
    /// The quadrature points per element of the Cosserat shells, e.g. `"3"` (comma-separated when
    /// shells differ; `"-"` for a model without them).
    #[serde(default)]
    pub quadrature_points: String,
    /// Number of shells.
    pub n_shells: usize,
    /// Number of cells (elements) of the meshes.
    pub n_cells: usize,
    /// Number of displacement degrees of freedom.
    pub n_displacement_dofs: usize,
    /// Number of rotation degrees of freedom.
    pub n_rotation_dofs: usize,
    /// Quadrature points with a curved rest geometry (the curved-shell terms ran there).
    pub n_curved_points: usize,
    /// Names of the energy terms of the incremental potential that were active.
    pub active_terms: Vec<String>,
    /// Nonzeros of the Hessian's upper triangle.
    pub hessian_nnz: usize,
    /// Time step size requested by the scene (time units; 1 in quasi-static runs).
    pub dt: f64,
    /// Number of completed time steps (load levels).
    pub n_steps: usize,
    /// Number of frames written.
    pub n_frames: usize,
    /// Average number of Newton iterations per completed step: a time step counts every solve of its
    /// accepted attempt (one solved again after its contact candidates grew counts both), a load level
    /// every solve towards it (intermediate and failed ones included).
    pub avg_newton_iterations: f64,
    /// Most Newton iterations of a completed step.
    pub max_newton_iterations: usize,
    /// Newton iterations of attempts that failed and were retried with a smaller step.
    pub wasted_newton_iterations: usize,
    /// Number of time step reductions (dt halvings, load bisections), those of a failed step included.
    pub n_step_reductions: usize,
    /// Intermediate load levels a quasi-static run solved on the way to its written levels (after
    /// bisections, or where a level needed many Newton iterations); 0 in other runs.
    pub n_intermediate_levels: usize,
    /// Total wall-clock time of the run \[s\].
    pub wall_seconds: f64,
    /// Average wall-clock time per completed step \[ms\].
    pub avg_step_ms: f64,
    /// Fraction of the time in steps spent in assembly (0 to 1), failed attempts included.
    pub assembly_share: f64,
    /// Fraction of the time in steps spent in linear solves (0 to 1), failed attempts included.
    pub linear_solve_share: f64,
    /// The process's peak resident memory \[MB\], where the operating system reports it.
    pub peak_memory_mb: Option<f64>,
    /// How the Newton solves met their tolerance (`null` if no step finished).
    pub convergence: Option<ConvergenceRecord>,
    /// The linear solves.
    pub linear_solver: LinearSolverRecord,
    /// The smallest deformed-to-rest area ratio over the shells' quadrature points at the output times
    /// (negative: an element turned inside out).
    pub min_area_ratio: Option<f64>,
    /// Contact (`null` without contact).
    pub contact: Option<ContactRecord>,
    /// Warnings about the scene's settings and about the run.
    pub warnings: Vec<String>,
    /// Energies at the output times.
    pub energy: EnergyHistory,
    /// Bounding box of the rest configuration.
    pub rest_bbox: BoundingBox,
}

impl RunSummary {
    /// The summary of a run that failed before it could report anything else (for instance a scene
    /// that did not validate): counts, times and the bounding box are zero.
    pub fn failed(scene: impl Into<String>, status: RunStatus, reason: impl Into<String>) -> Self {
        Self {
            scene: scene.into(),
            status,
            reason: Some(reason.into()),
            ..Self::default()
        }
    }

    /// Every number of the record with its field path.
    fn numbers(&self) -> Vec<(String, f64)> {
        let mut out: Vec<(String, f64)> = [
            ("dt", self.dt),
            ("avg_newton_iterations", self.avg_newton_iterations),
            ("wall_seconds", self.wall_seconds),
            ("avg_step_ms", self.avg_step_ms),
            ("assembly_share", self.assembly_share),
            ("linear_solve_share", self.linear_solve_share),
        ]
        .into_iter()
        .map(|(k, v)| (k.to_owned(), v))
        .collect();
        let optional = [
            ("stopped_at", self.stopped_at),
            ("peak_memory_mb", self.peak_memory_mb),
            ("min_area_ratio", self.min_area_ratio),
            (
                "linear_solver.cg_iterations_per_newton",
                self.linear_solver.cg_iterations_per_newton,
            ),
        ];
        out.extend(optional.into_iter().filter_map(|(k, v)| Some((k.to_owned(), v?))));
        for k in 0..3 {
            out.push((format!("rest_bbox.min[{k}]"), self.rest_bbox.min[k]));
            out.push((format!("rest_bbox.max[{k}]"), self.rest_bbox.max[k]));
        }
        if let Some(f) = &self.linear_solver.factor {
            out.push(("linear_solver.factor.flops".into(), f.flops));
            out.push(("linear_solver.factor.seconds".into(), f.seconds));
            if let Some(rate) = f.gflops_per_s {
                out.push(("linear_solver.factor.gflops_per_s".into(), rate));
            }
        }
        if let Some(c) = &self.contact {
            c.numbers_into(&mut out);
        }
        let energies = [
            ("t", &self.energy.t),
            ("kinetic", &self.energy.kinetic),
            ("elastic", &self.energy.elastic),
        ];
        for (name, values) in energies {
            out.extend(values.iter().enumerate().map(|(i, v)| (format!("energy.{name}[{i}]"), *v)));
        }
        if let Some(c) = &self.convergence {
            let fields = [
                ("tolerance", c.tolerance),
                ("max_step_tolerance", c.max_step_tolerance),
                ("max_residual", c.max_residual),
                ("max_relative_residual", c.max_relative_residual),
            ];
            out.extend(fields.into_iter().map(|(k, v)| (format!("convergence.{k}"), v)));
        }
        if let Some(step) = &self.failed_step {
            step.numbers_into(&mut out);
        }
        out
    }

    /// Checks that every number is finite.
    ///
    /// # Errors
    /// [`OutputError::NonFiniteSummary`] naming the first non-finite field.
    pub fn validate(&self) -> Result<(), OutputError> {
        match self.numbers().into_iter().find(|(_, v)| !v.is_finite()) {
            Some((field, value)) => Err(OutputError::NonFiniteSummary { field, value }),
            None => Ok(()),
        }
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

impl ContactRecord {
    /// The record's numbers with their field paths in the summary.
    fn numbers_into(&self, out: &mut Vec<(String, f64)>) {
        let fields = [
            ("energy_seconds", self.energy_seconds),
            ("ccd_seconds", self.ccd_seconds),
            ("broad_phase_seconds", self.broad_phase_seconds),
            ("share_of_step", self.share_of_step),
            ("energy_share", self.energy_share),
            ("ccd_share", self.ccd_share),
            ("broad_phase_share", self.broad_phase_share),
            ("mean_active_pairs", self.mean_active_pairs),
            ("max_obstacle_lag", self.max_obstacle_lag),
            ("final_obstacle_lag", self.final_obstacle_lag),
        ];
        out.extend(fields.into_iter().map(|(k, v)| (format!("contact.{k}"), v)));
        if let Some(gap) = self.min_gap {
            out.push(("contact.min_gap".into(), gap));
        }
    }
}

impl FailedStep {
    /// The record's numbers with their field paths in the summary.
    fn numbers_into(&self, out: &mut Vec<(String, f64)>) {
        out.push(("failed_step.t".into(), self.t));
        for (k, a) in self.attempts.iter().enumerate() {
            out.push((format!("failed_step.attempts[{k}].dt"), a.dt));
            out.extend(
                a.residuals
                    .iter()
                    .enumerate()
                    .map(|(i, r)| (format!("failed_step.attempts[{k}].residuals[{i}]"), *r)),
            );
        }
    }
}

/// Validates `summary` and writes it to `path` atomically as pretty-printed JSON.
///
/// # Errors
/// As [`RunSummary::to_json_string`] (then nothing is written), plus the errors of
/// [`crate::atomic::write_atomic`].
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
