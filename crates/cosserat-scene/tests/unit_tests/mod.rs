//! Unit test modules mirroring `src/`.

mod scene_contact;
mod scene_errors;
mod scene_expr;
mod scene_files;
mod scene_gmsh;
mod scene_mesh_source;
mod scene_models;
mod scene_obj;
mod scene_overrides;
mod scene_ply;
mod scene_region;
