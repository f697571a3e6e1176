//! The settings of Newton's method and their validation.

use super::convergence::Tolerance;
use crate::error::{NewtonError, SettingName};
use crate::linear::{CgForcing, LinearSolverSettings};

/// What Newton's method does when the Hessian is not positive definite (with the default
/// [`LinearSolverKind::Auto`](crate::LinearSolverKind::Auto); an explicitly chosen factorisation is
/// always used as it is).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum IndefiniteHessian {
    /// The factorisation of `H` itself first (as [`Factorise`](Self::Factorise)) while its steps pass
    /// the line search in full and reduce the residual; once a step along such a direction ascends,
    /// is shortened or rejected by the line search, or does not reduce the residual, the rest of the
    /// solve shifts (as [`Shift`](Self::Shift)), and an ascending or rejected step is retried at once
    /// with the shift. Near a solution whose Hessian is indefinite (a twisted strip's
    /// massless rotations at a saddle of their energy) Newton's own steps converge quadratically, while
    /// a shifted descent cannot settle there; far from a solution (a coiling snap) the shift's
    /// trust-region steps get through where the unshifted direction stalls.
    Adaptive,
    /// A Levenberg-style shift: Cholesky of `H + μ D` with `D` the absolute diagonal of `H` and the
    /// smallest `μ` (grown by factors of 4 from a quarter of the previous solve's) that makes it
    /// positive definite. The step is then a descent direction that turns from Newton's towards the
    /// scaled gradient as the curvature gets more negative, the behaviour of a trust region. Default:
    /// the most robust through snaps (docs/stability.md), but it cannot settle on a solution that is
    /// a saddle of the energy.
    #[default]
    Shift,
    /// The symmetric indefinite factorisation (then LU) of `H` itself, with the direction negated when
    /// it ascends (the reference code's behaviour).
    Factorise,
}

/// Settings of Newton's method. Defaults are those of the paper's shell scenes (model.md §7.3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonSettings {
    /// Convergence test on the residual `max_i |∂Π/∂x_i| / residual_scale` over free unknowns (default
    /// [`Tolerance::Relative`] with [`Tolerance::DEFAULT_RELATIVE`]: relative to the problem's loads,
    /// never below the residual's round-off floor; see [`Tolerance`]).
    pub tolerance: Tolerance,
    /// Divisor turning gradient entries into the residual (default 1). When the unknowns are
    /// velocities and `Π` is the incremental potential of a step of length `Δt`, `∂Π/∂v = Δt · f`, so
    /// `residual_scale = Δt` (in s) makes the residual a force in N for velocity unknowns and a torque
    /// in N·m for angular-velocity unknowns, compared with one common tolerance.
    pub residual_scale: f64,
    /// Maximum number of Newton iterations (linear solves), default 100.
    pub max_iterations: usize,
    /// Minimum number of Newton iterations before convergence may be declared, default 0. A good initial
    /// guess can already satisfy the tolerance; one iteration then still
    /// adds the step's linear response (the time stepper uses 1, so small but growing forces — an
    /// unstable mode — are always integrated). At an exactly stationary point (every free gradient entry
    /// zero) that response is zero: such an iteration takes the zero step and converges.
    pub min_iterations: usize,
    /// Reuse the last factorisation (a chord step: gradient only, no Hessian assembly or numeric
    /// factorisation) while Newton converges fast: after a full step that cut the residual to below
    /// `reuse_max_ratio` times its previous value. A chord step that makes slower progress turns reuse
    /// off until the next factorisation, and one whose direction does not descend is replaced by a
    /// fresh Newton step at the same point. Factors that still gave fast progress when a solve
    /// converged start the next solve (the next time step) with a chord step, unless the fixed unknowns
    /// changed. The converged states satisfy the same tolerance as without reuse; only the path there
    /// differs. Off by default (`None`); on large systems, where the factorisation dominates,
    /// `Some(0.1)` trades a few cheap iterations for fewer factorisations. The factors are not part of
    /// a checkpoint: a resumed run starts with a fresh factorisation.
    /// Ignored with [`LinearSolverKind::Cg`](crate::LinearSolverKind::Cg), which has no factors to reuse.
    pub reuse_max_ratio: Option<f64>,
    /// Maximum number of step reductions in one line search, default 20.
    pub max_line_search_iterations: usize,
    /// Armijo constant `c` of the sufficient-decrease test `ΔΠ ≤ c α dx·∇Π` (default 1e-4).
    pub armijo_constant: f64,
    /// Factor by which the line search shortens the step (default 0.5).
    pub backtracking_factor: f64,
    /// Use the noise-resistant line search of Longva et al. 2023 (default on): when the Armijo test
    /// fails but `|ΔΠ| ≤ 0.1 |Π₀|`, estimate `ΔΠ` from gradients and accept if the estimate plus its
    /// error bound passes the test.
    pub noise_resistant_line_search: bool,
    /// Negate the Newton direction when it is not a descent direction (default on); otherwise fail with
    /// [`NewtonError::NotDescent`].
    pub flip_on_non_descent: bool,
    /// What to do with a Hessian that is not positive definite (default [`IndefiniteHessian::Shift`]).
    pub indefinite_hessian: IndefiniteHessian,
    /// Smallest accepted fraction of the Newton step when the problem limits it or rejects states
    /// (default 0.01); below it the iteration fails with [`NewtonError::InfeasibleStep`].
    pub min_step_fraction: f64,
    /// The mixed-integration-point (MIP) Newton method of Magisano, Leonetti and Garcea (2017)
    /// (default off). The second-order (geometric) terms of each Hessian are weighted with the stresses
    /// of strains predicted linearly along the previous steps, `s_k + α (∂s/∂x)(x_k) dx_k`, instead of
    /// the stresses at the iterate; energy, gradient and convergence test are unchanged, so it converges
    /// to the same solutions. In thin shells a step's second-order strain error (spurious stretching
    /// after a large rotation) carries membrane stresses far above the bending stresses, and the
    /// ordinary Hessian then predicts the next step poorly; the predicted stresses leave that error
    /// out. For a problem that predicts them ([`NewtonProblem::predicts_strains`](crate::NewtonProblem::predicts_strains)),
    /// the full step of a positive definite matrix is taken even where it raises the energy (a relaxed
    /// step): the stretch that raises it is what the next step removes, where a line search would cut
    /// the step and crawl. The steps after it are searched as usual; unless each cuts the energy's excess
    /// over the relaxed step's start fourfold until it falls below, within eight steps, they are undone
    /// (see the `relaxed` module). See
    /// [`NewtonProblem::linearize_strains`](crate::NewtonProblem::linearize_strains).
    pub mixed_integration_points: bool,
    /// The sparse linear solver (default: `Auto`, AMD ordering, sequential).
    pub linear_solver: LinearSolverSettings,
    /// With [`LinearSolverKind::Cg`](crate::LinearSolverKind::Cg): how the relative CG tolerance of each Newton step is chosen
    /// (default [`CgForcing::Reference`], `η = min(0.1, ‖g‖ · min(0.5, √‖g‖))` with `‖g‖` the 2-norm of
    /// the gradient over free unknowns divided by `residual_scale`). It overrides
    /// `linear_solver.cg.relative_tolerance` before every solve; the iteration cap stays
    /// `linear_solver.cg.max_iterations` (default `max(1000, n)`). Ignored by the factorisations.
    pub cg_forcing: CgForcing,
}

impl Default for NewtonSettings {
    fn default() -> Self {
        Self {
            tolerance: Tolerance::default(),
            residual_scale: 1.0,
            max_iterations: 100,
            min_iterations: 0,
            reuse_max_ratio: None,
            max_line_search_iterations: 20,
            armijo_constant: 1e-4,
            backtracking_factor: 0.5,
            noise_resistant_line_search: true,
            flip_on_non_descent: true,
            indefinite_hessian: IndefiniteHessian::default(),
            min_step_fraction: 0.01,
            mixed_integration_points: false,
            linear_solver: LinearSolverSettings::default(),
            cg_forcing: CgForcing::Reference,
        }
    }
}

impl NewtonSettings {
    /// Checks the ranges of the numerical settings.
    ///
    /// # Errors
    /// [`NewtonError::InvalidSetting`] naming the first setting out of range.
    pub fn validate(&self) -> Result<(), NewtonError> {
        let positive = |v: f64| v.is_finite() && v > 0.0;
        let open_unit = |v: f64| v > 0.0 && v < 1.0;
        let checks = [
            (
                SettingName::ResidualTolerance,
                self.tolerance.value(),
                positive(self.tolerance.value())
                    && !(matches!(self.tolerance, Tolerance::Relative(_)) && self.tolerance.value() >= 1.0),
            ),
            (
                SettingName::ResidualScale,
                self.residual_scale,
                positive(self.residual_scale),
            ),
            (
                SettingName::ArmijoConstant,
                self.armijo_constant,
                open_unit(self.armijo_constant),
            ),
            (
                SettingName::BacktrackingFactor,
                self.backtracking_factor,
                open_unit(self.backtracking_factor),
            ),
            (
                SettingName::MinStepFraction,
                self.min_step_fraction,
                self.min_step_fraction > 0.0 && self.min_step_fraction <= 1.0,
            ),
            (
                SettingName::MaxBackwardError,
                self.linear_solver.max_backward_error,
                self.linear_solver.max_backward_error > 0.0,
            ),
            (
                SettingName::CgRelativeTolerance,
                self.linear_solver.cg.relative_tolerance,
                open_unit(self.linear_solver.cg.relative_tolerance),
            ),
            (
                SettingName::CgMaxIterations,
                0.0,
                self.linear_solver.cg.max_iterations != Some(0),
            ),
            match self.cg_forcing {
                CgForcing::Fixed(eta) => (SettingName::CgForcing, eta, open_unit(eta)),
                CgForcing::Reference => (SettingName::CgForcing, 0.0, true),
            },
        ];
        match checks.into_iter().find(|c| !c.2) {
            Some((name, value, _)) => Err(NewtonError::InvalidSetting { name, value }),
            None => Ok(()),
        }
    }
}
