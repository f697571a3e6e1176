//! Error types of the solver crate: failures of the sparse linear solvers, of a problem's own
//! evaluation, and of Newton's method.
//!
//! The three enums are layered: a [`ProblemError`] is what a [`NewtonProblem`](crate::NewtonProblem)
//! reports about itself, a [`LinearSolveError`] is what the sparse factorisations report, and a
//! [`NewtonError`] wraps both together with the iteration and the residual history, so that a time
//! stepper can decide between halving the time step and stopping with a diagnostic.

use cosserat_geometry::Num;
pub use cosserat_sparse::{Factorisation, LinearSolveError, LinearSolveStage};
use thiserror::Error;

/// A failure reported by a [`NewtonProblem`](crate::NewtonProblem) about its own evaluation.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum ProblemError {
    /// The energy contribution of one part of the problem (an element, a term, a spring; the problem
    /// says which numbering it uses) is not finite.
    #[error("non-finite energy in {part}")]
    NonFiniteEnergy {
        /// Index of the offending part in the problem's own numbering.
        index: usize,
        /// What the part is, for messages (e.g. "term `gravity` at node 3", or "part 3").
        part: String,
    },
    /// The state is outside the problem's domain (an inverted element, an interpenetration, a
    /// quaternion outside its hemisphere). During a Newton step this makes the solver shorten the step.
    #[error("invalid state: {reason}")]
    InvalidState {
        /// What is invalid, for diagnostics.
        reason: String,
    },
}

/// Which quantity was found to be NaN or infinite.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum NonFiniteQuantity {
    /// The energy Π.
    Energy,
    /// An entry of the gradient ∇Π.
    Gradient,
    /// A value of the Hessian ∇²Π.
    Hessian,
    /// The feasible step fraction returned by the problem.
    StepFraction,
}

/// A setting of [`NewtonSettings`](crate::NewtonSettings) or of the linear solver that is out of range.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum SettingName {
    /// `tolerance` must be positive and finite (and below 1 when relative).
    ResidualTolerance,
    /// `residual_scale` must be positive and finite.
    ResidualScale,
    /// `armijo_constant` must lie in (0, 1).
    ArmijoConstant,
    /// `backtracking_factor` must lie in (0, 1).
    BacktrackingFactor,
    /// `min_step_fraction` must lie in (0, 1].
    MinStepFraction,
    /// `linear_solver.max_backward_error` must be positive (infinity disables the check).
    MaxBackwardError,
    /// `linear_solver.cg.relative_tolerance` must lie in (0, 1).
    CgRelativeTolerance,
    /// `linear_solver.cg.max_iterations` must not be `Some(0)`.
    CgMaxIterations,
    /// A fixed `cg_forcing` tolerance must lie in (0, 1).
    CgForcing,
    /// Arc-length settings: a finite non-zero first increment, a finite end, a positive iteration
    /// target, `0 < min_ratio ≤ 1 ≤ max_ratio`.
    ArcLength,
}

/// A failure of Newton's method.
///
/// Every variant carries the residual history `residuals` (the residual at the start and after each
/// iteration, see [`NewtonReport`](crate::NewtonReport)) for diagnostics; [`NewtonError::residuals`]
/// returns it whatever the variant.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum NewtonError {
    /// The residual did not fall below the tolerance within the allowed number of iterations.
    #[error("no convergence in {iterations} Newton iterations (last residual {:e})", last(.residuals))]
    MaxIterations {
        /// Number of Newton iterations performed.
        iterations: usize,
        /// Residual history.
        residuals: Vec<f64>,
    },
    /// The backtracking line search exhausted its iterations without satisfying the Armijo test.
    #[error("line search failed in Newton iteration {iteration} (residual {residual:e})")]
    LineSearchFailed {
        /// The Newton iteration (1-based) whose line search failed.
        iteration: usize,
        /// The residual at the start of that iteration.
        residual: f64,
        /// Residual history.
        residuals: Vec<f64>,
    },
    /// The Newton direction is not a descent direction (`dx·∇Π ≥ 0`) and flipping is disabled, or the
    /// direction is orthogonal to the gradient.
    #[error("Newton direction is not a descent direction in iteration {iteration} (dx·∇Π = {slope:e})")]
    NotDescent {
        /// The Newton iteration (1-based).
        iteration: usize,
        /// The directional derivative `dx·∇Π`.
        slope: f64,
        /// Residual history.
        residuals: Vec<f64>,
    },
    /// The linear solve of a Newton iteration failed.
    #[error("linear solve failed in Newton iteration {iteration}: {source}")]
    LinearSolve {
        /// The Newton iteration (1-based).
        iteration: usize,
        /// The linear solver's error.
        #[source]
        source: LinearSolveError,
        /// Residual history.
        residuals: Vec<f64>,
    },
    /// The problem reported an error of its own (iteration 0 is the initial evaluation).
    #[error("problem evaluation failed in Newton iteration {iteration}: {source}")]
    Problem {
        /// The Newton iteration (0 for the initial evaluation).
        iteration: usize,
        /// The problem's error.
        #[source]
        source: ProblemError,
        /// Residual history.
        residuals: Vec<f64>,
    },
    /// A NaN or infinity appeared in a quantity returned by the problem (iteration 0 is the initial
    /// evaluation). Such values are never accepted.
    #[error("non-finite {quantity:?} (entry {index:?}) in Newton iteration {iteration}")]
    NonFinite {
        /// The Newton iteration (0 for the initial evaluation).
        iteration: usize,
        /// Which quantity.
        quantity: NonFiniteQuantity,
        /// The offending entry for gradients and Hessian values.
        index: Option<usize>,
        /// Residual history.
        residuals: Vec<f64>,
    },
    /// No feasible step: the step fraction allowed by the problem (after halving until the state is
    /// valid) fell below `min_step_fraction`.
    #[error("infeasible step in Newton iteration {iteration}: step fraction {step_fraction:e} below the minimum")]
    InfeasibleStep {
        /// The Newton iteration (1-based).
        iteration: usize,
        /// The last step fraction tried.
        step_fraction: f64,
        /// Residual history.
        residuals: Vec<f64>,
    },
    /// A buffer or mask has the wrong length.
    #[error("{what} has length {found}, expected {expected}")]
    DimensionMismatch {
        /// Which buffer.
        what: &'static str,
        /// Expected length.
        expected: usize,
        /// Actual length.
        found: usize,
    },
    /// The problem's Hessian pattern differs from the one the solver was built for.
    #[error("the problem's Hessian pattern differs from the one the solver was built for")]
    PatternChanged,
    /// A setting is out of range.
    #[error("setting {name:?} is out of range: {}", Num(*value))]
    InvalidSetting {
        /// Which setting.
        name: SettingName,
        /// Its value.
        value: f64,
    },
    /// Building the linear solver for the problem's pattern failed.
    #[error("cannot build the linear solver: {0}")]
    Setup(#[source] LinearSolveError),
}

fn last(residuals: &[f64]) -> f64 {
    residuals.last().copied().unwrap_or(f64::NAN)
}

impl NewtonError {
    /// The error with the residual history of its solve (set-up errors carry none).
    pub(crate) fn with_residuals(mut self, history: Vec<f64>) -> Self {
        match &mut self {
            Self::MaxIterations { residuals, .. }
            | Self::LineSearchFailed { residuals, .. }
            | Self::NotDescent { residuals, .. }
            | Self::LinearSolve { residuals, .. }
            | Self::Problem { residuals, .. }
            | Self::NonFinite { residuals, .. }
            | Self::InfeasibleStep { residuals, .. } => *residuals = history,
            Self::DimensionMismatch { .. } | Self::PatternChanged | Self::InvalidSetting { .. } | Self::Setup(_) => {}
        }
        self
    }

    /// The residual history carried by the error (empty for set-up errors).
    pub fn residuals(&self) -> &[f64] {
        match self {
            Self::MaxIterations { residuals, .. }
            | Self::LineSearchFailed { residuals, .. }
            | Self::NotDescent { residuals, .. }
            | Self::LinearSolve { residuals, .. }
            | Self::Problem { residuals, .. }
            | Self::NonFinite { residuals, .. }
            | Self::InfeasibleStep { residuals, .. } => residuals,
            Self::DimensionMismatch { .. } | Self::PatternChanged | Self::InvalidSetting { .. } | Self::Setup(_) => &[],
        }
    }
}

/// A failure of the scripts that prepare a time step or a load level: a load scale, a target or a rest
/// field that is not finite at the time it is needed, with the item and the expression named. It is not
/// Newton's failure, so the step is not retried with a smaller time step.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("{0}")]
pub struct ScriptError(pub String);
