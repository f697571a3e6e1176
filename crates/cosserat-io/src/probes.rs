//! `probes.csv`: one row per output time with the values of the scene's probes.
//!
//! The header `t,<probe>.<component>,...` is fixed when the writer is created and written atomically;
//! rows are then appended. Each row is formatted completely in memory and handed to the operating system
//! in one `write_all` followed by a flush, and rows are refused before anything is written if they have
//! the wrong length or a non-finite value, so an interrupted run never leaves half a row or a `NaN`.
//! Numbers are written with the shortest text that reads back to the same `f64`.

use std::collections::HashSet;
use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};

use crate::OutputError;
use crate::atomic::write_atomic;
use cosserat_geometry::Num;

/// Name of the time column.
pub const TIME_COLUMN: &str = "t";

/// Why `column` cannot name a probe column, if it cannot.
fn column_problem(column: &str) -> Option<&'static str> {
    let Some((probe, component)) = column.rsplit_once('.') else {
        return Some("expected the form <probe>.<component>");
    };
    if probe.is_empty() || component.is_empty() {
        Some("probe and component must both be non-empty")
    } else if column
        .chars()
        .any(|c| c == ',' || c == '"' || c.is_whitespace() || c.is_control())
    {
        Some("commas, quotes, white space and control characters are not allowed")
    } else {
        None
    }
}

/// Why `line` cannot be a row this writer wrote with `n_values` values (the time included), if it
/// cannot: a resumed run keeps the earlier run's rows, which must still read as numbers.
fn row_problem(line: &str, n_values: usize) -> Option<String> {
    let fields: Vec<&str> = line.trim_end_matches('\n').split(',').collect();
    if fields.len() != n_values {
        return Some(format!("{} values where the header names {n_values}", fields.len()));
    }
    fields
        .iter()
        .find(|f| !f.parse::<f64>().is_ok_and(f64::is_finite))
        .map(|f| format!("`{f}` is not a finite number"))
}

/// Refuses malformed or repeated probe column names.
pub(crate) fn check_columns<S: AsRef<str>>(columns: &[S]) -> Result<(), OutputError> {
    let mut seen = HashSet::new();
    for column in columns.iter().map(AsRef::as_ref) {
        if let Some(reason) = column_problem(column) {
            return Err(OutputError::InvalidName {
                what: "probe column",
                name: column.to_owned(),
                reason,
            });
        }
        if !seen.insert(column) {
            return Err(OutputError::DuplicateName {
                what: "probe column",
                name: column.to_owned(),
            });
        }
    }
    Ok(())
}

/// Appends rows to a probes CSV file.
#[derive(Debug)]
pub struct ProbeWriter {
    path: PathBuf,
    file: File,
    columns: Vec<String>,
    n_rows: usize,
}

impl ProbeWriter {
    /// Creates (or replaces) the file at `path` with the header `t,<columns...>`.
    ///
    /// # Errors
    /// [`OutputError::InvalidName`] for a column not of the form `<probe>.<component>` or containing
    /// commas, quotes or white space, [`OutputError::DuplicateName`] for a repeated column, and I/O errors
    /// naming `path`.
    pub fn create<S: AsRef<str>>(path: &Path, columns: &[S]) -> Result<Self, OutputError> {
        check_columns(columns)?;
        let columns: Vec<String> = columns.iter().map(|c| c.as_ref().to_owned()).collect();
        let mut header = String::from(TIME_COLUMN);
        for column in &columns {
            header.push(',');
            header.push_str(column);
        }
        header.push('\n');
        write_atomic(path, header.as_bytes())?;
        let file = OpenOptions::new().append(true).open(path).map_err(|source| OutputError::Io {
            operation: "open for appending",
            path: path.to_path_buf(),
            source,
        })?;
        Ok(Self {
            path: path.to_path_buf(),
            file,
            columns,
            n_rows: 0,
        })
    }

    /// Reopens the file of an earlier run at `path` for appending after its first `n_rows` rows (a run
    /// resumed from a checkpoint): the rows after them, written by the earlier run after its last
    /// checkpoint, are removed (the resumed run writes them again).
    ///
    /// # Errors
    /// The errors of [`ProbeWriter::keep`] and I/O errors naming the file.
    pub fn reopen<S: AsRef<str>>(path: &Path, columns: &[S], n_rows: usize) -> Result<Self, OutputError> {
        Self::keep(path, columns, n_rows)?.reopen()
    }

    /// Reads and checks the file of an earlier run at `path` and its first `n_rows` rows, without
    /// changing it: [`KeptProbes::reopen`] then cuts it there.
    ///
    /// # Errors
    /// The column errors of [`ProbeWriter::create`]; [`OutputError::Format`] when the header does not
    /// name these columns, the file has fewer rows or one of them is not a row of numbers of the
    /// header's length; I/O errors naming the file.
    pub fn keep<S: AsRef<str>>(path: &Path, columns: &[S], n_rows: usize) -> Result<KeptProbes, OutputError> {
        check_columns(columns)?;
        let text = std::fs::read_to_string(path).map_err(|source| OutputError::Io {
            operation: "read",
            path: path.to_path_buf(),
            source,
        })?;
        let columns: Vec<String> = columns.iter().map(|c| c.as_ref().to_owned()).collect();
        let header = std::iter::once(TIME_COLUMN.to_owned())
            .chain(columns.iter().cloned())
            .collect::<Vec<_>>()
            .join(",");
        let mut lines = text.split_inclusive('\n');
        if lines.next().map(|l| l.trim_end_matches('\n')) != Some(header.as_str()) {
            return Err(OutputError::Format {
                path: path.to_path_buf(),
                reason: format!("the header is not `{header}`: the file belongs to another run"),
            });
        }
        let kept: Vec<&str> = lines.take(n_rows).filter(|l| l.ends_with('\n')).collect();
        if kept.len() < n_rows {
            return Err(OutputError::Format {
                path: path.to_path_buf(),
                reason: format!("holds {} complete rows, the checkpoint expects {n_rows}", kept.len()),
            });
        }
        if let Some((row, reason)) = kept
            .iter()
            .enumerate()
            .find_map(|(k, l)| row_problem(l, columns.len() + 1).map(|r| (k, r)))
        {
            return Err(OutputError::Format {
                path: path.to_path_buf(),
                reason: format!("row {row} (line {}) is damaged: {reason}", row + 2),
            });
        }
        Ok(KeptProbes {
            path: path.to_path_buf(),
            contents: format!("{header}\n{}", kept.concat()),
            columns,
            n_rows,
        })
    }

    /// The probe columns, without `t`.
    pub fn columns(&self) -> &[String] {
        &self.columns
    }

    /// Number of data rows written so far.
    pub fn n_rows(&self) -> usize {
        self.n_rows
    }

    /// Path of the file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Appends the row `t, values...`, one value per declared column.
    ///
    /// # Errors
    /// [`OutputError::ProbeRowLength`] if `values` does not match the columns, [`OutputError::NonFiniteProbe`]
    /// naming the column of a NaN or infinity (then nothing is written), and I/O errors naming the file.
    pub fn write_row(&mut self, t: f64, values: &[f64]) -> Result<(), OutputError> {
        let row = self.n_rows;
        if values.len() != self.columns.len() {
            return Err(OutputError::ProbeRowLength {
                row,
                expected: self.columns.len(),
                found: values.len(),
            });
        }
        let named = std::iter::once((TIME_COLUMN, t))
            .chain(self.columns.iter().map(String::as_str).zip(values.iter().copied()));
        let mut line = String::new();
        for (idx, (column, value)) in named.enumerate() {
            if !value.is_finite() {
                return Err(OutputError::NonFiniteProbe {
                    column: column.to_owned(),
                    row,
                    value,
                });
            }
            if idx > 0 {
                line.push(',');
            }
            line.push_str(&Num(value).to_string());
        }
        line.push('\n');
        let Self { path, file, .. } = self;
        let path = &*path;
        let io_error = |operation| {
            move |source| OutputError::Io {
                operation,
                path: path.clone(),
                source,
            }
        };
        file.write_all(line.as_bytes()).map_err(io_error("append a row to"))?;
        file.flush().map_err(io_error("flush"))?;
        self.n_rows += 1;
        Ok(())
    }
}

/// The probes file of an earlier run, checked by [`ProbeWriter::keep`] and not yet changed.
#[derive(Debug)]
pub struct KeptProbes {
    path: PathBuf,
    contents: String,
    columns: Vec<String>,
    n_rows: usize,
}

impl KeptProbes {
    /// Cuts the file after the kept rows and opens it for appending.
    ///
    /// # Errors
    /// I/O errors naming the file.
    pub fn reopen(self) -> Result<ProbeWriter, OutputError> {
        write_atomic(&self.path, self.contents.as_bytes())?;
        let file = OpenOptions::new()
            .append(true)
            .open(&self.path)
            .map_err(|source| OutputError::Io {
                operation: "open for appending",
                path: self.path.clone(),
                source,
            })?;
        Ok(ProbeWriter {
            path: self.path,
            file,
            columns: self.columns,
            n_rows: self.n_rows,
        })
    }
}
