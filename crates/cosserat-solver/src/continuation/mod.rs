//! Path following: equilibria `∇Π(x; λ) = 0` traced as a curve in `(x, λ)` by arc-length
//! continuation, through limit points of the load (snap-through) and of the displacement (snap-back).
//!
//! Load control fails at a limit point: beyond the largest load of a branch there is no nearby
//! equilibrium, and Newton's method jumps or fails. Arc-length continuation (Riks; Crisfield's
//! cylindrical form) makes the load factor `λ` an unknown and adds the constraint that each step
//! advances a given distance `Δl` along the path, measured on the unknowns:
//!
//! `‖Δx‖²_W = Δl²`, with `W` diagonal weights ([`PathProblem::arc_length_weights`]).
//!
//! Each step starts from the last equilibrium with a predictor that follows the path's direction: the
//! tangent `t = −H⁻¹ ∂∇Π/∂λ` for the first step, then the previous step's increment scaled to the new
//! arc length (a secant, which keeps its orientation through limit points, where the tangent's load
//! component changes sign). The corrector iterates Newton's method on the equilibrium equations and the
//! constraint together (see `corrector.rs`: Crisfield's quadratic constraint, the root that continues
//! forward). The arc length adapts to the corrector's iterations
//! (`Δl ← Δl √(target / iterations)`, within a factor of two per step), and a step whose corrector does
//! not converge is retried from the last equilibrium with half the arc length.
//!
//! The load enters through [`PathProblem::set_load_factor`]; `∂∇Π/∂λ` is taken by central differences
//! of the gradient in `λ` once per step, which is exact to round-off for dead loads proportional to `λ`
//! (and for prescribed motions linear in `λ` on linear constraints); loads that follow the deformation
//! would need it at every iteration.

use crate::error::{LinearSolveError, NewtonError, ProblemError};
use crate::newton::{Convergence, NewtonSettings, Tolerance};
use crate::problem::NewtonProblem;
use cosserat_geometry::Num;
use thiserror::Error;

mod corrector;
mod potential;

pub use potential::{LoadScript, PathStepper, trace_quasi_static};

/// A problem `Π(x; λ)` whose load factor can be set, evaluated at increments from its last committed
/// equilibrium.
pub trait PathProblem: NewtonProblem {
    /// Sets the load factor `λ` of the following evaluations (loads, prescribed motions).
    ///
    /// # Errors
    /// A [`ProblemError`] if the loads cannot be set (e.g. a script fails).
    fn set_load_factor(&mut self, lambda: f64) -> Result<(), ProblemError>;

    /// Writes the values of the fixed unknowns ([`NewtonProblem::fixed_dofs`]) for the current load
    /// factor into `x`. The default fixes nothing.
    fn prescribe(&self, x: &mut [f64]) {
        let _ = x;
    }

    /// Accepts `x` as the new equilibrium: later evaluations are increments from it.
    fn commit(&mut self, x: &[f64]);

    /// The weights `W` of the arc length `‖Δx‖²_W = Σ W_i Δx_i²`, default 1 for every unknown (fixed
    /// unknowns never count). Unknowns of other units (rotations beside displacements) can be weighted
    /// down or left out.
    fn arc_length_weights(&self, w: &mut [f64]) {
        w.fill(1.0);
    }
}

/// Settings of arc-length continuation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArcLengthSettings {
    /// The corrector's tolerance, iteration limit and linear solver (the residual scale is 1; the
    /// corrector takes full Newton steps, without line search or shift, since it follows unstable
    /// branches too). Default [`NewtonSettings::default`] with at most 25 iterations.
    pub newton: NewtonSettings,
    /// The load-factor increment of the first step, which sets the first arc length (default 0.05).
    pub initial_increment: f64,
    /// The path ends at the first equilibrium with `λ = end` reached from below (default 1).
    pub end: f64,
    /// At most this many steps (default 1000).
    pub max_steps: usize,
    /// The corrector iterations the arc length aims at (default 5).
    pub target_iterations: usize,
    /// At most this many halvings of the arc length in one step (default 10).
    pub max_cuts: usize,
    /// The arc length stays within `[min_ratio, max_ratio]` times the first one (defaults 1e-6 and 1:
    /// the first step sets the path's resolution, and later steps only shorten where the corrector
    /// needs more iterations).
    pub min_ratio: f64,
    /// See `min_ratio`.
    pub max_ratio: f64,
}

impl Default for ArcLengthSettings {
    fn default() -> Self {
        Self {
            newton: NewtonSettings {
                max_iterations: 25,
                ..NewtonSettings::default()
            },
            initial_increment: 0.05,
            end: 1.0,
            max_steps: 1000,
            target_iterations: 5,
            max_cuts: 10,
            min_ratio: 1e-6,
            max_ratio: 1.0,
        }
    }
}

/// One equilibrium on the path.
#[derive(Debug, Clone, PartialEq)]
pub struct PathPoint {
    /// Step number (1 for the first equilibrium after the start).
    pub step: usize,
    /// The load factor `λ`.
    pub load_factor: f64,
    /// The arc length of the step `‖Δx‖_W`.
    pub arc_length: f64,
    /// Corrector iterations of the converged attempt.
    pub iterations: usize,
    /// Corrector iterations of failed attempts (halved arc lengths) before it.
    pub wasted_iterations: usize,
    /// Halvings of the arc length in this step.
    pub cuts: usize,
    /// The final residual, in the gradient's units.
    pub residual: f64,
    /// How the corrector converged (tolerance, load scale, floor).
    pub convergence: Convergence,
    /// Seconds in Hessian assembly, gradient evaluations and linear solves of this step.
    pub assembly_seconds: f64,
    /// See `assembly_seconds`.
    pub linear_solve_seconds: f64,
}

/// Why a corrector attempt failed.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum CorrectorError {
    /// The residual did not pass the tolerance within the iteration limit.
    #[error("no convergence in {iterations} corrector iterations (last residual {residual:e})")]
    MaxIterations {
        /// Iterations done.
        iterations: usize,
        /// The last residual.
        residual: f64,
    },
    /// The residual grew beyond a thousand times the step's first one.
    #[error("the corrector diverged in iteration {iteration} (residual {residual:e})")]
    Diverged {
        /// The iteration.
        iteration: usize,
        /// The residual.
        residual: f64,
    },
    /// The tangent could not be factorised or solved with.
    #[error("linear solve failed in corrector iteration {iteration}: {source}")]
    LinearSolve {
        /// The iteration.
        iteration: usize,
        /// The linear solver's error.
        #[source]
        source: LinearSolveError,
    },
    /// The problem could not be evaluated.
    #[error("problem evaluation failed in corrector iteration {iteration}: {source}")]
    Problem {
        /// The iteration.
        iteration: usize,
        /// The problem's error.
        #[source]
        source: ProblemError,
    },
    /// A NaN or infinity in the residual or the tangent.
    #[error("non-finite residual or tangent in corrector iteration {iteration}")]
    NonFinite {
        /// The iteration.
        iteration: usize,
    },
}

/// A path that could not be followed to its end.
#[derive(Debug, Clone, Error)]
#[non_exhaustive]
pub enum PathError {
    /// Invalid settings or a pattern the linear solver rejects.
    #[error("cannot set up the continuation: {0}")]
    Setup(#[source] NewtonError),
    /// A step failed with every allowed arc length.
    #[error(
        "path following stopped after step {step} at load factor {}: the arc length was halved {cuts} times down to {}; last: {error}",
        Num(*load_factor),
        Num(*arc_length)
    )]
    StepFailed {
        /// The last equilibrium's step number.
        step: usize,
        /// Its load factor.
        load_factor: f64,
        /// Halvings tried.
        cuts: usize,
        /// The last arc length tried.
        arc_length: f64,
        /// The last attempt's failure.
        error: CorrectorError,
    },
    /// The first step's predictor moves no unknown the arc length measures, so the path has no step
    /// length to keep (every later predictor would be scaled by `0/0`).
    #[error(
        "the first load increment {} moves no unknown that the arc length measures (the loads do not act on the free unknowns, or the increment is too small to move them): the path has no step length",
        Num(*initial_increment)
    )]
    NoFirstArc {
        /// The first load increment.
        initial_increment: f64,
    },
    /// The scripts could not set the loads of a load factor (no shorter step helps).
    #[error("{0}")]
    Scripts(#[source] crate::error::ScriptError),
    /// A term of the problem that path following does not support.
    #[error("arc-length continuation does not support {0}")]
    Unsupported(&'static str),
    /// The path did not reach the end within the allowed steps.
    #[error(
        "the path did not reach load factor {} within {steps} steps (last load factor {})",
        Num(*end),
        Num(*load_factor)
    )]
    TooManySteps {
        /// The end load factor.
        end: f64,
        /// Steps taken.
        steps: usize,
        /// The last load factor.
        load_factor: f64,
    },
}

impl ArcLengthSettings {
    fn validate(&self) -> Result<(), NewtonError> {
        self.newton.validate()?;
        let ok = self.initial_increment.is_finite()
            && self.initial_increment != 0.0
            && self.end.is_finite()
            && self.target_iterations > 0
            && self.min_ratio > 0.0
            && self.max_ratio >= 1.0
            && self.min_ratio <= 1.0;
        if ok {
            Ok(())
        } else {
            Err(NewtonError::InvalidSetting {
                name: crate::error::SettingName::ArcLength,
                value: self.initial_increment,
            })
        }
    }
}

/// Follows the equilibrium path of `problem` from its committed state at `λ = 0` until `λ` reaches
/// `settings.end`, calling `reached(problem, point)` after every converged step (the problem is then
/// committed at that equilibrium).
///
/// # Errors
/// [`PathError`] when a step fails with every allowed arc length, when the first step's predictor
/// moves nothing, when the end is not reached within `max_steps`, or for invalid settings; the problem
/// then holds the last equilibrium.
pub fn trace_path<P: PathProblem + ?Sized>(
    problem: &mut P,
    settings: &ArcLengthSettings,
    reached: &mut dyn FnMut(&mut P, &PathPoint),
) -> Result<Vec<PathPoint>, PathError> {
    settings.validate().map_err(PathError::Setup)?;
    let mut tracer = corrector::Tracer::new(problem, settings).map_err(PathError::Setup)?;
    let mut points = Vec::new();
    let mut lambda = 0.0;
    while points.is_empty() || !reached_end(lambda, settings.end, tracer.last_increment()) {
        if points.len() == settings.max_steps {
            return Err(PathError::TooManySteps {
                end: settings.end,
                steps: points.len(),
                load_factor: lambda,
            });
        }
        let point = tracer.step(problem, points.len() + 1, lambda)?;
        lambda = point.load_factor;
        reached(problem, &point);
        points.push(point);
    }
    Ok(points)
}

/// Whether the last step (of load-factor increment `dl`) ended at the end load factor from below.
fn reached_end(lambda: f64, end: f64, dl: f64) -> bool {
    lambda == end && dl > 0.0
}

/// The corrector's tolerance (relative or absolute).
fn tolerance(settings: &ArcLengthSettings) -> Tolerance {
    settings.newton.tolerance
}
