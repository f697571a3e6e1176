//! Acceptance tests of the backtracking line search: the Armijo sufficient-decrease test and its
//! noise-resistant variant (Longva et al. 2023, "Pitfalls of projection").
//!
//! Near convergence the energy change of a step can fall below the round-off of the energy itself
//! (`|ΔΠ| ≈ ε |Π|`), and the plain Armijo test then rejects good steps at random. The noise-resistant
//! variant estimates `ΔΠ` from gradients instead, by the trapezoidal rule on
//! `ΔΠ = ∫₀^α dx·∇Π(x₀ + t dx) dt`, and bounds the estimate's error by the gradient difference.
//!
//! Unlike the reference code's standard variant, the Armijo bound here carries the step length `α`
//! (`ΔΠ ≤ c α dx·∇Π₀`), as in the textbook condition.

/// The acceptance test of a trial step `x₀ + α dx`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ArmijoTest {
    /// The Armijo constant `c ∈ (0, 1)`.
    pub(crate) c: f64,
    /// Whether to use the gradient-based estimate when the energy change is small.
    pub(crate) noise_resistant: bool,
}

impl ArmijoTest {
    /// The Armijo test on energies: `Π − Π₀ ≤ c α dx·∇Π₀`, with `slope = dx·∇Π₀ < 0`.
    pub(crate) fn sufficient_decrease(&self, e0: f64, e: f64, alpha: f64, slope: f64) -> bool {
        e - e0 <= self.c * alpha * slope
    }

    /// Whether the gradient-based estimate should be tried: the noise-resistant variant is on and
    /// `|Π − Π₀| ≤ 0.1 |Π₀|`.
    pub(crate) fn in_noise_regime(&self, e0: f64, e: f64) -> bool {
        self.noise_resistant && (e - e0).abs() <= 0.1 * e0.abs()
    }

    /// The gradient-based test: with `ΔΠ ≈ α/2 · dx·(∇Π + ∇Π₀)` and error bound
    /// `ε = α/2 · |dx·(∇Π − ∇Π₀)|`, accept if `ΔΠ + ε ≤ c α dx·∇Π₀`.
    pub(crate) fn estimated_decrease(&self, alpha: f64, slope: f64, dx: &[f64], g0: &[f64], g: &[f64]) -> bool {
        let (mut sum, mut diff) = (0.0, 0.0);
        for ((d, a), b) in dx.iter().zip(g).zip(g0) {
            sum += d * (a + b);
            diff += d * (a - b);
        }
        let estimate = 0.5 * alpha * sum;
        let error = 0.5 * alpha * diff.abs();
        estimate + error <= self.c * alpha * slope
    }

    /// The full test when the gradient at the trial point is known.
    pub(crate) fn accepts_with_gradient(
        &self,
        e0: f64,
        e: f64,
        alpha: f64,
        slope: f64,
        dx: &[f64],
        g0: &[f64],
        g: &[f64],
    ) -> bool {
        self.sufficient_decrease(e0, e, alpha, slope)
            || (self.in_noise_regime(e0, e) && self.estimated_decrease(alpha, slope, dx, g0, g))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEST: ArmijoTest = ArmijoTest {
        c: 1e-4,
        noise_resistant: true,
    };

    #[test]
    fn armijo_bound_scales_with_alpha() {
        // Π(x) = x² from x₀ = 1, dx = −1 (slope −2): at α the decrease is 2α − α².
        let slope = -2.0;
        for alpha in [1.0, 0.5, 1e-3] {
            let e = (1.0 - alpha) * (1.0f64 - alpha);
            assert!(TEST.sufficient_decrease(1.0, e, alpha, slope));
        }
        // An increase is never accepted.
        assert!(!TEST.sufficient_decrease(1.0, 1.0 + 1e-12, 1e-3, slope));
        // Exactly the bound is accepted, half of it is not (Π₀ = 0 keeps the arithmetic exact).
        let bound = TEST.c * 0.5 * slope;
        assert!(TEST.sufficient_decrease(0.0, bound, 0.5, slope));
        assert!(!TEST.sufficient_decrease(0.0, bound * 0.5, 0.5, slope));
    }

    #[test]
    fn trapezoid_estimate_is_exact_for_quadratics() {
        // Π(x) = ½ x·x with ∇Π = x: from x₀ = (1, 2) along dx = −x₀ the exact change at α is
        // ½|x₀|²((1−α)² − 1), and the trapezoid estimate of a quadratic is exact.
        let x0 = [1.0, 2.0];
        let dx = [-1.0, -2.0];
        let slope = -5.0;
        let alpha = 0.25;
        let g: Vec<f64> = x0.iter().zip(&dx).map(|(a, d)| a + alpha * d).collect();
        let exact = 0.5 * 5.0 * ((1.0 - alpha) * (1.0 - alpha) - 1.0);
        let (mut sum, mut diff) = (0.0, 0.0);
        for i in 0..2 {
            sum += dx[i] * (g[i] + x0[i]);
            diff += dx[i] * (g[i] - x0[i]);
        }
        assert!((0.5 * alpha * sum - exact).abs() < 1e-15);
        // The decrease 1.09 exceeds c α |slope| + ε = 1.25e-4 + 0.156, so the step is accepted.
        assert!(0.5 * alpha * diff.abs() < exact.abs());
        assert!(TEST.estimated_decrease(alpha, slope, &dx, &x0, &g));
    }

    #[test]
    fn noise_regime_rescues_steps_hidden_by_round_off() {
        // Π(x) = 1e10 + ½ x² from x₀ = 4.47e-5 along dx = −x₀: the true decrease at α = ½ is about
        // 7.5e-10, far below the spacing of doubles near 1e10, so Π − Π₀ evaluates to exactly 0.
        let x0 = [4.47e-5];
        let dx = [-x0[0]];
        let alpha = 0.5;
        let g = [x0[0] * (1.0 - alpha)];
        let slope = -x0[0] * x0[0];
        let e0 = 1e10 + 0.5 * x0[0] * x0[0];
        let e = 1e10 + 0.5 * g[0] * g[0];
        assert_eq!(e - e0, 0.0);
        assert!(!TEST.sufficient_decrease(e0, e, alpha, slope));
        assert!(TEST.in_noise_regime(e0, e));
        // Estimate −0.375 x₀², error bound 0.125 x₀²: their sum −0.25 x₀² is below c α slope.
        assert!(TEST.accepts_with_gradient(e0, e, alpha, slope, &dx, &x0, &g));
        let off = ArmijoTest {
            noise_resistant: false,
            ..TEST
        };
        assert!(!off.accepts_with_gradient(e0, e, alpha, slope, &dx, &x0, &g));
        // Outside the regime (a large relative change) the estimate is not consulted.
        assert!(!TEST.in_noise_regime(1.0, 2.0));
    }
}
