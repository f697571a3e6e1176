//! Mesh tests, one module per source file of `src/mesh/`.

mod curvature;
mod normals;
mod procedural;
mod refine;
mod topology;
mod tri_mesh;
mod upgrade;
mod validate;
