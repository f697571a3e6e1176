//! The broad phase: point–triangle and edge–edge pairs that can come within their contact distance
//! during a linear motion of all contact vertices.
//!
//! Each primitive's box covers its positions at the start and the end of the motion (hence every
//! intermediate position, by convexity) and is inflated by its body's thickness plus half the extra
//! reach `r`. Two such boxes that do not overlap are more than `δ + r` apart in the maximum norm, hence
//! in the Euclidean norm, at every instant of the motion: the candidate set contains every pair that
//! gets within `δ + r`. Pairs whose primitives share a vertex (a triangle's own vertices, edges with a
//! common endpoint) and pairs between two obstacles are excluded.
//!
//! Queries run in parallel over the query primitives and are concatenated in primitive order, with the
//! hits of each query sorted, so the result is the same sorted list for any number of threads.

use crate::bvh::{Aabb, Bvh};
use crate::mesh::ContactMesh;
use cosserat_assembly::Parallelism;
use nalgebra::Vector3;
use rayon::prelude::*;

/// Candidate pairs in contact vertex, triangle and edge indices of a [`ContactMesh`], sorted.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct CandidatePairs {
    /// `[vertex, triangle]` pairs, sorted lexicographically.
    pub point_triangle: Vec<[u32; 2]>,
    /// `[edge_a, edge_b]` pairs with `edge_a < edge_b`, sorted lexicographically.
    pub edge_edge: Vec<[u32; 2]>,
}

impl CandidatePairs {
    /// Total number of pairs.
    pub fn len(&self) -> usize {
        self.point_triangle.len() + self.edge_edge.len()
    }

    /// Whether there are no pairs.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

fn swept_box(vertices: &[u32], start: &[Vector3<f64>], end: &[Vector3<f64>], r: f64) -> Aabb {
    let mut b = Aabb::empty();
    for &v in vertices {
        b.grow(&start[v as usize]);
        b.grow(&end[v as usize]);
    }
    b.inflated(r)
}

/// Queries per parallel task: each task reuses one set of buffers and returns one list.
const QUERY_CHUNK: usize = 512;

/// Reusable buffers of one task of queries: BVH hits and the traversal stack.
#[derive(Default)]
struct QueryBuffers {
    hits: Vec<u32>,
    stack: Vec<u32>,
}

/// `f(i, buffers, out)` for `i in 0..n`, in chunks (in parallel with `Rayon`), with the outputs
/// concatenated in increasing `i` whatever the number of threads.
fn map_collect<T: Send>(
    n: usize,
    par: Parallelism,
    f: impl Fn(usize, &mut QueryBuffers, &mut Vec<T>) + Sync + Send,
) -> Vec<T> {
    let chunk = |c: usize| {
        let mut buffers = QueryBuffers::default();
        let mut out = Vec::new();
        for i in c * QUERY_CHUNK..((c + 1) * QUERY_CHUNK).min(n) {
            f(i, &mut buffers, &mut out);
        }
        out
    };
    let n_chunks = n.div_ceil(QUERY_CHUNK);
    let parts: Vec<Vec<T>> = match par {
        Parallelism::Sequential => (0..n_chunks).map(chunk).collect(),
        Parallelism::Rayon => (0..n_chunks).into_par_iter().map(chunk).collect(),
    };
    parts.into_iter().flatten().collect()
}

/// Swept, inflated boxes of every point, triangle and edge of a [`ContactMesh`] over one motion.
#[derive(Debug, Clone, Default)]
pub(crate) struct PrimitiveBoxes {
    pub points: Vec<Aabb>,
    pub triangles: Vec<Aabb>,
    pub edges: Vec<Aabb>,
}

impl PrimitiveBoxes {
    /// The boxes of every primitive moving linearly from `start` to `end`, each inflated by
    /// `inflation(thickness)` of its body.
    pub fn new(
        mesh: &ContactMesh,
        start: &[Vector3<f64>],
        end: &[Vector3<f64>],
        inflation: impl Fn(f64) -> f64,
    ) -> Self {
        let bodies = mesh.bodies();
        let r = |body: usize| inflation(bodies[body].thickness);
        Self {
            points: (0..mesh.n_vertices())
                .map(|v| swept_box(&[v as u32], start, end, r(mesh.vertex_body(v))))
                .collect(),
            triangles: mesh
                .triangles()
                .iter()
                .enumerate()
                .map(|(t, tri)| swept_box(tri, start, end, r(mesh.triangle_body(t))))
                .collect(),
            edges: mesh
                .edges()
                .iter()
                .enumerate()
                .map(|(e, edge)| swept_box(edge, start, end, r(mesh.edge_body(e))))
                .collect(),
        }
    }
}

/// All pairs of `mesh` that can get within their thickness sum plus `reach` \[m\] while each contact
/// vertex moves linearly from `start` to `end`.
///
/// # Panics
/// If `start` or `end` does not have one position per contact vertex (programmer error).
#[track_caller]
pub fn candidate_pairs(
    mesh: &ContactMesh,
    start: &[Vector3<f64>],
    end: &[Vector3<f64>],
    reach: f64,
    par: Parallelism,
) -> CandidatePairs {
    assert_eq!(start.len(), mesh.n_vertices(), "one start position per contact vertex");
    assert_eq!(end.len(), mesh.n_vertices(), "one end position per contact vertex");
    let boxes = PrimitiveBoxes::new(mesh, start, end, |thickness| thickness + 0.5 * reach);
    let (tri_bvh, edge_bvh) = match par {
        Parallelism::Sequential => (Bvh::build(boxes.triangles.clone()), Bvh::build(boxes.edges.clone())),
        Parallelism::Rayon => rayon::join(
            || Bvh::build(boxes.triangles.clone()),
            || Bvh::build(boxes.edges.clone()),
        ),
    };
    overlapping_pairs(mesh, &tri_bvh, &edge_bvh, &boxes, par)
}

/// The pairs whose boxes overlap: every point's box queried in `triangles` (a hierarchy over
/// `boxes.triangles`) and every edge's box in `edges` (over `boxes.edges`), without the excluded pairs.
pub(crate) fn overlapping_pairs(
    mesh: &ContactMesh,
    triangles: &Bvh,
    edges: &Bvh,
    boxes: &PrimitiveBoxes,
    par: Parallelism,
) -> CandidatePairs {
    let bodies = mesh.bodies();
    let point_triangle = map_collect(mesh.n_vertices(), par, |v, buffers, out| {
        let body = mesh.vertex_body(v);
        buffers.hits.clear();
        triangles.query_with(&boxes.points[v], &mut buffers.hits, &mut buffers.stack);
        let obstacle = bodies[body].is_obstacle;
        out.extend(
            buffers
                .hits
                .iter()
                .filter(|&&t| {
                    let tri = &mesh.triangles()[t as usize];
                    let both_obstacles = obstacle && bodies[mesh.triangle_body(t as usize)].is_obstacle;
                    !(tri.contains(&(v as u32)) || both_obstacles)
                })
                .map(|&t| [v as u32, t]),
        );
    });
    let edge_edge = map_collect(mesh.edges().len(), par, |e, buffers, out| {
        let ea = mesh.edges()[e];
        let obstacle = bodies[mesh.edge_body(e)].is_obstacle;
        buffers.hits.clear();
        edges.query_with(&boxes.edges[e], &mut buffers.hits, &mut buffers.stack);
        out.extend(
            buffers
                .hits
                .iter()
                .filter(|&&f| {
                    let eb = mesh.edges()[f as usize];
                    let shared = eb.contains(&ea[0]) || eb.contains(&ea[1]);
                    let both_obstacles = obstacle && bodies[mesh.edge_body(f as usize)].is_obstacle;
                    f as usize > e && !shared && !both_obstacles
                })
                .map(|&f| [e as u32, f]),
        );
    });
    CandidatePairs {
        point_triangle,
        edge_edge,
    }
}
