//! The broad phase against brute force on random meshes (static and swept), exclusions, sorted and
//! thread-independent output; contact-mesh validation.

use super::common::{random_vec, rng};
use cosserat_assembly::Parallelism;
use cosserat_contact::broad_phase::{CandidatePairs, candidate_pairs};
use cosserat_contact::candidate_cache::CandidateCache;
use cosserat_contact::distance::{edge_edge_distance, point_triangle_distance};
use cosserat_contact::{ContactError, ContactMesh, ContactSurface, Obstacle};
use nalgebra::Vector3;
use rand_chacha::ChaCha8Rng;

/// Triangles of an `n × n` quad grid whose node `(i, j)` is `offset + i (n + 1) + j`.
pub fn grid_triangles(n: usize, offset: usize) -> Vec<[usize; 3]> {
    let idx = |i: usize, j: usize| offset + i * (n + 1) + j;
    let mut t = Vec::new();
    for i in 0..n {
        for j in 0..n {
            t.push([idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)]);
            t.push([idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)]);
        }
    }
    t
}

/// Node positions of an `n × n` grid of side `size` at height `z`, jittered by `jitter`.
pub fn grid_nodes(rng: &mut ChaCha8Rng, n: usize, size: f64, z: f64, jitter: f64) -> Vec<Vector3<f64>> {
    let h = size / n as f64;
    let mut x = Vec::new();
    for i in 0..=n {
        for j in 0..=n {
            x.push(Vector3::new(i as f64 * h, j as f64 * h, z) + random_vec(rng, jitter));
        }
    }
    x
}

struct Scene {
    mesh: ContactMesh,
    positions: Vec<Vector3<f64>>,
}

/// Two jittered grids (surfaces 0 and 1, different thicknesses) close to each other and an obstacle.
fn random_scene(seed: u64) -> Scene {
    random_scene_of_size(seed, 6)
}

/// Two noisy `n × n` grids 6 cm apart and a small obstacle grid below them.
fn random_scene_of_size(seed: u64, n: usize) -> Scene {
    let mut rng = rng(seed);
    let mut x = grid_nodes(&mut rng, n, 1.0, 0.0, 0.03);
    let second = grid_nodes(&mut rng, n, 1.0, 0.06, 0.03);
    let offset = x.len();
    x.extend(second);
    let surfaces = vec![
        ContactSurface {
            id: 0,
            triangles: grid_triangles(n, 0),
            thickness: 0.01,
        },
        ContactSurface {
            id: 1,
            triangles: grid_triangles(n, offset),
            thickness: 0.005,
        },
    ];
    let mut orng = rng.clone();
    let obstacle = Obstacle {
        id: 2,
        positions: grid_nodes(&mut orng, 3, 1.0, -0.05, 0.03),
        triangles: grid_triangles(3, 0),
        thickness: 0.002,
    };
    let mesh = ContactMesh::try_new(&surfaces, std::slice::from_ref(&obstacle), x.len()).unwrap();
    let positions = mesh.positions(|i| x[i], |_, v| obstacle.positions[v]);
    Scene { mesh, positions }
}

fn thickness(mesh: &ContactMesh, body: usize) -> f64 {
    mesh.bodies()[body].thickness
}

fn excluded_pt(mesh: &ContactMesh, v: usize, t: usize) -> bool {
    let both = mesh.bodies()[mesh.vertex_body(v)].is_obstacle && mesh.bodies()[mesh.triangle_body(t)].is_obstacle;
    mesh.triangles()[t].contains(&(v as u32)) || both
}

fn excluded_ee(mesh: &ContactMesh, e: usize, f: usize) -> bool {
    let (a, b) = (mesh.edges()[e], mesh.edges()[f]);
    let both = mesh.bodies()[mesh.edge_body(e)].is_obstacle && mesh.bodies()[mesh.edge_body(f)].is_obstacle;
    b.contains(&a[0]) || b.contains(&a[1]) || both
}

/// Every pair within `δ + reach` at `x` must be a candidate.
fn assert_contains_close_pairs(mesh: &ContactMesh, x: &[Vector3<f64>], reach: f64, c: &CandidatePairs) -> usize {
    let mut n_close = 0;
    for v in 0..mesh.n_vertices() {
        for t in 0..mesh.triangles().len() {
            if excluded_pt(mesh, v, t) {
                continue;
            }
            let tri = mesh.triangles()[t];
            let y = [x[v], x[tri[0] as usize], x[tri[1] as usize], x[tri[2] as usize]];
            let delta = thickness(mesh, mesh.vertex_body(v)) + thickness(mesh, mesh.triangle_body(t));
            if point_triangle_distance(&y).1.sqrt() < delta + reach {
                n_close += 1;
                assert!(
                    c.point_triangle.binary_search(&[v as u32, t as u32]).is_ok(),
                    "missing ({v}, {t})"
                );
            }
        }
    }
    for e in 0..mesh.edges().len() {
        for f in e + 1..mesh.edges().len() {
            if excluded_ee(mesh, e, f) {
                continue;
            }
            let (a, b) = (mesh.edges()[e], mesh.edges()[f]);
            let y = [x[a[0] as usize], x[a[1] as usize], x[b[0] as usize], x[b[1] as usize]];
            let delta = thickness(mesh, mesh.edge_body(e)) + thickness(mesh, mesh.edge_body(f));
            if edge_edge_distance(&y).1.sqrt() < delta + reach {
                n_close += 1;
                assert!(
                    c.edge_edge.binary_search(&[e as u32, f as u32]).is_ok(),
                    "missing ({e}, {f})"
                );
            }
        }
    }
    n_close
}

fn assert_sorted_and_valid(mesh: &ContactMesh, c: &CandidatePairs) {
    assert!(c.point_triangle.windows(2).all(|w| w[0] < w[1]));
    assert!(c.edge_edge.windows(2).all(|w| w[0] < w[1]));
    for &[v, t] in &c.point_triangle {
        assert!(!excluded_pt(mesh, v as usize, t as usize));
    }
    for &[e, f] in &c.edge_edge {
        assert!(e < f && !excluded_ee(mesh, e as usize, f as usize));
    }
}

#[test]
fn static_candidates_contain_every_pair_within_reach() {
    for seed in [1, 2, 3] {
        let s = random_scene(seed);
        let reach = 0.02;
        let c = candidate_pairs(&s.mesh, &s.positions, &s.positions, reach, Parallelism::Rayon);
        assert_sorted_and_valid(&s.mesh, &c);
        let n_close = assert_contains_close_pairs(&s.mesh, &s.positions, reach, &c);
        assert!(n_close > 20, "the scene has close pairs ({n_close})");
        // The boxes are conservative but not wildly so.
        assert!(
            c.len() < 20 * n_close,
            "{} candidates for {n_close} close pairs",
            c.len()
        );
    }
}

#[test]
fn swept_candidates_contain_every_pair_close_at_any_time() {
    let s = random_scene(4);
    let mut rng = rng(40);
    let end: Vec<Vector3<f64>> = s.positions.iter().map(|p| p + random_vec(&mut rng, 0.08)).collect();
    let reach = 0.01;
    let c = candidate_pairs(&s.mesh, &s.positions, &end, reach, Parallelism::Rayon);
    assert_sorted_and_valid(&s.mesh, &c);
    for k in 0..=10 {
        let a = k as f64 / 10.0;
        let x: Vec<Vector3<f64>> = s.positions.iter().zip(&end).map(|(p, q)| p + (q - p) * a).collect();
        assert_contains_close_pairs(&s.mesh, &x, reach, &c);
    }
}

#[test]
fn output_is_identical_for_any_number_of_threads() {
    let s = random_scene(5);
    let seq = candidate_pairs(&s.mesh, &s.positions, &s.positions, 0.05, Parallelism::Sequential);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(3).build().unwrap();
    let par = pool.install(|| candidate_pairs(&s.mesh, &s.positions, &s.positions, 0.05, Parallelism::Rayon));
    assert_eq!(seq, par);
    assert!(!seq.is_empty());
    // Several chunks of queries (over a thousand vertices, thousands of edges), still complete and in
    // order.
    let s = random_scene_of_size(6, 24);
    assert!(s.mesh.n_vertices() > 1200);
    let seq = candidate_pairs(&s.mesh, &s.positions, &s.positions, 0.01, Parallelism::Sequential);
    let par = pool.install(|| candidate_pairs(&s.mesh, &s.positions, &s.positions, 0.01, Parallelism::Rayon));
    assert_eq!(seq, par);
    assert_sorted_and_valid(&s.mesh, &par);
    assert_contains_close_pairs(&s.mesh, &s.positions, 0.01, &par);
}

/// A drifting sequence of motions (small steps that stay in the margin, and jumps that leave it): each
/// answer of the cache equals a fresh broad phase, and contains every pair close at any instant of the
/// motion, whether it came from the kept pairs, a refitted or a rebuilt hierarchy, or an uncached query.
#[test]
fn cached_candidates_equal_a_fresh_broad_phase() {
    let s = random_scene_of_size(8, 8);
    let mut rng = rng(80);
    let (reach, max_reach) = (0.01, 0.02);
    let mut cache = CandidateCache::new(max_reach, 1.0 / 8.0);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(3).build().unwrap();
    let mut sequential = cache.clone();
    let mut x = s.positions.clone();
    for k in 0..40 {
        // Every tenth motion jumps by more than the largest margin; the others creep.
        let size = if k % 10 == 9 { 0.1 } else { 0.004 };
        let end: Vec<Vector3<f64>> = x.iter().map(|p| p + random_vec(&mut rng, size)).collect();
        let r = if k % 3 == 0 { max_reach } else { reach };
        let fresh = candidate_pairs(&s.mesh, &x, &end, r, Parallelism::Sequential);
        let cached = pool.install(|| cache.candidate_pairs(&s.mesh, &x, &end, r, Parallelism::Rayon));
        assert_eq!(cached, fresh, "motion {k}");
        assert_eq!(
            sequential.candidate_pairs(&s.mesh, &x, &end, r, Parallelism::Sequential),
            fresh
        );
        for a in [0.0, 0.5, 1.0] {
            let y: Vec<Vector3<f64>> = x.iter().zip(&end).map(|(p, q)| p + (q - p) * a).collect();
            assert_contains_close_pairs(&s.mesh, &y, r, &cached);
        }
        x = end;
    }
    // A reach beyond the cache's goes uncached and is still exact.
    let wide = cache.candidate_pairs(&s.mesh, &x, &x, 0.05, Parallelism::Rayon);
    assert_eq!(wide, candidate_pairs(&s.mesh, &x, &x, 0.05, Parallelism::Rayon));
    let c = cache.counters();
    assert_eq!(c.queries, 41);
    assert!(c.requeries >= 4 && c.requeries < 30, "{c:?}");
    assert!(c.builds >= 1 && c.builds < c.requeries, "refits happen: {c:?}");
    assert!(c.uncached >= 1, "{c:?}");
    assert_eq!(sequential.counters().requeries, c.requeries);
}

#[test]
fn contact_mesh_numbers_nodes_then_obstacles_and_rejects_bad_input() {
    let tri = vec![[4, 7, 9], [7, 9, 2]];
    let surface = ContactSurface {
        id: 3,
        triangles: tri,
        thickness: 1e-3,
    };
    let obstacle = Obstacle {
        id: 0,
        positions: vec![Vector3::zeros(), Vector3::x(), Vector3::y()],
        triangles: vec![[0, 1, 2]],
        thickness: 0.0,
    };
    let mesh = ContactMesh::try_new(std::slice::from_ref(&surface), std::slice::from_ref(&obstacle), 10).unwrap();
    assert_eq!(mesh.n_vertices(), 7);
    assert_eq!(mesh.n_node_vertices(), 4);
    assert_eq!(
        (0..4).map(|v| mesh.node(v).unwrap()).collect::<Vec<_>>(),
        vec![4, 7, 9, 2]
    );
    assert_eq!(mesh.node(4), None);
    assert_eq!(mesh.edges().len(), 5 + 3);
    let err = ContactMesh::try_new(std::slice::from_ref(&surface), &[], 9).unwrap_err();
    assert!(
        matches!(
            err,
            ContactError::VertexOutOfRange {
                body: "surface",
                tri_idx: 0,
                vertex: 9,
                ..
            }
        ),
        "{err}"
    );
    let repeated = ContactSurface {
        triangles: vec![[1, 2, 1]],
        ..surface.clone()
    };
    let err = ContactMesh::try_new(&[repeated], &[], 10).unwrap_err();
    assert!(matches!(err, ContactError::RepeatedVertex { tri_idx: 0, .. }), "{err}");
    let other = ContactSurface {
        id: 4,
        triangles: vec![[0, 1, 2]],
        thickness: 1e-3,
    };
    let err = ContactMesh::try_new(&[surface.clone(), other], &[], 10).unwrap_err();
    assert!(
        matches!(
            err,
            ContactError::NodeInTwoSurfaces {
                node: 2,
                first: 0,
                second: 1
            }
        ),
        "{err}"
    );
    let negative = ContactSurface {
        thickness: -1.0,
        ..surface.clone()
    };
    assert!(matches!(
        ContactMesh::try_new(&[negative], &[], 10),
        Err(ContactError::InvalidParameter { .. })
    ));
    let mut bad = obstacle.clone();
    bad.positions[1].y = f64::NAN;
    assert!(matches!(
        ContactMesh::try_new(&[], &[bad], 0),
        Err(ContactError::NonFinite { vertex: 1, .. })
    ));
}
