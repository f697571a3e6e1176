//! Wavefront OBJ input: triangle surface meshes for shells, read with the file's own vertex numbering
//! and checked before simulation.
//!
//! Only `v` (positions), `f` (faces), `g` (groups) and `o` (objects) statements matter; normals,
//! texture coordinates, smoothing groups, materials and vertex colours (`v x y z r g b`) are ignored. A
//! vertex may carry the weight `w` of `v x y z w` only if it is 1: any other weight makes the vertex
//! rational (the OBJ format's curves and surfaces), which a triangle mesh cannot represent. Each group or object name becomes
//! a [`MeshGroup`] of the vertices of its faces (`g a b` puts the following faces in both `a` and `b`;
//! the exporters' `default` group is skipped), which regions select with `group = "name"`. Face corners may be written `i`, `i/t`,
//! `i//n` or `i/t/n`, with negative (relative) indices allowed. Every face must be a triangle: the
//! reader does not triangulate, because the triangulation of a polygon is a modelling decision the
//! simulation should not make silently.
//!
//! Why not `tobj`: it renumbers vertices in order of first use per object, silently drops
//! unreferenced vertices and splits a vertex that faces use with different normals or texture
//! coordinates into several. Each of these changes the mesh a scene refers to (vertex lists in
//! regions, seams that would become open boundaries), so this reader keeps the file's vertices and
//! reports problems instead, each with its line:
//! non-triangle faces, degenerate triangles, unreferenced vertices, edges shared by more than two
//! faces and faces repeated with the same three vertices ([`cosserat_fem::TriMesh::validate`] does the geometric checks).
//!
//! Two things a file may do on purpose are reported as [`ObjMesh::warnings`] rather than refused:
//! vertices at the same position (an exporter's split along seams: the surface falls apart into
//! pieces there, unless [`ObjMesh::welded`] merges them) and bowtie vertices (two fans of faces that
//! touch in one vertex only, so that the shell can turn freely about it).

use crate::error::{Num, ObjError};
use crate::gmsh::MeshGroup;
use cosserat_fem::{MeshError, Tri3Mesh, TriMesh};
use nalgebra::Vector3;
use std::collections::HashMap;
use std::path::Path;

/// A triangle mesh read from an OBJ file, with the line of every vertex and face.
#[derive(Debug, Clone, PartialEq)]
pub struct ObjMesh {
    /// The mesh, vertices and faces in file order (0-based).
    pub mesh: Tri3Mesh,
    /// The 1-based line of each vertex.
    pub vertex_lines: Vec<usize>,
    /// The 1-based line of each face.
    pub face_lines: Vec<usize>,
    /// The `g` and `o` groups, in order of first appearance.
    pub groups: Vec<MeshGroup>,
}

/// Reads and validates an OBJ file.
///
/// # Errors
/// [`ObjError::Read`] if the file cannot be read, otherwise as [`parse_obj`].
pub fn read_obj(path: &Path) -> Result<ObjMesh, ObjError> {
    let text = std::fs::read_to_string(path).map_err(|source| ObjError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    parse_obj(&text, path)
}

/// Parses and validates OBJ text; `path` is only used in messages.
///
/// # Errors
/// [`ObjError::Parse`] for malformed statements or indices, [`ObjError::NonTriangle`],
/// [`ObjError::Empty`], [`ObjError::DegenerateFace`], [`ObjError::UnreferencedVertex`],
/// [`ObjError::NonManifoldEdge`] and [`ObjError::DuplicateFace`], each with the line concerned.
pub fn parse_obj(text: &str, path: &Path) -> Result<ObjMesh, ObjError> {
    let parse_error = |line: usize, reason: String| ObjError::Parse {
        path: path.to_path_buf(),
        line,
        reason,
    };
    let statements = Statements::read(text, path, &parse_error)?;
    if statements.faces.is_empty() {
        return Err(ObjError::Empty {
            path: path.to_path_buf(),
        });
    }
    let elements = statements.elements(&parse_error)?;
    let face_lines = statements.faces.iter().map(|&(_, line)| line).collect();
    let groups = statements
        .groups
        .into_iter()
        .filter(|(_, faces)| !faces.is_empty())
        .map(|(name, faces)| {
            let mut vertices: Vec<usize> = faces.iter().flat_map(|&f| elements[f]).collect();
            vertices.sort_unstable();
            vertices.dedup();
            MeshGroup { name, dim: 2, vertices }
        })
        .collect();
    let mesh = TriMesh {
        nodes: statements.nodes,
        elements,
    };
    let obj = ObjMesh {
        mesh,
        vertex_lines: statements.vertex_lines,
        face_lines,
        groups,
    };
    obj.check(path)?;
    Ok(obj)
}

/// What the statements of an OBJ file define, before the faces' indices are checked.
struct Statements {
    nodes: Vec<Vector3<f64>>,
    /// The 1-based line of each vertex.
    vertex_lines: Vec<usize>,
    /// Faces as raw indices (positive 1-based or already resolved relative ones) with their lines.
    faces: Vec<([i64; 3], usize)>,
    /// Group names, and per group the faces in it.
    groups: Vec<(String, Vec<usize>)>,
}

impl Statements {
    /// The `v`, `f`, `g` and `o` statements of the text, in order; `l` and `p` are refused.
    fn read(text: &str, path: &Path, parse_error: &dyn Fn(usize, String) -> ObjError) -> Result<Self, ObjError> {
        let mut out = Self {
            nodes: Vec::new(),
            vertex_lines: Vec::new(),
            faces: Vec::new(),
            groups: Vec::new(),
        };
        // The groups that the following faces belong to.
        let mut current: Vec<usize> = Vec::new();
        for (k, raw_line) in text.lines().enumerate() {
            let line = k + 1;
            let content = raw_line.split('#').next().unwrap_or("");
            let mut words = content.split_whitespace();
            let Some(keyword) = words.next() else { continue };
            match keyword {
                "v" => {
                    out.nodes.push(parse_vertex(words, line, parse_error)?);
                    out.vertex_lines.push(line);
                }
                "f" => {
                    let face = parse_face(words, line, out.nodes.len(), out.faces.len(), path, parse_error)?;
                    for &g in &current {
                        out.groups[g].1.push(out.faces.len());
                    }
                    out.faces.push((face, line));
                }
                "g" | "o" => {
                    current = words.filter(|name| *name != "default").map(|name| out.group(name)).collect();
                }
                "l" | "p" => {
                    return Err(parse_error(
                        line,
                        format!("`{keyword}` elements (lines, points) are not supported in a shell mesh"),
                    ));
                }
                _ => {}
            }
        }
        Ok(out)
    }

    /// The index of the group of this name, added if new.
    fn group(&mut self, name: &str) -> usize {
        match self.groups.iter().position(|(n, _)| n == name) {
            Some(g) => g,
            None => {
                self.groups.push((name.to_string(), Vec::new()));
                self.groups.len() - 1
            }
        }
    }

    /// The faces as 0-based vertex indices, each checked to name an existing vertex.
    fn elements(&self, parse_error: &dyn Fn(usize, String) -> ObjError) -> Result<Vec<[usize; 3]>, ObjError> {
        let n_vertices = self.nodes.len();
        let mut elements = Vec::with_capacity(self.faces.len());
        for (face, line) in &self.faces {
            let mut element = [0; 3];
            for (slot, &i) in element.iter_mut().zip(face) {
                if i as usize > n_vertices {
                    return Err(parse_error(
                        *line,
                        format!("vertex {i} does not exist: the file has {n_vertices} vertices"),
                    ));
                }
                *slot = i as usize - 1;
            }
            elements.push(element);
        }
        Ok(elements)
    }
}

/// The coordinates of a `v` statement: `x y z`, optionally followed by the weight `w`, by a colour
/// `r g b`, or by both (`x y z w r g b`).
fn parse_vertex<'a>(
    words: impl Iterator<Item = &'a str>,
    line: usize,
    parse_error: &dyn Fn(usize, String) -> ObjError,
) -> Result<Vector3<f64>, ObjError> {
    let coords: Vec<&str> = words.collect();
    let number = |word: &str| word.parse::<f64>().ok().filter(|v| v.is_finite());
    let weight = match coords.len() {
        0..3 => {
            return Err(parse_error(
                line,
                format!("a vertex needs 3 coordinates, found {}", coords.len()),
            ));
        }
        3 | 6 => None,
        4 | 7 => Some(coords[3]),
        // With 5 or more than 7 numbers, which of them is the weight is a guess.
        n => {
            return Err(parse_error(
                line,
                format!("a vertex is `v x y z`, with an optional weight `w` and colour `r g b`; found {n} values"),
            ));
        }
    };
    let mut p = [0.0; 3];
    for (c, word) in p.iter_mut().zip(&coords) {
        *c = number(word).ok_or_else(|| parse_error(line, format!("`{word}` is not a finite coordinate")))?;
    }
    if let Some(word) = weight {
        let w = number(word).ok_or_else(|| parse_error(line, format!("`{word}` is not a finite weight")))?;
        // Exporters write w = 1 (the default); any other weight makes the vertex rational.
        if (w - 1.0).abs() > 1e-12 {
            return Err(parse_error(
                line,
                format!(
                    "the vertex has the weight w = {}; only w = 1 is supported (a rational vertex cannot be a \
                     node of a triangle mesh)",
                    Num(w)
                ),
            ));
        }
    }
    Ok(Vector3::from(p))
}

/// The 1-based vertex indices of an `f` statement (relative indices resolved against the `n_vertices`
/// defined so far); the face must be a triangle.
fn parse_face<'a>(
    words: impl Iterator<Item = &'a str>,
    line: usize,
    n_vertices: usize,
    face: usize,
    path: &Path,
    parse_error: &dyn Fn(usize, String) -> ObjError,
) -> Result<[i64; 3], ObjError> {
    let corners: Vec<&str> = words.collect();
    if corners.len() != 3 {
        return Err(ObjError::NonTriangle {
            path: path.to_path_buf(),
            line,
            face,
            n_vertices: corners.len(),
        });
    }
    let mut out = [0_i64; 3];
    for (slot, corner) in out.iter_mut().zip(&corners) {
        let index_text = corner.split('/').next().unwrap_or("");
        let index: i64 = index_text
            .parse()
            .map_err(|_| parse_error(line, format!("`{corner}` is not a vertex reference")))?;
        *slot = match index {
            0 => return Err(parse_error(line, "vertex indices start at 1; 0 is not valid".into())),
            i if i < 0 => {
                // Relative to the vertices defined so far.
                let resolved = n_vertices as i64 + i + 1;
                if resolved < 1 {
                    return Err(parse_error(
                        line,
                        format!("relative index {i} reaches before the first vertex"),
                    ));
                }
                resolved
            }
            i => i,
        };
    }
    Ok(out)
}

impl ObjMesh {
    /// Degenerate faces, unreferenced vertices, non-manifold edges and doubled faces, in that order.
    fn check(&self, path: &Path) -> Result<(), ObjError> {
        let path_buf = || path.to_path_buf();
        self.mesh.check_degenerate().map_err(|e| match e {
            MeshError::DegenerateElement { elem_idx, area } => ObjError::DegenerateFace {
                path: path_buf(),
                line: self.face_lines[elem_idx],
                face: elem_idx,
                area,
            },
            source => ObjError::Mesh {
                path: path_buf(),
                source,
            },
        })?;
        self.mesh.check_unreferenced().map_err(|e| match e {
            MeshError::UnreferencedNode { node_idx } => ObjError::UnreferencedVertex {
                path: path_buf(),
                line: self.vertex_lines[node_idx],
                vertex: node_idx,
            },
            source => ObjError::Mesh {
                path: path_buf(),
                source,
            },
        })?;
        self.mesh.check_manifold_edges().map_err(|e| match e {
            MeshError::NonManifoldEdge { a, b, n_faces } => {
                let has_edge = |f: &[usize; 3]| f.contains(&a) && f.contains(&b);
                let third = self.mesh.elements.iter().enumerate().filter(|(_, f)| has_edge(f)).nth(2);
                ObjError::NonManifoldEdge {
                    path: path_buf(),
                    line: third.map_or(0, |(f, _)| self.face_lines[f]),
                    a,
                    b,
                    n_faces,
                }
            }
            MeshError::DuplicateElement { first, second } => ObjError::DuplicateFace {
                path: path_buf(),
                line: self.face_lines[second],
                face: second,
                first_line: self.face_lines[first],
                first,
            },
            source => ObjError::Mesh {
                path: path_buf(),
                source,
            },
        })
    }
}

impl ObjMesh {
    /// The mesh with every vertex within `tolerance` \[m\] of an earlier one merged into it (vertex
    /// order kept, later duplicates removed, faces renumbered), and the number of vertices merged.
    ///
    /// # Errors
    /// [`ObjError::DegenerateFace`] if merging collapses a face, and the other checks of
    /// [`parse_obj`] on the welded mesh.
    pub fn welded(&self, tolerance: f64, path: &Path) -> Result<(ObjMesh, usize), ObjError> {
        let nodes = &self.mesh.nodes;
        let cell = |p: &Vector3<f64>| p.map(|c| (c / tolerance).floor() as i64);
        let mut grid: HashMap<Vector3<i64>, Vec<usize>> = HashMap::new();
        let mut target = vec![usize::MAX; nodes.len()];
        let mut kept: Vec<usize> = Vec::new();
        for (i, p) in nodes.iter().enumerate() {
            let c = cell(p);
            let near = (-1..=1)
                .flat_map(|dx| (-1..=1).flat_map(move |dy| (-1..=1).map(move |dz| c + Vector3::new(dx, dy, dz))))
                .filter_map(|c| grid.get(&c))
                .flatten()
                .copied()
                .find(|&k| (nodes[kept[k]] - p).norm() <= tolerance);
            target[i] = match near {
                Some(k) => k,
                None => {
                    kept.push(i);
                    grid.entry(c).or_default().push(kept.len() - 1);
                    kept.len() - 1
                }
            };
        }
        let merged = nodes.len() - kept.len();
        let elements: Vec<[usize; 3]> = self.mesh.elements.iter().map(|f| f.map(|v| target[v])).collect();
        if let Some(face) = elements.iter().position(|f| f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) {
            return Err(ObjError::DegenerateFace {
                path: path.to_path_buf(),
                line: self.face_lines[face],
                face,
                area: 0.0,
            });
        }
        let welded = ObjMesh {
            mesh: TriMesh {
                nodes: kept.iter().map(|&i| nodes[i]).collect(),
                elements,
            },
            vertex_lines: kept.iter().map(|&i| self.vertex_lines[i]).collect(),
            face_lines: self.face_lines.clone(),
            groups: self
                .groups
                .iter()
                .map(|g| {
                    let mut vertices: Vec<usize> = g.vertices.iter().map(|&v| target[v]).collect();
                    vertices.sort_unstable();
                    vertices.dedup();
                    MeshGroup { vertices, ..g.clone() }
                })
                .collect(),
        };
        welded.check(path)?;
        Ok((welded, merged))
    }

    /// What the file does that is allowed but probably not meant: vertices at the same position
    /// (the surface is split there) and bowtie vertices, each with its line.
    pub fn warnings(&self, path: &Path) -> Vec<String> {
        let mut warnings = Vec::new();
        let coincident = self.coincident_vertices();
        if let Some(&(first, duplicate)) = coincident.first() {
            warnings.push(format!(
                "`{}`: {} vertices lie exactly on earlier ones (first: line {} on line {}), so the surface is split \
                 into pieces along them; merge them with `weld = <distance>` in the mesh section if they are one \
                 surface",
                path.display(),
                coincident.len(),
                self.vertex_lines[duplicate],
                self.vertex_lines[first]
            ));
        }
        let bowties = self.bowtie_vertices();
        if let Some(&v) = bowties.first() {
            warnings.push(format!(
                "`{}`: {} vertices join faces that share no edge there (first: line {}), like a bowtie; the shell \
                 can turn freely about such a vertex",
                path.display(),
                bowties.len(),
                self.vertex_lines[v]
            ));
        }
        warnings
    }

    /// Pairs `(earlier, later)` of distinct vertices at the same position.
    fn coincident_vertices(&self) -> Vec<(usize, usize)> {
        let mut seen: HashMap<[u64; 3], usize> = HashMap::new();
        let mut pairs = Vec::new();
        for (i, p) in self.mesh.nodes.iter().enumerate() {
            // `+ 0.0` makes −0 and +0 one key.
            let key = [p.x + 0.0, p.y + 0.0, p.z + 0.0].map(f64::to_bits);
            match seen.get(&key) {
                Some(&first) => pairs.push((first, i)),
                None => {
                    seen.insert(key, i);
                }
            }
        }
        pairs
    }

    /// Vertices whose faces form more than one fan (groups of faces joined through edges at the vertex).
    fn bowtie_vertices(&self) -> Vec<usize> {
        let mut faces_at: Vec<Vec<usize>> = vec![Vec::new(); self.mesh.nodes.len()];
        for (f, face) in self.mesh.elements.iter().enumerate() {
            for &v in face {
                faces_at[v].push(f);
            }
        }
        let mut bowties = Vec::new();
        for (v, faces) in faces_at.iter().enumerate() {
            // Union the faces around `v` that share one of its edges, then count the groups.
            let mut group: Vec<usize> = (0..faces.len()).collect();
            fn root(group: &mut [usize], mut i: usize) -> usize {
                while group[i] != i {
                    group[i] = group[group[i]];
                    i = group[i];
                }
                i
            }
            for a in 0..faces.len() {
                for b in a + 1..faces.len() {
                    let (fa, fb) = (&self.mesh.elements[faces[a]], &self.mesh.elements[faces[b]]);
                    let shares_edge = fa.iter().any(|&w| w != v && fb.contains(&w));
                    if shares_edge {
                        let (ra, rb) = (root(&mut group, a), root(&mut group, b));
                        group[ra] = rb;
                    }
                }
            }
            let fans = (0..faces.len()).filter(|&i| root(&mut group, i) == i).count();
            if fans > 1 {
                bowties.push(v);
            }
        }
        bowties
    }
}
