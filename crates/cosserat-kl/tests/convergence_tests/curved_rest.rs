//! A strip whose rest shape is a quarter circle, unbent by the end moment `−E I κ₀`: the rest state is
//! stress-free and the moment–curvature relation holds relative to the rest curvature.

use super::common::{ClampLine, mean, settings, shaped_strip};
use super::roll_up::end_couple;
use cosserat_kl::{HyperelasticModel, KlMaterial, KlShell};
use cosserat_solver::solve_quasi_static;
use nalgebra::Vector3;
use std::f64::consts::PI;

/// The end of an arc of length `l` and curvature `kappa` leaving the origin along +x, curling to +z.
fn arc_end(l: f64, kappa: f64) -> Vector3<f64> {
    if kappa.abs() < 1e-12 {
        Vector3::new(l, 0.0, 0.0)
    } else {
        Vector3::new((kappa * l).sin() / kappa, 0.0, (1.0 - (kappa * l).cos()) / kappa)
    }
}

#[test]
fn an_end_moment_unbends_a_curved_strip_by_its_rest_curvature() {
    let (l, w, h, e) = (1.0, 0.1, 0.01, 1e6);
    let kappa0 = 0.5 * PI / l;
    let (nx, ny) = (48, 1);
    for model in [HyperelasticModel::StVenantKirchhoff, HyperelasticModel::NeoHookean] {
        let shell = KlShell::new(KlMaterial::new(model, e, 0.0), h, 1.0);
        let ei = e * w * h * h * h / 12.0;
        let couple = end_couple(nx, ny);
        let moment = couple.handle();
        let shape = |x: Vector3<f64>| {
            Vector3::new(
                (kappa0 * x.x).sin() / kappa0,
                x.y,
                (1.0 - (kappa0 * x.x).cos()) / kappa0,
            )
        };
        let mut s = shaped_strip(l, w, (nx, ny), &shell, ClampLine::Centred, Some(couple), shape);
        // The curved rest state is stress-free.
        let rest_energy = s.system.elastic_energy().unwrap();
        assert!(
            rest_energy.abs() < 1e-12 * ei * kappa0 * kappa0 * l,
            "rest energy {rest_energy}"
        );
        let tip = s.column(nx);
        let mut tips = Vec::new();
        solve_quasi_static(
            &mut s.system.potential,
            &[0.5, 1.0],
            &settings(1e-9),
            &mut |_, lambda| moment.set(-ei * kappa0 * lambda),
            &mut |p, lambda| tips.push((lambda, mean(p, &tip))),
        )
        .unwrap();
        for (lambda, end) in tips {
            let expected = arc_end(l, kappa0 * (1.0 - lambda));
            let err = (end - expected).norm() / l;
            eprintln!(
                "{model:?} {nx}x{ny}: M = -{lambda} E I κ₀: tip {end:?}, expected {expected:?}, error {err:.2e} L"
            );
            assert!(err < 5e-3, "λ = {lambda}: error {err} L");
        }
    }
}
