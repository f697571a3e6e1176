//! Sparse symmetric solvers: accuracy on SPD and indefinite matrices against dense references,
//! symbolic reuse, elimination of fixed unknowns, error reporting and factor statistics.

use cosserat_sparse::{
    Factorisation, FillOrdering, LinearSolveError, LinearSolverKind, LinearSolverSettings, SparseSolver,
};
use faer::sparse::SymbolicSparseColMat;
use nalgebra::{DMatrix, DVector};

use cosserat_sparse::testing::{
    PatternBuilder, UpperMatrix, block_grid, laplacian_2d, random_vector, relative_residual, rng, saddle_point,
};

const ALL_KINDS: [LinearSolverKind; 4] = [
    LinearSolverKind::Cholesky,
    LinearSolverKind::Ldlt,
    LinearSolverKind::Lu,
    LinearSolverKind::Auto,
];

fn settings(kind: LinearSolverKind) -> LinearSolverSettings {
    LinearSolverSettings {
        kind,
        ..Default::default()
    }
}

/// Factorises and solves `A x = b`, returning `x` and the factorisation used.
fn solve(
    a: &UpperMatrix,
    b: &[f64],
    kind: LinearSolverKind,
    fixed: Option<&[bool]>,
) -> Result<(Vec<f64>, Factorisation), LinearSolveError> {
    let mut solver = SparseSolver::try_new(a.pattern.as_ref(), settings(kind))?;
    solver.factorise(&a.values, fixed)?;
    let mut x = b.to_vec();
    let used = solver.solve_in_place(&mut x)?;
    Ok((x, used))
}

fn expected_spd_factorisation(kind: LinearSolverKind) -> Factorisation {
    match kind {
        LinearSolverKind::Ldlt => Factorisation::Lblt,
        LinearSolverKind::Lu => Factorisation::Lu,
        _ => Factorisation::Llt,
    }
}

#[test]
fn spd_laplacian_is_solved_by_every_kind() {
    let mut r = rng(1);
    let a = laplacian_2d(17, 13, &mut r);
    let b = random_vector(a.n(), &mut r);
    for kind in ALL_KINDS {
        let (x, used) = solve(&a, &b, kind, None).unwrap();
        assert_eq!(used, expected_spd_factorisation(kind), "{kind:?}");
        let res = relative_residual(&a, &x, &b);
        assert!(res <= 1e-10, "{kind:?}: relative residual {res:e}");
    }
}

#[test]
fn spd_block_pattern_is_solved_by_every_kind() {
    let mut r = rng(2);
    let a = block_grid(7, 6, 1e-2, &mut r);
    let b = random_vector(a.n(), &mut r);
    for kind in ALL_KINDS {
        let (x, used) = solve(&a, &b, kind, None).unwrap();
        assert_eq!(used, expected_spd_factorisation(kind), "{kind:?}");
        let res = relative_residual(&a, &x, &b);
        assert!(res <= 1e-10, "{kind:?}: relative residual {res:e}");
    }
}

#[test]
fn every_ordering_solves_definite_and_indefinite_systems() {
    // The symmetric factorisations work on the matrix in their own order (gathered through a map built
    // with the analysis) and move the right-hand side into it and back: every order must give the
    // caller's solution, for the Cholesky factor and for L B Lᵀ.
    let mut r = rng(3);
    let spd = block_grid(5, 4, 1e-1, &mut r);
    let k = laplacian_2d(9, 8, &mut r);
    let indefinite = saddle_point(&k, 12, 3, 1e-3, &mut r);
    let orderings = [
        FillOrdering::Identity,
        FillOrdering::Amd,
        FillOrdering::Auto,
        FillOrdering::NestedDissection { block: 1 },
    ];
    for ordering in orderings {
        for (a, kinds) in [(&spd, &ALL_KINDS[..]), (&indefinite, &[LinearSolverKind::Ldlt][..])] {
            let b = random_vector(a.n(), &mut r);
            for &kind in kinds {
                let s = LinearSolverSettings {
                    kind,
                    ordering,
                    ..Default::default()
                };
                let mut solver = SparseSolver::try_new(a.pattern.as_ref(), s).unwrap();
                // Twice: the second factorisation gathers new values into the same reordered pattern.
                for scale in [1.0, 2.0] {
                    let scaled = a.with_values(a.values.iter().map(|v| v * scale).collect());
                    solver.factorise(&scaled.values, None).unwrap();
                    let mut x = b.clone();
                    solver.solve_in_place(&mut x).unwrap();
                    let res = relative_residual(&scaled, &x, &b);
                    assert!(
                        res <= 1e-10,
                        "{ordering:?} {kind:?} ×{scale}: relative residual {res:e}"
                    );
                }
            }
        }
    }
}

#[test]
fn saddle_point_matrix_is_rejected_by_cholesky_and_solved_by_the_others() {
    let mut r = rng(4);
    let k = laplacian_2d(9, 8, &mut r);
    let a = saddle_point(&k, 12, 3, 1e-3, &mut r);
    let b = random_vector(a.n(), &mut r);
    assert!(matches!(
        solve(&a, &b, LinearSolverKind::Cholesky, None),
        Err(LinearSolveError::NotPositiveDefinite { .. })
    ));
    // Reference: dense LU of the full matrix (nalgebra).
    let reference = a.to_dense().lu().solve(&DVector::from_column_slice(&b)).unwrap();
    for kind in [LinearSolverKind::Ldlt, LinearSolverKind::Lu, LinearSolverKind::Auto] {
        let (x, used) = solve(&a, &b, kind, None).unwrap();
        if kind == LinearSolverKind::Auto {
            assert_ne!(used, Factorisation::Llt, "Auto must fall back from Cholesky");
        }
        assert!(relative_residual(&a, &x, &b) <= 1e-10, "{kind:?}");
        let err = (DVector::from_column_slice(&x) - &reference).norm() / reference.norm();
        assert!(
            err <= 1e-9,
            "{kind:?}: relative difference to the dense solution {err:e}"
        );
    }
}

#[test]
fn auto_keeps_to_l_b_lt_while_the_matrices_stay_indefinite_and_returns_to_cholesky() {
    // After an indefinite matrix `Auto` starts with L B Lᵀ; where that finds the matrix positive
    // definite, Cholesky must still be the factorisation used, as without the shortcut.
    let mut r = rng(15);
    let k = laplacian_2d(9, 8, &mut r);
    let indefinite = saddle_point(&k, 12, 3, 1e-3, &mut r);
    let entries = indefinite.entries();
    let mut off_diagonal = vec![0.0; indefinite.n()];
    for (&(i, j), v) in entries.iter().zip(&indefinite.values) {
        if i != j {
            off_diagonal[i] += v.abs();
            off_diagonal[j] += v.abs();
        }
    }
    // The same pattern, diagonally dominant: positive definite.
    let definite = indefinite.with_values(
        entries
            .iter()
            .zip(&indefinite.values)
            .map(|(&(i, j), &v)| if i == j { off_diagonal[i] + 1.0 } else { v })
            .collect(),
    );
    let mut solver = SparseSolver::try_new(indefinite.pattern.as_ref(), LinearSolverSettings::default()).unwrap();
    let b = random_vector(indefinite.n(), &mut r);
    let sequence = [
        (&definite, Factorisation::Llt),
        (&indefinite, Factorisation::Lblt),
        (&indefinite, Factorisation::Lblt),
        (&definite, Factorisation::Llt),
        (&definite, Factorisation::Llt),
        (&indefinite, Factorisation::Lblt),
    ];
    for (step, (a, expected)) in sequence.into_iter().enumerate() {
        assert_eq!(solver.factorise(&a.values, None), Ok(expected), "step {step}");
        let mut x = b.clone();
        solver.solve_in_place(&mut x).unwrap();
        let res = relative_residual(a, &x, &b);
        assert!(res <= 1e-10, "step {step}: relative residual {res:e}");
    }
}

#[test]
fn saddle_point_with_zero_block_is_solved_by_auto() {
    // A zero (2, 2) block makes every unpivoted factorisation break down; Auto must still solve it,
    // with the pivoted L B Lᵀ or, failing that, LU.
    let mut r = rng(5);
    let k = laplacian_2d(8, 8, &mut r);
    let a = saddle_point(&k, 10, 4, 0.0, &mut r);
    let b = random_vector(a.n(), &mut r);
    let (x, used) = solve(&a, &b, LinearSolverKind::Auto, None).unwrap();
    assert_ne!(used, Factorisation::Llt);
    assert!(relative_residual(&a, &x, &b) <= 1e-10);
    let (x, _) = solve(&a, &b, LinearSolverKind::Lu, None).unwrap();
    assert!(relative_residual(&a, &x, &b) <= 1e-10);
}

#[test]
fn backward_error_bound_is_enforced_and_auto_falls_back_to_lu() {
    // A bound no floating-point solution can meet: L B Lᵀ is rejected as inaccurate, Auto retries with
    // LU, which is rejected as well, and the error names the factorisation that failed last.
    let mut r = rng(15);
    let k = laplacian_2d(6, 5, &mut r);
    let a = saddle_point(&k, 5, 3, 1e-2, &mut r);
    let b = random_vector(a.n(), &mut r);
    for (kind, expected) in [
        (LinearSolverKind::Ldlt, Factorisation::Lblt),
        (LinearSolverKind::Auto, Factorisation::Lu),
    ] {
        let s = LinearSolverSettings {
            kind,
            max_backward_error: 1e-300,
            ..Default::default()
        };
        let mut solver = SparseSolver::try_new(a.pattern.as_ref(), s).unwrap();
        assert_eq!(solver.factorise(&a.values, None).unwrap(), Factorisation::Lblt);
        let mut x = b.clone();
        match solver.solve_in_place(&mut x) {
            Err(LinearSolveError::Inaccurate {
                factorisation,
                backward_error,
                bound,
            }) => {
                assert_eq!(factorisation, expected, "{kind:?}");
                assert!(backward_error > bound && backward_error < 1e-12, "{backward_error:e}");
            }
            other => panic!("{kind:?}: expected Inaccurate, got {other:?}"),
        }
    }
}

#[test]
fn new_values_on_the_same_pattern_reuse_the_symbolic_analysis() {
    let mut r = rng(6);
    let a1 = block_grid(6, 5, 1e-1, &mut r);
    let a2 = block_grid(6, 5, 1e-1, &mut r);
    assert_eq!(a1.pattern.row_idx(), a2.pattern.row_idx());
    let b = random_vector(a1.n(), &mut r);
    for kind in ALL_KINDS {
        let mut solver = SparseSolver::try_new(a1.pattern.as_ref(), settings(kind)).unwrap();
        let analyses = solver.symbolic_analysis_count();
        assert_eq!(analyses, 1, "{kind:?}");
        for (a, other) in [(&a1, &a2), (&a2, &a1), (&a1, &a2)] {
            solver.factorise(&a.values, None).unwrap();
            let mut x = b.clone();
            solver.solve_in_place(&mut x).unwrap();
            assert!(relative_residual(a, &x, &b) <= 1e-10, "{kind:?}");
            // The solution belongs to the new values, not to stale ones.
            assert!(relative_residual(other, &x, &b) > 1e-3, "{kind:?}");
        }
        assert_eq!(solver.symbolic_analysis_count(), analyses, "{kind:?}");
    }
}

#[test]
fn auto_analyses_lu_at_most_once() {
    let mut r = rng(7);
    let k = laplacian_2d(6, 6, &mut r);
    let a = saddle_point(&k, 8, 3, 0.0, &mut r);
    let mut solver = SparseSolver::try_new(a.pattern.as_ref(), settings(LinearSolverKind::Auto)).unwrap();
    for _ in 0..3 {
        let b = random_vector(a.n(), &mut r);
        solver.factorise(&a.values, None).unwrap();
        let mut x = b.clone();
        solver.solve_in_place(&mut x).unwrap();
        assert!(relative_residual(&a, &x, &b) <= 1e-10);
    }
    assert!(solver.symbolic_analysis_count() <= 2);
}

#[test]
fn fixed_unknowns_get_zero_and_the_rest_solves_the_reduced_system() {
    let mut r = rng(8);
    for (a, name) in [
        (block_grid(5, 5, 1e-1, &mut r), "spd"),
        (
            saddle_point(&laplacian_2d(7, 6, &mut r), 6, 3, 1e-2, &mut r),
            "indefinite",
        ),
    ] {
        let n = a.n();
        let fixed: Vec<bool> = (0..n).map(|i| i % 5 == 1 || i == n - 1).collect();
        let free: Vec<usize> = (0..n).filter(|&i| !fixed[i]).collect();
        let b = random_vector(n, &mut r);
        let dense = a.to_dense();
        let reduced = DMatrix::from_fn(free.len(), free.len(), |i, j| dense[(free[i], free[j])]);
        let rhs = DVector::from_iterator(free.len(), free.iter().map(|&i| b[i]));
        let reference = reduced.lu().solve(&rhs).unwrap();
        for kind in ALL_KINDS {
            if name == "indefinite" && kind == LinearSolverKind::Cholesky {
                continue;
            }
            let (x, _) = solve(&a, &b, kind, Some(&fixed)).unwrap();
            for i in 0..n {
                if fixed[i] {
                    assert_eq!(x[i], 0.0, "{name} {kind:?}: fixed entry {i}");
                }
            }
            let xf = DVector::from_iterator(free.len(), free.iter().map(|&i| x[i]));
            let err = (xf - &reference).norm() / reference.norm();
            assert!(err <= 1e-10, "{name} {kind:?}: {err:e}");
        }
    }
}

#[test]
fn singular_matrix_is_reported_by_every_kind() {
    // [[1, 1], [1, 1]] has rank 1.
    let mut b = PatternBuilder::new(2);
    b.add(0, 0, 1.0);
    b.add(0, 1, 1.0);
    b.add(1, 1, 1.0);
    let a = b.build();
    let rhs = [1.0, 2.0];
    assert!(matches!(
        solve(&a, &rhs, LinearSolverKind::Cholesky, None),
        Err(LinearSolveError::NotPositiveDefinite { .. })
    ));
    for (kind, expected) in [
        (LinearSolverKind::Ldlt, Factorisation::Lblt),
        (LinearSolverKind::Lu, Factorisation::Lu),
        (LinearSolverKind::Auto, Factorisation::Lu),
    ] {
        match solve(&a, &rhs, kind, None) {
            Err(LinearSolveError::Singular { factorisation, .. }) => assert_eq!(factorisation, expected, "{kind:?}"),
            other => panic!("{kind:?}: expected Singular, got {other:?}"),
        }
    }
}

#[test]
fn failed_pivots_name_the_column_in_the_callers_numbering() {
    // A diagonally dominant matrix with one negative diagonal entry at column c: every leading minor
    // without c is positive definite, so elimination in any order fails exactly at c.
    let mut r = rng(14);
    let lap = laplacian_2d(6, 5, &mut r);
    for c in [0, 17, 29] {
        let mut values = lap.values.clone();
        let (index, _) = lap.entries().iter().enumerate().find(|(_, e)| **e == (c, c)).unwrap();
        values[index] = -100.0;
        let a = lap.with_values(values);
        for ordering in [FillOrdering::Amd, FillOrdering::Identity] {
            let s = LinearSolverSettings {
                kind: LinearSolverKind::Cholesky,
                ordering,
                ..Default::default()
            };
            let mut solver = SparseSolver::try_new(a.pattern.as_ref(), s).unwrap();
            assert_eq!(
                solver.factorise(&a.values, None),
                Err(LinearSolveError::NotPositiveDefinite { col: c }),
                "{ordering:?}"
            );
        }
    }
    // Diagonal matrices get a simplicial analysis from faer whatever is requested: the same holds.
    let mut b = PatternBuilder::new(4);
    for (j, d) in [1.0, 1.0, -1.0, 1.0].into_iter().enumerate() {
        b.add(j, j, d);
    }
    let a = b.build();
    for ordering in [FillOrdering::Amd, FillOrdering::Identity] {
        let s = LinearSolverSettings {
            kind: LinearSolverKind::Cholesky,
            ordering,
            ..Default::default()
        };
        let mut solver = SparseSolver::try_new(a.pattern.as_ref(), s).unwrap();
        assert_eq!(
            solver.factorise(&a.values, None),
            Err(LinearSolveError::NotPositiveDefinite { col: 2 })
        );
    }
    // An indefinite diagonal matrix is solved exactly by the symmetric indefinite factorisation; a
    // zero on the diagonal is reported with its column.
    let (x, used) = solve(&a, &[1.0, 2.0, 3.0, 4.0], LinearSolverKind::Ldlt, None).unwrap();
    assert_eq!(used, Factorisation::Lblt);
    assert_eq!(x, vec![1.0, 2.0, -3.0, 4.0]);
    let mut b = PatternBuilder::new(3);
    for (j, d) in [2.0, 0.0, 1.0].into_iter().enumerate() {
        b.add(j, j, d);
    }
    let a = b.build();
    assert_eq!(
        solve(&a, &[1.0, 1.0, 1.0], LinearSolverKind::Ldlt, None).unwrap_err(),
        LinearSolveError::Singular {
            factorisation: Factorisation::Lblt,
            col: Some(1)
        }
    );
}

#[test]
fn non_finite_input_is_named() {
    let mut r = rng(9);
    let a = laplacian_2d(3, 3, &mut r);
    let mut solver = SparseSolver::try_new(a.pattern.as_ref(), LinearSolverSettings::default()).unwrap();
    let mut x = vec![1.0; a.n()];
    assert_eq!(solver.solve_in_place(&mut x), Err(LinearSolveError::NotFactorised));

    let mut values = a.values.clone();
    values[4] = f64::NAN;
    let (row, col) = a.entries()[4];
    match solver.factorise(&values, None) {
        Err(LinearSolveError::NonFiniteValue {
            index,
            row: r0,
            col: c0,
            ..
        }) => {
            assert_eq!((index, r0, c0), (4, row, col));
        }
        other => panic!("expected NonFiniteValue, got {other:?}"),
    }
    // A failed factorisation leaves nothing to solve with.
    assert_eq!(solver.solve_in_place(&mut x), Err(LinearSolveError::NotFactorised));

    solver.factorise(&a.values, None).unwrap();
    x[2] = f64::INFINITY;
    assert!(matches!(
        solver.solve_in_place(&mut x),
        Err(LinearSolveError::NonFiniteRhs { index: 2, .. })
    ));
}

#[test]
fn malformed_patterns_and_settings_are_rejected() {
    // Column 1 holds row 1 only and column 0 holds rows 0 and 1: an entry below the diagonal.
    let lower = SymbolicSparseColMat::new_checked(2, 2, vec![0, 2, 3], None, vec![0, 1, 1]);
    assert_eq!(
        SparseSolver::try_new(lower.as_ref(), LinearSolverSettings::default()).unwrap_err(),
        LinearSolveError::LowerTriangleEntry { row: 1, col: 0 }
    );
    let no_diagonal = SymbolicSparseColMat::new_checked(2, 2, vec![0, 1, 2], None, vec![0, 0]);
    assert_eq!(
        SparseSolver::try_new(no_diagonal.as_ref(), LinearSolverSettings::default()).unwrap_err(),
        LinearSolveError::MissingDiagonal { col: 1 }
    );
    let diagonal = SymbolicSparseColMat::new_checked(2, 2, vec![0, 1, 2], None, vec![0, 1]);
    let bad = LinearSolverSettings {
        max_backward_error: f64::NAN,
        ..Default::default()
    };
    assert!(matches!(
        SparseSolver::try_new(diagonal.as_ref(), bad),
        Err(LinearSolveError::InvalidBackwardErrorBound { .. })
    ));
}

#[test]
fn factor_statistics_match_closed_forms() {
    // A dense SPD matrix: L is full lower triangular, c_j = n − j, so nnz(L) = n(n+1)/2 and
    // Σ c_j² = n(n+1)(2n+1)/6, whatever the ordering and supernode partition.
    let n = 7;
    let mut b = PatternBuilder::new(n);
    for j in 0..n {
        for i in 0..=j {
            b.add(i, j, if i == j { n as f64 + 1.0 } else { 1.0 });
        }
    }
    let dense = b.build();
    let solver = SparseSolver::try_new(dense.pattern.as_ref(), LinearSolverSettings::default()).unwrap();
    let stats = solver.symmetric_stats().unwrap();
    assert_eq!(stats.nnz_l, n * (n + 1) / 2);
    assert_eq!(stats.flops, (n * (n + 1) * (2 * n + 1) / 6) as f64);

    // A diagonal matrix: L is diagonal, nnz(L) = n, Σ c_j² = n.
    let mut b = PatternBuilder::new(n);
    for j in 0..n {
        b.add(j, j, 2.0);
    }
    let diagonal = b.build();
    let solver = SparseSolver::try_new(diagonal.pattern.as_ref(), LinearSolverSettings::default()).unwrap();
    let stats = solver.symmetric_stats().unwrap();
    assert_eq!((stats.nnz_l, stats.flops), (n, n as f64));

    // Pure LU does not expose its factor structure.
    let lu = SparseSolver::try_new(diagonal.pattern.as_ref(), settings(LinearSolverKind::Lu)).unwrap();
    assert!(lu.symmetric_stats().is_none());
}

#[test]
fn changing_the_kind_keeps_the_symmetric_analysis() {
    let mut r = rng(10);
    let a = block_grid(4, 4, 1e-1, &mut r);
    let b = random_vector(a.n(), &mut r);
    let mut solver = SparseSolver::try_new(a.pattern.as_ref(), settings(LinearSolverKind::Cholesky)).unwrap();
    solver.set_settings(settings(LinearSolverKind::Ldlt)).unwrap();
    assert_eq!(solver.symbolic_analysis_count(), 1);
    assert_eq!(solver.factorisation(), None);
    solver.set_settings(settings(LinearSolverKind::Lu)).unwrap();
    assert_eq!(solver.symbolic_analysis_count(), 2);
    solver.factorise(&a.values, None).unwrap();
    let mut x = b.clone();
    assert_eq!(solver.solve_in_place(&mut x).unwrap(), Factorisation::Lu);
    assert!(relative_residual(&a, &x, &b) <= 1e-10);
    assert!(solver.last_backward_error().unwrap() <= 1e-12);
}
