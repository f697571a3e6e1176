//! `cargo xtask tidy`: checks of the repository that no compiler makes, run as a test as well.
//!
//! - **Self-contained.** No file refers to a folder beside the clone (a sibling `shared` directory of
//!   reading material exists on developers' machines only; scenes, tests and docs must work without
//!   it).
//! - **Layering.** Each crate depends only on the crates below it ([`LAYERS`]), and the numeric core
//!   (geometry, fem, material) on no serialisation or sparse-solver crate.
//! - **No measurements in comments.** A timing in a comment of a library's `src/` is stale the day
//!   after; figures belong in the generated reports (an order of magnitude that explains a design is
//!   fine in words, and a setting such as `Δt = 10 ms` is not a measurement).
//! - **Current docs.** Generated pages that are cheap to make (the scene-format reference) equal a
//!   fresh generation.
//! - **Short functions.** A function of `src/` longer than [`MAX_FUNCTION_LINES`] (80) lines, counted
//!   from its signature to its closing brace, says why in a comment that starts with `// Long because`
//!   inside it or just above it. A data table or a match over every variant of a schema is a reason;
//!   doing many things is not (split it into steps that read as the algorithm).

use anyhow::{Context, Result, bail};
use std::path::{Path, PathBuf};

/// Folders below the workspace root that hold no sources: build output, run output, git's store.
const SKIPPED_DIRS: [&str; 3] = ["target", "out", ".git"];

/// Every crate of the workspace with the workspace crates it may depend on (normal dependencies).
pub const LAYERS: [(&str, &[&str]); 15] = [
    ("cosserat-geometry", &[]),
    ("cosserat-sparse", &[]),
    ("cosserat-fem", &["cosserat-geometry"]),
    ("cosserat-material", &["cosserat-geometry", "cosserat-fem"]),
    (
        "cosserat-assembly",
        &["cosserat-geometry", "cosserat-fem", "cosserat-material"],
    ),
    (
        "cosserat-solver",
        &["cosserat-geometry", "cosserat-assembly", "cosserat-sparse"],
    ),
    ("cosserat-contact", &["cosserat-geometry", "cosserat-assembly"]),
    (
        "cosserat-kl",
        &[
            "cosserat-geometry",
            "cosserat-fem",
            "cosserat-material",
            "cosserat-assembly",
        ],
    ),
    (
        "cosserat-volume",
        &[
            "cosserat-geometry",
            "cosserat-fem",
            "cosserat-material",
            "cosserat-assembly",
        ],
    ),
    ("cosserat-io", &["cosserat-geometry"]),
    (
        "cosserat-scene",
        &[
            "cosserat-geometry",
            "cosserat-fem",
            "cosserat-material",
            "cosserat-assembly",
            "cosserat-solver",
            "cosserat-volume",
        ],
    ),
    (
        "cosserat",
        &[
            "cosserat-geometry",
            "cosserat-fem",
            "cosserat-material",
            "cosserat-assembly",
            "cosserat-solver",
            "cosserat-contact",
            "cosserat-kl",
            "cosserat-volume",
            "cosserat-io",
            "cosserat-scene",
        ],
    ),
    ("cosserat-lab", &["cosserat"]),
    ("xtask", &["cosserat", "cosserat-lab"]),
    ("cosserat-py", &["cosserat"]),
];

/// External crates the numeric core (geometry, fem, material) must not use: the core is generic
/// numerics, independent of file formats and of the sparse solvers.
pub const NOT_IN_THE_CORE: [&str; 4] = ["serde", "toml", "faer", "serde_json"];

/// Functions longer than this (signature to closing brace) need a reason: the style's "no function
/// over about 80 lines", so that a function reads as one step of its algorithm.
pub const MAX_FUNCTION_LINES: usize = 80;

/// Runs every check from the workspace root and fails with the list of findings.
///
/// # Errors
/// One line per finding; I/O errors while walking the tree.
pub fn run(root: &Path) -> Result<()> {
    let mut findings = references_outside_the_clone(root)?;
    findings.extend(layering(root)?);
    findings.extend(measurements_in_comments(root)?);
    findings.extend(long_functions(root)?);
    findings.extend(stale_docs(root)?);
    if !findings.is_empty() {
        bail!("tidy found {} problem(s):\n{}", findings.len(), findings.join("\n"));
    }
    Ok(())
}

/// Generated pages that differ from a fresh generation.
///
/// # Errors
/// A schema that cannot be read or parsed.
pub fn stale_docs(root: &Path) -> Result<Vec<String>> {
    let fresh = crate::scene_reference::generate(root)?;
    let committed = std::fs::read_to_string(root.join(crate::scene_reference::REFERENCE_PATH)).unwrap_or_default();
    Ok(if fresh == committed {
        Vec::new()
    } else {
        vec![format!(
            "{} is not current: run `cargo xtask scene-reference`",
            crate::scene_reference::REFERENCE_PATH
        )]
    })
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

/// Workspace dependencies that break [`LAYERS`], crates missing from it, and external crates of
/// [`NOT_IN_THE_CORE`] in the core.
///
/// # Errors
/// Unreadable manifests.
pub fn layering(root: &Path) -> Result<Vec<String>> {
    let mut findings = Vec::new();
    let mut manifests: Vec<PathBuf> = std::fs::read_dir(root.join("crates"))?
        .filter_map(|e| e.ok().map(|e| e.path().join("Cargo.toml")))
        .filter(|p| p.exists())
        .collect();
    manifests.push(root.join("xtask/Cargo.toml"));
    manifests.sort();
    for manifest in manifests {
        let text = std::fs::read_to_string(&manifest).with_context(|| format!("reading {}", manifest.display()))?;
        let Some(name) = package_name(&text) else { continue };
        let deps = normal_dependencies(&text);
        let Some((_, allowed)) = LAYERS.iter().find(|(crate_name, _)| *crate_name == name) else {
            findings.push(format!(
                "{}: crate `{name}` has no place in tidy's LAYERS",
                manifest.display()
            ));
            continue;
        };
        for dep in &deps {
            let internal = dep == "cosserat" || dep.starts_with("cosserat-");
            if internal && !allowed.contains(&dep.as_str()) {
                findings.push(format!(
                    "{name} depends on {dep}, which is not below it (tidy's LAYERS)"
                ));
            }
            let core = ["cosserat-geometry", "cosserat-fem", "cosserat-material"].contains(&name.as_str());
            if core && NOT_IN_THE_CORE.contains(&dep.as_str()) {
                findings.push(format!(
                    "{name} depends on {dep}: the numeric core knows no formats or solvers"
                ));
            }
        }
    }
    Ok(findings)
}

/// The `name` of the `[package]` section.
fn package_name(manifest: &str) -> Option<String> {
    let package = manifest
        .split("\n[")
        .find(|s| s.starts_with("[package]") || s.starts_with("package]"))?;
    package.lines().find_map(|l| {
        let rest = l.trim().strip_prefix("name")?.trim().strip_prefix('=')?;
        Some(rest.trim().trim_matches('"').to_string())
    })
}

/// The names of the `[dependencies]` section (not dev- or build-dependencies).
fn normal_dependencies(manifest: &str) -> Vec<String> {
    let mut deps = Vec::new();
    let mut inside = false;
    for line in manifest.lines() {
        let line = line.trim();
        if line.starts_with('[') {
            inside = line == "[dependencies]";
            continue;
        }
        if inside && !line.is_empty() && !line.starts_with('#') {
            let key = line.split(['=', '.']).next().unwrap_or("").trim();
            deps.push(key.to_string());
        }
    }
    deps
}

/// Comment lines of the libraries' `src/` files that quote a timing (a number with a time unit).
///
/// # Errors
/// I/O errors while walking the tree.
pub fn measurements_in_comments(root: &Path) -> Result<Vec<String>> {
    let mut findings = Vec::new();
    let libraries = source_files(root)?.into_iter().filter(|p| p.starts_with(root.join("crates")));
    for path in libraries {
        let text = std::fs::read_to_string(&path)?;
        for (n, line) in text.lines().enumerate() {
            let Some(comment) = line.find("//").map(|i| &line[i..]) else {
                continue;
            };
            if quotes_a_timing(comment) {
                let shown = path.strip_prefix(root).unwrap_or(&path).display();
                findings.push(format!("{shown}:{}: a timing in a comment: {}", n + 1, line.trim()));
            }
        }
    }
    Ok(findings)
}

/// Whether `text` holds a number followed by a time unit (`12 ms`, `0.5µs`, `3.2 GFLOP/s`) that is
/// not a setting (`Δt = 10 ms`).
fn quotes_a_timing(text: &str) -> bool {
    const UNITS: [&str; 5] = ["ms", "µs", "us", "ns", "GFLOP/s"];
    let chars: Vec<char> = text.chars().collect();
    for (i, c) in chars.iter().enumerate() {
        let starts_a_number = c.is_ascii_digit() && (i == 0 || !(chars[i - 1].is_ascii_digit() || chars[i - 1] == '.'));
        let a_setting = i >= 2 && chars[i - 1] == ' ' && chars[i - 2] == '=';
        if !starts_a_number || a_setting {
            continue;
        }
        let mut j = i + 1;
        while j < chars.len() && (chars[j].is_ascii_digit() || chars[j] == '.') {
            j += 1;
        }
        while j < chars.len() && chars[j] == ' ' {
            j += 1;
        }
        let rest: String = chars[j..].iter().collect();
        for unit in UNITS {
            if let Some(after) = rest.strip_prefix(unit)
                && !after.starts_with(|c: char| c.is_alphanumeric() || c == '_')
            {
                return true;
            }
        }
    }
    false
}

/// Functions of `src/` files longer than [`MAX_FUNCTION_LINES`] without a `// Long because` comment.
///
/// # Errors
/// I/O errors while walking the tree.
pub fn long_functions(root: &Path) -> Result<Vec<String>> {
    let mut findings = Vec::new();
    for path in source_files(root)? {
        let text = std::fs::read_to_string(&path)?;
        let lines: Vec<&str> = text.lines().collect();
        for (start, end, name) in functions(&lines) {
            let length = end - start + 1;
            let explained = lines[start.saturating_sub(3)..=end]
                .iter()
                .any(|l| l.trim_start().starts_with("// Long because"));
            if length > MAX_FUNCTION_LINES && !explained {
                let shown = path.strip_prefix(root).unwrap_or(&path).display();
                findings.push(format!(
                    "{shown}:{}: `{name}` has {length} lines; split it or say why in a `// Long because` comment",
                    start + 1
                ));
            }
        }
    }
    Ok(findings)
}

/// The functions of a source file with a body: `(first line, last line, name)`, found by their
/// signature line and the closing brace at the same indentation (rustfmt's layout).
fn functions(lines: &[&str]) -> Vec<(usize, usize, String)> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let line = lines[i];
        let trimmed = line.trim_start();
        let indent = line.len() - trimmed.len();
        let signature = [
            "fn ",
            "pub fn ",
            "pub(crate) fn ",
            "pub(super) fn ",
            "const fn ",
            "pub const fn ",
        ]
        .iter()
        .find_map(|prefix| trimmed.strip_prefix(prefix));
        if let Some(rest) = signature {
            let name: String = rest.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
            let closing = " ".repeat(indent) + "}";
            if let Some(end) = (i + 1..lines.len()).find(|&j| lines[j] == closing) {
                // A declaration without a body ends with `;` before any `{`.
                let has_body = lines[i..=end].iter().any(|l| l.contains('{'));
                if has_body {
                    out.push((i, end, name));
                    i = end;
                }
            }
        }
        i += 1;
    }
    out
}

/// The `.rs` files under `crates/*/src` and `xtask/src`.
fn source_files(root: &Path) -> Result<Vec<PathBuf>> {
    let mut dirs: Vec<PathBuf> = std::fs::read_dir(root.join("crates"))?
        .filter_map(|e| e.ok().map(|e| e.path().join("src")))
        .filter(|p| p.is_dir())
        .collect();
    dirs.push(root.join("xtask/src"));
    let mut files = Vec::new();
    for dir in dirs {
        files.extend(
            files_below(&dir)?
                .into_iter()
                .filter(|p| p.extension().is_some_and(|e| e == "rs")),
        );
    }
    files.sort();
    Ok(files)
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn timings_are_recognised_and_other_numbers_are_not() {
        assert!(quotes_a_timing("// took 143–160 ms against 58 ms"));
        assert!(quotes_a_timing("//! about 7 µs per pair"));
        assert!(quotes_a_timing("// 56.4GFLOP/s in-run"));
        assert!(!quotes_a_timing("// 3 msgs, 12 mm, 2 ns_per (a name)"));
        assert!(!quotes_a_timing("// a few microseconds per point"));
        assert!(!quotes_a_timing("/// h = 10 mm (Δt = 10 ms, the full 5 s)"));
    }

    #[test]
    fn functions_are_found_by_their_braces() {
        let src = [
            "fn a() {",
            "    let x = 1;",
            "}",
            "",
            "    pub fn b(",
            "        y: u8,",
            "    ) {",
            "    }",
        ];
        let found = functions(&src);
        assert_eq!(found, [(0, 2, "a".to_string()), (4, 7, "b".to_string())]);
    }

    #[test]
    fn manifests_are_read_for_name_and_normal_dependencies() {
        let manifest = "[package]\nname = \"cosserat-io\"\n\n[dependencies]\nserde.workspace = true\nbase64 = \"0.22\"\n\n[dev-dependencies]\nrand.workspace = true\n";
        assert_eq!(package_name(manifest).as_deref(), Some("cosserat-io"));
        assert_eq!(normal_dependencies(manifest), ["serde", "base64"]);
    }
}
