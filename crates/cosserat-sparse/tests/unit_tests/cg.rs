//! Block-Jacobi preconditioned conjugate gradients (`LinearSolverKind::Cg`): the requested relative
//! tolerance on SPD systems and agreement with Cholesky, exactness of the preconditioner on
//! block-diagonal matrices, negative curvature, caps, fixed unknowns and settings.

use cosserat_sparse::{
    CgSettings, CgStop, Factorisation, LinearSolveError, LinearSolverKind, LinearSolverSettings, SparseSolver,
};
use nalgebra::DMatrix;
use rand::Rng;

use cosserat_sparse::testing::{
    PatternBuilder, UpperMatrix, block_grid, laplacian_2d, random_vector, relative_residual, rng,
};

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
