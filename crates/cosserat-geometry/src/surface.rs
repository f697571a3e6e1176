//! Surface geometry at a point from the tangent `G = [a₁ a₂]` (3×2) and the gradient of a normal field.
//!
//! Notation of the supplement (section 2) and model.md §2.1:
//! - `I = Gᵀ G` is the first fundamental form, `G⁺ = I⁻¹ Gᵀ` the pseudo-inverse (rows `a¹, a²`),
//!   `a = G G⁺ = I − n₀ ⊗ n₀` the tangent projector (first fundamental tensor).
//! - `n₀ = a₁ × a₂ / |a₁ × a₂|` is the geometric normal; its orientation follows the parametrisation.
//! - `∇_ξ n` (3×2) is the derivative of a normal field with respect to the reference coordinates.
//! - `II = −Gᵀ ∇_ξ n` (eq. 9), `S = I⁻¹ II = −G⁺ ∇_ξ n` (eq. 8), `b = −∇_ξ n G⁺` (eq. 10),
//!   `H = ½ tr b`, `K = ½ ((tr b)² − tr b²)` (eq. 12), `c = (a₁ ⊗ a₂ − a₂ ⊗ a₁)/√det I` (eq. 13).
//!
//! **Sign convention.** `b` is the *negative* surface gradient of the normal, so with the outward normal
//! of a sphere of radius `R` one gets `b = −a/R`, `H = −1/R` and `K = 1/R²`; for a cylinder
//! `H = −1/(2R)`, `K = 0`. Flipping the normal flips `b`, `H` and `c` together and leaves `K` and every
//! energy term unchanged.
//!
//! With the exact normal of a smooth surface, `b` is symmetric and tangential (`b n₀ = 0`,
//! `n₀ᵀ b = 0`). A discrete normal field (interpolated nodal normals) gives a slightly non-symmetric `b`
//! with a small normal part; [`tangential_symmetric_part`] removes both, which is what the energy uses.

use crate::error::GeometryError;
use crate::real::Real;
use nalgebra::{Matrix2, Matrix2x3, Matrix3, Matrix3x2, Vector3};

/// Relative tolerance below which two tangent vectors count as parallel: `|a₁ × a₂| ≤ tol |a₁| |a₂|`.
pub const DEGENERACY_TOLERANCE: f64 = 1e-12;

/// The metric quantities of a surface point that depend on the tangent only.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceMetric<T> {
    /// The covariant basis `G = [a₁ a₂]`.
    pub tangent: Matrix3x2<T>,
    /// `G⁺ = (GᵀG)⁻¹ Gᵀ`; its rows are the contravariant vectors `a¹, a²`.
    pub pinv: Matrix2x3<T>,
    /// The area element `√det(GᵀG) = |a₁ × a₂|`.
    pub area_element: T,
    /// The unit normal `n₀ = a₁ × a₂ / |a₁ × a₂|`.
    pub normal: Vector3<T>,
}

impl<T: Real> SurfaceMetric<T> {
    /// Builds the metric of a tangent.
    ///
    /// # Errors
    /// [`GeometryError::DegenerateTangent`] when the tangent vectors are zero, parallel or not finite.
    pub fn try_new(tangent: &Matrix3x2<T>) -> Result<Self, GeometryError> {
        let a1: Vector3<T> = tangent.column(0).into();
        let a2: Vector3<T> = tangent.column(1).into();
        let cross = a1.cross(&a2);
        let area_element = cross.norm();
        let (l1, l2, area) = (a1.norm().re(), a2.norm().re(), area_element.re());
        if !(area.is_finite() && l1.is_finite() && l2.is_finite()) || area <= DEGENERACY_TOLERANCE * l1 * l2 {
            return Err(GeometryError::DegenerateTangent {
                area_element: area,
                len1: l1,
                len2: l2,
            });
        }
        let normal = cross / area_element;
        let metric = first_fundamental_form(tangent);
        // Inverse of a 2×2 metric with det = |a₁ × a₂|² (Lagrange's identity), exact for any T.
        let det = area_element * area_element;
        let inv = Matrix2::new(metric[(1, 1)], -metric[(0, 1)], -metric[(1, 0)], metric[(0, 0)]) / det;
        let pinv = inv * tangent.transpose();
        Ok(Self {
            tangent: *tangent,
            pinv,
            area_element,
            normal,
        })
    }

    /// The first fundamental form `I = GᵀG`.
    pub fn first_fundamental_form(&self) -> Matrix2<T> {
        first_fundamental_form(&self.tangent)
    }

    /// The tangent projector (first fundamental tensor) `a = G G⁺ = I − n₀ ⊗ n₀`.
    pub fn tangent_projector(&self) -> Matrix3<T> {
        self.tangent * self.pinv
    }

    /// The surface alternating tensor `c = (a₁ ⊗ a₂ − a₂ ⊗ a₁)/√det I` (eq. 13); `c y = y × n₀`.
    pub fn alternating_tensor(&self) -> Matrix3<T> {
        let a1: Vector3<T> = self.tangent.column(0).into();
        let a2: Vector3<T> = self.tangent.column(1).into();
        (a1 * a2.transpose() - a2 * a1.transpose()) / self.area_element
    }

    /// An orthonormal frame `[t₁ t₂ n₀]` with `t₁ = a₁/|a₁|` and `t₂ = n₀ × t₁` (a rotation matrix).
    pub fn orthonormal_frame(&self) -> Matrix3<T> {
        let a1: Vector3<T> = self.tangent.column(0).into();
        let t1 = a1.normalize();
        let t2 = self.normal.cross(&t1);
        Matrix3::from_columns(&[t1, t2, self.normal])
    }
}

/// The first fundamental form `I = GᵀG`.
pub fn first_fundamental_form<T: Real>(tangent: &Matrix3x2<T>) -> Matrix2<T> {
    tangent.transpose() * tangent
}

/// The second fundamental form `II = −Gᵀ ∇_ξ n` (supplement eq. 9).
pub fn second_fundamental_form<T: Real>(tangent: &Matrix3x2<T>, normal_gradient: &Matrix3x2<T>) -> Matrix2<T> {
    -(tangent.transpose() * normal_gradient)
}

/// The shape operator (Weingarten map) `S = I⁻¹ II = −G⁺ ∇_ξ n` (supplement eq. 8).
pub fn shape_operator<T: Real>(metric: &SurfaceMetric<T>, normal_gradient: &Matrix3x2<T>) -> Matrix2<T> {
    -(metric.pinv * normal_gradient)
}

/// The second fundamental tensor `b = −∇_ξ n G⁺ = −∇_S n` (supplement eq. 10).
pub fn second_fundamental_tensor<T: Real>(metric: &SurfaceMetric<T>, normal_gradient: &Matrix3x2<T>) -> Matrix3<T> {
    -(normal_gradient * metric.pinv)
}

/// `b` with its normal part removed and symmetrised: `sym(a b a)`.
///
/// For the exact normal of a smooth surface this is `b` itself. For interpolated discrete normals it
/// is the closest symmetric tangential tensor, which keeps the energy's rest state exact.
pub fn tangential_symmetric_part<T: Real>(b: &Matrix3<T>, projector: &Matrix3<T>) -> Matrix3<T> {
    let p = projector * b * projector;
    (p + p.transpose()) * T::from(0.5)
}

/// The mean curvature `H = ½ tr b` (supplement eq. 12).
pub fn mean_curvature<T: Real>(b: &Matrix3<T>) -> T {
    b.trace() * 0.5
}

/// The Gaussian curvature `K = ½ ((tr b)² − tr(b²))` (supplement eq. 12).
pub fn gaussian_curvature<T: Real>(b: &Matrix3<T>) -> T {
    let t = b.trace();
    (t * t - (b * b).trace()) * 0.5
}

/// The curvature data the curved-shell energy needs at a point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Curvature<T> {
    /// The second fundamental tensor `b`.
    pub b: Matrix3<T>,
    /// The mean curvature `H = ½ tr b`.
    pub mean: T,
    /// The Gaussian curvature `K`.
    pub gaussian: T,
}

impl<T: Real> Curvature<T> {
    /// Curvature from a normal field's gradient, using the tangential symmetric part of `b`.
    pub fn from_normal_gradient(metric: &SurfaceMetric<T>, normal_gradient: &Matrix3x2<T>) -> Self {
        let raw = second_fundamental_tensor(metric, normal_gradient);
        Self::from_b(tangential_symmetric_part(&raw, &metric.tangent_projector()))
    }

    /// Curvature of a given second fundamental tensor.
    pub fn from_b(b: Matrix3<T>) -> Self {
        Self {
            mean: mean_curvature(&b),
            gaussian: gaussian_curvature(&b),
            b,
        }
    }

    /// A flat point: `b = 0`, `H = K = 0`.
    pub fn flat() -> Self {
        Self::from_b(Matrix3::zeros())
    }
}
