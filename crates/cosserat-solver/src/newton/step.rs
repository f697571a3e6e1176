//! The line search of an iteration: the full feasible step with its gradient, then backtracking on
//! energies with the (noise-resistant) Armijo test of [`crate::line_search`].

use super::evaluation::{non_finite, problem_error};
use super::{NewtonSolver, Point, Run, Step};
use crate::error::{NewtonError, NonFiniteQuantity, ProblemError};
use crate::problem::NewtonProblem;

impl NewtonSolver {
    /// Moves `x` along `dx` (slope `dx·∇Π`): the full feasible step if it passes the convergence or the
    /// Armijo test, otherwise the first backtracked step that passes Armijo's.
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
        if run.test.accepts(r1)
            || armijo.accepts_with_gradient(at.energy, e1, alpha, slope, &self.dx, &self.grad, &self.grad_trial)
        {
            self.accept_with_gradient(x, run, e1);
            *at = Point::with_gradient(e1);
            return Ok(Step::Full { alpha });
        }
        for _ in 0..self.settings.max_line_search_iterations {
            alpha *= self.settings.backtracking_factor;
            run.report.line_search_backtracks += 1;
            self.set_trial(x, alpha);
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
                return Ok(Step::Backtracked);
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
                return Ok(Step::Backtracked);
            }
        }
        Ok(Step::Failed)
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

fn infeasible(iteration: usize, step_fraction: f64) -> NewtonError {
    NewtonError::InfeasibleStep {
        iteration,
        step_fraction,
        residuals: Vec::new(),
    }
}
