//! An inexact Newton method whose steps come from block-Jacobi preconditioned conjugate gradients, for
//! any [`NewtonProblem`] (in particular the incremental potential through
//! [`cosserat_solver::potential_problem::PotentialProblem`]).
//!
//! `cosserat-solver`'s [`NewtonSolver`](cosserat_solver::NewtonSolver) is built around a sparse
//! factorisation; this loop keeps its contract (the same problem trait, fixed unknowns, feasible step
//! fractions, residual `max_i |∂Π/∂x_i| / residual_scale` over free unknowns, convergence tested wherever
//! the gradient of an accepted iterate is known) and replaces the factorisation by [`pcg`] with the
//! reference's forcing sequence: the CG system is solved to the relative residual
//! `η = min(0.1, ‖g‖ min(0.5, √‖g‖))`, with `‖g‖` the Euclidean norm of the scaled gradient, so far from
//! the solution a few CG iterations suffice and near it the steps become exact Newton steps
//! (superlinear convergence). The line search is backtracking Armijo.

use crate::error::{CgError, CgNewtonError, CgNewtonSetting};
use crate::pcg::{BlockJacobi, CgSettings, CgWorkspace, SymmetricUpper, pcg};
use cosserat_solver::{NewtonProblem, ProblemError};
use faer::sparse::SymbolicSparseColMat;
use std::time::Instant;

/// How the CG tolerance of each Newton step is chosen.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum ForcingTerm {
    /// The reference's sequence `η = min(0.1, ‖g‖ min(0.5, √‖g‖))` (relative CG residual), with `‖g‖`
    /// the Euclidean norm of the gradient over free unknowns divided by the residual scale. Default.
    #[default]
    Reference,
    /// A fixed relative CG residual in (0, 1).
    Fixed(f64),
}

impl ForcingTerm {
    /// The relative CG tolerance for a scaled gradient norm.
    pub fn tolerance(&self, gradient_norm: f64) -> f64 {
        match *self {
            ForcingTerm::Reference => 0.1f64.min(gradient_norm * 0.5f64.min(gradient_norm.sqrt())),
            ForcingTerm::Fixed(eta) => eta,
        }
    }
}

/// Settings of [`CgNewtonSolver`]. The Newton defaults are those of `cosserat_solver::NewtonSettings`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CgNewtonSettings {
    /// Convergence tolerance on `max_i |∂Π/∂x_i| / residual_scale` over free unknowns (default 1e-7).
    pub residual_tolerance: f64,
    /// Divisor turning gradient entries into the residual (default 1; `Δt` makes it a force in N for an
    /// incremental potential in velocities).
    pub residual_scale: f64,
    /// Maximum number of Newton iterations (default 100).
    pub max_iterations: usize,
    /// Minimum number of Newton iterations before convergence may be declared (default 0).
    pub min_iterations: usize,
    /// Maximum number of step reductions in one line search (default 20).
    pub max_line_search_iterations: usize,
    /// Armijo constant `c` of `ΔΠ ≤ c α dx·∇Π` (default 1e-4).
    pub armijo_constant: f64,
    /// Step reduction factor of the line search (default 0.5).
    pub backtracking_factor: f64,
    /// Negate a direction that does not descend (default on); otherwise fail.
    pub flip_on_non_descent: bool,
    /// The CG forcing sequence (default [`ForcingTerm::Reference`]).
    pub forcing: ForcingTerm,
    /// CG iterations per solve: at most `max(cg_min_cap, cg_iterations_per_dof · n)` (defaults 1000 and
    /// 1, the reference's `max(1000, n)`).
    pub cg_min_cap: usize,
    /// See `cg_min_cap`.
    pub cg_iterations_per_dof: f64,
}

impl Default for CgNewtonSettings {
    fn default() -> Self {
        Self {
            residual_tolerance: 1e-7,
            residual_scale: 1.0,
            max_iterations: 100,
            min_iterations: 0,
            max_line_search_iterations: 20,
            armijo_constant: 1e-4,
            backtracking_factor: 0.5,
            flip_on_non_descent: true,
            forcing: ForcingTerm::Reference,
            cg_min_cap: 1000,
            cg_iterations_per_dof: 1.0,
        }
    }
}

impl CgNewtonSettings {
    /// Checks the ranges of the numerical settings.
    ///
    /// # Errors
    /// [`CgNewtonError::InvalidSetting`] naming the first setting out of range.
    pub fn validate(&self) -> Result<(), CgNewtonError> {
        let positive = |v: f64| v.is_finite() && v > 0.0;
        let open_unit = |v: f64| v > 0.0 && v < 1.0;
        let forcing = match self.forcing {
            ForcingTerm::Reference => 0.5,
            ForcingTerm::Fixed(eta) => eta,
        };
        let checks = [
            (
                CgNewtonSetting::ResidualTolerance,
                self.residual_tolerance,
                positive(self.residual_tolerance),
            ),
            (
                CgNewtonSetting::ResidualScale,
                self.residual_scale,
                positive(self.residual_scale),
            ),
            (
                CgNewtonSetting::ArmijoConstant,
                self.armijo_constant,
                open_unit(self.armijo_constant),
            ),
            (
                CgNewtonSetting::BacktrackingFactor,
                self.backtracking_factor,
                open_unit(self.backtracking_factor),
            ),
            (CgNewtonSetting::Forcing, forcing, open_unit(forcing)),
        ];
        match checks.into_iter().find(|c| !c.2) {
            Some((name, value, _)) => Err(CgNewtonError::InvalidSetting { name, value }),
            None => Ok(()),
        }
    }
}

/// The outcome of a converged Newton-CG solve.
#[derive(Debug, Clone, PartialEq)]
pub struct CgNewtonReport {
    /// Newton iterations (CG solves whose step was taken).
    pub iterations: usize,
    /// Residual history: `residuals[0]` at the initial state.
    pub residuals: Vec<f64>,
    /// The energy at the solution.
    pub energy: f64,
    /// CG iterations of each Newton iteration.
    pub cg_iterations: Vec<usize>,
    /// CG solves stopped by the iteration cap before reaching their tolerance.
    pub truncated_solves: usize,
    /// CG solves stopped by non-positive curvature.
    pub negative_curvature_solves: usize,
    /// Directions negated because they did not descend.
    pub direction_flips: usize,
    /// Step reductions in all line searches (feasibility halvings included).
    pub line_search_backtracks: usize,
    /// Wall-clock seconds in Hessian assembly.
    pub assembly_seconds: f64,
    /// Wall-clock seconds in energy and gradient evaluations.
    pub evaluation_seconds: f64,
    /// Wall-clock seconds in CG (preconditioner set-up included).
    pub linear_solve_seconds: f64,
}

impl CgNewtonReport {
    /// The final residual.
    pub fn residual(&self) -> f64 {
        self.residuals.last().copied().unwrap_or(f64::NAN)
    }

    /// All CG iterations of the solve.
    pub fn total_cg_iterations(&self) -> usize {
        self.cg_iterations.iter().sum()
    }
}

/// Newton's method with conjugate-gradient steps, owning every buffer of one problem size.
#[derive(Debug)]
pub struct CgNewtonSolver {
    settings: CgNewtonSettings,
    pattern: SymbolicSparseColMat<usize>,
    grad: Vec<f64>,
    hess: Vec<f64>,
    masked: Vec<f64>,
    rhs: Vec<f64>,
    dx: Vec<f64>,
    x_trial: Vec<f64>,
    fixed: Vec<bool>,
    workspace: CgWorkspace,
}

/// Counters of one solve.
struct Run {
    residuals: Vec<f64>,
    report: CgNewtonReport,
}

impl CgNewtonSolver {
    /// A solver for `problem`'s size and Hessian pattern.
    ///
    /// # Errors
    /// [`CgNewtonError::InvalidSetting`] or [`CgNewtonError::DimensionMismatch`].
    pub fn for_problem<P: NewtonProblem + ?Sized>(
        problem: &P,
        settings: CgNewtonSettings,
    ) -> Result<Self, CgNewtonError> {
        settings.validate()?;
        let pattern = problem.hessian_pattern();
        let n = problem.n_dofs();
        if pattern.ncols() != n || pattern.nrows() != n {
            return Err(CgNewtonError::DimensionMismatch {
                pattern: pattern.ncols(),
                problem: n,
            });
        }
        let pattern = SymbolicSparseColMat::new_checked(
            n,
            n,
            pattern.col_ptr().to_vec(),
            None,
            pattern.row_idx()[..pattern.col_ptr()[n]].to_vec(),
        );
        let nnz = pattern.row_idx().len();
        Ok(Self {
            settings,
            pattern,
            grad: vec![0.0; n],
            hess: vec![0.0; nnz],
            masked: vec![0.0; nnz],
            rhs: vec![0.0; n],
            dx: vec![0.0; n],
            x_trial: vec![0.0; n],
            fixed: vec![false; n],
            workspace: CgWorkspace::default(),
        })
    }

    /// The settings.
    pub fn settings(&self) -> &CgNewtonSettings {
        &self.settings
    }

    /// Mutable settings (validated at the next solve).
    pub fn settings_mut(&mut self) -> &mut CgNewtonSettings {
        &mut self.settings
    }

    fn residual(&self, grad: &[f64]) -> f64 {
        let mut r: f64 = 0.0;
        for (g, &f) in grad.iter().zip(&self.fixed) {
            if !f {
                r = r.max(g.abs());
            }
        }
        r / self.settings.residual_scale
    }

    /// Minimises `problem` from `x`, which holds the solution on success and the last accepted iterate
    /// on failure.
    ///
    /// # Errors
    /// A [`CgNewtonError`] with the residual history.
    ///
    /// # Panics
    /// If `x` has a length other than the problem's dimension.
    #[track_caller]
    pub fn solve<P: NewtonProblem + ?Sized>(
        &mut self,
        problem: &mut P,
        x: &mut [f64],
    ) -> Result<CgNewtonReport, CgNewtonError> {
        self.settings.validate()?;
        let n = self.grad.len();
        assert_eq!(x.len(), n, "state length differs from the problem dimension");
        if problem.n_dofs() != n {
            return Err(CgNewtonError::DimensionMismatch {
                pattern: n,
                problem: problem.n_dofs(),
            });
        }
        match problem.fixed_dofs() {
            Some(f) => self.fixed.copy_from_slice(f),
            None => self.fixed.fill(false),
        }
        let s = self.settings;
        let mut run = Run {
            residuals: Vec::new(),
            report: CgNewtonReport {
                iterations: 0,
                residuals: Vec::new(),
                energy: f64::NAN,
                cg_iterations: Vec::new(),
                truncated_solves: 0,
                negative_curvature_solves: 0,
                direction_flips: 0,
                line_search_backtracks: 0,
                assembly_seconds: 0.0,
                evaluation_seconds: 0.0,
                linear_solve_seconds: 0.0,
            },
        };
        // Whether `grad` holds ∇Π(x) and its residual is the last entry of the history.
        let mut grad_current = false;
        let mut energy;
        let mut k = 0;
        loop {
            let t = Instant::now();
            self.hess.fill(0.0);
            self.grad.fill(0.0);
            let e0 = problem.hessian(x, &mut self.grad, &mut self.hess);
            run.report.assembly_seconds += t.elapsed().as_secs_f64();
            energy = self.check_evaluation(e0, k, &mut run)?;
            let r = self.residual(&self.grad);
            if !grad_current {
                run.residuals.push(r);
                if r < s.residual_tolerance && k >= s.min_iterations {
                    return Ok(finish(run, k, energy));
                }
            }
            if r == 0.0 {
                // An exact stationary point: every free gradient entry vanishes, there is no direction.
                return Ok(finish(run, k, energy));
            }
            if k == s.max_iterations {
                return Err(CgNewtonError::MaxIterations {
                    iterations: k,
                    residuals: run.residuals,
                });
            }
            k += 1;
            let slope = self.direction(k, &mut run)?;

            // Full feasible step, with its gradient; halve while the state is invalid.
            let mut alpha = problem.max_step_fraction(x, &self.dx).clamp(0.0, 1.0);
            let mut backtracks = 0;
            let e1 = loop {
                self.set_trial(x, alpha);
                let t = Instant::now();
                self.grad.fill(0.0);
                let result = problem.gradient(&self.x_trial, &mut self.grad);
                run.report.evaluation_seconds += t.elapsed().as_secs_f64();
                match result {
                    Err(ProblemError::InvalidState { .. }) => {
                        alpha *= s.backtracking_factor;
                        backtracks += 1;
                        if backtracks > s.max_line_search_iterations {
                            return Err(CgNewtonError::LineSearchFailed {
                                iteration: k,
                                backtracks,
                                residuals: run.residuals,
                            });
                        }
                    }
                    other => break self.check_evaluation(other, k, &mut run)?,
                }
            };
            let r1 = self.residual(&self.grad);
            if r1 < s.residual_tolerance && k >= s.min_iterations {
                x.copy_from_slice(&self.x_trial);
                run.residuals.push(r1);
                run.report.line_search_backtracks += backtracks;
                return Ok(finish(run, k, e1));
            }
            let mut e_trial = e1;
            let mut gradient_at_trial = true;
            // A NaN energy fails the Armijo test.
            let armijo_passes = |e: f64, alpha: f64| e <= energy + s.armijo_constant * alpha * slope;
            while !armijo_passes(e_trial, alpha) {
                alpha *= s.backtracking_factor;
                backtracks += 1;
                if backtracks > s.max_line_search_iterations {
                    return Err(CgNewtonError::LineSearchFailed {
                        iteration: k,
                        backtracks,
                        residuals: run.residuals,
                    });
                }
                self.set_trial(x, alpha);
                let t = Instant::now();
                let result = problem.value(&self.x_trial);
                run.report.evaluation_seconds += t.elapsed().as_secs_f64();
                gradient_at_trial = false;
                e_trial = match result {
                    Err(ProblemError::InvalidState { .. }) => f64::INFINITY,
                    other => self.check_evaluation(other, k, &mut run)?,
                };
            }
            run.report.line_search_backtracks += backtracks;
            x.copy_from_slice(&self.x_trial);
            grad_current = gradient_at_trial;
            if grad_current {
                run.residuals.push(r1);
            }
        }
    }

    /// The CG direction into `dx` (zero on fixed unknowns) and its slope `dx · ∇Π`.
    fn direction(&mut self, k: usize, run: &mut Run) -> Result<f64, CgNewtonError> {
        let t = Instant::now();
        let col_ptr = self.pattern.col_ptr();
        let row_idx = self.pattern.row_idx();
        self.masked.copy_from_slice(&self.hess);
        if self.fixed.iter().any(|&f| f) {
            for col in 0..self.grad.len() {
                for idx in col_ptr[col]..col_ptr[col + 1] {
                    let row = row_idx[idx];
                    if self.fixed[row] || self.fixed[col] {
                        self.masked[idx] = if row == col { 1.0 } else { 0.0 };
                    }
                }
            }
        }
        let mut g_norm2 = 0.0;
        for i in 0..self.grad.len() {
            self.rhs[i] = if self.fixed[i] { 0.0 } else { -self.grad[i] };
            g_norm2 += self.rhs[i] * self.rhs[i];
        }
        let a = SymmetricUpper {
            pattern: self.pattern.as_ref(),
            values: &self.masked,
        };
        let m = BlockJacobi::new(&a);
        let n = self.grad.len();
        let cap = self
            .settings
            .cg_min_cap
            .max((self.settings.cg_iterations_per_dof * n as f64).ceil() as usize);
        let eta = self.settings.forcing.tolerance(g_norm2.sqrt() / self.settings.residual_scale);
        let settings = CgSettings {
            relative_tolerance: eta,
            max_iterations: cap,
        };
        self.dx.fill(0.0);
        let result = pcg(&a, &m, &self.rhs, &mut self.dx, &settings, &mut self.workspace);
        run.report.linear_solve_seconds += t.elapsed().as_secs_f64();
        let report = result.map_err(|source: CgError| CgNewtonError::Linear {
            iteration: k,
            source,
            residuals: run.residuals.clone(),
        })?;
        run.report.cg_iterations.push(report.iterations);
        if report.negative_curvature {
            run.report.negative_curvature_solves += 1;
        } else if !report.converged {
            run.report.truncated_solves += 1;
        }
        let mut slope: f64 = self.dx.iter().zip(&self.grad).map(|(d, g)| d * g).sum();
        let descends = slope < 0.0;
        if !descends {
            if self.settings.flip_on_non_descent && slope > 0.0 {
                self.dx.iter_mut().for_each(|d| *d = -*d);
                slope = -slope;
                run.report.direction_flips += 1;
            } else {
                return Err(CgNewtonError::NotDescent {
                    iteration: k,
                    residuals: run.residuals.clone(),
                });
            }
        }
        Ok(slope)
    }

    fn set_trial(&mut self, x: &[f64], alpha: f64) {
        for i in 0..x.len() {
            self.x_trial[i] = x[i] + alpha * self.dx[i];
        }
    }

    fn check_evaluation(
        &self,
        result: Result<f64, ProblemError>,
        iteration: usize,
        run: &mut Run,
    ) -> Result<f64, CgNewtonError> {
        match result {
            Err(source) => Err(CgNewtonError::Problem {
                iteration,
                source,
                residuals: std::mem::take(&mut run.residuals),
            }),
            Ok(e) if e.is_finite() && self.grad.iter().all(|g| g.is_finite()) => Ok(e),
            Ok(_) => Err(CgNewtonError::NonFinite {
                iteration,
                residuals: std::mem::take(&mut run.residuals),
            }),
        }
    }
}

fn finish(mut run: Run, iterations: usize, energy: f64) -> CgNewtonReport {
    run.report.iterations = iterations;
    run.report.energy = energy;
    run.report.residuals = run.residuals;
    run.report
}
