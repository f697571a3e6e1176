//! Wavefront OBJ input: triangle surface meshes for shells, read with the file's own vertex numbering
//! and checked before simulation.
//!
//! Only `v` (positions) and `f` (faces) statements matter; normals, texture coordinates, groups,
//! objects, smoothing groups and materials are ignored. Face corners may be written `i`, `i/t`,
//! `i//n` or `i/t/n`, with negative (relative) indices allowed. Every face must be a triangle: the
//! reader does not triangulate, because the triangulation of a polygon is a modelling decision the
//! simulation should not make silently.
//!
//! Why not `tobj`: it renumbers vertices in order of first use per object, silently drops
//! unreferenced vertices and splits a vertex that faces use with different normals or texture
//! coordinates into several. Each of these changes the mesh a scene refers to (vertex lists in
//! regions, seams that would become open boundaries), so this reader keeps the file's vertices and
//! reports problems instead, each with its line:
//! non-triangle faces, degenerate triangles, unreferenced vertices and edges shared by more than two
//! faces ([`cosserat_fem::TriMesh::validate`] does the geometric checks).

use crate::error::ObjError;
use cosserat_fem::{MeshError, Tri3Mesh, TriMesh};
use nalgebra::Vector3;
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
/// [`ObjError::Empty`], [`ObjError::DegenerateFace`], [`ObjError::UnreferencedVertex`] and
/// [`ObjError::NonManifoldEdge`], each with the line concerned.
pub fn parse_obj(text: &str, path: &Path) -> Result<ObjMesh, ObjError> {
    let parse_error = |line: usize, reason: String| ObjError::Parse {
        path: path.to_path_buf(),
        line,
        reason,
    };
    let mut nodes: Vec<Vector3<f64>> = Vec::new();
    let mut vertex_lines = Vec::new();
    // Faces as raw indices (positive 1-based or already resolved relative ones) with their lines.
    let mut raw_faces: Vec<([i64; 3], usize)> = Vec::new();
    for (k, raw_line) in text.lines().enumerate() {
        let line = k + 1;
        let content = raw_line.split('#').next().unwrap_or("");
        let mut words = content.split_whitespace();
        let Some(keyword) = words.next() else { continue };
        match keyword {
            "v" => {
                let coords: Vec<&str> = words.collect();
                if coords.len() < 3 {
                    return Err(parse_error(
                        line,
                        format!("a vertex needs 3 coordinates, found {}", coords.len()),
                    ));
                }
                let mut p = [0.0; 3];
                for (c, word) in p.iter_mut().zip(&coords) {
                    *c = word
                        .parse::<f64>()
                        .ok()
                        .filter(|v| v.is_finite())
                        .ok_or_else(|| parse_error(line, format!("`{word}` is not a finite coordinate")))?;
                }
                nodes.push(Vector3::from(p));
                vertex_lines.push(line);
            }
            "f" => {
                let corners: Vec<&str> = words.collect();
                if corners.len() != 3 {
                    return Err(ObjError::NonTriangle {
                        path: path.to_path_buf(),
                        line,
                        face: raw_faces.len(),
                        n_vertices: corners.len(),
                    });
                }
                let mut face = [0_i64; 3];
                for (slot, corner) in face.iter_mut().zip(&corners) {
                    let index_text = corner.split('/').next().unwrap_or("");
                    let index: i64 = index_text
                        .parse()
                        .map_err(|_| parse_error(line, format!("`{corner}` is not a vertex reference")))?;
                    *slot = match index {
                        0 => return Err(parse_error(line, "vertex indices start at 1; 0 is not valid".into())),
                        i if i < 0 => {
                            // Relative to the vertices defined so far.
                            let resolved = nodes.len() as i64 + i + 1;
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
                raw_faces.push((face, line));
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
    if raw_faces.is_empty() {
        return Err(ObjError::Empty {
            path: path.to_path_buf(),
        });
    }
    let n_vertices = nodes.len();
    let mut elements = Vec::with_capacity(raw_faces.len());
    let mut face_lines = Vec::with_capacity(raw_faces.len());
    for (face, line) in &raw_faces {
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
        face_lines.push(*line);
    }
    let mesh = TriMesh { nodes, elements };
    let obj = ObjMesh {
        mesh,
        vertex_lines,
        face_lines,
    };
    obj.check(path)?;
    Ok(obj)
}

impl ObjMesh {
    /// Degenerate faces, unreferenced vertices and non-manifold edges, in that order.
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
            source => ObjError::Mesh {
                path: path_buf(),
                source,
            },
        })
    }
}
