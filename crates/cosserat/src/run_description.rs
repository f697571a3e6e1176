//! One run of a sweep or study, described as data: the scene, its overrides, where the outputs go,
//! a label and a thread bound.
//!
//! The same description serves three runners: the `cosserat run` command line ([`RunDescription::cli_args`]),
//! a run in this process ([`RunDescription::run`]), and JSON lists that the Python package's
//! `load_descriptions` reads and `save_descriptions` writes (the keys are the same), so that a study
//! written by `cargo xtask study --emit-runs` can be run on a Dask cluster and a Python sweep can be
//! run by the studies' child-process runner.

use crate::stop::StopRequest;
use crate::{Simulation, SimulationError};
use cosserat_io::RunSummary;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// One run: `scene` with `overrides` (`"key=value"`, as `cosserat run --set`), writing into `out_dir`.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunDescription {
    /// The scene file.
    pub scene: PathBuf,
    /// The output folder.
    pub out_dir: PathBuf,
    /// `key=value` overrides of the scene.
    #[serde(default)]
    pub overrides: Vec<String>,
    /// The run's name in a table (may be empty).
    #[serde(default)]
    pub label: String,
    /// The number of threads (`None`: all cores; one suits one run per core).
    #[serde(default = "one_thread")]
    pub threads: Option<usize>,
}

// The default of the Python package's `RunDescription`: sweeps run one run per core.
#[allow(clippy::unnecessary_wraps)]
fn one_thread() -> Option<usize> {
    Some(1)
}

impl RunDescription {
    /// A run of `scene` with `overrides` into `out_dir`, unlabelled, on one thread.
    pub fn new(scene: impl Into<PathBuf>, out_dir: impl Into<PathBuf>, overrides: &[String]) -> Self {
        Self {
            scene: scene.into(),
            out_dir: out_dir.into(),
            overrides: overrides.to_vec(),
            label: String::new(),
            threads: one_thread(),
        }
    }

    /// The arguments of `cosserat run` (or `cargo xtask run`) for this run.
    pub fn cli_args(&self) -> Vec<String> {
        let mut args = vec![
            "run".to_string(),
            self.scene.display().to_string(),
            "--out".to_string(),
            self.out_dir.display().to_string(),
        ];
        for text in &self.overrides {
            args.extend(["--set".to_string(), text.clone()]);
        }
        if let Some(n) = self.threads {
            args.extend(["--threads".to_string(), n.to_string()]);
        }
        args
    }

    /// Runs the scene in this process on a pool of [`threads`](Self::threads) threads and returns
    /// its summary (also written into `out_dir` with the other outputs).
    ///
    /// # Errors
    /// A scene that does not load or build, a thread pool that cannot be created, or an output
    /// folder that cannot be written.
    pub fn run(&self, stop: &StopRequest) -> Result<RunSummary, RunDescriptionError> {
        let scene = cosserat_scene::load_scene(&self.scene, &self.overrides)?;
        let mut sim = Simulation::new(scene)?;
        // Checkpoints name the scene with its overrides, so that `cosserat resume` builds it again.
        sim.set_scene_origin(crate::checkpoint::SceneOrigin {
            path: std::path::absolute(&self.scene).unwrap_or_else(|_| self.scene.clone()),
            overrides: self.overrides.clone(),
        });
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(self.threads.unwrap_or(0))
            .build()
            .map_err(|e| RunDescriptionError::Threads(e.to_string()))?;
        Ok(pool.install(|| sim.run(&self.out_dir, &mut |_| {}, stop))?)
    }
}

/// Reads a JSON list of run descriptions (as `cargo xtask study --emit-runs` or the Python package's
/// `to_dict` writes them).
///
/// # Errors
/// An unreadable file, or JSON that is not a list of descriptions (the message names the file, the
/// line and the field).
pub fn read_runs(path: &Path) -> Result<Vec<RunDescription>, RunDescriptionError> {
    let text = std::fs::read_to_string(path).map_err(|e| RunDescriptionError::Read {
        path: path.to_path_buf(),
        reason: e.to_string(),
    })?;
    serde_json::from_str(&text).map_err(|e| RunDescriptionError::Read {
        path: path.to_path_buf(),
        reason: e.to_string(),
    })
}

/// Writes a JSON list of run descriptions.
///
/// # Errors
/// A file that cannot be written.
pub fn write_runs(path: &Path, runs: &[RunDescription]) -> Result<(), RunDescriptionError> {
    let text = serde_json::to_string_pretty(runs).map_err(|e| RunDescriptionError::Read {
        path: path.to_path_buf(),
        reason: e.to_string(),
    })?;
    std::fs::write(path, text + "\n").map_err(|e| RunDescriptionError::Read {
        path: path.to_path_buf(),
        reason: e.to_string(),
    })
}

/// Why a described run could not be read or run.
#[derive(Debug, thiserror::Error)]
pub enum RunDescriptionError {
    /// The scene does not load.
    #[error(transparent)]
    Scene(#[from] cosserat_scene::SceneError),
    /// The simulation could not be built or run.
    #[error(transparent)]
    Simulation(#[from] SimulationError),
    /// The thread pool could not be created.
    #[error("creating the thread pool: {0}")]
    Threads(String),
    /// A run list could not be read or written.
    #[error("{}: {reason}", path.display())]
    Read {
        /// The run list.
        path: PathBuf,
        /// What went wrong.
        reason: String,
    },
}
