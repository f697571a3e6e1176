//! The membrane stress that raises the stabilisation of a stretched element, against the plane-stress
//! membrane forces of the model's isotropic law, and the factors it raises.

use cosserat_material::strain_space::{DensityMatrix, local_geometry, strain_hessian, strain_offset};
use cosserat_material::tension::{TENSION_SAFETY, membrane_stretch, membrane_stretch_predicted, membrane_tension};
use cosserat_material::{MaterialParameters, ModelOptions, ShellModel, StrainProjection, TermSet};
use nalgebra::{Matrix3, Rotation3, Vector3};

const E: f64 = 1e6;
const NU: f64 = 0.3;
const H: f64 = 0.01;

/// The density of a flat plate point with the rest frame `frame`.
fn plate_density(frame: &Matrix3<f64>) -> DensityMatrix {
    let moduli = MaterialParameters::new(H, E, NU, 1000.0, 1e-3).moduli().unwrap();
    let terms = TermSet::select(&ModelOptions::new(ShellModel::Plate), &moduli, false).unwrap();
    DensityMatrix::new(strain_hessian(
        &terms,
        &local_geometry(frame, &Matrix3::zeros()),
        &moduli,
    ))
}

/// The tangent vectors of the rest frame's plane after the in-plane strain `(ε₁, ε₂)` along its first
/// two columns and the rigid rotation `rotation`.
fn stretched(frame: &Matrix3<f64>, strain: [f64; 2], rotation: &Matrix3<f64>) -> [Vector3<f64>; 2] {
    std::array::from_fn(|g| rotation * frame.column(g) * (1.0 + strain[g]))
}

#[test]
fn membrane_tension_is_the_plane_stress_membrane_force() {
    let frame = *Rotation3::from_euler_angles(0.3, -0.2, 1.1).matrix();
    let density = plate_density(&frame);
    let offset = strain_offset(&frame, None, None);
    let spin = *Rotation3::from_euler_angles(1.0, 0.4, -2.0).matrix();
    let eps = 1e-3;
    // Equal stretch in both directions: N = E h ε / (1 − ν); a stretch along one direction only, the
    // other held: N = E h ε / (1 − ν²) along it. Neither depends on a rigid rotation of the sheet.
    for rotation in [Matrix3::identity(), spin] {
        let biaxial = membrane_tension(
            &membrane_stretch(&stretched(&frame, [eps, eps], &rotation), &offset),
            &density,
        );
        let expected = E * H * eps / (1.0 - NU);
        assert!((biaxial - expected).abs() <= 1e-9 * expected, "{biaxial} vs {expected}");
        let uniaxial = membrane_tension(
            &membrane_stretch(&stretched(&frame, [0.0, eps], &rotation), &offset),
            &density,
        );
        let expected = E * H * eps / (1.0 - NU * NU);
        assert!(
            (uniaxial - expected).abs() <= 1e-9 * expected,
            "{uniaxial} vs {expected}"
        );
    }
    // A compressed or unstretched sheet has no tension.
    assert_eq!(
        membrane_tension(
            &membrane_stretch(&stretched(&frame, [-eps, -eps], &spin), &offset),
            &density
        ),
        0.0
    );
    let rest = membrane_tension(
        &membrane_stretch(&stretched(&frame, [0.0, 0.0], &spin), &offset),
        &density,
    );
    assert!(rest.abs() <= 1e-12 * E * H, "{rest}");
}

#[test]
fn held_in_tension_raises_the_factors_to_the_stress() {
    let frame = Matrix3::identity();
    let density = plate_density(&frame);
    let d = density.matrix();
    let rest = StrainProjection {
        membrane: 1.0,
        drilling: 0.05,
        shear: 0.05,
    };
    assert_eq!(rest.held_in_tension(0.0, &density), rest);
    // A stress below `α² K / κ` leaves the factors; above, `α² = κ N / K` for the shear (K its stiffness)
    // and for the drilling with twice the stress (a turn about the normal shortens both directions).
    let small = 0.5 * rest.shear.powi(2) * d[(2, 2)] / TENSION_SAFETY;
    assert_eq!(rest.held_in_tension(small, &density), rest);
    let n = 1e-3 * E * H;
    let held = rest.held_in_tension(n, &density);
    assert!((held.shear.powi(2) - TENSION_SAFETY * n / d[(2, 2)]).abs() <= 1e-12);
    let drilling = d[(1, 1)] - 2.0 * d[(1, 3)] + d[(3, 3)];
    assert!((held.drilling.powi(2) - TENSION_SAFETY * 2.0 * n / drilling).abs() <= 1e-12);
    assert_eq!(held.membrane, rest.membrane);
    // The factors never exceed one (the point strains).
    let huge = rest.held_in_tension(E * H, &density);
    assert_eq!((huge.shear, huge.drilling), (1.0, 1.0));
}

/// The stretch predicted along a step is the stretch's first-order Taylor polynomial: its increment
/// matches the central difference of [`membrane_stretch`] along the step (an anisotropically stretched
/// and sheared surface, where the derivative of `√(F̂ᵀ F̂)` is not the symmetric part of `Qᵀ dF̂`), so
/// it misses the actual stretch by the step's square; a step that turns the surface, `dF̂ = W F̂` with
/// `W` skew, predicts no stretch while the turned surface does stretch at second order.
#[test]
fn the_predicted_stretch_is_the_first_order_taylor_polynomial() {
    let frame = *Rotation3::from_euler_angles(0.3, -0.2, 1.1).matrix();
    let offset = strain_offset(&frame, None, None);
    let spin = *Rotation3::from_euler_angles(1.0, 0.4, -2.0).matrix();
    let mut f = stretched(&frame, [0.03, -0.02], &spin);
    f[1] += 0.04 * f[0];
    let df = [Vector3::new(0.3, -0.7, 0.2), Vector3::new(-0.4, 0.1, 0.9)];
    let at = |t: f64| membrane_stretch(&[f[0] + df[0] * t, f[1] + df[1] * t], &offset);
    let step = 1e-4;
    let h = 1e-6;
    let (plus, minus, start) = (at(h), at(-h), at(0.0));
    let predicted = membrane_stretch_predicted(&f, &[df[0] * step, df[1] * step], &offset);
    let actual = at(step);
    for k in 0..4 {
        let difference = start[k] + step * (plus[k] - minus[k]) / (2.0 * h);
        assert!(
            (predicted[k] - difference).abs() <= 1e-11,
            "entry {k}: {} vs {difference}",
            predicted[k]
        );
        assert!(
            (predicted[k] - actual[k]).abs() <= 1e-7,
            "entry {k}: {} vs {}",
            predicted[k],
            actual[k]
        );
    }
    // A turn of an equally stretched surface by 0.1 rad about its normal and about a tangent.
    let f = stretched(&frame, [0.01, 0.01], &Matrix3::identity());
    let normal = f[0].cross(&f[1]).normalize();
    for axis in [normal, f[0].normalize()] {
        let w = axis.cross_matrix() * 0.1;
        let predicted = membrane_stretch_predicted(&f, &[w * f[0], w * f[1]], &offset);
        let turned = membrane_stretch(&[f[0] + w * f[0], f[1] + w * f[1]], &offset);
        let start = membrane_stretch(&f, &offset);
        for k in 0..4 {
            assert!(
                (predicted[k] - start[k]).abs() <= 1e-14,
                "entry {k}: {predicted:?} vs {start:?}"
            );
        }
        assert!(
            turned[0] + turned[3] - start[0] - start[3] > 1e-3,
            "the turned surface stretches: {turned:?} vs {start:?}"
        );
    }
}
