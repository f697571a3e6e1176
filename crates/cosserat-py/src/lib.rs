//! Python bindings of the Cosserat shell simulator: the extension module `cosserat._cosserat`, which the
//! Python package `cosserat` (in `python/cosserat`) re-exports.
//!
//! The bindings sit on the facade of the `cosserat` crate: `cosserat.Simulation` wraps
//! [`cosserat::Simulation`], scenes come from `cosserat-scene` (a file or a dict of the same structure,
//! with `--set`-style overrides), the run record is the typed [`cosserat::io::RunSummary`]. State arrays
//! are NumPy views of the simulation's memory where its layout allows (positions, velocities,
//! rotations, angular velocities, rest positions), fresh arrays otherwise; steps and runs release the
//! GIL, and Ctrl-C stops a run after its current step.
//!
//! Build it with maturin (`pip install ./crates/cosserat-py`); `pyproject.toml` turns on PyO3's
//! `extension-module` feature, so the crate also builds in the workspace without it.

// NumPy views of the simulation's state need one unsafe call (`PyArray::borrow_from_array`), in
// `array.rs`, with its safety argument there.
#![allow(unsafe_code)]

mod array;
mod error;
mod frame;
mod scene;
mod simulation;
mod summary;

use pyo3::prelude::*;

/// The extension module.
#[pymodule]
fn _cosserat(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add_class::<simulation::PySimulation>()?;
    m.add_class::<simulation::PyStepInfo>()?;
    m.add_class::<summary::PyRunSummary>()?;
    m.add_class::<frame::PyFrame>()?;
    m.add("SceneError", py.get_type::<error::SceneError>())?;
    m.add("SimulationError", py.get_type::<error::SimulationError>())?;
    m.add("StepFailed", py.get_type::<error::StepFailed>())?;
    m.add_function(wrap_pyfunction!(frame::read_vtu, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
