//! The triangle mesh type shared by all element orders.

use crate::error::MeshError;
use nalgebra::Vector3;

/// A surface mesh of Lagrange triangles with `N` nodes each (3, 6 or 10), embedded in 3D.
///
/// Node order within an element follows the element type (see `element`): corners first, then
/// edge nodes, then interior nodes. Meshes upgraded from a Tri3 mesh keep the Tri3 vertices as their
/// first nodes, so the rotation (Tri3) mesh of a Tri6 displacement mesh uses the same indices.
#[derive(Debug, Clone, PartialEq)]
pub struct TriMesh<const N: usize> {
    /// Node positions.
    pub nodes: Vec<Vector3<f64>>,
    /// Element connectivity: node indices per element.
    pub elements: Vec<[usize; N]>,
}

/// Linear triangles.
pub type Tri3Mesh = TriMesh<3>;
/// Quadratic triangles.
pub type Tri6Mesh = TriMesh<6>;
/// Cubic triangles.
pub type Tri10Mesh = TriMesh<10>;

impl<const N: usize> TriMesh<N> {
    /// A mesh from nodes and elements, checking that every index is in range.
    ///
    /// # Errors
    /// [`MeshError::NodeIndexOutOfRange`] for the first element with a bad index.
    pub fn try_new(nodes: Vec<Vector3<f64>>, elements: Vec<[usize; N]>) -> Result<Self, MeshError> {
        let n_nodes = nodes.len();
        for (elem_idx, elem) in elements.iter().enumerate() {
            if let Some(&node_idx) = elem.iter().find(|&&i| i >= n_nodes) {
                return Err(MeshError::NodeIndexOutOfRange {
                    elem_idx,
                    node_idx,
                    n_nodes,
                });
            }
        }
        Ok(Self { nodes, elements })
    }

    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.nodes.len()
    }

    /// Number of elements.
    pub fn n_elements(&self) -> usize {
        self.elements.len()
    }

    /// The node positions of one element.
    pub fn element_nodes(&self, elem_idx: usize) -> [Vector3<f64>; N] {
        self.elements[elem_idx].map(|i| self.nodes[i])
    }
}
