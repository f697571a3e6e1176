//! Errors of the volumetric model: invalid materials and meshes, an ill-posed system, and failures of
//! the conjugate-gradient solver and of the Newton loop built on it.

use cosserat_solver::ProblemError;
use thiserror::Error;

/// An invalid micropolar material parameter.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum MaterialError {
    /// A parameter outside its range.
    #[error("material parameter `{name}` = {value}: {reason}")]
    InvalidParameter {
        /// The parameter's field name.
        name: &'static str,
        /// Its value.
        value: f64,
        /// The admissible range.
        reason: &'static str,
    },
}

/// An invalid tetrahedral mesh or mesh request.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum MeshError {
    /// A generator parameter outside its range.
    #[error("mesh generator parameter `{name}` = {value}: {reason}")]
    InvalidParameter {
        /// The parameter's name.
        name: &'static str,
        /// Its value.
        value: f64,
        /// The admissible range.
        reason: &'static str,
    },
    /// An element refers to a node that does not exist.
    #[error("element {elem_idx} refers to node {node}, but the mesh has {n_nodes} nodes")]
    NodeOutOfRange {
        /// The element.
        elem_idx: usize,
        /// The missing node.
        node: usize,
        /// Number of nodes.
        n_nodes: usize,
    },
    /// A node position is NaN or infinite.
    #[error("node {node_idx} has a non-finite position")]
    NonFiniteNode {
        /// The node.
        node_idx: usize,
    },
    /// An element with (numerically) zero or negative volume: flat, or with its nodes in the wrong
    /// order (the volume `det[x₁ − x₀, x₂ − x₀, x₃ − x₀]/6` must be positive).
    #[error("element {elem_idx} has volume {volume} (relative {relative:e}); it must be positive")]
    DegenerateElement {
        /// The element.
        elem_idx: usize,
        /// Its signed volume \[m³\].
        volume: f64,
        /// The volume over the cube of its longest edge.
        relative: f64,
    },
    /// A mesh without elements.
    #[error("the mesh has no elements")]
    Empty,
}

/// A failure to build a volumetric system.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum BuildError {
    /// The material is invalid.
    #[error(transparent)]
    Material(#[from] MaterialError),
    /// The mesh is invalid.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// An input outside its range that is not a material parameter.
    #[error("`{name}` = {value}: {reason}")]
    InvalidInput {
        /// The field's name.
        name: &'static str,
        /// Its value.
        value: f64,
        /// The admissible range.
        reason: &'static str,
    },
    /// The rotation unknowns would have a singular Hessian at rest: without rotational inertia the
    /// energy alone must fix them, which needs `μ_c > 0` (the uniform rotation mode) and
    /// `μ L_c² b₁ > 0`, `μ L_c² b₂ > 0` (rotation fields whose element averages vanish).
    #[error("rotations are not determined without rotational inertia: {reason}")]
    IllPosedRotations {
        /// Which modulus vanishes.
        reason: &'static str,
    },
}

/// A failure of the preconditioned conjugate-gradient solver.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum CgError {
    /// A matrix value is NaN or infinite.
    #[error("matrix entry {index} (row {row}, column {col}) is not finite: {value}")]
    NonFiniteMatrix {
        /// Index in the values array.
        index: usize,
        /// Its row.
        row: usize,
        /// Its column.
        col: usize,
        /// The value.
        value: f64,
    },
    /// A right-hand-side entry is NaN or infinite.
    #[error("right-hand side entry {index} is not finite: {value}")]
    NonFiniteRhs {
        /// The entry.
        index: usize,
        /// Its value.
        value: f64,
    },
    /// An entry of the initial guess is NaN or infinite.
    #[error("initial guess entry {index} is not finite: {value}")]
    NonFiniteInitialGuess {
        /// The entry.
        index: usize,
        /// Its value.
        value: f64,
    },
    /// The iteration produced a non-finite value (breakdown).
    #[error("conjugate gradients broke down at iteration {iteration}")]
    Breakdown {
        /// The iteration.
        iteration: usize,
    },
}

/// Which setting of [`crate::CgNewtonSettings`] is out of range.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum CgNewtonSetting {
    /// `residual_tolerance`.
    ResidualTolerance,
    /// `residual_scale`.
    ResidualScale,
    /// `armijo_constant`.
    ArmijoConstant,
    /// `backtracking_factor`.
    BacktrackingFactor,
    /// The fixed forcing term.
    Forcing,
}

/// A failure of the conjugate-gradient Newton solver. Variants that end a solve carry the residual
/// history (`residuals[0]` at the initial state).
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum CgNewtonError {
    /// A setting out of range.
    #[error("invalid Newton-CG setting {name:?} = {value}")]
    InvalidSetting {
        /// The setting.
        name: CgNewtonSetting,
        /// Its value.
        value: f64,
    },
    /// The problem's dimension differs from the buffers or the pattern.
    #[error("dimension mismatch: pattern has {pattern} unknowns, problem {problem}")]
    DimensionMismatch {
        /// Dimension of the Hessian pattern.
        pattern: usize,
        /// `n_dofs()` of the problem.
        problem: usize,
    },
    /// The problem failed to evaluate.
    #[error("problem evaluation failed in iteration {iteration}: {source}")]
    Problem {
        /// The Newton iteration.
        iteration: usize,
        /// The cause.
        source: ProblemError,
        /// Residual history.
        residuals: Vec<f64>,
    },
    /// The problem returned a NaN or infinite energy or gradient entry.
    #[error("non-finite energy or gradient in iteration {iteration}")]
    NonFinite {
        /// The Newton iteration.
        iteration: usize,
        /// Residual history.
        residuals: Vec<f64>,
    },
    /// The linear solve failed.
    #[error("linear solve failed in iteration {iteration}: {source}")]
    Linear {
        /// The Newton iteration.
        iteration: usize,
        /// The cause.
        source: CgError,
        /// Residual history.
        residuals: Vec<f64>,
    },
    /// The CG direction does not descend and flipping is off.
    #[error("the Newton-CG direction does not descend in iteration {iteration}")]
    NotDescent {
        /// The Newton iteration.
        iteration: usize,
        /// Residual history.
        residuals: Vec<f64>,
    },
    /// The line search found no sufficient decrease.
    #[error("line search failed in iteration {iteration} after {backtracks} step reductions")]
    LineSearchFailed {
        /// The Newton iteration.
        iteration: usize,
        /// Step reductions tried.
        backtracks: usize,
        /// Residual history.
        residuals: Vec<f64>,
    },
    /// No convergence within the iteration limit.
    #[error("no convergence after {iterations} Newton iterations")]
    MaxIterations {
        /// Iterations done.
        iterations: usize,
        /// Residual history.
        residuals: Vec<f64>,
    },
}

impl CgNewtonError {
    /// The residual history of a failed solve (empty for setup errors).
    pub fn residuals(&self) -> &[f64] {
        match self {
            CgNewtonError::Problem { residuals, .. }
            | CgNewtonError::NonFinite { residuals, .. }
            | CgNewtonError::Linear { residuals, .. }
            | CgNewtonError::NotDescent { residuals, .. }
            | CgNewtonError::LineSearchFailed { residuals, .. }
            | CgNewtonError::MaxIterations { residuals, .. } => residuals,
            CgNewtonError::InvalidSetting { .. } | CgNewtonError::DimensionMismatch { .. } => &[],
        }
    }
}
