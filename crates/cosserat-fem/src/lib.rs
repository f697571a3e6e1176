//! Lagrange triangle elements, quadrature rules and element meshes for Cosserat shells.

pub mod error;
pub mod mesh;

pub use error::MeshError;
pub use mesh::{Tri3Mesh, Tri6Mesh, Tri10Mesh, TriMesh};
