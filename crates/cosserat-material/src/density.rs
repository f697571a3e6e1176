//! The energy densities of the Cosserat plate and curved shell (supplement eqs. 1–7), written once and
//! generic over the scalar type.
//!
//! Everything here is a function of the strain tensors `E` (membrane strain) and `Γ` (curvature tensor
//! after subtracting the rest curvature), together with rest data (`b`, `H`, `K`, `c`) that are plain
//! `f64`. The quadratic forms are
//!
//! - `W_mixt(A, B) = μ sym A : sym B + μ_c skew A : skew B + λμ/(λ+2μ) tr A tr B` (eq. 4),
//! - `W_m(A) = W_mixt(A, A)` (eq. 5),
//! - `W_mp(A) = μ |sym A|² + μ_c |skew A|² + λ/2 (tr A)²` (eq. 6),
//! - `W_curv(A) = μ L_c² (b₁ |sym A|² + b₂ |skew A|² + b₃ (tr A)²)` (eq. 7).
//!
//! Every strain-quadratic term is a homogeneous quadratic form of `(E, Γ)`, so the density's Hessian with
//! respect to the strains is a constant matrix for given rest data: `strain_space::strain_hessian` writes
//! it in closed form, the oracle differentiates [`density`] with num-dual, and the fast kernels chain it
//! with the strain maps.

use crate::model::{EnergyTerm, TermSet};
use crate::parameters::Moduli;
use cosserat_geometry::Real;
use nalgebra::Matrix3;

/// The rest data of a point that the curved terms need, expressed in the same frame as `E` and `Γ`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointGeometry {
    /// Second fundamental tensor `b` (tangential, symmetric).
    pub b: Matrix3<f64>,
    /// Mean curvature `H = ½ tr b`.
    pub mean: f64,
    /// Gaussian curvature `K`.
    pub gaussian: f64,
    /// Alternating tensor `c = −[n₀]×`.
    pub c: Matrix3<f64>,
}

impl PointGeometry {
    /// A flat point with normal `n₀`.
    pub fn flat(normal: &nalgebra::Vector3<f64>) -> Self {
        Self {
            b: Matrix3::zeros(),
            mean: 0.0,
            gaussian: 0.0,
            c: -cosserat_geometry::rotation::skew(normal),
        }
    }
}

#[inline]
fn sym<T: Real>(a: &Matrix3<T>) -> Matrix3<T> {
    (a + a.transpose()) * T::from(0.5)
}

#[inline]
fn skw<T: Real>(a: &Matrix3<T>) -> Matrix3<T> {
    (a - a.transpose()) * T::from(0.5)
}

#[inline]
fn frob<T: Real>(a: &Matrix3<T>, b: &Matrix3<T>) -> T {
    a.component_mul(b).sum()
}

/// `W_mixt(A, B)` (supplement eq. 4).
pub fn w_mixt<T: Real>(a: &Matrix3<T>, b: &Matrix3<T>, m: &Moduli) -> T {
    frob(&sym(a), &sym(b)) * m.mu + frob(&skw(a), &skw(b)) * m.mu_c + a.trace() * b.trace() * m.plane_lambda
}

/// `W_m(A)` (supplement eq. 5).
pub fn w_m<T: Real>(a: &Matrix3<T>, m: &Moduli) -> T {
    w_mixt(a, a, m)
}

/// `W_mp(A)` (supplement eq. 6).
pub fn w_mp<T: Real>(a: &Matrix3<T>, m: &Moduli) -> T {
    let (s, k, t) = (sym(a), skw(a), a.trace());
    frob(&s, &s) * m.mu + frob(&k, &k) * m.mu_c + t * t * (0.5 * m.lambda)
}

/// `W_curv(A)` (supplement eq. 7).
pub fn w_curv<T: Real>(a: &Matrix3<T>, m: &Moduli) -> T {
    let (s, k, t) = (sym(a), skw(a), a.trace());
    let [b1, b2, b3] = m.curvature_coefficients;
    let l2 = m.mu * m.length_scale * m.length_scale;
    (frob(&s, &s) * b1 + frob(&k, &k) * b2 + t * t * b3) * l2
}

/// The membrane energy without its trace term, `μ |sym E|² + μ_c |skew E|²`.
fn w_m_no_trace<T: Real>(a: &Matrix3<T>, m: &Moduli) -> T {
    let (s, k) = (sym(a), skw(a));
    frob(&s, &s) * m.mu + frob(&k, &k) * m.mu_c
}

/// The density of one strain-quadratic term (without its factor). Returns zero for
/// [`EnergyTerm::NonlinearVolume`], which is not a function of the strains (see `volume`).
pub fn term_density<T: Real>(
    term: EnergyTerm,
    e: &Matrix3<T>,
    gamma: &Matrix3<T>,
    geom: &PointGeometry,
    m: &Moduli,
) -> T {
    let h = m.thickness;
    let (h3, h5) = (h * h * h, h * h * h * h * h);
    let k = geom.gaussian;
    let c = geom.c.cast::<T>();
    let b = geom.b.cast::<T>();
    match term {
        EnergyTerm::Membrane => w_m(e, m) * h,
        EnergyTerm::MembraneNoTrace => w_m_no_trace(e, m) * h,
        EnergyTerm::NonlinearVolume => T::zero(),
        EnergyTerm::Bending => w_m(&(c * gamma), m) * (h3 / 12.0),
        EnergyTerm::Curvature => w_curv(gamma, m) * h,
        EnergyTerm::CurvedMembrane1 => w_m(e, m) * (h - k * h3 / 12.0),
        EnergyTerm::CurvedMembrane2 => w_m(&(e * b + c * gamma), m) * (h3 / 12.0 - k * h5 / 80.0),
        EnergyTerm::CurvedMembrane3 => {
            let cg = c * gamma;
            w_mixt(e, &(cg * b - cg * T::from(2.0 * geom.mean)), m) * (h3 / 6.0)
        }
        EnergyTerm::CurvedMembrane4 => w_mp(&(e * b * b + c * gamma * b), m) * (h5 / 80.0),
        EnergyTerm::CurvedBending1 => w_curv(gamma, m) * (h - k * h3 / 12.0),
        EnergyTerm::CurvedBending2 => w_curv(&(gamma * b), m) * (h3 / 12.0 - k * h5 / 80.0),
        EnergyTerm::CurvedBending3 => w_curv(&(gamma * b * b), m) * (h5 / 80.0),
    }
}

/// The strain-quadratic part of the energy density: the weighted sum of the active terms' densities
/// (energy per unit rest area, J/m²).
pub fn density<T: Real>(terms: &TermSet, e: &Matrix3<T>, gamma: &Matrix3<T>, geom: &PointGeometry, m: &Moduli) -> T {
    terms
        .terms()
        .iter()
        .filter(|t| t.term.is_strain_quadratic())
        .fold(T::zero(), |acc, t| {
            acc + term_density(t.term, e, gamma, geom, m) * t.factor
        })
}
