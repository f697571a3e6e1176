//! Errors of the sparse linear solvers.

use faer::sparse::FaerError;
use thiserror::Error;

/// The numerical factorisation (or, for [`Cg`](Self::Cg), the iterative solver) that produced or failed
/// to produce a solution.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Factorisation {
    /// Supernodal Cholesky `A = L Lᵀ` (symmetric positive definite matrices only).
    Llt,
    /// Supernodal `A = P L B Lᵀ Pᵀ` with Bunch–Kaufman (rook) pivoting inside each supernode, `B` block
    /// diagonal with 1×1 and 2×2 blocks (symmetric indefinite matrices).
    Lblt,
    /// Sparse LU with partial pivoting on the full (mirrored) matrix.
    Lu,
    /// No factorisation: block-Jacobi preconditioned conjugate gradients, an inexact solve.
    Cg,
}

impl std::fmt::Display for Factorisation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let name = match self {
            Self::Llt => "LLᵀ",
            Self::Lblt => "LBLᵀ",
            Self::Lu => "LU",
            Self::Cg => "CG",
        };
        f.write_str(name)
    }
}

/// The stage of the linear solver in which faer reported a resource failure.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum LinearSolveStage {
    /// Copying the sparsity pattern.
    Pattern,
    /// Ordering and symbolic analysis of the symmetric factorisations.
    SymmetricSymbolic,
    /// Column ordering and symbolic analysis of the LU factorisation.
    LuSymbolic,
    /// Allocation of workspace memory.
    Workspace,
    /// Numerical factorisation.
    Numeric,
}

/// A failure of the sparse linear solver.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum LinearSolveError {
    /// The pattern is not square.
    #[error("the matrix pattern is {nrows}×{ncols}, not square")]
    NotSquare {
        /// Number of rows of the pattern.
        nrows: usize,
        /// Number of columns of the pattern.
        ncols: usize,
    },
    /// The pattern stores per-column entry counts (a non-compact faer pattern); the values slice would
    /// have gaps, which this solver does not accept.
    #[error("the matrix pattern is not compact (it has explicit column counts)")]
    NonCompactPattern,
    /// The pattern has an entry strictly below the diagonal; only the upper triangle may be given.
    #[error("pattern entry ({row}, {col}) lies below the diagonal; give the upper triangle only")]
    LowerTriangleEntry {
        /// Row of the offending entry.
        row: usize,
        /// Column of the offending entry.
        col: usize,
    },
    /// The pattern has the same entry twice.
    #[error("pattern entry ({row}, {col}) appears more than once")]
    DuplicateEntry {
        /// Row of the offending entry.
        row: usize,
        /// Column of the offending entry.
        col: usize,
    },
    /// The pattern has no diagonal entry in a column. Every diagonal entry must be stored (possibly as
    /// an explicit zero) so that fixed unknowns can be eliminated without changing the pattern.
    #[error("the pattern has no diagonal entry in column {col}")]
    MissingDiagonal {
        /// The column without a diagonal entry.
        col: usize,
    },
    /// A matrix value is NaN or infinite.
    #[error("matrix value #{index} at ({row}, {col}) is not finite: {value}")]
    NonFiniteValue {
        /// Index into the values slice (pattern order).
        index: usize,
        /// Row of the entry.
        row: usize,
        /// Column of the entry.
        col: usize,
        /// The offending value.
        value: f64,
    },
    /// A right-hand-side entry is NaN or infinite.
    #[error("right-hand side entry {index} is not finite: {value}")]
    NonFiniteRhs {
        /// Index of the entry.
        index: usize,
        /// The offending value.
        value: f64,
    },
    /// The Cholesky factorisation met a non-positive pivot: the matrix is not positive definite.
    #[error("the matrix is not positive definite (non-positive pivot at column {col})")]
    NotPositiveDefinite {
        /// Column (in the caller's numbering) at which the pivot was found.
        col: usize,
    },
    /// The factorisation met a zero pivot or produced a non-finite solution: the matrix is singular to
    /// working precision.
    #[error("the matrix is singular ({factorisation} factorisation{})", column_suffix(.col))]
    Singular {
        /// The factorisation that failed.
        factorisation: Factorisation,
        /// The column (in the caller's numbering) of the zero pivot, where known.
        col: Option<usize>,
    },
    /// The solution's normwise backward error `‖b − A x‖∞ / (‖A‖∞ ‖x‖∞ + ‖b‖∞)` exceeds the accepted
    /// bound: the factorisation was numerically unstable for this matrix.
    #[error("{factorisation} solution has backward error {backward_error:e} above the bound {bound:e}")]
    Inaccurate {
        /// The factorisation that produced the solution.
        factorisation: Factorisation,
        /// The measured backward error.
        backward_error: f64,
        /// The accepted bound (`LinearSolverSettings::max_backward_error`).
        bound: f64,
    },
    /// `LinearSolverSettings::max_backward_error` is NaN or not positive.
    #[error("the backward-error bound must be positive, got {value}")]
    InvalidBackwardErrorBound {
        /// The rejected bound.
        value: f64,
    },
    /// `LinearSolverSettings::cg.relative_tolerance` (or a tolerance set for one solve) lies outside
    /// the open interval (0, 1).
    #[error("the relative CG tolerance must lie in (0, 1), got {value}")]
    InvalidCgTolerance {
        /// The rejected tolerance.
        value: f64,
    },
    /// `LinearSolverSettings::cg.max_iterations` is `Some(0)`.
    #[error("the CG iteration cap must be positive")]
    ZeroCgIterationCap,
    /// The conjugate-gradient recursion produced a NaN or infinity (overflow on badly scaled input).
    #[error("conjugate gradients broke down (non-finite value) in iteration {iteration}")]
    CgBreakdown {
        /// The CG iteration (0: the right-hand side's norm overflowed).
        iteration: usize,
    },
    /// `solve_in_place` was called before a successful `factorise`.
    #[error("no valid factorisation: call factorise successfully before solving")]
    NotFactorised,
    /// faer ran out of memory or overflowed its index type.
    #[error("faer failed during {stage:?}: {source}")]
    Faer {
        /// Where the failure happened.
        stage: LinearSolveStage,
        /// The underlying faer error.
        #[source]
        source: FaerError,
    },
}

fn column_suffix(col: &Option<usize>) -> String {
    col.map_or_else(String::new, |c| format!(", zero pivot at column {c}"))
}

/// The error of a workspace allocation that failed.
pub(crate) fn out_of_memory() -> LinearSolveError {
    LinearSolveError::Faer {
        stage: LinearSolveStage::Workspace,
        source: faer::sparse::FaerError::OutOfMemory,
    }
}
