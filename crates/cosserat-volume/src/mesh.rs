//! Tetrahedral meshes: the plain node/element lists with their validation, and the slab generator
//! (a box of `nx × ny × nz` hexahedra, each split into six tetrahedra).
//!
//! Every hexahedron is split along its main diagonal into the six tetrahedra of the Kuhn (Freudenthal)
//! subdivision, one per ordering of the three axes. Because the split of each face depends only on
//! the face's own corners, neighbouring hexahedra share conforming triangulated faces.

use crate::error::MeshError;
use nalgebra::{Matrix3, Vector3};

/// A mesh of linear tetrahedra.
#[derive(Debug, Clone, PartialEq)]
pub struct TetMesh {
    /// Node positions \[m\].
    pub nodes: Vec<Vector3<f64>>,
    /// Elements as four node indices, positively oriented
    /// (`det[x₁ − x₀, x₂ − x₀, x₃ − x₀] > 0`).
    pub elements: Vec<[usize; 4]>,
}

/// The signed volume `det[x₁ − x₀, x₂ − x₀, x₃ − x₀] / 6` of a tetrahedron \[m³\].
pub fn signed_volume(x: &[Vector3<f64>; 4]) -> f64 {
    Matrix3::from_columns(&[x[1] - x[0], x[2] - x[0], x[3] - x[0]]).determinant() / 6.0
}

/// Elements whose volume relative to the cube of their longest edge is below this are degenerate
/// (a regular tetrahedron has about 0.118; a sliver this flat loses about half the digits of its
/// shape-function gradients).
pub const MIN_RELATIVE_VOLUME: f64 = 1e-8;

impl TetMesh {
    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.nodes.len()
    }

    /// Number of elements.
    pub fn n_elements(&self) -> usize {
        self.elements.len()
    }

    /// The positions of element `e`'s nodes.
    ///
    /// # Panics
    /// If `e` or one of its nodes is out of range (call [`validate`](Self::validate) first).
    #[track_caller]
    pub fn element_positions(&self, e: usize) -> [Vector3<f64>; 4] {
        self.elements[e].map(|i| self.nodes[i])
    }

    /// Checks that the mesh has elements, finite nodes, node indices in range and positively oriented,
    /// non-degenerate elements.
    ///
    /// # Errors
    /// The first problem found, naming the element or node.
    pub fn validate(&self) -> Result<(), MeshError> {
        if self.elements.is_empty() {
            return Err(MeshError::Empty);
        }
        if let Some(node_idx) = self.nodes.iter().position(|x| !x.iter().all(|c| c.is_finite())) {
            return Err(MeshError::NonFiniteNode { node_idx });
        }
        let n_nodes = self.nodes.len();
        for (elem_idx, el) in self.elements.iter().enumerate() {
            if let Some(&node) = el.iter().find(|&&i| i >= n_nodes) {
                return Err(MeshError::NodeOutOfRange {
                    elem_idx,
                    node,
                    n_nodes,
                });
            }
            let x = self.element_positions(elem_idx);
            let volume = signed_volume(&x);
            let mut longest: f64 = 0.0;
            for a in 0..4 {
                for b in a + 1..4 {
                    longest = longest.max((x[a] - x[b]).norm());
                }
            }
            let relative = if longest > 0.0 {
                volume / (longest * longest * longest)
            } else {
                0.0
            };
            if relative.is_nan() || relative < MIN_RELATIVE_VOLUME {
                return Err(MeshError::DegenerateElement {
                    elem_idx,
                    volume,
                    relative,
                });
            }
        }
        Ok(())
    }

    /// The (signed) volume of every element \[m³\].
    ///
    /// # Panics
    /// If an element refers to a missing node.
    pub fn volumes(&self) -> Vec<f64> {
        (0..self.elements.len())
            .map(|e| signed_volume(&self.element_positions(e)))
            .collect()
    }
}

/// A slab mesh with its grid structure: node `(i, j, k)` sits at
/// `(−lx/2 + i lx/nx, −ly/2 + j ly/ny, −lz/2 + k lz/nz)`.
#[derive(Debug, Clone, PartialEq)]
pub struct SlabGrid {
    /// The tetrahedral mesh.
    pub mesh: TetMesh,
    /// Cells along x, y, z.
    pub cells: [usize; 3],
    /// Edge lengths `(lx, ly, lz)` \[m\].
    pub size: [f64; 3],
}

impl SlabGrid {
    /// The index of grid node `(i, j, k)`, `0 ≤ i ≤ nx`, `0 ≤ j ≤ ny`, `0 ≤ k ≤ nz`.
    #[inline]
    pub fn node(&self, i: usize, j: usize, k: usize) -> usize {
        let [_, ny, nz] = self.cells;
        (i * (ny + 1) + j) * (nz + 1) + k
    }

    /// The mid-surface of a configuration: for every `(i, j)` (row-major in `i`), the mean of the
    /// positions of the nodes `(i, j, 0..=nz)` through the thickness.
    ///
    /// # Panics
    /// If `positions` has fewer entries than the mesh has nodes.
    #[track_caller]
    pub fn mid_surface(&self, positions: &[Vector3<f64>]) -> Vec<Vector3<f64>> {
        let [nx, ny, nz] = self.cells;
        let mut out = Vec::with_capacity((nx + 1) * (ny + 1));
        for i in 0..=nx {
            for j in 0..=ny {
                let sum: Vector3<f64> = (0..=nz).map(|k| positions[self.node(i, j, k)]).sum();
                out.push(sum / (nz + 1) as f64);
            }
        }
        out
    }
}

/// A box `[−lx/2, lx/2] × [−ly/2, ly/2] × [−lz/2, lz/2]` of `nx × ny × nz` hexahedra, each split into
/// six positively oriented tetrahedra (Kuhn subdivision along the diagonal from the cell's lowest to its
/// highest corner).
///
/// # Errors
/// [`MeshError::InvalidParameter`] for a non-positive or non-finite edge length or a zero cell count.
pub fn slab(size: [f64; 3], cells: [usize; 3]) -> Result<SlabGrid, MeshError> {
    const LENGTHS: [&str; 3] = ["lx", "ly", "lz"];
    const COUNTS: [&str; 3] = ["nx", "ny", "nz"];
    for a in 0..3 {
        if !(size[a].is_finite() && size[a] > 0.0) {
            return Err(MeshError::InvalidParameter {
                name: LENGTHS[a],
                value: size[a],
                reason: "must be finite and positive",
            });
        }
        if cells[a] == 0 {
            return Err(MeshError::InvalidParameter {
                name: COUNTS[a],
                value: 0.0,
                reason: "must be at least 1",
            });
        }
    }
    let [nx, ny, nz] = cells;
    let mut grid = SlabGrid {
        mesh: TetMesh {
            nodes: Vec::with_capacity((nx + 1) * (ny + 1) * (nz + 1)),
            elements: Vec::with_capacity(6 * nx * ny * nz),
        },
        cells,
        size,
    };
    for i in 0..=nx {
        for j in 0..=ny {
            for k in 0..=nz {
                let c = [i, j, k];
                grid.mesh.nodes.push(Vector3::from_fn(|a, _| {
                    -0.5 * size[a] + size[a] * c[a] as f64 / cells[a] as f64
                }));
            }
        }
    }
    // The six axis orderings; a path from corner (0,0,0) to (1,1,1) steps along them in turn.
    const ORDERS: [[usize; 3]; 6] = [[0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]];
    for i in 0..nx {
        for j in 0..ny {
            for k in 0..nz {
                for order in ORDERS {
                    let mut corner = [i, j, k];
                    let mut tet = [grid.node(i, j, k); 4];
                    for (step, &axis) in order.iter().enumerate() {
                        corner[axis] += 1;
                        tet[step + 1] = grid.node(corner[0], corner[1], corner[2]);
                    }
                    let x = tet.map(|n| grid.mesh.nodes[n]);
                    if signed_volume(&x) < 0.0 {
                        tet.swap(2, 3);
                    }
                    grid.mesh.elements.push(tet);
                }
            }
        }
    }
    Ok(grid)
}
