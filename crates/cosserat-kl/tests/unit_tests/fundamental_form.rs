//! The discrete fundamental forms: closed forms on simple configurations and convergence of the shape
//! operator on regular stencils of a sphere and a cylinder.

use cosserat_kl::fundamental_form::{
    first_form, first_form_entries, inverse2, mid_edge_measure, second_form, shifted_metric, strain_locals,
};
use nalgebra::{Matrix2, SVector, Vector3};

#[test]
fn the_first_form_holds_the_edge_products() {
    let q = [
        Vector3::new(1.0, 1.0, 1.0),
        Vector3::new(3.0, 1.0, 1.0),
        Vector3::new(2.0, 2.0, 1.0),
    ];
    assert_eq!(first_form_entries(&q), [4.0, 2.0, 2.0]);
}

#[test]
fn the_mid_edge_measure_of_a_hinge_is_minus_twice_the_sine_of_half_the_fold() {
    // Face (qᵢ, qⱼ, qₖ) in the plane z = 0 with normal +z; the neighbour across the edge on the y axis is
    // folded up by φ. The mid-edge normal is the bisector (−sin φ/2, 0, cos φ/2), and qⱼ + qₖ − 2qᵢ = 2 e_x.
    let (qi, qj, qk) = (
        Vector3::new(-1.0, 0.0, 0.0),
        Vector3::new(0.0, -1.0, 0.0),
        Vector3::new(0.0, 1.0, 0.0),
    );
    for phi in [-1.2f64, -0.3, 0.0, 1e-3, 0.5, 1.4, 2.5] {
        let p = Vector3::new(phi.cos(), 0.3, phi.sin());
        let ii = mid_edge_measure(&qi, &qj, &qk, &p);
        let expected = -2.0 * (0.5 * phi).sin();
        assert!((ii - expected).abs() < 1e-14, "φ = {phi}: {ii} vs {expected}");
    }
}

#[test]
fn shifted_metric_and_inverse_are_consistent() {
    let a = Matrix2::new(2.0, 0.3, 0.3, 1.0);
    let b = Matrix2::new(0.2, -0.1, -0.1, 0.4);
    let ainv = inverse2(&a);
    assert!((ainv * a - Matrix2::identity()).amax() < 1e-15);
    // g(ξ) = (I − ξ b a⁻¹)ᵀ-weighted form: g = (a − ξ b) a⁻¹ (a − ξ b).
    let xi = 0.3;
    let g = shifted_metric(&a, &b, &(b * ainv * b), xi);
    let expected = (a - b * xi) * ainv * (a - b * xi);
    assert!((g - expected).amax() < 1e-15);
}

/// Six points of a regular stencil of side `s`: an equilateral face and the three faces across its
/// edges (reflections of the opposite corners), in a plane through the origin, mapped by `map`.
fn regular_stencil(s: f64, rotation: f64, map: impl Fn(Vector3<f64>) -> Vector3<f64>) -> SVector<f64, 18> {
    let corner = |k: f64| {
        let t = rotation + 2.0 * std::f64::consts::PI * k / 3.0;
        Vector3::new(t.cos(), t.sin(), 0.0) * (s / 3f64.sqrt())
    };
    let q = [corner(0.0), corner(1.0), corner(2.0)];
    let p: Vec<Vector3<f64>> = (0..3).map(|i| q[(i + 1) % 3] + q[(i + 2) % 3] - q[i]).collect();
    let pts = [q[0], q[1], q[2], p[0], p[1], p[2]];
    SVector::from_fn(|i, _| map(pts[i / 3])[i % 3])
}

/// `max |S + κ|` with the discrete shape operator `S = a⁻¹ b` and the expected one `−κ` (outward normal).
fn shape_operator_error(x: &SVector<f64, 18>, expected: &Matrix2<f64>) -> f64 {
    let s = strain_locals(x, [true; 3]);
    let (a, b) = (first_form(&s), second_form(&s));
    (inverse2(&a) * b - expected).amax()
}

#[test]
fn the_shape_operator_of_a_regular_stencil_on_a_sphere_converges_at_second_order() {
    // Points lifted onto the sphere of radius R with centre (0, 0, −R): the outward normal is +z at the
    // stencil and b = −∇n = −a/R, so S = −I/R.
    let r = 1.0;
    let lift = |v: Vector3<f64>| {
        let c = Vector3::new(0.0, 0.0, -r);
        c + (v - c).normalize() * r
    };
    let expected = -Matrix2::identity() / r;
    let sizes = [0.2, 0.1, 0.05, 0.025];
    for rotation in [0.0, 0.4] {
        let errors: Vec<f64> = sizes
            .iter()
            .map(|&s| shape_operator_error(&regular_stencil(s, rotation, lift), &expected))
            .collect();
        let orders: Vec<f64> = errors.windows(2).map(|e| (e[0] / e[1]).log2()).collect();
        eprintln!("sphere, regular stencil (rotation {rotation}): errors {errors:?}, orders {orders:?}");
        assert!(errors[3] < 1e-3, "{errors:?}");
        assert!(orders.iter().all(|&o| o > 1.8), "orders {orders:?}");
    }
}

#[test]
fn the_shape_operator_of_a_cylinder_converges_at_second_order_in_any_direction() {
    // Cylinder of radius R about an axis in the plane at angle θ to x, centre line at z = −R; the
    // isometric wrap of the plane. Expected S = −(1/R) d ⊗ d (in the parameter basis of the face)
    // with d the in-plane direction across the axis.
    let r = 1.0;
    for theta in [0.0, 0.3, std::f64::consts::FRAC_PI_2] {
        let axis = Vector3::new(theta.cos(), theta.sin(), 0.0);
        let across = Vector3::new(-theta.sin(), theta.cos(), 0.0);
        let wrap = |v: Vector3<f64>| {
            let (u, w) = (v.dot(&across), v.dot(&axis));
            axis * w + across * (r * (u / r).sin()) + Vector3::new(0.0, 0.0, r * ((u / r).cos() - 1.0))
        };
        let sizes = [0.2, 0.1, 0.05, 0.025];
        let errors: Vec<f64> = sizes
            .iter()
            .map(|&s| {
                let x = regular_stencil(s, 0.1, wrap);
                // The expected S in the face's parameter basis: eₐ · (−d ⊗ d / R) e_β, times a⁻¹.
                let q0 = Vector3::new(x[0], x[1], x[2]);
                let e1 = Vector3::new(x[3], x[4], x[5]) - q0;
                let e2 = Vector3::new(x[6], x[7], x[8]) - q0;
                let a = Matrix2::new(e1.dot(&e1), e1.dot(&e2), e1.dot(&e2), e2.dot(&e2));
                let da = Vector3::new(e1.dot(&across), e2.dot(&across), 0.0);
                let b = -Matrix2::new(da.x * da.x, da.x * da.y, da.x * da.y, da.y * da.y) / r;
                shape_operator_error(&x, &(inverse2(&a) * b))
            })
            .collect();
        let orders: Vec<f64> = errors.windows(2).map(|e| (e[0] / e[1]).log2()).collect();
        eprintln!("cylinder at θ = {theta}: errors {errors:?}, orders {orders:?}");
        assert!(errors[3] < 1e-3, "{errors:?}");
        assert!(orders.iter().all(|&o| o > 1.8), "orders {orders:?}");
    }
}

#[test]
fn boundary_edges_measure_no_bending() {
    let x = regular_stencil(0.1, 0.0, |v| v + Vector3::new(0.0, 0.0, v.x * v.x));
    let s = strain_locals(&x, [true, false, false]);
    assert!(s[3] != 0.0);
    assert_eq!((s[4], s[5]), (0.0, 0.0));
}
