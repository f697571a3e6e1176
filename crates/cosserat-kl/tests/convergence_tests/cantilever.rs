//! A cantilever under a small tip load against Euler–Bernoulli `F L³ / (3 E I)`.

use super::common::{ClampLine, edge_weights, observed_order, settings, strip};
use cosserat_kl::{HyperelasticModel, KlMaterial, KlShell};
use cosserat_solver::solve_quasi_static;
use nalgebra::Vector3;

/// Tip deflection over `F L³ / (3 E I)` for a strip of `nx × ny` quads.
fn deflection_ratio(model: HyperelasticModel, nx: usize, ny: usize, clamp: ClampLine) -> f64 {
    let (l, w, h, e) = (1.0, 0.1, 0.01, 1e9);
    // ν = 0: no anticlastic curvature, so the strip bends like a beam with E I = E w h³ / 12.
    let shell = KlShell::new(KlMaterial::new(model, e, 0.0), h, 1000.0);
    let ei = e * w * h * h * h / 12.0;
    // A tip deflection of 1e-3 L keeps the response linear (relative nonlinearity ~1e-6).
    let f = 1e-3 * 3.0 * ei / (l * l);
    let mut s = strip(l, w, (nx, ny), &shell, clamp, None);
    let tip = s.column(nx);
    let weights = edge_weights(ny);
    let total: f64 = weights.iter().sum();
    solve_quasi_static(
        &mut s.system.potential,
        &[1.0],
        // Round-off in the membrane forces limits the residual to ~1e-9 N, 4e-8 f; a residual of 1e-6 f
        // leaves a relative deflection error of ~1e-6 (the bending stiffness is 3 E I / L³).
        &settings(1e-6 * f),
        &mut |p, lambda| {
            for (&i, wi) in tip.iter().zip(&weights) {
                p.parts.loads.forces[i] = Vector3::new(0.0, 0.0, f * lambda * wi / total);
            }
        },
        &mut |_, _| {},
    )
    .unwrap();
    let deflection = s.column_mean(nx).z;
    deflection / (f * l * l * l / (3.0 * ei))
}

#[test]
fn a_tip_loaded_cantilever_converges_to_euler_bernoulli_at_second_order_with_a_centred_clamp() {
    let ns = [8, 16, 32, 64];
    let mut h = Vec::new();
    let mut errors = Vec::new();
    for &nx in &ns {
        let ratio = deflection_ratio(HyperelasticModel::StVenantKirchhoff, nx, 1, ClampLine::Centred);
        h.push(1.0 / nx as f64);
        errors.push((ratio - 1.0).abs());
        eprintln!("cantilever tip load, centred clamp, {nx}x1: deflection / Euler-Bernoulli = {ratio:.6}");
    }
    let order = observed_order(&h, &errors);
    eprintln!("observed order {order:.3}, errors {errors:?}");
    assert!(order > 1.8 && order < 2.3, "order {order}");
    assert!(errors[3] < 1e-3, "64x1 error {}", errors[3]);
}

#[test]
fn the_clamp_line_at_the_first_column_converges_at_first_order() {
    // The fixed segment [0, Δx] bends nowhere, which shortens the effective length by Δx/2.
    let ns = [8, 16, 32];
    let mut h = Vec::new();
    let mut errors = Vec::new();
    for &nx in &ns {
        let ratio = deflection_ratio(HyperelasticModel::StVenantKirchhoff, nx, 1, ClampLine::FirstColumn);
        h.push(1.0 / nx as f64);
        errors.push((ratio - 1.0).abs());
        eprintln!("cantilever tip load, clamp at first column, {nx}x1: deflection / Euler-Bernoulli = {ratio:.6}");
    }
    let order = observed_order(&h, &errors);
    eprintln!("observed order {order:.3}");
    assert!(order > 0.9 && order < 1.2, "order {order}");
}

#[test]
fn both_materials_and_wider_meshes_give_the_same_small_load_stiffness() {
    let stvk = deflection_ratio(HyperelasticModel::StVenantKirchhoff, 32, 2, ClampLine::Centred);
    let nh = deflection_ratio(HyperelasticModel::NeoHookean, 32, 2, ClampLine::Centred);
    eprintln!("32x2: St.VK {stvk:.6}, neo-Hookean {nh:.6}");
    assert!((stvk - 1.0).abs() < 2e-3, "St.VK {stvk}");
    assert!((nh - stvk).abs() < 1e-5, "neo-Hookean {nh} vs St.VK {stvk}");
}
