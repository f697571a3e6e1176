//! Materials: validation, moduli, and the plane-stress condensation of both densities.

use super::common::{MODELS, rng};
use cosserat_kl::material::{density_3d, plane_stress_c33, plane_stress_density};
use cosserat_kl::{HyperelasticModel, KlError, KlMaterial};
use nalgebra::Matrix2;
use num_dual::Dual2_64;
use rand::Rng;

#[test]
fn invalid_parameters_are_rejected_by_name() {
    for (e, nu, name) in [
        (0.0, 0.3, "youngs_modulus"),
        (f64::NAN, 0.3, "youngs_modulus"),
        (1.0, 0.5, "poisson_ratio"),
        (1.0, -1.0, "poisson_ratio"),
        (1.0, f64::INFINITY, "poisson_ratio"),
    ] {
        let m = KlMaterial::new(HyperelasticModel::NeoHookean, e, nu);
        match m.constants() {
            Err(KlError::InvalidParameter { name: n, .. }) => assert_eq!(n, name),
            other => panic!("E = {e}, ν = {nu}: {other:?}"),
        }
    }
}

#[test]
fn moduli_follow_from_young_and_poisson() {
    // E = 2.5, ν = 0.25: μ = E/(2(1+ν)) = 1, λ = Eν/((1+ν)(1−2ν)) = 1, λμ/(λ+2μ) = 1/3.
    let c = KlMaterial::new(HyperelasticModel::StVenantKirchhoff, 2.5, 0.25)
        .constants()
        .unwrap();
    assert!((c.mu() - 1.0).abs() < 1e-15 && (c.lambda() - 1.0).abs() < 1e-15);
    assert!((c.plane_lambda() - 1.0 / 3.0).abs() < 1e-15);
    let d = KlMaterial::new(HyperelasticModel::StVenantKirchhoff, 2.5, 0.25).plate_bending_stiffness(0.1);
    assert!((d - 2.5e-3 / (12.0 * 0.9375)).abs() < 1e-18);
}

/// A random symmetric positive-definite in-plane block near the identity.
fn random_block(r: &mut impl Rng, size: f64) -> Matrix2<f64> {
    let f = Matrix2::new(
        1.0 + size * r.random_range(-1.0..1.0),
        size * r.random_range(-1.0..1.0),
        size * r.random_range(-1.0..1.0),
        1.0 + size * r.random_range(-1.0..1.0),
    );
    f.transpose() * f
}

#[test]
fn the_closed_form_transverse_stretch_makes_the_3d_density_stationary_and_minimal() {
    let mut r = rng(21);
    for model in MODELS {
        for nu in [0.0, 0.3, 0.45, -0.3] {
            let c = KlMaterial::new(model, 3.0, nu).constants().unwrap();
            for _ in 0..20 {
                let m = random_block(&mut r, 0.3);
                let c33 = plane_stress_c33(&m, &c).unwrap();
                // ∂W/∂c₃₃ = 0 and ∂²W/∂c₃₃² > 0 at the closed form (second-order dual in c₃₃ only).
                let w = density_3d(&m.map(Dual2_64::from_re), Dual2_64::new(c33, 1.0, 0.0), &c);
                assert!(w.v1.abs() < 1e-12 * c.mu(), "{model:?} ν = {nu}: ∂W/∂c33 = {}", w.v1);
                assert!(w.v2 > 0.0, "{model:?} ν = {nu}: not a minimum");
                // The condensed density is the 3D density there.
                let ps = plane_stress_density(&m, &c);
                assert!(
                    (ps - w.re).abs() <= 1e-12 * w.re.abs().max(1e-12),
                    "{model:?}: {ps} vs {}",
                    w.re
                );
            }
        }
    }
}

#[test]
fn cylindrical_stretching_gives_the_plane_strain_free_modulus() {
    // M = diag(1 + 2ε, 1) is a Green strain ε along x only: St. Venant–Kirchhoff in plane stress gives
    // W = E/(2(1 − ν²)) ε² exactly.
    let (e, nu) = (7.0, 0.3);
    let c = KlMaterial::new(HyperelasticModel::StVenantKirchhoff, e, nu)
        .constants()
        .unwrap();
    for eps in [1e-3, 0.05, 0.3] {
        let w = plane_stress_density(&Matrix2::new(1.0 + 2.0 * eps, 0.0, 0.0, 1.0), &c);
        let expected = e / (2.0 * (1.0 - nu * nu)) * eps * eps;
        assert!((w - expected).abs() < 1e-13 * expected, "ε = {eps}: {w} vs {expected}");
    }
}

#[test]
fn both_densities_agree_at_small_strains_and_differ_at_third_order() {
    let mut r = rng(22);
    let c_svk = KlMaterial::new(HyperelasticModel::StVenantKirchhoff, 1.0, 0.3)
        .constants()
        .unwrap();
    let c_nh = KlMaterial::new(HyperelasticModel::NeoHookean, 1.0, 0.3).constants().unwrap();
    for _ in 0..10 {
        let dir = random_block(&mut r, 1.0) - Matrix2::identity();
        let rel = |t: f64| {
            let m = Matrix2::identity() + dir * t;
            let (a, b) = (plane_stress_density(&m, &c_svk), plane_stress_density(&m, &c_nh));
            (a - b).abs() / a
        };
        // The relative difference is linear in the strain amplitude.
        let (r1, r2) = (rel(1e-3), rel(1e-4));
        assert!(r1 < 1e-2 && r2 < 1e-3, "{r1} {r2}");
        assert!((r1 / r2 - 10.0).abs() < 0.5, "ratio {}", r1 / r2);
    }
}

#[test]
fn the_neo_hookean_density_is_infinite_not_nan_without_a_plane_stress_solution() {
    let c = KlMaterial::new(HyperelasticModel::NeoHookean, 1.0, 0.3).constants().unwrap();
    for m in [
        Matrix2::new(1.0, 0.0, 0.0, -0.5),
        Matrix2::zeros(),
        Matrix2::new(1.0, 2.0, 2.0, 1.0),
    ] {
        let w = plane_stress_density(&m, &c);
        assert!(w == f64::INFINITY, "{m}: {w}");
        assert!(plane_stress_c33(&m, &c).is_none());
    }
    // An auxetic material has no solution beyond det M = μ/|λ|.
    let aux = KlMaterial::new(HyperelasticModel::NeoHookean, 1.0, -0.4).constants().unwrap();
    let limit = aux.mu() / aux.lambda().abs();
    assert!(plane_stress_density(&(Matrix2::identity() * (0.9 * limit).sqrt()), &aux).is_finite());
    assert_eq!(
        plane_stress_density(&(Matrix2::identity() * (1.1 * limit).sqrt()), &aux),
        f64::INFINITY
    );
}

#[test]
fn the_densities_vanish_with_zero_derivative_at_the_identity() {
    for model in MODELS {
        let c = KlMaterial::new(model, 1.0, 0.3).constants().unwrap();
        let (v, g) = num_dual::gradient(
            |s: nalgebra::SVector<num_dual::DualSVec64<3>, 3>| {
                plane_stress_density(&Matrix2::new(s[0], s[1], s[1], s[2]), &c)
            },
            &nalgebra::SVector::<f64, 3>::new(1.0, 0.0, 1.0),
        );
        assert!(v.abs() < 1e-16 && g.amax() < 1e-15, "{model:?}: {v}, {g}");
    }
}
