//! Unit test modules mirroring `src/`, plus the scratch-directory helper they share.

use std::path::{Path, PathBuf};

mod output_atomic;
mod output_probes;
mod output_pvd;
mod output_run;
mod output_summary;
mod output_vtu;
mod render;
mod scene_contact;
mod scene_errors;
mod scene_expr;
mod scene_files;
mod scene_mesh_source;
mod scene_models;
mod scene_obj;
mod scene_overrides;
mod scene_region;

/// A fresh, empty directory for test `name` under Cargo's target temporary directory.
pub fn test_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cosserat-scene-tests").join(name);
    if dir.exists() {
        std::fs::remove_dir_all(&dir).expect("remove an old test directory");
    }
    std::fs::create_dir_all(&dir).expect("create the test directory");
    dir
}

/// Names of the entries of `dir`, sorted.
pub fn entries(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .expect("list the directory")
        .map(|entry| entry.expect("directory entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}
