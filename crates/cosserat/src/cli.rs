//! The command-line interface: `cosserat run <scene.toml>`, `cosserat resume <out dir>`,
//! `cosserat render <out dir>` and `cosserat intersections <out dir>`.
//!
//! Output on a terminal is a progress bar (step, time, Newton iterations, residual); otherwise plain
//! lines about once a second. Ctrl-C (SIGINT) or SIGTERM stops the run after the current step; the
//! frames written so far stay and the summary says where the run stopped. A second signal of the same
//! kind ends the process at once.

use crate::checkpoint::{Checkpoint, SceneOrigin};
use crate::memory::MemoryLimit;
use crate::simulation::{Simulation, StepInfo, write_setup_failure};
use crate::stop::{StopReason, StopRequest};
use anyhow::Context;
use clap::{Parser, Subcommand};
use cosserat_io::render::{RenderOptions, render_png};
use cosserat_io::{RunStatus, RunSummary};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// Command-line arguments.
#[derive(Debug, Parser)]
#[command(name = "cosserat", version, about = "Three-director Cosserat shell simulator")]
pub struct Cli {
    /// The command.
    #[command(subcommand)]
    pub command: Command,
}

/// Commands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run a scene and write summary.json, probes.csv and frames/ into the output directory.
    Run(RunArgs),
    /// Continue a run from the checkpoint in its output directory (`output.checkpoint_every`).
    Resume(ResumeArgs),
    /// Render frames of a finished run to PNG.
    Render(RenderArgs),
    /// Test every written frame of a run for intersecting triangles (exact test over all triangles,
    /// obstacles included); exit code 1 if any frame has an intersecting pair.
    Intersections(IntersectionsArgs),
}

/// Arguments of `intersections`.
#[derive(Debug, clap::Args)]
pub struct IntersectionsArgs {
    /// A run's output directory.
    pub dir: PathBuf,
}

/// Arguments of `resume`.
#[derive(Debug, clap::Args)]
pub struct ResumeArgs {
    /// The output directory of the run (it holds `checkpoint/state.bin`).
    pub dir: PathBuf,
    /// Number of threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// No progress output.
    #[arg(long)]
    pub quiet: bool,
    /// Refuse scenes that need more memory than this (e.g. `3G`, `512M`).
    #[arg(long, value_name = "SIZE", value_parser = crate::memory::parse_size)]
    pub max_memory: Option<u64>,
}

/// Arguments of `run`.
#[derive(Debug, clap::Args)]
pub struct RunArgs {
    /// The scene file (TOML).
    pub scene: PathBuf,
    /// Output directory (default: `out/<scene name>/`).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Override a scene field, e.g. `--set mesh.ny=8` (repeatable); `--set solver.tolerance=` (no value)
    /// removes the field, so that its default applies.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub overrides: Vec<String>,
    /// Number of threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// No progress output.
    #[arg(long)]
    pub quiet: bool,
    /// Refuse scenes that need more memory than this (e.g. `3G`, `512M`); the machine's available
    /// memory and the process's limits apply in any case.
    #[arg(long, value_name = "SIZE", value_parser = crate::memory::parse_size)]
    pub max_memory: Option<u64>,
}

/// Arguments of `render`.
#[derive(Debug, clap::Args)]
pub struct RenderArgs {
    /// A run's output directory.
    pub dir: PathBuf,
    /// Frame index (default: the last frame).
    #[arg(long)]
    pub frame: Option<usize>,
    /// Output PNG (default: DIR/frame_NNNNN.png).
    #[arg(long)]
    pub output: Option<PathBuf>,
    /// Colour by displacement magnitude.
    #[arg(long)]
    pub color_displacement: bool,
}

/// Parses arguments, runs, and returns the process exit code (0 on success).
pub fn main_with_args<I, T>(args: I) -> i32
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    let cli = match Cli::try_parse_from(args) {
        Ok(c) => c,
        Err(e) => {
            let _ = e.print();
            return if e.use_stderr() { 2 } else { 0 };
        }
    };
    match run(cli) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {}", error_chain(&e));
            1
        }
    }
}

/// The messages of an error and its causes, joined by `: ` as `{:#}` does, leaving out a cause whose
/// message the text before already holds: the output layer's errors quote their cause in their own
/// message and return it as `source()` too, which `{:#}` printed twice
/// (`cannot create the directory `x`: File exists (os error 17): File exists (os error 17)`).
pub fn error_chain(error: &anyhow::Error) -> String {
    let mut text = String::new();
    for cause in error.chain() {
        let message = cause.to_string();
        if text.contains(&message) {
            continue;
        }
        if !text.is_empty() {
            text.push_str(": ");
        }
        text.push_str(&message);
    }
    text
}

/// Executes a parsed command; returns the exit code (1 if the run ended with an error status).
///
/// # Errors
/// Invalid scenes, I/O failures.
pub fn run(cli: Cli) -> anyhow::Result<i32> {
    match cli.command {
        Command::Run(args) => run_scene(&args),
        Command::Resume(args) => resume_run(&args),
        Command::Render(args) => render(&args).map(|_| 0),
        Command::Intersections(args) => report_intersections(&args),
    }
}

/// Runs a scene file; returns the exit code: 0 when the run completed, 1 when the scene is invalid or
/// the run failed, 130 (SIGINT) or 143 (SIGTERM) when it was interrupted.
///
/// # Errors
/// I/O failures of the outputs, or signal handlers that cannot be installed.
pub fn run_scene(args: &RunArgs) -> anyhow::Result<i32> {
    let stop = StopRequest::new();
    install_signal_handlers(&stop).context("installing the signal handlers")?;
    let limit = MemoryLimit::of_machine(args.max_memory);
    let budget = limit.as_ref().map(MemoryLimit::element_budget).unwrap_or_default();
    let spec = match cosserat_scene::load_scene_within(&args.scene, &args.overrides, &budget) {
        Ok(spec) => spec,
        Err(e) => {
            let stem = args
                .scene
                .file_stem()
                .map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned());
            let dir = args.out.clone().unwrap_or_else(|| Path::new("out").join(&stem));
            return setup_failed(&dir, &stem, &e.to_string());
        }
    };
    let dir = args.out.clone().unwrap_or_else(|| Path::new("out").join(&spec.name));
    let name = spec.name.clone();
    let mut sim = match Simulation::with_memory_limit(spec, limit) {
        Ok(sim) => sim,
        // The scene passed validation, so the message comes from building the simulation (contact
        // bodies that start in contact, a system too large for the memory) and names no file.
        Err(e) => return setup_failed(&dir, &name, &format!("{}: {e}", args.scene.display())),
    };
    sim.set_scene_origin(SceneOrigin {
        path: std::path::absolute(&args.scene).unwrap_or_else(|_| args.scene.clone()),
        overrides: args.overrides.clone(),
    });
    execute(&mut sim, &dir, (args.threads, args.quiet), &stop)
}

/// Continues the run in `args.dir` from its checkpoint; returns the exit code as [`run_scene`].
///
/// # Errors
/// A missing, damaged or foreign checkpoint, a scene file that changed since the checkpoint was
/// written (each named with the reason), I/O failures of the outputs.
pub fn resume_run(args: &ResumeArgs) -> anyhow::Result<i32> {
    let stop = StopRequest::new();
    install_signal_handlers(&stop).context("installing the signal handlers")?;
    let checkpoint = Checkpoint::read(&args.dir)?;
    let origin = checkpoint.origin.clone().with_context(|| {
        format!(
            "{}: the checkpoint names no scene file (the scene was built by a program, which resumes it with \
             `Simulation::resume_from`)",
            crate::checkpoint::state_path(&args.dir).display()
        )
    })?;
    let limit = MemoryLimit::of_machine(args.max_memory);
    let budget = limit.as_ref().map(MemoryLimit::element_budget).unwrap_or_default();
    let spec = cosserat_scene::load_scene_within(&origin.path, &origin.overrides, &budget)
        .with_context(|| format!("the scene of the checkpoint, {}", origin.path.display()))?;
    let mut sim = Simulation::with_memory_limit(spec, limit)?;
    sim.set_scene_origin(origin);
    let step = checkpoint.step();
    sim.resume_from(&args.dir, checkpoint)?;
    if !args.quiet {
        eprintln!("resuming {} from step {step}", args.dir.display());
    }
    execute(&mut sim, &args.dir, (args.threads, args.quiet), &stop)
}

/// The discretisation a run used, e.g. `tri6/tri6 elements, regge_stabilized strains, 3 points`.
fn discretisation(summary: &RunSummary) -> String {
    if summary.strain_interpolation == "-" || summary.strain_interpolation.is_empty() {
        format!("{} elements", summary.displacement_element)
    } else {
        format!(
            "{}/{} elements, {} strains, {} points",
            summary.displacement_element,
            summary.rotation_element,
            summary.strain_interpolation,
            summary.quadrature_points
        )
    }
}

/// Runs a simulation that is set up into `dir` with `(threads, quiet)`, and reports how it ended;
/// returns the exit code.
fn execute(
    sim: &mut Simulation,
    dir: &Path,
    (threads, quiet): (Option<usize>, bool),
    stop: &StopRequest,
) -> anyhow::Result<i32> {
    for warning in sim.advice() {
        eprintln!("warning: {warning}");
    }
    if let Some(reason) = stop.reason() {
        eprintln!(
            "{}: stopped before the run started; {} is unchanged",
            reason.describe(),
            dir.display()
        );
        return Ok(reason.exit_code());
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build()
        .context("creating the thread pool")?;
    let summary = pool.install(|| {
        let mut reporter = Reporter::new(quiet);
        sim.run(dir, &mut |info| reporter.step(info), stop)
    })?;
    // Warnings found during the run (those about the scene were printed before it).
    for warning in &summary.warnings[sim.advice().len()..] {
        eprintln!("warning: {warning}");
    }
    // With an exponent where plain notation would run to hundreds of digits (a run stopped at 1e-300).
    let stopped_at = cosserat_scene::error::Num(summary.stopped_at.unwrap_or(0.0));
    match summary.status {
        RunStatus::Ok => {
            if !quiet {
                eprintln!(
                    "{} ({}): {} steps, {:.2} Newton iterations per step, {:.1} ms per step, {:.2} s; outputs in {}",
                    summary.scene,
                    discretisation(&summary),
                    summary.n_steps,
                    summary.avg_newton_iterations,
                    summary.avg_step_ms,
                    summary.wall_seconds,
                    dir.display()
                );
            }
            Ok(0)
        }
        RunStatus::Interrupted => {
            let reason = stop.reason().unwrap_or(StopReason::Requested);
            eprintln!(
                "{} at t = {stopped_at}; the {} complete steps are in {}",
                reason.describe(),
                summary.n_steps,
                dir.display()
            );
            Ok(reason.exit_code())
        }
        RunStatus::Error => {
            eprintln!(
                "run failed at t = {stopped_at}: {}; the {} complete steps are in {}",
                summary.reason.as_deref().unwrap_or("unknown reason"),
                summary.n_steps,
                dir.display()
            );
            Ok(1)
        }
    }
}

/// Reports a scene that could not be set up. A summary with the reason is written into `dir` only when
/// `dir` holds no earlier run: the outputs of an earlier run are never touched by a run that did not
/// start.
fn setup_failed(dir: &Path, scene: &str, reason: &str) -> anyhow::Result<i32> {
    eprintln!("error: {reason}");
    if holds_run_outputs(dir) {
        eprintln!("the earlier run's outputs in {} are left as they were", dir.display());
    } else {
        write_setup_failure(dir, scene, reason).with_context(|| format!("writing {}", dir.display()))?;
    }
    Ok(1)
}

/// Whether `dir` holds outputs of a run that started (probes or a frame collection); a summary alone is
/// the report of an earlier run that could not start, which a new report may replace.
fn holds_run_outputs(dir: &Path) -> bool {
    use cosserat_io::run::{FRAMES_DIR, PROBES_FILE, PVD_FILE};
    dir.join(PROBES_FILE).exists() || dir.join(FRAMES_DIR).join(PVD_FILE).exists()
}

/// SIGINT and SIGTERM ask the run to stop after its current step; a second one of the same kind ends
/// the process at once (for a step that takes too long), with the conventional status.
fn install_signal_handlers(stop: &StopRequest) -> std::io::Result<()> {
    use signal_hook::consts::{SIGINT, SIGTERM};
    use signal_hook::flag;
    for (signal, status) in [(SIGINT, 130), (SIGTERM, 143)] {
        let armed = Arc::new(AtomicBool::new(false));
        // Order matters: the shutdown checks `armed` before the first signal sets it.
        flag::register_conditional_shutdown(signal, status, armed.clone())?;
        flag::register(signal, armed)?;
        flag::register_usize(signal, stop.flag(), signal as usize)?;
    }
    Ok(())
}

/// Progress display: a bar on a terminal, plain lines otherwise.
struct Reporter {
    bar: Option<ProgressBar>,
    plain: bool,
    last: Instant,
}

impl Reporter {
    fn new(quiet: bool) -> Self {
        let terminal = std::io::stderr().is_terminal();
        let bar = (!quiet && terminal).then(|| {
            let bar = ProgressBar::new(1000);
            bar.set_style(
                ProgressStyle::with_template("{bar:30} {msg} [{elapsed_precise}]")
                    .unwrap_or_else(|_| ProgressStyle::default_bar()),
            );
            bar
        });
        Self {
            bar,
            plain: !quiet && !terminal,
            last: Instant::now(),
        }
    }

    fn step(&mut self, info: &StepInfo) {
        let msg = format!(
            "step {} t = {} Newton {} residual {:.2e}",
            info.step,
            progress_time(info.t, info.end),
            info.newton_iterations,
            info.residual
        );
        if let Some(bar) = &self.bar {
            bar.set_position(((info.t / info.end.max(1e-300)) * 1000.0) as u64);
            bar.set_message(msg);
        } else if self.plain && (self.last.elapsed().as_secs_f64() > 1.0 || info.t >= info.end) {
            eprintln!("{msg}");
            self.last = Instant::now();
        }
    }
}

/// `t/end` for the progress line: four decimals, or four digits with an exponent where the run's end
/// is so short (or long) that four decimals would show nothing (or too much).
fn progress_time(t: f64, end: f64) -> String {
    if (1e-2..1e6).contains(&end.abs()) {
        format!("{t:.4}/{end:.4}")
    } else {
        format!("{t:.3e}/{end:.3e}")
    }
}

impl Drop for Reporter {
    fn drop(&mut self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

/// Prints the frames of a run with intersecting triangle pairs; returns 1 if there are any.
///
/// # Errors
/// A missing or unreadable `run.pvd` or frame.
pub fn report_intersections(args: &IntersectionsArgs) -> anyhow::Result<i32> {
    let found = crate::intersections::intersections_in_frames(&args.dir)
        .with_context(|| format!("testing the frames of {}", args.dir.display()))?;
    for f in &found.crossing {
        println!("frame {} (t = {}): {} intersecting pairs", f.index, f.time, f.pairs);
    }
    println!(
        "{} of {} frames with intersecting triangle pairs",
        found.crossing.len(),
        found.frames
    );
    Ok(i32::from(!found.crossing.is_empty()))
}

/// Renders a frame of a run directory to PNG.
///
/// # Errors
/// Missing or unreadable frames, PNG encoding failures.
pub fn render(args: &RenderArgs) -> anyhow::Result<PathBuf> {
    use cosserat_io::run::{FRAMES_DIR, PVD_FILE};
    use cosserat_io::{read_pvd, read_pvd_frame};
    let pvd = args.dir.join(FRAMES_DIR).join(PVD_FILE);
    let entries = read_pvd(&pvd).with_context(|| format!("reading {}", pvd.display()))?;
    anyhow::ensure!(!entries.is_empty(), "{} lists no frames", pvd.display());
    let idx = args.frame.unwrap_or(entries.len() - 1);
    anyhow::ensure!(
        idx < entries.len(),
        "frame {idx} does not exist ({} frames)",
        entries.len()
    );
    let frame = read_pvd_frame(&pvd, idx).with_context(|| format!("reading frame {idx}"))?;
    let mut options = RenderOptions::default();
    if args.color_displacement {
        options.colouring = cosserat_io::render::Colouring::PointScalar {
            array: "displacement".into(),
            mode: cosserat_io::render::ScalarMode::Magnitude,
            range: None,
        };
    }
    let out = args
        .output
        .clone()
        .unwrap_or_else(|| args.dir.join(format!("frame_{idx:05}.png")));
    render_png(&frame, &options, &out).with_context(|| format!("writing {}", out.display()))?;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::progress_time;

    #[test]
    fn the_progress_line_shows_the_time_on_any_time_scale() {
        assert_eq!(progress_time(0.35, 2.0), "0.3500/2.0000");
        assert_eq!(progress_time(5e-8, 1e-7), "5.000e-8/1.000e-7");
        assert_eq!(progress_time(2.5e6, 1e7), "2.500e6/1.000e7");
    }
}
