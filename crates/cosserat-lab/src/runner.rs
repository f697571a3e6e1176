//! Running one scene for a study and reading its outputs back: in this process, or in a child process
//! of the xtask binary that also reports its peak memory.
//!
//! Studies run many scenes at extreme settings. A child process per run isolates them: a panic or an
//! abort in one run becomes a recorded failure instead of ending the sweep, and the child's peak
//! resident set size (`VmHWM` of `/proc/self/status`, read by the child itself just before it exits)
//! is the memory of that run alone. The child is the hidden `cargo xtask measure-run` command, which
//! runs the scene exactly like `cargo xtask run` and prints one `peak_rss_kib=N` line on stdout.

use crate::postprocess::ProbeTable;
use anyhow::{Context, Result};
use cosserat::RunDescription;
use cosserat::io::{RunStatus, RunSummary, read_summary};
use cosserat::record::peak_memory_kib;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// Where a run executes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Runner {
    /// In this process (panics are caught; no memory measurement).
    InProcess,
    /// In a child process: the given xtask executable with the hidden `measure-run` command, on one
    /// thread.
    Child(PathBuf),
}

impl Runner {
    /// A child-process runner re-invoking the current executable.
    ///
    /// # Errors
    /// If the path of the current executable cannot be found.
    pub fn current_exe() -> Result<Self> {
        Ok(Self::Child(
            std::env::current_exe().context("locating the xtask executable")?,
        ))
    }
}

/// A finished run: what it wrote, read back.
#[derive(Debug, Clone)]
pub struct RunOutcome {
    /// The summary, if the run got far enough to write one.
    pub summary: Option<RunSummary>,
    /// The probes, if written.
    pub probes: Option<ProbeTable>,
    /// Peak resident set size of the child process \[KiB\] (child runs only).
    pub peak_rss_kib: Option<u64>,
    /// Wall time seen from outside, including process start and output \[s\].
    pub outer_seconds: f64,
    /// Why the run produced no usable result (panic, crash, setup error), if so.
    pub failure: Option<String>,
}

impl RunOutcome {
    /// Whether the run ended with status `ok`.
    pub fn is_ok(&self) -> bool {
        self.failure.is_none() && self.summary.as_ref().is_some_and(|s| s.status == RunStatus::Ok)
    }

    /// A one-line reason for a run that did not end with `ok` (empty for a good run).
    pub fn reason(&self) -> String {
        if let Some(f) = &self.failure {
            return f.clone();
        }
        match &self.summary {
            Some(s) if s.status == RunStatus::Ok => String::new(),
            Some(s) => s.reason.clone().unwrap_or_else(|| format!("{:?}", s.status)),
            None => "no summary written".into(),
        }
    }

    /// The solver's wall time from the summary \[s\].
    pub fn wall_seconds(&self) -> Option<f64> {
        self.summary.as_ref().map(|s| s.wall_seconds)
    }
}

/// Runs `run`, writing its outputs into its `out_dir` (cleared first), and reads them back. A child
/// runs on the description's threads (one if unset); a run in this process on the caller's pool.
///
/// # Errors
/// Only if the output folder cannot be prepared or the child cannot be started; failures of the run
/// itself are reported in the outcome.
pub fn run_described(runner: &Runner, run: &RunDescription) -> Result<RunOutcome> {
    let dir = run.out_dir.as_path();
    if dir.exists() {
        std::fs::remove_dir_all(dir).with_context(|| format!("clearing {}", dir.display()))?;
    }
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let start = Instant::now();
    let (failure, peak_rss_kib) = match runner {
        Runner::InProcess => (run_in_process(run), None),
        Runner::Child(exe) => run_child(exe, run)?,
    };
    let outer_seconds = start.elapsed().as_secs_f64();
    let summary = read_summary(&dir.join("summary.json")).ok();
    let probes = ProbeTable::read(&dir.join("probes.csv")).ok();
    Ok(RunOutcome {
        summary,
        probes,
        peak_rss_kib,
        outer_seconds,
        failure,
    })
}

fn run_in_process(run: &RunDescription) -> Option<String> {
    let result = catch_unwind(AssertUnwindSafe(|| -> Result<()> {
        let scene = cosserat::scene::load_scene(&run.scene, &run.overrides)
            .with_context(|| format!("loading {}", run.scene.display()))?;
        let mut sim = cosserat::Simulation::new(scene).context("setting up the simulation")?;
        sim.run(&run.out_dir, &mut |_| {}, &cosserat::StopRequest::new())?;
        Ok(())
    }));
    match result {
        Ok(Ok(())) => None,
        Ok(Err(e)) => Some(format!("{e:#}")),
        Err(panic) => Some(format!("panicked: {}", panic_message(&*panic))),
    }
}

fn panic_message(panic: &(dyn std::any::Any + Send)) -> String {
    panic
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| panic.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic payload".into())
}

fn run_child(exe: &Path, run: &RunDescription) -> Result<(Option<String>, Option<u64>)> {
    let dir = run.out_dir.as_path();
    let mut args = run.cli_args();
    // The hidden `measure-run` takes the arguments of `run`.
    args[0] = "measure-run".into();
    if run.threads.is_none() {
        args.extend(["--threads".into(), "1".into()]);
    }
    let mut cmd = Command::new(exe);
    cmd.args(&args).arg("--quiet");
    let output = cmd.output().with_context(|| format!("starting {}", exe.display()))?;
    let stdout = String::from_utf8_lossy(&output.stdout);
    let peak = stdout
        .lines()
        .find_map(|l| l.strip_prefix("peak_rss_kib="))
        .and_then(|v| v.trim().parse().ok());
    let failure = if output.status.success() || dir.join("summary.json").exists() {
        None
    } else {
        let stderr = String::from_utf8_lossy(&output.stderr);
        let last = stderr.lines().rev().find(|l| !l.trim().is_empty()).unwrap_or("").trim();
        Some(format!("child process failed ({}): {last}", output.status))
    };
    Ok((failure, peak))
}

/// The hidden `measure-run` command: runs a scene like `cargo xtask run` and returns its exit code
/// with the peak memory of this process \[KiB\], which the binary prints as `peak_rss_kib=N`.
///
/// # Errors
/// As [`cosserat::cli::run_scene`].
pub fn measure_run(args: &cosserat::cli::RunArgs) -> Result<(i32, Option<u64>)> {
    let code = cosserat::cli::run_scene(args)?;
    Ok((code, peak_memory_kib()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn this_process_reports_a_positive_peak_memory() {
        // Linux-only field; the workspace runs on Linux.
        let kib = peak_memory_kib().expect("VmHWM in /proc/self/status");
        assert!(kib > 100, "implausible peak memory {kib} KiB");
    }
}
