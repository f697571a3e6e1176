//! Repository checks of the Cosserat shell workspace (`cargo xtask tidy`) and the generated
//! scene-format reference (`cargo xtask scene-reference`). The experiments, validation and studies
//! that `cargo xtask` also dispatches live in the `cosserat-lab` crate.

pub mod scene_reference;
pub mod tidy;
