//! Reading `.vtu` frames back: the renderer's input and the round-trip check of the writer.
//!
//! The reader accepts what [`crate::vtu`] writes and the simple variations of it that other tools
//! produce: one `Piece` of triangles, inline `binary` (with a `UInt32` or `UInt64` header) or `ascii`
//! arrays, any numeric VTK type for data arrays. Compressed or appended data, other cell types and
//! big-endian files are refused with an error naming the file and the array. What is read is validated like
//! a frame about to be written, so a frame read by this module never holds NaN or a dangling index.

use std::path::Path;

use base64::Engine as _;
use base64::engine::general_purpose::STANDARD;
use roxmltree::{Document, Node};

use crate::OutputError;
use crate::vtu::{DataArray, POINTS_ARRAY, TIME_ARRAY, VTK_TRIANGLE, VtuFrame};

/// Reads a `.vtu` file written by [`crate::vtu::write_vtu`] (or a compatible one).
///
/// # Errors
/// [`OutputError::Io`] if the file cannot be read, [`OutputError::Xml`] if it is not well-formed,
/// [`OutputError::Format`] or [`OutputError::Base64`] for an unsupported or inconsistent structure, and
/// [`OutputError::InvalidFrame`] if the data fail [`VtuFrame::validate`].
pub fn read_vtu(path: &Path) -> Result<VtuFrame, OutputError> {
    let text = std::fs::read_to_string(path).map_err(|source| OutputError::Io {
        operation: "read",
        path: path.to_path_buf(),
        source,
    })?;
    parse_vtu(&text, path)
}

/// Parses the text of a `.vtu` document; `path` is only used in error messages.
///
/// # Errors
/// As [`read_vtu`], without the I/O error.
pub fn parse_vtu(text: &str, path: &Path) -> Result<VtuFrame, OutputError> {
    let document = Document::parse(text).map_err(|source| OutputError::Xml {
        path: path.to_path_buf(),
        source,
    })?;
    let reader = Reader::new(&document, path)?;
    let frame = reader.frame()?;
    frame.validate().map_err(|source| OutputError::InvalidFrame {
        path: path.to_path_buf(),
        source: Box::new(source),
    })?;
    Ok(frame)
}

/// Decoded values of a data array.
enum Values {
    Float(Vec<f64>),
    Int(Vec<i128>),
}

/// Width of the byte-count header of inline binary arrays.
#[derive(Clone, Copy)]
enum HeaderType {
    UInt32,
    UInt64,
}

struct Reader<'a, 'input> {
    root: Node<'a, 'input>,
    header: HeaderType,
    path: &'a Path,
}

impl<'a, 'input> Reader<'a, 'input> {
    fn new(document: &'a Document<'input>, path: &'a Path) -> Result<Self, OutputError> {
        let root = document.root_element();
        let mut reader = Self {
            root,
            header: HeaderType::UInt32,
            path,
        };
        if root.tag_name().name() != "VTKFile" {
            return Err(reader.format(format!(
                "root element is <{}>, expected <VTKFile>",
                root.tag_name().name()
            )));
        }
        if root.attribute("type") != Some("UnstructuredGrid") {
            return Err(reader.format("VTKFile type is not \"UnstructuredGrid\"".to_owned()));
        }
        if let Some(order) = root.attribute("byte_order").filter(|&order| order != "LittleEndian") {
            return Err(reader.format(format!("byte_order \"{order}\" is not supported (LittleEndian only)")));
        }
        if let Some(compressor) = root.attribute("compressor") {
            return Err(reader.format(format!("compressed data (\"{compressor}\") is not supported")));
        }
        reader.header = match root.attribute("header_type").unwrap_or("UInt32") {
            "UInt32" => HeaderType::UInt32,
            "UInt64" => HeaderType::UInt64,
            other => return Err(reader.format(format!("header_type \"{other}\" is not supported"))),
        };
        Ok(reader)
    }

    fn format(&self, reason: String) -> OutputError {
        OutputError::Format {
            path: self.path.to_path_buf(),
            reason,
        }
    }

    fn child(&self, parent: Node<'a, 'input>, tag: &str) -> Result<Node<'a, 'input>, OutputError> {
        let mut matches = parent.children().filter(|node| node.has_tag_name(tag));
        match (matches.next(), matches.next()) {
            (Some(node), None) => Ok(node),
            (None, _) => Err(self.format(format!("<{}> has no <{tag}>", parent.tag_name().name()))),
            (Some(_), Some(_)) => Err(self.format(format!("<{}> has more than one <{tag}>", parent.tag_name().name()))),
        }
    }

    fn count_attribute(&self, node: Node<'a, 'input>, attribute: &str) -> Result<usize, OutputError> {
        let tag = node.tag_name().name();
        let text = node
            .attribute(attribute)
            .ok_or_else(|| self.format(format!("<{tag}> lacks {attribute}")))?;
        text.trim()
            .parse()
            .map_err(|_| self.format(format!("<{tag}> {attribute}=\"{text}\" is not a count")))
    }

    fn frame(&self) -> Result<VtuFrame, OutputError> {
        let grid = self.child(self.root, "UnstructuredGrid")?;
        let time = self.time(grid)?;
        let piece = self.child(grid, "Piece")?;
        let n_points = self.count_attribute(piece, "NumberOfPoints")?;
        let n_cells = self.count_attribute(piece, "NumberOfCells")?;

        let points_node = self.child(self.child(piece, "Points")?, "DataArray")?;
        let (n_components, coordinates) = self.float_array(points_node)?;
        if n_components != 3 || coordinates.len() != 3 * n_points {
            return Err(self.format(format!(
                "{POINTS_ARRAY} must hold {n_points} 3-vectors, found {} values in {n_components} components",
                coordinates.len()
            )));
        }
        let points = coordinates.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect();
        let triangles = self.triangles(piece, n_points, n_cells)?;
        Ok(VtuFrame {
            points,
            triangles,
            point_data: self.data_arrays(piece, "PointData")?,
            cell_data: self.data_arrays(piece, "CellData")?,
            time,
        })
    }

    fn time(&self, grid: Node<'a, 'input>) -> Result<f64, OutputError> {
        let field_data = self.child(grid, "FieldData")?;
        let node = field_data
            .children()
            .find(|node| node.has_tag_name("DataArray") && node.attribute("Name") == Some(TIME_ARRAY))
            .ok_or_else(|| self.format(format!("<FieldData> has no {TIME_ARRAY} array")))?;
        match self.float_array(node)?.1.as_slice() {
            &[time] => Ok(time),
            values => Err(self.format(format!("{TIME_ARRAY} must hold one value, found {}", values.len()))),
        }
    }

    fn triangles(
        &self,
        piece: Node<'a, 'input>,
        n_points: usize,
        n_cells: usize,
    ) -> Result<Vec<[usize; 3]>, OutputError> {
        let cells = self.child(piece, "Cells")?;
        let named = |name: &str| {
            cells
                .children()
                .find(|node| node.has_tag_name("DataArray") && node.attribute("Name") == Some(name))
                .ok_or_else(|| self.format(format!("<Cells> has no {name} array")))
        };
        let connectivity = self.index_array(named("connectivity")?)?;
        let offsets = self.index_array(named("offsets")?)?;
        let types = self.index_array(named("types")?)?;
        if offsets.len() != n_cells || types.len() != n_cells {
            return Err(self.format(format!(
                "NumberOfCells is {n_cells}, but offsets has {} and types {} entries",
                offsets.len(),
                types.len()
            )));
        }
        if let Some(cell) = types.iter().position(|&t| t != i128::from(VTK_TRIANGLE)) {
            return Err(self.format(format!(
                "cell {cell} has VTK type {}; only triangles (5) are supported",
                types[cell]
            )));
        }
        if let Some(cell) = offsets
            .iter()
            .enumerate()
            .position(|(cell, &offset)| offset != 3 * (cell as i128 + 1))
        {
            return Err(self.format(format!(
                "offset of cell {cell} is {}, expected {}",
                offsets[cell],
                3 * (cell + 1)
            )));
        }
        if connectivity.len() != 3 * n_cells {
            return Err(self.format(format!(
                "connectivity has {} entries, expected {} for {n_cells} triangles",
                connectivity.len(),
                3 * n_cells
            )));
        }
        connectivity
            .chunks_exact(3)
            .enumerate()
            .map(|(triangle, nodes)| {
                let mut out = [0; 3];
                for (slot, &node) in out.iter_mut().zip(nodes) {
                    *slot = usize::try_from(node).ok().filter(|&idx| idx < n_points).ok_or_else(|| {
                        self.format(format!(
                            "triangle {triangle} refers to point {node}, but there are {n_points}"
                        ))
                    })?;
                }
                Ok(out)
            })
            .collect()
    }

    fn data_arrays(&self, piece: Node<'a, 'input>, tag: &str) -> Result<Vec<DataArray>, OutputError> {
        let Some(section) = piece.children().find(|node| node.has_tag_name(tag)) else {
            return Ok(Vec::new());
        };
        section
            .children()
            .filter(|node| node.has_tag_name("DataArray"))
            .map(|node| {
                let name = node
                    .attribute("Name")
                    .ok_or_else(|| self.format(format!("a <{tag}> array has no Name")))?;
                let (n_components, values) = self.float_array(node)?;
                Ok(DataArray::new(name, n_components, values))
            })
            .collect()
    }

    /// Values of an array of any numeric type as `f64` (exact for floats and for integers up to 2^53).
    fn float_array(&self, node: Node<'a, 'input>) -> Result<(usize, Vec<f64>), OutputError> {
        let n_components = match node.attribute("NumberOfComponents") {
            None => 1,
            Some(_) => self.count_attribute(node, "NumberOfComponents")?,
        };
        let values = match self.decode(node)? {
            Values::Float(values) => values,
            Values::Int(values) => values.into_iter().map(|v| v as f64).collect(),
        };
        Ok((n_components, values))
    }

    fn index_array(&self, node: Node<'a, 'input>) -> Result<Vec<i128>, OutputError> {
        match self.decode(node)? {
            Values::Int(values) => Ok(values),
            Values::Float(_) => Err(self.format(format!("array {} must have an integer type", array_name(node)))),
        }
    }

    fn decode(&self, node: Node<'a, 'input>) -> Result<Values, OutputError> {
        let name = array_name(node);
        let vtk_type = node
            .attribute("type")
            .ok_or_else(|| self.format(format!("array {name} has no type")))?;
        let scalar = ScalarType::parse(vtk_type)
            .ok_or_else(|| self.format(format!("array {name} has the unsupported type \"{vtk_type}\"")))?;
        let text = node.text().unwrap_or("");
        match node.attribute("format").unwrap_or("ascii") {
            "binary" => self.decode_binary(name, scalar, text),
            "ascii" => self.decode_ascii(name, scalar, text),
            other => Err(self.format(format!("array {name} has the unsupported format \"{other}\""))),
        }
    }

    fn decode_binary(&self, name: &str, scalar: ScalarType, text: &str) -> Result<Values, OutputError> {
        let compact: String = text.chars().filter(|c| !c.is_ascii_whitespace()).collect();
        let bytes = STANDARD.decode(compact).map_err(|source| OutputError::Base64 {
            path: self.path.to_path_buf(),
            array: name.to_owned(),
            source,
        })?;
        let header_len = match self.header {
            HeaderType::UInt32 => 4,
            HeaderType::UInt64 => 8,
        };
        if bytes.len() < header_len {
            return Err(self.format(format!("array {name} is shorter than its byte-count header")));
        }
        let (header, data) = bytes.split_at(header_len);
        let declared = header.iter().rev().fold(0u128, |acc, &b| (acc << 8) | u128::from(b));
        if declared != data.len() as u128 {
            return Err(self.format(format!(
                "array {name} declares {declared} bytes but holds {}",
                data.len()
            )));
        }
        let width = scalar.width();
        if data.len() % width != 0 {
            return Err(self.format(format!(
                "array {name} holds {} bytes, not a multiple of {width}",
                data.len()
            )));
        }
        Ok(scalar.decode_le(data))
    }

    fn decode_ascii(&self, name: &str, scalar: ScalarType, text: &str) -> Result<Values, OutputError> {
        let bad = |token: &str| self.format(format!("array {name} holds \"{token}\", not a {scalar:?} value"));
        if scalar.is_float() {
            let values = text.split_ascii_whitespace().map(|t| t.parse::<f64>().map_err(|_| bad(t)));
            Ok(Values::Float(values.collect::<Result<_, _>>()?))
        } else {
            let values = text.split_ascii_whitespace().map(|t| t.parse::<i128>().map_err(|_| bad(t)));
            Ok(Values::Int(values.collect::<Result<_, _>>()?))
        }
    }
}

fn array_name<'a>(node: Node<'a, '_>) -> &'a str {
    node.attribute("Name").unwrap_or("(unnamed)")
}

/// The numeric VTK types.
#[derive(Debug, Clone, Copy)]
enum ScalarType {
    Float32,
    Float64,
    Int8,
    Int16,
    Int32,
    Int64,
    UInt8,
    UInt16,
    UInt32,
    UInt64,
}

impl ScalarType {
    fn parse(name: &str) -> Option<Self> {
        Some(match name {
            "Float32" => Self::Float32,
            "Float64" => Self::Float64,
            "Int8" => Self::Int8,
            "Int16" => Self::Int16,
            "Int32" => Self::Int32,
            "Int64" => Self::Int64,
            "UInt8" => Self::UInt8,
            "UInt16" => Self::UInt16,
            "UInt32" => Self::UInt32,
            "UInt64" => Self::UInt64,
            _ => return None,
        })
    }

    fn width(self) -> usize {
        match self {
            Self::Int8 | Self::UInt8 => 1,
            Self::Int16 | Self::UInt16 => 2,
            Self::Float32 | Self::Int32 | Self::UInt32 => 4,
            Self::Float64 | Self::Int64 | Self::UInt64 => 8,
        }
    }

    fn is_float(self) -> bool {
        matches!(self, Self::Float32 | Self::Float64)
    }

    /// Decodes little-endian values; `data.len()` is a multiple of `self.width()`.
    fn decode_le(self, data: &[u8]) -> Values {
        let chunks = data.chunks_exact(self.width());
        // `chunks_exact` yields slices of exactly `width` bytes, so the array conversions cannot fail.
        macro_rules! ints {
            ($t:ty) => {
                Values::Int(
                    chunks
                        .map(|c| i128::from(<$t>::from_le_bytes(c.try_into().unwrap_or_default())))
                        .collect(),
                )
            };
        }
        match self {
            Self::Float32 => Values::Float(
                chunks
                    .map(|c| f64::from(f32::from_le_bytes(c.try_into().unwrap_or_default())))
                    .collect(),
            ),
            Self::Float64 => {
                Values::Float(chunks.map(|c| f64::from_le_bytes(c.try_into().unwrap_or_default())).collect())
            }
            Self::Int8 => ints!(i8),
            Self::Int16 => ints!(i16),
            Self::Int32 => ints!(i32),
            Self::Int64 => ints!(i64),
            Self::UInt8 => ints!(u8),
            Self::UInt16 => ints!(u16),
            Self::UInt32 => ints!(u32),
            Self::UInt64 => ints!(u64),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn little_endian_integers_decode() {
        let data = [0xff, 0xff, 0x01, 0x00];
        match ScalarType::Int16.decode_le(&data) {
            Values::Int(values) => assert_eq!(values, vec![-1, 1]),
            Values::Float(_) => panic!("integers expected"),
        }
        match ScalarType::UInt16.decode_le(&data) {
            Values::Int(values) => assert_eq!(values, vec![65535, 1]),
            Values::Float(_) => panic!("integers expected"),
        }
    }

    #[test]
    fn float32_widens_exactly() {
        let data = 0.1f32.to_le_bytes();
        match ScalarType::Float32.decode_le(&data) {
            Values::Float(values) => assert_eq!(values, vec![f64::from(0.1f32)]),
            Values::Int(_) => panic!("floats expected"),
        }
    }
}
