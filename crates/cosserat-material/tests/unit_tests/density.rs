//! The energy density: its strain Hessian, the flat limit of the shell, pure bending and scalings.

use super::common;
use cosserat_geometry::rotation::{exp_map, quaternion_from_matrix};
use cosserat_material::density::{PointGeometry, density};
use cosserat_material::kernel::PointShape;
use cosserat_material::oracle::{PointContext, density_hessian, local_energy};
use cosserat_material::strain_space::{StrainVector, local_geometry, pack, strain_hessian, strain_offset, unpack};
use cosserat_material::{
    AxlVariant, CurvedTerms, MaterialParameters, MembraneVolume, ModelOptions, ShellModel, TermSet,
};
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};
use rand::Rng;

fn random_strain(rng: &mut rand_chacha::ChaCha8Rng) -> StrainVector {
    StrainVector::from_fn(|_, _| rng.random_range(-1.0..1.0))
}

#[test]
fn strain_hessian_reproduces_the_density_exactly() {
    let mut rng = common::rng(1);
    let mut mat = MaterialParameters::new(0.02, 3e6, 0.4, 1000.0, 0.01);
    mat.curvature_coefficients = [0.5, 1.5, 0.25];
    let moduli = mat.moduli().unwrap();
    for (model, curved) in [(ShellModel::Plate, false), (ShellModel::Shell, true)] {
        let terms = TermSet::select(&ModelOptions::new(model), &moduli, curved).unwrap();
        let frame = common::rotation(&mut rng, 3.0);
        let geom = local_geometry(&frame, &common::curvature_tensor(&mut rng, &frame, 20.0));
        let d = strain_hessian(&terms, &geom, &moduli);
        assert_eq!(d, d.transpose());
        for _ in 0..10 {
            let s = random_strain(&mut rng);
            let (e, g) = unpack(&s);
            let psi = density(&terms, &e, &g, &geom, &moduli);
            let quad = 0.5 * s.dot(&(d * s));
            assert!((psi - quad).abs() <= 1e-13 * psi.abs().max(d.amax()), "{psi} vs {quad}");
        }
        // The density is non-negative, so D is positive semi-definite.
        let eig = d.symmetric_eigenvalues();
        assert!(eig.min() >= -1e-12 * eig.amax(), "negative eigenvalue {}", eig.min());
    }
}

/// The closed-form strain Hessian equals the one num-dual differentiates out of `density` (which the
/// closed form does not use), for every term set of the models on random curved points.
#[test]
fn closed_form_strain_hessian_equals_the_differentiated_density() {
    let mut rng = common::rng(7);
    let mut mat = MaterialParameters::new(0.03, 5e6, 0.3, 1000.0, 0.02);
    mat.curvature_coefficients = [0.7, 1.3, 0.4];
    let moduli = mat.moduli().unwrap();
    let mut options = Vec::new();
    for model in [ShellModel::Plate, ShellModel::Shell] {
        let base = ModelOptions::new(model);
        options.push(base);
        options.push(ModelOptions {
            curved_terms: CurvedTerms::ReferenceCompatibility,
            ..base
        });
    }
    options.push(ModelOptions {
        membrane_volume: MembraneVolume::Nonlinear,
        ..ModelOptions::new(ShellModel::Plate)
    });
    for o in &options {
        for curved in [false, true] {
            let Ok(terms) = TermSet::select(o, &moduli, curved) else {
                continue;
            };
            for _ in 0..3 {
                let frame = common::rotation(&mut rng, 3.0);
                let geom = local_geometry(&frame, &common::curvature_tensor(&mut rng, &frame, 30.0));
                let closed = strain_hessian(&terms, &geom, &moduli);
                let dual = density_hessian(&terms, &geom, &moduli);
                let scale = dual.amax();
                assert!(
                    (closed - dual).amax() <= 1e-13 * scale,
                    "{o:?} curved {curved}: differs by {:e} of {scale:e}",
                    (closed - dual).amax()
                );
            }
        }
    }
}

#[test]
fn shell_density_with_zero_curvature_equals_plate_density() {
    let mut rng = common::rng(2);
    let moduli = MaterialParameters::new(0.01, 1e6, 0.3, 1000.0, 0.05).moduli().unwrap();
    // Force the curved term set on a flat point: every curved term must reduce to its plate counterpart.
    let shell = TermSet::select(&ModelOptions::new(ShellModel::Shell), &moduli, true).unwrap();
    let plate = TermSet::select(&ModelOptions::new(ShellModel::Plate), &moduli, false).unwrap();
    let flat = PointGeometry::flat(&Vector3::new(0.3, -0.2, 0.9).normalize());
    for _ in 0..10 {
        let (e, g) = unpack(&random_strain(&mut rng));
        let a = density(&shell, &e, &g, &flat, &moduli);
        let b = density(&plate, &e, &g, &flat, &moduli);
        assert!((a - b).abs() <= 1e-14 * b.abs(), "{a} vs {b}");
    }
}

/// Energy density of a flat strip along x bent about y with uniform curvature κ, evaluated on one tiny
/// linear rotation element (nodes (0,0), (δ,0), (0,δ), point at (δ/6, δ/6)) with rotations
/// `R(x) = exp(κ x [e_y]×)` and tangents `F̂ = [R e_x, e_y]`: the exact pure-bending state.
fn pure_bending_density(material: &MaterialParameters, kappa: f64) -> f64 {
    let moduli = material.moduli().unwrap();
    let terms = TermSet::select(&ModelOptions::new(ShellModel::Plate), &moduli, false).unwrap();
    let delta = 1e-4 / kappa;
    let xp = delta / 6.0;
    let rot = |x: f64| exp_map(&(Vector3::y() * (kappa * x)));
    let shape = PointShape::<3, 3> {
        disp_grad: SMatrix::zeros(),
        rot_values: SVector::from([2.0 / 3.0, 1.0 / 6.0, 1.0 / 6.0]),
        rot_grad: SMatrix::<f64, 2, 3>::new(-1.0, 1.0, 0.0, -1.0, 0.0, 1.0) / delta,
        frame: Matrix3::identity(),
        weight: 1.0,
    };
    let offset = strain_offset(&Matrix3::identity(), None, None);
    let geom = local_geometry(&Matrix3::identity(), &Matrix3::zeros());
    let ctx = PointContext {
        shape: &shape,
        point_quaternion: quaternion_from_matrix(&rot(xp)),
        node_quaternions: [
            quaternion_from_matrix(&rot(0.0)),
            quaternion_from_matrix(&rot(delta)),
            quaternion_from_matrix(&rot(0.0)),
        ],
        dt: 0.01,
        offset: &offset,
        geometry: &geom,
        terms: &terms,
        moduli: &moduli,
        axl: AxlVariant::SkewPart,
    };
    let f_hat = [rot(xp) * Vector3::x(), Vector3::y()];
    local_energy(&ctx, &f_hat, &[Vector3::zeros(); 3])
}

#[test]
fn pure_bending_energy_is_half_the_strip_stiffness_times_curvature_squared() {
    for (nu, lc, coeffs, kappa_b) in [
        (0.0, 0.0, [1.0, 1.0, 0.0], 1.0),
        (0.3, 2e-3, [1.0, 1.0, 0.0], 1.0),
        (0.45, 5e-3, [0.3, 2.0, 0.7], 0.8),
    ] {
        let mut m = MaterialParameters::new(1e-2, 2e6, nu, 1000.0, lc);
        m.curvature_coefficients = coeffs;
        m.bending_correction = kappa_b;
        let kappa = 3.0;
        let psi = pure_bending_density(&m, kappa);
        // B = κ_b E h³/(12(1−ν²)) + h μ L_c² (b₁ + b₂) (see MaterialParameters::strip_bending_stiffness).
        let h: f64 = 1e-2;
        let mu = 2e6 / (2.0 * (1.0 + nu));
        let b = kappa_b * 2e6 * h.powi(3) / (12.0 * (1.0 - nu * nu)) + h * mu * lc * lc * (coeffs[0] + coeffs[1]);
        assert!((b - m.strip_bending_stiffness()).abs() < 1e-14 * b);
        let expected = 0.5 * b * kappa * kappa;
        // The discrete curvature of the tiny element is exact to O((κδ)²) = 1e-8.
        assert!(
            (psi - expected).abs() < 1e-6 * expected,
            "ν = {nu}: {psi} vs {expected}"
        );
    }
}

#[test]
fn bending_scales_with_thickness_cubed_and_poisson_but_not_with_mu_c() {
    let base = |h: f64, nu: f64, mu_c: f64| {
        let mut m = MaterialParameters::new(h, 1e6, nu, 1000.0, 0.0);
        m.mu_c_factor = mu_c;
        pure_bending_density(&m, 2.0)
    };
    let r = base(2e-3, 0.3, 1.0) / base(1e-3, 0.3, 1.0);
    assert!((r - 8.0).abs() < 1e-7, "h³ scaling: ratio {r}");
    let r = base(1e-3, 0.4, 1.0) / base(1e-3, 0.0, 1.0);
    assert!((r - 1.0 / (1.0 - 0.16)).abs() < 1e-7, "Poisson dependence: ratio {r}");
    let r = base(1e-3, 0.3, 5.0) / base(1e-3, 0.3, 0.1);
    assert!((r - 1.0).abs() < 1e-7, "μ_c must not enter pure bending: ratio {r}");
}

#[test]
fn drilling_mismatch_costs_mu_c() {
    // E with a pure in-plane skew part (drilling): W_m = μ_c |skew E|², times h.
    let moduli = |f: f64| {
        let mut m = MaterialParameters::new(1e-2, 1e6, 0.3, 1000.0, 0.0);
        m.mu_c_factor = f;
        m.moduli().unwrap()
    };
    let terms = TermSet::select(&ModelOptions::new(ShellModel::Plate), &moduli(1.0), false).unwrap();
    let flat = PointGeometry::flat(&Vector3::z());
    let e = Matrix3::new(0.0, -0.01, 0.0, 0.01, 0.0, 0.0, 0.0, 0.0, 0.0);
    for f in [0.0, 0.5, 2.0] {
        let m = moduli(f);
        let psi = density(&terms, &e, &Matrix3::zeros(), &flat, &m);
        let expected = 1e-2 * m.mu_c * 2e-4;
        assert!(
            (psi - expected).abs() <= 1e-15 + 1e-13 * expected,
            "{psi} vs {expected}"
        );
    }
    let _ = pack(&e, &Matrix3::zeros());
}
