//! The direction of an iteration: Newton's, from the Hessian itself or, when it is not positive
//! definite, from the Hessian shifted to positive definiteness
//! ([`IndefiniteHessian`](super::IndefiniteHessian) says when), or a chord step with the factors of an
//! earlier iteration.
//!
//! The shift is Levenberg's with Marquardt's scaling: `H + μ D` with `D = |diag H|`, so that it acts
//! alike on unknowns of different units (velocities and angular velocities). `μ` runs through factors of
//! [`SHIFT_GROWTH`] from a fraction of the last shift that worked (or [`MIN_SHIFT`]), so that a run
//! of indefinite Hessians costs about two extra Cholesky attempts each. The shifted step is a descent direction whose
//! length shrinks and whose direction turns towards the scaled gradient as `μ` grows: the model
//! minimiser of a trust region whose radius the line search then adjusts. An unshifted indefinite
//! factorisation, by contrast, solves for the stationary point of the quadratic model: near a solution
//! that is itself a saddle (massless rotations) it converges quadratically, where a descent method
//! cannot settle, but far from one its direction (negated when it ascends) can be nearly orthogonal to
//! the gradient; on the coiling strip of the stability matrix such directions stall the line search
//! (docs/stability.md).

use std::time::Instant;

use super::{NewtonSolver, Point, Run, since};
use crate::error::{Factorisation, LinearSolveError, NewtonError};
use crate::linear::{CgStop, LinearSolverKind};
use crate::problem::NewtonProblem;

/// The smallest shift tried.
const MIN_SHIFT: f64 = 1e-6;

/// The factor between the shifts tried. The shift found exceeds the smallest that works by up to this
/// factor, and the step along a direction of negative curvature `−|κ|` is about
/// `|g|/(μ D − |κ|)`: a coarse grid over-damps the escape from a saddle, a fine one costs failed
/// factorisations.
const SHIFT_GROWTH: f64 = 4.0;

/// Beyond this shift `H + μ D` is diagonally dominant for any Hessian met in practice; one that is
/// still not positive definite fails the iteration.
const MAX_SHIFT: f64 = 1e8;

/// Diagonal entries below this fraction of the largest diagonal entry are shifted as if they had it.
const MIN_RELATIVE_DIAGONAL: f64 = 1e-8;

impl NewtonSolver {
    /// The direction `dx` at `x` and its slope `dx·∇Π < 0`: a chord step when `chord` and the old
    /// factors give a descent direction, otherwise Newton's from the Hessian at `x` (assembled here
    /// unless `at` holds it).
    pub(super) fn direction<P: NewtonProblem + ?Sized>(
        &mut self,
        problem: &mut P,
        x: &[f64],
        at: &mut Point,
        chord: bool,
        run: &mut Run,
    ) -> Result<f64, NewtonError> {
        let k = run.iterations;
        run.decrement = None;
        run.shifted = false;
        run.indefinite = false;
        if chord && let Some(slope) = self.chord_direction(run) {
            run.report.chord_iterations += 1;
            return Ok(slope);
        }
        if !at.hessian {
            at.energy = self.eval_hessian(problem, x, k, run)?;
            self.estimate_floor(problem, x, run);
        }
        at.hessian = false;
        let (mut shifted, mut used) = (self.factorise(k, run)?, self.solve_direction(k, run)?);
        let mut slope = dot(&self.dx, &self.grad);
        // An indefinite Hessian's own step that ascends heads for a maximum or a saddle the energy
        // does not lead to: with the adaptive treatment, this point is solved again shifted.
        if slope > 0.0 && !shifted && used != Factorisation::Llt && self.shift_from_now(run) {
            (shifted, used) = (self.factorise(k, run)?, self.solve_direction(k, run)?);
            slope = dot(&self.dx, &self.grad);
        }
        let flipped = slope > 0.0 && self.settings.flip_on_non_descent;
        if flipped {
            self.dx.iter_mut().for_each(|d| *d = -*d);
            slope = -slope;
            run.report.direction_flips += 1;
        }
        // A zero slope (a direction orthogonal to a non-zero gradient) cannot decrease the energy.
        if slope >= 0.0 {
            return Err(NewtonError::NotDescent {
                iteration: k,
                slope,
                residuals: Vec::new(),
            });
        }
        if !shifted && !flipped && matches!(used, Factorisation::Llt) {
            run.decrement = Some(-slope);
        }
        run.shifted = shifted;
        run.indefinite = !shifted && matches!(used, Factorisation::Lblt | Factorisation::Lu);
        Ok(slope)
    }

    /// Factorises the Hessian, shifting it when it is not positive definite and the settings allow;
    /// returns whether it was shifted.
    fn factorise(&mut self, iteration: usize, run: &mut Run) -> Result<bool, NewtonError> {
        let t = Instant::now();
        let fixed = self.has_fixed.then_some(self.fixed.as_slice());
        let mut result = self.linear.factorise(&self.hess_values, fixed);
        let shift = self.settings.linear_solver.kind == LinearSolverKind::Auto
            && self.linear.settings().kind == LinearSolverKind::Cholesky;
        let shifted = shift && matches!(result, Err(LinearSolveError::NotPositiveDefinite { .. }));
        if shifted {
            run.report.shifted_iterations += 1;
            result = self.factorise_shifted();
        }
        let seconds = since(t);
        run.report.factorisation_seconds += seconds;
        run.report.linear_solve_seconds += seconds;
        result.map(|_| shifted).map_err(|source| NewtonError::LinearSolve {
            iteration,
            source,
            residuals: Vec::new(),
        })
    }

    /// Cholesky of `H + μ D` for the smallest `μ` tried that makes it positive definite (see the module
    /// documentation), up to [`MAX_SHIFT`].
    fn factorise_shifted(&mut self) -> Result<Factorisation, LinearSolveError> {
        let fixed = self.has_fixed.then_some(self.fixed.as_slice());
        let largest = self
            .diagonal_slots
            .iter()
            .fold(0.0_f64, |m, &k| m.max(self.hess_values[k].abs()));
        for (d, &k) in self.shift_scale.iter_mut().zip(&self.diagonal_slots) {
            *d = self.hess_values[k].abs().max(MIN_RELATIVE_DIAGONAL * largest);
        }
        let mut mu = (self.last_shift / SHIFT_GROWTH).max(MIN_SHIFT);
        let mut applied = 0.0;
        loop {
            add_to_diagonal(
                &mut self.hess_values,
                &self.diagonal_slots,
                &self.shift_scale,
                mu - applied,
            );
            applied = mu;
            match self.linear.factorise(&self.hess_values, fixed) {
                Ok(used) => {
                    self.last_shift = mu;
                    return Ok(used);
                }
                Err(LinearSolveError::NotPositiveDefinite { .. }) if mu < MAX_SHIFT => mu *= SHIFT_GROWTH,
                Err(e) => return Err(e),
            }
        }
    }

    /// Solves `H dx = −∇Π` with the current factors (with CG to the forcing tolerance); returns the
    /// factorisation that produced the solution.
    fn solve_direction(&mut self, iteration: usize, run: &mut Run) -> Result<Factorisation, NewtonError> {
        for (d, g) in self.dx.iter_mut().zip(&self.grad) {
            *d = -g;
        }
        let t = Instant::now();
        let result = self.set_cg_forcing().and_then(|()| self.linear.solve_in_place(&mut self.dx));
        run.report.linear_solve_seconds += since(t);
        let used = result.map_err(|source| NewtonError::LinearSolve {
            iteration,
            source,
            residuals: Vec::new(),
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
        Ok(used)
    }

    /// With CG, sets the relative tolerance of the forcing sequence for the current gradient.
    fn set_cg_forcing(&mut self) -> Result<(), LinearSolveError> {
        if self.settings.linear_solver.kind != LinearSolverKind::Cg {
            return Ok(());
        }
        let g_norm = self
            .grad
            .iter()
            .zip(&self.fixed)
            .filter(|(_, f)| !**f)
            .map(|(g, _)| g * g)
            .sum::<f64>()
            .sqrt();
        let eta = self
            .settings
            .cg_forcing
            .relative_tolerance(g_norm / self.settings.residual_scale);
        self.linear.set_cg_relative_tolerance(eta)
    }

    /// A chord direction with the factors of an earlier iteration (no new factorisation), if they give
    /// a descent direction.
    fn chord_direction(&mut self, run: &mut Run) -> Option<f64> {
        for (d, g) in self.dx.iter_mut().zip(&self.grad) {
            *d = -g;
        }
        let t = Instant::now();
        let result = self.linear.solve_in_place(&mut self.dx);
        run.report.linear_solve_seconds += since(t);
        let slope = dot(&self.dx, &self.grad);
        (result.is_ok() && slope < 0.0).then_some(slope)
    }
}

/// `values[slots[i]] += s d_i`.
fn add_to_diagonal(values: &mut [f64], slots: &[usize], d: &[f64], s: f64) {
    for (&k, d) in slots.iter().zip(d) {
        values[k] += s * d;
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(a, b)| a * b).sum()
}
