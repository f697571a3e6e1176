//! Uniform refinement of Tri3 meshes: every triangle is split into four through its edge midpoints.
//!
//! Refinement keeps the vertex indices and appends one vertex per edge (as the Tri6 upgrade does), so
//! repeated refinement is exactly "upgrade to Tri6, then split every Tri6 into four triangles", the
//! procedure of the Dumpling experiment. A placement hook can move the new vertices, e.g. onto a
//! sphere.

use super::topology::Topology;
use super::tri_mesh::{Tri3Mesh, TriMesh};
use super::upgrade::{NewNode, chord_placement, edge_nodes};
use nalgebra::Vector3;

impl Tri3Mesh {
    /// Splits every triangle into four at the chord midpoints of its edges.
    ///
    /// The result has `V + E` vertices (edge `e` of [`Topology::edges`] gives vertex `V + e`) and
    /// `4F` triangles; face `f` becomes faces `4f..4f + 4` (three corner triangles, then the middle
    /// one), all with the orientation of `f`.
    ///
    /// # Panics
    /// If an element refers to a node index out of range.
    pub fn refine_uniform(&self) -> Tri3Mesh {
        self.refine_uniform_with(chord_placement)
    }

    /// As [`Tri3Mesh::refine_uniform`], with each new vertex placed by `place` (called once per edge,
    /// in edge order, with `t = ½`).
    ///
    /// # Panics
    /// If an element refers to a node index out of range.
    pub fn refine_uniform_with(&self, mut place: impl FnMut(NewNode) -> Vector3<f64>) -> Tri3Mesh {
        let topology = Topology::new(self);
        let (new_nodes, first) = edge_nodes(self, &topology, 1, &mut place);
        let mut elements = Vec::with_capacity(4 * self.n_elements());
        for f in 0..self.n_elements() {
            let [a, b, c] = self.elements[f];
            let [e0, e1, e2] = topology.face_edges(f).map(|e| first[e]);
            // e0 on (a, b), e1 on (b, c), e2 on (c, a).
            elements.push([a, e0, e2]);
            elements.push([e0, b, e1]);
            elements.push([e2, e1, c]);
            elements.push([e0, e1, e2]);
        }
        let mut nodes = self.nodes.clone();
        nodes.extend(new_nodes);
        TriMesh { nodes, elements }
    }
}
