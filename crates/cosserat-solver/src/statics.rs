//! Quasi-static solves: a sequence of equilibria under increasing load, with the same Newton solver.
//!
//! The potential must be built without inertia; the stepper sets its time step to
//! [`cosserat_assembly::PSEUDO_TIME_STEP`], so the velocity unknowns are displacement increments and
//! the residual is a force in N (torque in N·m). Each load
//! level starts from the previous equilibrium; a level whose Newton solve fails is approached through
//! bisected intermediate levels, up to a bounded number of times.

use crate::error::{NewtonError, ScriptError};
use crate::newton::{NewtonReport, NewtonSettings, NewtonSolver};
use crate::potential_problem::PotentialProblem;
use cosserat_assembly::IncrementalPotential;
use thiserror::Error;

/// Settings of a quasi-static solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QuasiStaticSettings {
    /// Newton settings (the residual scale is 1: forces in N).
    pub newton: NewtonSettings,
    /// How many times an increment may be bisected in total for one requested level.
    pub max_bisections: usize,
    /// Start each solve from the previous increment scaled to the new load step (a secant predictor)
    /// instead of from zero. Smooth loading paths then start close to the solution.
    pub extrapolate: bool,
}

impl Default for QuasiStaticSettings {
    fn default() -> Self {
        Self {
            newton: NewtonSettings::default(),
            max_bisections: 10,
            extrapolate: true,
        }
    }
}

/// The equilibrium at one requested load level.
#[derive(Debug, Clone)]
pub struct LoadLevelReport {
    /// The load factor.
    pub load_factor: f64,
    /// Newton's report of the solve that reached this level.
    pub newton: NewtonReport,
    /// Intermediate levels inserted to reach it.
    pub bisections: usize,
    /// Newton iterations over all solves for this level (intermediate and failed ones included).
    pub total_iterations: usize,
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
#[error("quasi-static solve failed between load factors {from} and {to}: {error}")]
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
}

/// Advances a potential through increasing load levels, one requested level at a time, from the
/// last equilibrium. Each level starts from the previous equilibrium; a level whose Newton solve fails
/// is approached through bisected intermediate levels, up to [`QuasiStaticSettings::max_bisections`].
pub struct QuasiStaticStepper {
    solver: NewtonSolver,
    settings: QuasiStaticSettings,
    u: Vec<f64>,
    /// The last converged increment and its load step, for the predictor.
    previous: Option<(Vec<f64>, f64)>,
    /// The load factor of the last equilibrium.
    current: f64,
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
            previous: None,
            current: 0.0,
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

    /// The predictor's memory: the last converged increment and its load step (`None` after a
    /// bisection or before the first level).
    pub fn predictor(&self) -> Option<(&[f64], f64)> {
        self.previous.as_ref().map(|(du, step)| (du.as_slice(), *step))
    }

    /// Continues from the equilibrium at `load_factor` with the predictor's memory `predictor` (to
    /// resume a run from a checkpoint; the potential must hold that equilibrium).
    ///
    /// # Errors
    /// A predictor increment whose length is not the number of unknowns (as a message).
    pub fn resume(&mut self, load_factor: f64, predictor: Option<(Vec<f64>, f64)>) -> Result<(), String> {
        if let Some((du, _)) = &predictor
            && du.len() != self.u.len()
        {
            return Err(format!(
                "the predictor increment has {} entries, the system {} unknowns",
                du.len(),
                self.u.len()
            ));
        }
        self.current = load_factor;
        self.previous = predictor;
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
        let mut bisections = 0;
        let mut total_iterations = 0;
        let mut stack = vec![target];
        let mut last_report = None;
        while let Some(&lambda) = stack.last() {
            let from = self.current;
            let fail = |error: LevelFailure, iterations: usize, bisections: usize| StaticError {
                from,
                to: lambda,
                error,
                iterations,
                bisections,
            };
            apply(potential, lambda).map_err(|e| fail(e.into(), total_iterations, bisections))?;
            let predicted = self.predict(lambda);
            self.prepare(potential)
                .map_err(|e| fail(e.into(), total_iterations, bisections))?;
            // The unpredicted start: the last equilibrium, with the new targets of eliminated unknowns.
            let mut start = vec![0.0; self.u.len()];
            let fixed = potential.fixed_dofs().map(|(mask, values)| {
                for (i, _) in mask.iter().enumerate().filter(|(_, m)| **m) {
                    self.u[i] = values[i];
                    start[i] = values[i];
                }
                mask
            });
            let mut problem = PotentialProblem::new(potential, fixed);
            let result = if predicted {
                self.solver.solve_from_prediction(&mut problem, &mut self.u, &start)
            } else {
                self.solver.solve(&mut problem, &mut self.u)
            };
            match result {
                Ok(report) => {
                    total_iterations += report.iterations;
                    potential.commit(&self.u);
                    self.previous = Some((self.u.clone(), lambda - self.current));
                    self.current = lambda;
                    stack.pop();
                    last_report = Some(report);
                }
                Err(error) => {
                    total_iterations += error.residuals().len().saturating_sub(1);
                    if bisections >= self.settings.max_bisections {
                        return Err(fail(error.into(), total_iterations, bisections));
                    }
                    bisections += 1;
                    // A failed predictor is not trusted for the bisected step.
                    self.previous = None;
                    stack.push(0.5 * (self.current + lambda));
                }
            }
        }
        Ok(LoadLevelReport {
            load_factor: target,
            newton: last_report.expect("the loop ends only after the target level converged"),
            bisections,
            total_iterations,
        })
    }

    /// The starting point for level `lambda`: the last increment scaled to the new load step (a secant
    /// predictor), or zero. Returns whether it predicted.
    fn predict(&mut self, lambda: f64) -> bool {
        match (&self.previous, self.settings.extrapolate) {
            (Some((du, step)), true) if *step != 0.0 => {
                let scale = (lambda - self.current) / step;
                self.u.iter_mut().zip(du).for_each(|(u, d)| *u = d * scale);
                true
            }
            _ => {
                self.u.fill(0.0);
                false
            }
        }
    }

    /// Lets the dynamic terms prepare around the starting point; a grown pattern gets a new symbolic
    /// analysis.
    fn prepare(&mut self, potential: &mut IncrementalPotential) -> Result<(), NewtonError> {
        let changed = potential.begin_step(&self.u).map_err(|e| NewtonError::Problem {
            iteration: 0,
            source: crate::potential_problem::map_error(e),
            residuals: Vec::new(),
        })?;
        if changed {
            self.solver = NewtonSolver::try_new(potential.pattern().symbolic(), *self.solver.settings())?;
        }
        Ok(())
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
