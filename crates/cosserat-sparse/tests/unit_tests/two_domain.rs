//! The two-domain Cholesky ([`DomainSplit`]): the same solutions as the whole factorisation on
//! connected and disconnected block patterns, fixed unknowns, failed pivots named in the caller's
//! numbering, the fall-back to `L B Lᵀ`, when `Auto` splits, and patterns grown by contact-like
//! couplings that reuse the orders.

use cosserat_sparse::{
    DomainSplit, Factorisation, FillOrdering, LinearSolveError, LinearSolverKind, LinearSolverSettings, SparseSolver,
};
use nalgebra::{DMatrix, DVector};

use cosserat_sparse::testing::{PatternBuilder, UpperMatrix, block_grid, random_vector, relative_residual, rng};

fn settings(kind: LinearSolverKind, domains: DomainSplit) -> LinearSolverSettings {
    LinearSolverSettings {
        kind,
        domains,
        ..Default::default()
    }
}

/// Factorises and solves with the given settings; returns the solution, the factorisation used and
/// the number of domains.
fn solve(
    a: &UpperMatrix,
    b: &[f64],
    s: LinearSolverSettings,
    fixed: Option<&[bool]>,
) -> Result<(Vec<f64>, Factorisation, usize), LinearSolveError> {
    let mut solver = SparseSolver::try_new(a.pattern.as_ref(), s)?;
    let domains = solver.symmetric_stats().map_or(0, |st| st.domains);
    solver.factorise(&a.values, fixed)?;
    let mut x = b.to_vec();
    let used = solver.solve_in_place(&mut x)?;
    Ok((x, used, domains))
}

/// Two block grids of 60 nodes each with no entry between them (two separate bodies: one per domain,
/// an empty separator).
fn two_bodies(r: &mut rand_chacha::ChaCha8Rng) -> UpperMatrix {
    let first = block_grid(10, 6, 1e-2, r);
    let second = block_grid(12, 5, 1e-2, r);
    let offset = first.n();
    let mut b = PatternBuilder::new(offset + second.n());
    for (m, shift) in [(&first, 0), (&second, offset)] {
        for (&v, (i, j)) in m.values.iter().zip(m.entries()) {
            b.add(i + shift, j + shift, v);
        }
    }
    b.build()
}

#[test]
fn two_domains_solve_connected_and_disconnected_patterns_like_the_whole_factorisation() {
    let mut r = rng(41);
    for (a, name) in [
        (block_grid(30, 12, 1e-2, &mut r), "grid"),
        (two_bodies(&mut r), "two bodies"),
    ] {
        let b = random_vector(a.n(), &mut r);
        let (whole, used, domains) =
            solve(&a, &b, settings(LinearSolverKind::Cholesky, DomainSplit::Off), None).unwrap();
        assert_eq!((used, domains), (Factorisation::Llt, 1), "{name}");
        for kind in [LinearSolverKind::Cholesky, LinearSolverKind::Auto] {
            let (x, used, domains) = solve(&a, &b, settings(kind, DomainSplit::Always), None).unwrap();
            assert_eq!((used, domains), (Factorisation::Llt, 2), "{name} {kind:?}");
            let res = relative_residual(&a, &x, &b);
            assert!(res <= 1e-12, "{name} {kind:?}: relative residual {res:e}");
            let diff = DVector::from_column_slice(&x) - DVector::from_column_slice(&whole);
            let rel = diff.norm() / DVector::from_column_slice(&whole).norm();
            assert!(
                rel <= 1e-10,
                "{name} {kind:?}: differs from the whole factorisation by {rel:e}"
            );
        }
    }
}

#[test]
fn two_domains_refactorise_new_values_and_keep_fixed_unknowns_at_zero() {
    let mut r = rng(42);
    let a1 = block_grid(20, 9, 1e-1, &mut r);
    let a2 = block_grid(20, 9, 1e-1, &mut r);
    let n = a1.n();
    let fixed: Vec<bool> = (0..n).map(|i| i % 7 == 3 || i < 3).collect();
    let free: Vec<usize> = (0..n).filter(|&i| !fixed[i]).collect();
    let b = random_vector(n, &mut r);
    let mut solver = SparseSolver::try_new(
        a1.pattern.as_ref(),
        settings(LinearSolverKind::Auto, DomainSplit::Always),
    )
    .unwrap();
    assert_eq!(solver.symmetric_stats().map(|s| s.domains), Some(2));
    for a in [&a1, &a2, &a1] {
        solver.factorise(&a.values, Some(&fixed)).unwrap();
        let mut x = b.clone();
        assert_eq!(solver.solve_in_place(&mut x).unwrap(), Factorisation::Llt);
        let dense = a.to_dense();
        let reduced = DMatrix::from_fn(free.len(), free.len(), |i, j| dense[(free[i], free[j])]);
        let rhs = DVector::from_iterator(free.len(), free.iter().map(|&i| b[i]));
        let reference = reduced.cholesky().unwrap().solve(&rhs);
        for i in (0..n).filter(|&i| fixed[i]) {
            assert_eq!(x[i], 0.0, "fixed entry {i}");
        }
        let xf = DVector::from_iterator(free.len(), free.iter().map(|&i| x[i]));
        let err = (xf - &reference).norm() / reference.norm();
        assert!(err <= 1e-10, "reduced solution error {err:e}");
    }
    assert_eq!(solver.symbolic_analysis_count(), 1);
}

#[test]
fn a_negative_pivot_is_named_whichever_domain_or_separator_holds_it_and_auto_falls_back() {
    // A negative diagonal entry makes every principal submatrix holding it indefinite, while those
    // without it stay positive definite: elimination fails exactly at that column, in a domain or in
    // the separator.
    let mut r = rng(43);
    let grid = block_grid(24, 10, 1e-1, &mut r);
    let entries = grid.entries();
    let mut solver = SparseSolver::try_new(
        grid.pattern.as_ref(),
        settings(LinearSolverKind::Cholesky, DomainSplit::Always),
    )
    .unwrap();
    // One unknown of every node: some lie in the separator, the others in either domain.
    for node in 0..grid.n() / 3 {
        let c = 3 * node + node % 3;
        let mut values = grid.values.clone();
        let index = entries.iter().position(|e| *e == (c, c)).unwrap();
        values[index] = -100.0;
        assert_eq!(
            solver.factorise(&values, None),
            Err(LinearSolveError::NotPositiveDefinite { col: c })
        );
        if node % 40 == 0 {
            let a = grid.with_values(values);
            let b = random_vector(a.n(), &mut r);
            let (x, used, _) = solve(&a, &b, settings(LinearSolverKind::Auto, DomainSplit::Always), None).unwrap();
            assert_eq!(used, Factorisation::Lblt, "column {c}");
            let res = relative_residual(&a, &x, &b);
            assert!(res <= 1e-10, "column {c}: relative residual {res:e}");
        }
    }
}

#[test]
fn auto_splits_large_patterns_with_the_amd_or_automatic_ordering_only() {
    let mut r = rng(44);
    let large = block_grid(100, 70, 1e-2, &mut r);
    assert!(large.n() >= DomainSplit::AUTO_MIN_UNKNOWNS);
    let small = block_grid(40, 20, 1e-2, &mut r);
    let domains = |a: &UpperMatrix, ordering: FillOrdering| {
        let s = LinearSolverSettings {
            ordering,
            ..Default::default()
        };
        SparseSolver::try_new(a.pattern.as_ref(), s)
            .unwrap()
            .symmetric_stats()
            .unwrap()
            .domains
    };
    assert_eq!(domains(&large, FillOrdering::Amd), 2);
    assert_eq!(domains(&large, FillOrdering::Auto), 2);
    assert_eq!(domains(&large, FillOrdering::Identity), 1);
    assert_eq!(domains(&small, FillOrdering::Amd), 1);
    // The large system is solved to working precision.
    let mut solver = SparseSolver::try_new(large.pattern.as_ref(), LinearSolverSettings::default()).unwrap();
    solver.factorise(&large.values, None).unwrap();
    let b = random_vector(large.n(), &mut r);
    let mut x = b.clone();
    solver.solve_in_place(&mut x).unwrap();
    let eta = solver.last_backward_error().unwrap();
    assert!(eta <= 1e-14, "backward error {eta:e}");
    // Switching the split off factorises the whole matrix, to the same solution.
    solver
        .set_settings(LinearSolverSettings {
            domains: DomainSplit::Off,
            ..Default::default()
        })
        .unwrap();
    assert_eq!(solver.symmetric_stats().unwrap().domains, 1);
    solver.factorise(&large.values, None).unwrap();
    let mut y = b.clone();
    solver.solve_in_place(&mut y).unwrap();
    assert!(solver.last_backward_error().unwrap() <= 1e-14);
    let diff = DVector::from_column_slice(&x) - DVector::from_column_slice(&y);
    assert!(diff.norm() <= 1e-10 * DVector::from_column_slice(&y).norm());
}

/// `a` plus, for every node pair, a random `Gᵀ G` on the pair's six unknowns: the couplings that
/// contact adds to a Hessian between nodes far apart on the mesh (still SPD).
fn with_couplings(a: &UpperMatrix, node_pairs: &[(usize, usize)], r: &mut rand_chacha::ChaCha8Rng) -> UpperMatrix {
    let mut b = PatternBuilder::new(a.n());
    for (&v, (i, j)) in a.values.iter().zip(a.entries()) {
        b.add(i, j, v);
    }
    let extra = block_grid(2, 1, 0.0, r);
    for &(p, q) in node_pairs {
        let dofs: Vec<usize> = (0..3).map(|d| 3 * p + d).chain((0..3).map(|d| 3 * q + d)).collect();
        for (&v, (i, j)) in extra.values.iter().zip(extra.entries()) {
            b.add(dofs[i], dofs[j], v);
        }
    }
    b.build()
}

/// Solves `a x = b` with `solver` (already analysed for `a`'s pattern) and checks the solution against
/// a fresh whole factorisation.
fn check_solution(solver: &mut SparseSolver, a: &UpperMatrix, b: &[f64], name: &str) {
    solver.factorise(&a.values, None).unwrap();
    let mut x = b.to_vec();
    solver.solve_in_place(&mut x).unwrap();
    let res = relative_residual(a, &x, b);
    assert!(res <= 1e-12, "{name}: relative residual {res:e}");
    let (whole, _, _) = solve(a, b, settings(LinearSolverKind::Cholesky, DomainSplit::Off), None).unwrap();
    let diff = DVector::from_column_slice(&x) - DVector::from_column_slice(&whole);
    let rel = diff.norm() / DVector::from_column_slice(&whole).norm();
    assert!(rel <= 1e-10, "{name}: differs from a fresh factorisation by {rel:e}");
}

#[test]
fn grown_patterns_reuse_the_orders_until_the_factor_grows_and_solve_like_a_fresh_analysis() {
    let mut r = rng(45);
    let (nx, ny) = (60, 20);
    let a = block_grid(nx, ny, 1e-2, &mut r);
    let n_nodes = nx * ny;
    // Couplings across the middle of the strip between nodes four columns apart; for the split, between
    // its two ends (they cross any bisection, so their nodes move into the separator); then many
    // between the two ends.
    let across: Vec<(usize, usize)> = [2, 9, 16].iter().map(|&j| (28 * ny + j, 32 * ny + j)).collect();
    let ends: Vec<(usize, usize)> = [2, 9, 16].iter().map(|&j| (j, n_nodes - 1 - j)).collect();
    let many: Vec<(usize, usize)> = (0..n_nodes / 3).map(|k| (k, n_nodes - 1 - 2 * k)).collect();
    let b = random_vector(a.n(), &mut r);
    for (domains, few) in [(DomainSplit::Off, &across), (DomainSplit::Always, &ends)] {
        let grown = with_couplings(&a, few, &mut r);
        let overgrown = with_couplings(&grown, &many, &mut r);
        let s = settings(LinearSolverKind::Auto, domains);
        let first = SparseSolver::try_new(a.pattern.as_ref(), s).unwrap();
        assert!(!first.reuses_orders());
        let split = first.symmetric_stats().unwrap().domains;
        assert_eq!(split, if domains == DomainSplit::Off { 1 } else { 2 });

        let mut second = first.try_grown(grown.pattern.as_ref(), s).unwrap();
        assert!(second.reuses_orders(), "{domains:?}: a few couplings keep the orders");
        assert_eq!(second.symmetric_stats().unwrap().domains, split);
        check_solution(&mut second, &grown, &b, &format!("{domains:?}, grown"));

        // Couplings across the whole strip multiply the factor's operations: ordered afresh.
        let mut third = second.try_grown(overgrown.pattern.as_ref(), s).unwrap();
        assert!(!third.reuses_orders(), "{domains:?}: the factor grew past the bound");
        check_solution(&mut third, &overgrown, &b, &format!("{domains:?}, overgrown"));
        // A new ordering would rather be kept by the next grown pattern (here: the same one).
        let fourth = third.try_grown(overgrown.pattern.as_ref(), s).unwrap();
        assert!(fourth.reuses_orders());
    }
}
