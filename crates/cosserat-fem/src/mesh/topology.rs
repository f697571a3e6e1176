//! Edge and vertex adjacency of a triangle mesh, boundary loops and orientation.
//!
//! Topology is built from the corner nodes of the elements, so it serves Tri3 meshes and the corner
//! structure of Tri6/Tri10 meshes alike. Nothing here assumes a consistent orientation: edges are
//! unordered vertex pairs, and [`Topology::consistent_orientation`] is an explicit attempt that fails
//! on non-orientable meshes such as the Möbius band.

use super::tri_mesh::TriMesh;
use crate::error::MeshError;
use std::collections::VecDeque;

/// Compressed adjacency lists: the items of entry `i` are `list[offsets[i]..offsets[i + 1]]`.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Adjacency {
    offsets: Vec<usize>,
    list: Vec<usize>,
}

impl Adjacency {
    fn from_pairs(n: usize, mut pairs: Vec<(usize, usize)>) -> Self {
        pairs.sort_unstable();
        let mut offsets = vec![0; n + 1];
        for &(i, _) in &pairs {
            offsets[i + 1] += 1;
        }
        for i in 0..n {
            offsets[i + 1] += offsets[i];
        }
        Self {
            offsets,
            list: pairs.into_iter().map(|(_, j)| j).collect(),
        }
    }

    fn get(&self, i: usize) -> &[usize] {
        &self.list[self.offsets[i]..self.offsets[i + 1]]
    }
}

/// Unique edges, edge→faces, face→edges and vertex→faces adjacency of a triangle mesh.
///
/// Edges are stored as `[a, b]` with `a < b`, sorted lexicographically, so edge indices are
/// deterministic. Local edge `k` of a face joins its corners `k` and `(k + 1) % 3`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Topology {
    n_vertices: usize,
    faces: Vec<[usize; 3]>,
    edges: Vec<[usize; 2]>,
    edge_faces: Adjacency,
    face_edges: Vec<[usize; 3]>,
    vertex_faces: Adjacency,
}

impl Topology {
    /// The topology of the corner structure of a mesh. Vertex indices are the mesh's node indices;
    /// nodes that are not corners simply have no faces.
    ///
    /// # Panics
    /// If an element refers to a node index out of range.
    pub fn new<const N: usize>(mesh: &TriMesh<N>) -> Self {
        let n_vertices = mesh.n_nodes();
        let faces: Vec<[usize; 3]> = (0..mesh.n_elements()).map(|e| mesh.element_corners(e)).collect();
        // (a, b, face, local edge) for every face side.
        let mut sides: Vec<(usize, usize, usize, usize)> = Vec::with_capacity(3 * faces.len());
        for (f, c) in faces.iter().enumerate() {
            for k in 0..3 {
                let (p, q) = (c[k], c[(k + 1) % 3]);
                assert!(
                    p < n_vertices && q < n_vertices,
                    "face {f} refers to a vertex out of range"
                );
                sides.push((p.min(q), p.max(q), f, k));
            }
        }
        sides.sort_unstable();
        let mut edges: Vec<[usize; 2]> = Vec::new();
        let mut edge_face_pairs = Vec::with_capacity(sides.len());
        let mut face_edges = vec![[usize::MAX; 3]; faces.len()];
        for &(a, b, f, k) in &sides {
            if edges.last() != Some(&[a, b]) {
                edges.push([a, b]);
            }
            let e = edges.len() - 1;
            edge_face_pairs.push((e, f));
            face_edges[f][k] = e;
        }
        edge_face_pairs.dedup();
        let edge_faces = Adjacency::from_pairs(edges.len(), edge_face_pairs);
        let mut vf_pairs: Vec<(usize, usize)> = faces
            .iter()
            .enumerate()
            .flat_map(|(f, c)| c.iter().map(move |&v| (v, f)))
            .collect();
        vf_pairs.dedup();
        let vertex_faces = Adjacency::from_pairs(n_vertices, vf_pairs);
        Self {
            n_vertices,
            faces,
            edges,
            edge_faces,
            face_edges,
            vertex_faces,
        }
    }

    /// The number of vertices (the node count of the mesh).
    pub fn n_vertices(&self) -> usize {
        self.n_vertices
    }

    /// The number of faces.
    pub fn n_faces(&self) -> usize {
        self.faces.len()
    }

    /// The number of unique edges.
    pub fn n_edges(&self) -> usize {
        self.edges.len()
    }

    /// The corner triples of the faces, as in the mesh.
    pub fn faces(&self) -> &[[usize; 3]] {
        &self.faces
    }

    /// All edges, `[a, b]` with `a < b`, sorted.
    pub fn edges(&self) -> &[[usize; 2]] {
        &self.edges
    }

    /// The index of the edge joining `a` and `b` (in either order), if there is one.
    pub fn find_edge(&self, a: usize, b: usize) -> Option<usize> {
        self.edges.binary_search(&[a.min(b), a.max(b)]).ok()
    }

    /// The faces containing edge `edge_idx` (one for a boundary edge, two for an interior edge of a
    /// manifold mesh), in increasing order.
    pub fn edge_faces(&self, edge_idx: usize) -> &[usize] {
        self.edge_faces.get(edge_idx)
    }

    /// The edges of a face: entry `k` joins corners `k` and `(k + 1) % 3`.
    pub fn face_edges(&self, face_idx: usize) -> [usize; 3] {
        self.face_edges[face_idx]
    }

    /// The faces around a vertex, in increasing order.
    pub fn vertex_faces(&self, vertex_idx: usize) -> &[usize] {
        self.vertex_faces.get(vertex_idx)
    }

    /// Whether an edge belongs to exactly one face.
    pub fn is_boundary_edge(&self, edge_idx: usize) -> bool {
        self.edge_faces(edge_idx).len() == 1
    }

    /// The boundary edges (those with exactly one face), in increasing order.
    pub fn boundary_edges(&self) -> Vec<usize> {
        (0..self.n_edges()).filter(|&e| self.is_boundary_edge(e)).collect()
    }

    /// The first edge shared by more than two faces, if any.
    pub fn non_manifold_edge(&self) -> Option<usize> {
        (0..self.n_edges()).find(|&e| self.edge_faces(e).len() > 2)
    }

    /// Checks that every edge has at most two faces.
    ///
    /// # Errors
    /// [`MeshError::NonManifoldEdge`] for the first edge with more than two faces.
    pub fn check_manifold_edges(&self) -> Result<(), MeshError> {
        match self.non_manifold_edge() {
            None => Ok(()),
            Some(e) => Err(MeshError::NonManifoldEdge {
                a: self.edges[e][0],
                b: self.edges[e][1],
                n_faces: self.edge_faces(e).len(),
            }),
        }
    }

    /// The boundary as closed vertex cycles. Each loop lists its vertices in walking order without
    /// repeating the first one at the end; loops start at their smallest boundary edge.
    ///
    /// Every boundary edge belongs to exactly one loop. A vertex where two boundary loops touch (a
    /// "bow tie") may appear in one loop twice.
    ///
    /// # Errors
    /// [`MeshError::NonManifoldEdge`] if some edge has more than two faces, and
    /// [`MeshError::DegenerateElement`] (with area 0) for a face that repeats a vertex; in both cases the
    /// boundary need not be a union of cycles.
    pub fn boundary_loops(&self) -> Result<Vec<Vec<usize>>, MeshError> {
        self.check_manifold_edges()?;
        if let Some(elem_idx) = self.faces.iter().position(|c| c[0] == c[1] || c[1] == c[2] || c[2] == c[0]) {
            return Err(MeshError::DegenerateElement { elem_idx, area: 0.0 });
        }
        let boundary = self.boundary_edges();
        // Boundary edges around each vertex.
        let pairs: Vec<(usize, usize)> = boundary
            .iter()
            .flat_map(|&e| [(self.edges[e][0], e), (self.edges[e][1], e)])
            .collect();
        let vertex_edges = Adjacency::from_pairs(self.n_vertices, pairs);
        let mut used = vec![false; self.n_edges()];
        let mut loops = Vec::new();
        for &start in &boundary {
            if used[start] {
                continue;
            }
            used[start] = true;
            let first = self.edges[start][0];
            let mut cycle = vec![first];
            let mut current = self.edges[start][1];
            while current != first {
                cycle.push(current);
                // Each face at a vertex has two edges there, and an interior edge counts two faces, so
                // with manifold edges every vertex has an even number of boundary edges: an unused one
                // exists until the cycle closes.
                let Some(next) = vertex_edges.get(current).iter().copied().find(|&e| !used[e]) else {
                    break;
                };
                used[next] = true;
                let [a, b] = self.edges[next];
                current = if a == current { b } else { a };
            }
            loops.push(cycle);
        }
        Ok(loops)
    }

    /// Tries to orient all faces consistently: returns per face whether to flip it (reverse its
    /// corner order), or `None` if no consistent orientation exists (a non-orientable mesh, or an
    /// edge with more than two faces).
    ///
    /// Two faces sharing an edge are consistent when they traverse it in opposite directions. Each
    /// connected component keeps the orientation of its smallest face.
    pub fn consistent_orientation(&self) -> Option<Vec<bool>> {
        let n = self.n_faces();
        let mut flip: Vec<Option<bool>> = vec![None; n];
        let mut queue = VecDeque::new();
        for seed in 0..n {
            if flip[seed].is_some() {
                continue;
            }
            flip[seed] = Some(false);
            queue.push_back(seed);
            while let Some(f) = queue.pop_front() {
                let f_flip = flip[f]?;
                for (k, &e) in self.face_edges[f].iter().enumerate() {
                    let neighbours = self.edge_faces(e);
                    if neighbours.len() > 2 {
                        return None;
                    }
                    let dir_f = self.edge_direction(f, k) != f_flip;
                    for &g in neighbours.iter().filter(|&&g| g != f) {
                        let kg = self.face_edges[g].iter().position(|&x| x == e)?;
                        // g must traverse the edge opposite to f: its direction after its own flip
                        // must differ from f's.
                        let dir_g_unflipped = self.edge_direction(g, kg);
                        let g_flip = dir_g_unflipped == dir_f;
                        match flip[g] {
                            None => {
                                flip[g] = Some(g_flip);
                                queue.push_back(g);
                            }
                            Some(existing) if existing != g_flip => return None,
                            Some(_) => {}
                        }
                    }
                }
            }
        }
        flip.into_iter().collect()
    }

    /// Whether local edge `k` of face `f` runs from the smaller to the larger vertex index.
    fn edge_direction(&self, f: usize, k: usize) -> bool {
        let c = self.faces[f];
        c[k] < c[(k + 1) % 3]
    }

    /// Euler characteristic `V − E + F`, counting only vertices that belong to some face.
    pub fn euler_characteristic(&self) -> i64 {
        let v = (0..self.n_vertices).filter(|&v| !self.vertex_faces(v).is_empty()).count();
        v as i64 - self.n_edges() as i64 + self.n_faces() as i64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn adjacency_groups_sorted_pairs() {
        let adj = Adjacency::from_pairs(3, vec![(2, 5), (0, 1), (2, 4), (0, 0)]);
        assert_eq!(adj.get(0), &[0, 1]);
        assert!(adj.get(1).is_empty());
        assert_eq!(adj.get(2), &[4, 5]);
    }
}
