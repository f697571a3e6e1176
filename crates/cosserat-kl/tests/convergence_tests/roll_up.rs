//! The roll-up of a strip under an end moment (Sze et al. 2004, problem 3.2 geometry): arcs of curvature
//! `M / (E I)`, closing into a circle at `M = 2π E I / L`.

use super::common::{ClampLine, column, edge_weights, mean, settings, strip};
use cosserat_kl::{ForceCouple, HyperelasticModel, KlMaterial, KlShell};
use cosserat_solver::solve_quasi_static;
use nalgebra::Vector3;
use std::f64::consts::PI;

/// The couple on the last segment of each grid row: pairs (column nx − 1, column nx) about −y, which curls
/// the strip towards +z for a positive moment; trapezoidal shares along the end edge.
pub fn end_couple(nx: usize, ny: usize) -> ForceCouple {
    let pairs = column(ny, nx - 1)
        .into_iter()
        .zip(column(ny, nx))
        .map(|(a, b)| [a, b])
        .collect();
    ForceCouple::try_new(
        "end_moment",
        pairs,
        &edge_weights(ny),
        -Vector3::y(),
        (nx + 1) * (ny + 1),
    )
    .unwrap()
}

/// Tip positions (mean of the end column) at the load levels `M / M_max = 0.05, 0.1, …, 1`.
fn roll_up(model: HyperelasticModel, nx: usize) -> Vec<(f64, Vector3<f64>)> {
    let (l, w, h, e) = (12.0, 1.0, 0.1, 1.2e6);
    let shell = KlShell::new(KlMaterial::new(model, e, 0.0), h, 1.0);
    let ei = e * w * h * h * h / 12.0; // = 100
    let m_max = 2.0 * PI * ei / l;
    let ny = 1;
    let couple = end_couple(nx, ny);
    let moment = couple.handle();
    let mut s = strip(l, w, (nx, ny), &shell, ClampLine::Centred, Some(couple));
    let tip = s.column(nx);
    let levels: Vec<f64> = (1..=20).map(|i| i as f64 * 0.05).collect();
    let mut tips = Vec::new();
    let reports = solve_quasi_static(
        &mut s.system.potential,
        &levels,
        &settings(1e-7),
        &mut |_, lambda| moment.set(m_max * lambda),
        &mut |p, lambda| tips.push((lambda, mean(p, &tip))),
    )
    .unwrap();
    eprintln!(
        "roll-up {nx}x1 Newton iterations per level: {:?}",
        reports.iter().map(|r| r.total_iterations).collect::<Vec<_>>()
    );
    tips
}

#[test]
fn an_end_moment_rolls_the_strip_into_arcs_and_closes_it_into_a_circle() {
    let l = 12.0;
    for model in [HyperelasticModel::StVenantKirchhoff, HyperelasticModel::NeoHookean] {
        let nx = 48;
        let tips = roll_up(model, nx);
        assert_eq!(tips.len(), 20);
        let mut worst: f64 = 0.0;
        for &(lambda, tip) in &tips {
            // Sze's "exact" column: the arc of curvature 2πλ / L from the clamp line.
            let phi = 2.0 * PI * lambda;
            let (u, wz) = (l * (1.0 - phi.sin() / phi), l * (1.0 - phi.cos()) / phi);
            let err = ((l - tip.x - u).powi(2) + (tip.z - wz).powi(2)).sqrt() / l;
            worst = worst.max(err);
            eprintln!(
                "{model:?} {nx}x1 M/Mmax = {lambda:.2}: -U = {:.4} (exact {u:.4}), W = {:.4} (exact {wz:.4}), |error|/L = {err:.2e}",
                l - tip.x,
                tip.z
            );
            assert!(err < 0.01, "λ = {lambda}: tip {tip:?}, error {err} L");
            // The two triangles of a quad differ, so the strip leaves its plane only by round-off-sized
            // amounts (measured below 1.1e-5 L on 48x1, shrinking under refinement).
            assert!(tip.y.abs() < 1e-4 * l, "the strip stays in its plane: {tip:?}");
        }
        // At the full moment the free end returns to the clamp line.
        let (_, end) = tips[19];
        let gap = (end - Vector3::new(0.0, 0.0, 0.0)).norm() / l;
        eprintln!("{model:?} {nx}x1: full moment, free end {end:?}, gap {gap:.2e} L, worst {worst:.2e} L");
        assert!(gap < 0.01, "gap {gap} L");
    }
}
