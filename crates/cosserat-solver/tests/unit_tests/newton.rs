//! Newton's method on toy problems with known minimisers: one-step convergence on quadratics,
//! Rosenbrock (2D and chained), a 3D spring chain between walls, quadratic convergence, fixed
//! unknowns, feasibility, and typed failures that carry the residual history.

use cosserat_solver::{
    IndefiniteHessian, LinearSolverKind, LinearSolverSettings, NewtonError, NewtonProblem, NewtonSettings,
    NewtonSolver, NonFiniteQuantity, ProblemError, Tolerance,
};
use faer::sparse::{SymbolicSparseColMat, SymbolicSparseColMatRef};
use nalgebra::DVector;

use super::fixtures::{block_grid, random_vector, rng};
use super::toy::{HalfTurn, Quadratic, Rosenbrock, Scalar, SpringChain, Taut, pattern_of};

/// The reference code's Newton: absolute tolerance 1e-7, indefinite Hessians factorised as they are.
fn reference_newton() -> NewtonSettings {
    NewtonSettings {
        tolerance: Tolerance::Absolute(1e-7),
        indefinite_hessian: IndefiniteHessian::Factorise,
        ..NewtonSettings::default()
    }
}

pub(super) fn solve<P: NewtonProblem>(
    problem: &mut P,
    x: &mut [f64],
    settings: NewtonSettings,
) -> Result<cosserat_solver::NewtonReport, NewtonError> {
    let mut solver = NewtonSolver::for_problem(problem, settings).unwrap();
    solver.solve(problem, x)
}

#[test]
fn convex_quadratic_converges_in_one_iteration() {
    let mut r = rng(11);
    let a = block_grid(5, 4, 1e-1, &mut r);
    let b = random_vector(a.n(), &mut r);
    let reference = a.to_dense().cholesky().unwrap().solve(&DVector::from_column_slice(&b));
    let mut problem = Quadratic { a, b };
    let mut x = vec![0.0; problem.n_dofs()];
    let report = solve(&mut problem, &mut x, reference_newton()).unwrap();
    assert_eq!(report.iterations, 1);
    assert_eq!(report.residuals.len(), 2);
    assert_eq!(report.line_search_backtracks, 0);
    assert_eq!(report.factorisations.llt, 1);
    // The factorisation's time is a part of the linear solves'.
    assert!(report.factorisation_seconds > 0.0);
    assert!(report.factorisation_seconds <= report.linear_solve_seconds);
    let err = (DVector::from_column_slice(&x) - &reference).amax();
    assert!(err <= 1e-10 * reference.amax(), "{err:e}");
    // The minimum of ½xᵀAx − bᵀx is −½ bᵀA⁻¹b.
    let exact = -0.5 * DVector::from_column_slice(&problem.b).dot(&reference);
    assert!((report.energy - exact).abs() <= 1e-12 * exact.abs());
}

#[test]
fn start_at_the_minimiser_takes_zero_iterations() {
    let mut problem = Rosenbrock::new(2);
    let mut x = [1.0, 1.0];
    let report = solve(&mut problem, &mut x, reference_newton()).unwrap();
    assert_eq!(report.iterations, 0);
    assert_eq!(report.residuals, vec![0.0]);
    assert_eq!(x, [1.0, 1.0]);
}

/// A problem that counts its gradient and Hessian evaluations and records the calls of the
/// mixed-integration-point method (with the Hessians among them).
struct Counting<P> {
    inner: P,
    gradients: usize,
    hessians: usize,
    calls: Vec<String>,
}

impl<P> Counting<P> {
    fn new(inner: P) -> Self {
        Self {
            inner,
            gradients: 0,
            hessians: 0,
            calls: Vec::new(),
        }
    }
}

impl<P: NewtonProblem> NewtonProblem for Counting<P> {
    fn n_dofs(&self) -> usize {
        self.inner.n_dofs()
    }
    fn hessian_pattern(&self) -> SymbolicSparseColMatRef<'_, usize> {
        self.inner.hessian_pattern()
    }
    fn value(&mut self, x: &[f64]) -> Result<f64, ProblemError> {
        self.inner.value(x)
    }
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> Result<f64, ProblemError> {
        self.gradients += 1;
        self.inner.gradient(x, g)
    }
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> Result<f64, ProblemError> {
        self.hessians += 1;
        self.calls.push("hessian".into());
        self.inner.hessian(x, g, h)
    }
    fn linearize_strains(&mut self, x: &[f64], dx: &[f64]) -> Result<(), ProblemError> {
        assert_eq!((x.len(), dx.len()), (self.n_dofs(), self.n_dofs()));
        self.calls.push(if dx.iter().all(|&d| d == 0.0) {
            format!("linearize at {x:?}")
        } else {
            "linearize".into()
        });
        Ok(())
    }
    fn advance_predicted_strains(&mut self, alpha: f64) {
        self.calls.push(format!("advance {alpha}"));
    }
    fn clear_predicted_strains(&mut self) {
        self.calls.push("clear".into());
    }
}

#[test]
fn the_first_hessian_brings_the_first_gradient_unless_the_last_solve_started_converged() {
    let mut r = rng(17);
    let a = block_grid(4, 3, 1e-1, &mut r);
    let b = random_vector(a.n(), &mut r);
    let mut problem = Counting::new(Quadratic { a, b });
    let mut solver = NewtonSolver::for_problem(&problem, reference_newton()).unwrap();
    let mut x = vec![0.0; problem.n_dofs()];
    let mut counts = |problem: &mut Counting<Quadratic>, x: &mut Vec<f64>| {
        (problem.gradients, problem.hessians) = (0, 0);
        let report = solver.solve(problem, x).unwrap();
        (report.iterations, problem.gradients, problem.hessians)
    };
    // One Newton step on a quadratic: the Hessian at the start, the gradient at the step.
    assert_eq!(counts(&mut problem, &mut x), (1, 1, 1));
    // From the minimiser: the Hessian at once (the last solve did not start converged), then no step.
    assert_eq!(counts(&mut problem, &mut x), (0, 0, 1));
    // Once more from the minimiser: the gradient alone.
    assert_eq!(counts(&mut problem, &mut x), (0, 1, 0));
    // Away from it again: the gradient alone shows the need for a step, then the step as before.
    x.iter_mut().for_each(|v| *v += 0.5);
    assert_eq!(counts(&mut problem, &mut x), (1, 2, 1));
    assert_eq!(counts(&mut problem, &mut x), (0, 0, 1));
}

#[test]
fn rosenbrock_converges_from_the_standard_start() {
    let mut problem = Rosenbrock::new(2);
    let mut x = [-1.2, 1.0];
    let report = solve(&mut problem, &mut x, reference_newton()).unwrap();
    assert!(report.residual() < 1e-7);
    assert_eq!(report.residuals.len(), report.iterations + 1);
    // Near (1, 1) the Hessian [[802, −400], [−400, 200]] has smallest eigenvalue ≈ 0.4, so a gradient
    // below 1e-7 puts x within about 2.5e-7 of the minimiser.
    assert!((x[0] - 1.0).abs() < 3e-7 && (x[1] - 1.0).abs() < 3e-7, "{x:?}");
    // The pure Newton step from the standard start overshoots along the valley: the line search
    // must act.
    assert!(report.line_search_backtracks > 0);
    // |∂Π/∂x₀| at (−1.2, 1) = |−400·(−1.2)·(1 − 1.44) − 2·2.2| = 215.6.
    assert!((report.residuals[0] - 215.6).abs() < 1e-12);
}

#[test]
fn chained_rosenbrock_converges_with_a_tridiagonal_hessian() {
    let n = 30;
    let mut problem = Rosenbrock::new(n);
    assert_eq!(problem.pattern.row_idx().len(), 2 * n - 1);
    let mut x: Vec<f64> = (0..n).map(|i| if i % 2 == 0 { -1.2 } else { 1.0 }).collect();
    let report = solve(&mut problem, &mut x, reference_newton()).unwrap();
    assert!(report.residual() < 1e-7);
    assert_eq!(report.residuals.len(), report.iterations + 1);
    let err = x.iter().map(|v| (v - 1.0).abs()).fold(0.0, f64::max);
    assert!(err < 1e-6, "max |x_i − 1| = {err:e}");
    // The Hessian is indefinite on the way: the symmetric indefinite factorisation is used.
    assert!(report.factorisations.lblt > 0, "{:?}", report.factorisations);
    assert_eq!(
        report.factorisations.llt + report.factorisations.lblt + report.factorisations.lu,
        report.iterations
    );
}

/// A stretched chain whose straight equilibrium is known in closed form.
fn stretched_chain() -> (SpringChain, Vec<f64>, Vec<f64>) {
    let stiffness = vec![10.0, 25.0, 40.0, 15.0, 30.0, 20.0, 35.0];
    let rest_length = vec![0.3, 0.5, 0.4, 0.6, 0.35, 0.45, 0.5];
    let chain = SpringChain::new(stiffness, rest_length);
    let n_nodes = chain.n_nodes;
    let exact = chain_equilibrium(&chain, [3.0, 2.0, 1.5]);
    // Start: perturb the free nodes of the equilibrium transversally and axially.
    let mut start = exact.clone();
    let mut r = rng(12);
    for node in 1..n_nodes - 1 {
        let p = random_vector(3, &mut r);
        for d in 0..3 {
            start[3 * node + d] += 0.4 * p[d];
        }
    }
    (chain, start, exact)
}

/// The equilibrium of `chain` stretched from the origin to `b`: equal tension `T` in all springs,
/// `d_i = l_i + T / k_i` and `Σ d_i = |b|`.
fn chain_equilibrium(chain: &SpringChain, b: [f64; 3]) -> Vec<f64> {
    let (stiffness, rest_length) = (&chain.stiffness, &chain.rest_length);
    let span = (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]).sqrt();
    let tension = (span - rest_length.iter().sum::<f64>()) / stiffness.iter().map(|k| 1.0 / k).sum::<f64>();
    assert!(tension > 0.0);
    let mut exact = vec![0.0; 3 * chain.n_nodes];
    let mut s = 0.0;
    for node in 0..chain.n_nodes {
        for d in 0..3 {
            exact[3 * node + d] = b[d] * s / span;
        }
        if node + 1 < chain.n_nodes {
            s += rest_length[node] + tension / stiffness[node];
        }
    }
    exact
}

#[test]
fn spring_chain_reaches_the_analytic_equilibrium() {
    let (mut chain, start, exact) = stretched_chain();
    let mut x = start.clone();
    // The softest mode is transverse with stiffness T/d ≈ 1 N/m, so a force residual of 1e-11 N bounds
    // the position error by about 1e-11 m.
    let settings = NewtonSettings {
        tolerance: cosserat_solver::Tolerance::Absolute(1e-11),
        ..reference_newton()
    };
    let report = solve(&mut chain, &mut x, settings).unwrap();
    assert!(report.residual() < 1e-11);
    assert_eq!(report.residuals.len(), report.iterations + 1);
    let err = x.iter().zip(&exact).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(err < 1e-9, "max position error {err:e}");
}

#[test]
fn fixed_unknowns_keep_their_values_and_do_not_count_in_the_residual() {
    let (mut chain, start, _) = stretched_chain();
    let mut x = start.clone();
    let report = solve(&mut chain, &mut x, reference_newton()).unwrap();
    let n = x.len();
    for i in (0..3).chain(n - 3..n) {
        assert_eq!(x[i], start[i], "wall unknown {i} moved");
    }
    // The walls carry the tension as reaction forces, far above the tolerance.
    let mut g = vec![0.0; n];
    chain.gradient(&x, &mut g).unwrap();
    assert!(g[0].abs() > 1.0);
    assert!(report.residual() < 1e-7);
}

/// Asserts `r_{k+1} ≤ C r_k²` for every iteration that starts with `r_k ≤ 0.1` (at least two of
/// them), and an observed order `log(r_m/r_{m−1}) / log(r_{m−1}/r_{m−2}) ≥ 1.8` on the last three
/// residuals.
fn assert_quadratic_tail(residuals: &[f64]) {
    // C = 10: the observed constants are 0.04–2 on these problems. The order estimate rules out linear
    // convergence (order 1) and the bound rules out a slow quadratic tail.
    const C: f64 = 10.0;
    let tail: Vec<(f64, f64)> = residuals.windows(2).map(|w| (w[0], w[1])).filter(|&(r, _)| r <= 0.1).collect();
    assert!(
        tail.len() >= 2,
        "too few iterations in the asymptotic regime: {residuals:?}"
    );
    for (r0, r1) in tail {
        assert!(r1 <= C * r0 * r0, "r_k = {r0:e}, r_k+1 = {r1:e}: not quadratic");
    }
    let m = residuals.len();
    let (a, b, c) = (residuals[m - 3], residuals[m - 2], residuals[m - 1]);
    let order = (c / b).ln() / (b / a).ln();
    assert!(order >= 1.8, "observed order {order} from {residuals:?}");
}

#[test]
fn convergence_is_quadratic_near_the_solution() {
    let (mut chain, start, _) = stretched_chain();
    let mut x = start;
    let report = solve(&mut chain, &mut x, reference_newton()).unwrap();
    assert_quadratic_tail(&report.residuals);

    let n = 30;
    let mut problem = Rosenbrock::new(n);
    let mut x: Vec<f64> = (0..n).map(|i| if i % 2 == 0 { -1.2 } else { 1.0 }).collect();
    let report = solve(&mut problem, &mut x, reference_newton()).unwrap();
    assert_quadratic_tail(&report.residuals);
}

#[test]
fn one_solver_serves_repeated_solves_without_new_analysis() {
    let n = 12;
    let mut problem = Rosenbrock::new(n);
    let mut solver = NewtonSolver::for_problem(&problem, reference_newton()).unwrap();
    let mut r = rng(13);
    for _ in 0..3 {
        let mut x: Vec<f64> = random_vector(n, &mut r).iter().map(|v| 1.0 + 0.3 * v).collect();
        let report = solver.solve(&mut problem, &mut x).unwrap();
        assert!(report.residual() < 1e-7);
        assert!(x.iter().all(|v| (v - 1.0).abs() < 1e-6), "{x:?}");
    }
    assert_eq!(solver.linear_solver().symbolic_analysis_count(), 1);
}

#[test]
fn the_chosen_linear_solver_is_used_and_reported() {
    let n = 8;
    let mut problem = Rosenbrock::new(n);
    let mut x = vec![0.5; n];
    let settings = NewtonSettings {
        linear_solver: LinearSolverSettings {
            kind: LinearSolverKind::Lu,
            ..Default::default()
        },
        ..reference_newton()
    };
    let report = solve(&mut problem, &mut x, settings).unwrap();
    assert_eq!(report.factorisations.lu, report.iterations);
    assert!(report.iterations > 0);
}

#[test]
fn residual_scale_divides_the_gradient() {
    let mut problem = Rosenbrock::new(2);
    let mut x = [-1.2, 1.0];
    let settings = NewtonSettings {
        residual_scale: 1e-2,
        max_iterations: 1,
        ..reference_newton()
    };
    let err = solve(&mut problem, &mut x, settings).unwrap_err();
    assert!((err.residuals()[0] - 215.6 / 1e-2).abs() < 1e-9);
}

#[test]
fn max_iterations_failure_carries_the_residual_history() {
    let mut full = Rosenbrock::new(2);
    let mut x = [-1.2, 1.0];
    let converged = solve(&mut full, &mut x, reference_newton()).unwrap();

    let mut problem = Rosenbrock::new(2);
    let mut x = [-1.2, 1.0];
    let settings = NewtonSettings {
        max_iterations: 3,
        ..reference_newton()
    };
    match solve(&mut problem, &mut x, settings) {
        Err(NewtonError::MaxIterations { iterations, residuals }) => {
            assert_eq!(iterations, 3);
            assert_eq!(residuals.len(), 4);
            // The same deterministic iterates as the unlimited run.
            assert_eq!(residuals[..], converged.residuals[..4]);
        }
        other => panic!("expected MaxIterations, got {other:?}"),
    }
    assert!(x.iter().all(|v| v.is_finite()));
}

/// Rosenbrock with injected NaNs.
struct Faulty {
    inner: Rosenbrock,
    nan_gradient: bool,
    nan_hessian: bool,
    nan_value: bool,
}

impl Faulty {
    fn new(nan_gradient: bool, nan_hessian: bool, nan_value: bool) -> Self {
        Self {
            inner: Rosenbrock::new(2),
            nan_gradient,
            nan_hessian,
            nan_value,
        }
    }
}

impl NewtonProblem for Faulty {
    fn n_dofs(&self) -> usize {
        2
    }
    fn hessian_pattern(&self) -> SymbolicSparseColMatRef<'_, usize> {
        self.inner.hessian_pattern()
    }
    fn value(&mut self, x: &[f64]) -> Result<f64, ProblemError> {
        if self.nan_value {
            Ok(f64::NAN)
        } else {
            self.inner.value(x)
        }
    }
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> Result<f64, ProblemError> {
        let e = self.inner.gradient(x, g)?;
        if self.nan_gradient {
            g[1] = f64::NAN;
        }
        Ok(e)
    }
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> Result<f64, ProblemError> {
        let e = self.inner.hessian(x, g, h)?;
        if self.nan_gradient {
            g[1] = f64::NAN;
        }
        if self.nan_hessian {
            h[2] = f64::INFINITY;
        }
        Ok(e)
    }
}

#[test]
fn non_finite_values_are_errors_never_states() {
    let start = [-1.2, 1.0];
    let cases = [
        (Faulty::new(true, false, false), NonFiniteQuantity::Gradient, Some(1), 0),
        // The first Hessian comes with the initial evaluation.
        (Faulty::new(false, true, false), NonFiniteQuantity::Hessian, Some(2), 0),
    ];
    for (mut problem, quantity, index, iteration) in cases {
        let mut x = start;
        match solve(&mut problem, &mut x, reference_newton()) {
            Err(NewtonError::NonFinite {
                quantity: q,
                index: i,
                iteration: k,
                ..
            }) => {
                assert_eq!((q, i, k), (quantity, index, iteration));
            }
            other => panic!("expected NonFinite {quantity:?}, got {other:?}"),
        }
        assert_eq!(x, start);
    }
    // NaN energies in the line search: Rosenbrock backtracks in its second iteration.
    let mut problem = Faulty::new(false, false, true);
    let mut x = start;
    match solve(&mut problem, &mut x, reference_newton()) {
        Err(NewtonError::NonFinite {
            quantity: NonFiniteQuantity::Energy,
            residuals,
            ..
        }) => {
            assert!(!residuals.is_empty());
        }
        other => panic!("expected a non-finite energy, got {other:?}"),
    }
    assert!(x.iter().all(|v| v.is_finite()));
}

#[test]
fn invalid_states_shorten_the_step() {
    // Π(x) = x − ln x on x > 0, minimiser x = 1. From x = 10 the Newton step is −90; the steps with
    // α = 1, ½, ¼, ⅛ land at x ≤ 0, α = 1/16 at 4.375.
    let mut problem = Scalar::new(|x: f64| x - x.ln(), |x: f64| 1.0 - 1.0 / x, |x: f64| 1.0 / (x * x));
    problem.lower = f64::MIN_POSITIVE;
    let mut x = [10.0];
    let report = solve(&mut problem, &mut x, reference_newton()).unwrap();
    assert!(report.feasibility_halvings >= 4);
    // |Π'(x)| = |1 − 1/x| < 1e-7 implies |x − 1| < 1.1e-7.
    assert!((x[0] - 1.0).abs() < 1.1e-7, "{x:?}");
}

#[test]
fn steps_below_the_minimum_fraction_are_infeasible() {
    let quadratic = || Scalar::new(|x: f64| 0.5 * (x + 10.0).powi(2), |x: f64| x + 10.0, |_| 1.0);
    // The problem itself caps the step at 0.1 %.
    let mut capped = quadratic();
    capped.max_fraction = 1e-3;
    let mut x = [0.0];
    assert!(matches!(
        solve(&mut capped, &mut x, reference_newton()),
        Err(NewtonError::InfeasibleStep { iteration: 1, .. })
    ));
    assert_eq!(x, [0.0]);
    // States below −1.5 are invalid while the minimiser is −10: the iterates approach the boundary
    // until halving goes below 1 %.
    let mut walled = quadratic();
    walled.lower = -1.5;
    let mut x = [0.0];
    match solve(&mut walled, &mut x, reference_newton()) {
        Err(NewtonError::InfeasibleStep {
            step_fraction,
            residuals,
            ..
        }) => {
            assert!(step_fraction < 0.01);
            assert!(residuals.len() >= 2);
        }
        other => panic!("expected InfeasibleStep, got {other:?}"),
    }
    assert!(x[0] >= -1.5 && x[0] < 0.0);
}

#[test]
fn ascent_directions_are_flipped_or_rejected() {
    // Π(x) = x⁴ − x² at x = 0.1: Π' = −0.196, Π'' = −1.88, so the Newton step −0.104 points uphill.
    let well = || {
        Scalar::new(
            |x: f64| x.powi(4) - x * x,
            |x: f64| 4.0 * x.powi(3) - 2.0 * x,
            |x: f64| 12.0 * x * x - 2.0,
        )
    };
    let mut problem = well();
    let mut x = [0.1];
    let settings = NewtonSettings {
        flip_on_non_descent: false,
        ..reference_newton()
    };
    match solve(&mut problem, &mut x, settings) {
        Err(NewtonError::NotDescent { iteration, slope, .. }) => {
            assert_eq!(iteration, 1);
            assert!((slope - 0.196 * 0.196 / 1.88).abs() < 1e-12);
        }
        other => panic!("expected NotDescent, got {other:?}"),
    }
    let mut problem = well();
    let mut x = [0.1];
    let report = solve(&mut problem, &mut x, reference_newton()).unwrap();
    assert!(report.direction_flips >= 1);
    assert!(
        report.factorisations.lblt >= 1,
        "a negative 1×1 Hessian is not positive definite"
    );
    assert!((x[0] - 0.5f64.sqrt()).abs() < 1e-7, "{x:?}");
}

#[test]
fn line_search_failure_is_reported() {
    // An inconsistent problem: Π = x² but the reported gradient is 2(x − 5) (and Π'' = 4). Every step
    // along +x raises Π, so no step length passes the Armijo test.
    let mut problem = Scalar::new(|x: f64| x * x, |x: f64| 2.0 * (x - 5.0), |_| 4.0);
    let mut x = [0.0];
    let settings = NewtonSettings {
        noise_resistant_line_search: false,
        ..reference_newton()
    };
    match solve(&mut problem, &mut x, settings) {
        Err(NewtonError::LineSearchFailed {
            iteration,
            residual,
            residuals,
        }) => {
            assert_eq!((iteration, residual), (1, 10.0));
            assert_eq!(residuals, vec![10.0]);
        }
        other => panic!("expected LineSearchFailed, got {other:?}"),
    }
    assert_eq!(x, [0.0]);
}

#[test]
fn noise_resistant_line_search_accepts_steps_hidden_by_round_off() {
    // Π = 1e10 + (x − 1)⁴: the Newton step divides the error by 3/2, so Π drops by 80 % of (x − 1)⁴,
    // which is below the spacing of doubles near 1e10 (1.9e-6) once |x − 1| < 0.04, while the residual
    // 4|x − 1|³ is still far above the tolerance.
    let offset = || {
        Scalar::new(
            |x: f64| 1e10 + (x - 1.0).powi(4),
            |x: f64| 4.0 * (x - 1.0).powi(3),
            |x: f64| 12.0 * (x - 1.0).powi(2),
        )
    };
    let mut problem = offset();
    let mut x = [1.03];
    let report = solve(&mut problem, &mut x, reference_newton()).unwrap();
    assert!(report.residual() < 1e-7);
    assert!((x[0] - 1.0).abs() < 3e-3);

    let mut problem = offset();
    let mut x = [1.03];
    let settings = NewtonSettings {
        noise_resistant_line_search: false,
        ..reference_newton()
    };
    assert!(matches!(
        solve(&mut problem, &mut x, settings),
        Err(NewtonError::LineSearchFailed { .. })
    ));
}

#[test]
fn misuse_is_reported_not_panicked() {
    let mut problem = Rosenbrock::new(3);
    let mut solver = NewtonSolver::for_problem(&problem, reference_newton()).unwrap();
    let mut short = [0.0; 2];
    assert!(matches!(
        solver.solve(&mut problem, &mut short),
        Err(NewtonError::DimensionMismatch {
            expected: 3,
            found: 2,
            ..
        })
    ));
    // A problem with another pattern (a dense 3×3 upper triangle).
    struct Other(SymbolicSparseColMat<usize>, Rosenbrock);
    impl NewtonProblem for Other {
        fn n_dofs(&self) -> usize {
            3
        }
        fn hessian_pattern(&self) -> SymbolicSparseColMatRef<'_, usize> {
            self.0.as_ref()
        }
        fn value(&mut self, x: &[f64]) -> Result<f64, ProblemError> {
            self.1.value(x)
        }
        fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> Result<f64, ProblemError> {
            self.1.gradient(x, g)
        }
        fn hessian(&mut self, x: &[f64], g: &mut [f64], _h: &mut [f64]) -> Result<f64, ProblemError> {
            self.1.gradient(x, g)
        }
    }
    let mut other = Other(
        pattern_of(3, (0..3).flat_map(|j| (0..=j).map(move |i| (i, j)))),
        Rosenbrock::new(3),
    );
    let mut x = [0.0; 3];
    assert!(matches!(
        solver.solve(&mut other, &mut x),
        Err(NewtonError::PatternChanged)
    ));

    solver.settings_mut().backtracking_factor = 1.0;
    assert!(matches!(
        solver.solve(&mut problem, &mut x),
        Err(NewtonError::InvalidSetting {
            name: cosserat_solver::SettingName::BacktrackingFactor,
            ..
        })
    ));
}

#[test]
fn chord_steps_reuse_the_factorisation_and_reach_the_same_equilibrium() {
    let (mut chain, start, exact) = stretched_chain();
    let newton = NewtonSettings {
        tolerance: cosserat_solver::Tolerance::Absolute(1e-11),
        ..reference_newton()
    };
    let chord = NewtonSettings {
        reuse_max_ratio: Some(0.1),
        ..newton
    };
    let mut x_newton = start.clone();
    let r_newton = solve(&mut chain, &mut x_newton, newton).unwrap();
    let mut x_chord = start.clone();
    let r_chord = solve(&mut chain, &mut x_chord, chord).unwrap();
    let err = x_chord.iter().zip(&exact).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(err < 1e-9, "chord solution off by {err:e}");
    assert!(r_chord.chord_iterations > 0, "no chord step taken");
    let factorisations =
        |r: &cosserat_solver::NewtonReport| r.factorisations.llt + r.factorisations.lblt + r.factorisations.lu;
    assert_eq!(factorisations(&r_chord) + r_chord.chord_iterations, r_chord.iterations);
    assert!(
        factorisations(&r_chord) < factorisations(&r_newton),
        "{r_chord:?} vs {r_newton:?}"
    );
    assert_eq!(r_newton.chord_iterations, 0);
}

#[test]
fn factors_that_converged_fast_start_the_next_solve_unless_the_fixed_unknowns_changed() {
    let (mut chain, start, exact) = stretched_chain();
    let settings = NewtonSettings {
        tolerance: cosserat_solver::Tolerance::Absolute(1e-8),
        reuse_max_ratio: Some(0.1),
        ..reference_newton()
    };
    let mut solver = NewtonSolver::for_problem(&chain, settings).unwrap();
    let mut x = start;
    solver.solve(&mut chain, &mut x).unwrap();
    let off = |x: &[f64], exact: &[f64]| x.iter().zip(exact).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    // The softest mode has a stiffness of about 1 N/m: a residual of 1e-8 N bounds the error by 1e-8 m.
    assert!(off(&x, &exact) < 1e-7);
    let factorisations =
        |r: &cosserat_solver::NewtonReport| r.factorisations.llt + r.factorisations.lblt + r.factorisations.lu;

    // The next "time step": the far end moves by 1 %. The first solve's factors start this one.
    let b = [3.03, 2.02, 1.515];
    let last = 3 * (chain.n_nodes - 1);
    x[last..].copy_from_slice(&b);
    let moved = solver.solve(&mut chain, &mut x).unwrap();
    assert!(off(&x, &chain_equilibrium(&chain, b)) < 1e-7);
    assert_eq!(factorisations(&moved), 0, "{moved:?}");
    assert!(moved.chord_iterations >= 1);

    // A node fixed from now on: the carried factors treat it as free, so they may not be used, and it
    // stays where it is.
    let held = 3 * 3;
    chain.fixed[held..held + 3].fill(true);
    let pinned: Vec<f64> = x[held..held + 3].iter().map(|v| v + 0.05).collect();
    x[held..held + 3].copy_from_slice(&pinned);
    let b = [3.06, 2.04, 1.53];
    x[last..].copy_from_slice(&b);
    let report = solver.solve(&mut chain, &mut x).unwrap();
    assert_eq!(&x[held..held + 3], pinned.as_slice());
    assert!(factorisations(&report) >= 1, "{report:?}");
}

/// With `mixed_integration_points`, every solve starts by clearing the predictions, every direction is
/// linearised before its line search, and every accepted step advances the prediction by its length
/// (here the line search's halvings on Rosenbrock); without it, only the clearing is called (a no-op
/// for a problem that never predicted).
#[test]
fn mixed_integration_points_linearise_every_direction_and_advance_by_the_accepted_step() {
    let run = |mixed: bool| {
        let mut problem = Counting::new(Rosenbrock::new(2));
        let mut x = [-1.2, 1.0];
        let settings = NewtonSettings {
            mixed_integration_points: mixed,
            ..reference_newton()
        };
        let report = solve(&mut problem, &mut x, settings).unwrap();
        (report, problem.calls)
    };
    let (report, calls) = run(true);
    assert_eq!(calls[0], "clear");
    let linearised = calls.iter().filter(|c| *c == "linearize").count();
    let advanced: Vec<f64> = calls
        .iter()
        .filter_map(|c| c.strip_prefix("advance ").map(|a| a.parse().unwrap()))
        .collect();
    assert_eq!(linearised, report.iterations);
    assert_eq!(advanced.len(), report.iterations);
    assert!(
        advanced.iter().any(|&a| a < 1.0),
        "the line search never shortened a step"
    );
    // Each advance follows its linearisation, and the next Hessian comes after both.
    for (i, _) in calls.iter().enumerate().filter(|(_, c)| c.starts_with("advance")) {
        assert_eq!(calls[i - 1], "linearize", "{calls:?}");
        if let Some(next) = calls.get(i + 1) {
            assert_eq!(next, "hessian", "{calls:?}");
        }
    }
    let (plain, calls) = run(false);
    assert_eq!(calls.iter().filter(|c| *c != "hessian").collect::<Vec<_>>(), ["clear"]);
    assert_eq!(plain.iterations, report.iterations);
}

/// With `mixed_integration_points`, a solve from a prediction weights its first Hessian's second-order
/// terms with the stresses of the state the prediction extrapolates (the last equilibrium), not with
/// the prediction's own: before that Hessian the strains are linearised there along no step and
/// advanced by nothing. A plain solve starts with the stresses of its own start.
#[test]
fn a_solve_from_a_prediction_starts_with_the_stresses_of_the_unpredicted_state() {
    let settings = NewtonSettings {
        mixed_integration_points: true,
        ..reference_newton()
    };
    let mut problem = Counting::new(Rosenbrock::new(2));
    let mut solver = NewtonSolver::for_problem(&problem, settings).unwrap();
    let mut x = [-1.0, 1.1];
    solver.solve_from_prediction(&mut problem, &mut x, &[-1.2, 1.0]).unwrap();
    assert_eq!(
        problem.calls[..4],
        ["clear", "linearize at [-1.2, 1.0]", "advance 0", "hessian"],
        "{:?}",
        problem.calls
    );
    problem.calls.clear();
    let mut x = [-1.0, 1.1];
    solver.solve(&mut problem, &mut x).unwrap();
    assert_eq!(problem.calls[..2], ["clear", "hessian"], "{:?}", problem.calls);
}

/// A solve from a prediction takes the scale of its relative test from the state the prediction
/// extrapolates (where the residual of ½xᵀAx − bᵀx is max |b|), not from the prediction, whose residual
/// is its own error: from a prediction a thousand units off, the plain solve would accept residuals a
/// million times larger.
#[test]
fn a_solve_from_a_prediction_measures_the_load_scale_at_the_unpredicted_start() {
    let mut r = rng(12);
    let a = block_grid(4, 3, 1e-1, &mut r);
    let b: Vec<f64> = random_vector(a.n(), &mut r).iter().map(|v| 1e-3 * v).collect();
    let b_max = b.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let mut problem = Quadratic { a, b };
    let n = problem.n_dofs();
    let settings = NewtonSettings::default();
    let mut solver = NewtonSolver::for_problem(&problem, settings).unwrap();
    let prediction = vec![1e3; n];
    let mut x = prediction.clone();
    let plain = solver.solve(&mut problem, &mut x).unwrap();
    assert!(plain.convergence.load_scale > 1e3 * b_max);
    let mut x = prediction;
    let predicted = solver.solve_from_prediction(&mut problem, &mut x, &vec![0.0; n]).unwrap();
    assert_eq!(predicted.convergence.load_scale, b_max);
    assert!(predicted.residual() <= 1e-6 * b_max);
    // The measured scale is spent by its solve: the next plain solve measures its own.
    let mut x = vec![1e3; n];
    assert_eq!(
        solver.solve(&mut problem, &mut x).unwrap().convergence.load_scale,
        plain.convergence.load_scale
    );
}

/// A sheet pulled taut within one solve: Newton's method from rest, with the stabilisation raised at
/// the accepted iterates that outrun it, converges to a stationary point of the final energy at which it
/// is positive definite; with the stabilisation of the start the energy has no minimum to find. A
/// failed solve puts the stabilisation back.
#[test]
fn following_the_iterate_keeps_a_sheet_pulled_taut_stable() {
    let settings = NewtonSettings {
        tolerance: Tolerance::Absolute(1e-12),
        ..NewtonSettings::default()
    };
    let mut taut = Taut::new(true);
    let mut x = [0.0, 0.0];
    let report = solve(&mut taut, &mut x, settings).unwrap();
    assert!(taut.raised >= 1, "the stabilisation never followed");
    assert_eq!(report.residuals.len(), report.iterations + 1);
    assert!(report.iterations <= 10, "{} iterations", report.iterations);
    let mut g = [0.0; 2];
    let mut h = [0.0; 3];
    taut.hessian(&x, &mut g, &mut h).unwrap();
    assert!(g[0].abs().max(g[1].abs()) <= 1e-12, "gradient {g:?} at {x:?}");
    assert!(h[0] > 0.0 && h[0] * h[2] - h[1] * h[1] > 0.0, "Hessian {h:?} at {x:?}");
    // The stretch nearly the pull, the turn that of the final stiffness.
    assert!((x[0] - taut.pull).abs() < 1e-3, "{x:?}");
    assert!((x[1] - taut.load / (taut.floor + taut.stabilisation - x[0])).abs() < 1e-12);

    let mut fixed = Taut::new(false);
    let mut x = [0.0, 0.0];
    assert!(
        solve(&mut fixed, &mut x, settings).is_err(),
        "with the start's stabilisation the solve ended at {x:?}"
    );

    let mut failing = Taut::new(true);
    let mut x = [0.0, 0.0];
    let short = NewtonSettings {
        max_iterations: 1,
        ..settings
    };
    assert!(solve(&mut failing, &mut x, short).is_err());
    assert!(failing.raised >= 1, "the failed solve never followed");
    assert_eq!(failing.stabilisation, 0.0);
}

/// An angle 0.01° short of a half turn, reached by a Cayley-type update: rebased at the angles it
/// reaches, Newton converges in a few iterations; the update alone must send its unknown towards
/// 2 tan(89.995°) ≈ 2.3e4 along a vanishing derivative. A failed solve puts the base back.
#[test]
fn rebasing_takes_an_update_past_its_singularity() {
    let target = (180.0_f64 - 0.01).to_radians();
    let settings = NewtonSettings {
        tolerance: Tolerance::Absolute(1e-12),
        ..NewtonSettings::default()
    };
    let mut rebased = HalfTurn::new(target, true);
    let mut x = [0.0];
    let report = solve(&mut rebased, &mut x, settings).unwrap();
    let reached = rebased.base + 2.0 * (0.5 * x[0]).atan();
    assert!((reached - target).abs() < 1e-10, "{reached} against {target}");
    assert!(rebased.rebased >= 1);
    assert_eq!(report.residuals.len(), report.iterations + 1);
    assert!(report.iterations <= 10, "{} iterations", report.iterations);
    let mut alone = HalfTurn::new(target, false);
    let mut x = [0.0];
    let without = solve(&mut alone, &mut x, settings);
    assert!(
        without.as_ref().map_or(true, |r| r.iterations > 2 * report.iterations),
        "without rebasing: {:?} iterations",
        without.map(|r| r.iterations)
    );
    let mut failing = HalfTurn::new(target, true);
    let mut x = [0.0];
    let short = NewtonSettings {
        max_iterations: 2,
        ..settings
    };
    assert!(solve(&mut failing, &mut x, short).is_err());
    assert!(failing.rebased >= 1, "the failed solve never rebased");
    assert_eq!(failing.base, failing.start);
}
