//! The line search of an iteration: the full feasible step with its gradient, then (with mixed
//! integration points, as a relaxed step, see the `relaxed` module) the full step anyway, or
//! backtracking on energies with the (noise-resistant) Armijo test of [`crate::line_search`].

use super::evaluation::{non_finite, problem_error};
use super::{NewtonSolver, Point, Relaxed, Run, Step};
use crate::error::{NewtonError, NonFiniteQuantity, ProblemError};
use crate::problem::NewtonProblem;

impl NewtonSolver {
    /// Moves `x` along `dx` (slope `dx·∇Π`): the full feasible step if it passes the convergence or the
    /// Armijo test or may be a relaxed step, otherwise the first backtracked step that passes Armijo's.
    pub(super) fn step<P: NewtonProblem + ?Sized>(
        &mut self,
        problem: &mut P,
        x: &mut [f64],
        slope: f64,
        at: &mut Point,
        run: &mut Run,
    ) -> Result<Step, NewtonError> {
        let k = run.iterations;
        let armijo = self.armijo();
        let mut alpha = self.feasible_fraction(problem, x, k)?;
        let e1 = self.full_step(problem, x, &mut alpha, k, run)?;
        let r1 = self.residual(&self.grad_trial);
        if run.test.accepts(r1) {
            self.accept_with_gradient(x, run, e1);
            *at = Point::with_gradient(e1);
            return Ok(Step::Full { alpha });
        }
        if armijo.accepts_with_gradient(at.energy, e1, alpha, slope, &self.dx, &self.grad, &self.grad_trial) {
            if run.shifted
                && let Some((beta, e)) = self.extrapolate(problem, x, at.energy, alpha, e1, slope, run)
            {
                for (x, d) in x.iter_mut().zip(&self.dx) {
                    *x += beta * d;
                }
                run.test.observe_energy(e);
                *at = Point::without_gradient(e);
                return Ok(Step::Backtracked { alpha: beta });
            }
            self.accept_with_gradient(x, run, e1);
            *at = Point::with_gradient(e1);
            return Ok(Step::Full { alpha });
        }
        if self.may_relax(run, slope) {
            run.relaxed = Some(Relaxed::new(x, at.energy));
            run.report.relaxed_steps += 1;
            self.accept_with_gradient(x, run, e1);
            *at = Point::with_gradient(e1);
            return Ok(Step::Relaxed { alpha });
        }
        for _ in 0..self.settings.max_line_search_iterations {
            alpha *= self.settings.backtracking_factor;
            run.report.line_search_backtracks += 1;
            self.set_trial(x, alpha);
            problem.cross_singularities(x, &mut self.x_trial);
            let e = match self.eval_trial_value(problem, run) {
                Ok(e) => e,
                Err(ProblemError::InvalidState { .. }) => continue,
                Err(source) => return Err(problem_error(k, source)),
            };
            self.check_energy(e, k)?;
            if armijo.sufficient_decrease(at.energy, e, alpha, slope) {
                x.copy_from_slice(&self.x_trial);
                run.test.observe_energy(e);
                *at = Point::without_gradient(e);
                return Ok(Step::Backtracked { alpha });
            }
            if !armijo.in_noise_regime(at.energy, e) {
                continue;
            }
            let e = match self.eval_trial_gradient(problem, run) {
                Ok(e) => e,
                Err(ProblemError::InvalidState { .. }) => continue,
                Err(source) => return Err(problem_error(k, source)),
            };
            self.check_energy(e, k)?;
            self.check_gradient(&self.grad_trial, k)?;
            if armijo.estimated_decrease(alpha, slope, &self.dx, &self.grad, &self.grad_trial) {
                self.accept_with_gradient(x, run, e);
                *at = Point::with_gradient(e);
                return Ok(Step::Backtracked { alpha });
            }
        }
        Ok(Step::Failed)
    }

    /// Along a direction from a shifted (indefinite) Hessian whose step `α` passed: doubles the step
    /// while the energy keeps decreasing (Armijo from `x`), up to [`MAX_EXTRAPOLATIONS`] times, and
    /// returns the best longer step and its energy, if one is better. Along negative curvature the
    /// energy falls faster than the shifted model predicts, and the shift's step is too short (see
    /// `direction.rs`): without this, escaping a saddle takes many short steps.
    fn extrapolate<P: NewtonProblem + ?Sized>(
        &mut self,
        problem: &mut P,
        x: &[f64],
        e0: f64,
        alpha: f64,
        e_alpha: f64,
        slope: f64,
        run: &mut Run,
    ) -> Option<(f64, f64)> {
        let armijo = self.armijo();
        let mut best = (alpha, e_alpha);
        let mut extra = std::mem::take(&mut self.x_extra);
        extra.resize(x.len(), 0.0);
        for _ in 0..MAX_EXTRAPOLATIONS {
            let beta = 2.0 * best.0;
            for ((t, xi), d) in extra.iter_mut().zip(x).zip(&self.dx) {
                *t = xi + beta * d;
            }
            problem.cross_singularities(x, &mut extra);
            if problem.max_step_fraction(x, &extra_step(&self.dx, beta)) < 1.0 {
                break;
            }
            let t = std::time::Instant::now();
            let e = problem.value(&extra);
            run.report.evaluation_seconds += t.elapsed().as_secs_f64();
            match e {
                Ok(e) if e.is_finite() && e < best.1 && armijo.sufficient_decrease(e0, e, beta, slope) => {
                    best = (beta, e);
                    run.report.extrapolations += 1;
                }
                _ => break,
            }
        }
        self.x_extra = extra;
        (best.0 > alpha).then_some(best)
    }

    /// The full step `x + α dx` with its gradient in `grad_trial`, `α` halved while the state is
    /// invalid; returns the energy there.
    fn full_step<P: NewtonProblem + ?Sized>(
        &mut self,
        problem: &mut P,
        x: &[f64],
        alpha: &mut f64,
        iteration: usize,
        run: &mut Run,
    ) -> Result<f64, NewtonError> {
        loop {
            self.set_trial(x, *alpha);
            problem.cross_singularities(x, &mut self.x_trial);
            match self.eval_trial_gradient(problem, run) {
                Ok(e) => {
                    self.check_energy(e, iteration)?;
                    self.check_gradient(&self.grad_trial, iteration)?;
                    return Ok(e);
                }
                Err(ProblemError::InvalidState { .. }) => {
                    *alpha *= 0.5;
                    run.report.feasibility_halvings += 1;
                    if *alpha < self.settings.min_step_fraction {
                        return Err(infeasible(iteration, *alpha));
                    }
                }
                Err(source) => return Err(problem_error(iteration, source)),
            }
        }
    }

    /// The problem's feasible step fraction, capped at 1 and checked against the minimum.
    fn feasible_fraction<P: NewtonProblem + ?Sized>(
        &mut self,
        problem: &mut P,
        x: &[f64],
        iteration: usize,
    ) -> Result<f64, NewtonError> {
        let alpha = problem.max_step_fraction(x, &self.dx);
        if alpha.is_nan() {
            return Err(non_finite(iteration, NonFiniteQuantity::StepFraction, None));
        }
        let alpha = alpha.min(1.0);
        if alpha < self.settings.min_step_fraction {
            return Err(infeasible(iteration, alpha));
        }
        Ok(alpha)
    }
}

impl Point {
    /// An accepted iterate whose gradient is in `grad`.
    fn with_gradient(energy: f64) -> Self {
        Self {
            energy,
            gradient: true,
            hessian: false,
        }
    }

    /// An accepted iterate known by its energy alone.
    fn without_gradient(energy: f64) -> Self {
        Self {
            energy,
            gradient: false,
            hessian: false,
        }
    }
}

/// At most this many doublings of a step along negative curvature.
const MAX_EXTRAPOLATIONS: usize = 6;

/// `β dx`.
fn extra_step(dx: &[f64], beta: f64) -> Vec<f64> {
    dx.iter().map(|d| beta * d).collect()
}

fn infeasible(iteration: usize, step_fraction: f64) -> NewtonError {
    NewtonError::InfeasibleStep {
        iteration,
        step_fraction,
        residuals: Vec::new(),
    }
}
