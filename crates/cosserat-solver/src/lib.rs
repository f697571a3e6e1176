//! Newton's method with a noise-resistant backtracking line search, and sparse symmetric linear
//! solvers on a fixed pattern, for the Cosserat shell simulator.
//!
//! Entry points:
//! - [`NewtonProblem`]: the trait a problem implements (energy, gradient, Hessian on a fixed sparse
//!   upper-triangle pattern, optional fixed unknowns and feasible step fractions).
//! - [`NewtonSolver`]: built once per Hessian pattern, it owns every buffer and the symbolic
//!   factorisation; [`NewtonSolver::solve`] minimises a problem and returns a [`NewtonReport`] (iterations,
//!   residual history, factorisations used, time in assembly and in linear solves) or a typed
//!   [`NewtonError`] carrying the residual history. [`NewtonSettings`] holds the tolerances: by default
//!   relative to the problem's loads with a round-off floor ([`Tolerance`]).
//! - [`linear::SparseSolver`]: supernodal Cholesky, symmetric indefinite `L B Lᵀ` and LU from faer,
//!   with the symbolic analysis done once per pattern, fixed unknowns eliminated without touching the
//!   pattern, and an `Auto` mode that falls back from Cholesky to `L B Lᵀ` to LU; large systems are
//!   factorised as two mesh halves at once, one per core ([`DomainSplit`]); and block-Jacobi
//!   preconditioned conjugate gradients ([`LinearSolverKind::Cg`]) for large positive definite
//!   systems, which Newton's method solves inexactly with the reference's forcing sequence
//!   ([`CgForcing`]).
//! - [`TimeStepper`], [`QuasiStaticStepper`] and [`solve_quasi_static`]: time steps and load levels with
//!   the same Newton solver.
//! - [`continuation`]: arc-length path following through limit points ([`trace_path`] for any
//!   [`PathProblem`], [`PathStepper`] and [`trace_quasi_static`] for a quasi-static potential).
//!
//! Non-goals: this crate knows nothing about meshes, elements or energies: the assembly layer adapts
//! its incremental potential to [`NewtonProblem`]. It does not project Hessians to positive
//! definiteness (that is per element, in assembly), and its only iterative linear solver is the
//! block-Jacobi CG (no multigrid, no incomplete factorisations).
//!
//! Feature flags: none.
//!
//! A tiny problem, `Π(x) = (x₀ − 1)⁴ + (x₀ − x₁)²`, minimised at `(1, 1)`:
//! ```
//! use cosserat_solver::{NewtonProblem, NewtonSettings, NewtonSolver, ProblemError};
//! use faer::sparse::{SymbolicSparseColMat, SymbolicSparseColMatRef};
//!
//! struct Tiny {
//!     // Upper triangle of a 2×2 Hessian: (0,0), (0,1), (1,1).
//!     pattern: SymbolicSparseColMat<usize>,
//! }
//!
//! impl NewtonProblem for Tiny {
//!     fn n_dofs(&self) -> usize {
//!         2
//!     }
//!     fn hessian_pattern(&self) -> SymbolicSparseColMatRef<'_, usize> {
//!         self.pattern.as_ref()
//!     }
//!     fn value(&mut self, x: &[f64]) -> Result<f64, ProblemError> {
//!         Ok((x[0] - 1.0).powi(4) + (x[0] - x[1]).powi(2))
//!     }
//!     fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> Result<f64, ProblemError> {
//!         g[0] = 4.0 * (x[0] - 1.0).powi(3) + 2.0 * (x[0] - x[1]);
//!         g[1] = -2.0 * (x[0] - x[1]);
//!         self.value(x)
//!     }
//!     fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> Result<f64, ProblemError> {
//!         h.copy_from_slice(&[12.0 * (x[0] - 1.0).powi(2) + 2.0, -2.0, 2.0]);
//!         self.gradient(x, g)
//!     }
//! }
//!
//! let pattern = SymbolicSparseColMat::new_checked(2, 2, vec![0, 1, 3], None, vec![0, 0, 1]);
//! let mut problem = Tiny { pattern };
//! let mut solver = NewtonSolver::for_problem(&problem, NewtonSettings::default()).unwrap();
//! let mut x = [3.0, -2.0];
//! let report = solver.solve(&mut problem, &mut x).unwrap();
//! // The default tolerance is relative: the residual ends below a millionth of the first one (here
//! // 4·2³ + 2·5 = 42), the largest force this problem shows.
//! assert_eq!(report.residuals[0], 42.0);
//! assert!(report.relative_residual() <= 1e-6 && report.residual() <= 42e-6);
//! // The error in x₀ shrinks by 2/3 per step on a quartic, so x₀ is accurate to about the
//! // cube root of the gradient's.
//! assert!((x[0] - 1.0).abs() < 2e-2 && (x[1] - x[0]).abs() < 1e-4);
//! ```

pub mod continuation;
pub mod error;
mod line_search;
pub use cosserat_sparse as linear;
pub mod newton;
pub mod potential_problem;
pub mod problem;
pub mod statics;
pub mod time_step;

pub use continuation::{
    ArcLengthSettings, CorrectorError, LoadScript, PathError, PathPoint, PathProblem, PathStepper, trace_path,
    trace_quasi_static,
};
pub use error::{
    Factorisation, LinearSolveError, LinearSolveStage, NewtonError, NonFiniteQuantity, ProblemError, ScriptError,
    SettingName,
};
pub use linear::{
    CgForcing, CgReport, CgSettings, CgStop, DomainSplit, FactorStats, FillOrdering, LinearSolverKind,
    LinearSolverSettings, SparseSolver,
};
pub use newton::{
    CarriedState, Convergence, Criterion, DomainCost, FactorisationCounts, IndefiniteHessian, NewtonReport,
    NewtonSettings, NewtonSolver, SolveCost, Tolerance,
};
pub use problem::NewtonProblem;
pub use statics::{
    IncrementControl, LevelFailure, LevelIncrement, LoadLevelReport, PredictorMemory, QuasiStaticSettings,
    QuasiStaticStepper, StaticError, solve_quasi_static,
};
pub use time_step::{InitialGuess, LastStep, StepError, StepReport, TimeStepSettings, TimeStepper};
