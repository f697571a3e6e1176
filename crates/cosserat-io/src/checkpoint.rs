//! The checkpoint container: a versioned little-endian binary file whose numbers keep their exact bit
//! patterns, so that a run resumed from it continues bit for bit like a run that was never stopped.
//!
//! Layout: the magic `COSSERAT-CHECKPOINT\n`, the format version (`u32`), the payload, and the CRC-32
//! of everything before it (`u32`). The payload is written by an [`Encoder`] and read back in the same
//! order by a [`Decoder`]: integers as `u64`, floats as the `u64` of their bits, strings and arrays with
//! their length first. A file that is truncated, altered or of another version is refused with an
//! error naming the file and the reason, never read halfway.

use std::path::{Path, PathBuf};

use crate::OutputError;
use crate::atomic::write_atomic;

/// The first bytes of every checkpoint file.
const MAGIC: &[u8] = b"COSSERAT-CHECKPOINT\n";

/// The version of the layout this build writes and reads.
pub const CHECKPOINT_VERSION: u32 = 8;

/// The CRC-32 of `bytes`: the fingerprint a checkpoint keeps of its scene, to refuse resuming with
/// another one.
pub fn fingerprint(bytes: &[u8]) -> u32 {
    crc32fast::hash(bytes)
}

/// Builds a checkpoint's payload.
#[derive(Debug)]
pub struct Encoder {
    bytes: Vec<u8>,
}

impl Default for Encoder {
    fn default() -> Self {
        Self::new()
    }
}

impl Encoder {
    /// An empty payload after the header.
    pub fn new() -> Self {
        let mut bytes = MAGIC.to_vec();
        bytes.extend_from_slice(&CHECKPOINT_VERSION.to_le_bytes());
        Self { bytes }
    }

    /// Appends an unsigned integer.
    pub fn usize(&mut self, value: usize) {
        self.bytes.extend_from_slice(&(value as u64).to_le_bytes());
    }

    /// Appends a flag.
    pub fn bool(&mut self, value: bool) {
        self.usize(usize::from(value));
    }

    /// Appends a float with its exact bits.
    pub fn f64(&mut self, value: f64) {
        self.bytes.extend_from_slice(&value.to_bits().to_le_bytes());
    }

    /// Appends floats, their number first.
    pub fn f64s(&mut self, values: &[f64]) {
        self.usize(values.len());
        for &v in values {
            self.f64(v);
        }
    }

    /// Appends integers, their number first.
    pub fn usizes(&mut self, values: &[usize]) {
        self.usize(values.len());
        for &v in values {
            self.usize(v);
        }
    }

    /// Appends a UTF-8 string, its length first.
    pub fn str(&mut self, value: &str) {
        self.usize(value.len());
        self.bytes.extend_from_slice(value.as_bytes());
    }

    /// Writes header, payload and checksum to `path` atomically (temporary file in the same
    /// directory, `fsync`, rename): a crash leaves the previous checkpoint or the new one, never a
    /// mixture. Returns the size in bytes.
    ///
    /// # Errors
    /// I/O errors naming the path.
    pub fn write(mut self, path: &Path) -> Result<usize, OutputError> {
        let crc = crc32fast::hash(&self.bytes);
        self.bytes.extend_from_slice(&crc.to_le_bytes());
        write_atomic(path, &self.bytes)?;
        Ok(self.bytes.len())
    }
}

/// Reads a checkpoint's payload in the order it was written.
#[derive(Debug)]
pub struct Decoder {
    path: PathBuf,
    bytes: Vec<u8>,
    at: usize,
}

impl Decoder {
    /// Opens `path` and checks its header, version and checksum.
    ///
    /// # Errors
    /// [`OutputError::Io`] for a missing or unreadable file; [`OutputError::Format`] for a file that is
    /// not a checkpoint, of another version, truncated or altered.
    pub fn open(path: &Path) -> Result<Self, OutputError> {
        let bytes = std::fs::read(path).map_err(|source| OutputError::Io {
            operation: "read",
            path: path.to_path_buf(),
            source,
        })?;
        let format = |reason: String| OutputError::Format {
            path: path.to_path_buf(),
            reason,
        };
        if !bytes.starts_with(MAGIC) {
            return Err(format("not a checkpoint file (its header is missing)".into()));
        }
        let body_start = MAGIC.len() + 4;
        if bytes.len() < body_start + 4 {
            return Err(format(format!("truncated ({} bytes)", bytes.len())));
        }
        let version = u32::from_le_bytes(bytes[MAGIC.len()..body_start].try_into().unwrap_or_default());
        if version != CHECKPOINT_VERSION {
            return Err(format(format!(
                "checkpoint format version {version}, but this build reads version {CHECKPOINT_VERSION}"
            )));
        }
        let (content, trailer) = bytes.split_at(bytes.len() - 4);
        let stored = u32::from_le_bytes(trailer.try_into().unwrap_or_default());
        if crc32fast::hash(content) != stored {
            return Err(format(
                "the checksum does not match: the file is truncated or damaged".into(),
            ));
        }
        let mut bytes = bytes;
        bytes.truncate(bytes.len() - 4);
        Ok(Self {
            path: path.to_path_buf(),
            bytes,
            at: body_start,
        })
    }

    /// The file read.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// An error about this file.
    pub fn error(&self, reason: impl Into<String>) -> OutputError {
        OutputError::Format {
            path: self.path.clone(),
            reason: reason.into(),
        }
    }

    fn word(&mut self) -> Result<u64, OutputError> {
        let end = self.at + 8;
        let Some(chunk) = self.bytes.get(self.at..end) else {
            return Err(self.error(format!("the payload ends early, at byte {}", self.at)));
        };
        self.at = end;
        Ok(u64::from_le_bytes(chunk.try_into().unwrap_or_default()))
    }

    /// Reads an unsigned integer.
    ///
    /// # Errors
    /// [`OutputError::Format`] when the payload ends or the value does not fit.
    pub fn usize(&mut self) -> Result<usize, OutputError> {
        let w = self.word()?;
        usize::try_from(w).map_err(|_| self.error(format!("the count {w} does not fit this machine")))
    }

    /// Reads a flag.
    ///
    /// # Errors
    /// [`OutputError::Format`] when the payload ends or the value is neither 0 nor 1.
    pub fn bool(&mut self) -> Result<bool, OutputError> {
        match self.word()? {
            0 => Ok(false),
            1 => Ok(true),
            w => Err(self.error(format!("a flag holds {w}"))),
        }
    }

    /// Reads a float.
    ///
    /// # Errors
    /// [`OutputError::Format`] when the payload ends.
    pub fn f64(&mut self) -> Result<f64, OutputError> {
        self.word().map(f64::from_bits)
    }

    /// A length that the rest of the payload can hold (`size` bytes per item).
    fn length(&mut self, size: usize) -> Result<usize, OutputError> {
        let n = self.usize()?;
        let left = self.bytes.len() - self.at;
        if n.checked_mul(size).is_none_or(|b| b > left) {
            return Err(self.error(format!("a list of {n} items is longer than the {left} bytes left")));
        }
        Ok(n)
    }

    /// Reads floats.
    ///
    /// # Errors
    /// [`OutputError::Format`] when the payload ends.
    pub fn f64s(&mut self) -> Result<Vec<f64>, OutputError> {
        let n = self.length(8)?;
        (0..n).map(|_| self.f64()).collect()
    }

    /// Reads integers.
    ///
    /// # Errors
    /// [`OutputError::Format`] when the payload ends.
    pub fn usizes(&mut self) -> Result<Vec<usize>, OutputError> {
        let n = self.length(8)?;
        (0..n).map(|_| self.usize()).collect()
    }

    /// Reads a string.
    ///
    /// # Errors
    /// [`OutputError::Format`] when the payload ends or the bytes are not UTF-8.
    pub fn string(&mut self) -> Result<String, OutputError> {
        let n = self.length(1)?;
        let bytes = self.bytes[self.at..self.at + n].to_vec();
        self.at += n;
        String::from_utf8(bytes).map_err(|_| self.error("a string is not UTF-8"))
    }

    /// Checks that the whole payload was read.
    ///
    /// # Errors
    /// [`OutputError::Format`] when bytes are left over.
    pub fn finish(self) -> Result<(), OutputError> {
        if self.at == self.bytes.len() {
            Ok(())
        } else {
            Err(self.error(format!(
                "{} bytes are left after the state was read",
                self.bytes.len() - self.at
            )))
        }
    }
}
