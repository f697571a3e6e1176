//! Newton's method with a backtracking (noise-resistant) Armijo line search for a
//! [`NewtonProblem`] on a fixed sparse Hessian pattern.
//!
//! One iteration from `x`:
//! 1. assemble the Hessian with the gradient (or reuse the last factors for a chord step);
//! 2. solve `H dx = −∇Π` with fixed unknowns eliminated: Cholesky, or, when `H` is not positive
//!    definite, Cholesky of `H + μ D` with the smallest tried shift that makes it so, or the symmetric
//!    indefinite factorisation of `H` itself ([`IndefiniteHessian`]); with [`LinearSolverKind::Cg`]
//!    inexactly, to the relative residual of the forcing sequence [`NewtonSettings::cg_forcing`]
//!    (truncated Newton-CG);
//! 3. take the full step (shortened to the problem's feasible fraction and halved while the state is
//!    invalid) with its gradient, accept it if it passes the Armijo test or the convergence test,
//!    otherwise backtrack on energies (the noise-resistant Armijo test of `line_search.rs`); an
//!    accepted iterate may be re-expressed in other unknowns ([`NewtonProblem::rebase`]) or the
//!    problem's energy adapted to it ([`NewtonProblem::follow_iterate`], also called with the start),
//!    and is then evaluated anew;
//! 4. stop when the residual passes the convergence test ([`Tolerance`]), or when the solve has
//!    stagnated at the residual's round-off floor.
//!
//! It follows the reference code's `NewtonsMethod` (model.md §7.1) without its quirks: convergence is
//! tested wherever the gradient of an accepted iterate is known (the initial state, the full step, a
//! line-search point whose gradient was needed, or the start of the next iteration, where the Hessian
//! assembly returns the gradient anyway); the Armijo bound carries the step length `α`;
//! `max_iterations` Newton steps are really allowed; the residual ignores fixed unknowns, whose
//! gradient entries are reaction forces. NaN or infinity in any returned quantity is an error, never an
//! accepted state.

use std::time::Instant;

use faer::sparse::SymbolicSparseColMatRef;

use crate::error::NewtonError;
use crate::line_search::ArmijoTest;
use crate::linear::{LinearSolverKind, SparseSolver};
use crate::problem::NewtonProblem;

mod convergence;
mod direction;
mod evaluation;
mod relaxed;
mod report;
mod settings;
mod step;

pub(crate) use convergence::ConvergenceTest;
pub use convergence::{Convergence, Criterion, Tolerance};
use evaluation::problem_error;
pub(crate) use evaluation::{round_off_scale, weighted_max_abs};
use relaxed::{Relaxed, undo_relaxed};
pub use report::{DomainCost, FactorisationCounts, NewtonReport, SolveCost};
pub use settings::{IndefiniteHessian, NewtonSettings};

/// What one solve leaves for the next ([`NewtonSolver::carried`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CarriedState {
    /// Whether the next solve assembles the Hessian with its first gradient (see
    /// [`NewtonSolver::solve`]).
    pub starts_with_hessian: bool,
    /// The last shift that made an indefinite Hessian positive definite, where the next search for a
    /// shift starts (0 before any).
    pub last_shift: f64,
}

/// Newton's method with all buffers and the symbolic factorisation of one Hessian pattern.
///
/// Build it once per pattern with [`try_new`](Self::try_new) or [`for_problem`](Self::for_problem)
/// and call [`solve`](Self::solve) once per time step: the buffers of length `n` and `nnz` are reused
/// and the symbolic analysis is never repeated.
#[derive(Debug)]
pub struct NewtonSolver {
    settings: NewtonSettings,
    linear: SparseSolver,
    grad: Vec<f64>,
    grad_trial: Vec<f64>,
    hess_values: Vec<f64>,
    dx: Vec<f64>,
    x_trial: Vec<f64>,
    fixed: Vec<bool>,
    has_fixed: bool,
    /// The problem's residual weights (see [`NewtonProblem::residual_weights`]) with a relative
    /// tolerance; all 1 with an absolute one, whose units are the gradient's own.
    weights: Vec<f64>,
    /// Per-unknown scratch of the round-off floor: the magnitudes `m` of the unknowns and the row sums
    /// `Σ_j |H_ij| m_j`.
    scratch: (Vec<f64>, Vec<f64>),
    /// Whether the next solve assembles the Hessian with its first gradient (see [`Self::solve`]).
    start_with_hessian: bool,
    /// Whether the factors left by the last solve start the next one with a chord step: the last
    /// solve converged with a step that kept reuse on ([`NewtonSettings::reuse_max_ratio`]).
    carry_factors: bool,
    /// Position of each diagonal entry in the pattern's values.
    diagonal_slots: Vec<usize>,
    /// `D` of the shift `H + μ D` (see [`direction`]).
    shift_scale: Vec<f64>,
    /// Trial states of the line search's extrapolation along negative curvature.
    x_extra: Vec<f64>,
    /// The last shift `μ` that made an indefinite Hessian positive definite (the next one starts near
    /// it).
    last_shift: f64,
    /// The cost of every solve so far, converged or failed.
    spent: SolveCost,
}

/// What is known at the current iterate `x`.
#[derive(Debug, Clone, Copy)]
struct Point {
    /// `Π(x)`.
    energy: f64,
    /// `grad` holds `∇Π(x)`, and the last residual recorded is `x`'s.
    gradient: bool,
    /// `hess_values` holds `∇²Π(x)`, not yet factorised.
    hessian: bool,
}

/// The state of one solve: residual history, counters, convergence test.
struct Run {
    residuals: Vec<f64>,
    iterations: usize,
    report: NewtonReport,
    test: ConvergenceTest,
    /// The Newton decrement `−dx·∇Π` of the last direction, when `dx` solved `H dx = −∇Π` exactly with
    /// a positive definite `H` (the stagnation test needs it).
    decrement: Option<f64>,
    /// Whether the round-off floor has been estimated in this solve.
    floor_known: bool,
    /// Whether the last direction came from a shifted (indefinite) Hessian.
    shifted: bool,
    /// Whether the last direction came from the factorisation of an indefinite (or singular) Hessian
    /// itself.
    indefinite: bool,
    /// Whether indefinite Hessians are shifted from now on in this solve
    /// ([`IndefiniteHessian::Adaptive`] after a shortened step along an unshifted direction).
    shift_from_now: bool,
    /// Whether the next direction is a chord step with the current factors (the last step was full
    /// and cut the residual by the factor of [`NewtonSettings::reuse_max_ratio`]).
    reuse: bool,
    /// The state measured before the solve (see [`NewtonSolver::solve_from_prediction`]).
    measured: Option<MeasuredStart>,
    /// With mixed integration points: the run of steps since a relaxed step, until the energy falls
    /// below that of the point it left (see the `relaxed` module).
    relaxed: Option<Relaxed>,
    /// Whether relaxed steps may still be taken in this solve (not after a run of them was undone).
    may_relax: bool,
}

impl Run {
    fn last_residual(&self) -> f64 {
        self.residuals.last().copied().unwrap_or(f64::NAN)
    }
}

/// What [`NewtonSolver::solve_from_prediction`] measured at the state its prediction starts from.
#[derive(Debug, Clone, Copy)]
struct MeasuredStart {
    /// The largest of its residual and reactions.
    load_scale: f64,
    /// Its energy.
    energy: f64,
}

/// How the line search of one iteration ended.
enum Step {
    /// The full (feasible) step `α dx` was accepted, with its gradient.
    Full { alpha: f64 },
    /// A shorter step `α dx` was accepted.
    Backtracked { alpha: f64 },
    /// The full (feasible) step `α dx` was taken although it raised the energy (see the `relaxed`
    /// module).
    Relaxed { alpha: f64 },
    /// No step length passed.
    Failed,
}

impl NewtonSolver {
    /// Builds the solver for a Hessian pattern (upper triangle with every diagonal entry).
    ///
    /// # Errors
    /// [`NewtonError::InvalidSetting`] or [`NewtonError::Setup`] if the pattern is malformed.
    pub fn try_new(pattern: SymbolicSparseColMatRef<'_, usize>, settings: NewtonSettings) -> Result<Self, NewtonError> {
        settings.validate()?;
        let linear =
            SparseSolver::try_new(pattern, effective_linear_settings(&settings)).map_err(NewtonError::Setup)?;
        Ok(Self::with_linear(pattern, settings, linear))
    }

    /// A solver with `settings` for `pattern`, this solver's pattern grown by new couplings (contact):
    /// the linear solver reuses the fill-reducing orders ([`SparseSolver::try_grown`]).
    ///
    /// # Errors
    /// [`NewtonError::Setup`] if the pattern is malformed.
    pub fn try_grown(
        &self,
        pattern: SymbolicSparseColMatRef<'_, usize>,
        settings: NewtonSettings,
    ) -> Result<Self, NewtonError> {
        settings.validate()?;
        let linear = self
            .linear
            .try_grown(pattern, effective_linear_settings(&settings))
            .map_err(NewtonError::Setup)?;
        Ok(Self::with_linear(pattern, settings, linear).continuing(self.spent))
    }

    fn with_linear(
        pattern: SymbolicSparseColMatRef<'_, usize>,
        settings: NewtonSettings,
        linear: SparseSolver,
    ) -> Self {
        let n = linear.n();
        let nnz = linear.nnz();
        Self {
            settings,
            linear,
            grad: vec![0.0; n],
            grad_trial: vec![0.0; n],
            hess_values: crate::linear::memory::mapped_zeros(nnz),
            dx: vec![0.0; n],
            x_trial: vec![0.0; n],
            fixed: vec![false; n],
            has_fixed: false,
            weights: vec![1.0; n],
            scratch: (vec![0.0; n], vec![0.0; n]),
            start_with_hessian: true,
            carry_factors: false,
            diagonal_slots: diagonal_slots(pattern),
            shift_scale: vec![0.0; n],
            x_extra: Vec::new(),
            last_shift: 0.0,
            spent: SolveCost::default(),
        }
    }

    /// Builds the solver for `problem`'s Hessian pattern.
    ///
    /// # Errors
    /// As [`try_new`](Self::try_new), and [`NewtonError::DimensionMismatch`] if the pattern's
    /// dimension differs from `problem.n_dofs()`.
    pub fn for_problem<P: NewtonProblem + ?Sized>(problem: &P, settings: NewtonSettings) -> Result<Self, NewtonError> {
        let solver = Self::try_new(problem.hessian_pattern(), settings)?;
        if solver.linear.n() != problem.n_dofs() {
            return Err(NewtonError::DimensionMismatch {
                what: "Hessian pattern dimension",
                expected: problem.n_dofs(),
                found: solver.linear.n(),
            });
        }
        Ok(solver)
    }

    /// The state a solve leaves for the next (a checkpoint saves it so that a resumed run repeats the
    /// same evaluations).
    pub fn carried(&self) -> CarriedState {
        CarriedState {
            starts_with_hessian: self.start_with_hessian,
            last_shift: self.last_shift,
        }
    }

    /// Sets what [`NewtonSolver::carried`] reports (to resume a run from a checkpoint).
    pub fn restore(&mut self, carried: CarriedState) {
        self.start_with_hessian = carried.starts_with_hessian;
        self.last_shift = carried.last_shift;
    }

    /// The settings.
    pub fn settings(&self) -> &NewtonSettings {
        &self.settings
    }

    /// Mutable access to the settings; they are validated at the next [`solve`](Self::solve), and a
    /// changed linear-solver ordering redoes the symbolic analysis there.
    pub fn settings_mut(&mut self) -> &mut NewtonSettings {
        &mut self.settings
    }

    /// The cost of every solve this solver ran, converged or failed (a solver grown from another
    /// continues its sum): the difference over a time step or a load level is what all of its solves
    /// cost.
    pub fn spent(&self) -> SolveCost {
        self.spent
    }

    /// Adds the domain check's work in a solve to [`Self::spent`].
    pub(crate) fn spend_on_domain(&mut self, f: impl FnOnce(&mut DomainCost)) {
        f(&mut self.spent.domain);
    }

    /// This solver continuing the sum `spent` of the one it replaces.
    pub(crate) fn continuing(mut self, spent: SolveCost) -> Self {
        self.spent = spent;
        self
    }

    /// The sparse linear solver (for its statistics).
    pub fn linear_solver(&self) -> &SparseSolver {
        &self.linear
    }

    /// [`solve`](Self::solve) from a predicted iterate `x` (an extrapolation of earlier solutions from
    /// `start`, e.g. a path's secant predictor). The scale of the [relative
    /// tolerance](Tolerance::Relative) is measured at `start` (its residual and reactions, beside the
    /// external loads), not at `x`: a prediction's residual and reactions are its own error, which in a
    /// thin shell's stiff stretching can exceed the loads a millionfold and would loosen the test by as
    /// much. Costs one gradient evaluation at `start`.
    ///
    /// With [`NewtonSettings::mixed_integration_points`], the first Hessian weights its second-order
    /// terms with the stresses of `start`, as the mixed-integration-point method carries its stresses
    /// from the last equilibrium into a new step: the prediction's own stresses carry its error, which
    /// in a thin shell is a spurious membrane stress far above the loads, whose geometric stiffness
    /// turns the first Hessian indefinite and sends the first step astray (out of the plane of a plane
    /// problem, for example). Costs one linearisation of the strains at `start`.
    ///
    /// # Errors
    /// As [`solve`](Self::solve); `start` must have the length of `x`.
    pub fn solve_from_prediction<P: NewtonProblem + ?Sized>(
        &mut self,
        problem: &mut P,
        x: &mut [f64],
        start: &[f64],
    ) -> Result<NewtonReport, NewtonError> {
        self.prepare(problem, start)?;
        self.grad.fill(0.0);
        let energy = problem
            .gradient(start, &mut self.grad)
            .map_err(|source| problem_error(0, source))?;
        self.check_gradient(&self.grad, 0)?;
        let measured = MeasuredStart {
            load_scale: self.residual(&self.grad).max(self.reactions()),
            energy,
        };
        self.solve_with_scale(problem, x, Some((measured, start)))
    }

    /// Minimises `problem` starting from `x`, which holds the solution on success. On failure `x`
    /// holds the last accepted iterate (always finite).
    ///
    /// # Errors
    /// A [`NewtonError`] carrying the residual history; see its variants.
    pub fn solve<P: NewtonProblem + ?Sized>(
        &mut self,
        problem: &mut P,
        x: &mut [f64],
    ) -> Result<NewtonReport, NewtonError> {
        self.solve_with_scale(problem, x, None)
    }

    /// [`solve`](Self::solve) with the load scale measured before the solve and the state it was
    /// measured at, if the solve starts from a prediction (see
    /// [`solve_from_prediction`](Self::solve_from_prediction)).
    fn solve_with_scale<P: NewtonProblem + ?Sized>(
        &mut self,
        problem: &mut P,
        x: &mut [f64],
        prediction: Option<(MeasuredStart, &[f64])>,
    ) -> Result<NewtonReport, NewtonError> {
        self.prepare(problem, x)?;
        problem.clear_predicted_strains();
        if let Some((_, start)) = prediction
            && self.settings.mixed_integration_points
        {
            // The strains of `start`, predicted along no step.
            self.dx.fill(0.0);
            problem
                .linearize_strains(start, &self.dx)
                .map_err(|source| problem_error(0, source))?;
            problem.advance_predicted_strains(0.0);
        }
        // A predicted start (a previous step's velocity, a path's secant) is an iterate too; nothing has
        // been evaluated yet, so whether it changed the energy does not matter.
        problem.follow_iterate(x);
        let mut run = Run {
            residuals: Vec::with_capacity(self.settings.max_iterations + 1),
            iterations: 0,
            report: NewtonReport::empty(),
            test: ConvergenceTest::new(self.settings.tolerance, 0.0, 0.0, 0.0),
            decrement: None,
            floor_known: false,
            shifted: false,
            indefinite: false,
            shift_from_now: false,
            reuse: self.carry_factors,
            measured: prediction.map(|(measured, _)| measured),
            relaxed: None,
            may_relax: self.settings.mixed_integration_points && problem.predicts_strains(),
        };
        let result = self.minimise(problem, x, &mut run);
        // A failed solve counts the iterations whose step was taken, as its residual history does.
        let taken = match &result {
            Ok(_) => run.iterations,
            Err(_) => run.residuals.len().saturating_sub(1),
        };
        self.spent.add(taken, &run.report);
        if result.is_err() {
            problem.abandon_solve();
        }
        // A solve that stopped where it started lets the next one evaluate the gradient alone first, so
        // that a state at rest does not pay for a Hessian; any other starts with the Hessian, whose
        // assembly brings the first gradient (one gradient evaluation less per solve).
        self.start_with_hessian = !(result.is_ok() && run.iterations == 0);
        // Factors that still gave fast progress at the end of this solve start the next one (the next
        // time step's Hessian differs from this one's by one step's change of the state).
        self.carry_factors = result.is_ok() && run.reuse;
        match result {
            Ok((energy, convergence)) => {
                let mut report = run.report;
                report.iterations = run.iterations;
                report.energy = energy;
                report.residuals = run.residuals;
                report.convergence = convergence;
                Ok(report)
            }
            Err(error) => Err(error.with_residuals(run.residuals)),
        }
    }

    /// Newton's iteration from `x`: the energy at the solution and how it converged, or why not.
    fn minimise<P: NewtonProblem + ?Sized>(
        &mut self,
        problem: &mut P,
        x: &mut [f64],
        run: &mut Run,
    ) -> Result<(f64, Convergence), NewtonError> {
        let s = self.settings;
        let mut at = self.start(problem, x, run)?;
        loop {
            if !at.gradient {
                self.refresh(problem, x, &mut at, run)?;
            }
            let (k, r) = (run.iterations, run.last_residual());
            if k >= s.min_iterations && run.test.accepts(r) {
                return Ok((at.energy, run.test.record(Criterion::Residual)));
            }
            if run.test.stagnated(&run.residuals, run.decrement, false) {
                return Ok((at.energy, run.test.record(Criterion::Stagnated)));
            }
            if run.relaxed.as_ref().is_some_and(Relaxed::overdue) {
                at = undo_relaxed(problem, x, run);
                continue;
            }
            if k == s.max_iterations {
                return Err(NewtonError::MaxIterations {
                    iterations: k,
                    residuals: Vec::new(),
                });
            }
            run.iterations += 1;
            if r == 0.0 {
                // Exactly stationary: the Newton step is zero whatever the Hessian, and no direction
                // (least of all a descent direction) exists.
                run.residuals.push(0.0);
                return Ok((at.energy, run.test.record(Criterion::Residual)));
            }
            let chord = run.reuse && !at.hessian;
            let slope = self.direction(problem, x, &mut at, chord, run)?;
            let step = self.search_along_direction(problem, x, slope, &mut at, run)?;
            let retry_shifted = self.shift_after(&step, r, run);
            match step {
                Step::Full { alpha } => {
                    // A full step with fast progress lets the next iteration keep the factorisation.
                    run.reuse = alpha == 1.0
                        && s.linear_solver.kind != LinearSolverKind::Cg
                        && s.reuse_max_ratio.is_some_and(|ratio| run.last_residual() < ratio * r);
                }
                Step::Backtracked { .. } | Step::Relaxed { .. } => run.reuse = false,
                // The old factors gave a poor direction: retry this point with a fresh Newton step.
                Step::Failed if chord => run.reuse = false,
                // The indefinite Hessian's own direction gave no step: retry this point shifted.
                Step::Failed if retry_shifted => run.reuse = false,
                // No step recovers from a relaxed step: go back to where it started.
                Step::Failed if run.relaxed.is_some() => {
                    at = undo_relaxed(problem, x, run);
                    continue;
                }
                Step::Failed if run.test.stagnated(&run.residuals, run.decrement, true) => {
                    return Ok((at.energy, run.test.record(Criterion::Stagnated)));
                }
                Step::Failed => {
                    return Err(NewtonError::LineSearchFailed {
                        iteration: run.iterations,
                        residual: r,
                        residuals: Vec::new(),
                    });
                }
            }
            if matches!(step, Step::Failed) {
                continue;
            }
            self.settle(problem, x, &mut at, run)?;
        }
    }

    /// After an accepted step to `x`: ends a run from a relaxed step that has recovered, rebases the
    /// rotations and lets the energy adapt to the iterate, after which its residual, gradient and
    /// Hessian are evaluated anew.
    fn settle<P: NewtonProblem + ?Sized>(
        &mut self,
        problem: &mut P,
        x: &mut [f64],
        at: &mut Point,
        run: &mut Run,
    ) -> Result<(), NewtonError> {
        if let Some(relaxed) = &mut run.relaxed
            && relaxed.recovered(at.energy)
        {
            run.relaxed = None;
        }
        // Rotations are rebased only outside a run from a relaxed step, whose start must stay in the
        // unknowns it was left in to be restored; the Cayley parameters serve up to a half turn.
        let rebased = run.relaxed.is_none() && problem.rebase(x);
        let adapted = problem.follow_iterate(x);
        if adapted && let Some(relaxed) = &mut run.relaxed {
            relaxed.energy = problem
                .value(&relaxed.start)
                .map_err(|source| problem_error(run.iterations, source))?;
        }
        if rebased || adapted {
            // The same state in other unknowns, or the same unknowns under an adapted energy: its
            // residual, gradient and Hessian are evaluated anew, and the old residual does not count.
            if at.gradient {
                run.residuals.pop();
            }
            at.gradient = false;
            run.reuse = false;
        }
        Ok(())
    }

    /// The line search along the direction just computed, with the mixed-integration-point strain
    /// prediction around it.
    fn search_along_direction<P: NewtonProblem + ?Sized>(
        &mut self,
        problem: &mut P,
        x: &mut [f64],
        slope: f64,
        at: &mut Point,
        run: &mut Run,
    ) -> Result<Step, NewtonError> {
        let mixed = self.settings.mixed_integration_points;
        if mixed {
            problem
                .linearize_strains(x, &self.dx)
                .map_err(|source| problem_error(run.iterations, source))?;
        }
        let step = self.step(problem, x, slope, at, run)?;
        if mixed && let Step::Full { alpha } | Step::Backtracked { alpha } | Step::Relaxed { alpha } = step {
            problem.advance_predicted_strains(alpha);
        }
        Ok(step)
    }

    /// With [`IndefiniteHessian::Adaptive`]: whether `step`, taken along the direction of an unshifted
    /// indefinite Hessian from a point of residual `r`, was shortened or rejected or did not reduce
    /// the residual (Newton's own steps converge only near a solution), so that indefinite Hessians
    /// are shifted from now on in this solve.
    fn shift_after(&mut self, step: &Step, r: f64, run: &mut Run) -> bool {
        let poor = match step {
            Step::Full { .. } | Step::Relaxed { .. } => run.last_residual() >= r,
            Step::Backtracked { .. } | Step::Failed => true,
        };
        run.indefinite && poor && self.shift_from_now(run)
    }

    /// With [`IndefiniteHessian::Adaptive`], and unless it happened before in this solve: shifts
    /// indefinite Hessians from now on in this solve (the linear solver then factorises by Cholesky
    /// alone, as with [`IndefiniteHessian::Shift`]); returns whether it switched.
    fn shift_from_now(&mut self, run: &mut Run) -> bool {
        if self.settings.indefinite_hessian != IndefiniteHessian::Adaptive || run.shift_from_now {
            return false;
        }
        let mut linear = *self.linear.settings();
        linear.kind = LinearSolverKind::Cholesky;
        // The symbolic analyses of `Auto` serve Cholesky as they are: nothing is redone.
        run.shift_from_now = self.linear.set_settings(linear).is_ok();
        run.shift_from_now
    }

    /// Evaluates the initial state: the Hessian with the gradient (see [`Self::solve`]) or the gradient
    /// alone; records the first residual and sets up the convergence test.
    fn start<P: NewtonProblem + ?Sized>(
        &mut self,
        problem: &mut P,
        x: &[f64],
        run: &mut Run,
    ) -> Result<Point, NewtonError> {
        let hessian = self.start_with_hessian && !run.reuse && self.settings.max_iterations > 0;
        let energy = if hessian {
            self.eval_hessian(problem, x, 0, run)?
        } else {
            self.eval_gradient(problem, x, 0, run)?
        };
        let r0 = self.residual(&self.grad);
        run.residuals.push(r0);
        let load = problem.load_scale() / self.settings.residual_scale;
        run.test = match run.measured {
            Some(start) => ConvergenceTest::with_measured_scale(
                self.settings.tolerance,
                load.max(start.load_scale),
                start.energy,
                energy,
            ),
            None => ConvergenceTest::new(self.settings.tolerance, load, r0, energy),
        };
        run.test.observe_reactions(self.reactions());
        if hessian {
            self.estimate_floor(problem, x, run);
        }
        Ok(Point {
            energy,
            gradient: true,
            hessian,
        })
    }

    /// Brings the gradient (and, unless the iterations are used up or the next step is a chord step,
    /// the Hessian) up to date at `x` after a step accepted on its energy alone, and records the
    /// residual.
    fn refresh<P: NewtonProblem + ?Sized>(
        &mut self,
        problem: &mut P,
        x: &[f64],
        at: &mut Point,
        run: &mut Run,
    ) -> Result<(), NewtonError> {
        let k = run.iterations;
        // A chord step needs the gradient alone; if the old factors fail, the direction assembles the
        // Hessian then.
        at.hessian = !run.reuse && k < self.settings.max_iterations;
        at.energy = if at.hessian {
            self.eval_hessian(problem, x, k + 1, run)?
        } else {
            self.eval_gradient(problem, x, k, run)?
        };
        at.gradient = true;
        run.residuals.push(self.residual(&self.grad));
        run.test.observe_reactions(self.reactions());
        run.test.observe_energy(at.energy);
        if at.hessian {
            self.estimate_floor(problem, x, run);
        }
        Ok(())
    }

    /// Estimates the residual's round-off floor from the first Hessian of the solve (with a relative
    /// tolerance only: an absolute one has no floor).
    fn estimate_floor<P: NewtonProblem + ?Sized>(&mut self, problem: &P, x: &[f64], run: &mut Run) {
        if !run.floor_known && matches!(self.settings.tolerance, Tolerance::Relative(_)) {
            run.test.observe_stiffness(self.stiffness_scale(problem, x));
            run.floor_known = true;
        }
    }

    /// Validates settings, dimensions and pattern, and copies the fixed mask.
    fn prepare<P: NewtonProblem + ?Sized>(&mut self, problem: &P, x: &[f64]) -> Result<(), NewtonError> {
        self.settings.validate()?;
        self.linear
            .set_settings(effective_linear_settings(&self.settings))
            .map_err(NewtonError::Setup)?;
        let n = self.linear.n();
        let mismatch = |what, found| NewtonError::DimensionMismatch {
            what,
            expected: n,
            found,
        };
        if problem.n_dofs() != n {
            return Err(mismatch("problem n_dofs", problem.n_dofs()));
        }
        if x.len() != n {
            return Err(mismatch("state x", x.len()));
        }
        if !self.linear.pattern_matches(problem.hessian_pattern()) {
            return Err(NewtonError::PatternChanged);
        }
        let mask = problem.fixed_dofs();
        if let Some(mask) = mask
            && mask.len() != n
        {
            return Err(mismatch("fixed-DOF mask", mask.len()));
        }
        // Carried factors eliminate the unknowns that were fixed when they were computed.
        let same_mask = mask.map_or(!self.has_fixed, |mask| mask == self.fixed.as_slice());
        self.carry_factors &= same_mask
            && self.settings.reuse_max_ratio.is_some()
            && self.settings.linear_solver.kind != LinearSolverKind::Cg;
        match mask {
            Some(mask) => {
                self.fixed.copy_from_slice(mask);
                self.has_fixed = mask.iter().any(|&f| f);
            }
            None => {
                self.fixed.fill(false);
                self.has_fixed = false;
            }
        }
        match self.settings.tolerance {
            Tolerance::Relative(_) => problem.residual_weights(&mut self.weights),
            Tolerance::Absolute(_) => self.weights.fill(1.0),
        }
        Ok(())
    }

    /// The Armijo test of the settings.
    fn armijo(&self) -> ArmijoTest {
        ArmijoTest {
            c: self.settings.armijo_constant,
            noise_resistant: self.settings.noise_resistant_line_search,
        }
    }
}

/// The linear solver's settings for Newton's settings at the start of a solve: with the shift
/// strategy, `Auto` factorises by Cholesky alone (the shift replaces the indefinite and LU fallbacks);
/// the adaptive strategy starts with the fallbacks.
fn effective_linear_settings(settings: &NewtonSettings) -> crate::linear::LinearSolverSettings {
    let mut linear = settings.linear_solver;
    if linear.kind == LinearSolverKind::Auto && settings.indefinite_hessian == IndefiniteHessian::Shift {
        linear.kind = LinearSolverKind::Cholesky;
    }
    linear
}

/// The position of each column's diagonal entry in the values of an upper-triangle pattern (every
/// diagonal entry is stored; the linear solver has checked it).
fn diagonal_slots(pattern: SymbolicSparseColMatRef<'_, usize>) -> Vec<usize> {
    let (col_ptr, row_idx) = (pattern.col_ptr(), pattern.row_idx());
    (0..pattern.ncols())
        .map(|j| {
            (col_ptr[j]..col_ptr[j + 1])
                .find(|&k| row_idx[k] == j)
                .expect("the linear solver accepts only patterns with every diagonal entry")
        })
        .collect()
}

/// Seconds since `t`.
fn since(t: Instant) -> f64 {
    t.elapsed().as_secs_f64()
}
