//! The paper's experiments, the validation benchmarks and the studies of the Cosserat shell
//! workspace, with the tables, plots and reports they write into `docs/`. `cargo xtask` dispatches to
//! this crate; nothing here is published.
//!
//! Every physical computation goes through the `cosserat` crate; this crate orchestrates runs,
//! post-processes their frames and compares them with published or closed-form references.
//!
//! - [`experiments`]: the paper's experiments and their expectations (`cargo xtask experiments`);
//! - [`bench_table`]: time per step of the reference code's cases (`cargo xtask bench-table`);
//! - [`validate`], [`obstacle`], [`path_validation`]: the validation benchmarks
//!   (`cargo xtask validate`);
//! - [`study`], [`problem`], [`reference`](mod@reference): the speed–accuracy study (`cargo xtask study`);
//! - [`stability`], [`locking`]: the stability matrix and the locking study (`cargo xtask stability`);
//! - [`paper`]: the paper's Table 1; [`postprocess`], [`plot`]: frame geometry and SVG plots;
//!   [`runner`]: runs in child processes to measure their peak memory.

pub mod bench_table;
pub mod ensemble;
pub mod experiments;
pub mod host;
pub mod locking;
pub mod obstacle;
pub mod paper;
pub mod path_validation;
pub mod plot;
pub mod postprocess;
pub mod problem;
pub mod reference;
pub mod runner;
pub mod stability;
pub mod study;
pub mod validate;

use std::path::{Path, PathBuf};

/// The workspace root (this crate lives two levels below it): scenes, meshes and docs are found from
/// here, so runs and tests work from any working directory.
#[must_use]
pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .ancestors()
        .nth(2)
        .map(Path::to_path_buf)
        .unwrap_or_default()
}
