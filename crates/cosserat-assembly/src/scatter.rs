//! Adding element contributions into the global gradient and Hessian through precomputed indices.
//!
//! This is the one place where element-level nalgebra matrices meet the global CSC values of
//! [`SparsityPattern`]. For each element the position of every coupled block pair is looked up once,
//! so adding an element Hessian is a loop over its upper blocks with direct index arithmetic.

use crate::pattern::SparsityPattern;
use nalgebra::{SMatrix, SVector};

/// Precomputed scatter positions of a set of elements that each couple `N` blocks.
#[derive(Debug, Clone)]
pub struct ElementScatter<const N: usize> {
    blocks: Vec<[usize; N]>,
    /// For each element, for each local pair `(i, j)` (row-major), the position of the block pair in
    /// the pattern, stored for the orientation with the smaller global block as the row.
    positions: Vec<[[u32; N]; N]>,
}

impl<const N: usize> ElementScatter<N> {
    /// Scatter data for elements given by their global block indices.
    ///
    /// # Panics
    /// If an element couples two blocks that the pattern does not couple (the pattern must have been
    /// built from the same groups).
    #[track_caller]
    pub fn new(pattern: &SparsityPattern, blocks: Vec<[usize; N]>) -> Self {
        let positions = blocks
            .iter()
            .map(|el| {
                let mut p = [[0u32; N]; N];
                for i in 0..N {
                    for j in 0..N {
                        let (a, b) = if el[i] <= el[j] { (el[i], el[j]) } else { (el[j], el[i]) };
                        p[i][j] = pattern
                            .block_position(a, b)
                            .expect("element block pair missing from the pattern")
                            as u32;
                    }
                }
                p
            })
            .collect();
        Self { blocks, positions }
    }

    /// Number of elements.
    pub fn len(&self) -> usize {
        self.blocks.len()
    }

    /// Whether there are no elements.
    pub fn is_empty(&self) -> bool {
        self.blocks.is_empty()
    }

    /// The global blocks of element `e`.
    pub fn blocks(&self, e: usize) -> &[usize; N] {
        &self.blocks[e]
    }

    /// Adds an element gradient (`3N` entries, block by block) into the global gradient.
    #[inline]
    pub fn add_gradient<const NE: usize>(&self, e: usize, g: &SVector<f64, NE>, global: &mut [f64]) {
        debug_assert_eq!(NE, 3 * N);
        for (i, &b) in self.blocks[e].iter().enumerate() {
            for c in 0..3 {
                global[3 * b + c] += g[3 * i + c];
            }
        }
    }

    /// Adds a symmetric element Hessian (`3N × 3N`) into the global upper-triangular values.
    ///
    /// Only the element's upper block triangle is read (blocks `(i, j)` with `i ≤ j`, of the diagonal
    /// blocks their upper triangles): where the global order of two blocks is the reverse of the local
    /// one, the transpose of the local upper block is added. Producers may therefore leave the lower
    /// triangle unfilled.
    #[inline]
    pub fn add_hessian<const NE: usize>(
        &self,
        e: usize,
        h: &SMatrix<f64, NE, NE>,
        pattern: &SparsityPattern,
        values: &mut [f64],
    ) {
        debug_assert_eq!(NE, 3 * N);
        let el = &self.blocks[e];
        let pos = &self.positions[e];
        for i in 0..N {
            for j in i..N {
                let (a, b) = (el[i], el[j]);
                debug_assert!(a != b || i == j, "an element couples a block with itself");
                let k = pos[i][j] as usize;
                // One bounds check per column segment of three values, so that the additions are
                // straight-line code.
                if a < b {
                    for c in 0..3 {
                        let start = pattern.col_start(3 * b + c) + 3 * k;
                        let src = h.fixed_view::<3, 1>(3 * i, 3 * j + c);
                        for (v, x) in values[start..start + 3].iter_mut().zip(src.iter()) {
                            *v += x;
                        }
                    }
                } else if a == b {
                    for c in 0..3 {
                        let start = pattern.col_start(3 * b + c) + 3 * k;
                        for (r, v) in values[start..=start + c].iter_mut().enumerate() {
                            *v += h[(3 * i + r, 3 * j + c)];
                        }
                    }
                } else {
                    for c in 0..3 {
                        let start = pattern.col_start(3 * a + c) + 3 * k;
                        for (r, v) in values[start..start + 3].iter_mut().enumerate() {
                            *v += h[(3 * i + c, 3 * j + r)];
                        }
                    }
                }
            }
        }
    }
}
