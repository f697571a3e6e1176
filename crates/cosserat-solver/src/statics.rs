//! Quasi-static solves: a sequence of equilibria under increasing load, with the same Newton solver.
//!
//! The potential must be built without inertia and with `Δt = 1` (a pseudo time), so the velocity
//! unknowns are displacement increments and the residual is a force in N (torque in N·m). Each load
//! level starts from the previous equilibrium; a level whose Newton solve fails is approached through
//! bisected intermediate levels, up to a bounded number of times.

use crate::error::NewtonError;
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

/// A load level that could not be reached.
#[derive(Debug, Clone, Error)]
#[error("quasi-static solve failed between load factors {from} and {to}: {error}")]
pub struct StaticError {
    /// Last equilibrium reached.
    pub from: f64,
    /// The level that failed.
    pub to: f64,
    /// The last Newton failure.
    pub error: NewtonError,
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
    let mut newton = settings.newton;
    newton.residual_scale = 1.0;
    let mut solver = NewtonSolver::try_new(potential.pattern().symbolic(), newton).map_err(|error| StaticError {
        from: 0.0,
        to: levels.first().copied().unwrap_or(0.0),
        error,
    })?;
    potential.dt = 1.0;
    let mut u = vec![0.0; potential.n_dofs()];
    // The last converged increment and its load step, for the predictor.
    let mut previous: Option<(Vec<f64>, f64)> = None;
    let mut current = 0.0;
    let mut reports = Vec::with_capacity(levels.len());
    for &target in levels {
        let mut bisections = 0;
        let mut total_iterations = 0;
        let mut stack = vec![target];
        let mut last_report = None;
        while let Some(&lambda) = stack.last() {
            apply(potential, lambda);
            match (&previous, settings.extrapolate) {
                (Some((du, step)), true) if *step != 0.0 => {
                    let scale = (lambda - current) / step;
                    u.iter_mut().zip(du).for_each(|(u, d)| *u = d * scale);
                }
                _ => u.fill(0.0),
            }
            let changed = potential.begin_step(&u).map_err(|e| StaticError {
                from: current,
                to: lambda,
                error: NewtonError::Problem {
                    iteration: 0,
                    source: crate::potential_problem::map_error(e),
                    residuals: Vec::new(),
                },
            })?;
            if changed {
                solver =
                    NewtonSolver::try_new(potential.pattern().symbolic(), *solver.settings()).map_err(|error| {
                        StaticError {
                            from: current,
                            to: lambda,
                            error,
                        }
                    })?;
            }
            let fixed = potential.fixed_dofs().map(|(mask, values)| {
                for (i, _) in mask.iter().enumerate().filter(|(_, m)| **m) {
                    u[i] = values[i];
                }
                mask
            });
            let result = solver.solve(&mut PotentialProblem::new(potential, fixed), &mut u);
            match result {
                Ok(report) => {
                    total_iterations += report.iterations;
                    potential.commit(&u);
                    previous = Some((u.clone(), lambda - current));
                    current = lambda;
                    stack.pop();
                    last_report = Some(report);
                }
                Err(error) => {
                    total_iterations += error.residuals().len().saturating_sub(1);
                    if bisections >= settings.max_bisections {
                        return Err(StaticError {
                            from: current,
                            to: lambda,
                            error,
                        });
                    }
                    bisections += 1;
                    // A failed predictor is not trusted for the bisected step.
                    previous = None;
                    stack.push(0.5 * (current + lambda));
                }
            }
        }
        reached(potential, target);
        let newton = last_report.expect("at least one solve converged for this level");
        reports.push(LoadLevelReport {
            load_factor: target,
            newton,
            bisections,
            total_iterations,
        });
    }
    Ok(reports)
}
