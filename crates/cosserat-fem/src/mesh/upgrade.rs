//! Upgrading a Tri3 mesh to Tri6 or Tri10, and the reverse: the corner (rotation) mesh of a
//! higher-order mesh.
//!
//! An upgrade keeps the Tri3 vertices as the first `n_vertices` nodes with the same indices, so the
//! Tri3 mesh itself is the rotation mesh of the upgraded displacement mesh. New nodes are shared
//! between neighbouring elements; a placement hook decides where they go (the chord position by
//! default, or the exact surface of a generator).

use super::topology::Topology;
use super::tri_mesh::{Tri3Mesh, Tri6Mesh, Tri10Mesh, TriMesh};
use nalgebra::Vector3;

/// A node about to be created by an upgrade or a refinement, passed to the placement hook.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NewNode {
    /// A node on the edge between Tri3 vertices `vertices[0] < vertices[1]`.
    Edge {
        /// The edge's vertex indices (smaller first).
        vertices: [usize; 2],
        /// The reference position along the edge from `vertices[0]` (½ for Tri6 and refinement,
        /// ⅓ or ⅔ for Tri10).
        t: f64,
        /// The chord position `(1 − t) X_a + t X_b`.
        chord: Vector3<f64>,
    },
    /// A node inside a face (the centroid node of Tri10).
    Interior {
        /// The face index.
        face: usize,
        /// The face's corner vertex indices, in element order.
        vertices: [usize; 3],
        /// The barycentric coordinates of the node with respect to `vertices`.
        barycentric: [f64; 3],
        /// The flat position `Σ λᵢ Xᵢ`.
        chord: Vector3<f64>,
    },
}

impl NewNode {
    /// The position on the straight edge or the flat face.
    pub fn chord(&self) -> Vector3<f64> {
        match *self {
            Self::Edge { chord, .. } | Self::Interior { chord, .. } => chord,
        }
    }
}

/// The chord (default) placement hook.
pub fn chord_placement(node: NewNode) -> Vector3<f64> {
    node.chord()
}

/// Creates `per_edge` nodes on every edge at `t = k / (per_edge + 1)`, appended after `first_node`.
/// Returns the positions and the index of the first node of each edge (node `k` of edge `e` is at
/// `first\[e\] + k`, ordered from the smaller vertex).
pub(crate) fn edge_nodes(
    mesh: &Tri3Mesh,
    topology: &Topology,
    per_edge: usize,
    place: &mut impl FnMut(NewNode) -> Vector3<f64>,
) -> (Vec<Vector3<f64>>, Vec<usize>) {
    let mut positions = Vec::with_capacity(per_edge * topology.n_edges());
    let mut first = Vec::with_capacity(topology.n_edges());
    for &[a, b] in topology.edges() {
        first.push(mesh.n_nodes() + positions.len());
        for k in 1..=per_edge {
            let t = k as f64 / (per_edge + 1) as f64;
            let chord = mesh.nodes[a] * (1.0 - t) + mesh.nodes[b] * t;
            positions.push(place(NewNode::Edge {
                vertices: [a, b],
                t,
                chord,
            }));
        }
    }
    (positions, first)
}

impl Tri3Mesh {
    /// The Tri6 mesh with one shared node per edge at the chord midpoint (a flat, straight-edged
    /// upgrade).
    ///
    /// Node count `V + E`: vertices keep their indices, edge `e` of [`Topology::edges`] gets node
    /// `V + e`.
    ///
    /// # Panics
    /// If an element refers to a node index out of range.
    pub fn to_tri6(&self) -> Tri6Mesh {
        self.to_tri6_with(chord_placement)
    }

    /// As [`Tri3Mesh::to_tri6`], with each new node placed by `place` (e.g. projected onto the exact
    /// surface). The hook is called once per edge, in edge order.
    ///
    /// # Panics
    /// If an element refers to a node index out of range.
    pub fn to_tri6_with(&self, mut place: impl FnMut(NewNode) -> Vector3<f64>) -> Tri6Mesh {
        let topology = Topology::new(self);
        let (new_nodes, first) = edge_nodes(self, &topology, 1, &mut place);
        let elements = (0..self.n_elements())
            .map(|f| {
                let c = self.elements[f];
                let e = topology.face_edges(f);
                [c[0], c[1], c[2], first[e[0]], first[e[1]], first[e[2]]]
            })
            .collect();
        let mut nodes = self.nodes.clone();
        nodes.extend(new_nodes);
        TriMesh { nodes, elements }
    }

    /// The Tri10 mesh with two shared nodes per edge at the chord's thirds and one node at each face
    /// centroid.
    ///
    /// Node count `V + 2E + F`: vertices keep their indices, edge `e` gets nodes `V + 2e` (near its
    /// smaller vertex) and `V + 2e + 1`, face `f` gets node `V + 2E + f`. Each element lists the
    /// nodes of its edge `i → j` from `i` to `j`, whichever way its neighbour traverses the edge.
    ///
    /// # Panics
    /// If an element refers to a node index out of range.
    pub fn to_tri10(&self) -> Tri10Mesh {
        self.to_tri10_with(chord_placement)
    }

    /// As [`Tri3Mesh::to_tri10`], with each new node placed by `place`. The hook is called for the
    /// edge nodes in edge order, then for the interior nodes in face order.
    ///
    /// # Panics
    /// If an element refers to a node index out of range.
    pub fn to_tri10_with(&self, mut place: impl FnMut(NewNode) -> Vector3<f64>) -> Tri10Mesh {
        let topology = Topology::new(self);
        let (edge_positions, first) = edge_nodes(self, &topology, 2, &mut place);
        let interior_start = self.n_nodes() + edge_positions.len();
        let mut nodes = self.nodes.clone();
        nodes.extend(edge_positions);
        let third = 1.0 / 3.0;
        for f in 0..self.n_elements() {
            let c = self.elements[f];
            let chord = (self.nodes[c[0]] + self.nodes[c[1]] + self.nodes[c[2]]) * third;
            nodes.push(place(NewNode::Interior {
                face: f,
                vertices: c,
                barycentric: [third; 3],
                chord,
            }));
        }
        let elements = (0..self.n_elements())
            .map(|f| {
                let c = self.elements[f];
                let e = topology.face_edges(f);
                let mut element = [0; 10];
                element[..3].copy_from_slice(&c);
                for k in 0..3 {
                    let (from, to) = (c[k], c[(k + 1) % 3]);
                    let (near_small, near_large) = (first[e[k]], first[e[k]] + 1);
                    let (n1, n2) = if from < to {
                        (near_small, near_large)
                    } else {
                        (near_large, near_small)
                    };
                    element[3 + 2 * k] = n1;
                    element[4 + 2 * k] = n2;
                }
                element[9] = interior_start + f;
                element
            })
            .collect();
        TriMesh { nodes, elements }
    }
}

impl<const N: usize> TriMesh<N> {
    /// The rotation mesh made of the corner nodes: a Tri3 mesh with the same elements in the same
    /// order, its vertices renumbered by increasing node index, and the map from Tri3 vertex to node
    /// of this mesh.
    ///
    /// For a mesh upgraded from a Tri3 mesh the corners are the first nodes, so the map is the
    /// identity and the result equals the original Tri3 mesh.
    ///
    /// # Panics
    /// If an element refers to a node index out of range.
    pub fn corner_mesh(&self) -> (Tri3Mesh, Vec<usize>) {
        let mut is_corner = vec![false; self.n_nodes()];
        for e in 0..self.n_elements() {
            for c in self.element_corners(e) {
                is_corner[c] = true;
            }
        }
        let vertex_to_node: Vec<usize> = (0..self.n_nodes()).filter(|&i| is_corner[i]).collect();
        let mut node_to_vertex = vec![usize::MAX; self.n_nodes()];
        for (v, &n) in vertex_to_node.iter().enumerate() {
            node_to_vertex[n] = v;
        }
        let nodes = vertex_to_node.iter().map(|&n| self.nodes[n]).collect();
        let elements = (0..self.n_elements())
            .map(|e| self.element_corners(e).map(|c| node_to_vertex[c]))
            .collect();
        (TriMesh { nodes, elements }, vertex_to_node)
    }
}
