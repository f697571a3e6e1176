//! Relaxed steps of the mixed-integration-point method: a full Newton step taken although it raises
//! the energy.
//!
//! From a thin shell's equilibrium, Newton's step under a new load bends and turns the shell rightly
//! but leaves out the second-order shortening that keeps it unstretched: the energy at the full step is
//! that spurious stretch's, orders of magnitude above the bending's. The next step, whose matrix weights
//! its geometric terms with the stresses predicted along the step (no stretch along a bending step)
//! rather than with the stretch's, removes it. A line search instead cuts the first step to a few per
//! cent, and each later one again, and the iteration crawls along the unstretched path.
//!
//! So with mixed integration points, where the full step of a positive definite matrix fails Armijo's
//! test, it is taken anyway; the steps after it are searched as usual. Once the energy falls below that
//! of the point the relaxed step left, the run is over. The steps that remove a spurious stretch cut the
//! energy's excess over the start many times each; a step that cuts it less than [`EXCESS_FACTOR`]
//! times shows a step that was wrong, not stretched (a slack membrane's first step, which the tension
//! it lacks would have held back). Then, or after [`MAX_STEPS_TO_RECOVER`] steps, or when a line search
//! fails, the run is undone and the solve goes on from its start with line searches only.

use super::{NewtonSolver, Point, Run};
use crate::problem::NewtonProblem;

/// The steps (the relaxed one included) within which the energy must fall below the start's.
const MAX_STEPS_TO_RECOVER: usize = 8;

/// The factor by which each step after the relaxed one must cut the energy's excess over the start's.
const EXCESS_FACTOR: f64 = 4.0;

/// A run from a relaxed step.
pub(super) struct Relaxed {
    /// The iterate the relaxed step left.
    pub(super) start: Vec<f64>,
    /// Its energy.
    pub(super) energy: f64,
    /// The steps taken since (the relaxed one included).
    steps: usize,
    /// The energy's excess over the start's at the last step.
    excess: f64,
    /// Whether a step cut the excess too little.
    stalled: bool,
}

impl Relaxed {
    /// A run leaving `start` of energy `energy`.
    pub(super) fn new(start: &[f64], energy: f64) -> Self {
        Self {
            start: start.to_vec(),
            energy,
            steps: 0,
            excess: f64::INFINITY,
            stalled: false,
        }
    }

    /// Counts an accepted step to an iterate of energy `energy`; returns whether it lies below the
    /// start's, which ends the run.
    pub(super) fn recovered(&mut self, energy: f64) -> bool {
        self.steps += 1;
        let excess = energy - self.energy;
        self.stalled = excess > self.excess / EXCESS_FACTOR;
        self.excess = excess;
        excess < 0.0
    }

    /// Whether the run is to be undone: a step cut the excess too little, or the steps ran out.
    pub(super) fn overdue(&self) -> bool {
        self.stalled || self.steps >= MAX_STEPS_TO_RECOVER
    }
}

impl NewtonSolver {
    /// Whether the full step along the last direction (slope `dx·∇Π`), which failed Armijo's test, may
    /// be taken as a relaxed step: outside a run from another, and only a Newton step of a positive
    /// definite matrix (along an indefinite matrix's own step or a shifted one the energy's rise may be
    /// the descent's failure, not the stretch's) whose decrement lies above the energy's round-off
    /// (below it the rise is noise, which the noise-resistant line search and the stagnation test
    /// handle).
    pub(super) fn may_relax(&self, run: &Run, slope: f64) -> bool {
        run.may_relax && run.relaxed.is_none() && !run.indefinite && !run.shifted && run.test.resolves(slope)
    }
}

/// Undoes the run from a relaxed step: back to its start, the iteration matrix at the start's own
/// stresses, and no relaxed step for the rest of the solve. Returns the start, whose gradient and
/// Hessian are to be evaluated anew; its residual will take the place of the last iterate's.
pub(super) fn undo_relaxed<P: NewtonProblem + ?Sized>(problem: &mut P, x: &mut [f64], run: &mut Run) -> Point {
    let relaxed = run.relaxed.take().expect("a run to undo");
    run.residuals.pop();
    x.copy_from_slice(&relaxed.start);
    run.may_relax = false;
    run.reuse = false;
    run.report.undone_relaxed_steps += relaxed.steps;
    problem.clear_predicted_strains();
    Point {
        energy: relaxed.energy,
        gradient: false,
        hessian: false,
    }
}
