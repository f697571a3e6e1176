//! Sparse LU with partial pivoting on the full matrix, the last-resort factorisation.
//!
//! LU needs both triangles, so the upper-triangle pattern is mirrored once into a full pattern with
//! sorted rows, together with the map from each upper entry to its one or two full slots. Each numeric
//! factorisation scatters the values through that map; faer's column ordering (COLAMD) and symbolic
//! analysis are computed once.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::sparse::linalg::LuError;
use faer::sparse::linalg::lu::{LuRef, NumericLu, SymbolicLu, factorize_symbolic_lu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par};

use super::pattern::UpperPattern;
use crate::error::{Factorisation, LinearSolveError, LinearSolveStage};

/// Marks an upper entry on the diagonal, which has no mirrored slot.
const NO_SLOT: usize = usize::MAX;

/// The mirrored pattern, its LU symbolic analysis and the numeric LU storage.
pub(crate) struct LuFactor {
    full: SymbolicSparseColMat<usize>,
    full_values: Vec<f64>,
    /// Full slot of upper entry `p` as `(row, col)`.
    slot: Vec<usize>,
    /// Full slot of upper entry `p` as `(col, row)`, or [`NO_SLOT`] on the diagonal.
    mirror_slot: Vec<usize>,
    symbolic: SymbolicLu<usize>,
    numeric: NumericLu<usize, f64>,
    mem: MemBuffer,
    par: Par,
}

impl std::fmt::Debug for LuFactor {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LuFactor")
            .field("nnz_full", &self.full_values.len())
            .field("symbolic", &self.symbolic)
            .field("par", &self.par)
            .finish_non_exhaustive()
    }
}

impl LuFactor {
    /// Mirrors the pattern and runs the LU symbolic analysis.
    pub(crate) fn try_new(pattern: &UpperPattern, par: Par) -> Result<Self, LinearSolveError> {
        let n = pattern.n();
        let rows = pattern.row_idx();
        let cols = pattern.col_idx();
        let mut col_ptr = vec![0usize; n + 1];
        for (&r, &c) in rows.iter().zip(cols) {
            col_ptr[c + 1] += 1;
            if r != c {
                col_ptr[r + 1] += 1;
            }
        }
        for j in 0..n {
            col_ptr[j + 1] += col_ptr[j];
        }
        let nnz_full = col_ptr[n];
        // Entries of each full column as (row, upper index, mirrored?), sorted by row.
        let mut entries: Vec<(usize, usize, bool)> = vec![(0, 0, false); nnz_full];
        let mut next = col_ptr[..n].to_vec();
        for (p, (&r, &c)) in rows.iter().zip(cols).enumerate() {
            entries[next[c]] = (r, p, false);
            next[c] += 1;
            if r != c {
                entries[next[r]] = (c, p, true);
                next[r] += 1;
            }
        }
        let mut slot = vec![NO_SLOT; rows.len()];
        let mut mirror_slot = vec![NO_SLOT; rows.len()];
        let mut row_idx = vec![0usize; nnz_full];
        for j in 0..n {
            let column = &mut entries[col_ptr[j]..col_ptr[j + 1]];
            column.sort_unstable_by_key(|e| e.0);
            for (k, &(r, p, mirrored)) in column.iter().enumerate() {
                let q = col_ptr[j] + k;
                row_idx[q] = r;
                if mirrored {
                    mirror_slot[p] = q;
                } else {
                    slot[p] = q;
                }
            }
        }
        let full = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        let symbolic =
            factorize_symbolic_lu(full.as_ref(), Default::default()).map_err(|source| LinearSolveError::Faer {
                stage: LinearSolveStage::LuSymbolic,
                source,
            })?;
        let req = StackReq::any_of(&[
            symbolic.factorize_numeric_lu_scratch::<f64>(par, Default::default()),
            symbolic.solve_in_place_scratch::<f64>(1, par),
        ]);
        let mem = super::memory::mapped_workspace(req).ok_or(LinearSolveError::Faer {
            stage: LinearSolveStage::Workspace,
            source: faer::sparse::FaerError::OutOfMemory,
        })?;
        Ok(Self {
            full,
            full_values: super::memory::mapped_zeros(nnz_full),
            slot,
            mirror_slot,
            symbolic,
            numeric: NumericLu::new(),
            mem,
            par,
        })
    }

    /// Numerical LU factorisation of the symmetric matrix whose upper triangle is `values`.
    pub(crate) fn factorise(&mut self, values: &[f64]) -> Result<(), LinearSolveError> {
        for ((&v, &q), &m) in values.iter().zip(&self.slot).zip(&self.mirror_slot) {
            self.full_values[q] = v;
            if m != NO_SLOT {
                self.full_values[m] = v;
            }
        }
        let a = SparseColMatRef::new(self.full.as_ref(), &self.full_values);
        let result = self.symbolic.factorize_numeric_lu(
            &mut self.numeric,
            a,
            self.par,
            MemStack::new(&mut self.mem),
            Default::default(),
        );
        match result {
            Ok(_) => Ok(()),
            Err(LuError::SymbolicSingular { index }) => {
                let col = self.symbolic.col_perm().arrays().0.get(index).copied();
                Err(LinearSolveError::Singular {
                    factorisation: Factorisation::Lu,
                    col,
                })
            }
            Err(LuError::Generic(source)) => Err(LinearSolveError::Faer {
                stage: LinearSolveStage::Numeric,
                source,
            }),
        }
    }

    /// Solves `A x = rhs` in place with the last LU factorisation.
    pub(crate) fn solve_in_place(&mut self, rhs: &mut [f64]) {
        let n = rhs.len();
        LuRef::new_unchecked(&self.symbolic, &self.numeric).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, n, 1),
            self.par,
            MemStack::new(&mut self.mem),
        );
    }
}
