//! Continuous collision detection: head-on motions are stopped above the minimum gap, tangential motion
//! is not limited, and on random trajectories dense sampling never finds the gap below the bound.

use super::common::{random_vec, rng};
use cosserat_contact::ccd::{CcdSettings, edge_edge_ccd, point_triangle_ccd};
use cosserat_contact::distance::{edge_edge_distance, point_triangle_distance};
use nalgebra::Vector3;
use rand::Rng;

fn v(x: f64, y: f64, z: f64) -> Vector3<f64> {
    Vector3::new(x, y, z)
}

fn at(x: &[Vector3<f64>; 4], dx: &[Vector3<f64>; 4], a: f64) -> [Vector3<f64>; 4] {
    std::array::from_fn(|i| x[i] + dx[i] * a)
}

fn pt_gap(x: &[Vector3<f64>; 4], delta: f64) -> f64 {
    point_triangle_distance(x).1.sqrt() - delta
}

fn ee_gap(x: &[Vector3<f64>; 4], delta: f64) -> f64 {
    edge_edge_distance(x).1.sqrt() - delta
}

/// The smallest gap on `[0, a]` by dense sampling.
fn sampled_min(
    gap: impl Fn(&[Vector3<f64>; 4]) -> f64,
    x: &[Vector3<f64>; 4],
    dx: &[Vector3<f64>; 4],
    a: f64,
    n: usize,
) -> f64 {
    (0..=n)
        .map(|k| gap(&at(x, dx, a * k as f64 / n as f64)))
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn a_point_moving_through_a_triangle_stops_above_the_minimum_gap() {
    let settings = CcdSettings::default();
    let delta = 0.01;
    let x = [v(0.2, 0.2, 0.1), v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0)];
    let dx = [v(0.05, 0.0, -0.3), Vector3::zeros(), Vector3::zeros(), Vector3::zeros()];
    let g0 = pt_gap(&x, delta);
    let alpha = point_triangle_ccd(&x, &dx, delta, &settings);
    // The gap reaches 0.1 g₀ at α* = (g₀ − 0.1 g₀)/0.3; the advancement stops within 10 % of
    // (g₀ − g_min) above the bound.
    let alpha_star = 0.9 * g0 / 0.3;
    assert!(alpha > 0.0 && alpha <= alpha_star, "{alpha} vs {alpha_star}");
    let g = pt_gap(&at(&x, &dx, alpha), delta);
    assert!(
        g >= 0.1 * g0 && g <= 0.1 * g0 + 0.1 * 0.9 * g0 + 1e-12,
        "gap {g} of {g0}"
    );
    assert!(sampled_min(|y| pt_gap(y, delta), &x, &dx, alpha, 1000) >= 0.1 * g0);
    // The triangle moving onto a resting point is the same relative motion.
    let dx2 = [Vector3::zeros(), -dx[0], -dx[0], -dx[0]];
    let alpha2 = point_triangle_ccd(&x, &dx2, delta, &settings);
    assert!((alpha2 - alpha).abs() < 1e-12);
}

#[test]
fn crossing_edges_stop_above_the_minimum_gap() {
    let settings = CcdSettings::default();
    let delta = 1e-3;
    let x = [
        v(-1.0, 0.0, 0.0),
        v(1.0, 0.0, 0.0),
        v(0.1, -1.0, 0.05),
        v(0.1, 1.0, 0.05),
    ];
    let dx = [
        Vector3::zeros(),
        Vector3::zeros(),
        v(0.0, 0.0, -0.1),
        v(0.02, 0.0, -0.1),
    ];
    let g0 = ee_gap(&x, delta);
    let alpha = edge_edge_ccd(&x, &dx, delta, &settings);
    assert!(alpha > 0.0 && alpha < 1.0);
    let g = ee_gap(&at(&x, &dx, alpha), delta);
    assert!(g >= 0.1 * g0 && g <= 0.2 * g0, "gap {g} of {g0}");
    assert!(sampled_min(|y| ee_gap(y, delta), &x, &dx, alpha, 1000) >= 0.1 * g0);
    // Without the limit the edges would pass through each other.
    assert!(sampled_min(|y| ee_gap(y, delta), &x, &dx, 1.0, 1000) < 0.0);
}

#[test]
fn tangential_motion_at_a_constant_gap_is_not_limited() {
    let settings = CcdSettings::default();
    let x = [
        v(0.1, 0.1, 0.02),
        v(-1.0, -1.0, 0.0),
        v(3.0, -1.0, 0.0),
        v(-1.0, 3.0, 0.0),
    ];
    let dx = [v(0.5, 0.4, 0.0), Vector3::zeros(), Vector3::zeros(), Vector3::zeros()];
    assert_eq!(point_triangle_ccd(&x, &dx, 0.01, &settings), 1.0);
    // Two parallel edges sliding along each other at a constant gap.
    let x = [v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, 0.3, 0.05), v(0.0, 1.3, 0.05)];
    let dx = [Vector3::zeros(), Vector3::zeros(), v(0.8, 0.0, 0.0), v(0.8, 0.0, 0.0)];
    assert_eq!(edge_edge_ccd(&x, &dx, 0.01, &settings), 1.0);
    // Rigid translation of the whole pair is never limited.
    let x = [v(0.2, 0.2, 1e-3), v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0)];
    let dx = [v(3.0, -2.0, 5.0); 4];
    assert_eq!(point_triangle_ccd(&x, &dx, 5e-4, &settings), 1.0);
}

#[test]
fn infeasible_or_static_starts() {
    let settings = CcdSettings::default();
    let x = [v(0.2, 0.2, 0.001), v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0)];
    let dx = [v(0.0, 0.0, 1.0), Vector3::zeros(), Vector3::zeros(), Vector3::zeros()];
    // Start gap below zero: no step is safe.
    assert_eq!(point_triangle_ccd(&x, &dx, 0.01, &settings), 0.0);
    // No motion: the full step.
    assert_eq!(point_triangle_ccd(&x, &[Vector3::zeros(); 4], 1e-4, &settings), 1.0);
    // A non-finite displacement is never safe.
    let bad = [
        v(f64::NAN, 0.0, 0.0),
        Vector3::zeros(),
        Vector3::zeros(),
        Vector3::zeros(),
    ];
    assert_eq!(point_triangle_ccd(&x, &bad, 1e-4, &settings), 0.0);
}

#[test]
fn random_trajectories_never_violate_the_bound() {
    // A generous step cap, so that only the geometry decides where the advancement stops.
    let settings = CcdSettings {
        max_iterations: 10_000_000,
        ..CcdSettings::default()
    };
    let mut rng = rng(21);
    let (mut limited, mut free) = (0, 0);
    for trial in 0..300 {
        let x: [Vector3<f64>; 4] = std::array::from_fn(|_| random_vec(&mut rng, 0.5));
        let dx: [Vector3<f64>; 4] = std::array::from_fn(|_| random_vec(&mut rng, 0.6));
        let delta = rng.random_range(0.0..0.05);
        for (name, gap, ccd) in [
            (
                "point-triangle",
                pt_gap as fn(&[Vector3<f64>; 4], f64) -> f64,
                point_triangle_ccd as fn(&_, &_, f64, &CcdSettings) -> f64,
            ),
            ("edge-edge", ee_gap, edge_edge_ccd),
        ] {
            let g0 = gap(&x, delta);
            if g0 <= 0.0 {
                continue;
            }
            let alpha = ccd(&x, &dx, delta, &settings);
            assert!((0.0..=1.0).contains(&alpha));
            let g_min = 0.1 * g0;
            let m = sampled_min(|y| gap(y, delta), &x, &dx, alpha, 2000);
            assert!(m >= g_min, "{name} trial {trial}: sampled gap {m} below {g_min}");
            // Not limited without cause: if the whole motion stays above the stopping level
            // (g_min + 10 % of g₀ − g_min), the full step is returned. Between two of the 2000 samples
            // the gap can dip by at most half a sample spacing times its rate bound Σ|Δxᵢ|.
            let full = sampled_min(|y| gap(y, delta), &x, &dx, 1.0, 2000);
            let rate: f64 = dx.iter().map(|d| d.norm()).sum();
            if full - rate / 4000.0 > g_min + 0.1 * (g0 - g_min) {
                assert_eq!(alpha, 1.0, "{name} trial {trial}");
                free += 1;
            } else {
                limited += 1;
            }
        }
    }
    assert!(
        limited > 50 && free > 50,
        "both outcomes occur: {limited} limited, {free} free"
    );
}
