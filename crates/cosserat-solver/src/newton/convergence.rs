//! When Newton's method stops: the residual test relative to the load scale, its round-off floor, and
//! the Newton-decrement test that accepts a solve stagnating at that floor.
//!
//! A residual is a force (or torque), and whether `1e-7 N` is tight or loose depends on the problem:
//! it lies below the round-off of a stiff shell's residual (Newton then never converges) and above the
//! whole load of a soft one (the initial guess then passes untouched). [`Tolerance::Relative`] therefore
//! compares the residual with the scale of the forces in the problem,
//!
//! `r ≤ max(relative · F, floor)`,
//!
//! where the load scale `F` is the largest of the external loads (as the problem reports them), the
//! reaction forces on the eliminated unknowns, and the first residual of the solve; and the floor is
//! the round-off of the residual itself, estimated from the assembled Hessian and the size of the state:
//! a gradient entry is a sum of terms `H_ij m_j` whose round-off is of the order of
//! `ε Σ_j |H_ij| m_j` (`m_j` the magnitude of the coordinate behind unknown `j`, e.g. a node's position,
//! see [`NewtonProblem::unknown_magnitudes`](crate::NewtonProblem::unknown_magnitudes)).
//!
//! Where that estimate is too low (round-off accumulates over more terms than it counts), Newton's
//! iterates stop improving at the true floor. Such a solve is accepted as [`Criterion::Stagnated`] when
//! its residual no longer decreases and the Newton decrement `−dx·∇Π = ∇Πᵀ H⁻¹ ∇Π` shows that the next
//! step would change the energy by less than its own round-off: no further iteration can improve the
//! state. The run reports such solves as a warning. [`Tolerance::Absolute`] keeps the fixed tolerance of
//! the reference code, without floor or stagnation test.

/// The residual tolerance of Newton's method.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Tolerance {
    /// Converged when `r ≤ max(relative · F, floor)` (see the module documentation); a solve stagnating
    /// at the round-off floor is accepted and reported. The default, with
    /// [`Tolerance::DEFAULT_RELATIVE`].
    Relative(f64),
    /// Converged when `r < tolerance`, in the residual's units (N and N·m for the time stepper): the
    /// reference code's fixed tolerance (1e-7 in the paper's scenes). No floor, no stagnation test.
    Absolute(f64),
}

impl Tolerance {
    /// The default relative tolerance of a static solve: the residual is a millionth of the largest
    /// force in the problem.
    pub const DEFAULT_RELATIVE: f64 = 1e-6;

    /// The default relative tolerance of a time step, where the residual is an error in momentum and
    /// the scale includes the nodes' momenta (see `PotentialProblem`'s load scale): each node's velocity
    /// is right to 1e-5 of the fastest node's velocity or of the velocity the loads impart in a step.
    /// Backward Euler's own error in a step is of the order of the step's velocity change, so more
    /// digits buy nothing; 1e-5 keeps the Newton iterations of the paper's scenes at those of their
    /// absolute tolerance of 1e-7.
    pub const DEFAULT_RELATIVE_DYNAMIC: f64 = 1e-5;

    /// The tolerance's value (relative or absolute).
    pub fn value(&self) -> f64 {
        match *self {
            Tolerance::Relative(v) | Tolerance::Absolute(v) => v,
        }
    }
}

impl Default for Tolerance {
    fn default() -> Self {
        Tolerance::Relative(Tolerance::DEFAULT_RELATIVE)
    }
}

/// Which test a converged solve passed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Criterion {
    /// The residual fell below the tolerance.
    Residual,
    /// The residual stopped decreasing above the tolerance, at a state where a Newton step would change
    /// the energy by less than its round-off ([`Tolerance::Relative`] only): accepted with a warning.
    Stagnated,
}

/// How a converged solve was judged, for its report.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Convergence {
    /// The test it passed.
    pub criterion: Criterion,
    /// The residual bound in force at the end of the solve, in the residual's units: the absolute
    /// tolerance, or `max(relative · load_scale, floor)`.
    pub tolerance: f64,
    /// The load scale `F` (the largest external load, reaction or first residual), residual units.
    pub load_scale: f64,
    /// The estimated round-off floor of the residual, residual units (0 with an absolute tolerance).
    pub floor: f64,
}

impl Convergence {
    /// `residual / load_scale` (infinite for a positive residual without load, 0 for none).
    pub fn relative_residual(&self, residual: f64) -> f64 {
        if residual == 0.0 {
            0.0
        } else {
            residual / self.load_scale
        }
    }
}

/// The round-off floor is this many times `ε Σ_j |H_ij| m_j`: a residual entry sums the contributions
/// of every element at a node (up to a few dozen quadrature points), each rounded in a chain of some
/// ten operations.
const FLOOR_FACTOR: f64 = 16.0;

/// A solve stagnates when its best residual has not halved over this many iterations.
const STAGNATION_WINDOW: usize = 3;

/// The Newton decrement `−dx·∇Π` counts as round-off below this many times `ε |Π|`: an energy is a sum
/// of many element contributions, each with a relative round-off of a few `ε`.
const DECREMENT_FACTOR: f64 = 1e3;

/// The convergence test of one solve, updated as the iterates reveal loads, reactions and stiffness.
#[derive(Debug, Clone)]
pub(crate) struct ConvergenceTest {
    tolerance: Tolerance,
    /// The largest of the external load, the reactions and the first residual seen so far.
    load_scale: f64,
    /// Whether the load scale was measured before the solve (at the state a prediction extrapolates
    /// from), so that the iterates' reactions do not enter it.
    scale_measured: bool,
    floor: f64,
    /// `|Π|` at the state the solve starts from (a prediction's start, where there is one).
    reference_energy: f64,
    /// The larger of `reference_energy` and `|Π|` at the latest iterate: the energy's size for the
    /// decrement. Not the largest over the iterates: a prediction or an early iterate far from the
    /// solution can carry a stretch energy many orders of magnitude above the solution's, whose
    /// round-off would then pass the decrement of a state still far from its minimum.
    energy_scale: f64,
}

impl ConvergenceTest {
    /// A test with the problem's external load scale and the first residual, both in residual units.
    pub(crate) fn new(tolerance: Tolerance, external_load: f64, first_residual: f64, energy: f64) -> Self {
        Self {
            tolerance,
            load_scale: external_load.max(first_residual),
            scale_measured: false,
            floor: 0.0,
            reference_energy: energy.abs(),
            energy_scale: energy.abs(),
        }
    }

    /// A test whose load scale `scale` was measured before the solve, at the state its initial iterate
    /// is predicted from (the external load, the residual and the reactions there): the residual and
    /// the reactions of the iterates, a prediction's among them, are errors of the iterates and not
    /// forces of the problem, and do not enter it. For the same reason the energy scale's reference is
    /// the energy `start_energy` there; `energy` is the first iterate's.
    pub(crate) fn with_measured_scale(tolerance: Tolerance, scale: f64, start_energy: f64, energy: f64) -> Self {
        let mut test = Self {
            scale_measured: true,
            ..Self::new(tolerance, scale, 0.0, start_energy)
        };
        test.observe_energy(energy);
        test
    }

    /// Takes the reactions (the largest gradient entry of the eliminated unknowns) of a new iterate
    /// into the load scale, unless the scale was measured before the solve.
    pub(crate) fn observe_reactions(&mut self, reactions: f64) {
        if !self.scale_measured {
            self.load_scale = self.load_scale.max(reactions);
        }
    }

    /// The energy of the latest iterate sets the energy scale (never below the reference).
    pub(crate) fn observe_energy(&mut self, energy: f64) {
        self.energy_scale = self.reference_energy.max(energy.abs());
    }

    /// Takes `max_i Σ_j |H_ij| m_j` of a new Hessian (residual units) into the round-off floor.
    pub(crate) fn observe_stiffness(&mut self, stiffness_times_magnitude: f64) {
        self.floor = self.floor.max(FLOOR_FACTOR * f64::EPSILON * stiffness_times_magnitude);
    }

    /// The residual bound.
    pub(crate) fn bound(&self) -> f64 {
        match self.tolerance {
            Tolerance::Absolute(t) => t,
            Tolerance::Relative(rel) => (rel * self.load_scale).max(self.floor),
        }
    }

    /// Whether the residual passes the tolerance.
    pub(crate) fn accepts(&self, residual: f64) -> bool {
        match self.tolerance {
            Tolerance::Absolute(t) => residual < t,
            Tolerance::Relative(_) => residual <= self.bound(),
        }
    }

    /// Whether a solve whose residuals are `residuals` (one per accepted iterate) and whose last Newton
    /// decrement was `decrement` has stagnated at the round-off floor: its best residual has not halved
    /// over the last [`STAGNATION_WINDOW`] iterations (or its line search can make no progress,
    /// `stuck`), and the decrement of a positive definite Hessian is below the energy's round-off: the
    /// state is a minimum to within what the energy can resolve. Its residual may still be well above
    /// the bound (a stiff direction holds a large force for a tiny displacement error); the report
    /// shows it.
    pub(crate) fn stagnated(&self, residuals: &[f64], decrement: Option<f64>, stuck: bool) -> bool {
        if matches!(self.tolerance, Tolerance::Absolute(_)) {
            return false;
        }
        let Some(decrement) = decrement else { return false };
        let no_progress = stuck || {
            let n = residuals.len();
            n > STAGNATION_WINDOW && {
                let best = |r: &[f64]| r.iter().copied().fold(f64::INFINITY, f64::min);
                let (before, window) = residuals.split_at(n - STAGNATION_WINDOW);
                best(window) > 0.5 * best(before)
            }
        };
        no_progress && !self.resolves(decrement)
    }

    /// Whether a Newton decrement `−dx·∇Π` lies above the energy's round-off.
    pub(crate) fn resolves(&self, decrement: f64) -> bool {
        decrement.abs() > DECREMENT_FACTOR * f64::EPSILON * self.energy_scale
    }

    /// The record of a converged solve.
    pub(crate) fn record(&self, criterion: Criterion) -> Convergence {
        Convergence {
            criterion,
            tolerance: self.bound(),
            load_scale: self.load_scale,
            floor: self.floor,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_bound_is_the_larger_of_the_scaled_load_and_the_floor() {
        // Powers of two keep the products exact.
        let mut test = ConvergenceTest::new(Tolerance::Relative(0.25), 2.0, 0.5, 1.0);
        assert_eq!(test.bound(), 0.5);
        test.observe_reactions(8.0);
        assert_eq!(test.bound(), 2.0);
        // A floor above the relative bound takes over.
        test.observe_stiffness(4.0 / (FLOOR_FACTOR * f64::EPSILON));
        assert_eq!(test.bound(), 4.0);
        assert!(test.accepts(4.0) && !test.accepts(4.5));
    }

    #[test]
    fn absolute_tolerance_ignores_loads_and_floor_and_is_strict() {
        let mut test = ConvergenceTest::new(Tolerance::Absolute(1e-7), 1e6, 1e6, 1.0);
        test.observe_stiffness(1e30);
        assert_eq!(test.bound(), 1e-7);
        assert!(test.accepts(0.99e-7) && !test.accepts(1e-7));
        assert!(!test.stagnated(&[1.0; 10], Some(0.0), true));
    }

    #[test]
    fn stagnation_needs_no_progress_and_a_round_off_decrement() {
        let test = ConvergenceTest::new(Tolerance::Relative(1e-6), 1.0, 1.0, 1.0);
        let tiny = f64::EPSILON;
        // Progress in the last three iterations: not stagnated.
        assert!(!test.stagnated(&[1.0, 1e-3, 1e-5, 2e-6, 1.5e-6, 1e-6 * 1.2], Some(tiny), false));
        // The best residual of the last three is above half the best before them: stagnated.
        let flat = [1.0, 1e-3, 2e-6, 1.9e-6, 2.1e-6, 1.95e-6];
        assert!(test.stagnated(&flat, Some(tiny), false));
        // But not with a decrement above the energy's round-off, nor without one.
        assert!(!test.stagnated(&flat, Some(1e-6), false));
        assert!(!test.stagnated(&flat, None, false));
        // A line search that cannot move counts as no progress.
        assert!(test.stagnated(&[1.0, 2e-6], Some(tiny), true));
    }

    #[test]
    fn a_prediction_s_energy_does_not_set_the_round_off_of_the_iterates() {
        // A prediction far from the solution (energy 1e9) from a start of energy 1: once the iterates
        // are back at energies of order one, a decrement of 1e-9 is far above their energy's
        // round-off, and the solve has not stagnated.
        let flat = [1e3, 2e-3, 1.9e-3, 2.1e-3, 1.95e-3];
        let mut test = ConvergenceTest::with_measured_scale(Tolerance::Relative(1e-6), 1.0, 1.0, 1e9);
        assert!(
            test.stagnated(&flat, Some(1e-9), false),
            "at the prediction the energy is 1e9"
        );
        test.observe_energy(2.0);
        assert!(!test.stagnated(&flat, Some(1e-9), false));
        // Nor does the energy scale fall below the start's.
        test.observe_energy(1e-30);
        assert!(test.stagnated(&flat, Some(f64::EPSILON), false));
    }
}
