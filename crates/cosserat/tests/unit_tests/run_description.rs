//! Run descriptions: the JSON the Python package writes, the command line, and a run in this process.

use cosserat::RunDescription;
use cosserat::StopRequest;
use cosserat::io::{RunStatus, read_summary};
use cosserat::run_description::{read_runs, write_runs};
use std::path::PathBuf;

fn tmp(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("run_description").join(name);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// What `cosserat.sweep.save_descriptions` writes for one run (the keys of `RunDescription.to_dict`).
const FROM_PYTHON: &str = r#"[
  {
    "scene": "scenes/twisting_strip.toml",
    "out_dir": "out/nx=4",
    "overrides": ["mesh.nx=4"],
    "label": "nx=4",
    "threads": 1
  },
  {
    "scene": "scenes/plate_under_load.toml",
    "out_dir": "out/all_cores",
    "overrides": [],
    "label": "",
    "threads": null
  }
]"#;

#[test]
fn descriptions_written_by_python_are_read_and_written_back_alike() {
    let path = tmp("lists").join("runs.json");
    std::fs::write(&path, FROM_PYTHON).unwrap();
    let runs = read_runs(&path).unwrap();
    assert_eq!(runs.len(), 2);
    assert_eq!(runs[0].scene, PathBuf::from("scenes/twisting_strip.toml"));
    assert_eq!(runs[0].overrides, ["mesh.nx=4"]);
    assert_eq!(runs[0].threads, Some(1));
    assert_eq!(runs[1].threads, None);
    assert_eq!(
        runs[0].cli_args(),
        [
            "run",
            "scenes/twisting_strip.toml",
            "--out",
            "out/nx=4",
            "--set",
            "mesh.nx=4",
            "--threads",
            "1"
        ]
    );
    assert_eq!(
        runs[1].cli_args(),
        ["run", "scenes/plate_under_load.toml", "--out", "out/all_cores"]
    );
    let again = tmp("lists").join("again.json");
    write_runs(&again, &runs).unwrap();
    let text = std::fs::read_to_string(&again).unwrap();
    let python: serde_json::Value = serde_json::from_str(FROM_PYTHON).unwrap();
    let ours: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(ours, python);
}

#[test]
fn a_bad_list_names_its_file_and_field() {
    let path = tmp("bad").join("runs.json");
    std::fs::write(&path, r#"[{"scene": "a.toml", "out_dir": "o", "treads": 2}]"#).unwrap();
    let message = read_runs(&path).unwrap_err().to_string();
    assert!(message.contains("runs.json") && message.contains("treads"), "{message}");
    let missing = read_runs(&tmp("bad").join("absent.json")).unwrap_err().to_string();
    assert!(missing.contains("absent.json"), "{missing}");
}

#[test]
fn a_description_runs_in_this_process_on_its_threads() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let out = tmp("run");
    let mut run = RunDescription::new(
        root.join("scenes/twisting_strip.toml"),
        &out,
        &["mesh.nx=8".into(), "mesh.ny=2".into(), "time.end=0.03".into()],
    );
    run.threads = Some(2);
    let summary = run.run(&StopRequest::new()).unwrap();
    assert_eq!(summary.status, RunStatus::Ok);
    assert_eq!(
        read_summary(&out.join("summary.json")).unwrap().n_steps,
        summary.n_steps
    );
    run.overrides.push("time.dt=-1".into());
    assert!(run.run(&StopRequest::new()).is_err());
}
