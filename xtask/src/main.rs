//! Developer tasks for the Cosserat shell workspace, run as `cargo xtask <command>`.
//!
//! xtask only orchestrates: every physical computation goes through the `cosserat` crate, so anything
//! here is also reachable by users through the `cosserat` binary and library.

mod run;

use cosserat_lab::{bench_table, experiments, runner, stability, study, validate};
use xtask::{scene_reference, tidy};

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
    /// Run the paper's experiments and write docs/experiments.md.
    Experiments(ExperimentsArgs),
    /// Time per step of the reference code's cases; writes docs/performance.md and docs/performance.json.
    BenchTable {
        /// Add the paper's largest plate (Tri6 640x64, 620k unknowns).
        #[arg(long)]
        large: bool,
        /// Rounds over all cases; each case reports its run with the median time per step.
        #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..))]
        rounds: u32,
    },
    /// Run the validation benchmarks and write docs/validation.md.
    Validate(ValidateArgs),
    /// Speed-accuracy study (refinement ladders per element pair) into docs/speed-accuracy.md.
    Study(study::StudyArgs),
    /// Stability matrix at extreme parameters and the locking study into docs/stability.md.
    Stability(stability::StabilityArgs),
    /// Repository checks that no compiler makes (also run by the test suite).
    Tidy,
    /// Regenerate docs/scene-format.md from the scene schema's doc comments.
    SceneReference,
    /// Run one scene and print the peak memory (used by the studies; one scene per process).
    #[command(hide = true)]
    MeasureRun(cosserat::cli::RunArgs),
}

#[derive(Debug, clap::Args)]
struct ValidateArgs {
    /// Only the scene's own mesh and the next ladder mesh (writes out/validation_quick.md instead).
    #[arg(long)]
    quick: bool,
}

#[derive(Debug, clap::Args)]
struct ExperimentsArgs {
    /// A few steps of each run on the coarsest meshes (writes out/experiments_quick.md instead).
    #[arg(long)]
    quick: bool,
    /// Every row of the paper's Table 1 at its mesh, time step and duration (the largest meshes, the
    /// paper's armadillo mesh, the thin bunnies for 5 s): hours on two cores.
    #[arg(long)]
    large: bool,
    /// Only experiments whose name contains this.
    #[arg(long)]
    only: Option<String>,
    /// Only rows whose variant contains this (Table 1's "Variant", e.g. "h = 1.5 mm" or "320x32").
    #[arg(long)]
    row: Option<String>,
    /// Directory of the experiments' OBJ meshes.
    #[arg(long, default_value = "assets/meshes")]
    meshes: PathBuf,
    /// Take each complete earlier run of exactly the same scene and overrides from out/ instead of
    /// running it again (the report marks such rows and names the revision that produced them), so
    /// that `--large` can be completed row by row.
    #[arg(long)]
    reuse: bool,
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
    // `run` and `render` are the user's runner: their paths (scene, --out, the default out/<name>)
    // stay relative to the folder the command was started in. The other commands work on the
    // workspace's scenes and docs from its root.
    if !matches!(args.command, Command::Run(_) | Command::Render(_)) {
        std::env::set_current_dir(workspace_root())?;
    }
    let code = match args.command {
        Command::Run(a) => run::run(&a)?,
        Command::BenchTable { large, rounds } => {
            bench_table::run(large, rounds as usize)?;
            0
        }
        Command::Experiments(a) => run_experiments(&a)?,
        Command::Validate(a) => run_validation(&a)?,
        Command::Study(a) => study::run(&a)?,
        Command::SceneReference => {
            scene_reference::write(&workspace_root())?;
            eprintln!("wrote {}", scene_reference::REFERENCE_PATH);
            0
        }
        Command::Tidy => {
            tidy::run(&workspace_root())?;
            eprintln!("tidy: ok");
            0
        }
        Command::Stability(a) => stability::run(&a)?,
        Command::MeasureRun(a) => {
            let (code, peak) = runner::measure_run(&a)?;
            if let Some(kib) = peak {
                println!("peak_rss_kib={kib}");
            }
            code
        }
        Command::Render(a) => {
            let path = cosserat::cli::render(&a)?;
            eprintln!("wrote {}", path.display());
            0
        }
    };
    std::process::exit(code)
}

/// `cargo xtask experiments`: runs them, writes the report (docs/experiments.md for a full run, a
/// file under `out/` otherwise) and lists the checks that failed; the exit code is 1 when one did.
fn run_experiments(a: &ExperimentsArgs) -> Result<i32> {
    let partial = a.only.is_some() || a.row.is_some();
    let options = experiments::Options {
        quick: a.quick,
        large: a.large,
        only: a.only.clone(),
        row: a.row.clone(),
        meshes: a.meshes.clone(),
        out: PathBuf::from(if a.quick {
            "out/experiments_quick"
        } else {
            "out/experiments"
        }),
        render_dir: (!a.quick && !partial).then(|| PathBuf::from("docs/img")),
        reuse: a.reuse,
    };
    let report = experiments::run_all(&options)?;
    let path = if a.quick || partial {
        PathBuf::from("out").join(if a.quick {
            "experiments_quick.md"
        } else {
            "experiments_partial.md"
        })
    } else {
        PathBuf::from("docs/experiments.md")
    };
    std::fs::create_dir_all(path.parent().unwrap_or(std::path::Path::new(".")))?;
    std::fs::write(&path, &report.markdown)?;
    eprintln!("wrote {}", path.display());
    if report.failures.is_empty() {
        return Ok(0);
    }
    eprintln!("{} experiment check(s) failed:", report.failures.len());
    for f in &report.failures {
        eprintln!("  - {f}");
    }
    Ok(1)
}

/// `cargo xtask validate`: runs the validation benchmarks and writes docs/validation.md (or
/// out/validation_quick.md with `--quick`).
fn run_validation(a: &ValidateArgs) -> Result<i32> {
    let options = validate::Options {
        runner: runner::Runner::current_exe()?,
        out: PathBuf::from("out/validation"),
        images: PathBuf::from(if a.quick { "out/img" } else { "docs/img" }),
        quick: a.quick,
    };
    let md = validate::run_all(&options)?;
    let path = PathBuf::from(if a.quick {
        "out/validation_quick.md"
    } else {
        "docs/validation.md"
    });
    std::fs::write(&path, md)?;
    eprintln!("wrote {}", path.display());
    Ok(0)
}
