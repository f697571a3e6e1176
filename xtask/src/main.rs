//! Developer tasks for the Cosserat shell workspace, run as `cargo xtask <command>`.
//!
//! xtask only orchestrates: every physical computation goes through the `cosserat` crate, so anything
//! here is also reachable by users through the `cosserat` binary and library.

mod run;

use anyhow::Result;
use clap::{Parser, Subcommand};
use std::path::PathBuf;

#[derive(Debug, Parser)]
#[command(
    name = "cargo xtask",
    about = "Developer tasks: runs, experiments, studies and tables"
)]
struct Xtask {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Run a scene (same as the `cosserat run` binary).
    Run(cosserat::cli::RunArgs),
    /// Render frames of a finished run to PNG.
    Render(cosserat::cli::RenderArgs),
}

/// The workspace root (xtask lives one level below it).
fn workspace_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(PathBuf::from)
        .unwrap_or_default()
}

fn main() -> Result<()> {
    let args = Xtask::parse();
    std::env::set_current_dir(workspace_root())?;
    let code = match args.command {
        Command::Run(a) => run::run(&a)?,
        Command::Render(a) => {
            let path = cosserat::cli::render(&a)?;
            eprintln!("wrote {}", path.display());
            0
        }
    };
    std::process::exit(code)
}
