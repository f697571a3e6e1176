//! Scenes and run outputs of the Cosserat shell simulator.
//!
//! Entry points:
//! - [`output`]: the files of a run (VTU frames with a `.pvd` collection, `probes.csv`, `summary.json`),
//!   all written atomically and owned by [`output::RunWriter`];
//! - [`render`]: a small software rasteriser that turns a frame into a PNG image for quick looks and
//!   reports.
//!
//! Non-goals: this crate does no physics; the outputs and the renderer take plain data (points,
//! triangles, named arrays) and know no simulation type. There are no feature flags.
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

pub mod output;
pub mod render;
