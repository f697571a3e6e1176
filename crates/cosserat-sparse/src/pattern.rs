//! The validated upper-triangular pattern of a symmetric system and the per-iteration value
//! operations on it: elimination of fixed unknowns, the symmetric product `A x` and the norm `‖A‖∞`.
//!
//! The pattern is checked and copied once; every operation here is a single pass over the stored
//! values, so nothing is allocated per Newton iteration.

use faer::sparse::{SymbolicSparseColMat, SymbolicSparseColMatRef};
use rayon::prelude::*;

use crate::error::{LinearSolveError, LinearSolveStage};

/// An owned, validated upper triangle (diagonal included) of a symmetric `n × n` pattern.
#[derive(Debug, Clone)]
pub(crate) struct UpperPattern {
    symbolic: SymbolicSparseColMat<usize>,
    /// Column of every stored entry, in pattern order.
    col_of_entry: Vec<usize>,
}

impl UpperPattern {
    /// Checks that `pattern` is square, compact, upper triangular, free of duplicates and stores every
    /// diagonal entry, and copies it.
    pub(crate) fn try_new(pattern: SymbolicSparseColMatRef<'_, usize>) -> Result<Self, LinearSolveError> {
        let (nrows, ncols) = (pattern.nrows(), pattern.ncols());
        if nrows != ncols {
            return Err(LinearSolveError::NotSquare { nrows, ncols });
        }
        if pattern.col_nnz().is_some() {
            return Err(LinearSolveError::NonCompactPattern);
        }
        let n = ncols;
        let col_ptr = pattern.col_ptr();
        let row_idx = pattern.row_idx();
        let nnz = col_ptr[n];
        // `seen[row] == col + 1` marks a row already met in column `col`.
        let mut seen = vec![0usize; n];
        let mut col_of_entry = Vec::with_capacity(nnz);
        for col in 0..n {
            let mut has_diagonal = false;
            for &row in &row_idx[col_ptr[col]..col_ptr[col + 1]] {
                if row > col {
                    return Err(LinearSolveError::LowerTriangleEntry { row, col });
                }
                if seen[row] == col + 1 {
                    return Err(LinearSolveError::DuplicateEntry { row, col });
                }
                seen[row] = col + 1;
                has_diagonal |= row == col;
                col_of_entry.push(col);
            }
            if !has_diagonal {
                return Err(LinearSolveError::MissingDiagonal { col });
            }
        }
        let symbolic = pattern.to_owned().map_err(|source| LinearSolveError::Faer {
            stage: LinearSolveStage::Pattern,
            source,
        })?;
        Ok(Self { symbolic, col_of_entry })
    }

    /// The dimension `n`.
    pub(crate) fn n(&self) -> usize {
        self.symbolic.ncols()
    }

    /// The number of stored entries.
    pub(crate) fn nnz(&self) -> usize {
        self.col_of_entry.len()
    }

    /// The faer view of the pattern.
    pub(crate) fn as_ref(&self) -> SymbolicSparseColMatRef<'_, usize> {
        self.symbolic.as_ref()
    }

    /// Row indices of the stored entries, in pattern order.
    pub(crate) fn row_idx(&self) -> &[usize] {
        self.symbolic.row_idx()
    }

    /// Column indices of the stored entries, in pattern order.
    pub(crate) fn col_idx(&self) -> &[usize] {
        &self.col_of_entry
    }

    /// Whether `other` is the same pattern (same dimension, same entries in the same order).
    pub(crate) fn same_as(&self, other: SymbolicSparseColMatRef<'_, usize>) -> bool {
        other.nrows() == self.n()
            && other.ncols() == self.n()
            && other.col_nnz().is_none()
            && other.col_ptr() == self.symbolic.col_ptr()
            && other.row_idx() == self.symbolic.row_idx()
    }

    /// The column ranges of the tasks of [`ColumnTasks`]: about equal numbers of entries, and a
    /// count that depends on the number of entries only, so that the sums (and so CG's iterates) are
    /// the same on any number of threads.
    fn column_task_bounds(&self) -> Vec<usize> {
        if self.n() == 0 {
            return vec![0, 0];
        }
        let col_ptr = self.symbolic.col_ptr();
        let nnz = self.nnz();
        let tasks = (nnz / TASK_ENTRIES).clamp(1, MAX_TASKS);
        let mut bounds = vec![0];
        for t in 1..tasks {
            bounds.push(col_ptr.partition_point(|&p| p < t * nnz / tasks));
        }
        bounds.push(self.n());
        bounds.dedup();
        bounds
    }
}

/// Entries per task of [`ColumnTasks`]: smaller patterns run as one task, on the calling thread.
const TASK_ENTRIES: usize = 1 << 18;
/// The most tasks a pass is split into (fixed, whatever the number of threads).
const MAX_TASKS: usize = 4;

/// The per-iteration passes over the stored values (the symmetric product `A x`, and the values of a
/// factorisation with their norm), split into tasks of consecutive columns that run on the rayon pool.
///
/// Both passes go column by column and scatter each entry above the diagonal into its row. A task's
/// columns only scatter into rows before its last column, so every task but the last writes into a
/// partial vector of that length, and the partials are added to the last task's result in task
/// order. The product is where CG spends its time and it checks every direct solve; the values'
/// preparation precedes every factorisation: both are memory-bound sweeps over every entry of the
/// Hessian (17 million at the paper's largest plate).
#[derive(Debug, Clone)]
pub(crate) struct ColumnTasks {
    /// Column boundaries of the tasks (`tasks + 1` entries).
    bounds: Vec<usize>,
    /// One partial result per task but the last, as long as the task's last column.
    partials: Vec<Vec<f64>>,
}

impl ColumnTasks {
    /// The tasks and partial vectors for `pattern`.
    pub(crate) fn new(pattern: &UpperPattern) -> Self {
        let bounds = pattern.column_task_bounds();
        let partials = bounds[1..bounds.len() - 1].iter().map(|&end| vec![0.0; end]).collect();
        Self { bounds, partials }
    }

    /// `y = A x`.
    pub(crate) fn product_into(&mut self, pattern: &UpperPattern, values: &[f64], x: &[f64], y: &mut [f64]) {
        let symbolic = pattern.as_ref();
        let (col_ptr, row_idx) = (symbolic.col_ptr(), symbolic.row_idx());
        let columns = |start: usize, end: usize, t: &mut [f64]| {
            t.fill(0.0);
            for col in start..end {
                let x_col = x[col];
                let mut acc = 0.0;
                for (&row, &v) in row_idx[col_ptr[col]..col_ptr[col + 1]]
                    .iter()
                    .zip(&values[col_ptr[col]..col_ptr[col + 1]])
                {
                    if row == col {
                        acc += v * x_col;
                    } else {
                        t[row] += v * x_col;
                        acc += v * x[row];
                    }
                }
                // Entries of row `col` lie in later columns, so `t[col]` is still zero here.
                t[col] = acc;
            }
        };
        let bounds = &self.bounds;
        let last = bounds.len() - 2;
        if last == 0 {
            columns(0, bounds[1], y);
            return;
        }
        rayon::join(
            || {
                self.partials
                    .par_iter_mut()
                    .enumerate()
                    .for_each(|(c, t)| columns(bounds[c], bounds[c + 1], t));
            },
            || columns(bounds[last], bounds[last + 1], y),
        );
        self.add_partials(y);
    }

    /// Prepares the values of a factorisation in one pass over the entries: checks them for NaN and
    /// infinity, copies them into `out` with the rows and columns of fixed unknowns replaced by those of
    /// the identity, and returns `‖out‖∞` (the largest absolute row sum of the symmetric matrix), using
    /// `row_sums` (length `n`) for the row sums.
    ///
    /// One pass instead of three, split into the tasks. The system solved with `out` and a right-hand
    /// side whose fixed entries are zero has the solution of the reduced (free × free) system on the
    /// free unknowns and zero on the fixed ones.
    ///
    /// # Errors
    /// [`LinearSolveError::NonFiniteValue`] for the first non-finite entry in storage order.
    pub(crate) fn prepare_values(
        &mut self,
        pattern: &UpperPattern,
        values: &[f64],
        fixed: Option<&[bool]>,
        out: &mut [f64],
        row_sums: &mut [f64],
    ) -> Result<f64, LinearSolveError> {
        let col_ptr = pattern.as_ref().col_ptr();
        let rows = pattern.row_idx();
        // Columns `start..end` into `out` (their entries only) and `sums`; the first non-finite entry's
        // index, or `usize::MAX`.
        let task = |start: usize, end: usize, out: &mut [f64], sums: &mut [f64]| -> usize {
            sums.fill(0.0);
            let base = col_ptr[start];
            for col in start..end {
                let col_fixed = fixed.is_some_and(|f| f[col]);
                let mut col_sum = 0.0;
                for k in col_ptr[col]..col_ptr[col + 1] {
                    let (row, v) = (rows[k], values[k]);
                    if !v.is_finite() {
                        return k;
                    }
                    let v = if col_fixed || fixed.is_some_and(|f| f[row]) {
                        if row == col { 1.0 } else { 0.0 }
                    } else {
                        v
                    };
                    out[k - base] = v;
                    col_sum += v.abs();
                    if row != col {
                        sums[row] += v.abs();
                    }
                }
                // Entries of row `col` lie in later columns, so `sums[col]` is still zero here.
                sums[col] = col_sum;
            }
            usize::MAX
        };
        let bounds = &self.bounds;
        let last = bounds.len() - 2;
        let mut outs: [&mut [f64]; MAX_TASKS] = Default::default();
        let mut rest = out;
        for (c, slot) in outs.iter_mut().enumerate().take(last + 1) {
            let (head, tail) = rest.split_at_mut(col_ptr[bounds[c + 1]] - col_ptr[bounds[c]]);
            *slot = head;
            rest = tail;
        }
        let (head, tail) = outs.split_at_mut(last);
        let first_bad = if last == 0 {
            task(bounds[0], bounds[1], &mut *tail[0], row_sums)
        } else {
            let (a, b) = rayon::join(
                || {
                    self.partials
                        .par_iter_mut()
                        .zip(head.par_iter_mut())
                        .enumerate()
                        .map(|(c, (sums, out))| task(bounds[c], bounds[c + 1], out, sums))
                        .min()
                        .unwrap_or(usize::MAX)
                },
                || task(bounds[last], bounds[last + 1], &mut *tail[0], row_sums),
            );
            a.min(b)
        };
        if first_bad != usize::MAX {
            return Err(LinearSolveError::NonFiniteValue {
                index: first_bad,
                row: rows[first_bad],
                col: pattern.col_idx()[first_bad],
                value: values[first_bad],
            });
        }
        self.add_partials(row_sums);
        Ok(row_sums.iter().copied().fold(0.0, f64::max))
    }

    /// Adds the partial results of the tasks but the last to `y`, in task order.
    fn add_partials(&self, y: &mut [f64]) {
        for partial in &self.partials {
            for (yi, &pi) in y.iter_mut().zip(partial) {
                *yi += pi;
            }
        }
    }
}

/// The normwise backward error `‖b − A x‖∞ / (‖A‖∞ ‖x‖∞ + ‖b‖∞)` given the product `ax = A x`; zero
/// when `b = 0` and `x = 0`, infinite when anything is non-finite.
pub(crate) fn backward_error(norm_a: f64, b: &[f64], x: &[f64], ax: &[f64]) -> f64 {
    let max_abs = |v: &[f64]| {
        v.iter().fold(
            0.0_f64,
            |m, e| if e.is_finite() { m.max(e.abs()) } else { f64::INFINITY },
        )
    };
    let residual = b.iter().zip(ax).fold(0.0_f64, |m, (bi, ai)| {
        let r = (bi - ai).abs();
        if r.is_finite() { m.max(r) } else { f64::INFINITY }
    });
    let scale = norm_a * max_abs(x) + max_abs(b);
    if residual == 0.0 {
        return 0.0;
    }
    if !residual.is_finite() || !scale.is_finite() {
        return f64::INFINITY;
    }
    residual / scale
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pattern(n: usize, col_ptr: Vec<usize>, row_idx: Vec<usize>) -> SymbolicSparseColMat<usize> {
        SymbolicSparseColMat::new_unsorted_checked(n, n, col_ptr, None, row_idx)
    }

    #[test]
    fn elimination_puts_identity_on_fixed_rows_and_columns() {
        // Full upper triangle of a 3×3 matrix.
        let p = pattern(3, vec![0, 1, 3, 6], vec![0, 0, 1, 0, 1, 2]);
        let up = UpperPattern::try_new(p.as_ref()).unwrap();
        let values = [4.0, 1.0, 5.0, 2.0, 3.0, 6.0];
        let (mut out, mut scratch) = ([0.0; 6], [0.0; 3]);
        let norm =
            ColumnTasks::new(&up).prepare_values(&up, &values, Some(&[false, true, false]), &mut out, &mut scratch);
        assert_eq!(out, [4.0, 0.0, 1.0, 2.0, 0.0, 6.0]);
        // The eliminated matrix [[4, 0, 2], [0, 1, 0], [2, 0, 6]].
        assert_eq!(norm, Ok(8.0));
        let mut bad = values;
        bad[3] = f64::NAN;
        assert!(matches!(
            ColumnTasks::new(&up).prepare_values(&up, &bad, None, &mut out, &mut scratch),
            Err(LinearSolveError::NonFiniteValue {
                index: 3,
                row: 0,
                col: 2,
                ..
            })
        ));
    }

    #[test]
    fn symmetric_product_and_norm_match_the_full_matrix() {
        // A = [[4, 1, 2], [1, 5, 3], [2, 3, 6]].
        let p = pattern(3, vec![0, 1, 3, 6], vec![0, 0, 1, 0, 1, 2]);
        let up = UpperPattern::try_new(p.as_ref()).unwrap();
        let values = [4.0, 1.0, 5.0, 2.0, -3.0, 6.0];
        let mut y = [f64::NAN; 3];
        ColumnTasks::new(&up).product_into(&up, &values, &[1.0, 2.0, 3.0], &mut y);
        assert_eq!(y, [4.0 + 2.0 + 6.0, 1.0 + 10.0 - 9.0, 2.0 - 6.0 + 18.0]);
        let (mut out, mut scratch) = ([0.0; 6], [0.0; 3]);
        assert_eq!(
            ColumnTasks::new(&up).prepare_values(&up, &values, None, &mut out, &mut scratch),
            Ok(11.0)
        );
        assert_eq!(out, values);
    }

    #[test]
    fn the_product_split_into_tasks_matches_the_entrywise_product() {
        // A band of 31 diagonals (about 930 000 stored entries: three tasks). Small integers keep
        // every sum exact, so the task split must give exactly the entry-by-entry product.
        let (n, band) = (30_000usize, 30);
        let (mut col_ptr, mut row_idx) = (vec![0], Vec::new());
        for j in 0..n {
            row_idx.extend(j.saturating_sub(band)..=j);
            col_ptr.push(row_idx.len());
        }
        let up = UpperPattern::try_new(pattern(n, col_ptr, row_idx).as_ref()).unwrap();
        let values: Vec<f64> = (0..up.nnz())
            .map(|k| ((up.row_idx()[k] * 7 + up.col_idx()[k] * 13) % 17) as f64 - 8.0)
            .collect();
        let x: Vec<f64> = (0..n).map(|i| (i % 11) as f64 - 5.0).collect();
        let mut expected = vec![0.0; n];
        for ((&v, &row), &col) in values.iter().zip(up.row_idx()).zip(up.col_idx()) {
            expected[row] += v * x[col];
            if row != col {
                expected[col] += v * x[row];
            }
        }
        let mut tasks = ColumnTasks::new(&up);
        assert_eq!(tasks.bounds.len(), 4);
        let mut y = vec![f64::NAN; n];
        tasks.product_into(&up, &values, &x, &mut y);
        assert_eq!(y, expected);
        // Reused, it overwrites the previous result and its partials.
        let x2: Vec<f64> = x.iter().map(|v| -v).collect();
        tasks.product_into(&up, &values, &x2, &mut y);
        assert!(y.iter().zip(&expected).all(|(a, b)| *a == -b));

        // The values of a factorisation: unknowns fixed in every task, and the norm of the result.
        let fixed: Vec<bool> = (0..n).map(|i| i % 7_919 == 3).collect();
        let mut expected_out = values.clone();
        let mut row_sum = vec![0.0; n];
        for (k, (&row, &col)) in up.row_idx().iter().zip(up.col_idx()).enumerate() {
            if fixed[row] || fixed[col] {
                expected_out[k] = if row == col { 1.0 } else { 0.0 };
            }
            row_sum[row] += expected_out[k].abs();
            if row != col {
                row_sum[col] += expected_out[k].abs();
            }
        }
        let expected_norm = row_sum.iter().copied().fold(0.0, f64::max);
        let (mut out, mut sums) = (vec![f64::NAN; up.nnz()], vec![f64::NAN; n]);
        let norm = tasks.prepare_values(&up, &values, Some(&fixed), &mut out, &mut sums);
        assert_eq!(norm, Ok(expected_norm));
        assert_eq!(out, expected_out);
        // Non-finite values in two tasks: the first in storage order is named.
        let mut bad = values.clone();
        let (k1, k2) = (up.nnz() - 10, up.nnz() / 2);
        bad[k1] = f64::INFINITY;
        bad[k2] = f64::NAN;
        match tasks.prepare_values(&up, &bad, None, &mut out, &mut sums) {
            Err(LinearSolveError::NonFiniteValue { index, row, col, .. }) => {
                assert_eq!((index, row, col), (k2, up.row_idx()[k2], up.col_idx()[k2]));
            }
            other => panic!("expected a non-finite value error, got {other:?}"),
        }
    }

    #[test]
    fn backward_error_handles_zero_and_non_finite() {
        assert_eq!(backward_error(1.0, &[0.0], &[0.0], &[0.0]), 0.0);
        assert_eq!(backward_error(1.0, &[1.0], &[f64::NAN], &[f64::NAN]), f64::INFINITY);
        // b = 2, x = 1, A x = 1.5: residual 0.5 over ‖A‖‖x‖ + ‖b‖ = 1.5 + 2.
        assert_eq!(backward_error(1.5, &[2.0], &[1.0], &[1.5]), 0.5 / 3.5);
    }

    #[test]
    fn malformed_patterns_are_rejected_with_their_entry() {
        let lower = pattern(2, vec![0, 2, 3], vec![0, 1, 1]);
        assert_eq!(
            UpperPattern::try_new(lower.as_ref()).unwrap_err(),
            LinearSolveError::LowerTriangleEntry { row: 1, col: 0 }
        );
        let no_diag = pattern(2, vec![0, 1, 2], vec![0, 0]);
        assert_eq!(
            UpperPattern::try_new(no_diag.as_ref()).unwrap_err(),
            LinearSolveError::MissingDiagonal { col: 1 }
        );
        let rect = SymbolicSparseColMat::new_unsorted_checked(3, 2, vec![0, 1, 2], None, vec![0, 1]);
        assert_eq!(
            UpperPattern::try_new(rect.as_ref()).unwrap_err(),
            LinearSolveError::NotSquare { nrows: 3, ncols: 2 }
        );
    }
}
