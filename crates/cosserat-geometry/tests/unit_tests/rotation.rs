//! Rotations: the quaternion ↔ matrix maps, `axl`/`skew`, the exponential and Cayley maps, the time
//! update `Φ(q, ω, Δt)` with its measured order against the exponential map, the derivative jet of
//! the update, and the hemisphere guard.
//!
//! References are closed forms: the axis–angle quaternion `(cos θ/2, sin θ/2 u)`, the planar rotation
//! matrix, nalgebra's own quaternion algebra, the Cayley angle `2 arctan(|v|/2)` and, for the order
//! study, the exact angle deficit of the Cayley update about a fixed axis.

use super::{log_log_slope, max_abs, random_unit_quaternion, random_unit_vector, random_vector, rng, rotation_defect};
use cosserat_geometry::rotation::{
    RotationJet, axl, axl_upper, cayley, exp_map, quaternion_from_matrix, quaternion_product, quaternion_update,
    rotation_matrix, same_hemisphere, skew,
};
use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};
use num_dual::{Dual2_64, Dual64};
use rand::Rng;
use std::f64::consts::{FRAC_PI_2, PI, SQRT_2};

/// The unit quaternion of the rotation by `angle` about the unit vector `axis`.
fn axis_angle(axis: &Vector3<f64>, angle: f64) -> Quaternion<f64> {
    let s = (0.5 * angle).sin();
    Quaternion::new((0.5 * angle).cos(), s * axis.x, s * axis.y, s * axis.z)
}

/// The rotation by `angle` about the z axis, counter-clockwise seen from +z.
fn rotation_about_z(angle: f64) -> Matrix3<f64> {
    let (s, c) = angle.sin_cos();
    Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
}

/// `‖R_α − R_β‖_F` for two rotations about one axis whose angles differ by `delta`.
fn same_axis_distance(delta: f64) -> f64 {
    2.0 * SQRT_2 * (0.5 * delta).sin().abs()
}

fn quaternion_distance_up_to_sign(p: &Quaternion<f64>, q: &Quaternion<f64>) -> f64 {
    (p - q).norm().min((p + q).norm())
}

#[test]
fn rotation_matrix_matches_closed_forms() {
    assert_eq!(
        rotation_matrix(&Quaternion::new(1.0, 0.0, 0.0, 0.0)),
        Matrix3::identity()
    );
    // Half turn about x: diag(1, −1, −1).
    let half_x = rotation_matrix(&Quaternion::new(0.0, 1.0, 0.0, 0.0));
    assert_eq!(half_x, Matrix3::from_diagonal(&Vector3::new(1.0, -1.0, -1.0)));
    // Active, counter-clockwise rotation about z.
    for angle in [0.3, FRAC_PI_2, 2.0, -1.1] {
        let r = rotation_matrix(&axis_angle(&Vector3::z(), angle));
        assert!((r - rotation_about_z(angle)).amax() < 1e-15, "angle {angle}");
    }
    // nalgebra's independent conversion, on random unit quaternions.
    let mut rng = rng(1);
    for _ in 0..100 {
        let q = random_unit_quaternion(&mut rng);
        let reference = UnitQuaternion::new_unchecked(q).to_rotation_matrix().into_inner();
        assert!((rotation_matrix(&q) - reference).amax() < 1e-15);
    }
}

#[test]
fn rotation_matrix_of_a_unit_quaternion_is_a_rotation() {
    let mut rng = rng(2);
    for _ in 0..500 {
        let q = random_unit_quaternion(&mut rng);
        let (orth, det) = rotation_defect(&rotation_matrix(&q));
        assert!(
            orth < 1e-14 && det < 1e-14,
            "‖RᵀR − I‖ = {orth:e}, |det R − 1| = {det:e}"
        );
    }
}

#[test]
fn quaternion_product_composes_rotations() {
    let mut rng = rng(3);
    for _ in 0..100 {
        let (p, q) = (random_unit_quaternion(&mut rng), random_unit_quaternion(&mut rng));
        let pq = quaternion_product(&p, &q);
        assert!((pq - p * q).norm() < 1e-15, "differs from nalgebra's Hamilton product");
        let composed = rotation_matrix(&p) * rotation_matrix(&q);
        assert!((rotation_matrix(&pq) - composed).amax() < 1e-14, "R(p ⊗ q) ≠ R(p) R(q)");
    }
}

#[test]
fn quaternion_matrix_round_trips() {
    let mut rng = rng(4);
    // Quaternion → matrix → quaternion gives ±q, with a non-negative scalar part.
    for _ in 0..500 {
        let q = random_unit_quaternion(&mut rng);
        let back = quaternion_from_matrix(&rotation_matrix(&q));
        assert!(back.w >= 0.0);
        assert!((back.norm() - 1.0).abs() < 1e-15);
        assert!(
            quaternion_distance_up_to_sign(&back, &q) < 1e-14,
            "{q:?} came back as {back:?}"
        );
    }
    // Matrix → quaternion → matrix is the identity on rotations, including half turns about each
    // coordinate axis and near them (the three branches of Shepperd's method with tr R ≤ 0).
    let mut rotations: Vec<Matrix3<f64>> = (0..200).map(|_| exp_map(&random_vector(&mut rng, 2.0))).collect();
    for axis in [
        Vector3::x(),
        Vector3::y(),
        Vector3::z(),
        Vector3::new(1.0, 1.0, 0.0).normalize(),
    ] {
        for angle in [PI, PI - 1e-8, -(PI - 1e-3), 2.5, 0.0] {
            rotations.push(rotation_matrix(&axis_angle(&axis, angle)));
        }
    }
    for r in &rotations {
        let q = quaternion_from_matrix(r);
        assert!((rotation_matrix(&q) - r).amax() < 1e-14, "round trip of {r}");
    }
}

#[test]
fn quaternion_from_half_turns_about_the_axes() {
    // R = diag with two −1 entries: q = (0, e_k) up to sign.
    for (k, diag) in [(1, [1.0, -1.0, -1.0]), (2, [-1.0, 1.0, -1.0]), (3, [-1.0, -1.0, 1.0])] {
        let q = quaternion_from_matrix(&Matrix3::from_diagonal(&Vector3::from(diag)));
        let mut expected = [0.0; 4];
        expected[k] = 1.0;
        let expected = Quaternion::new(expected[0], expected[1], expected[2], expected[3]);
        assert!(quaternion_distance_up_to_sign(&q, &expected) < 1e-15, "axis {k}: {q:?}");
    }
}

#[test]
fn skew_and_axl_are_inverse_and_skew_is_the_cross_product() {
    let mut rng = rng(5);
    for _ in 0..100 {
        let (v, y) = (random_vector(&mut rng, 3.0), random_vector(&mut rng, 3.0));
        let k = skew(&v);
        assert!((k + k.transpose()).amax() == 0.0, "skew(v) not antisymmetric");
        assert!((k * y - v.cross(&y)).amax() < 1e-14, "skew(v) y ≠ v × y");
        assert!((axl(&k) - v).amax() < 1e-15, "axl(skew v) ≠ v");
        assert!((axl_upper(&k) - v).amax() < 1e-15, "axl_upper(skew v) ≠ v");
    }
}

#[test]
fn axl_reads_the_skew_part_and_axl_upper_the_upper_triangle() {
    let mut rng = rng(6);
    for _ in 0..50 {
        let v = random_vector(&mut rng, 2.0);
        let m_sym = Matrix3::from_fn(|_, _| rng.random_range(-1.0..1.0));
        let sym = (m_sym + m_sym.transpose()) * 0.5;
        let m = skew(&v) + sym;
        // axl sees only the skew part.
        assert!((axl(&m) - v).amax() < 1e-15);
        assert!(axl(&sym).amax() < 1e-16);
        // axl_upper reads (−m₂₃, −m₃₁, −m₁₂): off by the symmetric part's upper entries.
        let expected_upper = v - Vector3::new(sym[(1, 2)], sym[(2, 0)], sym[(0, 1)]);
        assert!((axl_upper(&m) - expected_upper).amax() < 1e-15);
        assert!(
            (axl_upper(&m) - axl(&m)).norm() > 1e-3,
            "a non-skew matrix must separate the variants"
        );
    }
}

/// Angles that exercise the Taylor branch of `exp_map` (`θ² < 1e-8`), both sides of the switch, and
/// large rotations up to and beyond a full turn.
const EXP_ANGLES: [f64; 13] = [
    1e-12, 1e-9, 1e-6, 0.99e-4, 1.01e-4, 1e-3, 1e-2, 0.5, 1.0, 2.0, PI, 4.0, 10.0,
];

#[test]
fn exp_map_is_the_axis_angle_rotation_and_orthogonal() {
    assert_eq!(exp_map(&Vector3::<f64>::zeros()), Matrix3::identity());
    let mut rng = rng(7);
    for angle in EXP_ANGLES {
        for _ in 0..20 {
            let axis = random_unit_vector(&mut rng);
            let r = exp_map(&(axis * angle));
            let reference = rotation_matrix(&axis_angle(&axis, angle));
            assert!(
                (r - reference).amax() < 1e-14,
                "angle {angle:e}: {:e}",
                (r - reference).amax()
            );
            let (orth, det) = rotation_defect(&r);
            assert!(
                orth < 1e-14 && det < 1e-14,
                "angle {angle:e}: ‖RᵀR − I‖ = {orth:e}, |det − 1| = {det:e}"
            );
            // The axis is fixed and the inverse is the opposite rotation.
            assert!((r * axis - axis).amax() < 1e-14);
            assert!((exp_map(&(-axis * angle)) * r - Matrix3::identity()).amax() < 1e-14);
        }
        let about_z = exp_map(&(Vector3::z() * angle));
        assert!((about_z - rotation_about_z(angle)).amax() < 1e-14, "angle {angle:e}");
    }
}

#[test]
fn exp_map_derivatives_with_dual_numbers() {
    let mut rng = rng(8);
    for _ in 0..20 {
        let d = random_vector(&mut rng, 2.0);
        let k = skew(&d);
        // At 0: d/dt exp(t [d]×) = [d]× and d²/dt² = [d]×².
        let v = d.map(|x| Dual64::new(0.0, x));
        let r = exp_map(&v);
        assert!((r.map(|x| x.re) - Matrix3::identity()).amax() == 0.0);
        assert!((r.map(|x| x.eps) - k).amax() < 1e-15, "first derivative at 0");
        let r2 = exp_map(&d.map(|x| Dual2_64::new(0.0, x, 0.0)));
        assert!((r2.map(|x| x.v1) - k).amax() < 1e-15);
        assert!((r2.map(|x| x.v2) - k * k).amax() < 1e-14, "second derivative at 0");
        // Along the axis at any t: d/dt exp(t [d]×) = [d]× exp(t [d]×), on both sides of the Taylor
        // switch at θ = 1e-4.
        for theta in [1e-7, 0.99e-4, 1.01e-4, 0.3, 2.0] {
            let t = theta / d.norm();
            let r = exp_map(&d.map(|x| Dual64::new(t * x, x)));
            let expected = k * exp_map(&(d * t));
            let err = (r.map(|x| x.eps) - expected).amax();
            assert!(err < 1e-14, "θ = {theta:e}: derivative error {err:e}");
        }
    }
}

/// `exp([v]×)` from its power series `Σ [v]×ⁿ/n!`, in any scalar: the definition, used as an oracle
/// for the derivatives of the closed form. Forty terms reach machine precision for `|v| ≤ 3`.
fn exp_series<T: cosserat_geometry::Real>(v: &Vector3<T>) -> Matrix3<T> {
    let k = v.cross_matrix();
    let mut term = Matrix3::<T>::identity();
    let mut sum = term;
    for n in 1..=40 {
        term = term * k * T::from(1.0 / n as f64);
        sum += term;
    }
    sum
}

#[test]
fn exp_map_directional_derivatives_match_the_power_series() {
    // First and second derivatives of v ↦ exp([v]×) along a random direction h (transverse to v),
    // through the Taylor switch at θ = 1e-4 and up to large angles. The remaining error of the
    // closed form's second derivative is ~ε/θ from sin θ/θ (≈ 6e-12 measured at θ = 1.01e-4); a
    // (1 − cos θ)/θ² coefficient would add ~ε/θ² ≈ 5e-9 there.
    let mut rng = rng(16);
    for theta in [1e-6, 0.99e-4, 1.01e-4, 2e-4, 1e-3, 1e-2, 0.1, 1.0, 3.0] {
        for _ in 0..20 {
            let (d, h) = (random_unit_vector(&mut rng), random_unit_vector(&mut rng));
            let v = (d * theta).map(Dual2_64::from_re) + h.map(|x| Dual2_64::new(0.0, x, 0.0));
            let (r, series) = (exp_map(&v), exp_series(&v));
            let err0 = (r.map(|x| x.re) - series.map(|x| x.re)).amax();
            let err1 = (r.map(|x| x.v1) - series.map(|x| x.v1)).amax();
            let err2 = (r.map(|x| x.v2) - series.map(|x| x.v2)).amax();
            assert!(err0 < 1e-14, "θ = {theta:e}: value error {err0:e}");
            assert!(err1 < 1e-14, "θ = {theta:e}: first derivative error {err1:e}");
            assert!(err2 < 1e-10, "θ = {theta:e}: second derivative error {err2:e}");
        }
    }
}

#[test]
fn cayley_is_a_rotation_by_twice_the_arctangent() {
    let mut rng = rng(9);
    for scale in [1e-9, 1e-3, 0.1, 1.0, 10.0, 1e3] {
        for _ in 0..20 {
            let v = random_vector(&mut rng, scale);
            let r = cayley(&v);
            let (orth, det) = rotation_defect(&r);
            assert!(
                orth < 1e-14 && det < 1e-14,
                "|v| = {:e}: ‖RᵀR − I‖ = {orth:e}",
                v.norm()
            );
            let angle = 2.0 * (0.5 * v.norm()).atan();
            let reference = rotation_matrix(&axis_angle(&v.normalize(), angle));
            assert!(
                (r - reference).amax() < 1e-14,
                "|v| = {:e}: not the rotation by 2 atan(|v|/2)",
                v.norm()
            );
            // The definition (I − [v]×/2)⁻¹ (I + [v]×/2).
            let half = skew(&v) * 0.5;
            let definition = (Matrix3::identity() - half).try_inverse().unwrap() * (Matrix3::identity() + half);
            assert!((r - definition).amax() < 1e-13);
        }
    }
    assert_eq!(cayley(&Vector3::<f64>::zeros()), Matrix3::identity());
}

#[test]
fn quaternion_update_stays_unit_and_in_the_hemisphere_of_its_input() {
    let mut rng = rng(10);
    for scale in [0.0, 1e-6, 1.0, 100.0, 1e6] {
        for _ in 0..50 {
            let q = random_unit_quaternion(&mut rng);
            let omega = random_vector(&mut rng, 1.0) * scale;
            let dt = rng.random_range(1e-4..1.0);
            let next = quaternion_update(&q, &omega, dt);
            assert!((next.norm() - 1.0).abs() < 1e-15, "|Φ| = {}", next.norm());
            assert!(next.dot(&q) > 0.0, "Φ left the hemisphere of q");
        }
    }
    let q = random_unit_quaternion(&mut rng);
    assert!((quaternion_update(&q, &Vector3::zeros(), 0.1) - q).norm() < 1e-16);
}

#[test]
fn quaternion_update_is_the_cayley_map_applied_from_the_left() {
    // model.md Appendix A: R(Φ(q, ω, Δt)) = cay(Δt ω) R(q) to machine precision.
    let mut rng = rng(11);
    let mut worst: f64 = 0.0;
    for scale in [1e-3, 1.0, 30.0] {
        for _ in 0..100 {
            let q = random_unit_quaternion(&mut rng);
            let omega = random_vector(&mut rng, scale);
            let dt = rng.random_range(1e-3..0.5);
            let lhs = rotation_matrix(&quaternion_update(&q, &omega, dt));
            let rhs = cayley(&(omega * dt)) * rotation_matrix(&q);
            worst = worst.max(max_abs(&(lhs - rhs)));
        }
    }
    assert!(worst < 5e-15, "‖R(Φ) − cay(Δt ω) R(q)‖_max = {worst:e}");
}

/// The local error `‖R(Φ(q, ω, Δt)) − exp(Δt [ω]×) R(q)‖_F` of one step.
fn local_error(q: &Quaternion<f64>, omega: &Vector3<f64>, dt: f64) -> f64 {
    let phi = rotation_matrix(&quaternion_update(q, omega, dt));
    (phi - exp_map(&(omega * dt)) * rotation_matrix(q)).norm()
}

/// The global error after `n` steps of `Δt = T/n` with constant `ω`, against `exp(T [ω]×) R(q)`.
fn global_error(q: &Quaternion<f64>, omega: &Vector3<f64>, t_end: f64, n: usize) -> f64 {
    let dt = t_end / n as f64;
    let mut state = *q;
    for _ in 0..n {
        state = quaternion_update(&state, omega, dt);
    }
    (rotation_matrix(&state) - exp_map(&(omega * t_end)) * rotation_matrix(q)).norm()
}

/// The exact distance between the Cayley and the exponential rotations about one axis: the Cayley
/// update turns by `2 arctan(Δt|ω|/2)` per step instead of `Δt|ω|`.
fn exact_deficit_error(speed: f64, dt: f64, n: usize) -> f64 {
    same_axis_distance(n as f64 * (speed * dt - 2.0 * (0.5 * speed * dt).atan()))
}

#[test]
fn quaternion_update_local_error_is_third_order() {
    let mut rng = rng(12);
    let steps: Vec<f64> = (0..=8).map(|k| 10f64.powf(-1.0 - k as f64 / 4.0)).collect();
    for _ in 0..3 {
        let q = random_unit_quaternion(&mut rng);
        let omega = random_unit_vector(&mut rng) * rng.random_range(0.5..3.0);
        let speed = omega.norm();
        let errors: Vec<f64> = steps.iter().map(|&dt| local_error(&q, &omega, dt)).collect();
        for (&dt, &e) in steps.iter().zip(&errors) {
            // Exact value of the distance; round-off is ~1e-16 against errors ≥ 1e-10.
            let exact = exact_deficit_error(speed, dt, 1);
            assert!(
                (e - exact).abs() < 1e-6 * exact + 1e-15,
                "Δt = {dt:e}: {e:e} vs exact {exact:e}"
            );
        }
        let slope = log_log_slope(&steps, &errors);
        assert!((slope - 3.0).abs() < 0.2, "local order {slope}");
        // Leading term √2 |ω|³ Δt³ / 12.
        let leading = SQRT_2 * speed.powi(3) / 12.0;
        let dt = steps[8];
        assert!((errors[8] / dt.powi(3) / leading - 1.0).abs() < 1e-3);
    }
}

#[test]
fn quaternion_update_global_error_is_second_order() {
    let mut rng = rng(13);
    let t_end = 1.0;
    let counts = [10usize, 20, 50, 100, 200, 500, 1000];
    let steps: Vec<f64> = counts.iter().map(|&n| t_end / n as f64).collect();
    for _ in 0..3 {
        let q = random_unit_quaternion(&mut rng);
        let omega = random_unit_vector(&mut rng) * rng.random_range(0.5..3.0);
        let speed = omega.norm();
        let errors: Vec<f64> = counts.iter().map(|&n| global_error(&q, &omega, t_end, n)).collect();
        for (&n, &e) in counts.iter().zip(&errors) {
            // n steps accumulate ~n·1e-16 of round-off against errors ≥ 1e-7.
            let exact = exact_deficit_error(speed, t_end / n as f64, n);
            assert!((e - exact).abs() < 1e-6 * exact, "n = {n}: {e:e} vs exact {exact:e}");
        }
        let slope = log_log_slope(&steps, &errors);
        assert!((slope - 2.0).abs() < 0.2, "global order {slope}");
        // Leading term √2 T |ω|³ Δt² / 12.
        let leading = SQRT_2 * t_end * speed.powi(3) / 12.0;
        assert!((errors[6] / steps[6].powi(2) / leading - 1.0).abs() < 1e-3);
    }
}

#[test]
fn rotation_jet_value_and_derivatives_match_finite_differences() {
    let mut rng = rng(14);
    let r_of = |q: &Quaternion<f64>, w: &Vector3<f64>, dt: f64| rotation_matrix(&quaternion_update(q, w, dt));
    for _ in 0..10 {
        let q = random_unit_quaternion(&mut rng);
        let omega = random_vector(&mut rng, 3.0);
        let dt = rng.random_range(0.01..0.5);
        let jet = RotationJet::of_update(&q, &omega, dt);
        assert!((jet.r - r_of(&q, &omega, dt)).amax() < 1e-15, "value");
        // Central differences: the map is smooth with derivatives of order Δt^k, so with h = 1e-5 the
        // first-derivative truncation is ~h² ≈ 1e-10 and round-off ~1e-16/h ≈ 1e-11; with h = 1e-4 the
        // second-derivative truncation is ~h² ≈ 1e-8 and round-off ~1e-16/h² ≈ 1e-8.
        let h1 = 1e-5;
        let h2 = 1e-4;
        let e = |i: usize| Vector3::ith(i, 1.0);
        for i in 0..3 {
            let fd = (r_of(&q, &(omega + e(i) * h1), dt) - r_of(&q, &(omega - e(i) * h1), dt)) / (2.0 * h1);
            let err = (jet.d1[i] - fd).amax();
            assert!(err < 1e-9, "d1[{i}]: {err:e}");
            for j in 0..3 {
                let f = |si: f64, sj: f64| r_of(&q, &(omega + e(i) * (si * h2) + e(j) * (sj * h2)), dt);
                let fd2 = (f(1.0, 1.0) - f(1.0, -1.0) - f(-1.0, 1.0) + f(-1.0, -1.0)) / (4.0 * h2 * h2);
                let err = (jet.second_derivative(i, j) - fd2).amax();
                assert!(err < 1e-6, "d2[{i}][{j}]: {err:e}");
                assert!(
                    (jet.second_derivative(i, j) - jet.second_derivative(j, i)).amax() < 1e-15,
                    "d2 not symmetric"
                );
            }
        }
    }
}

#[test]
fn rotation_jet_at_rest_is_the_cayley_expansion() {
    // At q = 1, ω = 0: R = cay(Δt ω) = I + Δt [ω]× + Δt² [ω]×²/2 + O(Δt³), so ∂R/∂ω_i = Δt E_i and
    // ∂²R/∂ω_i∂ω_j = Δt² (E_i E_j + E_j E_i)/2 with E_i = [e_i]×.
    let dt = 0.3;
    let jet = RotationJet::of_update(&Quaternion::identity(), &Vector3::zeros(), dt);
    assert_eq!(jet.r, Matrix3::identity());
    let big_e = |i: usize| Vector3::<f64>::ith(i, 1.0).cross_matrix();
    for i in 0..3 {
        assert!((jet.d1[i] - big_e(i) * dt).amax() < 1e-15);
        for j in 0..3 {
            let expected = (big_e(i) * big_e(j) + big_e(j) * big_e(i)) * (0.5 * dt * dt);
            assert!(
                (jet.second_derivative(i, j) - expected).amax() < 1e-15,
                "d2[{i}][{j}] = {}",
                jet.second_derivative(i, j)
            );
        }
    }
}

#[test]
fn constant_rotation_jet_has_no_derivatives() {
    let r = rotation_about_z(0.7);
    let jet = RotationJet::constant(r);
    assert_eq!(jet.r, r);
    assert!(jet.d1.iter().all(|m| *m == Matrix3::zeros()));
    assert!(jet.dense().d2.iter().flatten().all(|m| *m == Matrix3::zeros()));
}

#[test]
fn same_hemisphere_flips_exactly_when_the_dot_product_is_negative() {
    let mut rng = rng(15);
    for _ in 0..500 {
        let (q, reference) = (random_unit_quaternion(&mut rng), random_unit_quaternion(&mut rng));
        let guarded = same_hemisphere(&q, &reference);
        if q.dot(&reference) < 0.0 {
            assert_eq!(guarded, -q);
        } else {
            assert_eq!(guarded, q);
        }
        assert!(guarded.dot(&reference) >= 0.0);
        // Either way it is the same rotation.
        assert!((rotation_matrix(&guarded) - rotation_matrix(&q)).amax() < 1e-15);
    }
    // Boundary: orthogonal quaternions (dot exactly 0) are kept, the smallest negative dot flips.
    let (one, i) = (Quaternion::new(1.0, 0.0, 0.0, 0.0), Quaternion::new(0.0, 1.0, 0.0, 0.0));
    assert_eq!(same_hemisphere(&i, &one), i);
    let tiny = Quaternion::new(-f64::MIN_POSITIVE, 1.0, 0.0, 0.0);
    assert_eq!(same_hemisphere(&tiny, &one), -tiny);
    assert_eq!(same_hemisphere(&-one, &one), one);
}
