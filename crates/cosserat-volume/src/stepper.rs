//! Time stepping of an incremental potential with the Newton-CG solver: one solve per step, the step
//! halved and retried on failure, the state committed only from a converged solution.
//!
//! This mirrors `cosserat_solver::TimeStepper` (same order of operations, scripts re-run for every
//! attempt, previous velocities as the initial guess) with [`CgNewtonSolver`] in place of the direct
//! Newton solver.

use crate::error::CgNewtonError;
use crate::newton_cg::{CgNewtonReport, CgNewtonSettings, CgNewtonSolver};
use cosserat_assembly::IncrementalPotential;
use cosserat_solver::InitialGuess;
use cosserat_solver::potential_problem::PotentialProblem;
use thiserror::Error;

/// Settings of [`CgTimeStepper`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CgTimeStepSettings {
    /// The time step \[s\].
    pub dt: f64,
    /// Smallest time step tried after halvings \[s\].
    pub min_dt: f64,
    /// Maximum number of halvings of one step.
    pub max_reductions: usize,
    /// Newton-CG settings (the residual scale is set to the attempt's `Δt`).
    pub newton: CgNewtonSettings,
    /// Newton's starting point.
    pub initial_guess: InitialGuess,
}

impl CgTimeStepSettings {
    /// A fixed step `dt` with up to 8 halvings, at least one Newton iteration per step and the previous
    /// velocities as the initial guess (as `cosserat_solver::TimeStepSettings::fixed`).
    pub fn fixed(dt: f64) -> Self {
        Self {
            dt,
            min_dt: 1e-6,
            max_reductions: 8,
            newton: CgNewtonSettings {
                min_iterations: 1,
                ..CgNewtonSettings::default()
            },
            initial_guess: InitialGuess::PreviousVelocity,
        }
    }
}

/// A completed step.
#[derive(Debug, Clone)]
pub struct CgStepReport {
    /// Time at the end of the step \[s\].
    pub t: f64,
    /// The time step that succeeded \[s\].
    pub dt: f64,
    /// Newton-CG's report of the successful attempt.
    pub newton: CgNewtonReport,
    /// Failed attempts before it.
    pub reductions: usize,
}

/// A step that failed at every allowed time step; the potential's state is unchanged.
#[derive(Debug, Clone, Error)]
#[error("Newton-CG time step from t = {t} failed after {} attempt(s); last: {}", attempts.len(), attempts.last().map_or_else(String::new, |a| format!("dt = {}: {}", a.0, a.1)))]
pub struct CgStepError {
    /// Start time of the step \[s\].
    pub t: f64,
    /// Every attempt's time step and error, in order.
    pub attempts: Vec<(f64, CgNewtonError)>,
}

/// Advances an incremental potential in time with Newton-CG.
#[derive(Debug)]
pub struct CgTimeStepper {
    solver: CgNewtonSolver,
    settings: CgTimeStepSettings,
    t: f64,
    u: Vec<f64>,
}

impl CgTimeStepper {
    /// A stepper for `potential`, starting at `t = 0`.
    ///
    /// # Errors
    /// Invalid Newton-CG settings.
    pub fn new(potential: &mut IncrementalPotential, settings: CgTimeStepSettings) -> Result<Self, CgNewtonError> {
        let mut newton = settings.newton;
        newton.residual_scale = settings.dt;
        let n = potential.n_dofs();
        let solver = CgNewtonSolver::for_problem(&PotentialProblem::new(potential, None), newton)?;
        Ok(Self {
            solver,
            settings,
            t: 0.0,
            u: vec![0.0; n],
        })
    }

    /// The current time \[s\].
    pub fn time(&self) -> f64 {
        self.t
    }

    /// Performs one step. `scripts(potential, t, dt)` runs before every attempt with the attempt's
    /// start time and time step.
    ///
    /// # Errors
    /// [`CgStepError`] when every allowed attempt failed; nothing is committed then.
    pub fn step(
        &mut self,
        potential: &mut IncrementalPotential,
        scripts: &mut dyn FnMut(&mut IncrementalPotential, f64, f64),
    ) -> Result<CgStepReport, CgStepError> {
        let mut attempts = Vec::new();
        let mut dt = self.settings.dt;
        loop {
            potential.dt = dt;
            scripts(potential, self.t, dt);
            self.solver.settings_mut().residual_scale = dt;
            self.initial_guess(potential);
            // Terms with their own pattern (contact) may grow it; the solver copies the pattern.
            if potential.begin_step(&self.u) {
                let settings = *self.solver.settings();
                match CgNewtonSolver::for_problem(&PotentialProblem::new(potential, None), settings) {
                    Ok(solver) => self.solver = solver,
                    Err(error) => {
                        attempts.push((dt, error));
                        return Err(CgStepError { t: self.t, attempts });
                    }
                }
            }
            let fixed = potential.fixed_dofs().map(|(mask, values)| {
                for (i, _) in mask.iter().enumerate().filter(|(_, m)| **m) {
                    self.u[i] = values[i];
                }
                mask
            });
            let result = {
                let mut problem = PotentialProblem::new(potential, fixed);
                self.solver.solve(&mut problem, &mut self.u)
            };
            match result {
                Ok(newton) => {
                    potential.commit(&self.u);
                    self.t += dt;
                    return Ok(CgStepReport {
                        t: self.t,
                        dt,
                        newton,
                        reductions: attempts.len(),
                    });
                }
                Err(error) => {
                    attempts.push((dt, error));
                    let next = 0.5 * dt;
                    if attempts.len() > self.settings.max_reductions || next < self.settings.min_dt {
                        return Err(CgStepError { t: self.t, attempts });
                    }
                    dt = next;
                }
            }
        }
    }

    fn initial_guess(&mut self, potential: &IncrementalPotential) {
        match self.settings.initial_guess {
            InitialGuess::Zero => self.u.fill(0.0),
            InitialGuess::PreviousVelocity => {
                let st = &potential.parts.state;
                let layout = &potential.parts.layout;
                for (i, v) in st.v.iter().enumerate() {
                    let b = 3 * layout.disp_block(i);
                    self.u[b..b + 3].copy_from_slice(v.as_slice());
                }
                for (k, w) in st.omega.iter().enumerate() {
                    let b = 3 * layout.rot_block(k);
                    self.u[b..b + 3].copy_from_slice(w.as_slice());
                }
            }
        }
    }
}
