//! Element meshes: Tri3 surface meshes, their Tri6/Tri10 upgrades and the matching rotation meshes,
//! with validation, topology, refinement, normal fields, rest curvature and procedural generators.

mod curvature;
mod normals;
pub mod procedural;
mod refine;
mod topology;
mod tri_mesh;
mod upgrade;
mod validate;

pub use curvature::{
    CurvatureSettings, CurvatureSource, NormalField, PointGeometry, RestGeometry, deviation_from_affine, rest_geometry,
};
pub use normals::{AveragedNodalNormals, NormalSample, NormalWeighting, exact_normal};
pub use topology::Topology;
pub use tri_mesh::{MeshElement, Tri3Mesh, Tri6Mesh, Tri10Mesh, TriMesh};
pub use upgrade::{NewNode, chord_placement};
