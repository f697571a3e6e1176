//! What a converged Newton solve reports: iterations, residual history, factorisations and timings.

use super::convergence::{Convergence, Criterion};
use crate::error::Factorisation;

/// How often each factorisation produced a Newton step.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct FactorisationCounts {
    /// Steps solved by Cholesky.
    pub llt: usize,
    /// Steps solved by the symmetric indefinite `L B Lᵀ`.
    pub lblt: usize,
    /// Steps solved by LU.
    pub lu: usize,
    /// Steps solved by preconditioned conjugate gradients (no factorisation).
    pub cg: usize,
}

impl FactorisationCounts {
    /// The counts since `earlier`, a count this one continues.
    fn since(&self, earlier: &Self) -> Self {
        Self {
            llt: self.llt - earlier.llt,
            lblt: self.lblt - earlier.lblt,
            lu: self.lu - earlier.lu,
            cg: self.cg - earlier.cg,
        }
    }

    /// Adds the counts of `other`.
    fn add(&mut self, other: &Self) {
        self.llt += other.llt;
        self.lblt += other.lblt;
        self.lu += other.lu;
        self.cg += other.cg;
    }

    /// Numerical factorisations among the counted steps (every step but the conjugate-gradient ones).
    pub fn factorised(&self) -> usize {
        self.llt + self.lblt + self.lu
    }

    pub(super) fn record(&mut self, f: Factorisation) {
        match f {
            Factorisation::Llt => self.llt += 1,
            Factorisation::Lblt => self.lblt += 1,
            Factorisation::Lu => self.lu += 1,
            Factorisation::Cg => self.cg += 1,
        }
    }
}

/// The outcome of a converged Newton solve.
#[derive(Debug, Clone, PartialEq)]
pub struct NewtonReport {
    /// Number of Newton iterations (linear solves whose step was taken); 0 if the initial state had
    /// already converged.
    pub iterations: usize,
    /// Residual history: `residuals[0]` at the initial state, `residuals[k]` after iteration `k`.
    pub residuals: Vec<f64>,
    /// The energy `Π` at the solution.
    pub energy: f64,
    /// Total number of step reductions in all line searches (not counting feasibility halvings).
    pub line_search_backtracks: usize,
    /// Iterations that reused an earlier factorisation (chord steps).
    pub chord_iterations: usize,
    /// Total number of step halvings to reach a valid state.
    pub feasibility_halvings: usize,
    /// Number of Newton directions negated because they did not descend.
    pub direction_flips: usize,
    /// Iterations whose Hessian was not positive definite and was shifted
    /// ([`IndefiniteHessian`](crate::IndefiniteHessian)).
    pub shifted_iterations: usize,
    /// Doublings of shifted steps along negative curvature.
    pub extrapolations: usize,
    /// Full steps taken although they raised the energy (with mixed integration points).
    pub relaxed_steps: usize,
    /// Steps undone (the relaxed ones and those after them) because the energy did not fall below the
    /// relaxed steps' start; they count among the iterations.
    pub undone_relaxed_steps: usize,
    /// The test the solve passed, its tolerance, load scale and round-off floor.
    pub convergence: Convergence,
    /// Which factorisation solved each step, counted.
    pub factorisations: FactorisationCounts,
    /// Conjugate-gradient iterations over all CG solves (0 without [`LinearSolverKind::Cg`](crate::LinearSolverKind::Cg)).
    pub cg_iterations: usize,
    /// CG solves stopped by a direction of non-positive curvature (an indefinite Hessian).
    pub cg_negative_curvature_stops: usize,
    /// CG solves stopped by the iteration cap before reaching their tolerance.
    pub cg_iteration_cap_stops: usize,
    /// Wall-clock seconds in Hessian assembly (`NewtonProblem::hessian` calls).
    pub assembly_seconds: f64,
    /// Wall-clock seconds in energy and gradient evaluations (`value` and `gradient` calls).
    pub evaluation_seconds: f64,
    /// Wall-clock seconds in linear solves (numerical factorisation and triangular solves).
    pub linear_solve_seconds: f64,
    /// The part of `linear_solve_seconds` spent in numerical factorisations (`SparseSolver::factorise`
    /// calls; for CG, building the preconditioner).
    pub factorisation_seconds: f64,
}

impl NewtonReport {
    /// A report with nothing counted yet.
    pub(super) fn empty() -> Self {
        Self {
            iterations: 0,
            residuals: Vec::new(),
            energy: f64::NAN,
            line_search_backtracks: 0,
            chord_iterations: 0,
            feasibility_halvings: 0,
            direction_flips: 0,
            shifted_iterations: 0,
            extrapolations: 0,
            relaxed_steps: 0,
            undone_relaxed_steps: 0,
            convergence: Convergence {
                criterion: Criterion::Residual,
                tolerance: f64::NAN,
                load_scale: f64::NAN,
                floor: f64::NAN,
            },
            factorisations: FactorisationCounts::default(),
            cg_iterations: 0,
            cg_negative_curvature_stops: 0,
            cg_iteration_cap_stops: 0,
            assembly_seconds: 0.0,
            evaluation_seconds: 0.0,
            linear_solve_seconds: 0.0,
            factorisation_seconds: 0.0,
        }
    }

    /// The final residual.
    pub fn residual(&self) -> f64 {
        self.residuals.last().copied().unwrap_or(f64::NAN)
    }

    /// The final residual over the load scale.
    pub fn relative_residual(&self) -> f64 {
        self.convergence.relative_residual(self.residual())
    }
}

/// What Newton solves cost, summed over solves. A [`NewtonSolver`](super::NewtonSolver) keeps the sum
/// over every solve it ran, converged or failed ([`NewtonSolver::spent`](super::NewtonSolver::spent)),
/// so that a time step or a load level reports all of its solves: failed attempts, solves repeated
/// after contact candidates grew, and intermediate load levels, where a [`NewtonReport`] describes one
/// solve.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SolveCost {
    /// Newton iterations.
    pub iterations: usize,
    /// Iterations whose Hessian was shifted.
    pub shifted_iterations: usize,
    /// Which factorisation solved each step, counted.
    pub factorisations: FactorisationCounts,
    /// Conjugate-gradient iterations.
    pub cg_iterations: usize,
    /// Wall-clock seconds in Hessian assembly.
    pub assembly_seconds: f64,
    /// Wall-clock seconds in energy and gradient evaluations.
    pub evaluation_seconds: f64,
    /// Wall-clock seconds in linear solves.
    pub linear_solve_seconds: f64,
    /// The part of `linear_solve_seconds` spent in numerical factorisations.
    pub factorisation_seconds: f64,
    /// What keeping the solutions in the potential's domain cost (time steps and load levels).
    pub domain: DomainCost,
}

/// What keeping a solution in the potential's domain (no element turned inside out) cost: the work of
/// the domain check, counted over solves (see `solve_in_domain`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct DomainCost {
    /// Iterates the check turned back, which the line search shortened.
    pub rejected_iterates: usize,
    /// Halvings of initial guesses that would have turned an element inside out.
    pub retracted_guesses: usize,
    /// Solves repeated with the iterates free after the check blocked the way.
    pub free_retries: usize,
}

impl DomainCost {
    /// The counts since `earlier`, a sum these continue.
    fn since(&self, earlier: &Self) -> Self {
        Self {
            rejected_iterates: self.rejected_iterates - earlier.rejected_iterates,
            retracted_guesses: self.retracted_guesses - earlier.retracted_guesses,
            free_retries: self.free_retries - earlier.free_retries,
        }
    }
}

impl SolveCost {
    /// Adds a solve of `iterations` Newton iterations whose counters are those of `report` (a failed
    /// solve's report holds its counters but not its iteration count).
    pub(super) fn add(&mut self, iterations: usize, report: &NewtonReport) {
        self.iterations += iterations;
        self.shifted_iterations += report.shifted_iterations;
        self.factorisations.add(&report.factorisations);
        self.cg_iterations += report.cg_iterations;
        self.assembly_seconds += report.assembly_seconds;
        self.evaluation_seconds += report.evaluation_seconds;
        self.linear_solve_seconds += report.linear_solve_seconds;
        self.factorisation_seconds += report.factorisation_seconds;
    }

    /// The cost of the solves since `earlier`, a sum this one continues.
    pub fn since(&self, earlier: &Self) -> Self {
        Self {
            iterations: self.iterations - earlier.iterations,
            shifted_iterations: self.shifted_iterations - earlier.shifted_iterations,
            factorisations: self.factorisations.since(&earlier.factorisations),
            cg_iterations: self.cg_iterations - earlier.cg_iterations,
            assembly_seconds: self.assembly_seconds - earlier.assembly_seconds,
            evaluation_seconds: self.evaluation_seconds - earlier.evaluation_seconds,
            linear_solve_seconds: self.linear_solve_seconds - earlier.linear_solve_seconds,
            factorisation_seconds: self.factorisation_seconds - earlier.factorisation_seconds,
            domain: self.domain.since(&earlier.domain),
        }
    }
}
