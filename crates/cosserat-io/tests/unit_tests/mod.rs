//! Unit test modules mirroring `src/`, plus the scratch-directory helper they share.

use std::path::{Path, PathBuf};

mod atomic;
mod probes;
mod pvd;
mod render;
mod run;
mod summary;
mod vtu;

/// A fresh, empty directory for test `name` under Cargo's target temporary directory.
pub fn test_dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cosserat-io-tests").join(name);
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
