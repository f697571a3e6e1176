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
