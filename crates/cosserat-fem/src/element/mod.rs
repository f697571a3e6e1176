//! Lagrange triangle elements on the reference triangle `{ξ₁, ξ₂ ≥ 0, ξ₁ + ξ₂ ≤ 1}`.
//!
//! Each element is a zero-sized type implementing [`ShapeFunctions`]: node positions in reference
//! coordinates, the basis values, their gradients and their second derivatives. All elements are
//! surfaces embedded in 3D; the element-level [`ShapeFunctions::tangent`] gives the covariant basis
//! `G = X ∇N` of a surface element from its nodal positions.
//!
//! The elements are [`Tri3`] (linear), [`Tri6`] (quadratic, the paper's displacement element) and
//! [`Tri10`] (cubic). Their node orders are corners first, then edge nodes, then the interior node, as
//! in VTK's Lagrange cells, so a Tri3 rotation element uses the corner nodes of a higher-order element.

mod tri10;
mod tri3;
mod tri6;

pub use tri3::Tri3;
pub use tri6::Tri6;
pub use tri10::Tri10;

use cosserat_geometry::Real;
use nalgebra::{Matrix3x2, SMatrix, SVector, Vector3};

/// The Lagrange basis of a triangle element with `N` nodes.
///
/// Gradients are with respect to the reference coordinates: row 0 holds `∂Nᵢ/∂ξ₁`, row 1 holds
/// `∂Nᵢ/∂ξ₂`. Second derivatives have rows `∂²/∂ξ₁²`, `∂²/∂ξ₁∂ξ₂`, `∂²/∂ξ₂²`.
///
/// The node count is a const generic parameter (rather than an associated constant) so that
/// fixed-size nalgebra types can be sized by it in generic code.
pub trait ShapeFunctions<const N: usize> {
    /// The polynomial degree of the basis: every polynomial of at most this degree is reproduced.
    const DEGREE: usize;
    /// The element's kind.
    const KIND: ElementKind;

    /// The reference coordinates of the nodes, in node order.
    fn nodes() -> [[f64; 2]; N];

    /// The basis function values `Nᵢ(ξ)`.
    fn values(xi: [f64; 2]) -> SVector<f64, N>;

    /// The reference gradients: entry `(α, i)` is `∂Nᵢ/∂ξ_α`.
    fn gradients(xi: [f64; 2]) -> SMatrix<f64, 2, N>;

    /// The second derivatives: rows `∂²Nᵢ/∂ξ₁²`, `∂²Nᵢ/∂ξ₁∂ξ₂`, `∂²Nᵢ/∂ξ₂²`.
    fn second_derivatives(xi: [f64; 2]) -> SMatrix<f64, 3, N>;

    /// The interpolated position `x(ξ) = Σ Nᵢ(ξ) xᵢ`.
    fn position(nodes: &[Vector3<f64>; N], xi: [f64; 2]) -> Vector3<f64> {
        interpolate(&Self::values(xi), nodes)
    }

    /// The tangent (covariant basis) `G = [x,₁ x,₂] = X ∇Nᵀ` at `ξ`.
    fn tangent(nodes: &[Vector3<f64>; N], xi: [f64; 2]) -> Matrix3x2<f64> {
        tangent_from_gradients(nodes, &Self::gradients(xi))
    }

    /// The second derivatives of the position, `[x,₁₁, x,₁₂, x,₂₂]`, at `ξ`.
    fn position_second_derivatives(nodes: &[Vector3<f64>; N], xi: [f64; 2]) -> [Vector3<f64>; 3] {
        let d2 = Self::second_derivatives(xi);
        [0, 1, 2].map(|row| {
            nodes
                .iter()
                .enumerate()
                .fold(Vector3::zeros(), |acc, (i, x)| acc + x * d2[(row, i)])
        })
    }
}

/// The element types of this crate, for settings and output that choose an element at run time.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ElementKind {
    /// Linear triangle, 3 nodes.
    Tri3,
    /// Quadratic triangle, 6 nodes.
    Tri6,
    /// Cubic triangle, 10 nodes.
    Tri10,
}

impl ElementKind {
    /// The number of nodes per element.
    pub fn n_nodes(self) -> usize {
        match self {
            Self::Tri3 => 3,
            Self::Tri6 => 6,
            Self::Tri10 => 10,
        }
    }

    /// The polynomial degree of the basis.
    pub fn degree(self) -> usize {
        match self {
            Self::Tri3 => 1,
            Self::Tri6 => 2,
            Self::Tri10 => 3,
        }
    }
}

/// Interpolates nodal data with basis values: `Σ Nᵢ dᵢ`.
///
/// The basis values are `f64` (they depend on the reference point only); the nodal data may carry any
/// scalar type, so the same call interpolates positions, velocities or dual-number unknowns.
pub fn interpolate<T: Real, const N: usize, const D: usize>(
    values: &SVector<f64, N>,
    nodal: &[SVector<T, D>; N],
) -> SVector<T, D> {
    nodal
        .iter()
        .zip(values.iter())
        .fold(SVector::<T, D>::zeros(), |acc, (d, &n)| acc + d.map(|c| c * n))
}

/// The tangent `G = [x,₁ x,₂]` of nodal positions for given basis gradients (see
/// [`ShapeFunctions::gradients`]).
///
/// This map is linear in the nodal positions, so it also gives the current tangent `g` of unknown
/// positions of any scalar type.
pub fn tangent_from_gradients<T: Real, const N: usize>(
    nodes: &[Vector3<T>; N],
    gradients: &SMatrix<f64, 2, N>,
) -> Matrix3x2<T> {
    let mut g = Matrix3x2::<T>::zeros();
    for (i, x) in nodes.iter().enumerate() {
        for alpha in 0..2 {
            let d = gradients[(alpha, i)];
            for row in 0..3 {
                g[(row, alpha)] += x[row] * d;
            }
        }
    }
    g
}

/// The barycentric coordinates `(1 − ξ₁ − ξ₂, ξ₁, ξ₂)` of a reference point.
#[inline]
pub fn barycentric(xi: [f64; 2]) -> [f64; 3] {
    [1.0 - xi[0] - xi[1], xi[0], xi[1]]
}

/// A product `c · Π_k (a_k + b_k ξ₁ + c_k ξ₂)` of affine factors, with its exact derivatives.
///
/// Every Lagrange basis function on a triangle factors this way, which gives the gradients and second
/// derivatives of the higher-order elements by the product rule without hand-expanded polynomials.
#[derive(Debug, Clone, Copy)]
pub(crate) struct AffineProduct<const K: usize> {
    pub(crate) scale: f64,
    /// Factors as `[constant, ∂/∂ξ₁, ∂/∂ξ₂]`.
    pub(crate) factors: [[f64; 3]; K],
}

impl<const K: usize> AffineProduct<K> {
    fn factor_values(&self, xi: [f64; 2]) -> [f64; K] {
        self.factors.map(|f| f[0] + f[1] * xi[0] + f[2] * xi[1])
    }

    fn product_except(values: &[f64; K], skip: &[usize]) -> f64 {
        (0..K).filter(|k| !skip.contains(k)).map(|k| values[k]).product()
    }

    pub(crate) fn value(&self, xi: [f64; 2]) -> f64 {
        self.scale * self.factor_values(xi).iter().product::<f64>()
    }

    pub(crate) fn gradient(&self, xi: [f64; 2]) -> [f64; 2] {
        let v = self.factor_values(xi);
        let mut g = [0.0; 2];
        for k in 0..K {
            let rest = Self::product_except(&v, &[k]);
            g[0] += self.factors[k][1] * rest;
            g[1] += self.factors[k][2] * rest;
        }
        g.map(|x| x * self.scale)
    }

    /// `[∂₁₁, ∂₁₂, ∂₂₂]`.
    pub(crate) fn second_derivatives(&self, xi: [f64; 2]) -> [f64; 3] {
        let v = self.factor_values(xi);
        let mut h = [0.0; 3];
        for k in 0..K {
            for l in 0..K {
                if k == l {
                    continue;
                }
                let rest = Self::product_except(&v, &[k, l]);
                let (dk, dl) = (self.factors[k], self.factors[l]);
                h[0] += dk[1] * dl[1] * rest;
                h[1] += dk[1] * dl[2] * rest;
                h[2] += dk[2] * dl[2] * rest;
            }
        }
        h.map(|x| x * self.scale)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn affine_product_matches_expanded_polynomial() {
        // p = 2 (1 + x)(y − 3)(x + 2y) expanded: 2 (x y + 2 y² − 3x − 6y)(1 + x) ... compare at a point.
        let p = AffineProduct {
            scale: 2.0,
            factors: [[1.0, 1.0, 0.0], [-3.0, 0.0, 1.0], [0.0, 1.0, 2.0]],
        };
        let (x, y) = (0.3, -0.7);
        let f = |x: f64, y: f64| 2.0 * (1.0 + x) * (y - 3.0) * (x + 2.0 * y);
        assert!((p.value([x, y]) - f(x, y)).abs() < 1e-14);
        // ∂x f = 2[(y−3)(x+2y) + (1+x)(y−3)], ∂y f = 2[(1+x)(x+2y) + 2(1+x)(y−3)].
        let gx = 2.0 * ((y - 3.0) * (x + 2.0 * y) + (1.0 + x) * (y - 3.0));
        let gy = 2.0 * ((1.0 + x) * (x + 2.0 * y) + 2.0 * (1.0 + x) * (y - 3.0));
        let g = p.gradient([x, y]);
        assert!((g[0] - gx).abs() < 1e-13 && (g[1] - gy).abs() < 1e-13);
        // ∂xx = 4(y−3), ∂xy = 2[(x+2y) + 2(y−3) + (1+x)], ∂yy = 8(1+x).
        let h = p.second_derivatives([x, y]);
        assert!((h[0] - 4.0 * (y - 3.0)).abs() < 1e-13);
        assert!((h[1] - 2.0 * ((x + 2.0 * y) + 2.0 * (y - 3.0) + (1.0 + x))).abs() < 1e-13);
        assert!((h[2] - 8.0 * (1.0 + x)).abs() < 1e-13);
    }
}
