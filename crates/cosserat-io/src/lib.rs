//! Run outputs of the Cosserat shell simulator: VTU frames and their `.pvd` collection, `probes.csv`
//! and the typed run record `summary.json`, the reading of frames back, and a small renderer of frames
//! to PNG.
//!
//! Everything here takes plain data (points, triangle index triples, named arrays, a record of numbers
//! and names), so the simulator calls it without this crate knowing any simulation type. Entry points:
//! - [`RunWriter`]: owns a run's output directory (layout in [`run`]);
//! - [`RunSummary`]: the run record, written and read by [`write_summary`] and [`read_summary`];
//! - [`VtuFrame`] with [`write_vtu`], [`read_vtu`], [`read_pvd`] and [`read_pvd_frame`];
//! - [`mesh_frames`]: the same frames as OBJ or PLY sequences and one USD stage ([`FrameFormats`]);
//! - [`render`]: a software rasteriser for quick looks and report figures.
//!
//! Every file that is written whole goes through [`atomic::write_atomic`] and `probes.csv` is appended
//! one complete row at a time, so a crash never leaves a truncated file. Non-finite numbers are refused
//! with an error naming the array, column or field: an output file never contains NaN or infinity.
//!
//! Non-goals: no physics and no scene input (`cosserat-scene`). There are no feature flags.
//!
//! ```
//! use cosserat_io::render::{RenderOptions, render_image};
//! use cosserat_io::{DataArray, VtuFrame, vtu::to_vtu_string};
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

pub mod atomic;
pub mod checkpoint;
pub mod error;
pub mod mesh_frames;
pub mod probes;
pub mod pvd;
pub mod render;
pub mod run;
pub mod summary;
pub mod vtu;
pub mod vtu_read;

pub use atomic::write_atomic;
pub use error::OutputError;
pub use mesh_frames::{FrameFormats, UsdWriter};
pub use probes::{KeptProbes, ProbeWriter};
pub use pvd::{PvdEntry, read_pvd, read_pvd_frame, write_pvd};
pub use run::{RunWriter, clear_run_outputs, remove_temporaries, write_failure_summary};
pub use summary::{
    Attempt, BoundingBox, BroadPhaseRecord, ContactRecord, ConvergenceRecord, EnergyHistory, FactorRecord, FailedStep,
    LinearSolverRecord, ModelRecord, RunStatus, RunSummary, ToleranceMode, read_summary, write_summary,
};
pub use vtu::{DataArray, VtuFrame, write_vtu};
pub use vtu_read::read_vtu;
