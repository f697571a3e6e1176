//! The triangle mesh type shared by all element orders, and the link from node count to element type.

use crate::element::{ShapeFunctions, Tri3, Tri6, Tri10};
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

/// Links a mesh with `N` nodes per element to its element type, so that generic mesh code can use the
/// element's shape functions (`where TriMesh<N>: MeshElement<N>`).
pub trait MeshElement<const N: usize> {
    /// The element type of the mesh.
    type Element: ShapeFunctions<N>;
}

impl MeshElement<3> for Tri3Mesh {
    type Element = Tri3;
}

impl MeshElement<6> for Tri6Mesh {
    type Element = Tri6;
}

impl MeshElement<10> for Tri10Mesh {
    type Element = Tri10;
}

impl<const N: usize> TriMesh<N> {
    /// A mesh from nodes and elements, checking that every index is in range.
    ///
    /// # Errors
    /// [`MeshError::NodeIndexOutOfRange`] for the first element with a bad index.
    pub fn try_new(nodes: Vec<Vector3<f64>>, elements: Vec<[usize; N]>) -> Result<Self, MeshError> {
        let mesh = Self { nodes, elements };
        mesh.check_indices()?;
        Ok(mesh)
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
    ///
    /// # Panics
    /// If `elem_idx` or one of the element's node indices is out of range.
    #[track_caller]
    pub fn element_nodes(&self, elem_idx: usize) -> [Vector3<f64>; N] {
        self.elements[elem_idx].map(|i| self.nodes[i])
    }

    /// The three corner node indices of one element (its first three nodes).
    ///
    /// # Panics
    /// If `elem_idx` is out of range.
    #[track_caller]
    pub fn element_corners(&self, elem_idx: usize) -> [usize; 3] {
        let e = &self.elements[elem_idx];
        [e[0], e[1], e[2]]
    }

    /// Checks that every node index of every element is in range.
    ///
    /// # Errors
    /// [`MeshError::NodeIndexOutOfRange`] for the first element with a bad index.
    pub fn check_indices(&self) -> Result<(), MeshError> {
        let n_nodes = self.nodes.len();
        for (elem_idx, elem) in self.elements.iter().enumerate() {
            if let Some(&node_idx) = elem.iter().find(|&&i| i >= n_nodes) {
                return Err(MeshError::NodeIndexOutOfRange {
                    elem_idx,
                    node_idx,
                    n_nodes,
                });
            }
        }
        Ok(())
    }

    /// The same mesh with its unreferenced nodes removed, and the map from old node index to new
    /// (`None` for removed nodes). Node order is preserved.
    ///
    /// # Panics
    /// If an element refers to a node index out of range.
    pub fn without_unreferenced_nodes(&self) -> (Self, Vec<Option<usize>>) {
        let mut used = vec![false; self.nodes.len()];
        for elem in &self.elements {
            for &i in elem {
                used[i] = true;
            }
        }
        let mut map = vec![None; self.nodes.len()];
        let mut nodes = Vec::new();
        for (old, &u) in used.iter().enumerate() {
            if u {
                map[old] = Some(nodes.len());
                nodes.push(self.nodes[old]);
            }
        }
        let elements = self
            .elements
            .iter()
            .map(|e| e.map(|i| map[i].expect("referenced nodes are kept")))
            .collect();
        (Self { nodes, elements }, map)
    }
}
