//! `cargo xtask run <scene>`: the simulator's own runner.

use anyhow::Result;

/// Runs a scene; returns the process exit code.
pub fn run(args: &cosserat::cli::RunArgs) -> Result<i32> {
    cosserat::cli::run_scene(args)
}
