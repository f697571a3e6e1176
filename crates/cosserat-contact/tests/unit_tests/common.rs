//! Helpers shared by the tests: seeded random geometry and central finite differences.

use cosserat_contact::PairJet;
use nalgebra::{SMatrix, SVector, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

pub fn rng(seed: u64) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(seed)
}

pub fn random_vec(rng: &mut ChaCha8Rng, s: f64) -> Vector3<f64> {
    if s == 0.0 {
        return Vector3::zeros();
    }
    Vector3::from_fn(|_, _| rng.random_range(-s..s))
}

pub fn flatten(x: &[Vector3<f64>; 4]) -> SVector<f64, 12> {
    SVector::from_fn(|i, _| x[i / 3][i % 3])
}

pub fn unflatten(y: &SVector<f64, 12>) -> [Vector3<f64>; 4] {
    std::array::from_fn(|k| Vector3::new(y[3 * k], y[3 * k + 1], y[3 * k + 2]))
}

/// Central-difference gradient of `f` at `x` with step `h`.
pub fn fd_gradient(f: impl Fn(&[Vector3<f64>; 4]) -> f64, x: &[Vector3<f64>; 4], h: f64) -> SVector<f64, 12> {
    let y = flatten(x);
    SVector::from_fn(|i, _| {
        let (mut p, mut m) = (y, y);
        p[i] += h;
        m[i] -= h;
        (f(&unflatten(&p)) - f(&unflatten(&m))) / (2.0 * h)
    })
}

/// Central-difference Hessian of `f` from its gradient `g`.
pub fn fd_hessian(
    g: impl Fn(&[Vector3<f64>; 4]) -> SVector<f64, 12>,
    x: &[Vector3<f64>; 4],
    h: f64,
) -> SMatrix<f64, 12, 12> {
    let y = flatten(x);
    let mut out = SMatrix::<f64, 12, 12>::zeros();
    for j in 0..12 {
        let (mut p, mut m) = (y, y);
        p[j] += h;
        m[j] -= h;
        out.set_column(j, &((g(&unflatten(&p)) - g(&unflatten(&m))) / (2.0 * h)));
    }
    out
}

/// Checks a jet against central differences of its own value function, with relative tolerance
/// `tol` on the gradient and the Hessian (measured against the largest entry of each).
pub fn check_jet(
    name: &str,
    x: &[Vector3<f64>; 4],
    value: impl Fn(&[Vector3<f64>; 4]) -> f64,
    jet: impl Fn(&[Vector3<f64>; 4]) -> PairJet,
    h: f64,
    tol: f64,
) {
    let j = jet(x);
    assert!(
        (j.value - value(x)).abs() <= 1e-12 * j.value.abs().max(1e-300),
        "{name}: value"
    );
    let g = fd_gradient(&value, x, h);
    let scale = j.gradient.amax().max(1e-300);
    let err = (g - j.gradient).amax() / scale;
    assert!(err < tol, "{name}: gradient error {err:e} (scale {scale:e})");
    let hs = fd_hessian(|x| jet(x).gradient, x, h);
    let scale = j.hessian.amax().max(1e-300);
    let err = (hs - j.hessian).amax() / scale;
    assert!(err < tol, "{name}: Hessian error {err:e} (scale {scale:e})");
    let asym = (j.hessian - j.hessian.transpose()).amax() / scale;
    assert!(asym < 1e-12, "{name}: Hessian asymmetry {asym:e}");
}
