//! The interface between Newton's method and whatever it minimises.
//!
//! [`NewtonProblem`] is defined here, in the solver crate, rather than taken from the assembly layer:
//! Newton's method only needs an energy, its gradient and its Hessian on a fixed sparsity pattern. That
//! keeps the solver testable on toy problems (a quadratic, Rosenbrock, a spring chain) without any
//! mesh, and lets the time stepper wrap the incremental potential in a thin adapter.

use faer::sparse::SymbolicSparseColMatRef;

use crate::error::ProblemError;

/// A smooth minimisation problem `min Π(x)` over `x ∈ ℝⁿ` with a sparse symmetric Hessian.
///
/// All buffers passed to the methods have length [`n_dofs`](Self::n_dofs) (states, gradients) or the
/// number of stored entries of [`hessian_pattern`](Self::hessian_pattern) (Hessian values). The
/// solver zeroes the output buffers before each call, so implementations may accumulate into them.
///
/// Errors: return [`ProblemError::InvalidState`] for a state outside the problem's domain (the solver
/// then shortens the step) and [`ProblemError::NonFiniteEnergy`] when a part of the energy cannot be
/// evaluated. NaN or infinite values returned through `Ok` are detected by the solver and reported as
/// [`NewtonError::NonFinite`](crate::NewtonError::NonFinite); they are never accepted.
pub trait NewtonProblem {
    /// Number of unknowns `n`.
    fn n_dofs(&self) -> usize;

    /// The sparsity pattern of the Hessian: the upper triangle including the full diagonal, in
    /// compressed sparse column form, `n × n`. It must stay the same for the lifetime of a solver built
    /// for the problem.
    fn hessian_pattern(&self) -> SymbolicSparseColMatRef<'_, usize>;

    /// The energy `Π(x)` alone, used by the line search.
    ///
    /// # Errors
    /// A [`ProblemError`] if the state is invalid or the energy cannot be evaluated.
    fn value(&mut self, x: &[f64]) -> Result<f64, ProblemError>;

    /// The energy `Π(x)`, returned, and its gradient `∇Π(x)`, written into `grad`.
    ///
    /// # Errors
    /// A [`ProblemError`] if the state is invalid or the energy cannot be evaluated.
    fn gradient(&mut self, x: &[f64], grad: &mut [f64]) -> Result<f64, ProblemError>;

    /// The energy `Π(x)`, returned, its gradient, written into `grad`, and the values of the Hessian's
    /// upper triangle in the order of [`hessian_pattern`](Self::hessian_pattern), written into
    /// `hess_values`.
    ///
    /// # Errors
    /// A [`ProblemError`] if the state is invalid or the energy cannot be evaluated.
    fn hessian(&mut self, x: &[f64], grad: &mut [f64], hess_values: &mut [f64]) -> Result<f64, ProblemError>;

    /// A mask of unknowns that are eliminated exactly (`true` = fixed). Their Newton step is zero, they
    /// keep their current values, and their gradient entries (reaction forces) do not count towards
    /// the residual. `None` (the default) fixes nothing.
    fn fixed_dofs(&self) -> Option<&[bool]> {
        None
    }

    /// The largest fraction `α ∈ (0, 1]` of the step `dx` from `x` that keeps the state feasible, for
    /// example from continuous collision detection. The default allows the full step.
    fn max_step_fraction(&mut self, x: &[f64], dx: &[f64]) -> f64 {
        let _ = (x, dx);
        1.0
    }

    /// Whether [`linearize_strains`](Self::linearize_strains) predicts stresses for the Hessians' second-order
    /// terms: only then does [`NewtonSettings::mixed_integration_points`](crate::NewtonSettings::mixed_integration_points)
    /// take full steps that raise the energy (relaxed steps). The default predicts nothing.
    fn predicts_strains(&self) -> bool {
        false
    }

    /// With [`NewtonSettings::mixed_integration_points`](crate::NewtonSettings::mixed_integration_points):
    /// called with each Newton direction `dx` from the iterate `x`, before its line search. A problem
    /// whose Hessian has second-order terms weighted by stresses linearises its strains there (see
    /// [`advance_predicted_strains`](Self::advance_predicted_strains)). The default does nothing.
    ///
    /// # Errors
    /// A [`ProblemError`] if the state cannot be evaluated.
    fn linearize_strains(&mut self, x: &[f64], dx: &[f64]) -> Result<(), ProblemError> {
        let _ = (x, dx);
        Ok(())
    }

    /// With [`NewtonSettings::mixed_integration_points`](crate::NewtonSettings::mixed_integration_points):
    /// the step `α dx` along the last linearised direction was accepted. Until the next solve, the
    /// Hessians weight their second-order terms with the stresses of the strains predicted linearly
    /// along the steps (the mixed-integration-point iteration matrix of Magisano, Leonetti and Garcea
    /// 2017), while energy and gradient stay those of `x`. The default does nothing.
    fn advance_predicted_strains(&mut self, alpha: f64) {
        let _ = alpha;
    }

    /// Called at the start of every solve: the Hessians use the stresses of the current state again.
    /// The default does nothing.
    fn clear_predicted_strains(&mut self) {}

    /// Re-expresses the accepted iterate `x` in unknowns of the same state that lie farther from a
    /// singularity of the parametrisation (for example rotation updates rebased at the rotations they
    /// reached). The energy is unchanged; its gradient and Hessian are those of the new unknowns, which
    /// Newton's method evaluates next. Returns whether `x` changed. The default changes nothing.
    fn rebase(&mut self, x: &mut [f64]) -> bool {
        let _ = x;
        false
    }

    /// Lets a problem whose energy holds parameters fixed within a solve adapt them to the accepted
    /// iterate `x` (for example a shell's stabilisation, raised where the iterate stretches the sheet
    /// beyond what the start of the step holds). Returns whether the energy changed; Newton's method
    /// then evaluates `x` anew, and its residual history continues from there. It is also called with
    /// the solve's starting point (a prediction), before anything is evaluated. The changes must settle
    /// as the iterates converge (parameters that change only when the iterate has moved them by a
    /// factor, say), or the solve runs to its iteration limit. The default changes nothing.
    fn follow_iterate(&mut self, x: &[f64]) -> bool {
        let _ = x;
        false
    }

    /// The solve failed: undoes what [`rebase`](Self::rebase) and [`follow_iterate`](Self::follow_iterate)
    /// changed outside the unknowns. The default does nothing.
    fn abandon_solve(&mut self) {}

    /// Moves unknowns of a trial state `x`, reached from the iterate `from`, that run towards a
    /// singularity of the problem's parametrisation across it, to where the descent can continue (for
    /// example a rotation update whose parameter grows without bound as the rotation approaches a half
    /// turn). Newton's method calls it on every trial state before evaluating it; the line search then
    /// judges the moved state by its energy like any other. The default moves nothing.
    fn cross_singularities(&self, from: &[f64], x: &mut [f64]) {
        let _ = (from, x);
    }

    /// The size of the external loads in the units of the gradient (for example the largest nodal force
    /// times the time step), the scale of a [relative tolerance](crate::Tolerance::Relative). The
    /// default, 0, leaves the scale to the reactions of fixed unknowns and the first residual.
    fn load_scale(&self) -> f64 {
        0.0
    }

    /// Writes into `w` a weight per unknown that brings every gradient entry to one unit, for the
    /// [relative tolerance](crate::Tolerance::Relative): the residual, the loads, the reactions and the
    /// round-off floor are all compared as `w_i |∂Π/∂x_i|`. Without weights, a problem whose gradient
    /// holds forces and torques would mix newtons with newton-metres in one maximum, and the same
    /// dimensionless problem would converge differently in other units of length; a weight of one over
    /// a length turns a torque into a force. [`load_scale`](Self::load_scale) is in the weighted unit.
    /// The default weighs every entry 1 (a gradient in one unit).
    fn residual_weights(&self, w: &mut [f64]) {
        w.fill(1.0);
    }

    /// Writes into `m` the magnitude of the coordinate behind each unknown, in the unknown's units, for
    /// the round-off floor of the residual (`ε Σ_j |H_ij| m_j`, see [`Tolerance`](crate::Tolerance)).
    /// When the unknowns are increments of a state (velocities of positions), the round-off is that of
    /// the state: a velocity unknown's magnitude is its node's distance from the origin over `Δt`. The
    /// default takes the unknowns themselves, `m_j = |x_j|`.
    fn unknown_magnitudes(&self, x: &[f64], m: &mut [f64]) {
        for (m, x) in m.iter_mut().zip(x) {
            *m = x.abs();
        }
    }
}
