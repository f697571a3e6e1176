//! The starting point of a load level's Newton solve, extrapolated from the last converged increments.
//!
//! A level starts from the quadratic through the last three equilibria (exact for paths quadratic in
//! the load factor): on a shell that bends and turns under its load, its error is of the order of the
//! cube of each level's rotation. The secant (the last increment scaled to the new load step) leaves
//! out the path's curvature, a stretch of the order of the square of the rotation, whose membrane
//! forces in a thin shell lie orders of magnitude above the loads: from it Newton needs many
//! iterations or fails, where from the last equilibrium its first step is the tangent prediction and
//! the relaxed steps of the mixed-integration-point iteration cross the stretch that step leaves. So a
//! level with only one increment to go on (the second of a run, or the first after a bisection) starts
//! from the last equilibrium. On a path that is nearly linear the secant would have been as good as
//! the quadratic: such a run pays one iteration more at its second level. Plain Newton (without mixed
//! integration points) has no relaxed steps: from the last equilibrium its line search crawls along
//! the stretch, so it takes the secant there ([`PredictorMemory::secant`]).

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
/// first).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PredictorMemory {
    increments: Vec<LevelIncrement>,
}

/// How many increments the prediction uses.
const KEPT: usize = 2;

impl PredictorMemory {
    /// A memory holding `increments` (oldest first; only the last two are kept).
    pub fn new(mut increments: Vec<LevelIncrement>) -> Self {
        let excess = increments.len().saturating_sub(KEPT);
        increments.drain(..excess);
        Self { increments }
    }

    /// The increments held, oldest first.
    pub fn increments(&self) -> &[LevelIncrement] {
        &self.increments
    }

    /// Remembers a converged increment.
    pub(crate) fn push(&mut self, increment: LevelIncrement) {
        if self.increments.len() == KEPT {
            self.increments.remove(0);
        }
        self.increments.push(increment);
    }

    /// Forgets the increments (after a failed solve, whose prediction is not trusted).
    pub(crate) fn clear(&mut self) {
        self.increments.clear();
    }

    /// Writes into `u` the last increment scaled to a load step `c` (the secant); returns false (and
    /// leaves `u` alone) when no increment is known.
    pub(crate) fn secant(&self, c: f64, u: &mut [f64]) -> bool {
        match self.increments.last() {
            Some(last) if last.step != 0.0 => {
                let scale = c / last.step;
                u.iter_mut().zip(&last.du).for_each(|(u, d)| *u = d * scale);
                true
            }
            _ => false,
        }
    }

    /// Writes into `u` the predicted increment for a load step `c` from the last equilibrium; returns
    /// false (and leaves `u` alone) when fewer than two increments are known.
    pub(crate) fn predict(&self, c: f64, u: &mut [f64]) -> bool {
        let [earlier, last] = self.increments.as_slice() else {
            return false;
        };
        let (a, b) = (earlier.step, last.step);
        if a == 0.0 || b == 0.0 {
            return false;
        }
        // The increments' rates `du/step` are the path's velocities at the middle of their steps; their
        // difference over the distance between those middles is its curvature.
        let curvature = c * (b + c) / (a + b);
        for (u, (d, e)) in u.iter_mut().zip(last.du.iter().zip(&earlier.du)) {
            let velocity = d / b;
            *u = c * velocity + curvature * (velocity - e / a);
        }
        true
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

    #[test]
    fn two_increments_predict_a_quadratic_path_exactly() {
        let (l0, l1, l2, l3) = (0.1, 0.35, 0.5, 0.9);
        let memory = PredictorMemory::new(vec![
            increment(path(l1) - path(l0), l1 - l0),
            increment(path(l2) - path(l1), l2 - l1),
        ]);
        let mut u = [0.0];
        assert!(memory.predict(l3 - l2, &mut u));
        let exact = path(l3) - path(l2);
        assert!((u[0] - exact).abs() <= 1e-14 * exact.abs(), "{} against {exact}", u[0]);
        // The secant would miss the path's curvature.
        let secant = (path(l2) - path(l1)) / (l2 - l1) * (l3 - l2);
        assert!((secant - exact).abs() > 0.1);
    }

    #[test]
    fn fewer_than_two_increments_predict_nothing_but_the_secant_asked_for() {
        let mut memory = PredictorMemory::default();
        let mut u = [7.0];
        assert!(!memory.predict(0.5, &mut u));
        memory.push(increment(2.0, 0.25));
        assert!(
            !memory.predict(0.5, &mut u),
            "no secant: the level starts from the equilibrium"
        );
        assert_eq!(u, [7.0]);
        assert!(memory.secant(0.5, &mut u));
        assert_eq!(u, [4.0]);
        memory.push(increment(3.0, 0.25));
        assert!(memory.predict(0.25, &mut u));
        memory.clear();
        assert!(!memory.secant(0.5, &mut u));
        assert!(memory.increments().is_empty() && !memory.predict(0.25, &mut u));
    }

    #[test]
    fn the_memory_keeps_the_last_two_increments() {
        let mut memory = PredictorMemory::default();
        for k in 1..=3 {
            memory.push(increment(f64::from(k), 1.0));
        }
        let kept: Vec<f64> = memory.increments().iter().map(|i| i.du[0]).collect();
        assert_eq!(kept, [2.0, 3.0]);
        let restored = PredictorMemory::new((1..=3).map(|k| increment(f64::from(k), 1.0)).collect());
        assert_eq!(restored, memory);
    }
}
