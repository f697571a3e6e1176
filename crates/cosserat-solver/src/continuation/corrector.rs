//! One step of arc-length continuation: predictor, Crisfield's corrector, and the arc length's
//! adaptation and halving.
//!
//! The corrector linearises the equilibrium `∇Π(x; λ) = 0` at the current iterate,
//! `H δx + q δλ = −∇Π` with `q = ∂∇Π/∂λ`, so `δx = δx_g + δλ δx_q` with `δx_g = −H⁻¹ ∇Π` and
//! `δx_q = −H⁻¹ q` (one factorisation, two solves), and chooses `δλ` so that the step's increment
//! `Δx + δx` keeps the arc length: `‖Δx + δx_g + δλ δx_q‖²_W = Δl²`, a quadratic in `δλ`. Of its two
//! roots the one whose new increment makes the smaller angle with the current one continues forward
//! along the path (Crisfield 1981); without a real root the constraint's residual is minimised instead.
//! Near a limit point `H` is singular and indefinite beyond it, so the tangent is factorised as it is
//! (Cholesky, then the symmetric indefinite factorisation, then LU), never shifted. As Newton's method
//! does, the corrector offers each iterate to the problem, whose energy may adapt to it (a stretched
//! shell's stabilisation), and a failed corrector undoes that before the arc length is halved.

use std::time::Instant;

use super::{ArcLengthSettings, CorrectorError, PathError, PathPoint, PathProblem, tolerance};
use crate::error::{NewtonError, ProblemError};
use crate::linear::SparseSolver;
use crate::newton::{ConvergenceTest, Criterion, Tolerance, round_off_scale, weighted_max_abs};

/// A step whose residual grows beyond this factor over its first diverges.
const DIVERGENCE_FACTOR: f64 = 1e3;

/// The relative step in `λ` of the difference `∂∇Π/∂λ` (for loads linear in `λ` any step is exact but
/// for round-off, which grows as the step shrinks).
const LOAD_DIFFERENCE_STEP: f64 = 1e-3;

/// The state of the path between steps, and the buffers of the corrector.
pub(super) struct Tracer {
    settings: ArcLengthSettings,
    linear: SparseSolver,
    fixed: Vec<bool>,
    weights: Vec<f64>,
    /// The problem's residual weights with a relative tolerance, else 1
    /// ([`NewtonProblem::residual_weights`](crate::NewtonProblem::residual_weights)).
    residual_weights: Vec<f64>,
    /// The current step's increment `Δx` from the last equilibrium.
    x: Vec<f64>,
    grad: Vec<f64>,
    hess: Vec<f64>,
    /// `∂∇Π/∂λ` at the last equilibrium.
    q: Vec<f64>,
    dx_g: Vec<f64>,
    dx_q: Vec<f64>,
    scratch: (Vec<f64>, Vec<f64>),
    /// The last converged step's increment and load increment.
    previous: Option<(Vec<f64>, f64)>,
    /// The arc length of the next step, and the first step's.
    arc: f64,
    first_arc: f64,
}

/// A converged corrector.
struct Converged {
    iterations: usize,
    residual: f64,
    convergence: crate::newton::Convergence,
}

/// A failed corrector with the iterations it spent.
struct Failed {
    iterations: usize,
    error: CorrectorError,
}

/// Timings of one step.
#[derive(Default)]
struct Timing {
    assembly: f64,
    linear: f64,
}

impl Tracer {
    pub(super) fn new<P: PathProblem + ?Sized>(problem: &P, settings: &ArcLengthSettings) -> Result<Self, NewtonError> {
        let linear = SparseSolver::try_new(problem.hessian_pattern(), settings.newton.linear_solver)
            .map_err(NewtonError::Setup)?;
        let n = problem.n_dofs();
        if linear.n() != n {
            return Err(NewtonError::DimensionMismatch {
                what: "Hessian pattern dimension",
                expected: n,
                found: linear.n(),
            });
        }
        let fixed = problem.fixed_dofs().map_or_else(|| vec![false; n], <[bool]>::to_vec);
        let mut weights = vec![0.0; n];
        problem.arc_length_weights(&mut weights);
        for (w, f) in weights.iter_mut().zip(&fixed) {
            if *f {
                *w = 0.0;
            }
        }
        let mut residual_weights = vec![1.0; n];
        if matches!(tolerance(settings), Tolerance::Relative(_)) {
            problem.residual_weights(&mut residual_weights);
        }
        Ok(Self {
            residual_weights,
            settings: *settings,
            hess: vec![0.0; linear.nnz()],
            linear,
            fixed,
            weights,
            x: vec![0.0; n],
            grad: vec![0.0; n],
            q: vec![0.0; n],
            dx_g: vec![0.0; n],
            dx_q: vec![0.0; n],
            scratch: (vec![0.0; n], vec![0.0; n]),
            previous: None,
            arc: 0.0,
            first_arc: 0.0,
        })
    }

    /// The load-factor increment of the last converged step (0 before the first).
    pub(super) fn last_increment(&self) -> f64 {
        self.previous.as_ref().map_or(0.0, |p| p.1)
    }

    /// One step from the equilibrium at `lambda`, halving the arc length on failure; commits the
    /// problem at the new equilibrium.
    pub(super) fn step<P: PathProblem + ?Sized>(
        &mut self,
        problem: &mut P,
        step: usize,
        lambda: f64,
    ) -> Result<PathPoint, PathError> {
        let mut timing = Timing::default();
        let mut wasted = 0;
        let fail = |arc, cuts, error| PathError::StepFailed {
            step: step - 1,
            load_factor: lambda,
            cuts,
            arc_length: arc,
            error,
        };
        self.load_derivative(problem, lambda, &mut timing)
            .map_err(|error| fail(self.arc, 0, error))?;
        for cuts in 0..=self.settings.max_cuts {
            let dlambda = match self.predict(problem, lambda, &mut timing) {
                Ok(d) => d,
                Err(error) => return Err(fail(self.arc, cuts, error)),
            };
            if self.first_arc == 0.0 {
                return Err(PathError::NoFirstArc {
                    initial_increment: self.settings.initial_increment,
                });
            }
            let mut landing = self.passes_end(lambda, dlambda);
            let dlambda = if landing { self.land(lambda, dlambda) } else { dlambda };
            let mut corrected = self.correct(problem, lambda, dlambda, landing, &mut timing);
            // A corrector that passed the end (the path flattened in load, so its arc length spans more
            // of it than the predictor did) lands on it from its own increment scaled back: a path
            // that crossed the end would otherwise never reach it.
            if let Ok((passed, dl)) = &corrected
                && !landing
                && self.passes_end(lambda, *dl)
            {
                wasted += passed.iterations;
                problem.abandon_solve();
                let dl = self.land(lambda, *dl);
                landing = true;
                corrected = self.correct(problem, lambda, dl, landing, &mut timing);
            }
            if corrected.is_err() {
                problem.abandon_solve();
            }
            match corrected {
                Ok((converged, dlambda)) => {
                    problem.commit(&self.x);
                    let arc = self.norm(&self.x);
                    self.adapt(converged.iterations);
                    self.previous = Some((self.x.clone(), dlambda));
                    return Ok(PathPoint {
                        step,
                        load_factor: if landing { self.settings.end } else { lambda + dlambda },
                        arc_length: arc,
                        iterations: converged.iterations,
                        wasted_iterations: wasted,
                        cuts,
                        residual: converged.residual,
                        convergence: converged.convergence,
                        assembly_seconds: timing.assembly,
                        linear_solve_seconds: timing.linear,
                    });
                }
                Err(failed) if cuts < self.settings.max_cuts && self.arc > self.min_arc() => {
                    wasted += failed.iterations;
                    self.arc *= 0.5;
                }
                Err(failed) => return Err(fail(self.arc, cuts, failed.error)),
            }
        }
        unreachable!("the last cut returns")
    }

    /// Sets `x` to the predictor of a step from `lambda` and returns its load increment: the tangent
    /// for the first step, the previous increment scaled to the arc length after.
    fn predict<P: PathProblem + ?Sized>(
        &mut self,
        problem: &mut P,
        lambda: f64,
        timing: &mut Timing,
    ) -> Result<f64, CorrectorError> {
        match &self.previous {
            Some((dx, dl)) => {
                let s = self.arc / self.norm(dx);
                for (x, d) in self.x.iter_mut().zip(dx) {
                    *x = s * d;
                }
                Ok(s * dl)
            }
            None => {
                self.x.fill(0.0);
                problem
                    .set_load_factor(lambda)
                    .map_err(|source| CorrectorError::Problem { iteration: 0, source })?;
                problem.prescribe(&mut self.x);
                self.assemble(problem, 0, timing)?;
                self.factorise(0, timing)?;
                self.solve_tangents(0, false, timing)?;
                let dl = self.settings.initial_increment;
                for (x, t) in self.x.iter_mut().zip(&self.dx_q) {
                    *x += dl * t;
                }
                if self.arc == 0.0 {
                    self.arc = self.norm(&self.x);
                    self.first_arc = self.arc;
                } else {
                    // A halved first step: the tangent scaled to the arc length.
                    let s = self.arc / self.norm(&self.x);
                    self.x.iter_mut().for_each(|x| *x *= s);
                    return Ok(s * dl);
                }
                Ok(dl)
            }
        }
    }

    /// Whether a step of load increment `dlambda` from `lambda` passes the end load factor from below.
    fn passes_end(&self, lambda: f64, dlambda: f64) -> bool {
        lambda < self.settings.end && lambda + dlambda > self.settings.end && dlambda > 0.0
    }

    /// Scales the increment `x` to land on the end load factor; returns the new load increment.
    fn land(&mut self, lambda: f64, dlambda: f64) -> f64 {
        let s = (self.settings.end - lambda) / dlambda;
        self.x.iter_mut().for_each(|x| *x *= s);
        self.settings.end - lambda
    }

    /// Newton's iteration on equilibrium and arc length from the predictor; with `landing`, on
    /// equilibrium alone at the fixed load factor. Each iterate is offered to the problem
    /// ([`NewtonProblem::follow_iterate`](crate::NewtonProblem::follow_iterate)); a failed corrector
    /// leaves the undoing to the caller ([`NewtonProblem::abandon_solve`](crate::NewtonProblem::abandon_solve)).
    /// Returns the converged corrector and the step's load increment.
    fn correct<P: PathProblem + ?Sized>(
        &mut self,
        problem: &mut P,
        lambda: f64,
        mut dlambda: f64,
        landing: bool,
        timing: &mut Timing,
    ) -> Result<(Converged, f64), Failed> {
        let max = self.settings.newton.max_iterations;
        let mut first = None;
        for k in 0..=max {
            let failed = |error| Failed { iterations: k, error };
            let load = problem
                .set_load_factor(lambda + dlambda)
                .map_err(|source| failed(CorrectorError::Problem { iteration: k, source }));
            load?;
            problem.prescribe(&mut self.x);
            // The predictor and every corrected increment are iterates a problem may adapt its energy
            // to; the next assembly evaluates the adapted energy, and the divergence test keeps the
            // first residual.
            problem.follow_iterate(&self.x);
            self.assemble(problem, k, timing).map_err(failed)?;
            let r = self.residual();
            let first = *first.get_or_insert(r);
            let test = self.test(problem, lambda + dlambda);
            if test.accepts(r) {
                let convergence = test.record(Criterion::Residual);
                return Ok((
                    Converged {
                        iterations: k,
                        residual: r,
                        convergence,
                    },
                    dlambda,
                ));
            }
            if k == max {
                return Err(failed(CorrectorError::MaxIterations {
                    iterations: k,
                    residual: r,
                }));
            }
            if r > DIVERGENCE_FACTOR * first {
                return Err(failed(CorrectorError::Diverged {
                    iteration: k,
                    residual: r,
                }));
            }
            self.factorise(k, timing).map_err(failed)?;
            self.solve_tangents(k, true, timing).map_err(failed)?;
            let dl = if landing {
                0.0
            } else {
                constraint_root(&self.x, &self.dx_g, &self.dx_q, &self.weights, self.arc)
            };
            for ((x, g), q) in self.x.iter_mut().zip(&self.dx_g).zip(&self.dx_q) {
                *x += g + dl * q;
            }
            dlambda += dl;
        }
        unreachable!("the last iteration returns")
    }

    /// The convergence test at load factor `lambda`: relative to the external load (the problem's,
    /// and `λ q` with `|λ|` at least the first step's increment, so that the scale does not vanish
    /// where the path crosses `λ = 0`) and the reactions, with the Hessian's round-off floor.
    fn test<P: PathProblem + ?Sized>(&mut self, problem: &P, lambda: f64) -> ConvergenceTest {
        let lambda = lambda.abs().max(self.settings.initial_increment.abs());
        let w = &self.residual_weights;
        let q_scale = weighted_max_abs(&self.q, w, &self.fixed, false) * lambda;
        let mut test = ConvergenceTest::new(tolerance(&self.settings), problem.load_scale().max(q_scale), 0.0, 0.0);
        test.observe_reactions(weighted_max_abs(&self.grad, w, &self.fixed, true));
        let (magnitudes, sums) = &mut self.scratch;
        problem.unknown_magnitudes(&self.x, magnitudes);
        test.observe_stiffness(round_off_scale(
            problem.hessian_pattern(),
            &self.hess,
            magnitudes,
            sums,
            w,
            &self.fixed,
        ));
        test
    }

    /// `∂∇Π/∂λ` at the last equilibrium (increment zero), into `q`: the one-sided difference towards
    /// where the path goes (the sign of the last load increment, of the first step's before), so that
    /// a load script with a kink (a pressure that starts once a pull is complete) gives the corrector
    /// the derivative of the side it corrects on, where the central difference would mix both.
    fn load_derivative<P: PathProblem + ?Sized>(
        &mut self,
        problem: &mut P,
        lambda: f64,
        timing: &mut Timing,
    ) -> Result<(), CorrectorError> {
        let forward = match &self.previous {
            Some((_, dl)) => *dl >= 0.0,
            None => self.settings.initial_increment >= 0.0,
        };
        let h = LOAD_DIFFERENCE_STEP * lambda.abs().max(1.0) * if forward { 1.0 } else { -1.0 };
        let t = Instant::now();
        let problem_error = |source| CorrectorError::Problem { iteration: 0, source };
        for (step, out) in [(h, &mut self.q), (0.0, &mut self.scratch.0)] {
            problem.set_load_factor(lambda + step).map_err(problem_error)?;
            self.x.fill(0.0);
            problem.prescribe(&mut self.x);
            out.fill(0.0);
            problem.gradient(&self.x, out).map_err(problem_error)?;
        }
        for ((q, at), f) in self.q.iter_mut().zip(&self.scratch.0).zip(&self.fixed) {
            *q = if *f { 0.0 } else { (*q - at) / h };
        }
        problem.set_load_factor(lambda).map_err(problem_error)?;
        timing.assembly += t.elapsed().as_secs_f64();
        if self.q.iter().any(|v| !v.is_finite()) {
            return Err(CorrectorError::NonFinite { iteration: 0 });
        }
        Ok(())
    }

    /// Gradient and Hessian at the increment `x`, checked.
    fn assemble<P: PathProblem + ?Sized>(
        &mut self,
        problem: &mut P,
        iteration: usize,
        timing: &mut Timing,
    ) -> Result<(), CorrectorError> {
        self.grad.fill(0.0);
        self.hess.fill(0.0);
        let t = Instant::now();
        let result = problem.hessian(&self.x, &mut self.grad, &mut self.hess);
        timing.assembly += t.elapsed().as_secs_f64();
        result.map_err(|source: ProblemError| CorrectorError::Problem { iteration, source })?;
        if self.grad.iter().chain(&self.hess).any(|v| !v.is_finite()) {
            return Err(CorrectorError::NonFinite { iteration });
        }
        Ok(())
    }

    fn factorise(&mut self, iteration: usize, timing: &mut Timing) -> Result<(), CorrectorError> {
        let t = Instant::now();
        let fixed = self.fixed.iter().any(|f| *f).then_some(self.fixed.as_slice());
        let result = self.linear.factorise(&self.hess, fixed);
        timing.linear += t.elapsed().as_secs_f64();
        result
            .map(|_| ())
            .map_err(|source| CorrectorError::LinearSolve { iteration, source })
    }

    /// `δx_q = −H⁻¹ q` and, with `with_gradient`, `δx_g = −H⁻¹ ∇Π`.
    fn solve_tangents(
        &mut self,
        iteration: usize,
        with_gradient: bool,
        timing: &mut Timing,
    ) -> Result<(), CorrectorError> {
        let t = Instant::now();
        let mut solve = |rhs: &[f64], out: &mut Vec<f64>| {
            for (o, r) in out.iter_mut().zip(rhs) {
                *o = -r;
            }
            self.linear.solve_in_place(out)
        };
        let mut result = solve(&self.q, &mut self.dx_q);
        if with_gradient && result.is_ok() {
            result = solve(&self.grad, &mut self.dx_g);
        }
        timing.linear += t.elapsed().as_secs_f64();
        result
            .map(|_| ())
            .map_err(|source| CorrectorError::LinearSolve { iteration, source })
    }

    /// `max w_i |∇Π_i|` over free unknowns (`w` the residual weights).
    fn residual(&self) -> f64 {
        weighted_max_abs(&self.grad, &self.residual_weights, &self.fixed, false)
    }

    /// `‖v‖_W`.
    fn norm(&self, v: &[f64]) -> f64 {
        weighted_norm(v, &self.weights)
    }

    fn min_arc(&self) -> f64 {
        self.settings.min_ratio * self.first_arc
    }

    /// The next step's arc length from this step's corrector iterations.
    fn adapt(&mut self, iterations: usize) {
        let target = self.settings.target_iterations as f64;
        let factor = (target / iterations.max(1) as f64).sqrt().clamp(0.5, 2.0);
        self.arc = (self.arc * factor).clamp(self.min_arc(), self.settings.max_ratio * self.first_arc);
    }
}

/// `‖v‖_W`, computed on `v` divided by its largest weighted entry: the squares of an increment taken
/// from a tiny first load increment would otherwise underflow to zero (a zero arc length, and a NaN
/// scale of the next predictor), and those of a huge one overflow.
pub(super) fn weighted_norm(v: &[f64], w: &[f64]) -> f64 {
    let scale = v
        .iter()
        .zip(w)
        .filter(|(_, w)| **w != 0.0)
        .fold(0.0_f64, |m, (v, _)| m.max(v.abs()));
    if scale == 0.0 || !scale.is_finite() {
        return scale;
    }
    let sum: f64 = v
        .iter()
        .zip(w)
        .filter(|(_, w)| **w != 0.0)
        .map(|(v, w)| w * (v / scale).powi(2))
        .sum();
    scale * sum.sqrt()
}

/// `δλ` of the cylindrical constraint `‖x + dg + δλ dq‖²_W = arc²`: of the two roots the one whose
/// increment makes the smaller angle with `x`; without a real root the minimiser of the constraint's
/// left side.
///
/// The constraint is homogeneous in the lengths: divided by `σ = max(‖x + dg‖_∞, arc)` it reads
/// `‖y/σ + (δλ/σ) dq‖²_W = (arc/σ)²`, whose coefficients are of order one in `y` and `arc`, so that the
/// squares of the tiny increments of a tiny first step neither underflow nor lose their digits.
pub(super) fn constraint_root(x: &[f64], dg: &[f64], dq: &[f64], w: &[f64], arc: f64) -> f64 {
    let sigma = x
        .iter()
        .zip(dg)
        .zip(w)
        .filter(|(_, w)| **w != 0.0)
        .fold(arc.abs(), |m, ((x, g), _)| m.max((x + g).abs()));
    if sigma == 0.0 || !sigma.is_finite() {
        return scaled_constraint_root(x, dg, dq, w, arc, 1.0);
    }
    sigma * scaled_constraint_root(x, dg, dq, w, arc, sigma)
}

/// `δλ/σ` of the constraint divided by `σ` (see [`constraint_root`]).
fn scaled_constraint_root(x: &[f64], dg: &[f64], dq: &[f64], w: &[f64], arc: f64, sigma: f64) -> f64 {
    // Unknowns of zero weight are skipped: divided by a tiny `σ` they could overflow, and `0 · ∞` is NaN.
    let (mut a, mut b, mut c) = (0.0, 0.0, 0.0);
    for (((x, g), q), w) in x.iter().zip(dg).zip(dq).zip(w).filter(|(_, w)| **w != 0.0) {
        let y = (x + g) / sigma;
        a += w * q * q;
        b += 2.0 * w * y * q;
        c += w * y * y;
    }
    let arc = arc / sigma;
    c -= arc * arc;
    if a == 0.0 {
        return 0.0;
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return -b / (2.0 * a);
    }
    // The root of larger magnitude without cancellation, the other from the product of the roots.
    let big = -(b + b.signum() * disc.sqrt()) / (2.0 * a);
    let small = if big == 0.0 { 0.0 } else { c / (a * big) };
    let alignment = |mu: f64| -> f64 {
        x.iter()
            .zip(dg)
            .zip(dq)
            .zip(w)
            .filter(|(_, w)| **w != 0.0)
            .map(|(((x, g), q), w)| w * (x / sigma) * ((x + g) / sigma + mu * q))
            .sum()
    };
    if alignment(big) >= alignment(small) { big } else { small }
}

#[cfg(test)]
mod tests {
    use super::{constraint_root, weighted_norm};

    #[test]
    fn the_root_keeps_the_arc_length_and_continues_forward() {
        // In the plane with unit weights: increment x = (1, 0) (arc 1), correction dg = (0, 0.5),
        // load direction dq = (1, 0). Roots: (1 + δλ)² + 0.25 = 1, δλ = −1 ± √0.75; the forward one
        // keeps the increment pointing along +x.
        let (x, dg, dq, w) = ([1.0, 0.0], [0.0, 0.5], [1.0, 0.0], [1.0, 1.0]);
        let dl = constraint_root(&x, &dg, &dq, &w, 1.0);
        assert!((dl - (-1.0 + 0.75f64.sqrt())).abs() < 1e-15, "{dl}");
        // The increment after the correction has the arc length.
        let n = ((1.0 + dl) * (1.0 + dl) + 0.25f64).sqrt();
        assert!((n - 1.0).abs() < 1e-15);
        // Reversed increment: the other root continues the other way.
        let back = constraint_root(&[-1.0, 0.0], &dg, &dq, &w, 1.0);
        assert!((back - (1.0 - 0.75f64.sqrt())).abs() < 1e-15, "{back}");
    }

    #[test]
    fn without_a_real_root_the_constraint_residual_is_minimised() {
        // dg takes the increment 2 away across the load direction: no δλ restores arc 1, the closest is
        // δλ = −x·dq/|dq|² = −1.
        let dl = constraint_root(&[1.0, 0.0], &[0.0, 2.0], &[1.0, 0.0], &[1.0, 1.0], 1.0);
        assert_eq!(dl, -1.0);
        // Zero weights on the load direction: nothing to choose.
        assert_eq!(
            constraint_root(&[1.0, 0.0], &[0.0, 0.5], &[0.0, 1.0], &[1.0, 0.0], 1.0),
            0.0
        );
    }

    #[test]
    fn tiny_lengths_give_the_root_of_the_same_constraint_at_unit_scale() {
        // The first example scaled down to lengths whose squares underflow (1e-300) or are subnormal
        // (1e-160): δλ scales with the lengths, as the constraint is homogeneous in them.
        let (x, dg, dq, w) = ([1.0, 0.0], [0.0, 0.5], [1.0, 0.0], [1.0, 1.0]);
        let unit = constraint_root(&x, &dg, &dq, &w, 1.0);
        for s in [1e-300, 1e-160, 1e200] {
            let scaled = |v: [f64; 2]| v.map(|v| v * s);
            let dl = constraint_root(&scaled(x), &scaled(dg), &dq, &w, s);
            assert!((dl / s - unit).abs() < 1e-14 * unit.abs(), "scale {s:e}: δλ = {dl:e}");
        }
    }

    #[test]
    fn the_norm_of_tiny_and_huge_increments_is_neither_zero_nor_infinite() {
        let w = [1.0, 4.0, 0.0];
        assert_eq!(weighted_norm(&[3.0, 2.0, 7.0], &w), 5.0);
        for s in [1e-300, 1e-160, 1e300] {
            let n = weighted_norm(&[3.0 * s, 2.0 * s, 7.0 * s], &w);
            assert!((n / s - 5.0).abs() < 1e-14, "scale {s:e}: {n:e}");
        }
        assert_eq!(weighted_norm(&[0.0, 0.0, 1.0], &w), 0.0);
        // An unweighted entry far larger than the weighted ones does not count.
        let n = weighted_norm(&[3e-300, 2e-300, 1.0], &w);
        assert!((n / 1e-300 - 5.0).abs() < 1e-14, "{n:e}");
    }
}
