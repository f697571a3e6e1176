//! Block-Jacobi PCG: convergence to the requested tolerance on SPD systems, agreement with the direct
//! solver, exactness of the preconditioner on block-diagonal matrices, negative curvature, bad input.

use super::common::{dense, rng};
use cosserat_assembly::SparsityPattern;
use cosserat_assembly::scatter::ElementScatter;
use cosserat_solver::linear::{LinearSolverKind, LinearSolverSettings, SparseSolver};
use cosserat_volume::CgError;
use cosserat_volume::pcg::{BlockJacobi, CgSettings, CgWorkspace, SymmetricUpper, pcg};
use nalgebra::{DVector, SMatrix};
use rand::Rng;

/// A random SPD matrix with the block structure of a chain of 3-block "elements": a sum of element
/// Gram matrices plus a small multiple of the identity (condition number ~1e4).
fn spd_system(n_blocks: usize, seed: u64) -> (SparsityPattern, Vec<f64>) {
    let mut r = rng(seed);
    let groups: Vec<[usize; 3]> = (0..n_blocks - 2).map(|e| [e, e + 1, e + 2]).collect();
    let pattern = SparsityPattern::from_groups(n_blocks, groups.iter().map(|g| &g[..]));
    let scatter = ElementScatter::new(&pattern, groups.clone());
    let mut values = vec![0.0; pattern.nnz()];
    for e in 0..groups.len() {
        let m = SMatrix::<f64, 9, 9>::from_fn(|_, _| r.random_range(-1.0..1.0));
        let h = m.transpose() * m + SMatrix::<f64, 9, 9>::identity() * 1e-3;
        scatter.add_hessian(e, &h, &pattern, &mut values);
    }
    (pattern, values)
}

#[test]
fn converges_to_the_requested_tolerance_and_agrees_with_cholesky() {
    let (pattern, values) = spd_system(60, 1);
    let n = pattern.n_dofs();
    let mut r = rng(2);
    let b: Vec<f64> = (0..n).map(|_| r.random_range(-1.0..1.0)).collect();
    let a = SymmetricUpper {
        pattern: pattern.symbolic(),
        values: &values,
    };
    let m = BlockJacobi::new(&a);
    let dense_a = dense(&pattern, &values);
    let b_vec = DVector::from_column_slice(&b);
    let mut ws = CgWorkspace::default();
    let mut direct = b.clone();
    let mut solver = SparseSolver::try_new(
        pattern.symbolic(),
        LinearSolverSettings {
            kind: LinearSolverKind::Cholesky,
            ..Default::default()
        },
    )
    .unwrap();
    solver.factorise(&values, None).unwrap();
    solver.solve_in_place(&mut direct).unwrap();
    let cond = {
        let eig = dense_a.clone().symmetric_eigen().eigenvalues;
        eig.max() / eig.min()
    };
    for tol in [1e-4, 1e-8, 1e-12] {
        let mut x = vec![0.0; n];
        let report = pcg(
            &a,
            &m,
            &b,
            &mut x,
            &CgSettings {
                relative_tolerance: tol,
                max_iterations: 10_000,
            },
            &mut ws,
        )
        .unwrap();
        assert!(report.converged && !report.negative_curvature);
        // The true residual, from an independent dense product.
        let res = (&b_vec - &dense_a * DVector::from_column_slice(&x)).norm() / b_vec.norm();
        assert!(res <= 1.5 * tol, "tolerance {tol}: true relative residual {res}");
        assert!(report.relative_residual <= tol);
        // ‖x − x*‖/‖x*‖ ≤ κ ‖r‖/‖b‖.
        let diff = (DVector::from_column_slice(&x) - DVector::from_column_slice(&direct)).norm();
        let rel = diff / DVector::from_column_slice(&direct).norm();
        assert!(
            rel <= cond * 1.5 * tol + 1e-10,
            "tolerance {tol}: error {rel} (condition {cond:.1e})"
        );
    }
}

#[test]
fn block_jacobi_is_exact_on_block_diagonal_matrices() {
    let mut r = rng(3);
    let pattern = SparsityPattern::from_groups(10, std::iter::empty());
    let scatter = ElementScatter::new(&pattern, (0..10).map(|b| [b]).collect());
    let mut values = vec![0.0; pattern.nnz()];
    for e in 0..10 {
        let m = SMatrix::<f64, 3, 3>::from_fn(|_, _| r.random_range(-1.0..1.0));
        scatter.add_hessian(
            e,
            &(m.transpose() * m + SMatrix::<f64, 3, 3>::identity() * 0.1),
            &pattern,
            &mut values,
        );
    }
    let a = SymmetricUpper {
        pattern: pattern.symbolic(),
        values: &values,
    };
    let b: Vec<f64> = (0..30).map(|i| (i as f64).sin()).collect();
    let mut x = vec![0.0; 30];
    let report = pcg(
        &a,
        &BlockJacobi::new(&a),
        &b,
        &mut x,
        &CgSettings::default(),
        &mut CgWorkspace::default(),
    )
    .unwrap();
    assert_eq!(report.iterations, 1);
    assert!(report.relative_residual < 1e-12);
}

#[test]
fn negative_curvature_stops_with_a_descent_direction() {
    // diag(2, −1, 3) with b = (1, 1, 1): the preconditioner uses |A| on the indefinite block, so the first direction is M⁻¹ b = (1/2, 1, 1/3), of curvature
    // pᵀAp = 1/2 − 1 + 1/3 < 0, so the iteration stops at once with a multiple of M⁻¹ b.
    let pattern = SparsityPattern::from_groups(1, std::iter::empty());
    let mut values = vec![0.0; pattern.nnz()];
    for (i, d) in [2.0, -1.0, 3.0].into_iter().enumerate() {
        values[pattern.entry(i, i).unwrap()] = d;
    }
    let a = SymmetricUpper {
        pattern: pattern.symbolic(),
        values: &values,
    };
    let b = [1.0, 1.0, 1.0];
    let mut x = [0.0; 3];
    let report = pcg(
        &a,
        &BlockJacobi::new(&a),
        &b,
        &mut x,
        &CgSettings::default(),
        &mut CgWorkspace::default(),
    )
    .unwrap();
    assert!(report.negative_curvature && !report.converged);
    // Descent for the quadratic ½ xᵀAx − bᵀx at 0: bᵀx > 0.
    assert!(b.iter().zip(&x).map(|(b, x)| b * x).sum::<f64>() > 0.0);
    // The preconditioner used |A| on the indefinite block: x ∥ (1/2, 1, 1/3).
    assert!((x[1] / x[0] - 2.0).abs() < 1e-12 && (x[2] / x[0] - 2.0 / 3.0).abs() < 1e-12);
}

#[test]
fn iteration_cap_and_bad_input() {
    let (pattern, mut values) = spd_system(30, 4);
    let n = pattern.n_dofs();
    let b = vec![1.0; n];
    let mut x = vec![0.0; n];
    let mut ws = CgWorkspace::default();
    {
        let a = SymmetricUpper {
            pattern: pattern.symbolic(),
            values: &values,
        };
        let m = BlockJacobi::new(&a);
        let capped = CgSettings {
            relative_tolerance: 1e-14,
            max_iterations: 3,
        };
        let report = pcg(&a, &m, &b, &mut x, &capped, &mut ws).unwrap();
        assert_eq!(report.iterations, 3);
        assert!(!report.converged && report.relative_residual < 1.0);
        let mut bad_b = b.clone();
        bad_b[5] = f64::NAN;
        assert!(matches!(
            pcg(&a, &m, &bad_b, &mut x, &capped, &mut ws),
            Err(CgError::NonFiniteRhs { index: 5, .. })
        ));
    }
    values[7] = f64::INFINITY;
    let a = SymmetricUpper {
        pattern: pattern.symbolic(),
        values: &values,
    };
    let m = BlockJacobi::new(&a);
    assert!(matches!(
        pcg(&a, &m, &b, &mut x, &CgSettings::default(), &mut ws),
        Err(CgError::NonFiniteMatrix { index: 7, .. })
    ));
}
