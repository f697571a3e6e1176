//! Newton's method with a backtracking (noise-resistant) Armijo line search for a
//! [`NewtonProblem`] on a fixed sparse Hessian pattern.
//!
//! The algorithm follows the reference code's `NewtonsMethod` (model.md §7.1) without its quirks:
//! - convergence is tested wherever the gradient of an accepted iterate is known (the initial state,
//!   the full feasible Newton step, a line-search point whose gradient was needed, or the start of the
//!   next iteration, where the Hessian assembly returns the gradient anyway), not only after a full
//!   step;
//! - the Armijo bound carries the step length `α`;
//! - `max_iterations` Newton steps are really allowed;
//! - the residual ignores fixed unknowns, whose gradient entries are reaction forces.
//!
//! One iteration: assemble the Hessian and gradient; solve `H dx = −∇Π` with fixed unknowns
//! eliminated (with [`LinearSolverKind::Cg`] inexactly, to the relative residual of the forcing
//! sequence [`NewtonSettings::cg_forcing`]: an inexact, truncated Newton-CG method); flip `dx` if it is not a descent direction (or fail); cap the step by the problem's
//! feasible fraction and halve it until the state is valid; evaluate the gradient at the full feasible
//! step and stop if the residual is below the tolerance; otherwise backtrack until the Armijo test
//! passes. NaN or infinity in any returned quantity is an error, never an accepted state.

use std::time::Instant;

use faer::sparse::SymbolicSparseColMatRef;

use crate::error::{NewtonError, NonFiniteQuantity, ProblemError};
use crate::line_search::ArmijoTest;
use crate::linear::{CgStop, LinearSolverKind, SparseSolver};
use crate::problem::NewtonProblem;
use cosserat_assembly::finite::first_non_finite;

mod report;
mod settings;

pub use report::{FactorisationCounts, NewtonReport};
pub use settings::NewtonSettings;

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
    /// Whether the next solve assembles the Hessian with its first gradient (see [`Self::solve`]).
    start_with_hessian: bool,
}

/// Counters of one solve, turned into a report or an error.
struct Run {
    residuals: Vec<f64>,
    report: NewtonReport,
}

impl Run {
    fn last_residual(&self) -> f64 {
        self.residuals.last().copied().unwrap_or(f64::NAN)
    }

    fn finish(mut self, iterations: usize, energy: f64) -> NewtonReport {
        self.report.iterations = iterations;
        self.report.energy = energy;
        self.report.residuals = self.residuals;
        self.report
    }
}

impl NewtonSolver {
    /// Builds the solver for a Hessian pattern (upper triangle with every diagonal entry).
    ///
    /// # Errors
    /// [`NewtonError::InvalidSetting`] or [`NewtonError::Setup`] if the pattern is malformed.
    pub fn try_new(pattern: SymbolicSparseColMatRef<'_, usize>, settings: NewtonSettings) -> Result<Self, NewtonError> {
        settings.validate()?;
        let linear = SparseSolver::try_new(pattern, settings.linear_solver).map_err(NewtonError::Setup)?;
        let n = linear.n();
        let nnz = linear.nnz();
        Ok(Self {
            settings,
            linear,
            grad: vec![0.0; n],
            grad_trial: vec![0.0; n],
            hess_values: crate::linear::memory::mapped_zeros(nnz),
            dx: vec![0.0; n],
            x_trial: vec![0.0; n],
            fixed: vec![false; n],
            has_fixed: false,
            start_with_hessian: true,
        })
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

    /// The settings.
    pub fn settings(&self) -> &NewtonSettings {
        &self.settings
    }

    /// Mutable access to the settings; they are validated at the next [`solve`](Self::solve), and a
    /// changed linear-solver ordering redoes the symbolic analysis there.
    pub fn settings_mut(&mut self) -> &mut NewtonSettings {
        &mut self.settings
    }

    /// The sparse linear solver (for its statistics).
    pub fn linear_solver(&self) -> &SparseSolver {
        &self.linear
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
        self.prepare(problem, x)?;
        let s = self.settings;
        let armijo = ArmijoTest {
            c: s.armijo_constant,
            noise_resistant: s.noise_resistant_line_search,
        };
        let mut run = Run {
            residuals: Vec::with_capacity(s.max_iterations + 1),
            report: NewtonReport {
                iterations: 0,
                residuals: Vec::new(),
                energy: f64::NAN,
                line_search_backtracks: 0,
                chord_iterations: 0,
                feasibility_halvings: 0,
                direction_flips: 0,
                factorisations: FactorisationCounts::default(),
                cg_iterations: 0,
                cg_negative_curvature_stops: 0,
                cg_iteration_cap_stops: 0,
                assembly_seconds: 0.0,
                evaluation_seconds: 0.0,
                linear_solve_seconds: 0.0,
                factorisation_seconds: 0.0,
            },
        };

        // A solve seldom starts at a solution (a time step starts at its predictor), so the first
        // Hessian is assembled at once and its gradient gives the first residual: one gradient
        // evaluation less per solve. After a solve that stopped where it started, the next one
        // evaluates the gradient alone first, so that a state at rest does not pay for a Hessian.
        let mut hessian_at_x = None;
        let energy = if self.start_with_hessian && s.max_iterations > 0 {
            let e = self.eval_hessian(problem, x, 0, &mut run)?;
            hessian_at_x = Some(e);
            e
        } else {
            self.eval_gradient(problem, x, 0, &mut run)?
        };
        let r = self.residual(&self.grad);
        run.residuals.push(r);
        let converged_at_start = r < s.residual_tolerance && s.min_iterations == 0;
        self.start_with_hessian = !converged_at_start;
        if converged_at_start {
            return Ok(run.finish(0, energy));
        }
        // Whether `grad` holds ∇Π(x) and the last residual belongs to `x`.
        let mut grad_current = true;
        // Energy at `x` while `grad_current` (for chord steps, which do not reassemble).
        let mut energy_current = energy;
        // Whether the next iteration may reuse the last factorisation (see `reuse_max_ratio`).
        let mut reuse_next = false;
        let mut k = 0;
        loop {
            if k == s.max_iterations {
                if !grad_current {
                    let energy = self.eval_gradient(problem, x, k, &mut run)?;
                    let r = self.residual(&self.grad);
                    run.residuals.push(r);
                    if r < s.residual_tolerance && k >= s.min_iterations {
                        return Ok(run.finish(k, energy));
                    }
                }
                return Err(NewtonError::MaxIterations {
                    iterations: k,
                    residuals: run.residuals,
                });
            }
            k += 1;

            let chord = reuse_next && grad_current;
            let e0 = match (chord, hessian_at_x.take()) {
                (true, _) => energy_current,
                (false, Some(e)) => e,
                (false, None) => self.eval_hessian(problem, x, k, &mut run)?,
            };
            if !grad_current {
                let r = self.residual(&self.grad);
                run.residuals.push(r);
                grad_current = true;
                if r < s.residual_tolerance && k > s.min_iterations {
                    return Ok(run.finish(k - 1, e0));
                }
            }
            let r0 = run.last_residual();
            if r0 == 0.0 {
                // Exactly stationary: the Newton step is zero whatever the Hessian, and no direction
                // (least of all a descent direction) exists.
                run.residuals.push(0.0);
                return Ok(run.finish(k, e0));
            }

            let slope = match chord.then(|| self.chord_direction(k, &mut run)) {
                Some(Ok(slope)) => {
                    run.report.chord_iterations += 1;
                    slope
                }
                // No chord step, or an unusable one: a full Newton step from the same point.
                other => {
                    if other.is_some() {
                        self.eval_hessian(problem, x, k, &mut run)?;
                    }
                    self.newton_direction(k, &mut run)?
                }
            };
            let mut alpha = self.feasible_fraction(problem, x, k, &mut run)?;

            // The full feasible step, with its gradient: halve while the state is invalid.
            let e1 = loop {
                self.set_trial(x, alpha);
                match self.eval_trial_gradient(problem, &mut run) {
                    Ok(e) => break e,
                    Err(ProblemError::InvalidState { .. }) => {
                        alpha *= 0.5;
                        run.report.feasibility_halvings += 1;
                        if alpha < s.min_step_fraction {
                            return Err(NewtonError::InfeasibleStep {
                                iteration: k,
                                step_fraction: alpha,
                                residuals: run.residuals,
                            });
                        }
                    }
                    Err(source) => {
                        return Err(NewtonError::Problem {
                            iteration: k,
                            source,
                            residuals: run.residuals,
                        });
                    }
                }
            };
            self.check_energy(e1, k, &run)?;
            self.check_gradient(&self.grad_trial, k, &run)?;
            let r1 = self.residual(&self.grad_trial);
            if r1 < s.residual_tolerance
                || armijo.accepts_with_gradient(e0, e1, alpha, slope, &self.dx, &self.grad, &self.grad_trial)
            {
                self.accept_with_gradient(x, &mut run, r1);
                if r1 < s.residual_tolerance && k >= s.min_iterations {
                    return Ok(run.finish(k, e1));
                }
                energy_current = e1;
                // A full step with fast progress lets the next iteration keep the factorisation.
                reuse_next = alpha == 1.0
                    && s.linear_solver.kind != LinearSolverKind::Cg
                    && s.reuse_max_ratio.is_some_and(|ratio| r1 < ratio * r0);
                continue;
            }

            // Backtracking.
            let mut accepted = false;
            for _ in 0..s.max_line_search_iterations {
                alpha *= s.backtracking_factor;
                run.report.line_search_backtracks += 1;
                self.set_trial(x, alpha);
                let e = match self.eval_trial_value(problem, &mut run) {
                    Ok(e) => e,
                    Err(ProblemError::InvalidState { .. }) => continue,
                    Err(source) => {
                        return Err(NewtonError::Problem {
                            iteration: k,
                            source,
                            residuals: run.residuals,
                        });
                    }
                };
                self.check_energy(e, k, &run)?;
                if armijo.sufficient_decrease(e0, e, alpha, slope) {
                    x.copy_from_slice(&self.x_trial);
                    grad_current = false;
                    reuse_next = false;
                    accepted = true;
                    break;
                }
                if armijo.in_noise_regime(e0, e) {
                    let e = match self.eval_trial_gradient(problem, &mut run) {
                        Ok(e) => e,
                        Err(ProblemError::InvalidState { .. }) => continue,
                        Err(source) => {
                            return Err(NewtonError::Problem {
                                iteration: k,
                                source,
                                residuals: run.residuals,
                            });
                        }
                    };
                    self.check_energy(e, k, &run)?;
                    self.check_gradient(&self.grad_trial, k, &run)?;
                    if armijo.estimated_decrease(alpha, slope, &self.dx, &self.grad, &self.grad_trial) {
                        let r = self.residual(&self.grad_trial);
                        self.accept_with_gradient(x, &mut run, r);
                        grad_current = true;
                        energy_current = e;
                        reuse_next = false;
                        accepted = true;
                        if r < s.residual_tolerance && k >= s.min_iterations {
                            return Ok(run.finish(k, e));
                        }
                        break;
                    }
                }
            }
            if !accepted && chord {
                // The old factors gave a poor direction: retry this point with a fresh Newton step.
                reuse_next = false;
                continue;
            }
            if !accepted {
                return Err(NewtonError::LineSearchFailed {
                    iteration: k,
                    residual: r0,
                    residuals: run.residuals,
                });
            }
        }
    }

    /// Validates settings, dimensions and pattern, and copies the fixed mask.
    fn prepare<P: NewtonProblem + ?Sized>(&mut self, problem: &P, x: &[f64]) -> Result<(), NewtonError> {
        self.settings.validate()?;
        self.linear
            .set_settings(self.settings.linear_solver)
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
        match problem.fixed_dofs() {
            Some(mask) if mask.len() != n => return Err(mismatch("fixed-DOF mask", mask.len())),
            Some(mask) => {
                self.fixed.copy_from_slice(mask);
                self.has_fixed = mask.iter().any(|&f| f);
            }
            None => {
                self.fixed.fill(false);
                self.has_fixed = false;
            }
        }
        Ok(())
    }

    /// `max_i |g_i| / scale` over free unknowns.
    fn residual(&self, g: &[f64]) -> f64 {
        let max = g
            .iter()
            .zip(&self.fixed)
            .filter(|(_, f)| !**f)
            .fold(0.0_f64, |m, (v, _)| m.max(v.abs()));
        max / self.settings.residual_scale
    }

    fn check_energy(&self, e: f64, iteration: usize, run: &Run) -> Result<(), NewtonError> {
        if e.is_finite() {
            Ok(())
        } else {
            Err(NewtonError::NonFinite {
                iteration,
                quantity: NonFiniteQuantity::Energy,
                index: None,
                residuals: run.residuals.clone(),
            })
        }
    }

    fn check_gradient(&self, g: &[f64], iteration: usize, run: &Run) -> Result<(), NewtonError> {
        match first_non_finite(g) {
            None => Ok(()),
            Some(i) => Err(NewtonError::NonFinite {
                iteration,
                quantity: NonFiniteQuantity::Gradient,
                index: Some(i),
                residuals: run.residuals.clone(),
            }),
        }
    }

    /// Energy and gradient at `x` into `grad`, checked.
    fn eval_gradient<P: NewtonProblem + ?Sized>(
        &mut self,
        problem: &mut P,
        x: &[f64],
        iteration: usize,
        run: &mut Run,
    ) -> Result<f64, NewtonError> {
        self.grad.fill(0.0);
        let t = Instant::now();
        let result = problem.gradient(x, &mut self.grad);
        run.report.evaluation_seconds += t.elapsed().as_secs_f64();
        let e = result.map_err(|source| NewtonError::Problem {
            iteration,
            source,
            residuals: run.residuals.clone(),
        })?;
        self.check_energy(e, iteration, run)?;
        self.check_gradient(&self.grad, iteration, run)?;
        Ok(e)
    }

    /// Energy, gradient and Hessian at `x`, checked.
    fn eval_hessian<P: NewtonProblem + ?Sized>(
        &mut self,
        problem: &mut P,
        x: &[f64],
        iteration: usize,
        run: &mut Run,
    ) -> Result<f64, NewtonError> {
        self.grad.fill(0.0);
        self.hess_values.fill(0.0);
        let t = Instant::now();
        let result = problem.hessian(x, &mut self.grad, &mut self.hess_values);
        run.report.assembly_seconds += t.elapsed().as_secs_f64();
        let e = result.map_err(|source| NewtonError::Problem {
            iteration,
            source,
            residuals: run.residuals.clone(),
        })?;
        self.check_energy(e, iteration, run)?;
        self.check_gradient(&self.grad, iteration, run)?;
        if let Some(i) = first_non_finite(&self.hess_values) {
            return Err(NewtonError::NonFinite {
                iteration,
                quantity: NonFiniteQuantity::Hessian,
                index: Some(i),
                residuals: run.residuals.clone(),
            });
        }
        Ok(e)
    }

    /// Solves `H dx = −∇Π` (with CG to the forcing tolerance), makes `dx` a descent direction and
    /// returns the slope `dx·∇Π < 0`.
    fn newton_direction(&mut self, iteration: usize, run: &mut Run) -> Result<f64, NewtonError> {
        for (d, g) in self.dx.iter_mut().zip(&self.grad) {
            *d = -g;
        }
        let t = Instant::now();
        let fixed = self.has_fixed.then_some(self.fixed.as_slice());
        let cg = self.settings.linear_solver.kind == LinearSolverKind::Cg;
        let tolerance = if cg {
            let g_norm = self
                .grad
                .iter()
                .zip(&self.fixed)
                .filter(|(_, f)| !**f)
                .map(|(g, _)| g * g)
                .sum::<f64>()
                .sqrt();
            self.linear.set_cg_relative_tolerance(
                self.settings
                    .cg_forcing
                    .relative_tolerance(g_norm / self.settings.residual_scale),
            )
        } else {
            Ok(())
        };
        let result = tolerance
            .and_then(|()| {
                let t_factor = Instant::now();
                let factorised = self.linear.factorise(&self.hess_values, fixed);
                run.report.factorisation_seconds += t_factor.elapsed().as_secs_f64();
                factorised
            })
            .and_then(|_| self.linear.solve_in_place(&mut self.dx));
        run.report.linear_solve_seconds += t.elapsed().as_secs_f64();
        let used = result.map_err(|source| NewtonError::LinearSolve {
            iteration,
            source,
            residuals: run.residuals.clone(),
        })?;
        run.report.factorisations.record(used);
        if let Some(cg) = self.linear.last_cg_report() {
            run.report.cg_iterations += cg.iterations;
            match cg.stop {
                CgStop::NegativeCurvature => run.report.cg_negative_curvature_stops += 1,
                CgStop::IterationCap => run.report.cg_iteration_cap_stops += 1,
                CgStop::Converged => {}
            }
        }
        let mut slope: f64 = self.dx.iter().zip(&self.grad).map(|(d, g)| d * g).sum();
        if slope > 0.0 && self.settings.flip_on_non_descent {
            self.dx.iter_mut().for_each(|d| *d = -*d);
            slope = -slope;
            run.report.direction_flips += 1;
        }
        // A zero slope (a direction orthogonal to a non-zero gradient) cannot decrease the energy.
        if slope < 0.0 {
            Ok(slope)
        } else {
            Err(NewtonError::NotDescent {
                iteration,
                slope,
                residuals: run.residuals.clone(),
            })
        }
    }

    /// A chord direction: solves with the factors of an earlier iteration (no new factorisation).
    fn chord_direction(&mut self, iteration: usize, run: &mut Run) -> Result<f64, NewtonError> {
        for (d, g) in self.dx.iter_mut().zip(&self.grad) {
            *d = -g;
        }
        let t = Instant::now();
        let result = self.linear.solve_in_place(&mut self.dx);
        run.report.linear_solve_seconds += t.elapsed().as_secs_f64();
        result.map_err(|source| NewtonError::LinearSolve {
            iteration,
            source,
            residuals: run.residuals.clone(),
        })?;
        let slope: f64 = self.dx.iter().zip(&self.grad).map(|(d, g)| d * g).sum();
        if slope < 0.0 {
            Ok(slope)
        } else {
            Err(NewtonError::NotDescent {
                iteration,
                slope,
                residuals: run.residuals.clone(),
            })
        }
    }

    /// The problem's feasible step fraction, capped at 1 and checked against the minimum.
    fn feasible_fraction<P: NewtonProblem + ?Sized>(
        &mut self,
        problem: &mut P,
        x: &[f64],
        iteration: usize,
        run: &mut Run,
    ) -> Result<f64, NewtonError> {
        let alpha = problem.max_step_fraction(x, &self.dx);
        if alpha.is_nan() {
            return Err(NewtonError::NonFinite {
                iteration,
                quantity: NonFiniteQuantity::StepFraction,
                index: None,
                residuals: run.residuals.clone(),
            });
        }
        let alpha = alpha.min(1.0);
        if alpha < self.settings.min_step_fraction {
            return Err(NewtonError::InfeasibleStep {
                iteration,
                step_fraction: alpha,
                residuals: run.residuals.clone(),
            });
        }
        Ok(alpha)
    }

    /// `x_trial = x + α dx`.
    fn set_trial(&mut self, x: &[f64], alpha: f64) {
        for ((t, xi), d) in self.x_trial.iter_mut().zip(x).zip(&self.dx) {
            *t = xi + alpha * d;
        }
    }

    /// Energy and gradient at `x_trial` into `grad_trial`, unchecked.
    fn eval_trial_gradient<P: NewtonProblem + ?Sized>(
        &mut self,
        problem: &mut P,
        run: &mut Run,
    ) -> Result<f64, ProblemError> {
        self.grad_trial.fill(0.0);
        let t = Instant::now();
        let result = problem.gradient(&self.x_trial, &mut self.grad_trial);
        run.report.evaluation_seconds += t.elapsed().as_secs_f64();
        result
    }

    /// Energy at `x_trial`, unchecked.
    fn eval_trial_value<P: NewtonProblem + ?Sized>(
        &mut self,
        problem: &mut P,
        run: &mut Run,
    ) -> Result<f64, ProblemError> {
        let t = Instant::now();
        let result = problem.value(&self.x_trial);
        run.report.evaluation_seconds += t.elapsed().as_secs_f64();
        result
    }

    /// Accepts `x_trial` together with its gradient and records its residual.
    fn accept_with_gradient(&mut self, x: &mut [f64], run: &mut Run, residual: f64) {
        x.copy_from_slice(&self.x_trial);
        std::mem::swap(&mut self.grad, &mut self.grad_trial);
        run.residuals.push(residual);
    }
}
