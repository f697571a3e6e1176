//! Element meshes: Tri3 surface meshes, their Tri6/Tri10 upgrades and the matching rotation meshes.

mod tri_mesh;

pub use tri_mesh::{Tri3Mesh, Tri6Mesh, Tri10Mesh, TriMesh};
