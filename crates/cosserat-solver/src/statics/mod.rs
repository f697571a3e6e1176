//! Quasi-static solves: a sequence of equilibria under increasing load, with the same Newton solver.
//!
//! The potential must be built without inertia; the stepper sets its time step to
//! [`cosserat_assembly::PSEUDO_TIME_STEP`], so the velocity unknowns are displacement increments and
//! the residual is a force in N (torque in N·m). Each load
//! level starts from the previous equilibrium; a level whose Newton solve fails is approached through
//! bisected intermediate levels, up to a bounded number of times. With an [`IncrementControl`] the
//! load increment also follows Newton's effort: a level that needs many iterations makes the next
//! increments smaller, and increments grow back where Newton converges quickly.

mod predictor;

pub use predictor::{LevelIncrement, PredictorMemory};

use crate::error::{NewtonError, ScriptError};
use crate::newton::{IndefiniteHessian, NewtonReport, NewtonSettings, NewtonSolver, SolveCost};
use crate::potential_problem::{SolveStart, begin_step, solve_in_domain};
use cosserat_assembly::IncrementalPotential;
use cosserat_geometry::Num;
use thiserror::Error;

/// Settings of a quasi-static solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QuasiStaticSettings {
    /// Newton settings (the residual scale is 1: forces in N). The default takes Newton's own steps
    /// ([`IndefiniteHessian::Factorise`]): where a thin shell's level starts at an indefinite Hessian
    /// (plain Newton's first matrix takes the prediction's membrane error) they converge in far fewer
    /// iterations than the shift's descent (docs/time-integration.md); a level they cannot reach even
    /// after every bisection is tried once more with the shift (see
    /// [`LoadLevelReport::shift_retries`]). It uses mixed integration points
    /// ([`NewtonSettings::mixed_integration_points`]), whose first matrix of a predicted level takes the
    /// last equilibrium's stresses and whose relaxed steps cross a thin shell's spurious stretch where
    /// the line search would crawl.
    pub newton: NewtonSettings,
    /// How many times an increment may be bisected in total for one requested level.
    pub max_bisections: usize,
    /// Start each solve from a prediction extrapolated from the last converged increments instead of
    /// from the last equilibrium: the quadratic through the last three equilibria once two increments
    /// are known, and with plain Newton the secant while one is (see the `predictor` module). Smooth
    /// loading paths then start close to the solution.
    pub extrapolate: bool,
    /// Intermediate levels where Newton needs many iterations; `None` inserts them only when a solve
    /// fails (bisection).
    pub increment_control: Option<IncrementControl>,
}

impl Default for QuasiStaticSettings {
    fn default() -> Self {
        Self {
            newton: NewtonSettings {
                indefinite_hessian: IndefiniteHessian::Factorise,
                mixed_integration_points: true,
                ..NewtonSettings::default()
            },
            max_bisections: 10,
            extrapolate: true,
            increment_control: Some(IncrementControl::default()),
        }
    }
}

/// Load increments that follow Newton's effort (Crisfield's rule: the next increment is the last one
/// times `√(desired / used)` iterations, between a quarter and twice the last).
///
/// Thin shells converge far more slowly from a long prediction than from a short one: the
/// prediction's error sits in the stiff membrane, and the line search then cuts each step to a small
/// fraction. Shorter increments cost more solves but fewer iterations in all.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IncrementControl {
    /// The Newton iterations an increment should need. A requested level solved in one increment
    /// within them is never split; one that needs more shortens the increments after it.
    pub desired_iterations: usize,
}

impl Default for IncrementControl {
    fn default() -> Self {
        Self {
            desired_iterations: DEFAULT_DESIRED_ITERATIONS,
        }
    }
}

/// Above the few iterations of a well-predicted level, so that scenes whose levels converge normally
/// are never split.
const DEFAULT_DESIRED_ITERATIONS: usize = 30;

/// The equilibrium at one requested load level.
#[derive(Debug, Clone)]
pub struct LoadLevelReport {
    /// The load factor.
    pub load_factor: f64,
    /// Newton's report of the solve that reached this level.
    pub newton: NewtonReport,
    /// What every solve towards this level cost (intermediate and failed ones included).
    pub cost: SolveCost,
    /// Failed solves that were retried at a halved increment.
    pub bisections: usize,
    /// Intermediate levels solved on the way (after bisections or from the increment control).
    pub sub_levels: usize,
    /// Newton iterations over all solves for this level (intermediate and failed ones included).
    pub total_iterations: usize,
    /// Newton iterations of the failed solves among them.
    pub wasted_iterations: usize,
    /// Failed solves with Newton's own steps that were repeated with the shift, as a last resort before
    /// the level was given up ([`IndefiniteHessian::Factorise`] or `Adaptive`; see
    /// [`QuasiStaticSettings::newton`]).
    pub shift_retries: usize,
}

/// Why a load level could not be reached.
#[derive(Debug, Clone, Error)]
pub enum LevelFailure {
    /// Newton failed at the last allowed bisection.
    #[error(transparent)]
    Newton(#[from] NewtonError),
    /// The scripts could not set the loads of a level (not Newton's failure: no bisection helps).
    #[error(transparent)]
    Scripts(#[from] ScriptError),
}

/// A load level that could not be reached.
#[derive(Debug, Clone, Error)]
#[error("quasi-static solve failed between load factors {} and {}: {error}", Num(*from), Num(*to))]
pub struct StaticError {
    /// Last equilibrium reached.
    pub from: f64,
    /// The level that failed.
    pub to: f64,
    /// What failed.
    pub error: LevelFailure,
    /// Newton iterations spent on the failed level (every bisection included).
    pub iterations: usize,
    /// Bisections of the failed level.
    pub bisections: usize,
    /// Intermediate levels reached on the way to it.
    pub sub_levels: usize,
}

/// Advances a potential through increasing load levels, one requested level at a time, from the
/// last equilibrium. Each level starts from the previous equilibrium; a level whose Newton solve fails
/// is approached through bisected intermediate levels, up to [`QuasiStaticSettings::max_bisections`].
pub struct QuasiStaticStepper {
    solver: NewtonSolver,
    settings: QuasiStaticSettings,
    u: Vec<f64>,
    /// The last converged increments, for the prediction.
    predictor: PredictorMemory,
    /// The load factor of the last equilibrium.
    current: f64,
    /// The largest load increment the next solve may take (`None`: the whole next level).
    limit: Option<f64>,
}

/// What the solves towards one requested level have cost so far.
#[derive(Debug, Clone, Copy, Default)]
struct Tally {
    bisections: usize,
    sub_levels: usize,
    /// Newton iterations, failed solves' included.
    iterations: usize,
    /// Newton iterations of failed solves.
    wasted: usize,
    /// Solves repeated with the shift.
    shift_retries: usize,
}

impl Tally {
    /// Counts the iterations of a failed solve (those whose step was taken, as its residual history
    /// records them) as spent and wasted.
    fn waste(&mut self, error: &NewtonError) {
        let iterations = error.residuals().len().saturating_sub(1);
        self.iterations += iterations;
        self.wasted += iterations;
    }
}

/// The outcome of one Newton solve towards a level.
enum Attempt {
    Converged(NewtonReport),
    Failed(NewtonError),
}

impl QuasiStaticStepper {
    /// A stepper at load factor 0. Sets the potential's pseudo time step to 1.
    ///
    /// # Errors
    /// Invalid Newton settings, or a symbolic analysis failure of the pattern.
    pub fn new(potential: &mut IncrementalPotential, settings: &QuasiStaticSettings) -> Result<Self, NewtonError> {
        let mut newton = settings.newton;
        newton.residual_scale = 1.0;
        let solver = NewtonSolver::try_new(potential.pattern().symbolic(), newton)?;
        potential.set_time_step(cosserat_assembly::PSEUDO_TIME_STEP);
        Ok(Self {
            solver,
            settings: *settings,
            u: vec![0.0; potential.n_dofs()],
            predictor: PredictorMemory::default(),
            current: 0.0,
            limit: None,
        })
    }

    /// The load factor of the last equilibrium.
    pub fn load_factor(&self) -> f64 {
        self.current
    }

    /// The Newton solver (for linear-solver statistics).
    pub fn solver(&self) -> &NewtonSolver {
        &self.solver
    }

    /// The Newton solver, mutably (to resume a run from a checkpoint).
    pub fn solver_mut(&mut self) -> &mut NewtonSolver {
        &mut self.solver
    }

    /// The predictor's memory: the last converged increments (none after a bisection or before the
    /// first level, at most two).
    pub fn predictor(&self) -> &PredictorMemory {
        &self.predictor
    }

    /// The largest load increment the next solve may take (`None`: the whole next level).
    pub fn increment_limit(&self) -> Option<f64> {
        self.limit
    }

    /// Continues from the equilibrium at `load_factor` with the predictor's memory `predictor` and the
    /// increment limit `limit` (to resume a run from a checkpoint; the potential must hold that
    /// equilibrium).
    ///
    /// # Errors
    /// A predictor increment whose length is not the number of unknowns, or a limit that is not a
    /// positive number (as a message).
    pub fn resume(&mut self, load_factor: f64, predictor: PredictorMemory, limit: Option<f64>) -> Result<(), String> {
        if let Some(increment) = predictor.increments().iter().find(|i| i.du.len() != self.u.len()) {
            return Err(format!(
                "the predictor increment has {} entries, the system {} unknowns",
                increment.du.len(),
                self.u.len()
            ));
        }
        if let Some(limit) = limit
            && !(limit.is_finite() && limit > 0.0)
        {
            return Err(format!(
                "the load increment limit {} is not a positive number",
                Num(limit)
            ));
        }
        self.current = load_factor;
        self.predictor = predictor;
        self.limit = limit;
        Ok(())
    }

    /// Solves for equilibrium at load factor `target`, calling `apply(potential, λ)` to set loads and
    /// targets for every level tried (intermediate ones included).
    ///
    /// # Errors
    /// [`StaticError`] when the level cannot be reached within the allowed bisections, or `apply`
    /// fails; the potential then holds the last equilibrium.
    pub fn advance(
        &mut self,
        potential: &mut IncrementalPotential,
        target: f64,
        apply: &mut dyn FnMut(&mut IncrementalPotential, f64) -> Result<(), ScriptError>,
    ) -> Result<LoadLevelReport, StaticError> {
        let level_start = self.current;
        // Without increment control every level starts whole, as bisection leaves no memory.
        if self.settings.increment_control.is_none() {
            self.limit = None;
        }
        // No more increments per level than bisection alone could make.
        let smallest = (target - level_start) * 0.5f64.powi(self.settings.max_bisections as i32);
        let mut tally = Tally::default();
        let before = self.solver.spent();
        loop {
            let (from, lambda) = (self.current, next_level(self.current, target, self.limit));
            let fail = |error: LevelFailure, tally: &Tally| StaticError {
                from,
                to: lambda,
                error,
                iterations: tally.iterations,
                bisections: tally.bisections,
                sub_levels: tally.sub_levels,
            };
            let last_chance = tally.bisections >= self.settings.max_bisections;
            let attempt = self
                .attempt(potential, lambda, apply, (&mut tally, last_chance))
                .map_err(|e| fail(e, &tally))?;
            match attempt {
                Attempt::Converged(newton) => {
                    tally.iterations += newton.iterations;
                    let step = Increment {
                        length: lambda - from,
                        iterations: newton.iterations,
                        whole: from == level_start && lambda == target,
                    };
                    self.limit = adapted_limit(self.settings.increment_control, self.limit, step, smallest);
                    if lambda == target {
                        return Ok(LoadLevelReport {
                            load_factor: target,
                            newton,
                            cost: self.solver.spent().since(&before),
                            bisections: tally.bisections,
                            sub_levels: tally.sub_levels,
                            total_iterations: tally.iterations,
                            wasted_iterations: tally.wasted,
                            shift_retries: tally.shift_retries,
                        });
                    }
                    tally.sub_levels += 1;
                }
                Attempt::Failed(error) => {
                    tally.waste(&error);
                    if tally.bisections >= self.settings.max_bisections {
                        return Err(fail(error.into(), &tally));
                    }
                    tally.bisections += 1;
                    // A failed prediction is not trusted for the bisected step.
                    self.predictor.clear();
                    self.limit = Some(0.5 * (lambda - from));
                }
            }
        }
    }

    /// Newton's solve for level `lambda` from the last equilibrium, committed when it converges. On the
    /// `last_chance` of a level (no bisection left), a failed solve with Newton's own steps (the
    /// unshifted factorisation of indefinite Hessians) is repeated from the same start with the shift,
    /// whose trust-region descent gets through snaps where Newton's own direction stalls. It is the
    /// last resort rather than the first: on thin shells near the round-off floor the shift's damped
    /// steps fail where bisected levels with Newton's own steps converge, and a shifted retry of every
    /// failed level costs its iterations and changes the path of increments for the worse.
    fn attempt(
        &mut self,
        potential: &mut IncrementalPotential,
        lambda: f64,
        apply: &mut dyn FnMut(&mut IncrementalPotential, f64) -> Result<(), ScriptError>,
        (tally, last_chance): (&mut Tally, bool),
    ) -> Result<Attempt, LevelFailure> {
        let configured = self.settings.newton.indefinite_hessian;
        let mut result = self.solve_level(potential, lambda, apply)?;
        if let Err(error) = &result
            && last_chance
            && configured != IndefiniteHessian::Shift
        {
            tally.waste(error);
            tally.shift_retries += 1;
            self.solver.settings_mut().indefinite_hessian = IndefiniteHessian::Shift;
            let retried = self.solve_level(potential, lambda, apply);
            self.solver.settings_mut().indefinite_hessian = configured;
            result = retried?;
        }
        Ok(match result {
            Ok(report) => {
                potential.commit(&self.u);
                let increment = LevelIncrement {
                    du: self.u.clone(),
                    step: lambda - self.current,
                };
                self.predictor.push(increment);
                self.current = lambda;
                Attempt::Converged(report)
            }
            Err(error) => Attempt::Failed(error),
        })
    }

    /// One Newton solve for level `lambda` from the last equilibrium (not committed).
    fn solve_level(
        &mut self,
        potential: &mut IncrementalPotential,
        lambda: f64,
        apply: &mut dyn FnMut(&mut IncrementalPotential, f64) -> Result<(), ScriptError>,
    ) -> Result<Result<NewtonReport, NewtonError>, LevelFailure> {
        apply(potential, lambda)?;
        let predicted = self.predict(lambda);
        self.prepare(potential)?;
        // The unpredicted start: the last equilibrium, with the new targets of eliminated unknowns.
        let mut start = vec![0.0; self.u.len()];
        let fixed = potential.fixed_dofs().map(|(mask, values)| {
            for (i, _) in mask.iter().enumerate().filter(|(_, m)| **m) {
                self.u[i] = values[i];
                start[i] = values[i];
            }
            mask
        });
        let start = SolveStart {
            origin: &start,
            predicted,
        };
        Ok(solve_in_domain(&mut self.solver, potential, fixed, &mut self.u, start))
    }

    /// The starting point for level `lambda`: the increment extrapolated from the last ones (see the
    /// `predictor` module), or zero. Returns whether it predicted.
    fn predict(&mut self, lambda: f64) -> bool {
        let c = lambda - self.current;
        let plain = !self.solver.settings().mixed_integration_points;
        let predicted = self.settings.extrapolate
            && (self.predictor.predict(c, &mut self.u) || plain && self.predictor.secant(c, &mut self.u));
        if !predicted {
            self.u.fill(0.0);
        }
        predicted
    }

    /// Lets the dynamic terms prepare around the starting point; a grown pattern gets a new symbolic
    /// analysis.
    fn prepare(&mut self, potential: &mut IncrementalPotential) -> Result<(), NewtonError> {
        if begin_step(potential, &self.u)? {
            let spent = self.solver.spent();
            self.solver =
                NewtonSolver::try_new(potential.pattern().symbolic(), *self.solver.settings())?.continuing(spent);
        }
        Ok(())
    }
}

/// The next load factor from `current` on the way to `target`: the target, or the first of equal
/// increments within `limit`.
fn next_level(current: f64, target: f64, limit: Option<f64>) -> f64 {
    let remaining = target - current;
    match limit {
        Some(limit) if limit < remaining => {
            // Round-off in the ratio must not add an increment of nearly zero length.
            let n = (remaining / limit * (1.0 - 1e-12)).ceil();
            if n > 1.0 { current + remaining / n } else { target }
        }
        _ => target,
    }
}

/// A converged load increment.
#[derive(Debug, Clone, Copy)]
struct Increment {
    length: f64,
    iterations: usize,
    /// Whether it was a whole requested level.
    whole: bool,
}

/// The increment limit after the converged increment `step`, never below `smallest`.
fn adapted_limit(control: Option<IncrementControl>, limit: Option<f64>, step: Increment, smallest: f64) -> Option<f64> {
    match control {
        // Bisection only: after a success the pending level is retried at twice the increment.
        None => limit.map(|limit| 2.0 * limit),
        Some(control) => {
            let ratio = control.desired_iterations as f64 / step.iterations.max(1) as f64;
            if step.whole && ratio >= 1.0 {
                None
            } else {
                Some((step.length * ratio.sqrt().clamp(0.25, 2.0)).max(smallest))
            }
        }
    }
}

/// Solves for equilibrium at each load factor of `levels` (increasing), calling `apply(potential, λ)`
/// to set loads and targets for `λ`, and `reached(potential, λ)` after each requested level converged.
///
/// # Errors
/// [`StaticError`] when a level cannot be reached within the allowed bisections; the potential then
/// holds the last equilibrium.
pub fn solve_quasi_static(
    potential: &mut IncrementalPotential,
    levels: &[f64],
    settings: &QuasiStaticSettings,
    apply: &mut dyn FnMut(&mut IncrementalPotential, f64),
    reached: &mut dyn FnMut(&IncrementalPotential, f64),
) -> Result<Vec<LoadLevelReport>, StaticError> {
    let mut stepper = QuasiStaticStepper::new(potential, settings).map_err(|error| StaticError {
        from: 0.0,
        to: levels.first().copied().unwrap_or(0.0),
        error: error.into(),
        iterations: 0,
        bisections: 0,
        sub_levels: 0,
    })?;
    let mut reports = Vec::with_capacity(levels.len());
    for &target in levels {
        let report = stepper.advance(potential, target, &mut |p, lambda| {
            apply(p, lambda);
            Ok(())
        })?;
        reached(potential, target);
        reports.push(report);
    }
    Ok(reports)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_split_into_equal_increments_within_the_limit() {
        assert_eq!(next_level(0.25, 0.5, None), 0.5);
        assert_eq!(next_level(0.25, 0.5, Some(0.25)), 0.5);
        assert_eq!(next_level(0.25, 0.5, Some(1.0)), 0.5);
        // 0.25 / 0.1 needs three increments of 1/12.
        assert!((next_level(0.25, 0.5, Some(0.1)) - (0.25 + 0.25 / 3.0)).abs() < 1e-15);
        // A limit a hair below the remaining step does not add a sliver.
        assert!((next_level(0.0, 0.3, Some(0.1 * (1.0 - 1e-14))) - 0.1).abs() < 1e-15);
        assert_eq!(next_level(0.0, 0.3, Some(0.3 * (1.0 - 1e-14))), 0.3);
    }

    #[test]
    fn the_limit_follows_the_iterations_between_a_quarter_and_twice_the_increment() {
        let control = Some(IncrementControl { desired_iterations: 16 });
        let step = |iterations, whole| Increment {
            length: 0.1,
            iterations,
            whole,
        };
        let limit = |iterations, whole| adapted_limit(control, Some(0.1), step(iterations, whole), 1e-6).unwrap();
        // √(16 / 64) = 1/2, √(16 / 4) = 2; the factor stays within [1/4, 2].
        assert!((limit(64, false) - 0.05).abs() < 1e-15);
        assert!((limit(4, false) - 0.2).abs() < 1e-15);
        assert!((limit(1, false) - 0.2).abs() < 1e-15);
        assert!((limit(10_000, false) - 0.025).abs() < 1e-15);
        assert!((limit(64, true) - 0.05).abs() < 1e-15);
        // A whole level within the desired iterations lifts the limit; nothing goes below `smallest`.
        assert_eq!(adapted_limit(control, Some(0.1), step(16, true), 1e-6), None);
        assert_eq!(adapted_limit(control, None, step(10_000, false), 0.05), Some(0.05));
        // Without control the limit only doubles, back towards the pending level.
        assert_eq!(adapted_limit(None, Some(0.1), step(64, false), 1e-6), Some(0.2));
        assert_eq!(adapted_limit(None, None, step(64, true), 1e-6), None);
    }
}
