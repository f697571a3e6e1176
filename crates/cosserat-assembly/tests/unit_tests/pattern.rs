//! The block pattern and its index arithmetic.

use cosserat_assembly::SparsityPattern;

#[test]
fn entries_are_unique_and_cover_exactly_the_coupled_upper_blocks() {
    let groups: [&[usize]; 3] = [&[0, 3, 4], &[1, 4], &[2]];
    let p = SparsityPattern::from_groups(5, groups);
    let coupled = |a: usize, b: usize| a == b || groups.iter().any(|g| g.contains(&a) && g.contains(&b));
    let mut seen = vec![false; p.nnz()];
    for j in 0..p.n_dofs() {
        for i in 0..p.n_dofs() {
            match p.entry(i, j) {
                Some(k) => {
                    assert!(i <= j && coupled(i / 3, j / 3), "({i}, {j}) stored but not coupled");
                    assert!(!seen[k], "slot {k} used twice");
                    seen[k] = true;
                    // The slot holds this row in the CSC structure.
                    assert_eq!(p.symbolic().row_idx()[k], i);
                }
                None => assert!(i > j || !coupled(i / 3, j / 3), "({i}, {j}) missing"),
            }
        }
    }
    assert!(seen.iter().all(|&s| s));
}

/// Element Hessians enter the global upper triangle with their local block order reversed where the
/// global order is, and only their upper block triangle is read.
#[test]
fn element_hessians_scatter_from_their_upper_block_triangle() {
    use cosserat_assembly::scatter::ElementScatter;
    use nalgebra::SMatrix;
    // Local order 3, 0, 2: the pairs (0, 1) and (0, 2) are stored transposed in the global matrix.
    let elements = vec![[3, 0, 2], [0, 1, 2]];
    let p = SparsityPattern::from_groups(4, elements.iter().map(|e| &e[..]));
    let scatter = ElementScatter::new(&p, elements.clone());
    let hessian = |seed: f64| {
        let a = SMatrix::<f64, 9, 9>::from_fn(|r, c| (seed + 0.37 * r as f64 + 1.3 * c as f64).sin());
        a + a.transpose()
    };
    let mut dense = SMatrix::<f64, 12, 12>::zeros();
    let mut values = vec![0.0; p.nnz()];
    for (e, blocks) in elements.iter().enumerate() {
        let h = hessian(e as f64);
        for (i, &a) in blocks.iter().enumerate() {
            for (j, &b) in blocks.iter().enumerate() {
                let mut view = dense.fixed_view_mut::<3, 3>(3 * a, 3 * b);
                view += h.fixed_view::<3, 3>(3 * i, 3 * j);
            }
        }
        // What lies below the block diagonal must not matter.
        let mut upper_only = h;
        for c in 0..9 {
            for r in 3 * (c / 3 + 1)..9 {
                upper_only[(r, c)] = f64::NAN;
            }
        }
        scatter.add_hessian(e, &upper_only, &p, &mut values);
    }
    for j in 0..12 {
        for i in 0..=j {
            let expected = dense[(i, j)];
            match p.entry(i, j) {
                Some(k) => assert!(
                    (values[k] - expected).abs() <= 1e-14 * (1.0 + expected.abs()),
                    "({i}, {j}): {} against {expected}",
                    values[k]
                ),
                None => assert_eq!(expected, 0.0),
            }
        }
    }
}
