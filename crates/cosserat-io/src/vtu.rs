//! Frames of a triangle surface and their VTK XML UnstructuredGrid (`.vtu`) writer.
//!
//! A [`VtuFrame`] is plain data (points, triangles, named point and cell arrays, a time) so that the
//! simulator fills it without this crate knowing any simulation type. The writer produces a file ParaView
//! opens directly:
//!
//! - `VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64"`;
//! - every data array is inline `format="binary"`: base64 of one little-endian `UInt64` byte count
//!   followed by the raw little-endian values, encoded as a single base64 stream (the layout VTK reads
//!   for uncompressed inline data);
//! - coordinates and data arrays are `Float64`, `connectivity` and `offsets` are `Int64`, `types` is
//!   `UInt8` (5, `VTK_TRIANGLE`);
//! - the frame time is the field-data array `TimeValue`, which ParaView shows as the dataset time.
//!
//! Frames are validated before anything is written: no NaN or infinity, consistent lengths, indices in
//! range, valid unique names. Files are written through [`crate::atomic::write_atomic`].

use std::collections::HashSet;
use std::fmt::Write as _;
use std::path::Path;

use base64::Engine as _;
use base64::engine::general_purpose::STANDARD;

use crate::OutputError;
use crate::atomic::write_atomic;

/// VTK cell type code of a linear triangle.
pub const VTK_TRIANGLE: u8 = 5;

/// Name under which the coordinates appear in errors and in the file.
pub const POINTS_ARRAY: &str = "Points";

/// Name of the field-data array holding the frame time (recognised by ParaView).
pub const TIME_ARRAY: &str = "TimeValue";

/// A named array of `f64` tuples attached to the points or the cells of a frame.
#[derive(Debug, Clone, PartialEq)]
pub struct DataArray {
    /// Name shown in ParaView, e.g. `displacement` or `director_1`. Non-empty, without control characters,
    /// unique among the point (or cell) arrays of a frame.
    pub name: String,
    /// Number of components per tuple (1 for a scalar, 3 for a vector).
    pub n_components: usize,
    /// Values, tuple after tuple: `values[tuple * n_components + component]`.
    pub values: Vec<f64>,
}

impl DataArray {
    /// An array of `n_components`-tuples stored flat in `values`.
    pub fn new(name: impl Into<String>, n_components: usize, values: Vec<f64>) -> Self {
        Self {
            name: name.into(),
            n_components,
            values,
        }
    }

    /// A scalar array (one component).
    pub fn scalars(name: impl Into<String>, values: Vec<f64>) -> Self {
        Self::new(name, 1, values)
    }

    /// A 3-vector array.
    pub fn vectors(name: impl Into<String>, vectors: &[[f64; 3]]) -> Self {
        Self::new(name, 3, vectors.iter().flatten().copied().collect())
    }

    /// Number of tuples (`values.len() / n_components`, 0 if `n_components` is 0).
    pub fn n_tuples(&self) -> usize {
        self.values.len().checked_div(self.n_components).unwrap_or(0)
    }

    /// The components of tuple `idx`.
    ///
    /// # Panics
    /// If `idx >= self.n_tuples()`.
    #[track_caller]
    pub fn tuple(&self, idx: usize) -> &[f64] {
        &self.values[idx * self.n_components..(idx + 1) * self.n_components]
    }
}

/// One output frame of a triangle surface.
#[derive(Debug, Clone, PartialEq)]
pub struct VtuFrame {
    /// Point coordinates (length units of the scene).
    pub points: Vec<[f64; 3]>,
    /// Triangles as indices into `points` (counter-clockwise seen from the side the normal points to).
    pub triangles: Vec<[usize; 3]>,
    /// Arrays with one tuple per point.
    pub point_data: Vec<DataArray>,
    /// Arrays with one tuple per triangle.
    pub cell_data: Vec<DataArray>,
    /// Simulation time of the frame (time units of the scene).
    pub time: f64,
}

impl VtuFrame {
    /// A frame without data arrays.
    pub fn new(points: Vec<[f64; 3]>, triangles: Vec<[usize; 3]>, time: f64) -> Self {
        Self {
            points,
            triangles,
            point_data: Vec::new(),
            cell_data: Vec::new(),
            time,
        }
    }

    /// The point data array called `name`, if any.
    pub fn point_array(&self, name: &str) -> Option<&DataArray> {
        self.point_data.iter().find(|array| array.name == name)
    }

    /// The cell data array called `name`, if any.
    pub fn cell_array(&self, name: &str) -> Option<&DataArray> {
        self.cell_data.iter().find(|array| array.name == name)
    }

    /// Componentwise minimum and maximum of the points, `None` without points.
    pub fn bounding_box(&self) -> Option<([f64; 3], [f64; 3])> {
        let first = *self.points.first()?;
        Some(self.points.iter().fold((first, first), |(mut lo, mut hi), p| {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
            (lo, hi)
        }))
    }

    /// Checks everything a written file relies on.
    ///
    /// # Errors
    /// - [`OutputError::NonFiniteValue`] for NaN or infinity in the time, the points or any array,
    ///   naming the array, tuple and component;
    /// - [`OutputError::PointIndexOutOfRange`] for a triangle referring to a missing point;
    /// - [`OutputError::InvalidName`], [`OutputError::DuplicateName`], [`OutputError::ZeroComponents`] and
    ///   [`OutputError::ArrayLength`] for malformed data arrays.
    pub fn validate(&self) -> Result<(), OutputError> {
        check_finite(TIME_ARRAY, 1, &[self.time])?;
        check_finite(POINTS_ARRAY, 3, self.points.as_flattened())?;
        let n_points = self.points.len();
        for (triangle, nodes) in self.triangles.iter().enumerate() {
            if let Some(&point) = nodes.iter().find(|&&node| node >= n_points) {
                return Err(OutputError::PointIndexOutOfRange {
                    triangle,
                    point,
                    n_points,
                });
            }
        }
        validate_arrays("point data array", &self.point_data, n_points)?;
        validate_arrays("cell data array", &self.cell_data, self.triangles.len())
    }
}

/// Refuses non-finite values of an array of `n_components`-tuples.
pub(crate) fn check_finite(array: &str, n_components: usize, values: &[f64]) -> Result<(), OutputError> {
    match values.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(idx) => Err(OutputError::NonFiniteValue {
            array: array.to_owned(),
            tuple: idx / n_components.max(1),
            component: idx % n_components.max(1),
            value: values[idx],
        }),
    }
}

/// Why `name` cannot name a data array, if it cannot.
pub(crate) fn array_name_problem(name: &str) -> Option<&'static str> {
    if name.is_empty() {
        Some("it is empty")
    } else if name.chars().any(char::is_control) {
        Some("it contains a control character")
    } else if name.trim() != name {
        Some("it starts or ends with white space")
    } else {
        None
    }
}

fn validate_arrays(what: &'static str, arrays: &[DataArray], n_tuples: usize) -> Result<(), OutputError> {
    let mut seen = HashSet::new();
    for array in arrays {
        if let Some(reason) = array_name_problem(&array.name) {
            return Err(OutputError::InvalidName {
                what,
                name: array.name.clone(),
                reason,
            });
        }
        if !seen.insert(array.name.as_str()) {
            return Err(OutputError::DuplicateName {
                what,
                name: array.name.clone(),
            });
        }
        if array.n_components == 0 {
            return Err(OutputError::ZeroComponents {
                array: array.name.clone(),
            });
        }
        let expected = n_tuples * array.n_components;
        if array.values.len() != expected {
            return Err(OutputError::ArrayLength {
                array: array.name.clone(),
                expected,
                found: array.values.len(),
            });
        }
        check_finite(&array.name, array.n_components, &array.values)?;
    }
    Ok(())
}

/// Escapes the five XML special characters for use in text and attribute values.
pub(crate) fn xml_escape(text: &str) -> String {
    let mut escaped = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => escaped.push_str("&amp;"),
            '<' => escaped.push_str("&lt;"),
            '>' => escaped.push_str("&gt;"),
            '"' => escaped.push_str("&quot;"),
            '\'' => escaped.push_str("&apos;"),
            _ => escaped.push(c),
        }
    }
    escaped
}

/// Base64 of a `UInt64` little-endian byte count followed by the `n_bytes` bytes `fill` appends.
fn encode_binary(n_bytes: usize, fill: impl FnOnce(&mut Vec<u8>)) -> String {
    let mut bytes = Vec::with_capacity(8 + n_bytes);
    bytes.extend_from_slice(&(n_bytes as u64).to_le_bytes());
    fill(&mut bytes);
    debug_assert_eq!(bytes.len(), 8 + n_bytes, "declared and written byte counts differ");
    STANDARD.encode(bytes)
}

fn encode_f64(values: &[f64]) -> String {
    encode_binary(values.len() * 8, |bytes| {
        values.iter().for_each(|v| bytes.extend_from_slice(&v.to_le_bytes()))
    })
}

fn encode_i64(values: &[i64]) -> String {
    encode_binary(values.len() * 8, |bytes| {
        values.iter().for_each(|v| bytes.extend_from_slice(&v.to_le_bytes()))
    })
}

fn push_data_array(xml: &mut String, indent: &str, vtk_type: &str, name: &str, n_components: usize, data: &str) {
    let _ = writeln!(
        xml,
        "{indent}<DataArray type=\"{vtk_type}\" Name=\"{}\" NumberOfComponents=\"{n_components}\" \
         format=\"binary\">{data}</DataArray>",
        xml_escape(name)
    );
}

/// The complete `.vtu` document of `frame`.
///
/// # Errors
/// Any error of [`VtuFrame::validate`].
pub fn to_vtu_string(frame: &VtuFrame) -> Result<String, OutputError> {
    frame.validate()?;
    let n_points = frame.points.len();
    let n_cells = frame.triangles.len();
    let mut xml = String::new();
    xml.push_str("<?xml version=\"1.0\"?>\n");
    xml.push_str(
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n",
    );
    xml.push_str("  <UnstructuredGrid>\n    <FieldData>\n");
    let _ = writeln!(
        xml,
        "      <DataArray type=\"Float64\" Name=\"{TIME_ARRAY}\" NumberOfTuples=\"1\" format=\"binary\">{}</DataArray>",
        encode_f64(&[frame.time])
    );
    xml.push_str("    </FieldData>\n");
    let _ = writeln!(
        xml,
        "    <Piece NumberOfPoints=\"{n_points}\" NumberOfCells=\"{n_cells}\">"
    );

    for (tag, arrays) in [("PointData", &frame.point_data), ("CellData", &frame.cell_data)] {
        let _ = writeln!(xml, "      <{tag}>");
        for array in arrays {
            push_data_array(
                &mut xml,
                "        ",
                "Float64",
                &array.name,
                array.n_components,
                &encode_f64(&array.values),
            );
        }
        let _ = writeln!(xml, "      </{tag}>");
    }

    xml.push_str("      <Points>\n");
    push_data_array(
        &mut xml,
        "        ",
        "Float64",
        POINTS_ARRAY,
        3,
        &encode_f64(frame.points.as_flattened()),
    );
    xml.push_str("      </Points>\n      <Cells>\n");
    // Validation bounds every index by the number of points, which fits in i64 on every supported target.
    let connectivity: Vec<i64> = frame.triangles.iter().flatten().map(|&idx| idx as i64).collect();
    push_data_array(
        &mut xml,
        "        ",
        "Int64",
        "connectivity",
        1,
        &encode_i64(&connectivity),
    );
    let offsets: Vec<i64> = (1..=n_cells).map(|cell| 3 * cell as i64).collect();
    push_data_array(&mut xml, "        ", "Int64", "offsets", 1, &encode_i64(&offsets));
    let types = encode_binary(n_cells, |bytes| bytes.resize(bytes.len() + n_cells, VTK_TRIANGLE));
    push_data_array(&mut xml, "        ", "UInt8", "types", 1, &types);
    xml.push_str("      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n");
    Ok(xml)
}

/// Validates `frame` and writes it to `path` atomically as a `.vtu` file.
///
/// # Errors
/// Any error of [`VtuFrame::validate`] (then no file is created or changed), or of
/// [`crate::atomic::write_atomic`].
pub fn write_vtu(path: &Path, frame: &VtuFrame) -> Result<(), OutputError> {
    let xml = to_vtu_string(frame)?;
    write_atomic(path, xml.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn binary_encoding_starts_with_the_byte_count() {
        let decoded = STANDARD.decode(encode_f64(&[1.0, -2.0])).expect("valid base64");
        assert_eq!(decoded.len(), 8 + 16);
        assert_eq!(u64::from_le_bytes(decoded[..8].try_into().expect("8 bytes")), 16);
        assert_eq!(f64::from_le_bytes(decoded[8..16].try_into().expect("8 bytes")), 1.0);
        assert_eq!(f64::from_le_bytes(decoded[16..].try_into().expect("8 bytes")), -2.0);
    }

    #[test]
    fn xml_escape_covers_special_characters() {
        assert_eq!(xml_escape("a<b>&\"c'"), "a&lt;b&gt;&amp;&quot;c&apos;");
    }

    #[test]
    fn array_names_are_checked() {
        assert!(array_name_problem("displacement").is_none());
        assert!(array_name_problem("").is_some());
        assert!(array_name_problem("a\nb").is_some());
        assert!(array_name_problem(" padded").is_some());
    }
}
