//! Developer tasks of the Cosserat shell workspace (the library behind `cargo xtask`): the paper's
//! experiments, their post-processing and tables.
//!
//! xtask only orchestrates: every physical computation goes through the `cosserat` crate.

pub mod experiments;
pub mod paper;
pub mod postprocess;
