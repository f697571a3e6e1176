//! The 6-vertex stencils of the discrete second fundamental form.
//!
//! A face's curvature comes from its three mid-edge normals, and the mid-edge normal of an interior
//! edge depends on the face across it. The stencil of face `f` with corners `(q₀, q₁, q₂)` (mesh order)
//! is therefore `(q₀, q₁, q₂, p₀, p₁, p₂)`, where `pᵢ` is the vertex across edge `i`, the edge opposite
//! `qᵢ` (joining `qᵢ₊₁` and `qᵢ₊₂`). On a boundary edge there is no `pᵢ`. Local coordinates of a stencil
//! are ordered the same way: `3k + c` is coordinate `c` of stencil vertex `k`.

use crate::error::KlError;
use cosserat_fem::Tri3Mesh;
use cosserat_fem::mesh::Topology;

/// The vertices of one face's stencil.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Stencil {
    /// The face's corners `(q₀, q₁, q₂)`, in mesh order.
    pub face: [usize; 3],
    /// `pᵢ`: the vertex across the edge opposite corner `i`, or `None` on a boundary edge.
    pub opposite: [Option<usize>; 3],
}

impl Stencil {
    /// The six stencil vertices `(q₀, q₁, q₂, p₀, p₁, p₂)`, `None` for absent neighbours.
    pub fn vertices(&self) -> [Option<usize>; 6] {
        let [a, b, c] = self.face;
        let [p0, p1, p2] = self.opposite;
        [Some(a), Some(b), Some(c), p0, p1, p2]
    }

    /// Which neighbours exist (`false` on boundary edges).
    pub fn present(&self) -> [bool; 3] {
        self.opposite.map(|p| p.is_some())
    }
}

/// The stencil of every face of a mesh, in face order.
///
/// # Errors
/// [`KlError::Mesh`] for an invalid mesh (bad indices, degenerate faces, unreferenced vertices, edges
/// with more than two faces, two faces with the same vertices, whose stencils would name a vertex
/// twice).
pub fn build_stencils(mesh: &Tri3Mesh) -> Result<Vec<Stencil>, KlError> {
    mesh.validate()?;
    let topology = Topology::new(mesh);
    let faces = topology.faces();
    let mut stencils = Vec::with_capacity(faces.len());
    for (f, &face) in faces.iter().enumerate() {
        let edges = topology.face_edges(f);
        let mut opposite = [None; 3];
        for (i, slot) in opposite.iter_mut().enumerate() {
            // Local edge k of a face joins corners k and k + 1, so the edge opposite corner i is k = i + 1.
            let edge = edges[(i + 1) % 3];
            let (a, b) = (face[(i + 1) % 3], face[(i + 2) % 3]);
            if let Some(&g) = topology.edge_faces(edge).iter().find(|&&g| g != f) {
                let p = faces[g]
                    .into_iter()
                    .find(|&v| v != a && v != b)
                    .expect("a valid neighbour face has a third vertex");
                debug_assert_ne!(p, face[i], "the mesh check refuses faces with the same vertices");
                *slot = Some(p);
            }
        }
        stencils.push(Stencil { face, opposite });
    }
    Ok(stencils)
}
