//! Triangle–triangle intersection: a geometric test (no distance threshold) for checking that a
//! configuration is free of intersections.
//!
//! Two closed triangles that are not coplanar intersect exactly when an edge of one meets the other
//! (the intersection is a segment whose endpoints lie on edges of the triangles). Each edge–triangle
//! test uses orientation predicates (signed volumes): the edge must touch or straddle the triangle's
//! plane, and the line through it must pass inside or on the triangle's three edges. Coplanar pairs are
//! decided in 2D (edge crossings and containment). Every predicate is the sign of a determinant
//! evaluated in floating point with a forward error bound (Shewchuk's static filter, slightly widened);
//! when the bound cannot decide the sign it counts as zero, i.e. as touching. Since zeros only ever
//! widen the intersection conditions, the test has no false negatives: configurations within round-off
//! of touching are reported as intersecting.

use crate::bvh::{Aabb, Bvh};
use nalgebra::{Vector2, Vector3};
use rayon::prelude::*;

const ORIENT_ERROR: f64 = 1e-15;

/// The sign of `(a − d)·((b − d) × (c − d))`, or 0 if round-off could change it.
fn orient3d(a: &Vector3<f64>, b: &Vector3<f64>, c: &Vector3<f64>, d: &Vector3<f64>) -> i8 {
    let (ad, bd, cd) = (a - d, b - d, c - d);
    let det =
        ad.x * (bd.y * cd.z - bd.z * cd.y) + bd.x * (cd.y * ad.z - cd.z * ad.y) + cd.x * (ad.y * bd.z - ad.z * bd.y);
    let permanent = ad.x.abs() * ((bd.y * cd.z).abs() + (bd.z * cd.y).abs())
        + bd.x.abs() * ((cd.y * ad.z).abs() + (cd.z * ad.y).abs())
        + cd.x.abs() * ((ad.y * bd.z).abs() + (ad.z * bd.y).abs());
    sign(det, ORIENT_ERROR * permanent)
}

/// The sign of `(a − c) × (b − c)` in 2D, or 0 if round-off could change it.
fn orient2d(a: &Vector2<f64>, b: &Vector2<f64>, c: &Vector2<f64>) -> i8 {
    let (ac, bc) = (a - c, b - c);
    let l = ac.x * bc.y;
    let r = ac.y * bc.x;
    sign(l - r, ORIENT_ERROR * (l.abs() + r.abs()))
}

fn sign(det: f64, bound: f64) -> i8 {
    if det > bound {
        1
    } else if det < -bound {
        -1
    } else {
        0
    }
}

/// Whether three signs are all ≥ 0 or all ≤ 0.
fn same_side(s: [i8; 3]) -> bool {
    s.iter().all(|&x| x >= 0) || s.iter().all(|&x| x <= 0)
}

/// Whether the closed 2D segments `[p₀, p₁]` and `[q₀, q₁]` meet.
fn segments_meet_2d(p: [&Vector2<f64>; 2], q: [&Vector2<f64>; 2]) -> bool {
    let o = [
        orient2d(p[0], p[1], q[0]),
        orient2d(p[0], p[1], q[1]),
        orient2d(q[0], q[1], p[0]),
        orient2d(q[0], q[1], p[1]),
    ];
    if o[0] * o[1] < 0 && o[2] * o[3] < 0 {
        return true;
    }
    let within = |a: &Vector2<f64>, b: &Vector2<f64>, x: &Vector2<f64>| {
        (0..2).all(|k| x[k] >= a[k].min(b[k]) && x[k] <= a[k].max(b[k]))
    };
    (o[0] == 0 && within(p[0], p[1], q[0]))
        || (o[1] == 0 && within(p[0], p[1], q[1]))
        || (o[2] == 0 && within(q[0], q[1], p[0]))
        || (o[3] == 0 && within(q[0], q[1], p[1]))
}

/// Whether `x` lies in the closed 2D triangle `t` (false for a degenerate triangle, whose edges the
/// caller tests instead).
fn inside_2d(t: &[Vector2<f64>; 3], x: &Vector2<f64>) -> bool {
    orient2d(&t[0], &t[1], &t[2]) != 0
        && same_side([
            orient2d(&t[0], &t[1], x),
            orient2d(&t[1], &t[2], x),
            orient2d(&t[2], &t[0], x),
        ])
}

/// The two coordinates kept when projecting along the dominant axis of `n`.
fn projection_axes(n: &Vector3<f64>) -> (usize, usize) {
    let a = n.abs();
    if a.x >= a.y && a.x >= a.z {
        (1, 2)
    } else if a.y >= a.z {
        (2, 0)
    } else {
        (0, 1)
    }
}

fn project(points: &[&Vector3<f64>], axes: (usize, usize)) -> Vec<Vector2<f64>> {
    points.iter().map(|p| Vector2::new(p[axes.0], p[axes.1])).collect()
}

fn plane_normal(t: [&Vector3<f64>; 3], other: [&Vector3<f64>; 3]) -> Vector3<f64> {
    let n = (t[1] - t[0]).cross(&(t[2] - t[0]));
    if n.norm_squared() > 0.0 {
        n
    } else {
        (other[1] - other[0]).cross(&(other[2] - other[0]))
    }
}

/// Whether a closed segment and a closed triangle that lie in one plane meet.
fn coplanar_segment_triangle(p: [&Vector3<f64>; 2], t: [&Vector3<f64>; 3]) -> bool {
    let axes = projection_axes(&plane_normal(t, [t[0], t[1], p[0]]));
    let t2 = project(&t, axes);
    let p2 = project(&p, axes);
    let tri = [t2[0], t2[1], t2[2]];
    inside_2d(&tri, &p2[0])
        || inside_2d(&tri, &p2[1])
        || (0..3).any(|k| segments_meet_2d([&p2[0], &p2[1]], [&tri[k], &tri[(k + 1) % 3]]))
}

/// Whether the closed segment `[p, q]` meets the closed triangle `t`, given the plane signs of `p`, `q`.
fn segment_triangle(p: &Vector3<f64>, q: &Vector3<f64>, t: [&Vector3<f64>; 3], sp: i8, sq: i8) -> bool {
    if sp * sq > 0 {
        return false;
    }
    if sp == 0 && sq == 0 {
        return coplanar_segment_triangle([p, q], t);
    }
    same_side([
        orient3d(p, q, t[0], t[1]),
        orient3d(p, q, t[1], t[2]),
        orient3d(p, q, t[2], t[0]),
    ])
}

fn coplanar_triangles(a: [&Vector3<f64>; 3], b: [&Vector3<f64>; 3]) -> bool {
    let axes = projection_axes(&plane_normal(a, b));
    let a2 = project(&a, axes);
    let b2 = project(&b, axes);
    let (ta, tb) = ([a2[0], a2[1], a2[2]], [b2[0], b2[1], b2[2]]);
    (0..3).any(|i| (0..3).any(|j| segments_meet_2d([&ta[i], &ta[(i + 1) % 3]], [&tb[j], &tb[(j + 1) % 3]])))
        || ta.iter().any(|x| inside_2d(&tb, x))
        || tb.iter().any(|x| inside_2d(&ta, x))
}

/// Whether two closed triangles intersect (touching counts).
pub fn triangles_intersect(a: [&Vector3<f64>; 3], b: [&Vector3<f64>; 3]) -> bool {
    let sb = [
        orient3d(a[0], a[1], a[2], b[0]),
        orient3d(a[0], a[1], a[2], b[1]),
        orient3d(a[0], a[1], a[2], b[2]),
    ];
    if sb.iter().all(|&s| s > 0) || sb.iter().all(|&s| s < 0) {
        return false;
    }
    let sa = [
        orient3d(b[0], b[1], b[2], a[0]),
        orient3d(b[0], b[1], b[2], a[1]),
        orient3d(b[0], b[1], b[2], a[2]),
    ];
    if sa.iter().all(|&s| s > 0) || sa.iter().all(|&s| s < 0) {
        return false;
    }
    if sb.iter().all(|&s| s == 0) || sa.iter().all(|&s| s == 0) {
        return coplanar_triangles(a, b);
    }
    (0..3).any(|k| segment_triangle(a[k], a[(k + 1) % 3], b, sa[k], sa[(k + 1) % 3]))
        || (0..3).any(|k| segment_triangle(b[k], b[(k + 1) % 3], a, sb[k], sb[(k + 1) % 3]))
}

/// All pairs `(s, t)`, `s < t`, of triangles of a mesh that share no vertex and intersect, sorted.
///
/// # Panics
/// If a triangle names a vertex without a position (programmer error).
#[track_caller]
pub fn intersecting_pairs(triangles: &[[usize; 3]], positions: &[Vector3<f64>]) -> Vec<(usize, usize)> {
    let boxes: Vec<Aabb> = triangles
        .iter()
        .map(|t| Aabb::from_points(t.iter().map(|&v| &positions[v])))
        .collect();
    let bvh = Bvh::build(boxes.clone());
    let per_triangle: Vec<Vec<(usize, usize)>> = (0..triangles.len())
        .into_par_iter()
        .with_min_len(64)
        .map(|s| {
            let mut hits = Vec::new();
            bvh.query(&boxes[s], &mut hits);
            let ts = &triangles[s];
            let a = [&positions[ts[0]], &positions[ts[1]], &positions[ts[2]]];
            hits.into_iter()
                .map(|t| t as usize)
                .filter(|&t| t > s && !triangles[t].iter().any(|v| ts.contains(v)))
                .filter(|&t| {
                    let tt = &triangles[t];
                    triangles_intersect(a, [&positions[tt[0]], &positions[tt[1]], &positions[tt[2]]])
                })
                .map(|t| (s, t))
                .collect()
        })
        .collect();
    per_triangle.into_iter().flatten().collect()
}
