//! Value, gradient and Hessian of a scalar function of the four points of a contact pair, and the chain
//! rule from "difference locals" to the pair's twelve coordinates.
//!
//! Contact distances depend on the points only through a few differences of them (`p − t₀`,
//! `t₁ − t₀`, ...), because they are invariant under translation. Their derivatives are taken with
//! respect to those differences (3, 6 or 9 numbers) instead of all twelve coordinates; the map back to
//! the twelve coordinates is a constant matrix of ±1 blocks, applied here by index arithmetic.

use cosserat_assembly::finite::all_finite;
use nalgebra::{SMatrix, SVector};
#[cfg(test)]
use {nalgebra::Vector3, num_dual::Dual2SVec64};

/// Value, gradient (12) and Hessian (12×12) of a scalar function of the four points `x₀ … x₃` of a pair,
/// coordinates ordered point by point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairJet {
    /// The value.
    pub value: f64,
    /// The gradient with respect to `(x₀, x₁, x₂, x₃)`.
    pub gradient: SVector<f64, 12>,
    /// The Hessian, symmetric.
    pub hessian: SMatrix<f64, 12, 12>,
}

impl PairJet {
    /// The zero function.
    pub fn zeros() -> Self {
        Self {
            value: 0.0,
            gradient: SVector::zeros(),
            hessian: SMatrix::zeros(),
        }
    }

    /// The jet of a function `φ(y₀, …, y_{L−1})` of `L` difference vectors `y_k = x[plus_k] − x[minus_k]`,
    /// given `φ`'s value, gradient (`N = 3L` entries) and Hessian.
    ///
    /// # Panics
    /// If `N ≠ 3L` or a point index is not below 4 (programmer error).
    #[track_caller]
    pub fn from_differences<const L: usize, const N: usize>(
        value: f64,
        g: &SVector<f64, N>,
        h: &SMatrix<f64, N, N>,
        diffs: [(usize, usize); L],
    ) -> Self {
        assert_eq!(N, 3 * L, "a difference local has three components");
        let mut out = Self::zeros();
        out.value = value;
        for (k, &(p, m)) in diffs.iter().enumerate() {
            for c in 0..3 {
                out.gradient[3 * p + c] += g[3 * k + c];
                out.gradient[3 * m + c] -= g[3 * k + c];
            }
        }
        for (k, &(pk, mk)) in diffs.iter().enumerate() {
            for (l, &(pl, ml)) in diffs.iter().enumerate() {
                let block = h.fixed_view::<3, 3>(3 * k, 3 * l);
                for (row, col, sign) in [(pk, pl, 1.0), (pk, ml, -1.0), (mk, pl, -1.0), (mk, ml, 1.0)] {
                    let mut target = out.hessian.fixed_view_mut::<3, 3>(3 * row, 3 * col);
                    target += block * sign;
                }
            }
        }
        out
    }

    /// The jet of a product `a b` of two functions of the same points.
    pub fn product(a: &Self, b: &Self) -> Self {
        let cross = a.gradient * b.gradient.transpose();
        Self {
            value: a.value * b.value,
            gradient: a.gradient * b.value + b.gradient * a.value,
            hessian: a.hessian * b.value + b.hessian * a.value + cross + cross.transpose(),
        }
    }

    /// The jet of `f(φ)` for a scalar function `f` with `f(φ)`, `f'(φ)`, `f''(φ)` given.
    pub fn compose(&self, f: f64, df: f64, d2f: f64) -> Self {
        Self {
            value: f,
            gradient: self.gradient * df,
            hessian: self.hessian * df + self.gradient * self.gradient.transpose() * d2f,
        }
    }

    /// Whether every entry is finite.
    pub fn is_finite(&self) -> bool {
        self.value.is_finite() && all_finite(self.gradient.as_slice()) && all_finite(self.hessian.as_slice())
    }
}

/// Value, gradient and Hessian of a function of `N` local numbers, by a second-order dual pass (the
/// derivative oracle of the closed forms).
#[cfg(test)]
pub(crate) fn local_hessian<const N: usize>(
    f: impl Fn(SVector<Dual2SVec64<N>, N>) -> Dual2SVec64<N>,
    locals: &SVector<f64, N>,
) -> (f64, SVector<f64, N>, SMatrix<f64, N, N>) {
    num_dual::hessian(f, locals)
}

/// Stacks `L` difference vectors of the four points into one local vector (`N = 3L`).
#[cfg(test)]
pub(crate) fn stack_differences<const L: usize, const N: usize>(
    x: &[Vector3<f64>; 4],
    diffs: [(usize, usize); L],
) -> SVector<f64, N> {
    let mut out = SVector::<f64, N>::zeros();
    for (k, &(p, m)) in diffs.iter().enumerate() {
        out.fixed_rows_mut::<3>(3 * k).copy_from(&(x[p] - x[m]));
    }
    out
}

/// The `k`-th 3-vector of a stacked local vector.
#[cfg(test)]
pub(crate) fn local<T: nalgebra::Scalar + Copy, const N: usize>(y: &SVector<T, N>, k: usize) -> Vector3<T> {
    Vector3::new(y[3 * k], y[3 * k + 1], y[3 * k + 2])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn difference_chain_matches_a_direct_twelve_coordinate_pass() {
        // φ(y₀, y₁) = |y₀|² (y₀·y₁) with y₀ = x₀ − x₂, y₁ = x₃ − x₁, differentiated both ways.
        let x = [
            Vector3::new(0.3, -0.2, 0.5),
            Vector3::new(-0.1, 0.4, 0.2),
            Vector3::new(0.7, 0.1, -0.3),
            Vector3::new(0.2, 0.9, 0.4),
        ];
        let diffs = [(0, 2), (3, 1)];
        let y: SVector<f64, 6> = stack_differences(&x, diffs);
        let (v, g, h) = local_hessian(
            |y| {
                let (a, b) = (local(&y, 0), local(&y, 1));
                a.dot(&a) * a.dot(&b)
            },
            &y,
        );
        let jet = PairJet::from_differences(v, &g, &h, diffs);
        let mut flat = SVector::<f64, 12>::zeros();
        for (i, p) in x.iter().enumerate() {
            flat.fixed_rows_mut::<3>(3 * i).copy_from(p);
        }
        let (v2, g2, h2) = num_dual::hessian(
            |z: SVector<Dual2SVec64<12>, 12>| {
                let a = local(&z, 0) - local(&z, 2);
                let b = local(&z, 3) - local(&z, 1);
                a.dot(&a) * a.dot(&b)
            },
            &flat,
        );
        assert!((jet.value - v2).abs() < 1e-14);
        assert!((jet.gradient - g2).norm() < 1e-13);
        assert!((jet.hessian - h2).norm() < 1e-12);
    }
}
