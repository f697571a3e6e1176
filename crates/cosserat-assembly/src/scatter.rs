//! Adding element contributions into the global gradient and Hessian through precomputed indices.
//!
//! This is the one place where element-level nalgebra matrices meet the global CSC values of
//! [`SparsityPattern`]. For each element the position of every coupled block pair is looked up once,
//! so adding an element Hessian is a loop over its upper blocks with direct index arithmetic.
//! [`ElementScatter`] serves elements whose slots are distinct blocks (the shell, volume and pressure
//! terms); [`GroupScatter`] serves stencils with absent or repeated slots (the Kirchhoff–Love
//! stencils); [`add_diagonal_block`] a single node's block.

use crate::pattern::SparsityPattern;
use nalgebra::{Matrix3, SMatrix, SVector};

/// Marks an absent slot of a [`GroupScatter`].
const ABSENT: u32 = u32::MAX;

/// The pattern position of every slot pair of a group, for the orientation with the smaller global
/// block as the row (`ABSENT` where a slot is absent).
#[track_caller]
fn block_positions<const N: usize>(pattern: &SparsityPattern, group: [Option<usize>; N]) -> [[u32; N]; N] {
    let mut p = [[ABSENT; N]; N];
    for i in 0..N {
        for j in 0..N {
            let (Some(a), Some(b)) = (group[i], group[j]) else {
                continue;
            };
            p[i][j] = pattern
                .block_position(a.min(b), a.max(b))
                .expect("element block pair missing from the pattern") as u32;
        }
    }
    p
}

/// Adds a symmetric 3×3 block onto the diagonal block of `block` in the upper-triangular values (its
/// upper triangle).
///
/// # Panics
/// If the pattern lacks the diagonal block (every pattern has them).
pub fn add_diagonal_block(pattern: &SparsityPattern, values: &mut [f64], block: usize, h: &Matrix3<f64>) {
    let k = pattern
        .block_position(block, block)
        .expect("diagonal block is always in the pattern");
    for c in 0..3 {
        let start = pattern.col_start(3 * block + c) + 3 * k;
        for r in 0..=c {
            values[start + r] += h[(r, c)];
        }
    }
}

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
        let positions = blocks.iter().map(|el| block_positions(pattern, el.map(Some))).collect();
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

/// Precomputed scatter positions of groups of up to `N` blocks with absent or repeated slots.
///
/// A boundary stencil lacks the vertices across its boundary edges, and its energy does not depend on
/// those slots: absent slots are skipped, so no spurious couplings enter the pattern. A block may fill
/// two slots of a group (the faces across two edges of a face share their third vertex where a vertex
/// has valence 3): both slot orders then add into that block's diagonal block, so the result is the
/// Hessian of the energy as a function of the distinct blocks.
#[derive(Debug, Clone)]
pub struct GroupScatter<const N: usize> {
    blocks: Vec<[Option<usize>; N]>,
    /// For each group and local pair `(i, j)`, the position of the block pair in the pattern (for the
    /// orientation with the smaller global block as the row), or `ABSENT`.
    positions: Vec<[[u32; N]; N]>,
}

impl<const N: usize> GroupScatter<N> {
    /// Scatter data for groups given by their global blocks (`None` = absent slot).
    ///
    /// # Panics
    /// If a group couples two blocks that the pattern does not couple (the pattern must have been built
    /// from the present blocks of the same groups).
    #[track_caller]
    pub fn new(pattern: &SparsityPattern, blocks: Vec<[Option<usize>; N]>) -> Self {
        let positions = blocks.iter().map(|group| block_positions(pattern, *group)).collect();
        Self { blocks, positions }
    }

    /// Number of groups.
    pub fn len(&self) -> usize {
        self.blocks.len()
    }

    /// Whether there are no groups.
    pub fn is_empty(&self) -> bool {
        self.blocks.is_empty()
    }

    /// Adds a group gradient (`3N` entries, slot by slot) into the global gradient; absent slots are
    /// skipped.
    #[inline]
    pub fn add_gradient<const NE: usize>(&self, e: usize, g: &SVector<f64, NE>, global: &mut [f64]) {
        debug_assert_eq!(NE, 3 * N);
        for (i, b) in self.blocks[e].iter().enumerate() {
            if let Some(b) = *b {
                for c in 0..3 {
                    global[3 * b + c] += g[3 * i + c];
                }
            }
        }
    }

    /// Adds a group Hessian (`3N × 3N`, symmetric) into the global upper-triangular values.
    #[inline]
    pub fn add_hessian<const NE: usize>(
        &self,
        e: usize,
        h: &SMatrix<f64, NE, NE>,
        pattern: &SparsityPattern,
        values: &mut [f64],
    ) {
        debug_assert_eq!(NE, 3 * N);
        let group = &self.blocks[e];
        let pos = &self.positions[e];
        for i in 0..N {
            for j in 0..N {
                let (Some(a), Some(b)) = (group[i], group[j]) else {
                    continue;
                };
                // A diagonal block receives both orders of two slots that name the same block (the upper
                // triangle of H_ij + H_ji); a slot with itself once.
                if a > b {
                    continue;
                }
                let k = pos[i][j] as usize;
                for c in 0..3 {
                    let start = pattern.col_start(3 * b + c) + 3 * k;
                    let rows = if a == b { c + 1 } else { 3 };
                    for r in 0..rows {
                        values[start + r] += h[(3 * i + r, 3 * j + c)];
                    }
                }
            }
        }
    }
}
