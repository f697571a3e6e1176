//! Rest data of a stencil: areas, thickness weights over the exact rest volume, and the errors.

use super::common::{cases, stencil_case};
use cosserat_fem::MeshError;
use cosserat_fem::mesh::procedural;
use cosserat_kl::fundamental_form::inverse2;
use cosserat_kl::{KlError, StencilRest, ThicknessRule};
use nalgebra::SVector;

#[test]
fn weights_integrate_the_rest_volume_of_each_face() {
    // Σ w = A ∫ (1 − 2H̄ξ + K̄ξ²) dξ = A (h + K̄ h³/12), with the mean and Gauss curvature of the face.
    let h = 0.02;
    for case in cases() {
        let r = &case.rest;
        let s = inverse2(r.first_form()) * r.second_form();
        let (mean, gauss) = (0.5 * s.trace(), s.determinant());
        let total: f64 = r.points().iter().map(|p| p.weight).sum();
        let expected = r.area() * (h + gauss * h * h * h / 12.0);
        assert!(
            (total - expected).abs() < 1e-15 * expected,
            "{}: {total} vs {expected}",
            case.name
        );
        // Curved faces carry curvature; flat ones do not.
        let curved = case.name == "sphere" || case.name == "cylinder";
        assert_eq!(mean.abs() > 0.1, curved, "{}: H = {mean}", case.name);
        assert_eq!(r.points().len(), ThicknessRule::default().n_points());
    }
}

#[test]
fn the_area_is_half_the_cross_product() {
    let case = &cases()[0];
    let x = &case.x;
    let e1 = nalgebra::Vector3::new(x[3] - x[0], x[4] - x[1], x[5] - x[2]);
    let e2 = nalgebra::Vector3::new(x[6] - x[0], x[7] - x[1], x[8] - x[2]);
    assert!((case.rest.area() - 0.5 * e1.cross(&e2).norm()).abs() < 1e-16);
}

#[test]
fn a_shell_thicker_than_the_curvature_diameter_is_rejected() {
    // Unit icosphere: principal radii close to 1, so h = 2.2 folds the rest volume and h = 1.6 does not.
    let sphere = procedural::icosphere(1.0, 2).unwrap().mesh;
    let ok = stencil_case("sphere", &sphere, 3, 1.6);
    assert!(ok.rest.points().iter().all(|p| p.weight > 0.0));
    let x = ok.x;
    match StencilRest::try_new(3, &x, [true; 3], 2.2, &ThicknessRule::default()) {
        Err(KlError::ThickerThanCurvature {
            elem_idx: 3,
            thickness,
            radius,
        }) => {
            assert_eq!(thickness, 2.2);
            assert!(radius > 0.9 && radius < 1.1, "radius {radius}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn degenerate_faces_and_bad_thicknesses_are_rejected() {
    let case = &cases()[0];
    let rule = ThicknessRule::default();
    for h in [0.0, -1.0, f64::NAN] {
        assert!(matches!(
            StencilRest::try_new(0, &case.x, [true; 3], h, &rule),
            Err(KlError::InvalidParameter { name: "thickness", .. })
        ));
    }
    let mut x: SVector<f64, 18> = case.x;
    for k in 0..3 {
        x[6 + k] = x[k];
    }
    assert!(matches!(
        StencilRest::try_new(5, &x, [true; 3], 0.01, &rule),
        Err(KlError::Mesh(MeshError::DegenerateElement { elem_idx: 5, .. }))
    ));
}
