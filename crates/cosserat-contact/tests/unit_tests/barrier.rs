//! The scalar functions: barrier, mollifier and friction smoothing, their derivatives against finite
//! differences and their limits.

use super::common::{check_jet, random_vec, rng};
use cosserat_contact::ContactError;
use cosserat_contact::barrier::Barrier;
use cosserat_contact::friction::FrictionSmoothing;
use cosserat_contact::mollifier::{Mollifier, cross_squared, cross_squared_jet};
use nalgebra::{Matrix2, Vector2, Vector3};
use num_dual::Dual2_64;

fn fd(f: impl Fn(f64) -> f64, x: f64, h: f64) -> f64 {
    (f(x + h) - f(x - h)) / (2.0 * h)
}

#[test]
fn barrier_derivatives_match_finite_differences_and_duals() {
    let b = Barrier::try_new(250.0, 1e-3).unwrap();
    for g in [1e-6, 1e-5, 1e-4, 3e-4, 7e-4, 9.9e-4] {
        let (v, d1, d2) = b.derivatives(g);
        // Central differences with a step 1e-4 of the distance to the nearer end of (0, d̂), where the
        // derivatives vary fastest: truncation ~1e-8 relative.
        let h = 1e-4 * g.min(1e-3 - g);
        assert!(
            (fd(|x| b.derivatives(x).0, g, h) - d1).abs() <= 1e-6 * d1.abs(),
            "b' at {g}"
        );
        assert!(
            (fd(|x| b.derivatives(x).1, g, h) - d2).abs() <= 1e-6 * d2.abs(),
            "b'' at {g}"
        );
        // The generic value with a second-order dual gives the same three numbers.
        let dual = b.value(Dual2_64::from_re(g).derivative());
        assert!((dual.re - v).abs() <= 1e-14 * v.abs());
        assert!((dual.v1 - d1).abs() <= 1e-12 * d1.abs());
        assert!((dual.v2 - d2).abs() <= 1e-12 * d2.abs());
        // A compressed gap repels: b > 0, b' < 0, b'' > 0.
        assert!(v > 0.0 && d1 < 0.0 && d2 > 0.0);
    }
}

#[test]
fn barrier_limits() {
    let b = Barrier::try_new(2.0, 1e-3).unwrap();
    // C² at the barrier width: value, slope and curvature tend to zero from below and are zero beyond.
    let (v, d1, d2) = b.derivatives(1e-3 * (1.0 - 1e-9));
    assert!(v.abs() < 1e-20 && d1.abs() < 1e-14 && d2.abs() < 1e-7);
    assert_eq!(b.derivatives(1e-3), (0.0, 0.0, 0.0));
    assert_eq!(b.derivatives(1.0), (0.0, 0.0, 0.0));
    // Unbounded as the gap closes, infinite at and below zero.
    assert!(b.derivatives(1e-12).0 > b.derivatives(1e-9).0);
    assert!(b.derivatives(1e-300).0 > 1e-3);
    assert_eq!(b.derivatives(0.0).0, f64::INFINITY);
    assert_eq!(b.value(-1e-9), f64::INFINITY);
    // Closed form at g = d̂/e: b = −κ d̂² (1/e − 1)² ln(1/e) = κ d̂² (1 − 1/e)².
    let g = 1e-3 / std::f64::consts::E;
    let expected = 2.0 * 1e-6 * (1.0 - 1.0 / std::f64::consts::E).powi(2);
    assert!((b.derivatives(g).0 - expected).abs() < 1e-15 * expected.max(1.0));
}

#[test]
fn barrier_of_squared_distance_chains_the_square_root() {
    let b = Barrier::try_new(10.0, 2e-3).unwrap();
    let delta = 5e-3;
    for d in [5.0001e-3, 5.5e-3, 6.9e-3] {
        let s = d * d;
        let (e, de, d2e) = b.of_squared_distance(s, delta);
        assert!((e - b.derivatives(d - delta).0).abs() <= 1e-15 * e.abs());
        let h = 1e-5 * (d - delta) * d;
        assert!((fd(|s| b.of_squared_distance(s, delta).0, s, h) - de).abs() <= 1e-6 * de.abs());
        assert!((fd(|s| b.of_squared_distance(s, delta).1, s, h) - d2e).abs() <= 1e-6 * d2e.abs());
    }
    assert_eq!(b.of_squared_distance(1.0, delta), (0.0, 0.0, 0.0));
}

#[test]
fn invalid_barrier_parameters_are_rejected() {
    for (k, d) in [
        (0.0, 1e-3),
        (-1.0, 1e-3),
        (1.0, 0.0),
        (f64::NAN, 1e-3),
        (1.0, f64::INFINITY),
    ] {
        assert!(
            matches!(Barrier::try_new(k, d), Err(ContactError::InvalidParameter { .. })),
            "{k}, {d}"
        );
    }
}

#[test]
fn mollifier_derivatives_and_c1_threshold() {
    let m = Mollifier::from_rest_lengths(0.5, 2.0);
    assert!((m.threshold - 1e-3).abs() < 1e-18);
    for c in [1e-6, 2e-4, 5e-4, 9e-4] {
        let (v, d1, d2) = m.derivatives(c);
        assert!((fd(|x| m.derivatives(x).0, c, 1e-7) - d1).abs() < 1e-8 * d1.abs().max(1.0));
        assert!((fd(|x| m.derivatives(x).1, c, 1e-7) - d2).abs() < 1e-6 * d2.abs());
        assert!(v > 0.0 && v < 1.0);
    }
    // m(0) = 0, m(ε×) = 1 with zero slope from below: C¹.
    assert_eq!(m.derivatives(0.0).0, 0.0);
    let below = m.derivatives(m.threshold * (1.0 - 1e-12));
    assert!((below.0 - 1.0).abs() < 1e-12 && below.1.abs() < 1e-6);
    assert_eq!(m.derivatives(m.threshold), (1.0, 0.0, 0.0));
}

#[test]
fn cross_squared_jet_matches_finite_differences() {
    let mut rng = rng(11);
    for _ in 0..20 {
        let x: [Vector3<f64>; 4] = std::array::from_fn(|_| random_vec(&mut rng, 1.0));
        check_jet("cross", &x, cross_squared, cross_squared_jet, 1e-6, 1e-6);
    }
}

#[test]
fn friction_smoothing_is_c1_with_stick_and_coulomb_limits() {
    let f = FrictionSmoothing::new(0.01, 0.1);
    let e = f.epsilon;
    assert!((e - 1e-3).abs() < 1e-18);
    // f₀' = f₁ and f₁' by finite differences, on both sides of ε.
    for y in [1e-5, 3e-4, 9e-4, 1.1e-3, 5e-3] {
        assert!((fd(|x| f.f0(x), y, 1e-8) - f.f1(y)).abs() < 1e-7, "f0' at {y}");
        assert!(
            (fd(|x| f.f1(x), y, 1e-8) - f.f1_derivative(y)).abs() < 1e-4,
            "f1' at {y}"
        );
        assert!((f.f1_over_y(y) - f.f1(y) / y).abs() < 1e-9 * f.f1_over_y(y));
    }
    // Continuity of f₀, f₁ and f₁' at ε.
    let below = e * (1.0 - 1e-12);
    assert!((f.f0(below) - f.f0(e)).abs() < 1e-14);
    assert!((f.f1(below) - 1.0).abs() < 1e-11);
    assert!(f.f1_derivative(below).abs() < 1e-6);
    // Stick: f₁ grows linearly from zero with slope 2/ε (a spring); f₁/y is finite at zero.
    assert_eq!(f.f1(0.0), 0.0);
    assert!((f.f1(1e-9) / 1e-9 - 2.0 / e).abs() < 1e-3 / e);
    assert_eq!(f.f1_over_y(0.0), 2.0 / e);
    // Coulomb: above ε the force magnitude is exactly 1 (μλ after scaling) and f₀ is the slip.
    for y in [e, 2.0 * e, 1.0] {
        assert_eq!(f.f1(y), 1.0);
        assert_eq!(f.f0(y), y);
    }
}

#[test]
fn friction_potential_derivatives_and_positive_hessian() {
    let f = FrictionSmoothing::new(0.1, 0.01);
    let e = f.epsilon;
    for z in [
        Vector2::new(0.0, 0.0),
        Vector2::new(1e-4, -2e-4),
        Vector2::new(5e-4, 6e-4),
        Vector2::new(-2e-3, 1e-3),
        Vector2::new(0.3, 0.1),
    ] {
        let (v, g, h) = f.potential(&z);
        let h_step = 1e-7 * e;
        let fd_g = Vector2::from_fn(|i, _| {
            let mut d = Vector2::zeros();
            d[i] = h_step;
            (f.potential(&(z + d)).0 - f.potential(&(z - d)).0) / (2.0 * h_step)
        });
        assert!((fd_g - g).amax() < 1e-6, "gradient at {z:?}");
        if z.norm() > 10.0 * h_step {
            let fd_h = Matrix2::from_fn(|i, j| {
                let mut d = Vector2::zeros();
                d[j] = h_step;
                (f.potential(&(z + d)).1[i] - f.potential(&(z - d)).1[i]) / (2.0 * h_step)
            });
            assert!((fd_h - h).amax() < 1e-5 * h.amax(), "Hessian at {z:?}");
        } else {
            assert_eq!(h, Matrix2::identity() * (2.0 / e));
        }
        assert!(v >= e / 3.0 - 1e-18);
        let eig = h.symmetric_eigen().eigenvalues;
        assert!(eig.iter().all(|&l| l >= -1e-12 * h.amax()), "PSD at {z:?}: {eig:?}");
    }
}
