//! Gmsh MSH 4.1 input (ASCII and binary): 3-node and 6-node triangles, with the file's physical
//! groups as named vertex sets.
//!
//! What is read: `$MeshFormat` (version 4.1 only; earlier versions are reported with the advice to
//! save as 4.1), `$PhysicalNames`, `$Entities` (which physical groups each point, curve and surface
//! belongs to), `$Nodes` and `$Elements`. Other sections are skipped. Triangles (types 2 and 9) make
//! the mesh; lines (types 1 and 8) and points (type 15) only carry groups; quadrangles, volumes and
//! higher orders are refused with the element's tag. A file must not mix 3- and 6-node triangles.
//!
//! - **Vertices** are the triangles' corner nodes, numbered in the order of the `$Nodes` section (so a
//!   region's `nodes = [...]` counts them in that order, as the OBJ reader counts `v` lines).
//! - **6-node triangles** keep their own mid-edge nodes: [`GmshMesh::mid_edge`] holds each edge's node
//!   position, which the mesh pipeline uses instead of the chord midpoint, so curved geometry meshed
//!   by Gmsh stays curved. Gmsh's node order (corners, then the nodes on edges 0–1, 1–2, 2–0) is ours.
//! - **Physical groups** become [`MeshGroup`]s: the corner vertices of the group's elements (curves or
//!   surfaces or points), named by `$PhysicalNames` or, without a name, by the group's number. A
//!   region `group = "clamp"` selects them like a vertex list: with 6-node triangles the mid-edge node
//!   of every edge whose two corners are selected comes with them.
//!
//! Why not the `mshio` crate: it does not read `$PhysicalNames`, and its errors carry no line, byte or
//! element, which users need to fix a file. The subset read here is small.

use crate::error::MeshFileError;
use cosserat_fem::{MeshError, Tri3Mesh, TriMesh};
use nalgebra::Vector3;
use std::collections::HashMap;
use std::path::Path;

/// A named set of vertices from a mesh file (a Gmsh physical group, an OBJ group).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MeshGroup {
    /// The name.
    pub name: String,
    /// The topological dimension of its elements (0 points, 1 edges, 2 faces).
    pub dim: usize,
    /// Its corner vertices (sorted, unique).
    pub vertices: Vec<usize>,
}

/// A triangle mesh read from a Gmsh file.
#[derive(Debug, Clone, PartialEq)]
pub struct GmshMesh {
    /// The corner mesh (vertices in `$Nodes` order, triangles in `$Elements` order).
    pub mesh: Tri3Mesh,
    /// For a 6-node file, the position of the mid-edge node of every edge, by its corner vertices
    /// (smaller first).
    pub mid_edge: Option<HashMap<[usize; 2], Vector3<f64>>>,
    /// The physical groups.
    pub groups: Vec<MeshGroup>,
    /// The Gmsh tag of each triangle.
    pub element_tags: Vec<u64>,
}

/// Reads a Gmsh MSH 4.1 file.
///
/// # Errors
/// [`MeshFileError`] naming the file, the line (ASCII) or byte (binary) or element, and the reason.
pub fn read_gmsh(path: &Path) -> Result<GmshMesh, MeshFileError> {
    let bytes = std::fs::read(path).map_err(|source| MeshFileError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    parse_gmsh(&bytes, path)
}

/// Where in a file something is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Location {
    /// A 1-based line (text files).
    Line(usize),
    /// A byte offset (binary data).
    Byte(usize),
    /// An element by its tag in the file.
    Element(u64),
}

impl std::fmt::Display for Location {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Location::Line(l) => write!(f, "line {l}"),
            Location::Byte(b) => write!(f, "byte {b}"),
            Location::Element(t) => write!(f, "element {t}"),
        }
    }
}

/// A cursor over the file: text tokens with line numbers, or little-endian binary values.
struct Cursor<'a> {
    data: &'a [u8],
    pos: usize,
    line: usize,
    /// Whether values are read as binary now (inside the data of a binary file's section).
    binary: bool,
    /// Whether the file is binary (`$MeshFormat` says `4.1 1 8`).
    binary_file: bool,
    path: &'a Path,
}

impl<'a> Cursor<'a> {
    fn error(&self, reason: impl Into<String>) -> MeshFileError {
        let at = if self.binary {
            Location::Byte(self.pos)
        } else {
            Location::Line(self.line)
        };
        MeshFileError::Parse {
            path: self.path.to_path_buf(),
            at,
            reason: reason.into(),
        }
    }

    /// The next line (without its end), or `None` at the end of the file; `line` then names the line
    /// after it.
    fn next_line(&mut self) -> Option<&'a str> {
        if self.pos >= self.data.len() {
            return None;
        }
        let rest = &self.data[self.pos..];
        let end = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
        self.pos += (end + 1).min(rest.len());
        if end < rest.len() {
            self.line += 1;
        }
        Some(std::str::from_utf8(&rest[..end]).unwrap_or("").trim_end_matches('\r'))
    }

    /// The next whitespace-separated token (text mode), counting lines.
    fn token(&mut self) -> Result<&'a str, MeshFileError> {
        while self.pos < self.data.len() && self.data[self.pos].is_ascii_whitespace() {
            if self.data[self.pos] == b'\n' {
                self.line += 1;
            }
            self.pos += 1;
        }
        let start = self.pos;
        while self.pos < self.data.len() && !self.data[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        if start == self.pos {
            return Err(self.error("the file ends inside a section"));
        }
        std::str::from_utf8(&self.data[start..self.pos]).map_err(|_| self.error("a value is not text"))
    }

    fn bytes<const N: usize>(&mut self) -> Result<[u8; N], MeshFileError> {
        let chunk = self
            .data
            .get(self.pos..self.pos + N)
            .ok_or_else(|| self.error("the file ends inside binary data"))?;
        self.pos += N;
        Ok(chunk.try_into().expect("the slice has N bytes"))
    }

    /// An `int` (4 bytes in binary files).
    fn int(&mut self) -> Result<i64, MeshFileError> {
        if self.binary {
            return Ok(i32::from_le_bytes(self.bytes()?) as i64);
        }
        let t = self.token()?;
        t.parse().map_err(|_| self.error(format!("`{t}` is not an integer")))
    }

    /// A `size_t` (8 bytes in binary files).
    fn size(&mut self) -> Result<u64, MeshFileError> {
        if self.binary {
            return Ok(u64::from_le_bytes(self.bytes()?));
        }
        let t = self.token()?;
        t.parse()
            .map_err(|_| self.error(format!("`{t}` is not a non-negative integer")))
    }

    /// A count, bounded by what the rest of the file could hold (so a corrupt count is an error, not
    /// an allocation of terabytes).
    fn count(&mut self) -> Result<usize, MeshFileError> {
        let n = self.size()?;
        if n as usize > self.data.len() {
            return Err(self.error(format!("the count {n} is larger than the file")));
        }
        Ok(n as usize)
    }

    fn float(&mut self) -> Result<f64, MeshFileError> {
        let v = if self.binary {
            f64::from_le_bytes(self.bytes()?)
        } else {
            let t = self.token()?;
            t.parse().map_err(|_| self.error(format!("`{t}` is not a number")))?
        };
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.error(format!("the coordinate {v} is not finite")))
        }
    }

    /// Skips past the line `$End<name>`.
    fn end_section(&mut self, name: &str) -> Result<(), MeshFileError> {
        let marker = format!("$End{name}");
        // Binary data may end without a line break before the marker.
        let rest = &self.data[self.pos..];
        let found = rest.windows(marker.len()).position(|w| w == marker.as_bytes());
        let Some(offset) = found else {
            return Err(self.error(format!("`${name}` has no `{marker}`")));
        };
        self.line += rest[..offset].iter().filter(|&&b| b == b'\n').count();
        self.pos += offset;
        self.next_line();
        Ok(())
    }
}

/// What `$Entities` says: the physical tags of each (dimension, entity tag).
type EntityGroups = HashMap<(i64, i64), Vec<i64>>;

/// An element block of `$Elements`.
struct Block {
    dim: i64,
    entity: i64,
    /// Nodes per element and the element tags with their node tags.
    nodes_per_element: usize,
    elements: Vec<(u64, Vec<u64>)>,
}

/// Nodes per element of the types this reader accepts; other types are refused.
fn nodes_per_element(kind: i64) -> Option<usize> {
    match kind {
        1 => Some(2),
        2 | 8 => Some(3),
        9 => Some(6),
        15 => Some(1),
        _ => None,
    }
}

/// Parses MSH 4.1 bytes; `path` is only used in messages.
///
/// # Errors
/// As [`read_gmsh`].
pub fn parse_gmsh(bytes: &[u8], path: &Path) -> Result<GmshMesh, MeshFileError> {
    let mut c = Cursor {
        data: bytes,
        pos: 0,
        line: 1,
        binary: false,
        binary_file: false,
        path,
    };
    let mut names: HashMap<(i64, i64), String> = HashMap::new();
    let mut entities: EntityGroups = HashMap::new();
    let mut nodes: Vec<(u64, Vector3<f64>)> = Vec::new();
    let mut blocks: Vec<Block> = Vec::new();
    let mut seen_format = false;
    loop {
        let header_line = c.line;
        let Some(line) = c.next_line() else { break };
        let Some(section) = line.trim().strip_prefix('$') else {
            if line.trim().is_empty() {
                continue;
            }
            return Err(MeshFileError::Parse {
                path: path.to_path_buf(),
                at: Location::Line(header_line),
                reason: format!("expected a section such as `$Nodes`, found `{}`", line.trim()),
            });
        };
        let section = section.to_string();
        match section.as_str() {
            "MeshFormat" => {
                read_format(&mut c)?;
                seen_format = true;
            }
            _ if !seen_format => return Err(c.error("the file does not start with `$MeshFormat`")),
            "PhysicalNames" => read_names(&mut c, &mut names)?,
            "Entities" => read_entities(&mut c, &mut entities)?,
            "Nodes" => nodes = read_nodes(&mut c)?,
            "Elements" => blocks = read_elements(&mut c)?,
            _ => {}
        }
        c.end_section(&section)?;
    }
    if !seen_format {
        return Err(c.error("not a Gmsh file: no `$MeshFormat` section"));
    }
    assemble(path, &names, &entities, &nodes, &blocks)
}

fn read_format(c: &mut Cursor<'_>) -> Result<(), MeshFileError> {
    let version = c.token()?;
    if version != "4.1" {
        return Err(c.error(format!(
            "MSH version {version} is not supported; save the mesh as version 4.1 (Gmsh: `-format msh41`)"
        )));
    }
    let file_type = c.token()?;
    let data_size = c.token()?;
    if data_size != "8" {
        return Err(c.error(format!("data size {data_size} is not supported (only 8-byte `size_t`)")));
    }
    match file_type {
        "0" => Ok(()),
        "1" => {
            c.next_line();
            c.binary = true;
            c.binary_file = true;
            let one = c.int()?;
            c.binary = false;
            if one != 1 {
                return Err(c.error("the binary file is big-endian or corrupt (its check value is not 1)"));
            }
            Ok(())
        }
        other => Err(c.error(format!("file type {other} is neither 0 (ASCII) nor 1 (binary)"))),
    }
}

fn read_names(c: &mut Cursor<'_>, names: &mut HashMap<(i64, i64), String>) -> Result<(), MeshFileError> {
    // `$PhysicalNames` is text in binary files too.
    let n = c.token()?;
    let n: usize = n.parse().map_err(|_| c.error(format!("`{n}` is not a count")))?;
    c.next_line();
    for _ in 0..n {
        let line = c.next_line().ok_or_else(|| c.error("the file ends inside `$PhysicalNames`"))?;
        let mut parts = line.splitn(3, char::is_whitespace);
        let (dim, tag, name) = (parts.next(), parts.next(), parts.next());
        let parse = |s: Option<&str>| s.and_then(|s| s.trim().parse::<i64>().ok());
        let (Some(dim), Some(tag), Some(name)) = (parse(dim), parse(tag), name) else {
            return Err(c.error(format!("expected `dim tag \"name\"`, found `{line}`")));
        };
        names.insert((dim, tag), name.trim().trim_matches('"').to_string());
    }
    Ok(())
}

/// Reads the physical tags of one entity, and skips its bounding entities.
fn read_entity(c: &mut Cursor<'_>, dim: i64, entities: &mut EntityGroups) -> Result<(), MeshFileError> {
    let tag = c.int()?;
    let n_coords = if dim == 0 { 3 } else { 6 };
    for _ in 0..n_coords {
        c.float()?;
    }
    let n_physical = c.count()?;
    let physical = (0..n_physical).map(|_| c.int()).collect::<Result<Vec<_>, _>>()?;
    if dim > 0 {
        let n_bounding = c.count()?;
        for _ in 0..n_bounding {
            c.int()?;
        }
    }
    entities.insert((dim, tag), physical);
    Ok(())
}

fn read_entities(c: &mut Cursor<'_>, entities: &mut EntityGroups) -> Result<(), MeshFileError> {
    c.binary = c.binary_file;
    let counts = [c.count()?, c.count()?, c.count()?, c.count()?];
    for (dim, &n) in counts.iter().enumerate() {
        for _ in 0..n {
            read_entity(c, dim as i64, entities)?;
        }
    }
    c.binary = false;
    Ok(())
}

fn read_nodes(c: &mut Cursor<'_>) -> Result<Vec<(u64, Vector3<f64>)>, MeshFileError> {
    c.binary = c.binary_file;
    let (n_blocks, n_nodes) = (c.count()?, c.count()?);
    c.size()?;
    c.size()?;
    let mut nodes = Vec::with_capacity(n_nodes);
    for _ in 0..n_blocks {
        let dim = c.int()?;
        c.int()?;
        let parametric = c.int()? != 0;
        let n = c.count()?;
        let tags = (0..n).map(|_| c.size()).collect::<Result<Vec<_>, _>>()?;
        for tag in tags {
            let p = Vector3::new(c.float()?, c.float()?, c.float()?);
            if parametric {
                for _ in 0..dim.clamp(0, 3) {
                    c.float()?;
                }
            }
            nodes.push((tag, p));
        }
    }
    c.binary = false;
    Ok(nodes)
}

fn read_elements(c: &mut Cursor<'_>) -> Result<Vec<Block>, MeshFileError> {
    c.binary = c.binary_file;
    let n_blocks = c.count()?;
    c.count()?;
    c.size()?;
    c.size()?;
    let mut blocks = Vec::with_capacity(n_blocks);
    for _ in 0..n_blocks {
        let (dim, entity, kind) = (c.int()?, c.int()?, c.int()?);
        let n = c.count()?;
        let Some(per) = nodes_per_element(kind) else {
            let first = if n > 0 { c.size()? } else { 0 };
            return Err(MeshFileError::Parse {
                path: c.path.to_path_buf(),
                at: Location::Element(first),
                reason: format!(
                    "element type {kind} is not supported: a shell mesh has 3- or 6-node triangles (and lines or \
                     points for groups)"
                ),
            });
        };
        let mut elements = Vec::with_capacity(n);
        for _ in 0..n {
            let tag = c.size()?;
            let nodes = (0..per).map(|_| c.size()).collect::<Result<Vec<_>, _>>()?;
            elements.push((tag, nodes));
        }
        blocks.push(Block {
            dim,
            entity,
            nodes_per_element: per,
            elements,
        });
    }
    c.binary = false;
    Ok(blocks)
}

/// Builds the mesh and groups from the sections read.
fn assemble(
    path: &Path,
    names: &HashMap<(i64, i64), String>,
    entities: &EntityGroups,
    nodes: &[(u64, Vector3<f64>)],
    blocks: &[Block],
) -> Result<GmshMesh, MeshFileError> {
    let element_error = |tag: u64, reason: String| MeshFileError::Parse {
        path: path.to_path_buf(),
        at: Location::Element(tag),
        reason,
    };
    let node_index: HashMap<u64, usize> = nodes.iter().enumerate().map(|(i, (t, _))| (*t, i)).collect();
    let triangles: Vec<&(u64, Vec<u64>)> =
        blocks.iter().filter(|b| b.dim == 2).flat_map(|b| b.elements.iter()).collect();
    let Some(first) = triangles.first() else {
        return Err(MeshFileError::Empty {
            path: path.to_path_buf(),
        });
    };
    let order = first.1.len();
    if let Some(other) = triangles.iter().find(|t| t.1.len() != order) {
        return Err(element_error(
            other.0,
            format!("mixes {}-node and {order}-node triangles; use one order", other.1.len()),
        ));
    }
    let lookup = |tag: u64, node: u64| {
        node_index
            .get(&node)
            .copied()
            .ok_or_else(|| element_error(tag, format!("node {node} is not in `$Nodes`")))
    };
    let (vertex_of, positions) = corner_vertices(nodes, &triangles, &lookup)?;
    let (elements, mid_edge) = vertex_triangles(nodes, &triangles, order, &vertex_of, &lookup, &element_error)?;
    let mesh = TriMesh {
        nodes: positions,
        elements,
    };
    let element_tags: Vec<u64> = triangles.iter().map(|t| t.0).collect();
    check_triangles(&mesh, &|e| Location::Element(element_tags[e]), path)?;
    let groups = groups(names, entities, blocks, &node_index, &vertex_of, &element_error)?;
    Ok(GmshMesh {
        mesh,
        mid_edge,
        groups,
        element_tags,
    })
}

/// A triangle's tag and its node tags, as read.
type Triangle = (u64, Vec<u64>);

/// Numbers the triangles' corner nodes as vertices in `$Nodes` order: each node's vertex
/// (`usize::MAX` for a node that is no corner) and the vertices' positions.
fn corner_vertices(
    nodes: &[(u64, Vector3<f64>)],
    triangles: &[&Triangle],
    lookup: &dyn Fn(u64, u64) -> Result<usize, MeshFileError>,
) -> Result<(Vec<usize>, Vec<Vector3<f64>>), MeshFileError> {
    let mut is_corner = vec![false; nodes.len()];
    for (tag, el) in triangles {
        for &n in &el[..3] {
            is_corner[lookup(*tag, n)?] = true;
        }
    }
    let mut vertex_of = vec![usize::MAX; nodes.len()];
    let mut positions = Vec::new();
    for (i, (_, p)) in nodes.iter().enumerate().filter(|(i, _)| is_corner[*i]) {
        vertex_of[i] = positions.len();
        positions.push(*p);
    }
    Ok((vertex_of, positions))
}

/// The triangles by their corner vertices and, for 6-node triangles, the position of each edge's
/// mid-edge node by the edge's sorted vertex pair; triangles sharing an edge must share its node.
fn vertex_triangles(
    nodes: &[(u64, Vector3<f64>)],
    triangles: &[&Triangle],
    order: usize,
    vertex_of: &[usize],
    lookup: &dyn Fn(u64, u64) -> Result<usize, MeshFileError>,
    element_error: &dyn Fn(u64, String) -> MeshFileError,
) -> Result<MidEdgeTriangles, MeshFileError> {
    let mut elements = Vec::with_capacity(triangles.len());
    let mut mid_edge = (order == 6).then(HashMap::new);
    for (tag, el) in triangles {
        let mut v = [0; 3];
        for (slot, &n) in v.iter_mut().zip(&el[..3]) {
            *slot = vertex_of[lookup(*tag, n)?];
        }
        if let Some(mid) = &mut mid_edge {
            for k in 0..3 {
                let (a, b) = (v[k], v[(k + 1) % 3]);
                let p = nodes[lookup(*tag, el[3 + k])?].1;
                let key = [a.min(b), a.max(b)];
                if let Some(q) = mid.insert(key, p)
                    && q != p
                {
                    return Err(element_error(
                        *tag,
                        format!(
                            "its mid-edge node {} differs from the neighbour's on the same edge",
                            el[3 + k]
                        ),
                    ));
                }
            }
        }
        elements.push(v);
    }
    Ok((elements, mid_edge))
}

/// Triangles by corner vertices, with the mid-edge node positions of a 6-node mesh.
type MidEdgeTriangles = (Vec<[usize; 3]>, Option<HashMap<[usize; 2], Vector3<f64>>>);

/// The physical groups as vertex sets.
fn groups(
    names: &HashMap<(i64, i64), String>,
    entities: &EntityGroups,
    blocks: &[Block],
    node_index: &HashMap<u64, usize>,
    vertex_of: &[usize],
    element_error: &dyn Fn(u64, String) -> MeshFileError,
) -> Result<Vec<MeshGroup>, MeshFileError> {
    let mut sets: std::collections::BTreeMap<(i64, i64), Vec<usize>> = std::collections::BTreeMap::new();
    for b in blocks {
        let Some(physical) = entities.get(&(b.dim, b.entity)) else {
            continue;
        };
        let corners = match b.nodes_per_element {
            6 => 3,
            3 if b.dim == 2 => 3,
            3 | 2 => 2,
            n => n,
        };
        for &group in physical {
            let set = sets.entry((b.dim, group.abs())).or_default();
            for (tag, el) in &b.elements {
                for n in &el[..corners] {
                    let v = node_index.get(n).map(|&i| vertex_of[i]).unwrap_or(usize::MAX);
                    if v == usize::MAX {
                        return Err(element_error(
                            *tag,
                            format!("node {n} of this group element is not a corner of any triangle"),
                        ));
                    }
                    set.push(v);
                }
            }
        }
    }
    Ok(sets
        .into_iter()
        .map(|((dim, tag), mut vertices)| {
            vertices.sort_unstable();
            vertices.dedup();
            MeshGroup {
                name: names.get(&(dim, tag)).cloned().unwrap_or_else(|| tag.to_string()),
                dim: dim as usize,
                vertices,
            }
        })
        .collect())
}

/// Degenerate triangles, edges shared by more than two triangles and doubled triangles, each reported
/// where `location` says the triangle is in the file.
pub(crate) fn check_triangles(
    mesh: &Tri3Mesh,
    location: &dyn Fn(usize) -> Location,
    path: &Path,
) -> Result<(), MeshFileError> {
    let at = |elem_idx: usize, reason: String| MeshFileError::Parse {
        path: path.to_path_buf(),
        at: location(elem_idx),
        reason,
    };
    mesh.check_degenerate().map_err(|e| match e {
        MeshError::DegenerateElement { elem_idx, area } => at(
            elem_idx,
            format!(
                "the triangle is degenerate (area {area:e}): {}",
                cosserat_fem::error::degenerate_cause(area, "corners")
            ),
        ),
        source => MeshFileError::Mesh {
            path: path.to_path_buf(),
            source,
        },
    })?;
    mesh.check_manifold_edges().map_err(|e| match e {
        MeshError::NonManifoldEdge { a, b, n_faces } => {
            let has_edge = |f: &[usize; 3]| f.contains(&a) && f.contains(&b);
            let third = mesh
                .elements
                .iter()
                .enumerate()
                .filter(|(_, f)| has_edge(f))
                .nth(2)
                .map_or(0, |(e, _)| e);
            at(
                third,
                format!(
                    "the edge between vertices {a} and {b} is shared by {n_faces} triangles (at most two are allowed)"
                ),
            )
        }
        MeshError::DuplicateElement { first, second } => at(
            second,
            format!(
                "the triangle has the same three corners as the one at {}; a doubled triangle is not a surface",
                location(first)
            ),
        ),
        source => MeshFileError::Mesh {
            path: path.to_path_buf(),
            source,
        },
    })
}
