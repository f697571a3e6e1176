//! Triangle–triangle intersection: constructed crossing, touching, coplanar and separated cases, random
//! pairs against an independent parametric segment–triangle solve, and whole meshes.

use super::broad_phase::{grid_nodes, grid_triangles};
use super::common::{random_vec, rng};
use cosserat_contact::{intersecting_pairs, triangles_intersect};
use nalgebra::{Matrix3, Vector3};

fn v(x: f64, y: f64, z: f64) -> Vector3<f64> {
    Vector3::new(x, y, z)
}

fn meet(a: &[Vector3<f64>; 3], b: &[Vector3<f64>; 3]) -> bool {
    let r1 = triangles_intersect([&a[0], &a[1], &a[2]], [&b[0], &b[1], &b[2]]);
    let r2 = triangles_intersect([&b[0], &b[1], &b[2]], [&a[0], &a[1], &a[2]]);
    assert_eq!(r1, r2, "symmetric");
    r1
}

#[test]
fn constructed_cases() {
    let a = [v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0)];
    let shift = |t: &[Vector3<f64>; 3], d: Vector3<f64>| t.map(|p| p + d);
    let cases: [(&str, [Vector3<f64>; 3], bool); 10] = [
        (
            "crossing",
            [v(0.2, 0.2, -0.5), v(0.3, 0.2, 0.5), v(0.2, 0.4, 0.5)],
            true,
        ),
        (
            "near miss beside the hypotenuse",
            [v(0.8, 0.8, -0.5), v(0.9, 0.8, 0.5), v(0.8, 0.9, 0.5)],
            false,
        ),
        ("parallel above", shift(&a, v(0.0, 0.0, 0.1)), false),
        ("coplanar overlapping", shift(&a, v(0.2, 0.2, 0.0)), true),
        ("coplanar disjoint", shift(&a, v(2.0, 0.0, 0.0)), false),
        (
            "coplanar contained",
            [v(0.1, 0.1, 0.0), v(0.2, 0.1, 0.0), v(0.1, 0.2, 0.0)],
            true,
        ),
        (
            "vertex on the face",
            [v(0.2, 0.2, 0.0), v(0.2, 0.2, 1.0), v(1.0, 1.0, 1.0)],
            true,
        ),
        (
            "edge touching an edge",
            [v(0.5, 0.0, -1.0), v(0.5, 0.0, 1.0), v(0.5, -1.0, 0.0)],
            true,
        ),
        (
            "vertex to vertex",
            [v(1.0, 0.0, 0.0), v(2.0, 0.0, 1.0), v(2.0, 1.0, 0.0)],
            true,
        ),
        (
            "separated by a hair",
            [v(0.2, 0.2, 1e-9), v(0.2, 0.2, 1.0), v(1.0, 1.0, 1.0)],
            false,
        ),
    ];
    for (name, b, expected) in cases {
        assert_eq!(meet(&a, &b), expected, "{name}");
    }
}

/// Independent reference: a segment meets a triangle iff the 3×3 system
/// `p + t (q − p) = a + u (b − a) + w (c − a)` has `t ∈ [0, 1]`, `u, w ≥ 0`, `u + w ≤ 1`.
fn segment_hits(p: &Vector3<f64>, q: &Vector3<f64>, t: &[Vector3<f64>; 3]) -> bool {
    let m = Matrix3::from_columns(&[q - p, t[0] - t[1], t[0] - t[2]]);
    let Some(inv) = m.try_inverse() else { return false };
    let s = inv * (t[0] - p);
    s[0] >= 0.0 && s[0] <= 1.0 && s[1] >= 0.0 && s[2] >= 0.0 && s[1] + s[2] <= 1.0
}

#[test]
fn random_pairs_agree_with_a_parametric_reference() {
    let mut rng = rng(31);
    let (mut hits, mut misses) = (0, 0);
    for _ in 0..3000 {
        let a: [Vector3<f64>; 3] = std::array::from_fn(|_| random_vec(&mut rng, 1.0));
        let b: [Vector3<f64>; 3] = std::array::from_fn(|_| random_vec(&mut rng, 1.0));
        let reference = (0..3).any(|k| segment_hits(&a[k], &a[(k + 1) % 3], &b))
            || (0..3).any(|k| segment_hits(&b[k], &b[(k + 1) % 3], &a));
        assert_eq!(meet(&a, &b), reference, "{a:?} {b:?}");
        if reference {
            hits += 1;
        } else {
            misses += 1;
        }
    }
    assert!(hits > 300 && misses > 300, "{hits} hits, {misses} misses");
}

#[test]
fn intersecting_pairs_of_meshes() {
    let mut rng = rng(32);
    let n = 8;
    let mut x = grid_nodes(&mut rng, n, 1.0, 0.0, 0.01);
    let mut tris = grid_triangles(n, 0);
    // A jittered grid is free of intersections (adjacent triangles share vertices and are skipped).
    assert!(intersecting_pairs(&tris, &x).is_empty());
    // A separate needle triangle piercing the grid vertically near (0.43, 0.57).
    let first = x.len();
    x.extend([v(0.43, 0.57, -0.3), v(0.44, 0.57, 0.3), v(0.43, 0.58, 0.3)]);
    tris.push([first, first + 1, first + 2]);
    let found = intersecting_pairs(&tris, &x);
    let needle = tris.len() - 1;
    assert!(!found.is_empty());
    assert!(found.iter().all(|&(s, t)| s < t && t == needle), "{found:?}");
    // Brute force over all pairs without shared vertices gives the same list.
    let mut brute = Vec::new();
    for s in 0..tris.len() {
        for t in s + 1..tris.len() {
            if tris[t].iter().any(|p| tris[s].contains(p)) {
                continue;
            }
            let (a, b) = (tris[s].map(|i| x[i]), tris[t].map(|i| x[i]));
            if triangles_intersect([&a[0], &a[1], &a[2]], [&b[0], &b[1], &b[2]]) {
                brute.push((s, t));
            }
        }
    }
    assert_eq!(found, brute);
    // The grid triangle under the needle is among them: the one containing (0.43, 0.57) in projection.
    assert!(found.len() <= 3);
}
