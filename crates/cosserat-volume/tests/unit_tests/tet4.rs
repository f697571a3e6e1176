//! Tet4 shape data: gradients, affine reproduction, degenerate elements.

use super::common::{mat3, rng, tet, vec3};
use cosserat_volume::tet4::{deformation_gradient, point_omega, tet4_point};
use nalgebra::{Matrix3, Vector3};

#[test]
fn gradients_sum_to_zero_and_reproduce_affine_maps() {
    let mut r = rng(4);
    for _ in 0..5 {
        let x = tet(&mut r);
        let p = tet4_point(&x).unwrap();
        let sum: Vector3<f64> = p.grad.column_iter().map(|c| c.into_owned()).sum();
        assert!(sum.norm() < 1e-12 * p.grad.amax());
        assert!((p.values.sum() - 1.0).abs() < 1e-15);
        // The volume of the tetrahedron, det[x₁ − x₀, …]/6.
        let v = Matrix3::from_columns(&[x[1] - x[0], x[2] - x[0], x[3] - x[0]]).determinant() / 6.0;
        assert!((p.weight - v).abs() < 1e-15);
        let a = Matrix3::identity() + mat3(&mut r, 0.3);
        let b = vec3(&mut r, 1.0);
        let f = deformation_gradient(&p, &x.map(|xi| a * xi + b));
        assert!((Matrix3::from_columns(&f) - a).amax() < 1e-12);
        // A uniform angular velocity interpolates to itself.
        let w = vec3(&mut r, 1.0);
        assert!((point_omega(&p, &[w; 4]) - w).norm() < 1e-15);
    }
}

#[test]
fn flat_and_inverted_tetrahedra_have_no_point() {
    let flat = [
        Vector3::zeros(),
        Vector3::x(),
        Vector3::y(),
        Vector3::new(1.0, 1.0, 0.0),
    ];
    assert!(tet4_point(&flat).is_none());
    let inverted = [Vector3::zeros(), Vector3::y(), Vector3::x(), Vector3::z()];
    assert!(tet4_point(&inverted).is_none());
}
