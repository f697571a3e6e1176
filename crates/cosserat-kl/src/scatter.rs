//! Adding stencil contributions into the global gradient and Hessian through precomputed positions.
//!
//! This is `cosserat_assembly::scatter::ElementScatter` for groups with absent members: a boundary face's
//! stencil lacks the vertices across its boundary edges, and its energy does not depend on those slots.
//! Absent slots are skipped, so no spurious couplings enter the pattern. A block may fill two slots of
//! a group (the faces across two edges of a face share their third vertex where a vertex has valence
//! 3): both slot orders then add into that block's diagonal block, so the result is the Hessian of the
//! energy as a function of the distinct vertices.

use cosserat_assembly::SparsityPattern;
use nalgebra::{SMatrix, SVector};

/// Marks an absent slot.
const ABSENT: u32 = u32::MAX;

/// Precomputed scatter positions of groups of up to `N` blocks.
#[derive(Debug, Clone)]
pub struct LocalScatter<const N: usize> {
    blocks: Vec<[Option<usize>; N]>,
    /// For each group and local pair `(i, j)`, the position of the block pair in the pattern (for the
    /// orientation with the smaller global block as the row), or `ABSENT`.
    positions: Vec<[[u32; N]; N]>,
}

impl<const N: usize> LocalScatter<N> {
    /// Scatter data for groups given by their global blocks (`None` = absent slot).
    ///
    /// # Panics
    /// If a group couples two blocks that the pattern does not couple (the pattern must have been built
    /// from the present blocks of the same groups).
    #[track_caller]
    pub fn new(pattern: &SparsityPattern, blocks: Vec<[Option<usize>; N]>) -> Self {
        let positions = blocks
            .iter()
            .map(|group| {
                let mut p = [[ABSENT; N]; N];
                for i in 0..N {
                    for j in 0..N {
                        let (Some(a), Some(b)) = (group[i], group[j]) else {
                            continue;
                        };
                        let (a, b) = (a.min(b), a.max(b));
                        p[i][j] =
                            pattern.block_position(a, b).expect("group block pair missing from the pattern") as u32;
                    }
                }
                p
            })
            .collect();
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
