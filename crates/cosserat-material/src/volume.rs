//! The optional nonlinear membrane volume term (model.md §3.4).
//!
//! `h ½ λμ/(λ+2μ) ((J − 1)² + (1/J − 1)²)` with the area ratio `J = |F̂₁ × F̂₂|` (the current area element
//! over the rest one, because `F̂` is taken on orthonormal rest tangents). It replaces the trace term of
//! the membrane energy; for small strains both agree, and this one grows without bound as an element's
//! area goes to zero. It depends on `F̂` only, so its derivatives are taken with a 6-direction dual.

use crate::parameters::Moduli;
use cosserat_geometry::Real;
use nalgebra::{SMatrix, SVector, Vector3};
use num_dual::Dual2SVec64;

/// The volume term's density (per unit rest area).
pub fn volume_density<T: Real>(f_hat: &[Vector3<T>; 2], m: &Moduli) -> T {
    let j = f_hat[0].cross(&f_hat[1]).norm();
    let a = j - T::one();
    let b = j.recip() - T::one();
    (a * a + b * b) * (0.5 * m.thickness * m.plane_lambda)
}

/// Value, gradient and Hessian of the volume density with respect to `(F̂₁, F̂₂)`.
pub fn volume_hessian(f_hat: &[Vector3<f64>; 2], m: &Moduli) -> (f64, SVector<f64, 6>, SMatrix<f64, 6, 6>) {
    let x = SVector::<f64, 6>::from_fn(|i, _| f_hat[i / 3][i % 3]);
    num_dual::hessian(
        |v: SVector<Dual2SVec64<6>, 6>| {
            let f = [Vector3::new(v[0], v[1], v[2]), Vector3::new(v[3], v[4], v[5])];
            volume_density(&f, m)
        },
        &x,
    )
}
