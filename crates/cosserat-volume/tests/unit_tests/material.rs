//! Validation and derived moduli of the micropolar material.

use cosserat_material::MaterialParameters;
use cosserat_volume::{ContinuumParameters, MaterialError, MicropolarModuli, Slab};

#[test]
fn moduli_follow_from_young_and_poisson() {
    let m = MicropolarModuli::of(&ContinuumParameters::new(2.6e6, 0.3, 1000.0, 0.1)).unwrap();
    assert!((m.mu - 1e6).abs() < 1e-6);
    // λ = E ν / ((1 + ν)(1 − 2ν)) = 2.6e6 · 0.3 / (1.3 · 0.4) = 1.5e6.
    assert!((m.lambda - 1.5e6).abs() < 1e-6);
    assert_eq!(m.mu_c, m.mu);
    assert_eq!(m.curvature_coefficients, [1.0, 1.0, 0.0]);
}

#[test]
fn invalid_parameters_are_named() {
    let base = ContinuumParameters::new(1e6, 0.3, 1000.0, 0.1);
    type Spoil = fn(&mut ContinuumParameters);
    let cases: [(&str, Spoil); 6] = [
        ("poisson_ratio", |m| m.poisson_ratio = 0.5),
        ("youngs_modulus", |m| m.youngs_modulus = f64::NAN),
        ("density", |m| m.density = 0.0),
        ("mu_c_factor", |m| m.mu_c_factor = -1.0),
        ("length_scale", |m| m.length_scale = f64::INFINITY),
        ("curvature_coefficients[2]", |m| m.curvature_coefficients[2] = -0.1),
    ];
    for (field, spoil) in cases {
        let mut m = base;
        spoil(&mut m);
        match MicropolarModuli::of(&m) {
            Err(MaterialError::InvalidParameter { name, .. }) => assert_eq!(name, field),
            other => panic!("{field}: expected an error, got {other:?}"),
        }
    }
}

#[test]
fn invalid_parameters_are_rejected_as_for_the_shell() {
    // The same bad value of a shared parameter gets the same error from both models' materials.
    let volume = ContinuumParameters::new(1e6, 0.3, 1000.0, 0.1);
    let shell = MaterialParameters::new(0.01, 1e6, 0.3, 1000.0, 0.1);
    let cases: [(f64, f64, f64, f64); 4] = [
        (-1e6, 0.3, 1000.0, 0.1),
        (1e6, -1.0, 1000.0, 0.1),
        (1e6, 0.3, f64::NAN, 0.1),
        (1e6, 0.3, 1000.0, -0.1),
    ];
    for (e, nu, rho, l) in cases {
        let v = MicropolarModuli::of(&ContinuumParameters::new(e, nu, rho, l)).unwrap_err();
        let s = MaterialParameters::new(shell.thickness, e, nu, rho, l).moduli().unwrap_err();
        // The message names the field, the value and the reason (`PartialEq` would fail on NaN).
        assert_eq!(v.to_string(), s.to_string());
    }
    assert!(MicropolarModuli::of(&volume).is_ok() && shell.moduli().is_ok());
    // The shell's continuum part is the volume's material with the same defaults.
    assert_eq!(shell.continuum(), volume);
}

#[test]
fn slab_curvature_under_rest_curvature_is_the_stiffness_weighted_mean() {
    // E = 1e6, ν = 0.25, h = 0.02, L_c = 0.1, b₁ + b₂ = 2: D = 1e6·8e-6/(12·0.9375) = 0.71111…,
    // C = 0.02 · 4e5 · 0.01 · 2 = 160, k/κ = C/(C + D).
    let slab = Slab {
        material: ContinuumParameters::new(1e6, 0.25, 1000.0, 0.1),
        thickness: 0.02,
    };
    let d = 1e6 * 8e-6 / (12.0 * 0.9375);
    assert!((slab.plate_bending_stiffness() - d).abs() < 1e-12);
    assert!((slab.curvature_stiffness() - 160.0).abs() < 1e-9);
    let k = slab.curvature_under_rest_curvature(3.0);
    assert!((k - 3.0 * 160.0 / (160.0 + d)).abs() < 1e-12);
}
