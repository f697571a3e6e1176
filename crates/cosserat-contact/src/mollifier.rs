//! IPC's mollifier for edge–edge pairs, which smoothly switches the edge–edge barrier off as the two
//! edges become parallel.
//!
//! When two edges turn parallel, their closest features jump between the interior (line–line) form and
//! the endpoint forms, and the edge–edge barrier alone is not C¹ across that switch; the nearly parallel
//! configuration is covered by the point–triangle pairs of the edges' endpoints instead. IPC (Li et al.
//! 2020, §4.3) multiplies the edge–edge barrier by
//!
//! ```text
//! m(c) = (2 − c/ε×) c/ε×   for c < ε×,     1 otherwise,     c = |(a₁ − a₀) × (b₁ − b₀)|²,
//! ```
//!
//! with `ε× = 10⁻³ |a₁ − a₀|² |b₁ − b₀|²` measured at rest: `m` is C¹ at `c = ε×` and vanishes with
//! `c`, so the product stays C¹ through the parallel configuration.

use crate::closed_form;
use crate::jet::PairJet;
use cosserat_geometry::Real;
use nalgebra::Vector3;

/// The relative threshold of IPC: `ε× = 10⁻³ |a|² |b|²` at rest.
pub const MOLLIFIER_SCALE: f64 = 1e-3;

/// The mollifier `m(c)` of one edge–edge pair.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mollifier {
    /// The threshold `ε×` \[m⁴\] below which the mollifier is active.
    pub threshold: f64,
}

impl Mollifier {
    /// The mollifier of edges with rest squared lengths `la2`, `lb2` \[m²\].
    pub fn from_rest_lengths(la2: f64, lb2: f64) -> Self {
        Self {
            threshold: MOLLIFIER_SCALE * la2 * lb2,
        }
    }

    /// `m(c)`.
    pub fn value<T: Real>(&self, c: T) -> T {
        if c.re() >= self.threshold {
            return T::one();
        }
        let r = c / T::from(self.threshold);
        (-r + T::from(2.0)) * r
    }

    /// `(m(c), m'(c), m''(c))`.
    pub fn derivatives(&self, c: f64) -> (f64, f64, f64) {
        if c >= self.threshold {
            return (1.0, 0.0, 0.0);
        }
        let e = self.threshold;
        let r = c / e;
        ((2.0 - r) * r, (2.0 - 2.0 * r) / e, -2.0 / (e * e))
    }

    /// Whether the mollifier is below one for this `c`.
    pub fn is_active(&self, c: f64) -> bool {
        c < self.threshold
    }
}

/// `c = |(x₁ − x₀) × (x₃ − x₂)|²` of an edge–edge pair `[a₀, a₁, b₀, b₁]`.
pub fn cross_squared<T: Real>(x: &[Vector3<T>; 4]) -> T {
    (x[1] - x[0]).cross(&(x[3] - x[2])).norm_squared()
}

/// `c` with its gradient and Hessian.
pub fn cross_squared_jet(x: &[Vector3<f64>; 4]) -> PairJet {
    let (v, g, h) = closed_form::cross_squared(&(x[1] - x[0]), &(x[3] - x[2]));
    PairJet::from_differences(v, &g, &h, [(1, 0), (3, 2)])
}
