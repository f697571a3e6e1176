//! Scenes and run outputs of the Cosserat shell simulator.
//!
//! Entry points:
//! - [`spec::SceneSpec::from_file`] and [`spec::SceneSpec::from_str`]: a TOML scene (format in
//!   [`schema`]) with `--set key=value` overrides ([`overrides`]) checked into a [`spec::SceneSpec`],
//!   the typed description the simulator runs; errors ([`error::SceneError`]) name the file, the line,
//!   the field and the reason;
//! - the building blocks of that: [`expr`] (scripted formulas compiled once), [`region`] (node
//!   selections), [`mesh_source`] (generators, OBJ input via [`obj`], refinement, projections and
//!   transforms);
//!
//! Non-goals: this crate does no physics and writes no outputs (`cosserat-io`). Scene loading builds
//! meshes, resolves regions and compiles scripts, but computes no rest state or energy. There are no
//! feature flags.
//!
//! ```
//! use cosserat_scene::spec::SceneSpec;
//! use std::path::Path;
//!
//! let text = "name = \"disk\"\n[time]\nmode = \"quasi_static\"\nn_levels = 2\n\
//!             [mesh]\ngenerator = \"disk\"\nradius = 1.0\nn_radial = 2\nn_angular = 8\n\
//!             [material]\nmodel = \"plate\"\nthickness = 0.01\nyoungs_modulus = 1e6\n\
//!             poisson_ratio = 0.3\ndensity = 1000.0\nlength_scale = 1e-3\n";
//! let spec = SceneSpec::from_str(text, "disk.toml", Path::new("."), &[])?;
//! // A fan of 8 triangles around the centre and a ring of 8 quads (16 triangles).
//! assert_eq!(spec.shells[0].mesh.corners.n_elements(), 8 + 16);
//! # Ok::<(), cosserat_scene::SceneError>(())
//! ```

pub mod error;
pub mod expr;
pub mod gmsh;
pub mod mesh_source;
pub mod obj;
pub mod overrides;
pub mod ply;
pub mod region;
pub mod schema;
pub mod spec;
mod validate;

pub use error::SceneError;
pub use spec::SceneSpec;

/// Reads and validates a scene file with `--set key=value` overrides (see [`SceneSpec::from_file`]).
///
/// # Errors
/// A [`SceneError`] naming the file, the line, the field and the reason.
pub fn load_scene(path: &std::path::Path, overrides: &[String]) -> Result<SceneSpec, SceneError> {
    SceneSpec::from_file(path, overrides)
}

/// [`load_scene`] with a limit on the size of every mesh ([`SceneSpec::from_file_within`]).
///
/// # Errors
/// As [`load_scene`].
pub fn load_scene_within(
    path: &std::path::Path,
    overrides: &[String],
    budget: &mesh_source::ElementBudget,
) -> Result<SceneSpec, SceneError> {
    SceneSpec::from_file_within(path, overrides, budget)
}
