//! `cargo xtask tidy`: checks of the repository that no compiler makes, run as a test as well.
//!
//! - The repository is self-contained: no file refers to a folder beside the clone (a sibling
//!   `shared` directory of reading material exists on developers' machines only; scenes, tests and
//!   docs must work without it).

use anyhow::{Result, bail};
use std::path::{Path, PathBuf};

/// Folders below the workspace root that hold no sources: build output, run output, git's store.
const SKIPPED_DIRS: [&str; 3] = ["target", "out", ".git"];

/// Runs every check from the workspace root and fails with the list of findings.
///
/// # Errors
/// One line per finding; I/O errors while walking the tree.
pub fn run(root: &Path) -> Result<()> {
    let findings = references_outside_the_clone(root)?;
    if !findings.is_empty() {
        bail!("tidy found {} problem(s):\n{}", findings.len(), findings.join("\n"));
    }
    Ok(())
}

/// Lines of any file that name the developers' sibling folder, as `path:line: text`.
///
/// # Errors
/// I/O errors while walking the tree.
pub fn references_outside_the_clone(root: &Path) -> Result<Vec<String>> {
    // Built from parts so that this file does not match itself.
    let needles = [
        ["..", "/shared"].concat(),
        ["shared", "/models"].concat(),
        ["shared", "/refdata"].concat(),
    ];
    let mut findings = Vec::new();
    for path in files_below(root)? {
        let Ok(text) = std::fs::read_to_string(&path) else {
            continue; // binary files (images) cannot name a path in a way anything reads
        };
        for (n, line) in text.lines().enumerate() {
            if needles.iter().any(|needle| line.contains(needle.as_str())) {
                let shown = path.strip_prefix(root).unwrap_or(&path).display();
                findings.push(format!("{shown}:{}: {}", n + 1, line.trim()));
            }
        }
    }
    Ok(findings)
}

/// Every file below `root`, skipping [`SKIPPED_DIRS`] at the top level.
fn files_below(root: &Path) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir)? {
            let entry = entry?;
            let path = entry.path();
            let kind = entry.file_type()?;
            if kind.is_dir() {
                let skipped = dir == root && SKIPPED_DIRS.iter().any(|s| entry.file_name() == *s);
                if !skipped {
                    stack.push(path);
                }
            } else if kind.is_file() {
                files.push(path);
            }
        }
    }
    files.sort();
    Ok(files)
}
