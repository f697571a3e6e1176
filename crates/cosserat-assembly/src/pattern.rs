//! The sparsity pattern of the Hessian, built once per topology.
//!
//! Unknowns come in blocks of three (a node's velocity or angular velocity). The Hessian is symmetric,
//! so only its upper triangle (including the diagonal) is stored, column by column (CSC), which is the
//! input of the symmetric factorisations. Within a scalar column `3B + c` the rows are ordered by block
//! row, and the diagonal block comes last with its `c + 1` upper entries, so the entry `(3A + r, 3B + c)`
//! lives at `col_ptr[3B + c] + 3 k + r`, where `k` is the position of block row `A` in block column `B`
//! ([`SparsityPattern::block_position`]). Scatter indices are precomputed from this once.

use faer::sparse::{SymbolicSparseColMat, SymbolicSparseColMatRef};

/// The upper-triangular block sparsity pattern of a symmetric matrix with 3×3 blocks.
#[derive(Debug, Clone)]
pub struct SparsityPattern {
    n_blocks: usize,
    /// Block-column pointers into `block_rows`.
    block_col_ptr: Vec<usize>,
    /// Sorted block rows `A ≤ B` of each block column `B`.
    block_rows: Vec<u32>,
    symbolic: SymbolicSparseColMat<usize>,
}

impl SparsityPattern {
    /// The pattern coupling every pair of blocks that appear together in one of `groups` (for example
    /// the nodes of an element), plus every diagonal block.
    pub fn from_groups<'a>(n_blocks: usize, groups: impl IntoIterator<Item = &'a [usize]>) -> Self {
        let mut cols: Vec<Vec<u32>> = (0..n_blocks).map(|b| vec![b as u32]).collect();
        for group in groups {
            for &a in group {
                for &b in group {
                    if a < b {
                        cols[b].push(a as u32);
                    }
                }
            }
        }
        let mut block_col_ptr = Vec::with_capacity(n_blocks + 1);
        let mut block_rows = Vec::new();
        block_col_ptr.push(0);
        for col in &mut cols {
            col.sort_unstable();
            col.dedup();
            block_rows.extend_from_slice(col);
            block_col_ptr.push(block_rows.len());
        }
        let n = 3 * n_blocks;
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for b in 0..n_blocks {
            let rows = &block_rows[block_col_ptr[b]..block_col_ptr[b + 1]];
            for c in 0..3 {
                for &a in rows {
                    let a = a as usize;
                    let last = if a == b { c + 1 } else { 3 };
                    row_idx.extend((0..last).map(|r| 3 * a + r));
                }
                col_ptr.push(row_idx.len());
            }
        }
        let symbolic = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        Self {
            n_blocks,
            block_col_ptr,
            block_rows,
            symbolic,
        }
    }

    /// The union of two patterns of the same size.
    ///
    /// # Panics
    /// If the sizes differ.
    #[track_caller]
    pub fn union(a: &SparsityPattern, b: &SparsityPattern) -> SparsityPattern {
        assert_eq!(a.n_blocks, b.n_blocks, "patterns of different sizes");
        let groups: Vec<[usize; 2]> = (0..a.n_blocks)
            .flat_map(|col| {
                let ra = a.block_rows[a.block_col_ptr[col]..a.block_col_ptr[col + 1]].iter();
                let rb = b.block_rows[b.block_col_ptr[col]..b.block_col_ptr[col + 1]].iter();
                ra.chain(rb).map(move |&row| [row as usize, col])
            })
            .collect();
        SparsityPattern::from_groups(a.n_blocks, groups.iter().map(|g| g.as_slice()))
    }

    /// Number of 3×3 blocks per row and column.
    pub fn n_blocks(&self) -> usize {
        self.n_blocks
    }

    /// Number of scalar unknowns, `3 n_blocks`.
    pub fn n_dofs(&self) -> usize {
        3 * self.n_blocks
    }

    /// Number of stored (upper-triangular) entries.
    pub fn nnz(&self) -> usize {
        self.symbolic.row_idx().len()
    }

    /// The scalar CSC pattern (upper triangle) for the linear solvers.
    pub fn symbolic(&self) -> SymbolicSparseColMatRef<'_, usize> {
        self.symbolic.as_ref()
    }

    /// Start of scalar column `j` in the values array.
    #[inline]
    pub fn col_start(&self, j: usize) -> usize {
        self.symbolic.col_ptr()[j]
    }

    /// Position `k` of block row `a` in block column `b` (`a ≤ b`), or `None` if the blocks are not
    /// coupled.
    pub fn block_position(&self, a: usize, b: usize) -> Option<usize> {
        let rows = &self.block_rows[self.block_col_ptr[b]..self.block_col_ptr[b + 1]];
        rows.binary_search(&(a as u32)).ok()
    }

    /// Index in the values array of the upper entry `(i, j)` (`i ≤ j`), if stored.
    pub fn entry(&self, i: usize, j: usize) -> Option<usize> {
        let (a, r, b, c) = (i / 3, i % 3, j / 3, j % 3);
        if i > j {
            return None;
        }
        self.block_position(a, b).map(|k| self.col_start(3 * b + c) + 3 * k + r)
    }
}
