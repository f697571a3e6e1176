//! PLY input (ASCII, binary little- and big-endian): triangle surfaces, with integer vertex
//! properties as named vertex sets.
//!
//! The `vertex` element must have `x`, `y`, `z`; the `face` element a list property `vertex_indices`
//! (or `vertex_index`) of three entries per face: polygons are refused, as in OBJ input, because their
//! triangulation is a modelling decision. Other elements (edges, materials) are skipped.
//!
//! Every integer vertex property other than the colour channels (`red`, `green`, `blue`, `alpha`)
//! names a [`MeshGroup`]: the vertices where it is not zero. A point attribute `clamp` set to 1 on the
//! clamped vertices in Houdini or Blender and written with the PLY file is selected by
//! `region = { group = "clamp" }`.
//!
//! Why not a crate (`ply-rs`): its reader does not report the line or face of an error, and the subset
//! needed here is small.

use crate::error::MeshFileError;
use crate::gmsh::{Location, MeshGroup, check_triangles};
use cosserat_fem::{Tri3Mesh, TriMesh};
use nalgebra::Vector3;
use std::path::Path;

/// A triangle mesh read from a PLY file.
#[derive(Debug, Clone, PartialEq)]
pub struct PlyMesh {
    /// The mesh, vertices and faces in file order.
    pub mesh: Tri3Mesh,
    /// Groups from integer vertex properties.
    pub groups: Vec<MeshGroup>,
}

/// Reads a PLY file.
///
/// # Errors
/// [`MeshFileError`] naming the file, the line (ASCII), byte (binary) or face, and the reason.
pub fn read_ply(path: &Path) -> Result<PlyMesh, MeshFileError> {
    let bytes = std::fs::read(path).map_err(|source| MeshFileError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    parse_ply(&bytes, path)
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Encoding {
    Ascii,
    Little,
    Big,
}

/// A scalar type of the format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &str) -> Option<Self> {
        Some(match name {
            "char" | "int8" => Self::I8,
            "uchar" | "uint8" => Self::U8,
            "short" | "int16" => Self::I16,
            "ushort" | "uint16" => Self::U16,
            "int" | "int32" => Self::I32,
            "uint" | "uint32" => Self::U32,
            "float" | "float32" => Self::F32,
            "double" | "float64" => Self::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Self::I8 | Self::U8 => 1,
            Self::I16 | Self::U16 => 2,
            Self::I32 | Self::U32 | Self::F32 => 4,
            Self::F64 => 8,
        }
    }

    fn is_integer(self) -> bool {
        !matches!(self, Self::F32 | Self::F64)
    }
}

#[derive(Debug, Clone)]
enum Property {
    Scalar(String, Scalar),
    List(String, Scalar, Scalar),
}

#[derive(Debug, Clone)]
struct Element {
    name: String,
    count: usize,
    properties: Vec<Property>,
}

struct Reader<'a> {
    data: &'a [u8],
    pos: usize,
    line: usize,
    encoding: Encoding,
    path: &'a Path,
}

impl<'a> Reader<'a> {
    fn error(&self, reason: impl Into<String>) -> MeshFileError {
        MeshFileError::Parse {
            path: self.path.to_path_buf(),
            at: match self.encoding {
                Encoding::Ascii => Location::Line(self.line),
                _ => Location::Byte(self.pos),
            },
            reason: reason.into(),
        }
    }

    fn next_line(&mut self) -> Option<&'a str> {
        if self.pos >= self.data.len() {
            return None;
        }
        let rest = &self.data[self.pos..];
        let end = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
        self.pos += (end + 1).min(rest.len());
        self.line += 1;
        Some(std::str::from_utf8(&rest[..end]).unwrap_or("").trim_end_matches('\r'))
    }

    /// One value: a token of the current ASCII line, or binary bytes.
    fn value(&mut self, kind: Scalar, words: &mut std::str::SplitWhitespace<'a>) -> Result<f64, MeshFileError> {
        if self.encoding == Encoding::Ascii {
            let w = words
                .next()
                .ok_or_else(|| self.error("the line has fewer values than the header declares"))?;
            return w.parse().map_err(|_| self.error(format!("`{w}` is not a number")));
        }
        let n = kind.size();
        let bytes = self
            .data
            .get(self.pos..self.pos + n)
            .ok_or_else(|| self.error("the file ends inside the binary data"))?;
        self.pos += n;
        let mut b = [0u8; 8];
        b[..n].copy_from_slice(bytes);
        if self.encoding == Encoding::Big {
            b[..n].reverse();
        }
        let v = match kind {
            Scalar::I8 => b[0] as i8 as f64,
            Scalar::U8 => b[0] as f64,
            Scalar::I16 => i16::from_le_bytes([b[0], b[1]]) as f64,
            Scalar::U16 => u16::from_le_bytes([b[0], b[1]]) as f64,
            Scalar::I32 => i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::F64 => f64::from_le_bytes(b),
        };
        Ok(v)
    }
}

/// Parses PLY bytes; `path` is only used in messages.
///
/// # Errors
/// As [`read_ply`].
pub fn parse_ply(bytes: &[u8], path: &Path) -> Result<PlyMesh, MeshFileError> {
    let mut r = Reader {
        data: bytes,
        pos: 0,
        line: 0,
        encoding: Encoding::Ascii,
        path,
    };
    let elements = header(&mut r)?;
    let mut nodes: Vec<Vector3<f64>> = Vec::new();
    let mut faces: Vec<[usize; 3]> = Vec::new();
    let mut face_lines: Vec<Location> = Vec::new();
    let mut groups: Vec<MeshGroup> = Vec::new();
    for element in &elements {
        match element.name.as_str() {
            "vertex" => (nodes, groups) = vertices(&mut r, element)?,
            "face" => (faces, face_lines) = triangles(&mut r, element, nodes.len())?,
            _ => {
                for _ in 0..element.count {
                    record(&mut r, element, &mut |_, _| Ok(()))?;
                }
            }
        }
    }
    if faces.is_empty() {
        return Err(MeshFileError::Empty {
            path: path.to_path_buf(),
        });
    }
    let mesh = TriMesh { nodes, elements: faces };
    check_triangles(&mesh, &|f| face_lines[f], path)?;
    Ok(PlyMesh { mesh, groups })
}

/// The header up to `end_header`: the encoding and the elements.
fn header(r: &mut Reader<'_>) -> Result<Vec<Element>, MeshFileError> {
    if r.next_line() != Some("ply") {
        return Err(r.error("not a PLY file: the first line is not `ply`"));
    }
    let mut elements: Vec<Element> = Vec::new();
    let mut encoding = None;
    loop {
        let line = r.next_line().ok_or_else(|| r.error("the header has no `end_header`"))?;
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            ["end_header"] => break,
            ["format", f, _] => {
                encoding = Some(match *f {
                    "ascii" => Encoding::Ascii,
                    "binary_little_endian" => Encoding::Little,
                    "binary_big_endian" => Encoding::Big,
                    other => return Err(r.error(format!("unknown format `{other}`"))),
                });
            }
            ["comment", ..] | ["obj_info", ..] | [] => {}
            ["element", name, count] => elements.push(Element {
                name: name.to_string(),
                count: count.parse().map_err(|_| r.error(format!("`{count}` is not a count")))?,
                properties: Vec::new(),
            }),
            ["property", "list", count, item, name] => {
                let (Some(c), Some(i)) = (Scalar::parse(count), Scalar::parse(item)) else {
                    return Err(r.error(format!("unknown type in `{line}`")));
                };
                let e = elements.last_mut().ok_or_else(|| r.error("a property before any element"))?;
                e.properties.push(Property::List(name.to_string(), c, i));
            }
            ["property", kind, name] => {
                let k = Scalar::parse(kind).ok_or_else(|| r.error(format!("unknown type `{kind}`")))?;
                let e = elements.last_mut().ok_or_else(|| r.error("a property before any element"))?;
                e.properties.push(Property::Scalar(name.to_string(), k));
            }
            _ => return Err(r.error(format!("unexpected header line `{line}`"))),
        }
    }
    r.encoding = encoding.ok_or_else(|| r.error("the header has no `format` line"))?;
    Ok(elements)
}

/// Receives each property of a record: its index and its values.
type PropertySink<'s> = dyn FnMut(usize, &[f64]) -> Result<(), MeshFileError> + 's;

/// Reads one record of `element`, passing each property's values to `sink`.
fn record<'a>(r: &mut Reader<'a>, element: &Element, sink: &mut PropertySink<'_>) -> Result<(), MeshFileError> {
    let mut words = "".split_whitespace();
    if r.encoding == Encoding::Ascii {
        words = r
            .next_line()
            .ok_or_else(|| {
                r.error(format!(
                    "the file ends before all {} `{}` records",
                    element.count, element.name
                ))
            })?
            .split_whitespace();
    }
    let mut values = Vec::new();
    for (k, p) in element.properties.iter().enumerate() {
        values.clear();
        match p {
            Property::Scalar(_, kind) => values.push(r.value(*kind, &mut words)?),
            Property::List(_, count, item) => {
                let n = r.value(*count, &mut words)?;
                if !(0.0..=1e6).contains(&n) || n.fract() != 0.0 {
                    return Err(r.error(format!("list length {n} is not valid")));
                }
                for _ in 0..n as usize {
                    values.push(r.value(*item, &mut words)?);
                }
            }
        }
        sink(k, &values)?;
    }
    Ok(())
}

type Vertices = (Vec<Vector3<f64>>, Vec<MeshGroup>);

fn vertices(r: &mut Reader<'_>, element: &Element) -> Result<Vertices, MeshFileError> {
    let find = |name: &str| {
        element
            .properties
            .iter()
            .position(|p| matches!(p, Property::Scalar(n, _) if n == name))
    };
    let (Some(ix), Some(iy), Some(iz)) = (find("x"), find("y"), find("z")) else {
        return Err(r.error("the `vertex` element needs `x`, `y` and `z` properties"));
    };
    let group_props: Vec<(usize, String)> = element
        .properties
        .iter()
        .enumerate()
        .filter_map(|(k, p)| match p {
            Property::Scalar(n, kind)
                if kind.is_integer() && !["red", "green", "blue", "alpha"].contains(&n.as_str()) =>
            {
                Some((k, n.clone()))
            }
            _ => None,
        })
        .collect();
    let mut nodes = Vec::with_capacity(element.count);
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); group_props.len()];
    for i in 0..element.count {
        let mut p = [0.0; 3];
        record(r, element, &mut |k, v| {
            if let Some(c) = [ix, iy, iz].iter().position(|&j| j == k) {
                p[c] = v[0];
            }
            if let Some(g) = group_props.iter().position(|(j, _)| *j == k)
                && v[0] != 0.0
            {
                members[g].push(i);
            }
            Ok(())
        })?;
        if p.iter().any(|c| !c.is_finite()) {
            return Err(r.error(format!("vertex {i} has a coordinate that is not finite")));
        }
        nodes.push(Vector3::from(p));
    }
    let groups = group_props
        .into_iter()
        .zip(members)
        .map(|((_, name), vertices)| MeshGroup { name, dim: 0, vertices })
        .collect();
    Ok((nodes, groups))
}

fn triangles(
    r: &mut Reader<'_>,
    element: &Element,
    n_vertices: usize,
) -> Result<(Vec<[usize; 3]>, Vec<Location>), MeshFileError> {
    let index = element
        .properties
        .iter()
        .position(|p| matches!(p, Property::List(n, _, _) if n == "vertex_indices" || n == "vertex_index"))
        .ok_or_else(|| r.error("the `face` element needs a `vertex_indices` list"))?;
    let mut faces = Vec::with_capacity(element.count);
    let mut locations = Vec::with_capacity(element.count);
    for f in 0..element.count {
        let mut face = None;
        let (at, path) = (r.encoding, r.path);
        record(r, element, &mut |k, v| {
            if k != index {
                return Ok(());
            }
            if v.len() != 3 {
                return Err(MeshFileError::Parse {
                    path: path.to_path_buf(),
                    at: Location::Element(f as u64),
                    reason: format!("face {f} has {} vertices; only triangles are supported", v.len()),
                });
            }
            face = Some([v[0], v[1], v[2]]);
            Ok(())
        })?;
        let face = face.expect("the index property was read");
        let mut tri = [0usize; 3];
        for (slot, &v) in tri.iter_mut().zip(&face) {
            if v < 0.0 || v >= n_vertices as f64 {
                return Err(r.error(format!("face {f} names vertex {v}; the file has {n_vertices} vertices")));
            }
            *slot = v as usize;
        }
        faces.push(tri);
        locations.push(match at {
            Encoding::Ascii => Location::Line(r.line),
            _ => Location::Element(f as u64),
        });
    }
    Ok((faces, locations))
}
