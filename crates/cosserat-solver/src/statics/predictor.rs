//! The starting point of a load level's Newton solve, extrapolated from the last converged increments.
//!
//! The secant prediction (the last increment scaled to the new load step) leaves the path's curvature
//! out. On a shell that bends and turns under its load that error is a stretch of the order of the
//! square of each level's rotation. A moderately thin shell's Newton removes it in a step or two; in a
//! thin one the stretch's membrane forces lie orders of magnitude above the loads and turn the
//! Hessian strongly indefinite, so that Newton needs tens of shortened steps per level. The quadratic
//! through the last three equilibria (exact for paths quadratic in the load factor) leaves an error
//! of the order of the cube of the rotation per level, which such a shell needs; on thicker shells it
//! starts Newton no better than the secant, and often a little worse. So a run predicts with the
//! secant until a level shows the secant's failure (its solve started from the prediction at an
//! indefinite Hessian, whether it converged or not) and with the quadratic from then on. Where the
//! quadratic has too little to go on (one increment, after a bisection) such a run starts from the
//! last equilibrium instead of the secant it knows to fail: Newton's first step from there is the
//! tangent prediction, and the relaxed steps of the mixed-integration-point iteration cross the
//! stretch it leaves.

/// A converged load increment: the change of the unknowns from one equilibrium to the next, and of
/// the load factor.
#[derive(Debug, Clone, PartialEq)]
pub struct LevelIncrement {
    /// The change of the unknowns.
    pub du: Vec<f64>,
    /// The change of the load factor.
    pub step: f64,
}

/// What a prediction extrapolates from: the last increments (none, the last, or the last two, oldest
/// first) and whether the run predicts quadratically (see the module documentation).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PredictorMemory {
    increments: Vec<LevelIncrement>,
    quadratic: bool,
}

/// How many increments the prediction uses.
const KEPT: usize = 2;

impl PredictorMemory {
    /// A memory holding `increments` (oldest first; only the last two are kept), predicting
    /// quadratically if `quadratic`.
    pub fn new(mut increments: Vec<LevelIncrement>, quadratic: bool) -> Self {
        let excess = increments.len().saturating_sub(KEPT);
        increments.drain(..excess);
        Self { increments, quadratic }
    }

    /// The increments held, oldest first.
    pub fn increments(&self) -> &[LevelIncrement] {
        &self.increments
    }

    /// Whether predictions are quadratic once two increments are known.
    pub fn is_quadratic(&self) -> bool {
        self.quadratic
    }

    /// Remembers a converged increment; `poor_start` tells that its solve started where the Hessian
    /// was indefinite, which makes the predictions quadratic from now on.
    pub(crate) fn push(&mut self, increment: LevelIncrement, poor_start: bool) {
        if self.increments.len() == KEPT {
            self.increments.remove(0);
        }
        self.increments.push(increment);
        self.quadratic |= poor_start;
    }

    /// Forgets the increments (after a failed solve, whose prediction is not trusted); `poor_start`
    /// tells that the solve started from a prediction at an indefinite Hessian, which makes the
    /// predictions quadratic from now on.
    pub(crate) fn clear(&mut self, poor_start: bool) {
        self.increments.clear();
        self.quadratic |= poor_start;
    }

    /// Writes into `u` the predicted increment for a load step `c` from the last equilibrium; returns
    /// false (and leaves `u` alone) when nothing is known to extrapolate from, or only the one
    /// increment of a secant that a quadratic run knows to fail.
    pub(crate) fn predict(&self, c: f64, u: &mut [f64]) -> bool {
        match self.increments.as_slice() {
            [.., earlier, last] if self.quadratic && earlier.step != 0.0 && last.step != 0.0 => {
                // The increments' rates `du/step` are the path's velocities at the middle of their
                // steps; their difference over the distance between those middles is its curvature.
                let (a, b) = (earlier.step, last.step);
                let curvature = c * (b + c) / (a + b);
                for (u, (d, e)) in u.iter_mut().zip(last.du.iter().zip(&earlier.du)) {
                    let velocity = d / b;
                    *u = c * velocity + curvature * (velocity - e / a);
                }
                true
            }
            [.., last] if !self.quadratic && last.step != 0.0 => {
                let scale = c / last.step;
                u.iter_mut().zip(&last.du).for_each(|(u, d)| *u = d * scale);
                true
            }
            _ => false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn increment(du: f64, step: f64) -> LevelIncrement {
        LevelIncrement { du: vec![du], step }
    }

    /// The path `x(λ) = 3λ² − λ + 2`, sampled at unequal load factors.
    fn path(lambda: f64) -> f64 {
        3.0 * lambda * lambda - lambda + 2.0
    }

    /// A memory of the path's increments over `[l0, l1]` and `[l1, l2]`.
    fn memory_of_path(l0: f64, l1: f64, l2: f64, quadratic: bool) -> PredictorMemory {
        let increments = vec![
            increment(path(l1) - path(l0), l1 - l0),
            increment(path(l2) - path(l1), l2 - l1),
        ];
        PredictorMemory::new(increments, quadratic)
    }

    #[test]
    fn a_quadratic_memory_predicts_a_quadratic_path_exactly() {
        let (l0, l1, l2, l3) = (0.1, 0.35, 0.5, 0.9);
        let mut u = [0.0];
        assert!(memory_of_path(l0, l1, l2, true).predict(l3 - l2, &mut u));
        let exact = path(l3) - path(l2);
        assert!((u[0] - exact).abs() <= 1e-14 * exact.abs(), "{} against {exact}", u[0]);
        // The secant misses the path's curvature.
        assert!(memory_of_path(l0, l1, l2, false).predict(l3 - l2, &mut u));
        let secant = (path(l2) - path(l1)) / (l2 - l1) * (l3 - l2);
        assert_eq!(u[0], secant);
        assert!((secant - exact).abs() > 0.1);
    }

    #[test]
    fn one_increment_predicts_the_secant_and_none_predicts_nothing() {
        let mut memory = PredictorMemory::new(Vec::new(), false);
        let mut u = [7.0];
        assert!(!memory.predict(0.5, &mut u));
        assert_eq!(u, [7.0]);
        memory.push(increment(2.0, 0.25), false);
        assert!(memory.predict(0.5, &mut u));
        assert_eq!(u, [4.0]);
    }

    #[test]
    fn a_quadratic_run_with_one_increment_starts_from_the_equilibrium() {
        let mut memory = PredictorMemory::new(vec![increment(2.0, 0.25)], true);
        let mut u = [7.0];
        assert!(!memory.predict(0.5, &mut u), "the secant a quadratic run knows to fail");
        assert_eq!(u, [7.0]);
        memory.push(increment(3.0, 0.25), false);
        assert!(memory.predict(0.25, &mut u));
    }

    #[test]
    fn a_solve_that_fails_from_a_poor_prediction_makes_the_predictions_quadratic() {
        let mut memory = PredictorMemory::default();
        memory.push(increment(1.0, 1.0), false);
        memory.clear(false);
        assert!(
            !memory.is_quadratic(),
            "a failed solve from the equilibrium says nothing of the secant"
        );
        memory.push(increment(1.0, 1.0), false);
        memory.clear(true);
        assert!(memory.is_quadratic() && memory.increments().is_empty());
    }

    #[test]
    fn a_poor_start_makes_the_predictions_quadratic_for_good() {
        let mut memory = PredictorMemory::default();
        memory.push(increment(1.0, 1.0), false);
        assert!(!memory.is_quadratic());
        memory.push(increment(2.0, 1.0), true);
        memory.push(increment(3.0, 1.0), false);
        memory.clear(false);
        assert!(memory.is_quadratic() && memory.increments().is_empty());
    }

    #[test]
    fn the_memory_keeps_the_last_two_increments() {
        let mut memory = PredictorMemory::default();
        for k in 1..=3 {
            memory.push(increment(f64::from(k), 1.0), false);
        }
        let kept: Vec<f64> = memory.increments().iter().map(|i| i.du[0]).collect();
        assert_eq!(kept, [2.0, 3.0]);
        let restored = PredictorMemory::new((1..=3).map(|k| increment(f64::from(k), 1.0)).collect(), false);
        assert_eq!(restored, memory);
    }
}
