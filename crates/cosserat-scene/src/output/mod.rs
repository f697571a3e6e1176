//! Run outputs: VTU frames and their `.pvd` collection, `probes.csv` and `summary.json`.
//!
//! Everything here takes plain data (points, triangle index triples, named arrays, a summary struct), so
//! the simulator calls it without this module knowing any simulation type. The directory layout of a run
//! is documented in [`run`]; [`RunWriter`] owns it. Every file that is written whole goes through
//! [`atomic::write_atomic`] and `probes.csv` is appended one complete row at a time, so a crash never
//! leaves a truncated file. Non-finite numbers are refused with an error naming the array, column or
//! field: an output file never contains NaN or infinity.

pub mod atomic;
pub mod error;
mod number;
pub mod probes;
pub mod pvd;
pub mod run;
pub mod summary;
pub mod vtu;
pub mod vtu_read;

pub use atomic::write_atomic;
pub use error::OutputError;
pub use probes::ProbeWriter;
pub use pvd::{PvdEntry, read_pvd, read_pvd_frame, write_pvd};
pub use run::{RunWriter, clear_run_outputs, write_failure_summary};
pub use summary::{
    Attempt, BoundingBox, ConvergenceSummary, FailedStep, RunStatus, RunSummary, ToleranceMode, read_summary,
    write_summary,
};
pub use vtu::{DataArray, VtuFrame, write_vtu};
pub use vtu_read::read_vtu;
