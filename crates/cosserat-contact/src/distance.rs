//! Squared distances of point–triangle and edge–edge pairs with classification of the closest features,
//! and their exact first and second derivatives.
//!
//! The distance between a point and a triangle (or between two segments) is the minimum of a convex
//! quadratic over a triangle (a square) of barycentric parameters. If the unconstrained minimiser lies
//! strictly inside, the distance is the point–plane (line–line) distance; otherwise it lies on the
//! boundary, which consists of point–segment problems, each of which is again a point–line or a
//! point–point distance. Classifying first and then evaluating one closed form per feature gives a
//! function that is smooth within each feature's region, C¹ across regions, and finite with finite
//! derivatives in every degenerate case (parallel edges, a point on a triangle's edge or vertex,
//! coincident points, zero-length edges, zero-area triangles): degenerate configurations are routed to
//! the point–segment and point–point forms, which have no singularity.
//!
//! Every closed form is written once, generic over [`Real`], in terms of differences of the points (the
//! generic versions serve `f64` evaluation and, with dual numbers, as the derivative oracle in tests).
//! Gradients and Hessians with respect to those differences (3, 6 or 9 numbers) come from the
//! hand-derived forms of [`crate::closed_form`], checked against the dual pass, and are chained to the
//! pair's twelve coordinates ([`PairJet::from_differences`]).
//!
//! Point order of a pair: point–triangle `[p, t₀, t₁, t₂]`, edge–edge `[a₀, a₁, b₀, b₁]`.

use crate::closed_form;
use crate::jet::PairJet;
use cosserat_geometry::Real;
use nalgebra::{Matrix3, SVector, Vector3};

/// The closest feature of a triangle to a point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum PointTriangleFeature {
    /// Triangle vertex `k` (0, 1 or 2): point–point distance.
    Vertex(usize),
    /// The interior of triangle edge `k`, from vertex `k` to vertex `(k + 1) mod 3`: point–line distance.
    Edge(usize),
    /// The triangle's interior: point–plane distance.
    Face,
}

/// The closest features of two segments `a = [a₀, a₁]` and `b = [b₀, b₁]`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum EdgeEdgeFeature {
    /// Endpoint `i` of `a` and endpoint `j` of `b`: point–point distance.
    VertexVertex(usize, usize),
    /// Endpoint `i` of `a` and the interior of `b`: point–line distance.
    VertexEdge(usize),
    /// The interior of `a` and endpoint `j` of `b`: point–line distance.
    EdgeVertex(usize),
    /// Both interiors: line–line distance.
    Interior,
}

/// Squared sine below which two edges count as parallel (the line–line form is then not used).
const PARALLEL_SIN2: f64 = 1e-12;
/// Squared sine of the smallest angle below which a triangle counts as degenerate (no face feature).
const DEGENERATE_SIN2: f64 = 1e-16;

/// `|p − q|²`.
pub fn point_point_squared<T: Real>(p: &Vector3<T>, q: &Vector3<T>) -> T {
    (p - q).norm_squared()
}

/// The squared distance from `p` to the line through `e₀` and `e₁` (`e₀ ≠ e₁`).
pub fn point_line_squared<T: Real>(p: &Vector3<T>, e0: &Vector3<T>, e1: &Vector3<T>) -> T {
    point_line_of_differences(&(p - e0), &(e1 - e0))
}

/// The squared distance from `p` to the plane through `t₀, t₁, t₂` (not collinear).
pub fn point_plane_squared<T: Real>(p: &Vector3<T>, t0: &Vector3<T>, t1: &Vector3<T>, t2: &Vector3<T>) -> T {
    point_plane_of_differences(&(p - t0), &(t1 - t0), &(t2 - t0))
}

/// The squared distance between the line through `a₀, a₁` and the line through `b₀, b₁` (not parallel).
pub fn line_line_squared<T: Real>(a0: &Vector3<T>, a1: &Vector3<T>, b0: &Vector3<T>, b1: &Vector3<T>) -> T {
    line_line_of_differences(&(a0 - b0), &(a1 - a0), &(b1 - b0))
}

/// `|r × e|² / |e|²` with `r = p − e₀`, `e = e₁ − e₀` (the cross form avoids the cancellation of
/// `|r|² − (r·e)²/|e|²`).
fn point_line_of_differences<T: Real>(r: &Vector3<T>, e: &Vector3<T>) -> T {
    r.cross(e).norm_squared() / e.norm_squared()
}

/// `(r·n)² / |n|²` with `n = a × b`, `r = p − t₀`, `a = t₁ − t₀`, `b = t₂ − t₀`.
fn point_plane_of_differences<T: Real>(r: &Vector3<T>, a: &Vector3<T>, b: &Vector3<T>) -> T {
    let n = a.cross(b);
    let rn = r.dot(&n);
    rn * rn / n.norm_squared()
}

/// `(r·n)² / |n|²` with `n = u × v`, `r = a₀ − b₀`, `u = a₁ − a₀`, `v = b₁ − b₀`.
fn line_line_of_differences<T: Real>(r: &Vector3<T>, u: &Vector3<T>, v: &Vector3<T>) -> T {
    point_plane_of_differences(r, u, v)
}

/// Where the closest point of segment `[e₀, e₁]` to `p` lies: `(parameter t ∈ [0, 1], squared distance,
/// 0 = at e₀, 1 = at e₁, 2 = interior)`.
fn point_segment(p: &Vector3<f64>, e0: &Vector3<f64>, e1: &Vector3<f64>) -> (f64, f64, u8) {
    let e = e1 - e0;
    let r = p - e0;
    let ee = e.norm_squared();
    if ee == 0.0 {
        return (0.0, r.norm_squared(), 0);
    }
    let t = r.dot(&e) / ee;
    if t <= 0.0 {
        (0.0, r.norm_squared(), 0)
    } else if t >= 1.0 {
        (1.0, (p - e1).norm_squared(), 1)
    } else {
        (t, point_line_of_differences(&r, &e), 2)
    }
}

/// Barycentric coordinates `(v, w)` of the projection of `r = p − t₀` onto the plane spanned by `a`, `b`
/// (so the projection is `t₀ + v a + w b`), or `None` for a degenerate triangle.
fn plane_coordinates(r: &Vector3<f64>, a: &Vector3<f64>, b: &Vector3<f64>) -> Option<(f64, f64)> {
    let n = a.cross(b);
    let nn = n.norm_squared();
    if !(nn > DEGENERATE_SIN2 * a.norm_squared() * b.norm_squared()) {
        return None;
    }
    Some((r.cross(b).dot(&n) / nn, a.cross(r).dot(&n) / nn))
}

/// The closest feature of triangle `t₀ t₁ t₂` to `p`.
pub fn point_triangle_feature(p: &Vector3<f64>, t: [&Vector3<f64>; 3]) -> PointTriangleFeature {
    point_triangle_classify(p, t).0
}

/// The closest feature and the squared distance.
fn point_triangle_classify(p: &Vector3<f64>, t: [&Vector3<f64>; 3]) -> (PointTriangleFeature, f64) {
    let (a, b, r) = (t[1] - t[0], t[2] - t[0], p - t[0]);
    if let Some((v, w)) = plane_coordinates(&r, &a, &b)
        && v > 0.0
        && w > 0.0
        && v + w < 1.0
    {
        return (PointTriangleFeature::Face, point_plane_of_differences(&r, &a, &b));
    }
    let mut best = (PointTriangleFeature::Vertex(0), f64::INFINITY);
    for k in 0..3 {
        let (_, d2, at) = point_segment(p, t[k], t[(k + 1) % 3]);
        if d2 < best.1 {
            best.1 = d2;
            best.0 = match at {
                0 => PointTriangleFeature::Vertex(k),
                1 => PointTriangleFeature::Vertex((k + 1) % 3),
                _ => PointTriangleFeature::Edge(k),
            };
        }
    }
    best
}

/// The closest feature of triangle `x[1..4]` to the point `x[0]`, and the squared distance.
pub fn point_triangle_distance(x: &[Vector3<f64>; 4]) -> (PointTriangleFeature, f64) {
    point_triangle_classify(&x[0], [&x[1], &x[2], &x[3]])
}

/// The closest features of segments `[a₀, a₁]` and `[b₀, b₁]`.
pub fn edge_edge_feature(a: [&Vector3<f64>; 2], b: [&Vector3<f64>; 2]) -> EdgeEdgeFeature {
    edge_edge_classify(a, b).0
}

/// The line parameters `(s, t)` of the closest points of two non-parallel lines, or `None` if parallel.
fn line_parameters(a: [&Vector3<f64>; 2], b: [&Vector3<f64>; 2]) -> Option<(f64, f64)> {
    let (u, v, w) = (a[1] - a[0], b[1] - b[0], b[0] - a[0]);
    let n = u.cross(&v);
    let nn = n.norm_squared();
    if !(nn > PARALLEL_SIN2 * u.norm_squared() * v.norm_squared()) {
        return None;
    }
    Some((w.cross(&v).dot(&n) / nn, w.cross(&u).dot(&n) / nn))
}

fn edge_edge_classify(a: [&Vector3<f64>; 2], b: [&Vector3<f64>; 2]) -> (EdgeEdgeFeature, f64) {
    if let Some((s, t)) = line_parameters(a, b)
        && s > 0.0
        && s < 1.0
        && t > 0.0
        && t < 1.0
    {
        let d2 = line_line_of_differences(&(a[0] - b[0]), &(a[1] - a[0]), &(b[1] - b[0]));
        return (EdgeEdgeFeature::Interior, d2);
    }
    let mut best = (EdgeEdgeFeature::VertexVertex(0, 0), f64::INFINITY);
    for i in 0..2 {
        let (_, d2, at) = point_segment(a[i], b[0], b[1]);
        if d2 < best.1 {
            best.1 = d2;
            best.0 = match at {
                0 => EdgeEdgeFeature::VertexVertex(i, 0),
                1 => EdgeEdgeFeature::VertexVertex(i, 1),
                _ => EdgeEdgeFeature::VertexEdge(i),
            };
        }
    }
    for j in 0..2 {
        let (_, d2, at) = point_segment(b[j], a[0], a[1]);
        if d2 < best.1 {
            best.1 = d2;
            best.0 = match at {
                0 => EdgeEdgeFeature::VertexVertex(0, j),
                1 => EdgeEdgeFeature::VertexVertex(1, j),
                _ => EdgeEdgeFeature::EdgeVertex(j),
            };
        }
    }
    best
}

/// The closest features of the segments `[x₀, x₁]` and `[x₂, x₃]`, and their squared distance.
pub fn edge_edge_distance(x: &[Vector3<f64>; 4]) -> (EdgeEdgeFeature, f64) {
    edge_edge_classify([&x[0], &x[1]], [&x[2], &x[3]])
}

/// The closed form a feature selects, as point indices into the pair.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Form {
    /// `|x_i − x_j|²`.
    PointPoint(usize, usize),
    /// Point `p` to the line through `x_e0`, `x_e1`.
    PointLine(usize, usize, usize),
    /// Point 0 to the plane of 1, 2, 3.
    PointPlane,
    /// Line 0–1 to line 2–3.
    LineLine,
}

fn point_triangle_form(feature: PointTriangleFeature) -> Form {
    match feature {
        PointTriangleFeature::Vertex(k) => Form::PointPoint(0, 1 + k),
        PointTriangleFeature::Edge(k) => Form::PointLine(0, 1 + k, 1 + (k + 1) % 3),
        PointTriangleFeature::Face => Form::PointPlane,
    }
}

fn edge_edge_form(feature: EdgeEdgeFeature) -> Form {
    match feature {
        EdgeEdgeFeature::VertexVertex(i, j) => Form::PointPoint(i, 2 + j),
        EdgeEdgeFeature::VertexEdge(i) => Form::PointLine(i, 2, 3),
        EdgeEdgeFeature::EdgeVertex(j) => Form::PointLine(2 + j, 0, 1),
        EdgeEdgeFeature::Interior => Form::LineLine,
    }
}

fn form_value<T: Real>(x: &[Vector3<T>; 4], form: Form) -> T {
    match form {
        Form::PointPoint(i, j) => point_point_squared(&x[i], &x[j]),
        Form::PointLine(p, e0, e1) => point_line_squared(&x[p], &x[e0], &x[e1]),
        Form::PointPlane => point_plane_squared(&x[0], &x[1], &x[2], &x[3]),
        Form::LineLine => line_line_squared(&x[0], &x[1], &x[2], &x[3]),
    }
}

fn form_jet(x: &[Vector3<f64>; 4], form: Form) -> PairJet {
    match form {
        Form::PointPoint(i, j) => {
            let r = x[i] - x[j];
            let g = SVector::<f64, 3>::from(r * 2.0);
            let h = Matrix3::identity() * 2.0;
            PairJet::from_differences(r.norm_squared(), &g, &h, [(i, j)])
        }
        Form::PointLine(p, e0, e1) => {
            let (v, g, h) = closed_form::point_line(&(x[p] - x[e0]), &(x[e1] - x[e0]));
            PairJet::from_differences(v, &g, &h, [(p, e0), (e1, e0)])
        }
        Form::PointPlane => {
            let (v, g, h) = closed_form::point_plane(&(x[0] - x[1]), &(x[2] - x[1]), &(x[3] - x[1]));
            PairJet::from_differences(v, &g, &h, [(0, 1), (2, 1), (3, 1)])
        }
        Form::LineLine => {
            let (v, g, h) = closed_form::point_plane(&(x[0] - x[2]), &(x[1] - x[0]), &(x[3] - x[2]));
            PairJet::from_differences(v, &g, &h, [(0, 2), (1, 0), (3, 2)])
        }
    }
}

/// The squared point–triangle distance of `x = [p, t₀, t₁, t₂]` by the closed form of `feature`
/// (exact when `feature` is the classified closest feature; elsewhere the distance to that feature's
/// line or plane).
pub fn point_triangle_squared<T: Real>(x: &[Vector3<T>; 4], feature: PointTriangleFeature) -> T {
    form_value(x, point_triangle_form(feature))
}

/// The squared edge–edge distance of `x = [a₀, a₁, b₀, b₁]` by the closed form of `feature`.
pub fn edge_edge_squared<T: Real>(x: &[Vector3<T>; 4], feature: EdgeEdgeFeature) -> T {
    form_value(x, edge_edge_form(feature))
}

/// The squared point–triangle distance with its gradient and Hessian, for the given feature.
pub fn point_triangle_jet(x: &[Vector3<f64>; 4], feature: PointTriangleFeature) -> PairJet {
    form_jet(x, point_triangle_form(feature))
}

/// The squared edge–edge distance with its gradient and Hessian, for the given feature.
pub fn edge_edge_jet(x: &[Vector3<f64>; 4], feature: EdgeEdgeFeature) -> PairJet {
    form_jet(x, edge_edge_form(feature))
}

/// Weights `β` of the closest-point difference `Σ βᵢ xᵢ = p − q` (point minus its closest point `q` on
/// the triangle) for a point–triangle pair with the given feature.
pub fn point_triangle_weights(x: &[Vector3<f64>; 4], feature: PointTriangleFeature) -> [f64; 4] {
    let mut w = [1.0, 0.0, 0.0, 0.0];
    match feature {
        PointTriangleFeature::Vertex(k) => w[1 + k] = -1.0,
        PointTriangleFeature::Edge(k) => {
            let (i, j) = (1 + k, 1 + (k + 1) % 3);
            let (t, _, _) = point_segment(&x[0], &x[i], &x[j]);
            w[i] = -(1.0 - t);
            w[j] = -t;
        }
        PointTriangleFeature::Face => {
            let (a, b, r) = (x[2] - x[1], x[3] - x[1], x[0] - x[1]);
            let (v, s) = plane_coordinates(&r, &a, &b).unwrap_or((0.0, 0.0));
            w[1] = -(1.0 - v - s);
            w[2] = -v;
            w[3] = -s;
        }
    }
    w
}

/// Weights `β` of the closest-point difference `Σ βᵢ xᵢ = pₐ − p_b` (closest point on `a` minus closest
/// point on `b`) for an edge–edge pair with the given feature.
pub fn edge_edge_weights(x: &[Vector3<f64>; 4], feature: EdgeEdgeFeature) -> [f64; 4] {
    let mut w = [0.0; 4];
    match feature {
        EdgeEdgeFeature::VertexVertex(i, j) => {
            w[i] = 1.0;
            w[2 + j] = -1.0;
        }
        EdgeEdgeFeature::VertexEdge(i) => {
            let (t, _, _) = point_segment(&x[i], &x[2], &x[3]);
            w[i] = 1.0;
            w[2] = -(1.0 - t);
            w[3] = -t;
        }
        EdgeEdgeFeature::EdgeVertex(j) => {
            let (s, _, _) = point_segment(&x[2 + j], &x[0], &x[1]);
            w[0] = 1.0 - s;
            w[1] = s;
            w[2 + j] = -1.0;
        }
        EdgeEdgeFeature::Interior => {
            let (s, t) = line_parameters([&x[0], &x[1]], [&x[2], &x[3]]).unwrap_or((0.0, 0.0));
            w = [1.0 - s, s, -(1.0 - t), -t];
        }
    }
    w
}
