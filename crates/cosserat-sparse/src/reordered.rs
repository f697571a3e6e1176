//! The matrix in the order of its symmetric factor, kept from one factorisation to the next.
//!
//! faer's supernodal factorisations read the lower triangle of `P A Pᵀ`, with `P` the fill-reducing
//! order. Given `A`'s upper triangle and an analysis that holds `P`, they build that matrix on every
//! call: count the entries of each permuted column, then move every row index and value, twice where a
//! Cholesky attempt is followed by `L B Lᵀ`. The permuted pattern is the same every time, so it is
//! built here once, with the position in `A`'s values of each of its entries; a factorisation then only
//! gathers the values, and the analysis is made on the permuted pattern in its own order (no
//! permutation left to faer). Solves move the right-hand side into the factor's order and back.
//!
//! It costs the permuted pattern's row indices, the gather map and a copy of the values: three words
//! per stored entry of `A`.

use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};

use super::memory::mapped_zeros;
use super::pattern::UpperPattern;

/// `A` in the factor's order: the lower triangle of `P A Pᵀ` by columns, rows sorted.
#[derive(Debug)]
pub(crate) struct ReorderedMatrix {
    /// `order[new] = old`.
    order: Vec<usize>,
    lower: SymbolicSparseColMat<usize>,
    /// The index in `A`'s values of each stored entry of `lower`.
    source: Vec<usize>,
    values: Vec<f64>,
    /// A right-hand side in the factor's order.
    rhs: Vec<f64>,
}

impl ReorderedMatrix {
    /// The pattern of `P A Pᵀ` for the factorisation order `order` (`order[new] = old`), and its upper
    /// triangle for the symbolic analysis (see [`lower_and_upper`]).
    pub(crate) fn new(pattern: &UpperPattern, order: Vec<usize>) -> (Self, SymbolicSparseColMat<usize>) {
        let n = pattern.n();
        let mut new_of = vec![0; n];
        for (new, &old) in order.iter().enumerate() {
            new_of[old] = new;
        }
        let (lower, source, upper) = lower_and_upper(n, lower_entries(pattern, &new_of));
        let matrix = Self {
            order,
            lower,
            values: mapped_zeros(source.len()),
            source,
            rhs: vec![0.0; n],
        };
        (matrix, upper)
    }

    /// The factorisation order (`order[new] = old`).
    pub(crate) fn order(&self) -> &[usize] {
        &self.order
    }

    /// `P A Pᵀ`'s lower triangle with the values of `A`'s upper triangle `values`.
    pub(crate) fn gather(&mut self, values: &[f64]) -> SparseColMatRef<'_, usize, f64> {
        for (v, &k) in self.values.iter_mut().zip(&self.source) {
            *v = values[k];
        }
        SparseColMatRef::new(self.lower.as_ref(), &self.values)
    }

    /// Runs `solve` on `rhs` moved into the factor's order, and moves the solution back.
    pub(crate) fn solve_in_order(&mut self, rhs: &mut [f64], solve: impl FnOnce(&mut [f64])) {
        for (r, &old) in self.rhs.iter_mut().zip(&self.order) {
            *r = rhs[old];
        }
        solve(&mut self.rhs);
        for (r, &old) in self.rhs.iter().zip(&self.order) {
            rhs[old] = *r;
        }
    }
}

/// The entries of `pattern` whose row and column both have a local index (`local[i]` is `usize::MAX`
/// where `i` has none), in the lower triangle of the local numbering: `(local row, local column,
/// position)` with `row ≥ column`.
pub(crate) fn lower_entries(pattern: &UpperPattern, local: &[usize]) -> Vec<(usize, usize, usize)> {
    let mut out = Vec::new();
    for (k, (&r, &c)) in pattern.row_idx().iter().zip(pattern.col_idx()).enumerate() {
        let (lr, lc) = (local[r], local[c]);
        if lr != usize::MAX && lc != usize::MAX {
            out.push((lr.max(lc), lr.min(lc), k));
        }
    }
    out
}

/// The lower triangle of the `n × n` pattern of `entries` (`(row, column, position)`, `row ≥ column`)
/// with the values position of each stored entry, and its transpose: faer 0.24's symbolic analysis
/// without a permutation reads its input as the upper triangle whatever side it is told.
pub(crate) fn lower_and_upper(
    n: usize,
    mut entries: Vec<(usize, usize, usize)>,
) -> (SymbolicSparseColMat<usize>, Vec<usize>, SymbolicSparseColMat<usize>) {
    let (lower, gather) = csc(n, &entries);
    for e in &mut entries {
        (e.0, e.1) = (e.1, e.0);
    }
    let (upper, _) = csc(n, &entries);
    (lower, gather, upper)
}

/// The start of each of `n` buckets in a list ordered by bucket (`n + 1` offsets), for items in
/// `buckets`.
fn offsets(n: usize, buckets: impl Iterator<Item = usize>) -> Vec<usize> {
    let mut ptr = vec![0usize; n + 1];
    for b in buckets {
        ptr[b + 1] += 1;
    }
    for b in 0..n {
        ptr[b + 1] += ptr[b];
    }
    ptr
}

/// The item indices ordered by their bucket in `0..n`, in item order within a bucket.
fn bucketed(n: usize, buckets: impl Iterator<Item = usize> + Clone) -> Vec<usize> {
    let mut next = offsets(n, buckets.clone());
    let mut order = vec![0usize; next[n]];
    for (i, b) in buckets.enumerate() {
        order[next[b]] = i;
        next[b] += 1;
    }
    order
}

/// The compressed pattern of `n × n` with the given `(row, column, position)` entries (rows sorted in
/// each column) and the values position of each stored entry. The entries are bucketed by row first
/// and then dealt to their columns in row order, so each column's rows arrive sorted (two counting
/// passes instead of a sort per column).
fn csc(n: usize, entries: &[(usize, usize, usize)]) -> (SymbolicSparseColMat<usize>, Vec<usize>) {
    let by_row = bucketed(n, entries.iter().map(|&(r, _, _)| r));
    let col_ptr = offsets(n, entries.iter().map(|&(_, c, _)| c));
    let mut next = col_ptr.clone();
    let mut slots = vec![(0usize, 0usize); entries.len()];
    for &i in &by_row {
        let (r, c, k) = entries[i];
        slots[next[c]] = (r, k);
        next[c] += 1;
    }
    let (row_idx, gather): (Vec<usize>, Vec<usize>) = slots.into_iter().unzip();
    let pattern = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
    (pattern, gather)
}
