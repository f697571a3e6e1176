//! The problem's evaluations as Newton's method sees them: timed, checked for non-finite values, and
//! reduced to the residual, the reactions and the stiffness behind the round-off floor.

use std::time::Instant;

use super::{NewtonSolver, Run, since};
use crate::error::{NewtonError, NonFiniteQuantity, ProblemError};
use crate::problem::NewtonProblem;
use cosserat_assembly::finite::first_non_finite;
use faer::sparse::SymbolicSparseColMatRef;

impl NewtonSolver {
    /// `max_i w_i |g_i| / scale` over free unknowns (`w` the residual weights).
    pub(super) fn residual(&self, g: &[f64]) -> f64 {
        weighted_max_abs(g, &self.weights, &self.fixed, false) / self.settings.residual_scale
    }

    /// The largest reaction `max_i w_i |∂Π/∂x_i| / scale` over fixed unknowns at the current iterate.
    pub(super) fn reactions(&self) -> f64 {
        if !self.has_fixed {
            return 0.0;
        }
        weighted_max_abs(&self.grad, &self.weights, &self.fixed, true) / self.settings.residual_scale
    }

    /// `max_i Σ_j |H_ij| m_j / scale` over free rows `i`, with the problem's magnitudes `m` of the
    /// unknowns at `x`: the size of the terms whose round-off makes the residual's floor.
    pub(super) fn stiffness_scale<P: NewtonProblem + ?Sized>(&mut self, problem: &P, x: &[f64]) -> f64 {
        let (magnitudes, sums) = &mut self.scratch;
        problem.unknown_magnitudes(x, magnitudes);
        let max = round_off_scale(
            problem.hessian_pattern(),
            &self.hess_values,
            magnitudes,
            sums,
            &self.weights,
            &self.fixed,
        );
        max / self.settings.residual_scale
    }

    pub(super) fn check_energy(&self, e: f64, iteration: usize) -> Result<(), NewtonError> {
        if e.is_finite() {
            Ok(())
        } else {
            Err(non_finite(iteration, NonFiniteQuantity::Energy, None))
        }
    }

    pub(super) fn check_gradient(&self, g: &[f64], iteration: usize) -> Result<(), NewtonError> {
        match first_non_finite(g) {
            None => Ok(()),
            Some(i) => Err(non_finite(iteration, NonFiniteQuantity::Gradient, Some(i))),
        }
    }

    /// Energy and gradient at `x` into `grad`, checked.
    pub(super) fn eval_gradient<P: NewtonProblem + ?Sized>(
        &mut self,
        problem: &mut P,
        x: &[f64],
        iteration: usize,
        run: &mut Run,
    ) -> Result<f64, NewtonError> {
        self.grad.fill(0.0);
        let t = Instant::now();
        let result = problem.gradient(x, &mut self.grad);
        run.report.evaluation_seconds += since(t);
        let e = result.map_err(|source| problem_error(iteration, source))?;
        self.check_energy(e, iteration)?;
        self.check_gradient(&self.grad, iteration)?;
        Ok(e)
    }

    /// Energy, gradient and Hessian at `x`, checked.
    pub(super) fn eval_hessian<P: NewtonProblem + ?Sized>(
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
        run.report.assembly_seconds += since(t);
        let e = result.map_err(|source| problem_error(iteration, source))?;
        self.check_energy(e, iteration)?;
        self.check_gradient(&self.grad, iteration)?;
        match first_non_finite(&self.hess_values) {
            Some(i) => Err(non_finite(iteration, NonFiniteQuantity::Hessian, Some(i))),
            None => Ok(e),
        }
    }

    /// `x_trial = x + α dx`.
    pub(super) fn set_trial(&mut self, x: &[f64], alpha: f64) {
        for ((t, xi), d) in self.x_trial.iter_mut().zip(x).zip(&self.dx) {
            *t = xi + alpha * d;
        }
    }

    /// Energy and gradient at `x_trial` into `grad_trial`, unchecked.
    pub(super) fn eval_trial_gradient<P: NewtonProblem + ?Sized>(
        &mut self,
        problem: &mut P,
        run: &mut Run,
    ) -> Result<f64, ProblemError> {
        self.grad_trial.fill(0.0);
        let t = Instant::now();
        let result = problem.gradient(&self.x_trial, &mut self.grad_trial);
        run.report.evaluation_seconds += since(t);
        result
    }

    /// Energy at `x_trial`, unchecked.
    pub(super) fn eval_trial_value<P: NewtonProblem + ?Sized>(
        &mut self,
        problem: &mut P,
        run: &mut Run,
    ) -> Result<f64, ProblemError> {
        let t = Instant::now();
        let result = problem.value(&self.x_trial);
        run.report.evaluation_seconds += since(t);
        result
    }

    /// Accepts `x_trial` together with its gradient and records its residual and reactions.
    pub(super) fn accept_with_gradient(&mut self, x: &mut [f64], run: &mut Run, energy: f64) {
        x.copy_from_slice(&self.x_trial);
        std::mem::swap(&mut self.grad, &mut self.grad_trial);
        run.residuals.push(self.residual(&self.grad));
        run.test.observe_reactions(self.reactions());
        run.test.observe_energy(energy);
    }
}

/// `max_i w_i Σ_j |H_ij| m_j` over free rows `i` of the symmetric matrix whose upper triangle is
/// `values` on `pattern` (`w` the residual weights), with `sums` as scratch (length `n`).
pub(crate) fn round_off_scale(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    values: &[f64],
    magnitudes: &[f64],
    sums: &mut [f64],
    weights: &[f64],
    fixed: &[bool],
) -> f64 {
    sums.fill(0.0);
    let (col_ptr, row_idx) = (pattern.col_ptr(), pattern.row_idx());
    for j in 0..sums.len() {
        for k in col_ptr[j]..col_ptr[j + 1] {
            let (i, h) = (row_idx[k], values[k].abs());
            sums[i] += h * magnitudes[j];
            if i != j {
                sums[j] += h * magnitudes[i];
            }
        }
    }
    weighted_max_abs(sums, weights, fixed, false)
}

/// `max_i w_i |v_i|` over the unknowns with `fixed_i == of_fixed`.
pub(crate) fn weighted_max_abs(v: &[f64], weights: &[f64], fixed: &[bool], of_fixed: bool) -> f64 {
    v.iter()
        .zip(weights)
        .zip(fixed)
        .filter(|(_, f)| **f == of_fixed)
        .fold(0.0_f64, |m, ((v, w), _)| m.max(w * v.abs()))
}

/// A problem's own error in an iteration (its residual history is attached when the solve ends).
pub(super) fn problem_error(iteration: usize, source: ProblemError) -> NewtonError {
    NewtonError::Problem {
        iteration,
        source,
        residuals: Vec::new(),
    }
}

/// A non-finite quantity in an iteration.
pub(super) fn non_finite(iteration: usize, quantity: NonFiniteQuantity, index: Option<usize>) -> NewtonError {
    NewtonError::NonFinite {
        iteration,
        quantity,
        index,
        residuals: Vec::new(),
    }
}
