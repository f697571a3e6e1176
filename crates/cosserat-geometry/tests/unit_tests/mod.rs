//! Unit tests mirroring `src/`, and the seeded random inputs they share.

mod rotation;
mod surface;

use nalgebra::{Matrix3, Quaternion, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::TAU;

/// A seeded generator, so every run sees the same inputs.
pub fn rng(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

/// A uniformly distributed unit quaternion (Shoemake's method), scalar first.
pub fn random_unit_quaternion(rng: &mut impl Rng) -> Quaternion<f64> {
    let (u1, u2, u3): (f64, f64, f64) = (rng.random(), rng.random(), rng.random());
    let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
    Quaternion::new(
        a * (TAU * u2).sin(),
        a * (TAU * u2).cos(),
        b * (TAU * u3).sin(),
        b * (TAU * u3).cos(),
    )
}

/// A vector with independent components uniform in `[-scale, scale]`.
pub fn random_vector(rng: &mut impl Rng, scale: f64) -> Vector3<f64> {
    Vector3::from_fn(|_, _| rng.random_range(-scale..scale))
}

/// A uniformly distributed unit vector.
pub fn random_unit_vector(rng: &mut impl Rng) -> Vector3<f64> {
    loop {
        let v = random_vector(rng, 1.0);
        let n = v.norm();
        if n > 0.1 && n <= 1.0 {
            return v / n;
        }
    }
}

/// The largest absolute entry of `m`.
pub fn max_abs(m: &Matrix3<f64>) -> f64 {
    m.amax()
}

/// `‖RᵀR − I‖_max` and `|det R − 1|`: how far `r` is from a rotation matrix.
pub fn rotation_defect(r: &Matrix3<f64>) -> (f64, f64) {
    (
        (r.transpose() * r - Matrix3::identity()).amax(),
        (r.determinant() - 1.0).abs(),
    )
}

/// The least-squares slope of `log y` against `log x`.
pub fn log_log_slope(x: &[f64], y: &[f64]) -> f64 {
    assert_eq!(x.len(), y.len());
    let lx: Vec<f64> = x.iter().map(|v| v.ln()).collect();
    let ly: Vec<f64> = y.iter().map(|v| v.ln()).collect();
    let n = lx.len() as f64;
    let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
    let sxy: f64 = lx.iter().zip(&ly).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = lx.iter().map(|a| (a - mx) * (a - mx)).sum();
    sxy / sxx
}
