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
//! - [`output`]: the files of a run (VTU frames with a `.pvd` collection, `probes.csv`, `summary.json`),
//!   all written atomically and owned by [`output::RunWriter`];
//! - [`grid`]: flat rectangular grids recognised in a mesh (the mid-surface of a volumetric slab);
//! - [`render`]: a small software rasteriser that turns a frame into a PNG image for quick looks and
//!   reports.
//!
//! Non-goals: this crate does no physics. Scene loading builds meshes, resolves regions and compiles
//! scripts, but computes no rest state or energy; the outputs and the renderer take plain data
//! (points, triangles, named arrays) and know no simulation type. There are no feature flags.
//!
//! ```
//! use cosserat_scene::output::{DataArray, VtuFrame, vtu::to_vtu_string};
//! use cosserat_scene::render::{RenderOptions, render_image};
//!
//! let mut frame = VtuFrame::new(vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], vec![[0, 1, 2]], 0.0);
//! frame.point_data.push(DataArray::scalars("height", vec![0.0, 1.0, 2.0]));
//! assert!(to_vtu_string(&frame)?.contains("NumberOfCells=\"1\""));
//!
//! let options = RenderOptions { width: 64, height: 48, ..RenderOptions::default() };
//! let image = render_image(&frame, &options)?;
//! assert_eq!((image.width, image.height), (64, 48));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod error;
pub mod expr;
pub mod grid;
pub mod mesh_source;
pub mod obj;
pub mod output;
pub mod overrides;
pub mod region;
pub mod render;
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
