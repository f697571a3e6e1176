//! Atomic file writes: a file either keeps its old content or gets its complete new content.
//!
//! The bytes go to a temporary file in the target's directory (same file system, so the final rename is
//! atomic on POSIX), which is flushed and synced before it is renamed over the target. A crash therefore
//! never leaves a truncated file under the final name; at worst a hidden temporary file
//! `.<name>.tmp<pid>-<n>` remains, which [`crate::RunWriter`] removes when it starts a new run.

use std::fs::{self, File, OpenOptions};
use std::io::Write;
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

use crate::OutputError;

/// Distinguishes temporary files of concurrent writes from one process.
static TEMPORARY_COUNTER: AtomicU64 = AtomicU64::new(0);

/// Marker between the target name and the unique suffix of a temporary file name.
const TEMPORARY_MARKER: &str = ".tmp";

/// Writes `contents` to `path` atomically: temporary file in the same directory, write, flush,
/// `sync_all`, rename over `path`.
///
/// The directory must exist. On success no temporary file is left behind; on failure the temporary file
/// is removed and `path` is untouched.
///
/// # Errors
/// [`OutputError::NotAFilePath`] if `path` has no file name; [`OutputError::Io`] naming `path` if the
/// temporary file cannot be created, written or synced, or the rename fails (e.g. missing directory).
pub fn write_atomic(path: &Path, contents: &[u8]) -> Result<(), OutputError> {
    let file_name = path.file_name().ok_or_else(|| OutputError::NotAFilePath {
        path: path.to_path_buf(),
    })?;
    let dir = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    let n = TEMPORARY_COUNTER.fetch_add(1, Ordering::Relaxed);
    let tmp_name = format!(
        ".{}{TEMPORARY_MARKER}{}-{n}",
        file_name.to_string_lossy(),
        std::process::id()
    );
    let tmp_path = dir.join(tmp_name);

    let result = write_synced(&tmp_path, contents, path).and_then(|()| {
        fs::rename(&tmp_path, path).map_err(|source| OutputError::Io {
            operation: "rename a temporary file onto",
            path: path.to_path_buf(),
            source,
        })
    });
    if result.is_err() {
        // The temporary file may or may not exist depending on where the failure happened; either way
        // it must not stay behind, and the original error is the one worth reporting.
        let _ = fs::remove_file(&tmp_path);
        return result;
    }
    sync_directory(dir);
    Ok(())
}

/// Creates `tmp_path` (which must not exist), writes `contents`, flushes and syncs it. Errors name `target`.
fn write_synced(tmp_path: &Path, contents: &[u8], target: &Path) -> Result<(), OutputError> {
    let io_error = |operation: &'static str| {
        move |source| OutputError::Io {
            operation,
            path: target.to_path_buf(),
            source,
        }
    };
    let mut file: File = OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(tmp_path)
        .map_err(io_error("create a temporary file for"))?;
    file.write_all(contents).map_err(io_error("write a temporary file for"))?;
    file.flush().map_err(io_error("flush a temporary file for"))?;
    file.sync_all().map_err(io_error("sync a temporary file for"))?;
    Ok(())
}

/// Makes the rename durable by syncing the directory entry (POSIX). Some file systems refuse to sync a
/// directory; the rename itself has already happened atomically, so this step is best effort.
fn sync_directory(dir: &Path) {
    if let Ok(handle) = File::open(dir) {
        let _ = handle.sync_all();
    }
}

/// If `file_name` is a temporary file name made by [`write_atomic`], the name of its target.
pub(crate) fn temporary_target(file_name: &str) -> Option<&str> {
    let rest = file_name.strip_prefix('.')?;
    let marker = rest.rfind(TEMPORARY_MARKER)?;
    let (target, suffix) = rest.split_at(marker);
    let suffix = &suffix[TEMPORARY_MARKER.len()..];
    let (pid, n) = suffix.split_once('-')?;
    let all_digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    (!target.is_empty() && all_digits(pid) && all_digits(n)).then_some(target)
}

/// Removes `path` if it exists.
///
/// # Errors
/// [`OutputError::Io`] naming `path` for any failure other than "not found".
pub(crate) fn remove_if_exists(path: &Path) -> Result<(), OutputError> {
    match fs::remove_file(path) {
        Ok(()) => Ok(()),
        Err(source) if source.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(source) => Err(OutputError::Io {
            operation: "remove",
            path: path.to_path_buf(),
            source,
        }),
    }
}

/// Creates `dir` and its parents.
///
/// # Errors
/// [`OutputError::Io`] naming `dir`.
pub(crate) fn create_dir_all(dir: &Path) -> Result<(), OutputError> {
    fs::create_dir_all(dir).map_err(|source| OutputError::Io {
        operation: "create the directory",
        path: dir.to_path_buf(),
        source,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn temporary_names_are_recognised() {
        assert_eq!(temporary_target(".frame_00001.vtu.tmp123-4"), Some("frame_00001.vtu"));
        assert_eq!(temporary_target(".summary.json.tmp1-0"), Some("summary.json"));
        // A target name that itself contains the marker keeps it.
        assert_eq!(temporary_target(".a.tmp.tmp77-12"), Some("a.tmp"));
        assert_eq!(temporary_target("summary.json.tmp1-0"), None);
        assert_eq!(temporary_target(".summary.json"), None);
        assert_eq!(temporary_target(".summary.json.tmp1-"), None);
        assert_eq!(temporary_target(".summary.json.tmpx-1"), None);
        assert_eq!(temporary_target("..tmp1-1"), None);
    }

    #[test]
    fn generated_temporary_name_round_trips() {
        let name = format!(".{}{TEMPORARY_MARKER}{}-{}", "probes.csv", std::process::id(), 42);
        assert_eq!(temporary_target(&name), Some("probes.csv"));
    }
}
