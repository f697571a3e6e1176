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
    let bodies = mesh.bodies();
    let inflation = |body: usize| bodies[body].thickness + 0.5 * reach;
    let tri_boxes: Vec<Aabb> = mesh
        .triangles()
        .iter()
        .enumerate()
        .map(|(t, tri)| swept_box(tri, start, end, inflation(mesh.triangle_body(t))))
        .collect();
    let edge_boxes: Vec<Aabb> = mesh
        .edges()
        .iter()
        .enumerate()
        .map(|(e, edge)| swept_box(edge, start, end, inflation(mesh.edge_body(e))))
        .collect();
    let (tri_bvh, edge_bvh) = match par {
        Parallelism::Sequential => (Bvh::build(tri_boxes), Bvh::build(edge_boxes.clone())),
        Parallelism::Rayon => rayon::join(|| Bvh::build(tri_boxes), || Bvh::build(edge_boxes.clone())),
    };
    let point_triangle = map_collect(mesh.n_vertices(), par, |v, buffers, out| {
        let body = mesh.vertex_body(v);
        let b = swept_box(&[v as u32], start, end, inflation(body));
        buffers.hits.clear();
        tri_bvh.query_with(&b, &mut buffers.hits, &mut buffers.stack);
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
        edge_bvh.query_with(&edge_boxes[e], &mut buffers.hits, &mut buffers.stack);
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
