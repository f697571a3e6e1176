//! [`RunWriter`]: the owner of a run's output directory.
//!
//! Layout of `DIR` (the output contract):
//!
//! | file | written |
//! |---|---|
//! | `DIR/frames/frame_00000.vtu`, `frame_00001.vtu`, ... | one per [`RunWriter::write_frame`], atomically |
//! | `DIR/frames/run.pvd` | rewritten atomically after every frame; lists the frames relative to `frames/` |
//! | `DIR/frames/frame_00000.obj`, `.ply` | with [`FrameFormats::obj`] and [`FrameFormats::ply`], one per frame, atomically |
//! | `DIR/frames/run.usda` | with [`FrameFormats::usd`], assembled by [`RunWriter::finish`] ([`crate::mesh_frames`]) |
//! | `DIR/probes.csv` | header at creation, one row per [`RunWriter::write_probes`] |
//! | `DIR/summary.json` | at the end, by [`RunWriter::finish`] (every run that started, whatever its status) or [`write_failure_summary`] (a run that could not start) |
//!
//! The collection lives next to the frames so that the frames directory is self-contained: it can be
//! moved or archived and still opens in ParaView. Frame numbers have five digits and simply grow wider
//! past 99 999 frames; the `.pvd` keeps the order either way.
//!
//! Starting a run removes what an earlier run left in `DIR`: the files above and the temporary files of
//! interrupted atomic writes; resuming one removes those temporary files. Nothing else in `DIR` is
//! touched. A run that ends early (an error, an
//! interrupt) keeps every frame and probe row written before, and the collection lists exactly the
//! frames that exist.

use std::fs;
use std::path::{Path, PathBuf};

use crate::OutputError;
use crate::atomic::{create_dir_all, remove_if_exists, temporary_target};
use crate::mesh_frames::{FrameFormats, UsdWriter, write_obj, write_ply};
use crate::probes::{ProbeWriter, check_columns};
use crate::pvd::{PvdEntry, write_pvd};
use crate::summary::{RunStatus, RunSummary, write_summary};
use crate::vtu::{VtuFrame, write_vtu};

/// Name of the summary file in `DIR`.
pub const SUMMARY_FILE: &str = "summary.json";
/// Name of the probes file in `DIR`.
pub const PROBES_FILE: &str = "probes.csv";
/// Name of the frames directory in `DIR`.
pub const FRAMES_DIR: &str = "frames";
/// Name of the `.pvd` collection inside the frames directory.
pub const PVD_FILE: &str = "run.pvd";

/// Name of the USD stage inside the frames directory.
pub const USD_FILE: &str = "run.usda";

/// File name of frame `frame_idx`: `frame_00000.vtu`, `frame_00001.vtu`, ...
pub fn frame_file_name(frame_idx: usize) -> String {
    format!("frame_{frame_idx:05}.vtu")
}

/// Whether `name` is a frame file name as made by [`frame_file_name`] (or its `.obj` and `.ply`
/// siblings).
fn is_frame_file_name(name: &str) -> bool {
    name.strip_prefix("frame_")
        .and_then(|rest| [".vtu", ".obj", ".ply"].iter().find_map(|ext| rest.strip_suffix(ext)))
        .is_some_and(|digits| digits.len() >= 5 && digits.bytes().all(|b| b.is_ascii_digit()))
}

/// Whether `name` is a file this module writes into `DIR` (`in_frames == false`) or `DIR/frames`.
fn is_run_file(name: &str, in_frames: bool) -> bool {
    if in_frames {
        name == PVD_FILE
            || name == USD_FILE
            || name.starts_with(&format!(".{USD_FILE}.part"))
            || is_frame_file_name(name)
    } else {
        name == SUMMARY_FILE || name == PROBES_FILE
    }
}

/// The entries of `dir`, or `None` where it does not exist.
fn entries_of(dir: &Path) -> Result<Option<fs::ReadDir>, OutputError> {
    match fs::read_dir(dir) {
        Ok(entries) => Ok(Some(entries)),
        Err(source) if source.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(source) => Err(OutputError::Io {
            operation: "list",
            path: dir.to_path_buf(),
            source,
        }),
    }
}

/// Removes from `dir` the files a run writes there, including leftover temporary files of atomic writes.
fn remove_run_files(dir: &Path, in_frames: bool) -> Result<(), OutputError> {
    let Some(entries) = entries_of(dir)? else {
        return Ok(());
    };
    for entry in entries {
        let entry = entry.map_err(|source| OutputError::Io {
            operation: "list",
            path: dir.to_path_buf(),
            source,
        })?;
        let name = entry.file_name();
        let Some(name) = name.to_str() else { continue };
        let target = temporary_target(name).unwrap_or(name);
        let is_file = entry.file_type().is_ok_and(|kind| kind.is_file());
        if is_file && is_run_file(target, in_frames) {
            remove_if_exists(&entry.path())?;
        }
    }
    Ok(())
}

/// Removes the frame files numbered `first` and up from `frames_dir`.
fn remove_frames_from(frames_dir: &Path, first: usize) -> Result<(), OutputError> {
    let Some(entries) = entries_of(frames_dir)? else {
        return create_dir_all(frames_dir);
    };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(name) = name.to_str() else { continue };
        let index = name
            .strip_prefix("frame_")
            .and_then(|rest| rest.split_once('.'))
            .and_then(|(digits, _)| digits.parse::<usize>().ok());
        if is_frame_file_name(name) && index.is_some_and(|k| k >= first) {
            remove_if_exists(&entry.path())?;
        }
    }
    Ok(())
}

/// Locks `dir` for one run, so that a second run into it is refused instead of mixing its rows and
/// frames into the first's. The lock is the operating system's advisory lock on the folder itself: it
/// leaves no file behind and goes with the process, however that ends. A file system without such
/// locks, or a system that does not open folders as files (Windows), gets no lock.
///
/// # Errors
/// [`OutputError::InUse`] when another process holds the lock.
fn lock_dir(dir: &Path) -> Result<Option<fs::File>, OutputError> {
    // A folder that cannot be opened here is reported by the writes into it, with their own path.
    let Ok(folder) = fs::File::open(dir) else {
        return Ok(None);
    };
    match folder.try_lock() {
        Ok(()) => Ok(Some(folder)),
        Err(fs::TryLockError::WouldBlock) => Err(OutputError::InUse {
            path: dir.to_path_buf(),
        }),
        Err(fs::TryLockError::Error(_)) => Ok(None),
    }
}

/// Removes from `dir` the temporary files of atomic writes that a killed process left there (hidden,
/// `.<name>.tmp<pid>-<n>`): a run that takes over `dir` owns them, and nobody else renames them.
///
/// # Errors
/// [`OutputError::Io`] naming the directory that cannot be listed or the file that cannot be removed.
pub fn remove_temporaries(dir: &Path) -> Result<(), OutputError> {
    let Some(entries) = entries_of(dir)? else {
        return Ok(());
    };
    for entry in entries.flatten() {
        let is_file = entry.file_type().is_ok_and(|kind| kind.is_file());
        if is_file && entry.file_name().to_str().and_then(temporary_target).is_some() {
            remove_if_exists(&entry.path())?;
        }
    }
    Ok(())
}

/// Refuses frames of a checkpoint of which a file is missing in one of the per-frame `formats`, or
/// whose VTU file is cut short or overwritten.
fn check_kept_frames(frames_dir: &Path, frames: &[PvdEntry], formats: FrameFormats) -> Result<(), OutputError> {
    let extensions = [(formats.vtu, "vtu"), (formats.obj, "obj"), (formats.ply, "ply")];
    let files = frames.iter().flat_map(|f| {
        extensions
            .iter()
            .filter(|(on, _)| *on)
            .map(|(_, extension)| frames_dir.join(&f.file).with_extension(extension))
    });
    for path in files {
        let reason = if !path.is_file() {
            "the frame is missing, but the checkpoint counts it"
        } else if path.extension().is_some_and(|e| e == "vtu") && !ends_like_vtu(&path) {
            "the frame is damaged (it does not end with `</VTKFile>`), but the checkpoint counts it"
        } else {
            continue;
        };
        return Err(OutputError::Format {
            path,
            reason: reason.into(),
        });
    }
    Ok(())
}

/// Whether the file at `path` ends as every VTU file this crate writes does. Only the end is read: a
/// resume checks every kept frame, and a cut or overwritten file seldom keeps the closing tag.
fn ends_like_vtu(path: &Path) -> bool {
    use std::io::{Read, Seek, SeekFrom};
    const END: &[u8] = b"</VTKFile>\n";
    let Ok(mut file) = fs::File::open(path) else {
        return false;
    };
    let mut tail = [0_u8; END.len()];
    file.seek(SeekFrom::End(-(END.len() as i64)))
        .and_then(|_| file.read_exact(&mut tail))
        .is_ok_and(|()| tail == END)
}

/// Removes everything a run writes into `dir` (frames, collection, probes, summary, temporary files),
/// and the frames directory itself if that leaves it empty. Other files are kept.
///
/// # Errors
/// [`OutputError::Io`] naming the file or directory that could not be listed or removed.
pub fn clear_run_outputs(dir: &Path) -> Result<(), OutputError> {
    let frames_dir = dir.join(FRAMES_DIR);
    remove_run_files(&frames_dir, true)?;
    // A frames directory that still holds files of the user stays; an empty one goes.
    let _ = fs::remove_dir(&frames_dir);
    remove_run_files(dir, false)
}

/// Reports a run that could not start (an invalid scene): writes `dir/summary.json` and touches nothing
/// else. Returns the path of the summary.
///
/// # Errors
/// [`OutputError::NotAFailure`] if the summary's status is `ok`, the errors of
/// [`RunSummary::validate`], and I/O errors naming the path.
pub fn write_failure_summary(dir: &Path, summary: &RunSummary) -> Result<PathBuf, OutputError> {
    if summary.status == RunStatus::Ok {
        return Err(OutputError::NotAFailure);
    }
    summary.validate()?;
    create_dir_all(dir)?;
    let path = dir.join(SUMMARY_FILE);
    write_summary(&path, summary)?;
    Ok(path)
}

/// Writes the outputs of one run into its directory.
#[derive(Debug)]
pub struct RunWriter {
    dir: PathBuf,
    frames: Vec<PvdEntry>,
    probes: ProbeWriter,
    formats: FrameFormats,
    usd: Option<UsdWriter>,
    /// Held while the writer lives ([`lock_dir`]).
    _lock: Option<fs::File>,
}

impl RunWriter {
    /// Prepares `dir` for a new run: creates `dir` and `dir/frames`, removes the outputs of an earlier
    /// run, and writes the header of `dir/probes.csv` with the given columns (`<probe>.<component>`; an
    /// empty list gives a file with the time column only).
    ///
    /// # Errors
    /// The column errors of [`ProbeWriter::create`] (checked before anything is removed),
    /// [`OutputError::InUse`] when another run writes into `dir` (nothing is removed then either), and
    /// I/O errors naming the path.
    pub fn create<S: AsRef<str>>(dir: impl Into<PathBuf>, probe_columns: &[S]) -> Result<Self, OutputError> {
        let dir = dir.into();
        // Bad columns are refused before anything is removed, so an earlier run stays intact.
        check_columns(probe_columns)?;
        create_dir_all(&dir)?;
        let lock = lock_dir(&dir)?;
        clear_run_outputs(&dir)?;
        create_dir_all(&dir.join(FRAMES_DIR))?;
        let probes = ProbeWriter::create(&dir.join(PROBES_FILE), probe_columns)?;
        Ok(Self {
            dir,
            frames: Vec::new(),
            probes,
            formats: FrameFormats::default(),
            usd: None,
            _lock: lock,
        })
    }

    /// Takes over `dir` of an earlier run to continue it from a checkpoint: keeps the first
    /// `probe_rows` rows of `probes.csv` and the frames of `frame_times` (the collection is rewritten to
    /// list exactly them), and removes the frames the earlier run wrote after them. The resumed run
    /// then writes the later rows and frames again; the earlier run's `summary.json` and the temporary
    /// files of atomic writes that it left when it was killed go. Everything is checked before anything changes: a
    /// refused resume leaves `dir` as it was.
    ///
    /// # Errors
    /// [`OutputError::InUse`] when another run writes into `dir`; the errors of [`ProbeWriter::keep`];
    /// [`OutputError::Format`] for a file of a frame of the
    /// checkpoint that is missing (in any of `formats` written per frame) or a VTU frame that does not
    /// end as one; I/O errors naming the path.
    pub fn resume<S: AsRef<str>>(
        dir: impl Into<PathBuf>,
        probe_columns: &[S],
        probe_rows: usize,
        frame_times: &[f64],
        formats: FrameFormats,
    ) -> Result<Self, OutputError> {
        let dir = dir.into();
        let lock = lock_dir(&dir)?;
        let kept = ProbeWriter::keep(&dir.join(PROBES_FILE), probe_columns, probe_rows)?;
        let frames_dir = dir.join(FRAMES_DIR);
        let frames: Vec<PvdEntry> = frame_times
            .iter()
            .enumerate()
            .map(|(k, &time)| PvdEntry {
                time,
                file: frame_file_name(k),
            })
            .collect();
        check_kept_frames(&frames_dir, &frames, formats)?;
        remove_temporaries(&dir)?;
        remove_temporaries(&frames_dir)?;
        // The collection first: a frames folder where files cannot be removed still lists only the
        // kept frames, and the earlier run's report stays until the rows change.
        if formats.vtu {
            write_pvd(&frames_dir.join(PVD_FILE), &frames)?;
        }
        remove_frames_from(&frames_dir, frames.len())?;
        // The earlier run's report describes rows that change from here on; a resumed run that is
        // killed must not leave it behind, as a killed run leaves no report.
        remove_if_exists(&dir.join(SUMMARY_FILE))?;
        Ok(Self {
            dir,
            frames,
            probes: kept.reopen()?,
            formats,
            usd: None,
            _lock: lock,
        })
    }

    /// Rows written to `probes.csv` so far (a resumed run counts those it kept).
    pub fn probe_rows(&self) -> usize {
        self.probes.n_rows()
    }

    /// Times of the frames written so far (a resumed run counts those it kept).
    pub fn frame_times(&self) -> Vec<f64> {
        self.frames.iter().map(|f| f.time).collect()
    }

    /// Chooses the formats of the frames written from now on (VTU only by default).
    ///
    /// # Errors
    /// I/O errors of creating the USD stage's part files.
    pub fn set_formats(&mut self, formats: FrameFormats) -> Result<(), OutputError> {
        self.formats = formats;
        self.usd = if formats.usd {
            Some(UsdWriter::create(self.frames_dir().join(USD_FILE))?)
        } else {
            None
        };
        Ok(())
    }

    /// The output directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// `DIR/frames`.
    pub fn frames_dir(&self) -> PathBuf {
        self.dir.join(FRAMES_DIR)
    }

    /// `DIR/frames/run.pvd`.
    pub fn pvd_path(&self) -> PathBuf {
        self.frames_dir().join(PVD_FILE)
    }

    /// `DIR/probes.csv`.
    pub fn probes_path(&self) -> &Path {
        self.probes.path()
    }

    /// `DIR/summary.json`.
    pub fn summary_path(&self) -> PathBuf {
        self.dir.join(SUMMARY_FILE)
    }

    /// The frames written so far, as listed in the collection.
    pub fn frames(&self) -> &[PvdEntry] {
        &self.frames
    }

    /// Number of frames written so far.
    pub fn n_frames(&self) -> usize {
        self.frames.len()
    }

    /// Writes `frame` as the next frame file and rewrites the collection. Returns the frame's path.
    ///
    /// # Errors
    /// [`OutputError::FrameTimeNotIncreasing`] if the time is not after the previous frame's, the errors
    /// of [`VtuFrame::validate`] (nothing is written then), and I/O errors naming the path (the files of
    /// the frame that were written before the failure are removed again).
    pub fn write_frame(&mut self, frame: &VtuFrame) -> Result<PathBuf, OutputError> {
        let frame_idx = self.frames.len();
        if let Some(previous) = self.frames.last().map(|entry| entry.time) {
            // A non-finite time is left to validation below, whose error names the array.
            if frame.time.is_finite() && frame.time <= previous {
                return Err(OutputError::FrameTimeNotIncreasing {
                    frame_idx,
                    time: frame.time,
                    previous,
                });
            }
        }
        let file = frame_file_name(frame_idx);
        let path = self.frames_dir().join(&file);
        frame.validate()?;
        if let Err(error) = self.write_frame_files(&path, &file, frame) {
            self.discard_frame_files(&path);
            return Err(error);
        }
        self.frames.push(PvdEntry { time: frame.time, file });
        Ok(path)
    }

    /// Writes every format of the frame at `path` and the collection that lists it. The USD sample
    /// comes last because it cannot be taken back.
    fn write_frame_files(&mut self, path: &Path, file: &str, frame: &VtuFrame) -> Result<(), OutputError> {
        if self.formats.obj {
            write_obj(&path.with_extension("obj"), frame)?;
        }
        if self.formats.ply {
            write_ply(&path.with_extension("ply"), frame)?;
        }
        if self.formats.vtu {
            write_vtu(path, frame)?;
            let mut listed = self.frames.clone();
            listed.push(PvdEntry {
                time: frame.time,
                file: file.to_owned(),
            });
            write_pvd(&self.pvd_path(), &listed)?;
        }
        if let Some(usd) = &mut self.usd {
            usd.append(frame)?;
        }
        Ok(())
    }

    /// Removes what a frame that failed halfway wrote (best effort: the failure itself is the error
    /// worth reporting), so that no file of a frame the collection and the probes do not list stays,
    /// and the collection lists the frames before it again.
    fn discard_frame_files(&self, path: &Path) {
        for extension in ["obj", "ply", "vtu"] {
            let _ = remove_if_exists(&path.with_extension(extension));
        }
        if self.formats.vtu {
            let _ = write_pvd(&self.pvd_path(), &self.frames);
        }
    }

    /// Appends a row to `DIR/probes.csv`: the time `t` and one value per declared column.
    ///
    /// # Errors
    /// The errors of [`ProbeWriter::write_row`].
    pub fn write_probes(&mut self, t: f64, values: &[f64]) -> Result<(), OutputError> {
        self.probes.write_row(t, values)
    }

    /// Ends the run, whatever its status: writes `DIR/summary.json` and keeps every frame and probe row
    /// written. Returns the summary's path.
    ///
    /// # Errors
    /// The errors of [`write_summary`].
    pub fn finish(mut self, summary: &RunSummary) -> Result<PathBuf, OutputError> {
        if let Some(usd) = self.usd.take() {
            usd.finish()?;
        }
        let path = self.summary_path();
        write_summary(&path, summary)?;
        Ok(path)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_names_are_recognised() {
        assert!(is_frame_file_name(&frame_file_name(0)));
        assert!(is_frame_file_name(&frame_file_name(123_456)));
        assert!(!is_frame_file_name("frame_0001.vtu"));
        assert!(!is_frame_file_name("frame_0000a.vtu"));
        assert!(!is_frame_file_name("frame_00001.vtk"));
        assert!(is_run_file(PVD_FILE, true));
        assert!(!is_run_file(PVD_FILE, false));
        assert!(is_run_file(SUMMARY_FILE, false));
        assert!(!is_run_file("notes.txt", false));
    }
}
