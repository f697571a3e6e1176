//! Distances: optimality certificates and brute-force sampling, every closest-feature case, derivatives
//! against finite differences (also next to region boundaries and in degenerate configurations) and
//! against a whole-pair dual-number oracle, C¹ continuity across region boundaries.

use super::common::{check_jet, flatten, random_vec, rng};
use cosserat_contact::distance::{
    EdgeEdgeFeature, PointTriangleFeature, edge_edge_distance, edge_edge_jet, edge_edge_squared, edge_edge_weights,
    point_triangle_distance, point_triangle_jet, point_triangle_squared, point_triangle_weights,
};
use nalgebra::{SVector, Vector3};
use num_dual::Dual2SVec64;
use rand::Rng;

fn v(x: f64, y: f64, z: f64) -> Vector3<f64> {
    Vector3::new(x, y, z)
}

fn closest_difference(x: &[Vector3<f64>; 4], w: &[f64; 4]) -> Vector3<f64> {
    (0..4).map(|i| x[i] * w[i]).sum()
}

/// Checks the convex-optimality certificate of a point–triangle distance: the closest point `q` lies
/// on the triangle, `|p − q|² = s`, and `(p − q)·(tₖ − q) ≤ 0` for every vertex.
fn certify_point_triangle(x: &[Vector3<f64>; 4]) {
    let (feature, s) = point_triangle_distance(x);
    let w = point_triangle_weights(x, feature);
    assert!(
        w[1..].iter().all(|&b| b <= 1e-12),
        "barycentric weights in [0, 1]: {w:?}"
    );
    assert!((w[1] + w[2] + w[3] + 1.0).abs() < 1e-12);
    let r = closest_difference(x, &w);
    let q = x[0] - r;
    let scale = (x[1] - x[0]).norm_squared() + (x[2] - x[0]).norm_squared() + (x[3] - x[0]).norm_squared();
    assert!(
        (r.norm_squared() - s).abs() <= 1e-12 * scale,
        "closest point attains the distance"
    );
    for k in 1..4 {
        assert!(
            r.dot(&(x[k] - q)) <= 1e-12 * scale,
            "optimality towards vertex {k} ({feature:?})"
        );
    }
}

fn certify_edge_edge(x: &[Vector3<f64>; 4]) {
    let (feature, s) = edge_edge_distance(x);
    let w = edge_edge_weights(x, feature);
    assert!(
        w[0] >= -1e-12 && w[1] >= -1e-12 && w[2] <= 1e-12 && w[3] <= 1e-12,
        "{w:?}"
    );
    assert!((w[0] + w[1] - 1.0).abs() < 1e-12 && (w[2] + w[3] + 1.0).abs() < 1e-12);
    let pa = x[0] * w[0] + x[1] * w[1];
    let pb = -(x[2] * w[2] + x[3] * w[3]);
    let r = pa - pb;
    let scale = x.iter().map(|p| (p - x[0]).norm_squared()).sum::<f64>();
    assert!(
        (r.norm_squared() - s).abs() <= 1e-12 * scale,
        "closest points attain the distance ({feature:?})"
    );
    for i in 0..2 {
        assert!(r.dot(&(x[i] - pa)) >= -1e-12 * scale, "optimality on a ({feature:?})");
        assert!(
            (-r).dot(&(x[2 + i] - pb)) >= -1e-12 * scale,
            "optimality on b ({feature:?})"
        );
    }
}

#[test]
fn random_point_triangle_distances_are_certified_minima() {
    let mut rng = rng(1);
    let mut seen = std::collections::BTreeSet::new();
    for _ in 0..2000 {
        let x: [Vector3<f64>; 4] = std::array::from_fn(|_| random_vec(&mut rng, 1.0));
        certify_point_triangle(&x);
        seen.insert(format!("{:?}", point_triangle_distance(&x).0));
    }
    // Every feature occurs.
    assert_eq!(seen.len(), 7, "{seen:?}");
}

#[test]
fn random_edge_edge_distances_are_certified_minima() {
    let mut rng = rng(2);
    let mut seen = std::collections::BTreeSet::new();
    for _ in 0..2000 {
        let x: [Vector3<f64>; 4] = std::array::from_fn(|_| random_vec(&mut rng, 1.0));
        certify_edge_edge(&x);
        seen.insert(format!("{:?}", edge_edge_distance(&x).0));
    }
    assert_eq!(seen.len(), 9, "{seen:?}");
}

#[test]
fn distances_agree_with_brute_force_sampling() {
    let mut rng = rng(3);
    let n = 120;
    for _ in 0..40 {
        let x: [Vector3<f64>; 4] = std::array::from_fn(|_| random_vec(&mut rng, 1.0));
        let d = point_triangle_distance(&x).1.sqrt();
        let mut best = f64::INFINITY;
        for i in 0..=n {
            for j in 0..=(n - i) {
                let (a, b) = (i as f64 / n as f64, j as f64 / n as f64);
                let q = x[1] * (1.0 - a - b) + x[2] * a + x[3] * b;
                best = best.min((x[0] - q).norm());
            }
        }
        let h = (x[2] - x[1]).norm().max((x[3] - x[1]).norm()) / n as f64;
        assert!(best >= d - 1e-12 && best <= d + h, "sampled {best} vs {d}");
        let de = edge_edge_distance(&x).1.sqrt();
        let mut best = f64::INFINITY;
        for i in 0..=n {
            for j in 0..=n {
                let (s, t) = (i as f64 / n as f64, j as f64 / n as f64);
                best = best.min((x[0] * (1.0 - s) + x[1] * s - x[2] * (1.0 - t) - x[3] * t).norm());
            }
        }
        let h = ((x[1] - x[0]).norm() + (x[3] - x[2]).norm()) / n as f64;
        assert!(best >= de - 1e-12 && best <= de + h, "sampled {best} vs {de}");
    }
}

#[test]
fn point_triangle_features_of_constructed_configurations() {
    let t = [v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0)];
    let cases = [
        (v(0.2, 0.3, 0.5), PointTriangleFeature::Face, 0.25),
        (v(0.5, -0.5, 0.5), PointTriangleFeature::Edge(0), 0.5),
        (v(0.8, 0.8, 0.0), PointTriangleFeature::Edge(1), 2.0 * 0.3 * 0.3),
        (v(-0.5, 0.5, 0.0), PointTriangleFeature::Edge(2), 0.25),
        (v(-1.0, -1.0, 1.0), PointTriangleFeature::Vertex(0), 3.0),
        (v(2.0, -0.5, 0.0), PointTriangleFeature::Vertex(1), 1.25),
        (v(0.0, 3.0, 1.0), PointTriangleFeature::Vertex(2), 5.0),
        // On the triangle: zero distance, classified by where it lies.
        (v(0.25, 0.25, 0.0), PointTriangleFeature::Face, 0.0),
        (v(0.5, 0.0, 0.0), PointTriangleFeature::Edge(0), 0.0),
        (v(1.0, 0.0, 0.0), PointTriangleFeature::Vertex(1), 0.0),
    ];
    for (p, feature, s) in cases {
        let x = [p, t[0], t[1], t[2]];
        let (f, d2) = point_triangle_distance(&x);
        assert_eq!(f, feature, "{p:?}");
        assert!((d2 - s).abs() < 1e-15, "{p:?}: {d2} vs {s}");
        let jet = point_triangle_jet(&x, f);
        assert!(jet.is_finite());
    }
    // A degenerate (collinear) triangle has no face: the point is measured to its segments.
    let x = [v(0.5, 0.5, 0.0), v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(2.0, 0.0, 0.0)];
    let (f, d2) = point_triangle_distance(&x);
    assert!(matches!(f, PointTriangleFeature::Edge(_)));
    assert!((d2 - 0.25).abs() < 1e-15);
    assert!(point_triangle_jet(&x, f).is_finite());
    // Coincident point and vertex: zero distance with finite derivatives (gradient zero, Hessian 2I).
    let x = [v(0.0, 0.0, 0.0), v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0)];
    let (f, d2) = point_triangle_distance(&x);
    assert_eq!(d2, 0.0);
    let jet = point_triangle_jet(&x, f);
    assert!(jet.is_finite() && jet.gradient.amax() == 0.0);
}

#[test]
fn edge_edge_features_of_constructed_configurations() {
    let cases = [
        // Skew crossing edges.
        (
            [v(-1.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, -1.0, 0.3), v(0.0, 1.0, 0.3)],
            EdgeEdgeFeature::Interior,
            0.09,
        ),
        // Parallel, overlapping: endpoint a₁ against the interior of b (or the symmetric choice).
        (
            [v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.5, 0.0, 0.2), v(1.5, 0.0, 0.2)],
            EdgeEdgeFeature::VertexEdge(1),
            0.04,
        ),
        // Parallel, disjoint in their direction: endpoint to endpoint.
        (
            [v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(2.0, 0.0, 1.0), v(3.0, 0.0, 1.0)],
            EdgeEdgeFeature::VertexVertex(1, 0),
            2.0,
        ),
        // T configuration: endpoint of b against the interior of a.
        (
            [v(-1.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.2, 0.5, 0.0), v(0.2, 2.0, 0.0)],
            EdgeEdgeFeature::EdgeVertex(0),
            0.25,
        ),
        // Collinear, disjoint.
        (
            [v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(3.0, 0.0, 0.0), v(2.0, 0.0, 0.0)],
            EdgeEdgeFeature::VertexVertex(1, 1),
            1.0,
        ),
        // A zero-length edge is a point.
        (
            [v(0.0, 0.0, 0.0), v(0.0, 0.0, 0.0), v(-1.0, 1.0, 0.0), v(1.0, 1.0, 0.0)],
            EdgeEdgeFeature::VertexEdge(0),
            1.0,
        ),
        // Intersecting edges: zero distance.
        (
            [v(-1.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, -1.0, 0.0), v(0.0, 1.0, 0.0)],
            EdgeEdgeFeature::Interior,
            0.0,
        ),
    ];
    for (x, feature, s) in cases {
        let (f, d2) = edge_edge_distance(&x);
        assert_eq!(f, feature, "{x:?}");
        assert!((d2 - s).abs() < 1e-15, "{x:?}: {d2} vs {s}");
        assert!(edge_edge_jet(&x, f).is_finite());
    }
    // Exactly parallel edges whose projections overlap: the line–line form is never used, and the
    // distance and its derivatives stay finite.
    let x = [v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.2, 0.0, 0.5), v(0.7, 0.0, 0.5)];
    let (f, d2) = edge_edge_distance(&x);
    assert_ne!(f, EdgeEdgeFeature::Interior);
    assert!((d2 - 0.25).abs() < 1e-15);
    assert!(edge_edge_jet(&x, f).is_finite());
}

fn pt_value(x: &[Vector3<f64>; 4]) -> f64 {
    point_triangle_distance(x).1
}

fn ee_value(x: &[Vector3<f64>; 4]) -> f64 {
    edge_edge_distance(x).1
}

fn pt_jet(x: &[Vector3<f64>; 4]) -> cosserat_contact::PairJet {
    point_triangle_jet(x, point_triangle_distance(x).0)
}

fn ee_jet(x: &[Vector3<f64>; 4]) -> cosserat_contact::PairJet {
    edge_edge_jet(x, edge_edge_distance(x).0)
}

#[test]
fn derivatives_match_finite_differences_in_every_region() {
    // Central differences with h = 1e-6 on coordinates of order 1: truncation ~h² ≈ 1e-12 and round-off
    // ~ε/h ≈ 1e-10 relative to the entries, so 1e-6 leaves a wide margin while catching wrong terms.
    let t = [v(0.0, 0.0, 0.0), v(1.0, 0.1, 0.0), v(0.2, 1.0, 0.1)];
    for p in [
        v(0.3, 0.3, 0.4),
        v(0.5, -0.6, 0.3),
        v(1.0, 1.0, 0.2),
        v(-0.4, 0.5, -0.3),
        v(-1.0, -0.5, 0.5),
        v(2.0, 0.0, 0.1),
        v(0.1, 2.0, 0.3),
    ] {
        let x = [p, t[0], t[1], t[2]];
        check_jet("point-triangle", &x, pt_value, pt_jet, 1e-6, 1e-6);
    }
    let mut rng = rng(4);
    for _ in 0..60 {
        let x: [Vector3<f64>; 4] = std::array::from_fn(|_| random_vec(&mut rng, 1.0));
        check_jet("random point-triangle", &x, pt_value, pt_jet, 1e-6, 1e-5);
        check_jet("random edge-edge", &x, ee_value, ee_jet, 1e-6, 1e-5);
    }
}

#[test]
fn derivatives_near_degenerate_configurations() {
    let t = [v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0)];
    // A point 1e-4 inside and outside a triangle edge and near a vertex, 1e-3 above the plane; the
    // finite-difference step 1e-8 stays within one region.
    for p in [
        v(0.5, 1e-4, 1e-3),
        v(0.5, -1e-4, 1e-3),
        v(1e-4, 1e-4, 1e-3),
        v(-1e-4, -1e-4, 1e-3),
        v(1.0 + 1e-4, 0.0, 1e-3),
        v(0.5 - 1e-4, 0.5 - 1e-4, 1e-3),
    ] {
        let x = [p, t[0], t[1], t[2]];
        check_jet("point-triangle near boundary", &x, pt_value, pt_jet, 1e-8, 1e-4);
    }
    // Nearly parallel edges (1e-3 rad) crossing in projection, and nearly parallel edges overlapping
    // end to end.
    let c = 1e-3f64.cos();
    let s = 1e-3f64.sin();
    let x = [v(-1.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(-c, -s, 0.01), v(c, s, 0.01)];
    assert_eq!(edge_edge_distance(&x).0, EdgeEdgeFeature::Interior);
    check_jet("nearly parallel crossing", &x, ee_value, ee_jet, 1e-8, 1e-4);
    let x = [
        v(0.0, 0.0, 0.0),
        v(1.0, 0.0, 0.0),
        v(0.5, 0.01, 0.01),
        v(1.5, 0.01 + s, 0.01),
    ];
    check_jet("nearly parallel overlapping", &x, ee_value, ee_jet, 1e-8, 1e-4);
}

#[test]
fn distance_is_c1_across_region_boundaries() {
    // Crossing from the face region to the edge region and from the interior to an endpoint form: value
    // and gradient agree on both sides up to the size of the step.
    let t = [v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0)];
    let eps = 1e-9;
    let inside = [v(0.4, eps, 0.3), t[0], t[1], t[2]];
    let outside = [v(0.4, -eps, 0.3), t[0], t[1], t[2]];
    assert_eq!(point_triangle_distance(&inside).0, PointTriangleFeature::Face);
    assert_eq!(point_triangle_distance(&outside).0, PointTriangleFeature::Edge(0));
    let (a, b) = (pt_jet(&inside), pt_jet(&outside));
    assert!((a.value - b.value).abs() < 1e-8);
    assert!((a.gradient - b.gradient).amax() < 1e-7);
    let x_in = [
        v(-1.0, 0.0, 0.0),
        v(1.0, 0.0, 0.0),
        v(0.3, -1.0, 0.2),
        v(0.3, eps - 0.0, 0.2),
    ];
    let x_out = [
        v(-1.0, 0.0, 0.0),
        v(1.0, 0.0, 0.0),
        v(0.3, -1.0, 0.2),
        v(0.3, -eps, 0.2),
    ];
    assert_eq!(edge_edge_distance(&x_in).0, EdgeEdgeFeature::Interior);
    assert_eq!(edge_edge_distance(&x_out).0, EdgeEdgeFeature::EdgeVertex(1));
    let (a, b) = (ee_jet(&x_in), ee_jet(&x_out));
    assert!((a.value - b.value).abs() < 1e-8);
    assert!((a.gradient - b.gradient).amax() < 1e-7);
}

#[test]
fn jets_match_a_whole_pair_dual_oracle() {
    // The generic closed forms evaluated with a 12-direction second-order dual number over all
    // coordinates: the difference-local chain must give the same gradient and Hessian.
    let mut rng = rng(5);
    for _ in 0..30 {
        let x: [Vector3<f64>; 4] = std::array::from_fn(|_| random_vec(&mut rng, 1.0));
        let unpack = |y: &SVector<Dual2SVec64<12>, 12>| -> [Vector3<Dual2SVec64<12>>; 4] {
            std::array::from_fn(|k| Vector3::new(y[3 * k], y[3 * k + 1], y[3 * k + 2]))
        };
        let (f, _) = point_triangle_distance(&x);
        let (val, g, h) = num_dual::hessian(|y| point_triangle_squared(&unpack(&y), f), &flatten(&x));
        let jet = point_triangle_jet(&x, f);
        assert!((jet.value - val).abs() < 1e-13);
        assert!((jet.gradient - g).amax() < 1e-11 * g.amax().max(1.0));
        assert!((jet.hessian - h).amax() < 1e-10 * h.amax().max(1.0));
        let (f, _) = edge_edge_distance(&x);
        let (val, g, h) = num_dual::hessian(|y| edge_edge_squared(&unpack(&y), f), &flatten(&x));
        let jet = edge_edge_jet(&x, f);
        assert!((jet.value - val).abs() < 1e-13);
        assert!((jet.gradient - g).amax() < 1e-11 * g.amax().max(1.0));
        assert!((jet.hessian - h).amax() < 1e-10 * h.amax().max(1.0));
    }
}

#[test]
fn distance_is_invariant_under_rigid_motion() {
    let mut rng = rng(6);
    for _ in 0..50 {
        let x: [Vector3<f64>; 4] = std::array::from_fn(|_| random_vec(&mut rng, 1.0));
        let axis = nalgebra::Unit::new_normalize(random_vec(&mut rng, 1.0));
        let rot = nalgebra::Rotation3::from_axis_angle(&axis, rng.random_range(0.0..6.0));
        let shift = random_vec(&mut rng, 5.0);
        let y = x.map(|p| rot * p + shift);
        assert!((pt_value(&x) - pt_value(&y)).abs() < 1e-12);
        assert!((ee_value(&x) - ee_value(&y)).abs() < 1e-12);
        // Translation invariance makes the gradient sum to zero over the four points.
        let g = pt_jet(&x).gradient;
        let sum: Vector3<f64> = (0..4).map(|k| Vector3::new(g[3 * k], g[3 * k + 1], g[3 * k + 2])).sum();
        assert!(sum.amax() < 1e-12);
    }
}
