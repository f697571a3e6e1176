//! The error type of the output layer.
//!
//! Every variant names what failed: the file (`path`), the data array, the frame, the probe column or the
//! summary field, so that a message alone is enough to find the culprit. Invalid data is refused before
//! anything is written, so an error never leaves a partial file behind.

use std::path::PathBuf;

use thiserror::Error;

/// A run output that could not be written or read back.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum OutputError {
    /// An operating-system call on a file or directory failed.
    #[error("cannot {operation} `{}`: {source}", path.display())]
    Io {
        /// What was being done, e.g. "create a temporary file for".
        operation: &'static str,
        /// The file or directory concerned (for atomic writes, the final target).
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// A path that cannot be a file target (it has no file name, e.g. `..` or `/`).
    #[error("`{}` does not name a file", path.display())]
    NotAFilePath {
        /// The offending path.
        path: PathBuf,
    },
    /// A data array holds NaN or an infinity; output files never contain non-finite numbers.
    #[error("array `{array}` has the non-finite value {value} at tuple {tuple}, component {component}")]
    NonFiniteValue {
        /// Name of the array (`Points` for the coordinates, `TimeValue` for the frame time).
        array: String,
        /// Index of the tuple (point or cell) holding the value.
        tuple: usize,
        /// Component within the tuple.
        component: usize,
        /// The refused value.
        value: f64,
    },
    /// A data array whose length does not match its number of components times the number of points or
    /// cells it is attached to.
    #[error("array `{array}` has {found} values, expected {expected}")]
    ArrayLength {
        /// Name of the array.
        array: String,
        /// Required number of values.
        expected: usize,
        /// Number of values present.
        found: usize,
    },
    /// A data array that declares zero components per tuple.
    #[error("array `{array}` declares zero components per tuple")]
    ZeroComponents {
        /// Name of the array.
        array: String,
    },
    /// A triangle refers to a point that does not exist.
    #[error("triangle {triangle} refers to point {point}, but the frame has {n_points} points")]
    PointIndexOutOfRange {
        /// Index of the triangle.
        triangle: usize,
        /// The offending point index.
        point: usize,
        /// Number of points of the frame.
        n_points: usize,
    },
    /// A name (data array, probe column) that cannot be written as given.
    #[error("invalid {what} name `{name}`: {reason}")]
    InvalidName {
        /// What kind of name, e.g. "point data array" or "probe column".
        what: &'static str,
        /// The offending name.
        name: String,
        /// Why it is refused.
        reason: &'static str,
    },
    /// Two arrays or columns of the same kind share a name.
    #[error("duplicate {what} name `{name}`")]
    DuplicateName {
        /// What kind of name, e.g. "cell data array" or "probe column".
        what: &'static str,
        /// The repeated name.
        name: String,
    },
    /// A frame time that does not come strictly after the previous frame's time.
    #[error("frame {frame_idx} has time {time}, which is not after the previous frame time {previous}")]
    FrameTimeNotIncreasing {
        /// Index of the refused frame in the run.
        frame_idx: usize,
        /// Its time.
        time: f64,
        /// Time of the last frame written.
        previous: f64,
    },
    /// A frame whose points or triangles differ from the first frame's, for a format with one
    /// topology per run (USD).
    #[error("frame {frame_idx} changes the mesh topology of `{}`, which holds one topology", path.display())]
    TopologyChanged {
        /// The file.
        path: PathBuf,
        /// Index of the refused frame.
        frame_idx: usize,
    },
    /// A frame index past the end of a `.pvd` collection.
    #[error("frame {frame_idx} requested from `{}`, which lists {n_frames} frames", path.display())]
    FrameIndexOutOfRange {
        /// The requested index.
        frame_idx: usize,
        /// Number of frames in the collection.
        n_frames: usize,
        /// The collection file.
        path: PathBuf,
    },
    /// A file that is not well-formed XML.
    #[error("`{}` is not well-formed XML: {source}", path.display())]
    Xml {
        /// The file.
        path: PathBuf,
        /// The parser's diagnostic (with line and column).
        #[source]
        source: roxmltree::Error,
    },
    /// A well-formed file whose structure is not the one this crate writes (missing element or
    /// attribute, unsupported encoding, inconsistent counts).
    #[error("`{}`: {reason}", path.display())]
    Format {
        /// The file.
        path: PathBuf,
        /// What is wrong, naming the element, attribute or array.
        reason: String,
    },
    /// An inline binary data array whose base64 text cannot be decoded.
    #[error("`{}`: array `{array}` holds invalid base64 data: {source}", path.display())]
    Base64 {
        /// The file.
        path: PathBuf,
        /// Name of the array.
        array: String,
        /// The decoder's diagnostic.
        #[source]
        source: base64::DecodeError,
    },
    /// A file that parsed but holds an invalid frame (non-finite value, bad index, wrong length).
    #[error("`{}` holds an invalid frame: {source}", path.display())]
    InvalidFrame {
        /// The file.
        path: PathBuf,
        /// The validation failure.
        #[source]
        source: Box<OutputError>,
    },
    /// A summary that serde_json cannot encode or a summary file it cannot decode.
    #[error("summary JSON `{}`: {source}", path.display())]
    Json {
        /// The summary file.
        path: PathBuf,
        /// The serde_json diagnostic.
        #[source]
        source: serde_json::Error,
    },
    /// A summary field holding NaN or an infinity (JSON would silently turn it into `null`).
    #[error("summary field `{field}` is not finite ({value})")]
    NonFiniteSummary {
        /// Name of the field, with the index for arrays (e.g. `rest_bbox.min[2]`).
        field: String,
        /// The refused value.
        value: f64,
    },
    /// A probe row whose number of values differs from the number of declared columns.
    #[error("probe row {row} has {found} values, but {expected} columns were declared")]
    ProbeRowLength {
        /// Index of the refused row (0 for the first data row).
        row: usize,
        /// Number of declared probe columns (without `t`).
        expected: usize,
        /// Number of values given.
        found: usize,
    },
    /// A probe value holding NaN or an infinity.
    #[error("probe column `{column}` has the non-finite value {value} in row {row}")]
    NonFiniteProbe {
        /// The column (`t` for the time).
        column: String,
        /// Index of the refused row (0 for the first data row).
        row: usize,
        /// The refused value.
        value: f64,
    },
    /// An output folder that another run or resume is writing into.
    #[error(
        "`{}` is in use by another run writing into it; wait until that run ends or choose another output folder",
        path.display()
    )]
    InUse {
        /// The output folder.
        path: PathBuf,
    },
    /// A failure-only summary requested with the status `ok`.
    #[error("a failure summary needs the status \"error\" or \"interrupted\", not \"ok\"")]
    NotAFailure,
}
