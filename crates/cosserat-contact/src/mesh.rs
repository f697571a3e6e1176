//! The contact geometry: shell surfaces and obstacles merged into one set of contact vertices, edges and
//! triangles, each tagged with the body it belongs to.
//!
//! Shell surfaces are given as triangles over global displacement nodes (the unknowns); obstacles as
//! their own vertex positions and triangles (not unknowns, static or moved per step). Contact vertices
//! number the surface nodes first (in order of first appearance), then the obstacle vertices, so a
//! contact vertex below [`ContactMesh::n_node_vertices`] is a displacement node.

use crate::barrier::non_negative;
use crate::error::ContactError;
use nalgebra::Vector3;
use std::collections::BTreeMap;

/// The contact surface of a shell: flat triangles over its global displacement nodes.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactSurface {
    /// Surface id, used to look up friction coefficients (shared ids share coefficients).
    pub id: usize,
    /// Triangles as global displacement-node triples.
    pub triangles: Vec<[usize; 3]>,
    /// Contact thickness \[m\]: pairs with another body are separated by the sum of both thicknesses.
    pub thickness: f64,
}

/// A triangle mesh whose vertices are not unknowns: static, or kinematic with positions set per step.
#[derive(Debug, Clone, PartialEq)]
pub struct Obstacle {
    /// Surface id, used to look up friction coefficients.
    pub id: usize,
    /// Vertex positions at the start \[m\].
    pub positions: Vec<Vector3<f64>>,
    /// Triangles as local vertex triples.
    pub triangles: Vec<[usize; 3]>,
    /// Contact thickness \[m\].
    pub thickness: f64,
}

/// Where a contact vertex comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum VertexSource {
    /// A global displacement node.
    Node(usize),
    /// Vertex `vertex` of obstacle `obstacle`.
    Obstacle {
        /// The obstacle.
        obstacle: usize,
        /// Its local vertex.
        vertex: usize,
    },
}

/// A body of the contact geometry: a shell surface or an obstacle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Body {
    /// The surface id (friction lookup).
    pub id: usize,
    /// Contact thickness \[m\].
    pub thickness: f64,
    /// Whether the body is an obstacle (its vertices are not unknowns).
    pub is_obstacle: bool,
}

/// All contact primitives of a system.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactMesh {
    vertices: Vec<VertexSource>,
    vertex_body: Vec<u32>,
    triangles: Vec<[u32; 3]>,
    triangle_body: Vec<u32>,
    edges: Vec<[u32; 2]>,
    edge_body: Vec<u32>,
    bodies: Vec<Body>,
    n_node_vertices: usize,
}

impl ContactMesh {
    /// Merges shell surfaces (over `n_nodes` displacement nodes) and obstacles.
    ///
    /// # Errors
    /// Out-of-range or repeated vertices in a triangle, a node in two surfaces, a negative or
    /// non-finite thickness, a non-finite obstacle position.
    pub fn try_new(surfaces: &[ContactSurface], obstacles: &[Obstacle], n_nodes: usize) -> Result<Self, ContactError> {
        let mut mesh = Self {
            vertices: Vec::new(),
            vertex_body: Vec::new(),
            triangles: Vec::new(),
            triangle_body: Vec::new(),
            edges: Vec::new(),
            edge_body: Vec::new(),
            bodies: Vec::with_capacity(surfaces.len() + obstacles.len()),
            n_node_vertices: 0,
        };
        mesh.add_surfaces(surfaces, n_nodes)?;
        mesh.n_node_vertices = mesh.vertices.len();
        for (o, obstacle) in obstacles.iter().enumerate() {
            mesh.add_obstacle(o, obstacle)?;
        }
        mesh.collect_edges();
        Ok(mesh)
    }

    /// The shell surfaces' bodies, vertices (one per displacement node, in order of first use) and
    /// triangles.
    fn add_surfaces(&mut self, surfaces: &[ContactSurface], n_nodes: usize) -> Result<(), ContactError> {
        let mut node_vertex: BTreeMap<usize, (u32, usize)> = BTreeMap::new();
        for (s, surface) in surfaces.iter().enumerate() {
            non_negative("surface.thickness", surface.thickness)?;
            self.bodies.push(Body {
                id: surface.id,
                thickness: surface.thickness,
                is_obstacle: false,
            });
            for (t, tri) in surface.triangles.iter().enumerate() {
                check_triangle("surface", s, t, tri, n_nodes)?;
                let mut local = [0u32; 3];
                for (k, &node) in tri.iter().enumerate() {
                    let entry = node_vertex.entry(node).or_insert_with(|| {
                        self.vertices.push(VertexSource::Node(node));
                        self.vertex_body.push(s as u32);
                        ((self.vertices.len() - 1) as u32, s)
                    });
                    if entry.1 != s {
                        return Err(ContactError::NodeInTwoSurfaces {
                            node,
                            first: entry.1,
                            second: s,
                        });
                    }
                    local[k] = entry.0;
                }
                self.triangles.push(local);
                self.triangle_body.push(s as u32);
            }
        }
        Ok(())
    }

    /// Obstacle `o`'s body, vertices and triangles.
    fn add_obstacle(&mut self, o: usize, obstacle: &Obstacle) -> Result<(), ContactError> {
        non_negative("obstacle.thickness", obstacle.thickness)?;
        if let Some(v) = obstacle.positions.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
            return Err(ContactError::NonFinite {
                what: "obstacle position",
                vertex: v,
            });
        }
        let body = self.bodies.len() as u32;
        self.bodies.push(Body {
            id: obstacle.id,
            thickness: obstacle.thickness,
            is_obstacle: true,
        });
        let first = self.vertices.len() as u32;
        for v in 0..obstacle.positions.len() {
            self.vertices.push(VertexSource::Obstacle { obstacle: o, vertex: v });
            self.vertex_body.push(body);
        }
        for (t, tri) in obstacle.triangles.iter().enumerate() {
            check_triangle("obstacle", o, t, tri, obstacle.positions.len())?;
            self.triangles.push(tri.map(|v| first + v as u32));
            self.triangle_body.push(body);
        }
        Ok(())
    }

    /// The triangles' edges, each once (sorted by its vertices), with the body of its first triangle.
    fn collect_edges(&mut self) {
        let mut edge_set: BTreeMap<[u32; 2], u32> = BTreeMap::new();
        for (tri, &body) in self.triangles.iter().zip(&self.triangle_body) {
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                edge_set.entry([a.min(b), a.max(b)]).or_insert(body);
            }
        }
        (self.edges, self.edge_body) = edge_set.into_iter().unzip();
    }

    /// Number of contact vertices.
    pub fn n_vertices(&self) -> usize {
        self.vertices.len()
    }

    /// Number of contact vertices that are displacement nodes (they come first).
    pub fn n_node_vertices(&self) -> usize {
        self.n_node_vertices
    }

    /// Where each contact vertex comes from.
    pub fn vertices(&self) -> &[VertexSource] {
        &self.vertices
    }

    /// The triangles (contact vertex triples), surfaces first.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// The unique edges (sorted contact vertex pairs), in lexicographic order.
    pub fn edges(&self) -> &[[u32; 2]] {
        &self.edges
    }

    /// The bodies: surfaces in the given order, then obstacles.
    pub fn bodies(&self) -> &[Body] {
        &self.bodies
    }

    /// The body of contact vertex `v`.
    #[inline]
    pub fn vertex_body(&self, v: usize) -> usize {
        self.vertex_body[v] as usize
    }

    /// The body of triangle `t`.
    #[inline]
    pub fn triangle_body(&self, t: usize) -> usize {
        self.triangle_body[t] as usize
    }

    /// The body of edge `e`.
    #[inline]
    pub fn edge_body(&self, e: usize) -> usize {
        self.edge_body[e] as usize
    }

    /// The displacement node of contact vertex `v`, if it is one.
    #[inline]
    pub fn node(&self, v: usize) -> Option<usize> {
        match self.vertices[v] {
            VertexSource::Node(i) => Some(i),
            VertexSource::Obstacle { .. } => None,
        }
    }

    /// Contact vertex positions: nodes from `node_position`, obstacle vertices from
    /// `obstacle_position(obstacle, vertex)`.
    pub fn positions(
        &self,
        node_position: impl Fn(usize) -> Vector3<f64>,
        obstacle_position: impl Fn(usize, usize) -> Vector3<f64>,
    ) -> Vec<Vector3<f64>> {
        self.vertices
            .iter()
            .map(|v| match *v {
                VertexSource::Node(i) => node_position(i),
                VertexSource::Obstacle { obstacle, vertex } => obstacle_position(obstacle, vertex),
            })
            .collect()
    }
}

fn check_triangle(
    body: &'static str,
    body_idx: usize,
    tri_idx: usize,
    tri: &[usize; 3],
    n_vertices: usize,
) -> Result<(), ContactError> {
    if let Some(&vertex) = tri.iter().find(|&&v| v >= n_vertices) {
        return Err(ContactError::VertexOutOfRange {
            body,
            body_idx,
            tri_idx,
            vertex,
            n_vertices,
        });
    }
    if tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] {
        return Err(ContactError::RepeatedVertex {
            body,
            body_idx,
            tri_idx,
            vertices: *tri,
        });
    }
    Ok(())
}
