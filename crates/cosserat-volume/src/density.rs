//! The isotropic micropolar energy density, written once and generic over the scalar, and its constant
//! Hessian on the 18 strain numbers.
//!
//! With the non-symmetric stretch `E = Rᵀ F − I` and the wryness tensor `Γ` (minus its prescribed rest
//! value), the energy per unit rest volume is
//!
//! `W(E, Γ) = μ |sym E|² + μ_c |skew E|² + λ/2 (tr E)² + μ L_c² (b₁ |sym Γ|² + b₂ |skew Γ|² + b₃ (tr Γ)²)`,
//!
//! which is `W_mp(E) + W_curv(Γ)` of the shell's supplement (eqs. 6–7), so the shell's defaults and
//! length scales carry over. It is a homogeneous quadratic form of the strains, `W = ½ sᵀ D s`, with a
//! constant `D` that [`strain_hessian`] takes once from [`density`] with num-dual; the fast kernel
//! (`kernel`) chains it with the strain maps.
//!
//! Strain vector layout: `E` column-major in entries 0–8, `Γ` column-major in 9–17, all in world axes
//! (the rest configuration is the reference, so no rest frame is needed).

use crate::material::MicropolarModuli;
use cosserat_geometry::Real;
use nalgebra::{Matrix3, SMatrix, SVector};
use num_dual::Dual2SVec64;

/// The 18 strain numbers `(vec E, vec Γ)`, column-major.
pub type StrainVector = SVector<f64, 18>;
/// The constant Hessian of the density with respect to a [`StrainVector`] \[Pa\].
pub type StrainMatrix = SMatrix<f64, 18, 18>;

#[inline]
fn frob<T: Real>(a: &Matrix3<T>, b: &Matrix3<T>) -> T {
    a.component_mul(b).sum()
}

/// `μ |sym E|² + μ_c |skew E|² + λ/2 (tr E)²` \[J/m³\] (the shell's `W_mp`, supplement eq. 6).
pub fn stretch_density<T: Real>(e: &Matrix3<T>, m: &MicropolarModuli) -> T {
    let s = (e + e.transpose()) * T::from(0.5);
    let k = (e - e.transpose()) * T::from(0.5);
    let t = e.trace();
    frob(&s, &s) * m.mu + frob(&k, &k) * m.mu_c + t * t * (0.5 * m.lambda)
}

/// `μ L_c² (b₁ |sym Γ|² + b₂ |skew Γ|² + b₃ (tr Γ)²)` \[J/m³\] (the shell's `W_curv`, supplement eq. 7).
pub fn curvature_density<T: Real>(gamma: &Matrix3<T>, m: &MicropolarModuli) -> T {
    let s = (gamma + gamma.transpose()) * T::from(0.5);
    let k = (gamma - gamma.transpose()) * T::from(0.5);
    let t = gamma.trace();
    let [b1, b2, b3] = m.curvature_coefficients;
    let l2 = m.mu * m.length_scale * m.length_scale;
    (frob(&s, &s) * b1 + frob(&k, &k) * b2 + t * t * b3) * l2
}

/// The energy density `W(E, Γ)` \[J/m³\].
pub fn density<T: Real>(e: &Matrix3<T>, gamma: &Matrix3<T>, m: &MicropolarModuli) -> T {
    stretch_density(e, m) + curvature_density(gamma, m)
}

/// Splits a strain vector into `(E, Γ)`.
pub fn unpack<T: nalgebra::Scalar + Copy>(s: &SVector<T, 18>) -> (Matrix3<T>, Matrix3<T>) {
    (
        Matrix3::from_fn(|r, c| s[3 * c + r]),
        Matrix3::from_fn(|r, c| s[9 + 3 * c + r]),
    )
}

/// Packs `(E, Γ)` into a strain vector.
pub fn pack(e: &Matrix3<f64>, gamma: &Matrix3<f64>) -> StrainVector {
    StrainVector::from_fn(|i, _| {
        if i < 9 {
            e[(i % 3, i / 3)]
        } else {
            gamma[((i - 9) % 3, (i - 9) / 3)]
        }
    })
}

/// The Hessian `D` of [`density`] with respect to the strain vector, from num-dual. The density is a
/// homogeneous quadratic form, so `W(s) = ½ sᵀ D s` exactly.
pub fn strain_hessian(m: &MicropolarModuli) -> StrainMatrix {
    let zero = StrainVector::zeros();
    let (_, _, h) = num_dual::hessian(
        |s: SVector<Dual2SVec64<18>, 18>| {
            let (e, g) = unpack(&s);
            density(&e, &g, m)
        },
        &zero,
    );
    (h + h.transpose()) * 0.5
}
