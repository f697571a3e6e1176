//! Time stepping: one Newton solve of the incremental potential per step (strong coupling of
//! displacements and rotations), with step-size reduction on failure.
//!
//! Order of operations per step (model.md §1.7): scripts set targets, loads and rest fields for the step
//! `tⁿ → tⁿ + Δt`; Newton minimises `Π(v, ω)`; on success the state is advanced (positions, velocities,
//! nodal and quadrature-point rotations) and `t` grows; on failure nothing is committed, `Δt` is halved
//! and the step is retried with the scripts re-run for the new `Δt`, up to a bounded number of times.
//! A state is only ever committed from a converged, finite solution.

use crate::error::{NewtonError, ScriptError};
use crate::linear::{DomainSplit, LinearSolverKind};
use crate::newton::{NewtonReport, NewtonSettings, NewtonSolver, SolveCost};
use crate::potential_problem::{SolveStart, begin_step, solve_in_domain};
use cosserat_assembly::IncrementalPotential;
use cosserat_geometry::Num;
use thiserror::Error;

/// Where Newton starts in each step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum InitialGuess {
    /// `v = 0`, `ω = 0`, as the reference code does.
    Zero,
    /// The previous step's velocities and angular velocities: the exact answer for steady motion.
    PreviousVelocity,
    /// The velocities extrapolated linearly in time from the last two steps, `vⁿ + Δt/Δtⁿ⁻¹ (vⁿ − vⁿ⁻¹)`
    /// (the previous velocities for a run's first step): the exact answer for uniformly accelerated
    /// motion, so a smooth step starts an order of `Δt` closer to its solution. Default.
    #[default]
    Extrapolated,
    /// Whichever of [`InitialGuess::Extrapolated`], [`InitialGuess::PreviousVelocity`] and
    /// [`InitialGuess::Zero`] has the least incremental potential. Near its minimiser the potential
    /// exceeds its minimum by half the squared distance in the Hessian's norm, so the least value is
    /// the start nearest the step's solution: the extrapolation in smooth motion, rest or the previous
    /// velocities where the extrapolation overshoots a motion that reverses from step to step. The
    /// comparison (up to three evaluations of the potential) is skipped after a step that started
    /// from the extrapolation and converged in one Newton iteration: the motion was smooth there, and
    /// the extrapolation is taken. Far from the solution the potential is not its quadratic model and
    /// its value is no distance: where steps bend a soft body far, the comparison can prefer a start
    /// from which Newton needs more iterations.
    LeastEnergy,
}

/// Settings of the time stepper.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeStepSettings {
    /// The (maximum) time step \[s\].
    pub dt: f64,
    /// Adaptive stepping: after a success `Δt ← min(dt, 1.05 Δt)`; without it, reduced steps stay
    /// reduced only for the retried step.
    pub adaptive: bool,
    /// Smallest allowed time step \[s\].
    pub min_dt: f64,
    /// Maximum number of halvings of one step before the run stops.
    pub max_reductions: usize,
    /// Growth factor after a successful step (adaptive only).
    pub growth: f64,
    /// Newton settings (the residual scale is set to `Δt` so the residual is a force in N / torque in
    /// N·m).
    pub newton: NewtonSettings,
    /// Newton's starting point.
    pub initial_guess: InitialGuess,
}

impl TimeStepSettings {
    /// Settings for a fixed time step `dt`, with up to 8 halvings on failure, at least one Newton
    /// iteration per step (a good initial guess alone could satisfy the tolerance and skip the step's
    /// response to small but growing forces) and the time step's relative tolerance
    /// ([`Tolerance::DEFAULT_RELATIVE_DYNAMIC`](crate::Tolerance::DEFAULT_RELATIVE_DYNAMIC)).
    pub fn fixed(dt: f64) -> Self {
        Self {
            dt,
            adaptive: false,
            min_dt: 1e-6,
            max_reductions: 8,
            growth: 1.05,
            newton: NewtonSettings {
                min_iterations: 1,
                tolerance: crate::Tolerance::Relative(crate::Tolerance::DEFAULT_RELATIVE_DYNAMIC),
                ..NewtonSettings::default()
            },
            initial_guess: InitialGuess::default(),
        }
    }
}

/// One failed Newton attempt of a step.
#[derive(Debug, Clone)]
pub struct FailedAttempt {
    /// The time step tried \[s\].
    pub dt: f64,
    /// Why Newton failed (with its residual history).
    pub error: NewtonError,
}

/// A step that could not be completed; the state is unchanged.
#[derive(Debug, Clone, Error)]
pub enum StepError {
    /// Newton failed in every allowed attempt (each halved `Δt`).
    #[error("time step from t = {} failed after {} attempt(s); last: dt = {}: {}", Num(*t), attempts.len(), Num(attempts.last().map_or(0.0, |a| a.dt)), attempts.last().map_or_else(String::new, |a| a.error.to_string()))]
    NotConverged {
        /// Start time of the step \[s\].
        t: f64,
        /// Every attempt, in order.
        attempts: Vec<FailedAttempt>,
    },
    /// The scripts could not prepare an attempt (e.g. a load scale that is not finite at its time):
    /// not Newton's failure, so no smaller step is tried.
    #[error("time step from t = {} (dt = {}): {source}", Num(*t), Num(*dt))]
    Scripts {
        /// Start time of the step \[s\].
        t: f64,
        /// The time step of the attempt the scripts failed for \[s\].
        dt: f64,
        /// The Newton attempts that failed before it.
        attempts: Vec<FailedAttempt>,
        /// What the scripts reported.
        source: ScriptError,
    },
}

impl StepError {
    /// Start time of the step \[s\].
    pub fn t(&self) -> f64 {
        match self {
            Self::NotConverged { t, .. } | Self::Scripts { t, .. } => *t,
        }
    }

    /// The failed Newton attempts, in order.
    pub fn attempts(&self) -> &[FailedAttempt] {
        match self {
            Self::NotConverged { attempts, .. } | Self::Scripts { attempts, .. } => attempts,
        }
    }
}

/// A completed step.
#[derive(Debug, Clone)]
pub struct StepReport {
    /// Time at the end of the step \[s\].
    pub t: f64,
    /// The time step that succeeded \[s\].
    pub dt: f64,
    /// Newton's report of the successful attempt's last solve (an attempt solves again when the
    /// converged state reached contacts outside the prepared candidates).
    pub newton: NewtonReport,
    /// What every solve of the step cost (failed attempts included).
    pub cost: SolveCost,
    /// Failed attempts before it (each halved `Δt`).
    pub reductions: usize,
    /// Newton iterations spent in failed attempts.
    pub wasted_iterations: usize,
}

impl StepReport {
    /// Newton iterations of the successful attempt, over all of its solves.
    pub fn iterations(&self) -> usize {
        self.cost.iterations - self.wasted_iterations
    }
}

/// The last accepted step, from which the next step's start is built.
#[derive(Debug, Clone, PartialEq)]
pub struct LastStep {
    /// The velocities at its start, in the layout of the unknowns.
    pub start_velocities: Vec<f64>,
    /// Its time step \[s\].
    pub dt: f64,
    /// Whether it started from the extrapolation and converged in one Newton iteration without a
    /// failed attempt: then [`InitialGuess::LeastEnergy`] takes the extrapolation without comparing.
    pub smooth: bool,
}

/// Advances an incremental potential in time.
pub struct TimeStepper {
    solver: NewtonSolver,
    settings: TimeStepSettings,
    t: f64,
    dt: f64,
    u: Vec<f64>,
    /// The last accepted step, for [`InitialGuess::Extrapolated`] and [`InitialGuess::LeastEnergy`].
    last_step: Option<LastStep>,
}

impl TimeStepper {
    /// A stepper for a potential, starting at `t = 0`.
    ///
    /// # Errors
    /// Invalid settings, or a symbolic analysis failure of the pattern.
    pub fn new(potential: &IncrementalPotential, settings: TimeStepSettings) -> Result<Self, NewtonError> {
        let mut newton = settings.newton;
        newton.residual_scale = settings.dt;
        let solver = NewtonSolver::try_new(potential.pattern().symbolic(), newton)?;
        Ok(Self {
            solver,
            settings,
            t: 0.0,
            dt: settings.dt,
            u: vec![0.0; potential.n_dofs()],
            last_step: None,
        })
    }

    /// The current time \[s\].
    pub fn time(&self) -> f64 {
        self.t
    }

    /// Sets the current time (e.g. to resume).
    pub fn set_time(&mut self, t: f64) {
        self.t = t;
    }

    /// The time step the next step will try \[s\].
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// Sets the time step the next step will try (to resume a run from a checkpoint, or to end a run
    /// on time).
    pub fn set_dt(&mut self, dt: f64) {
        self.dt = dt;
    }

    /// The last accepted step: what [`InitialGuess::Extrapolated`] extrapolates from (for a
    /// checkpoint; `None` before the first step and with the other initial guesses).
    pub fn last_step(&self) -> Option<&LastStep> {
        self.last_step.as_ref()
    }

    /// Sets what [`TimeStepper::last_step`] returned (to resume a run from a checkpoint).
    ///
    /// # Errors
    /// Velocities whose length is not the number of unknowns (nothing is set).
    pub fn set_last_step(&mut self, last_step: Option<LastStep>) -> Result<(), String> {
        if let Some(last) = &last_step
            && last.start_velocities.len() != self.u.len()
        {
            return Err(format!(
                "the last step's velocities have {} entries, the scene has {} unknowns",
                last.start_velocities.len(),
                self.u.len()
            ));
        }
        self.last_step = last_step;
        Ok(())
    }

    /// The Newton solver, mutably (to resume a run from a checkpoint).
    pub fn solver_mut(&mut self) -> &mut NewtonSolver {
        &mut self.solver
    }

    /// Takes over a pattern that the dynamic terms grew outside this stepper (a run resumed from a
    /// checkpoint restores the contact couplings of the run so far): a new symbolic analysis, with the
    /// ordering choice kept as when the pattern grows during a step.
    ///
    /// # Errors
    /// A symbolic analysis failure.
    pub fn adopt_pattern(&mut self, potential: &IncrementalPotential) -> Result<(), NewtonError> {
        self.rebuild_solver(potential)
    }

    /// The settings.
    pub fn settings(&self) -> &TimeStepSettings {
        &self.settings
    }

    /// The Newton solver (for linear-solver statistics).
    pub fn solver(&self) -> &NewtonSolver {
        &self.solver
    }

    /// Performs one step. `scripts(potential, t, dt)` is called before every attempt with the start
    /// time and the time step of that attempt; it sets targets, loads and rest fields.
    ///
    /// # Errors
    /// [`StepError`] when every allowed attempt failed; the potential's state is then unchanged.
    pub fn step(
        &mut self,
        potential: &mut IncrementalPotential,
        scripts: &mut dyn FnMut(&mut IncrementalPotential, f64, f64),
    ) -> Result<StepReport, StepError> {
        self.try_step(potential, &mut |p, t, dt| {
            scripts(p, t, dt);
            Ok(())
        })
    }

    /// [`TimeStepper::step`] with scripts that can fail: a script failure ends the step at once with
    /// [`StepError::Scripts`] (a smaller step would not help).
    ///
    /// # Errors
    /// [`StepError`]; the potential's state is then unchanged.
    pub fn try_step(
        &mut self,
        potential: &mut IncrementalPotential,
        scripts: &mut dyn FnMut(&mut IncrementalPotential, f64, f64) -> Result<(), ScriptError>,
    ) -> Result<StepReport, StepError> {
        let mut attempts = Vec::new();
        let mut dt = self.dt;
        let before = self.solver.spent();
        loop {
            potential.set_time_step(dt);
            if let Err(source) = scripts(potential, self.t, dt) {
                return Err(StepError::Scripts {
                    t: self.t,
                    dt,
                    attempts,
                    source,
                });
            }
            self.solver.settings_mut().residual_scale = dt;
            let from_extrapolation = self.initial_guess(potential);
            let attempt_start = self.solver.spent();
            // Contact candidates for this attempt; a grown pattern needs a new symbolic analysis.
            let error = match self.prepare_dynamic(potential) {
                Err(error) => error,
                Ok(()) => match self.solve_attempt(potential) {
                    Ok(newton) => {
                        let wasted_iterations = attempt_start.since(&before).iterations;
                        let cost = self.solver.spent().since(&before);
                        let smooth =
                            from_extrapolation && attempts.is_empty() && cost.iterations - wasted_iterations <= 1;
                        self.accept(potential, dt, smooth);
                        return Ok(StepReport {
                            t: self.t,
                            dt,
                            newton,
                            cost,
                            reductions: attempts.len(),
                            wasted_iterations,
                        });
                    }
                    Err(error) => error,
                },
            };
            attempts.push(FailedAttempt { dt, error });
            let next = dt * 0.5;
            if attempts.len() > self.settings.max_reductions || next < self.settings.min_dt {
                return Err(StepError::NotConverged { t: self.t, attempts });
            }
            dt = next;
        }
    }

    /// Newton from the initial guess in `self.u` with the fixed degrees of freedom set; a converged
    /// solution that reached contacts outside the prepared candidates is solved again with the
    /// candidates grown around it (up to three times).
    fn solve_attempt(&mut self, potential: &mut IncrementalPotential) -> Result<NewtonReport, NewtonError> {
        // Rest over the step, with the prescribed velocities.
        let mut rest = vec![0.0; self.u.len()];
        let fixed = potential.fixed_dofs().map(|(mask, values)| {
            set_fixed(&mut self.u, &mask, &values);
            set_fixed(&mut rest, &mask, &values);
            mask
        });
        let start = SolveStart {
            origin: &rest,
            predicted: false,
        };
        let mut result = solve_in_domain(&mut self.solver, potential, fixed.clone(), &mut self.u, start);
        for _ in 0..3 {
            if result.is_err() || !potential.needs_resolve(&self.u) {
                break;
            }
            self.refresh_dynamic(potential)?;
            result = solve_in_domain(&mut self.solver, potential, fixed.clone(), &mut self.u, start);
        }
        result
    }

    /// Commits the converged attempt of length `dt`, advances the time and sets the next time step
    /// (grown after an adaptive step, the set one otherwise). `smooth`: see [`LastStep::smooth`].
    fn accept(&mut self, potential: &mut IncrementalPotential, dt: f64, smooth: bool) {
        if matches!(
            self.settings.initial_guess,
            InitialGuess::Extrapolated | InitialGuess::LeastEnergy
        ) {
            let mut start = self.last_step.take().map(|l| l.start_velocities).unwrap_or_default();
            start.resize(self.u.len(), 0.0);
            state_velocities(potential, &mut start);
            self.last_step = Some(LastStep {
                start_velocities: start,
                dt,
                smooth,
            });
        }
        potential.commit(&self.u);
        self.t += dt;
        self.dt = if self.settings.adaptive {
            (dt * self.settings.growth).min(self.settings.dt)
        } else {
            self.settings.dt
        };
    }

    /// Prepares the dynamic terms (contact) for an attempt from the initial guess and limits the guess
    /// by continuous collision detection.
    fn prepare_dynamic(&mut self, potential: &mut IncrementalPotential) -> Result<(), NewtonError> {
        if !potential.has_dynamic_terms() {
            return Ok(());
        }
        self.refresh_dynamic(potential)?;
        let zero = vec![0.0; self.u.len()];
        let alpha = potential.max_step_fraction(&zero, &self.u);
        if alpha < 1.0 {
            self.u.iter_mut().for_each(|u| *u *= alpha);
        }
        Ok(())
    }

    /// Lets the dynamic terms prepare around `self.u`; a grown pattern gets a new symbolic analysis.
    fn refresh_dynamic(&mut self, potential: &mut IncrementalPotential) -> Result<(), NewtonError> {
        if begin_step(potential, &self.u)? {
            self.rebuild_solver(potential)?;
        }
        Ok(())
    }

    /// A new Newton solver for the potential's current pattern, which grew from the last one's.
    fn rebuild_solver(&mut self, potential: &IncrementalPotential) -> Result<(), NewtonError> {
        let mut settings = *self.solver.settings();
        // Contact only adds couplings to the same mesh, so `Auto`'s choice for the first pattern
        // holds for the grown ones: it is kept, which spares the grown patterns the split's cost
        // prediction (two orderings of each half and one of the whole matrix).
        if settings.linear_solver.domains == DomainSplit::Auto
            && settings.linear_solver.kind != LinearSolverKind::Cg
            && let Some(stats) = self.solver.linear_solver().symmetric_stats()
        {
            settings.linear_solver.domains = if stats.domains == 2 {
                DomainSplit::Always
            } else {
                DomainSplit::Off
            };
        }
        self.solver = self.solver.try_grown(potential.pattern().symbolic(), settings)?;
        Ok(())
    }

    /// Newton's start into `self.u`; returns whether it is the extrapolation.
    fn initial_guess(&mut self, potential: &mut IncrementalPotential) -> bool {
        match self.settings.initial_guess {
            InitialGuess::Zero => self.u.fill(0.0),
            InitialGuess::PreviousVelocity => state_velocities(potential, &mut self.u),
            InitialGuess::Extrapolated => self.extrapolated_velocities(potential),
            InitialGuess::LeastEnergy => return self.least_energy_start(potential),
        }
        self.settings.initial_guess == InitialGuess::Extrapolated
    }

    /// [`InitialGuess::Extrapolated`] into `self.u`.
    fn extrapolated_velocities(&mut self, potential: &IncrementalPotential) {
        state_velocities(potential, &mut self.u);
        if let Some(last) = &self.last_step {
            let ratio = potential.dt() / last.dt;
            for (u, v0) in self.u.iter_mut().zip(&last.start_velocities) {
                *u += ratio * (*u - v0);
            }
        }
    }

    /// [`InitialGuess::LeastEnergy`] into `self.u`. The candidates are compared with the fixed degrees
    /// of freedom set, as Newton will start from them; a candidate whose potential cannot be evaluated
    /// (a barrier crossed, a non-finite value) loses, and the extrapolation stands when all of them do.
    /// Returns whether the extrapolation was taken.
    fn least_energy_start(&mut self, potential: &mut IncrementalPotential) -> bool {
        self.extrapolated_velocities(potential);
        if self.last_step.as_ref().is_some_and(|last| last.smooth) {
            return true;
        }
        let extrapolated = self.u.clone();
        let mut previous = vec![0.0; self.u.len()];
        state_velocities(potential, &mut previous);
        let zero = vec![0.0; self.u.len()];
        let fixed = potential.fixed_dofs();
        let mut value = |candidate: &[f64]| -> f64 {
            let mut start = candidate.to_vec();
            if let Some((mask, values)) = &fixed {
                set_fixed(&mut start, mask, values);
            }
            potential.value(&start).ok().filter(|v| v.is_finite()).unwrap_or(f64::INFINITY)
        };
        let mut best = value(&extrapolated);
        let mut from_extrapolation = true;
        for candidate in [previous, zero] {
            if candidate == self.u {
                continue;
            }
            let candidate_value = value(&candidate);
            if candidate_value < best {
                best = candidate_value;
                self.u.copy_from_slice(&candidate);
                from_extrapolation = false;
            }
        }
        from_extrapolation
    }
}

/// The values of the fixed degrees of freedom (where `mask` is set) into `u`.
fn set_fixed(u: &mut [f64], mask: &[bool], values: &[f64]) {
    for (i, _) in mask.iter().enumerate().filter(|(_, m)| **m) {
        u[i] = values[i];
    }
}

/// The state's velocities and angular velocities, in the layout of the unknowns, into `u`.
fn state_velocities(potential: &IncrementalPotential, u: &mut [f64]) {
    let st = &potential.parts.state;
    let layout = &potential.parts.layout;
    for (i, v) in st.v.iter().enumerate() {
        u[3 * layout.disp_block(i)..3 * layout.disp_block(i) + 3].copy_from_slice(v.as_slice());
    }
    for (k, w) in st.omega.iter().enumerate() {
        u[3 * layout.rot_block(k)..3 * layout.rot_block(k) + 3].copy_from_slice(w.as_slice());
    }
}
