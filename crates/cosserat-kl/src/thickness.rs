//! Gauss–Legendre rules through the shell thickness.
//!
//! The energy of a face is `∫_{−h/2}^{h/2} W(ξ) dξ` per unit area. For St. Venant–Kirchhoff on a flat
//! rest state the integrand is a polynomial of degree 4 in `ξ` (the strain is quadratic in `ξ`), which
//! the 3-point rule (degree 5) integrates exactly; that is the default. Rest curvature and the
//! neo-Hookean logarithm make the integrand rational; their thickness error is of relative order
//! `(h κ)²` and `(h κ)⁴` and vanishes for thin shells.

use crate::error::KlError;

/// The most points a rule may have.
pub const MAX_THICKNESS_POINTS: usize = 5;

/// Points and weights on `[−1, 1]` of the `n`-point Gauss–Legendre rules, `n = 2..=5` (closed forms).
fn reference_rule(n: usize) -> ([f64; MAX_THICKNESS_POINTS], [f64; MAX_THICKNESS_POINTS]) {
    let mut x = [0.0; MAX_THICKNESS_POINTS];
    let mut w = [0.0; MAX_THICKNESS_POINTS];
    match n {
        2 => {
            let a = 1.0 / 3f64.sqrt();
            x[..2].copy_from_slice(&[-a, a]);
            w[..2].copy_from_slice(&[1.0, 1.0]);
        }
        3 => {
            let a = 0.6f64.sqrt();
            x[..3].copy_from_slice(&[-a, 0.0, a]);
            w[..3].copy_from_slice(&[5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0]);
        }
        4 => {
            let r = 2.0 / 7.0 * 1.2f64.sqrt();
            let (a, b) = ((3.0 / 7.0 - r).sqrt(), (3.0 / 7.0 + r).sqrt());
            let (wa, wb) = ((18.0 + 30f64.sqrt()) / 36.0, (18.0 - 30f64.sqrt()) / 36.0);
            x[..4].copy_from_slice(&[-b, -a, a, b]);
            w[..4].copy_from_slice(&[wb, wa, wa, wb]);
        }
        _ => {
            let r = 2.0 * (10.0f64 / 7.0).sqrt();
            let (a, b) = ((5.0 - r).sqrt() / 3.0, (5.0 + r).sqrt() / 3.0);
            let (wa, wb) = (
                (322.0 + 13.0 * 70f64.sqrt()) / 900.0,
                (322.0 - 13.0 * 70f64.sqrt()) / 900.0,
            );
            x.copy_from_slice(&[-b, -a, 0.0, a, b]);
            w.copy_from_slice(&[wb, wa, 128.0 / 225.0, wa, wb]);
        }
    }
    (x, w)
}

/// The volume measure of the thickness integral.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RestVolume {
    /// The exact rest volume of a face with constant rest curvature: weights times
    /// `det(I − ξ S̄) = 1 − 2H̄ξ + K̄ξ²`. Requires `h/2` below every principal radius of curvature.
    #[default]
    Exact,
    /// The mid-surface area times the thickness (the volume factor set to 1), with the strain measured
    /// in the mid-surface metric, `M = I + ā⁻¹ (g(ξ) − ḡ(ξ))`: the usual thin-shell approximation,
    /// which differs from [`RestVolume::Exact`] pointwise at relative order `ξ κ`; those terms are odd in
    /// `ξ`, so face energies differ at relative order `(h κ)²` (measured on a sphere stencil, see
    /// `docs/kirchhoff-love.md`). It admits faces more sharply
    /// curved than `2/h` (a coarse mesh of a thick closed surface), where the exact volume factor
    /// changes sign inside the thickness and `ḡ(ξ)` becomes singular.
    MidSurface,
}

/// An `n`-point Gauss–Legendre rule through the thickness, `2 ≤ n ≤ 5`, with its volume measure.
/// Default: 3 points, exact rest volume.
///
/// One point would see no bending at all (it samples the mid-surface only), so it is rejected.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ThicknessRule {
    n_points: usize,
    rest_volume: RestVolume,
}

impl Default for ThicknessRule {
    fn default() -> Self {
        Self {
            n_points: 3,
            rest_volume: RestVolume::Exact,
        }
    }
}

impl ThicknessRule {
    /// The `n`-point rule.
    ///
    /// # Errors
    /// [`KlError::InvalidParameter`] unless `2 ≤ n ≤ 5`.
    pub fn try_new(n_points: usize) -> Result<Self, KlError> {
        if (2..=MAX_THICKNESS_POINTS).contains(&n_points) {
            Ok(Self {
                n_points,
                rest_volume: RestVolume::Exact,
            })
        } else {
            Err(KlError::InvalidParameter {
                name: "thickness_points",
                value: n_points as f64,
                reason: "must be 2, 3, 4 or 5",
            })
        }
    }

    /// Number of points.
    pub fn n_points(&self) -> usize {
        self.n_points
    }

    /// The same rule with another volume measure.
    pub fn with_rest_volume(self, rest_volume: RestVolume) -> Self {
        Self { rest_volume, ..self }
    }

    /// The volume measure.
    pub fn rest_volume(&self) -> RestVolume {
        self.rest_volume
    }

    /// The thickness coordinates `ξ` \[m\] and weights \[m\] for a shell of thickness `h`: the weights sum
    /// to `h`, and `Σ w f(ξ) = ∫_{−h/2}^{h/2} f` for polynomials of degree `2n − 1`.
    pub fn points(&self, thickness: f64) -> impl Iterator<Item = (f64, f64)> {
        let (x, w) = reference_rule(self.n_points);
        let half = 0.5 * thickness;
        (0..self.n_points).map(move |q| (half * x[q], half * w[q]))
    }
}
