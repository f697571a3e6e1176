//! Block-Jacobi preconditioned conjugate gradients (`LinearSolverKind::Cg`): the requested relative
//! tolerance on SPD systems and agreement with Cholesky, exactness of the preconditioner on
//! block-diagonal matrices, negative curvature, caps, fixed unknowns and settings; and Newton's method
//! with CG steps on the toy problems.

use cosserat_solver::{
    CgForcing, CgSettings, CgStop, Factorisation, LinearSolveError, LinearSolverKind, LinearSolverSettings,
    NewtonError, NewtonProblem, NewtonSettings, NewtonSolver, SettingName, SparseSolver,
};
use nalgebra::{DMatrix, DVector};
use rand::Rng;

use super::fixtures::{PatternBuilder, UpperMatrix, block_grid, laplacian_2d, random_vector, relative_residual, rng};
use super::toy::{Quadratic, Rosenbrock, SpringChain};

fn cg_settings(relative_tolerance: f64, max_iterations: Option<usize>) -> LinearSolverSettings {
    LinearSolverSettings {
        kind: LinearSolverKind::Cg,
        cg: CgSettings {
            relative_tolerance,
            max_iterations,
        },
        ..Default::default()
    }
}

/// Runs CG on `A x = b` and returns `x` with the solver (for its report).
fn cg_solve(
    a: &UpperMatrix,
    b: &[f64],
    settings: LinearSolverSettings,
    fixed: Option<&[bool]>,
) -> (Vec<f64>, SparseSolver) {
    let mut solver = SparseSolver::try_new(a.pattern.as_ref(), settings).unwrap();
    assert_eq!(solver.factorise(&a.values, fixed).unwrap(), Factorisation::Cg);
    let mut x = b.to_vec();
    assert_eq!(solver.solve_in_place(&mut x).unwrap(), Factorisation::Cg);
    (x, solver)
}

fn cholesky_solve(a: &UpperMatrix, b: &[f64], fixed: Option<&[bool]>) -> Vec<f64> {
    let settings = LinearSolverSettings {
        kind: LinearSolverKind::Cholesky,
        ..Default::default()
    };
    let mut solver = SparseSolver::try_new(a.pattern.as_ref(), settings).unwrap();
    solver.factorise(&a.values, fixed).unwrap();
    let mut x = b.to_vec();
    solver.solve_in_place(&mut x).unwrap();
    x
}

/// The 2-norm condition number from the dense twin's eigenvalues.
fn condition_number(a: &UpperMatrix) -> f64 {
    let eig = a.to_dense().symmetric_eigen().eigenvalues;
    assert!(eig.min() > 0.0, "the fixture must be positive definite");
    eig.max() / eig.min()
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

#[test]
fn spd_systems_are_solved_to_the_requested_tolerance_and_agree_with_cholesky() {
    let mut r = rng(21);
    let laplacian = laplacian_2d(17, 13, &mut r);
    let blocks = block_grid(7, 6, 1e-2, &mut r);
    for a in [laplacian, blocks] {
        let b = random_vector(a.n(), &mut r);
        let direct = cholesky_solve(&a, &b, None);
        let kappa = condition_number(&a);
        for tol in [1e-4, 1e-8, 1e-12] {
            let (x, solver) = cg_solve(&a, &b, cg_settings(tol, Some(10_000)), None);
            let report = solver.last_cg_report().unwrap();
            assert_eq!(report.stop, CgStop::Converged);
            assert_eq!(report.relative_tolerance, tol);
            assert!(report.relative_residual <= tol);
            assert!(report.iterations > 0 && report.iterations == solver.last_cg_iterations());
            // The true residual from the dense twin: the recursive residual drifts from it only by
            // round-off (about 1e-16 κ).
            let res = relative_residual(&a, &x, &b);
            assert!(
                res <= 1.5 * tol,
                "n = {}, tolerance {tol}: relative residual {res:e}",
                a.n()
            );
            // ‖x − x*‖/‖x*‖ ≤ κ ‖b − A x‖/‖b‖.
            let diff: Vec<f64> = x.iter().zip(&direct).map(|(p, q)| p - q).collect();
            let err = norm(&diff) / norm(&direct);
            assert!(
                err <= kappa * res * (1.0 + 1e-6),
                "tolerance {tol}: error {err:e}, κ = {kappa:.1e}"
            );
            // No backward-error check and no symbolic analysis for CG.
            assert_eq!(solver.last_backward_error(), None);
            assert_eq!(solver.symbolic_analysis_count(), 0);
            assert!(solver.symmetric_stats().is_none());
        }
    }
}

#[test]
fn block_jacobi_is_exact_on_block_diagonal_matrices() {
    // Random SPD 3×3 blocks, and a trailing 1×1 block (dimension 3·5 + 1), which the preconditioner pads
    // with the identity: M⁻¹ = A⁻¹, so CG converges in one iteration.
    let mut r = rng(22);
    let n = 16;
    let mut builder = PatternBuilder::new(n);
    for blk in 0..5 {
        let g = DMatrix::<f64>::from_fn(3, 3, |_, _| r.random_range(-1.0..1.0));
        let k = g.transpose() * g + DMatrix::<f64>::identity(3, 3) * 0.1;
        for i in 0..3 {
            for j in i..3 {
                builder.add(3 * blk + i, 3 * blk + j, k[(i, j)]);
            }
        }
    }
    builder.add(15, 15, 2.5);
    let a = builder.build();
    let b = random_vector(n, &mut r);
    let (x, solver) = cg_solve(&a, &b, cg_settings(1e-12, None), None);
    let report = solver.last_cg_report().unwrap();
    assert_eq!(report.iterations, 1);
    assert_eq!(report.stop, CgStop::Converged);
    assert!(relative_residual(&a, &x, &b) < 1e-13);
}

#[test]
fn negative_curvature_stops_with_a_descent_direction() {
    // diag(2, −1, 3), b = (1, 1, 1): the preconditioner takes |A| on the indefinite block, so the first
    // direction is M⁻¹ b = (1/2, 1, 1/3) with curvature 1/2 − 1 + 1/3 < 0, and CG stops at once with a
    // positive multiple of it: bᵀx > 0, a descent direction of ½ xᵀAx − bᵀx at 0.
    let mut builder = PatternBuilder::new(3);
    for (i, d) in [2.0, -1.0, 3.0].into_iter().enumerate() {
        builder.add(i, i, d);
    }
    let a = builder.build();
    let b = [1.0, 1.0, 1.0];
    let (x, solver) = cg_solve(&a, &b, cg_settings(1e-10, None), None);
    let report = solver.last_cg_report().unwrap();
    assert_eq!((report.stop, report.iterations), (CgStop::NegativeCurvature, 1));
    assert!(b.iter().zip(&x).map(|(b, x)| b * x).sum::<f64>() > 0.0);
    assert!((x[1] / x[0] - 2.0).abs() < 1e-14 && (x[2] / x[0] - 2.0 / 3.0).abs() < 1e-14);

    // A shifted Laplacian with many negative eigenvalues: CG stops somewhere along the way, and the
    // iterate it returns still has bᵀx > 0.
    let mut r = rng(23);
    let lap = laplacian_2d(12, 10, &mut r);
    let shifted: Vec<f64> = lap
        .values
        .iter()
        .zip(lap.entries())
        .map(|(&v, (i, j))| if i == j { v - 4.5 } else { v })
        .collect();
    let indefinite = lap.with_values(shifted);
    let eig = indefinite.to_dense().symmetric_eigen().eigenvalues;
    assert!(eig.min() < 0.0 && eig.max() > 0.0);
    for seed in 0..5 {
        let b = random_vector(indefinite.n(), &mut rng(100 + seed));
        let (x, solver) = cg_solve(&indefinite, &b, cg_settings(1e-10, None), None);
        assert_eq!(solver.last_cg_report().unwrap().stop, CgStop::NegativeCurvature);
        let slope: f64 = b.iter().zip(&x).map(|(b, x)| b * x).sum();
        assert!(slope > 0.0, "seed {seed}: bᵀx = {slope:e}");
    }
}

#[test]
fn the_iteration_cap_returns_the_last_iterate() {
    let mut r = rng(24);
    let a = laplacian_2d(15, 15, &mut r);
    let b = random_vector(a.n(), &mut r);
    let (x, solver) = cg_solve(&a, &b, cg_settings(1e-14, Some(3)), None);
    let report = solver.last_cg_report().unwrap();
    assert_eq!((report.stop, report.iterations), (CgStop::IterationCap, 3));
    let res = relative_residual(&a, &x, &b);
    assert!(
        res < 1.0 && (res - report.relative_residual).abs() < 1e-12,
        "{res} vs {report:?}"
    );
    // The default cap is max(1000, n).
    assert_eq!(CgSettings::default().iteration_cap(10), 1000);
    assert_eq!(CgSettings::default().iteration_cap(5000), 5000);
    assert_eq!(
        CgSettings {
            max_iterations: Some(7),
            ..Default::default()
        }
        .iteration_cap(5000),
        7
    );
}

#[test]
fn fixed_unknowns_get_zero_and_the_rest_matches_cholesky() {
    let mut r = rng(25);
    let a = block_grid(5, 4, 1e-1, &mut r);
    let b = random_vector(a.n(), &mut r);
    let fixed: Vec<bool> = (0..a.n()).map(|i| i % 7 == 0 || i < 3).collect();
    let (x, _) = cg_solve(&a, &b, cg_settings(1e-12, None), Some(&fixed));
    let direct = cholesky_solve(&a, &b, Some(&fixed));
    for i in 0..a.n() {
        if fixed[i] {
            assert_eq!(x[i], 0.0, "fixed unknown {i}");
        } else {
            assert!((x[i] - direct[i]).abs() <= 1e-8 * norm(&direct), "unknown {i}");
        }
    }
}

#[test]
fn zero_right_hand_side_gives_zero_without_iterations() {
    let mut r = rng(26);
    let a = laplacian_2d(4, 4, &mut r);
    let (x, solver) = cg_solve(&a, &vec![0.0; a.n()], cg_settings(1e-8, None), None);
    assert!(x.iter().all(|&v| v == 0.0));
    let report = solver.last_cg_report().unwrap();
    assert_eq!((report.iterations, report.stop), (0, CgStop::Converged));
}

#[test]
fn cg_settings_and_input_are_checked() {
    let mut r = rng(27);
    let a = laplacian_2d(4, 3, &mut r);
    for bad in [0.0, 1.0, -1e-3, f64::NAN] {
        match SparseSolver::try_new(a.pattern.as_ref(), cg_settings(bad, None)) {
            Err(LinearSolveError::InvalidCgTolerance { value }) => {
                assert!(value == bad || (value.is_nan() && bad.is_nan()));
            }
            other => panic!("tolerance {bad}: expected InvalidCgTolerance, got {other:?}"),
        }
    }
    assert_eq!(
        SparseSolver::try_new(a.pattern.as_ref(), cg_settings(1e-6, Some(0))).unwrap_err(),
        LinearSolveError::ZeroCgIterationCap
    );
    let mut solver = SparseSolver::try_new(a.pattern.as_ref(), cg_settings(1e-6, None)).unwrap();
    let mut x = vec![1.0; a.n()];
    assert_eq!(solver.solve_in_place(&mut x), Err(LinearSolveError::NotFactorised));
    solver.factorise(&a.values, None).unwrap();
    assert_eq!(
        solver.set_cg_relative_tolerance(1.5),
        Err(LinearSolveError::InvalidCgTolerance { value: 1.5 })
    );
    assert_eq!(solver.settings().cg.relative_tolerance, 1e-6);
    // A new tolerance keeps the preconditioner: the solve needs no new `factorise`.
    solver.set_cg_relative_tolerance(1e-3).unwrap();
    assert_eq!(solver.factorisation(), Some(Factorisation::Cg));
    solver.solve_in_place(&mut x).unwrap();
    assert_eq!(solver.last_cg_report().unwrap().relative_tolerance, 1e-3);
    x[1] = f64::NAN;
    assert!(matches!(
        solver.solve_in_place(&mut x),
        Err(LinearSolveError::NonFiniteRhs { index: 1, .. })
    ));
    let mut values = a.values.clone();
    values[2] = f64::INFINITY;
    assert!(matches!(
        solver.factorise(&values, None),
        Err(LinearSolveError::NonFiniteValue { index: 2, .. })
    ));
    assert_eq!(Factorisation::Cg.to_string(), "CG");
}

#[test]
fn switching_between_cg_and_factorisations_keeps_analyses() {
    let mut r = rng(28);
    let a = block_grid(4, 4, 1e-1, &mut r);
    let b = random_vector(a.n(), &mut r);
    let mut solver = SparseSolver::try_new(a.pattern.as_ref(), cg_settings(1e-10, None)).unwrap();
    assert_eq!(solver.symbolic_analysis_count(), 0);
    let cholesky = LinearSolverSettings {
        kind: LinearSolverKind::Cholesky,
        ..Default::default()
    };
    solver.set_settings(cholesky).unwrap();
    assert_eq!(solver.symbolic_analysis_count(), 1);
    solver.factorise(&a.values, None).unwrap();
    let mut x = b.clone();
    assert_eq!(solver.solve_in_place(&mut x).unwrap(), Factorisation::Llt);
    assert_eq!(solver.last_cg_report(), None);
    solver.set_settings(cg_settings(1e-10, None)).unwrap();
    assert_eq!(solver.factorisation(), None);
    solver.factorise(&a.values, None).unwrap();
    let mut y = b.clone();
    assert_eq!(solver.solve_in_place(&mut y).unwrap(), Factorisation::Cg);
    assert_eq!(solver.symbolic_analysis_count(), 1);
    assert!(relative_residual(&a, &y, &b) <= 1.5e-10);
}

fn newton_cg(forcing: CgForcing) -> NewtonSettings {
    NewtonSettings {
        linear_solver: cg_settings(1e-8, None),
        cg_forcing: forcing,
        tolerance: cosserat_solver::Tolerance::Absolute(1e-7),
        ..Default::default()
    }
}

#[test]
fn newton_with_cg_minimises_a_quadratic() {
    let mut r = rng(29);
    let a = block_grid(6, 5, 1e-1, &mut r);
    let b = random_vector(a.n(), &mut r);
    let dense = a.to_dense();
    let lambda_min = dense.clone().symmetric_eigen().eigenvalues.min();
    let reference = dense.cholesky().unwrap().solve(&DVector::from_column_slice(&b));
    let mut problem = Quadratic { a, b };
    let mut x = vec![0.0; problem.n_dofs()];
    let mut solver = NewtonSolver::for_problem(&problem, newton_cg(CgForcing::Reference)).unwrap();
    let report = solver.solve(&mut problem, &mut x).unwrap();
    // Inexact steps: convergence, not one iteration.
    assert!(report.residual() < 1e-7);
    assert_eq!(report.residuals.len(), report.iterations + 1);
    assert_eq!(report.factorisations.cg, report.iterations);
    assert_eq!(
        report.factorisations.llt + report.factorisations.lblt + report.factorisations.lu,
        0
    );
    assert!(report.cg_iterations >= report.iterations);
    assert_eq!(report.cg_negative_curvature_stops + report.cg_iteration_cap_stops, 0);
    // ‖x − x*‖₂ ≤ ‖∇Π‖₂ / λ_min ≤ √n · residual / λ_min.
    let n = x.len() as f64;
    let err = (DVector::from_column_slice(&x) - &reference).norm();
    assert!(err <= n.sqrt() * report.residual() / lambda_min, "{err:e}");
    assert_eq!(solver.linear_solver().symbolic_analysis_count(), 0);
}

/// A stretched 3D spring chain between walls, with its straight equilibrium in closed form (equal
/// tension `T` in all springs: `d_i = l_i + T/k_i`, `Σ d_i = |B − A|`), and a perturbed start.
fn stretched_chain() -> (SpringChain, Vec<f64>, Vec<f64>) {
    let stiffness = vec![12.0, 30.0, 20.0, 45.0, 25.0, 18.0];
    let rest_length = vec![0.4, 0.3, 0.5, 0.45, 0.35, 0.5];
    let chain = SpringChain::new(stiffness.clone(), rest_length.clone());
    let n_nodes = chain.n_nodes;
    let end: [f64; 3] = [2.5, -1.5, 2.0];
    let span = end.iter().map(|v| v * v).sum::<f64>().sqrt();
    let tension = (span - rest_length.iter().sum::<f64>()) / stiffness.iter().map(|k| 1.0 / k).sum::<f64>();
    assert!(tension > 0.0);
    let mut exact = vec![0.0; 3 * n_nodes];
    let mut s = 0.0;
    for node in 0..n_nodes {
        for d in 0..3 {
            exact[3 * node + d] = end[d] * s / span;
        }
        if node + 1 < n_nodes {
            s += rest_length[node] + tension / stiffness[node];
        }
    }
    let mut start = exact.clone();
    let mut r = rng(30);
    for node in 1..n_nodes - 1 {
        let p = random_vector(3, &mut r);
        for d in 0..3 {
            start[3 * node + d] += 0.3 * p[d];
        }
    }
    (chain, start, exact)
}

#[test]
fn newton_with_cg_reaches_the_spring_chain_equilibrium_with_fixed_walls() {
    let (mut chain, start, exact) = stretched_chain();
    let mut x = start.clone();
    // The softest mode is transverse with stiffness about T/d ≥ 1 N/m: a force residual of 1e-10 N
    // bounds the position error by about 1e-10 m.
    let settings = NewtonSettings {
        tolerance: cosserat_solver::Tolerance::Absolute(1e-10),
        ..newton_cg(CgForcing::Reference)
    };
    let mut solver = NewtonSolver::for_problem(&chain, settings).unwrap();
    let report = solver.solve(&mut chain, &mut x).unwrap();
    assert!(report.residual() < 1e-10);
    let n = x.len();
    for i in (0..3).chain(n - 3..n) {
        assert_eq!(x[i], start[i], "wall unknown {i} moved");
    }
    let err = x.iter().zip(&exact).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(err < 1e-8, "max position error {err:e}");
    // The inexact steps still converge superlinearly: the reference forcing makes the relative CG
    // residual ~ ‖g‖^{3/2}, so the last residual ratio is far below the linear rate of a fixed forcing.
    let m = report.residuals.len();
    let (a, b, c) = (
        report.residuals[m - 3],
        report.residuals[m - 2],
        report.residuals[m - 1],
    );
    let order = (c / b).ln() / (b / a).ln();
    assert!(order > 1.3, "observed order {order} from {:?}", report.residuals);
}

#[test]
fn a_fixed_forcing_converges_linearly_and_sets_the_cg_tolerance() {
    let (mut chain, start, exact) = stretched_chain();
    let mut x = start;
    let settings = NewtonSettings {
        tolerance: cosserat_solver::Tolerance::Absolute(1e-10),
        ..newton_cg(CgForcing::Fixed(0.25))
    };
    let mut solver = NewtonSolver::for_problem(&chain, settings).unwrap();
    let report = solver.solve(&mut chain, &mut x).unwrap();
    let err = x.iter().zip(&exact).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(err < 1e-8, "max position error {err:e}");
    assert_eq!(
        solver.linear_solver().last_cg_report().unwrap().relative_tolerance,
        0.25
    );
    // Near the solution the Newton map is linear, and each inexact step removes at least the fraction
    // 1 − η of the error in the energy norm (CG is optimal there): the gradient shrinks, but no faster
    // than a fixed fraction per step on average, so more iterations than with the reference forcing.
    let mut reference = newton_cg(CgForcing::Reference);
    reference.tolerance = cosserat_solver::Tolerance::Absolute(1e-10);
    let (mut chain2, start2, _) = stretched_chain();
    let mut x2 = start2;
    let report_ref = NewtonSolver::for_problem(&chain2, reference)
        .unwrap()
        .solve(&mut chain2, &mut x2)
        .unwrap();
    assert!(
        report.iterations > report_ref.iterations,
        "fixed {} vs reference {}",
        report.iterations,
        report_ref.iterations
    );
}

#[test]
fn newton_with_cg_converges_on_the_chained_rosenbrock_function() {
    // The Hessian is indefinite on the way (the direct solver needs L B Lᵀ there); truncated CG still
    // yields descent directions.
    let n = 30;
    let mut problem = Rosenbrock::new(n);
    let mut x: Vec<f64> = (0..n).map(|i| if i % 2 == 0 { -1.2 } else { 1.0 }).collect();
    let mut solver = NewtonSolver::for_problem(&problem, newton_cg(CgForcing::Reference)).unwrap();
    let report = solver.solve(&mut problem, &mut x).unwrap();
    assert!(report.residual() < 1e-7);
    let err = x.iter().map(|v| (v - 1.0).abs()).fold(0.0, f64::max);
    assert!(err < 1e-6, "max |x_i − 1| = {err:e}");
    assert_eq!(report.factorisations.cg, report.iterations);
    // CG meets negative curvature on the way (measured: 3 of 63 solves) and the truncated directions
    // descend without being flipped.
    assert!(report.cg_negative_curvature_stops > 0, "{report:?}");
    assert_eq!(report.direction_flips, 0);
}

#[test]
fn chord_steps_are_not_taken_with_cg() {
    let (mut chain, start, _) = stretched_chain();
    let mut x = start;
    let settings = NewtonSettings {
        reuse_max_ratio: Some(0.9),
        ..newton_cg(CgForcing::Reference)
    };
    let report = NewtonSolver::for_problem(&chain, settings)
        .unwrap()
        .solve(&mut chain, &mut x)
        .unwrap();
    assert_eq!(report.chord_iterations, 0);
    assert_eq!(report.factorisations.cg, report.iterations);
}

#[test]
fn invalid_cg_settings_are_named() {
    let problem = Rosenbrock::new(4);
    let cases = [
        (newton_cg(CgForcing::Fixed(1.5)), SettingName::CgForcing),
        (newton_cg(CgForcing::Fixed(0.0)), SettingName::CgForcing),
        (
            NewtonSettings {
                linear_solver: cg_settings(0.0, None),
                ..Default::default()
            },
            SettingName::CgRelativeTolerance,
        ),
        (
            NewtonSettings {
                linear_solver: cg_settings(1e-8, Some(0)),
                ..Default::default()
            },
            SettingName::CgMaxIterations,
        ),
    ];
    for (settings, expected) in cases {
        match NewtonSolver::for_problem(&problem, settings) {
            Err(NewtonError::InvalidSetting { name, .. }) => assert_eq!(name, expected),
            other => panic!("expected InvalidSetting {expected:?}, got {other:?}"),
        }
    }
}

#[test]
fn an_exactly_stationary_start_converges_with_a_zero_step() {
    // With `min_iterations = 1` (the time stepper's setting) Newton must take a step even at a start that
    // satisfies the tolerance; at an exactly stationary point (a scene at rest, Rosenbrock at (1, 1))
    // that step is zero for a direct solve and for CG alike, and is accepted rather than rejected as a
    // non-descent direction.
    for linear_solver in [LinearSolverSettings::default(), cg_settings(1e-8, None)] {
        let mut problem = Rosenbrock::new(2);
        let mut x = [1.0, 1.0];
        let settings = NewtonSettings {
            min_iterations: 1,
            linear_solver,
            ..Default::default()
        };
        let report = NewtonSolver::for_problem(&problem, settings)
            .unwrap()
            .solve(&mut problem, &mut x)
            .unwrap();
        assert_eq!((report.iterations, report.residuals.clone()), (1, vec![0.0, 0.0]));
        assert_eq!(x, [1.0, 1.0]);
        assert_eq!(report.energy, 0.0);
    }
}
