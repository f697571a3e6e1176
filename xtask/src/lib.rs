//! Developer tasks of the Cosserat shell workspace (the library behind `cargo xtask`): the paper's
//! experiments, their post-processing and tables; the validation benchmarks (`validate`), the
//! speed–accuracy study (`study`), the stability matrix with the locking study (`stability`) and the
//! repository checks (`tidy`) and the generated scene-format reference (`scene-reference`).
//!
//! xtask only orchestrates: every physical computation goes through the `cosserat` crate.

pub mod ensemble;
pub mod experiments;
pub mod locking;
pub mod obstacle;
pub mod paper;
pub mod path_validation;
pub mod plot;
pub mod postprocess;
pub mod problem;
pub mod reference;
pub mod runner;
pub mod scene_reference;
pub mod stability;
pub mod study;
pub mod tidy;
pub mod validate;
