//! What a run of an experiment was made from, kept beside its outputs (`inputs.json`), so that
//! `--reuse` can take a complete earlier run of exactly the same inputs instead of running it again,
//! and the report can say which revision and machine produced each reused row.

use super::RunSpec;
use crate::host::Host;
use anyhow::{Context, Result};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The file beside a run's `summary.json` that records its inputs.
const FILE: &str = "inputs.json";

/// The inputs of one run and where it ran.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunInputs {
    /// The scene file as given.
    pub scene: String,
    /// The scene file's text when the run started: a changed scene is a different run.
    pub scene_text: String,
    /// The `--set` overrides, in order.
    pub overrides: Vec<String>,
    /// The short git revision of the code that ran.
    pub rev: String,
    /// When the run started (UTC).
    pub date_time: String,
    /// The machine it ran on.
    pub machine: String,
}

impl RunInputs {
    /// The inputs of `spec` on this machine, now.
    pub fn of(spec: &RunSpec) -> Result<Self> {
        let host = Host::current();
        Ok(Self {
            scene: spec.scene.display().to_string(),
            scene_text: std::fs::read_to_string(&spec.scene)
                .with_context(|| format!("reading {}", spec.scene.display()))?,
            overrides: spec.overrides.clone(),
            rev: host.rev.clone(),
            date_time: host.date_time.clone(),
            machine: format!("{}, {} cores", host.cpu, host.cores),
        })
    }

    /// Whether the run these inputs describe is `spec` as it stands now: same scene path, scene text
    /// and overrides. The revision, date and machine may differ; the report names them. A scene that
    /// cannot be read matches nothing.
    pub fn is_run_of(&self, spec: &RunSpec) -> bool {
        self.scene == spec.scene.display().to_string()
            && self.overrides == spec.overrides
            && std::fs::read_to_string(&spec.scene).is_ok_and(|text| text == self.scene_text)
    }

    /// Records the inputs in the run's folder (before it runs).
    pub fn write(&self, dir: &Path) -> Result<()> {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
        let path = dir.join(FILE);
        std::fs::write(&path, serde_json::to_string_pretty(self)?)
            .with_context(|| format!("writing {}", path.display()))
    }

    /// The inputs recorded in a run's folder, if any can be read.
    pub fn read(dir: &Path) -> Option<Self> {
        serde_json::from_str(&std::fs::read_to_string(dir.join(FILE)).ok()?).ok()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    #[test]
    fn a_run_is_the_same_only_with_the_same_scene_text_and_overrides() {
        let dir = std::env::temp_dir().join(format!("cosserat-provenance-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let scene = dir.join("s.toml");
        std::fs::write(&scene, "[time]\nend = 1.0\n").unwrap();
        let spec = RunSpec {
            variant: "v".into(),
            element: "tri6".into(),
            scene: scene.clone(),
            overrides: vec!["time.dt=0.01".into()],
        };
        let inputs = RunInputs::of(&spec).unwrap();
        inputs.write(&dir).unwrap();
        let back = RunInputs::read(&dir).unwrap();
        assert_eq!(back, inputs);
        let mut other = back.clone();
        other.rev = "0000000".into();
        other.date_time = "earlier".into();
        assert!(other.is_run_of(&spec), "revision and date do not make another run");
        let changed = RunSpec {
            overrides: vec!["time.dt=0.02".into()],
            ..spec.clone()
        };
        assert!(!inputs.is_run_of(&changed));
        std::fs::write(&scene, "[time]\nend = 2.0\n").unwrap();
        assert!(!inputs.is_run_of(&spec), "an edited scene is another run");
        assert!(RunInputs::read(&PathBuf::from("/nonexistent")).is_none());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
