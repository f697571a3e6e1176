//! Parameter validation: every bad value is rejected with its name, before any computation.

use cosserat_material::{
    ContinuumParameters, MaterialError, MaterialParameters, MembraneVolume, ModelOptions, ShellModel, TermSet,
};

fn valid() -> MaterialParameters {
    MaterialParameters::new(1e-3, 1e6, 0.3, 1000.0, 1e-3)
}

fn rejected_name(m: MaterialParameters) -> &'static str {
    match m.moduli() {
        Err(MaterialError::InvalidParameter { name, .. }) => name,
        other => panic!("expected an invalid parameter, got {other:?}"),
    }
}

#[test]
fn bad_parameters_are_rejected_by_name() {
    assert!(valid().moduli().is_ok());
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert_eq!(
            rejected_name(MaterialParameters {
                thickness: bad,
                ..valid()
            }),
            "thickness"
        );
        assert_eq!(
            rejected_name(MaterialParameters {
                youngs_modulus: bad,
                ..valid()
            }),
            "youngs_modulus"
        );
        assert_eq!(
            rejected_name(MaterialParameters {
                density: bad,
                ..valid()
            }),
            "density"
        );
    }
    for bad in [0.5, 0.7, -1.0, -2.0, f64::NAN] {
        assert_eq!(
            rejected_name(MaterialParameters {
                poisson_ratio: bad,
                ..valid()
            }),
            "poisson_ratio"
        );
    }
    for bad in [-1e-9, f64::NAN] {
        assert_eq!(
            rejected_name(MaterialParameters {
                mu_c_factor: bad,
                ..valid()
            }),
            "mu_c_factor"
        );
        assert_eq!(
            rejected_name(MaterialParameters {
                length_scale: bad,
                ..valid()
            }),
            "length_scale"
        );
    }
    let mut m = valid();
    m.curvature_coefficients[1] = -1.0;
    assert_eq!(rejected_name(m), "curvature_coefficients[1]");
}

#[test]
fn moduli_follow_the_three_dimensional_formulas() {
    let m = MaterialParameters::new(1e-3, 70e9, 0.35, 2700.0, 2e-6).moduli().unwrap();
    let mu = 70e9 / 2.7;
    let lambda = 70e9 * 0.35 / (1.35 * 0.3);
    assert!((m.mu - mu).abs() < 1e-6 * mu);
    assert!((m.lambda - lambda).abs() < 1e-6 * lambda);
    assert!((m.plane_lambda - lambda * mu / (lambda + 2.0 * mu)).abs() < 1e-6 * lambda);
    assert_eq!(m.mu_c, m.mu);
}

#[test]
fn active_terms_follow_model_material_and_rest_state() {
    let moduli = valid().moduli().unwrap();
    let plate = TermSet::select(&ModelOptions::new(ShellModel::Plate), &moduli, false).unwrap();
    assert_eq!(plate.names(), ["membrane", "bending", "curvature"]);
    let no_lc = MaterialParameters {
        length_scale: 0.0,
        ..valid()
    }
    .moduli()
    .unwrap();
    let plate = TermSet::select(&ModelOptions::new(ShellModel::Plate), &no_lc, false).unwrap();
    assert_eq!(plate.names(), ["membrane", "bending"]);
    let shell_flat = TermSet::select(&ModelOptions::new(ShellModel::Shell), &moduli, false).unwrap();
    assert_eq!(shell_flat.names(), ["membrane", "bending", "curvature"]);
    let shell = TermSet::select(&ModelOptions::new(ShellModel::Shell), &moduli, true).unwrap();
    assert_eq!(shell.terms().len(), 7);
    let compat = ModelOptions {
        curved_terms: cosserat_material::CurvedTerms::ReferenceCompatibility,
        ..ModelOptions::new(ShellModel::Shell)
    };
    let compat = TermSet::select(&compat, &moduli, true).unwrap();
    assert_eq!(
        compat.names(),
        [
            "curved_membrane_1 x2",
            "curved_membrane_2 x2",
            "curved_membrane_3 x2",
            "curved_membrane_4"
        ]
    );
    let nonlinear = ModelOptions {
        membrane_volume: MembraneVolume::Nonlinear,
        ..ModelOptions::new(ShellModel::Shell)
    };
    assert!(matches!(
        TermSet::select(&nonlinear, &moduli, true),
        Err(MaterialError::Unsupported(_))
    ));
}

#[test]
fn the_continuum_part_round_trips_and_shares_the_defaults() {
    let mut p = MaterialParameters::new(0.01, 2e6, 0.25, 900.0, 0.3);
    assert_eq!(p.continuum(), ContinuumParameters::new(2e6, 0.25, 900.0, 0.3));
    p.mu_c_factor = 0.5;
    p.curvature_coefficients = [2.0, 0.5, 0.1];
    assert_eq!(MaterialParameters::with_continuum(p.thickness, p.continuum()), p);
    // The one field the continuum does not carry keeps its default.
    p.bending_correction = 0.8;
    assert_eq!(
        MaterialParameters::with_continuum(p.thickness, p.continuum()).bending_correction,
        1.0
    );
}
