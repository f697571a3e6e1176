//! Arc-length runs (`time.mode = "arc_length"`): equilibria along the load path, through limit points
//! of the load and of the deflection.

use super::{Simulation, StepInfo, prepare_step};
use crate::error::SimulationError;
use crate::outcome::Outcome;
use crate::scripts::Scripts;
use crate::stop::StopRequest;
use cosserat_io::{FailedStep, RunWriter};
use cosserat_solver::{ArcLengthSettings, PathError, PathStepper};
use std::time::Instant;

/// At most this many corrector iterations per attempt: a corrector that needs more is better retried
/// with half the arc length.
const MAX_CORRECTOR_ITERATIONS: usize = 25;

impl Simulation {
    /// Follows the path from load factor 0 until it reaches `end` from below. Every equilibrium is a
    /// step with its frame and probe row: `t` counts the steps and the load factor is the column
    /// `path.load_factor` of `probes.csv`, since it falls and rises along the path.
    pub(super) fn run_arc_length(
        &mut self,
        writer: &mut RunWriter,
        initial_increment: f64,
        end: f64,
        max_steps: usize,
        progress: &mut dyn FnMut(&StepInfo, &mut Scripts),
        stop: &StopRequest,
    ) -> Result<Outcome, SimulationError> {
        let mut newton = self.time_step_settings(1.0, false).newton;
        newton.max_iterations = newton.max_iterations.min(MAX_CORRECTOR_ITERATIONS);
        let settings = ArcLengthSettings {
            newton,
            initial_increment,
            end,
            max_steps,
            ..ArcLengthSettings::default()
        };
        let mut stepper =
            PathStepper::new(&mut self.potential, &settings).map_err(|e| SimulationError::Setup(e.to_string()))?;
        let mut previous = 0.0;
        while !stepper.finished() {
            if let Some(reason) = stop.reason() {
                return Ok(Outcome::Interrupted(stepper.load_factor(), reason));
            }
            let t0 = Instant::now();
            let (scripts, model, contact) = (&mut self.scripts, &mut self.model, &mut self.contact);
            let result = stepper.step(&mut self.potential, &mut |p, lambda| {
                prepare_step(scripts, model.as_mut(), contact.as_mut(), p, lambda, 0.0)
            });
            let point = match result {
                Ok(point) => point,
                Err(e) => return Ok(failed_path(&e, stepper.load_factor())),
            };
            if let Some(contact) = &mut self.contact {
                contact.after_step(&self.potential);
            }
            self.stats.record_point(&point, t0.elapsed().as_secs_f64());
            self.t_reached = point.load_factor;
            let info = StepInfo {
                step: point.step,
                t: point.load_factor,
                end,
                dt: point.load_factor - previous,
                newton_iterations: point.iterations + point.wasted_iterations,
                residual: point.residual,
            };
            progress(&info, &mut self.scripts);
            self.record_output(writer, point.step as f64)?;
            previous = point.load_factor;
        }
        Ok(Outcome::Completed)
    }
}

/// The outcome of a path that could not go on from load factor `lambda`.
fn failed_path(e: &PathError, lambda: f64) -> Outcome {
    let reason = path_failure_reason(e);
    Outcome::Failed {
        t: lambda,
        step: Some(FailedStep {
            t: lambda,
            attempts: Vec::new(),
            reason: reason.clone(),
        }),
        reason,
    }
}

/// The message of a path error, naming the scene settings that decide it where the solver's own
/// message cannot (it does not know the scene's names).
fn path_failure_reason(e: &PathError) -> String {
    match e {
        PathError::NoFirstArc { .. } => format!("time.initial_increment: {e}"),
        // The arc length never grows beyond the first step's, so the first increment sets how finely
        // the path is sampled and with it how many steps it takes.
        PathError::TooManySteps { .. } => {
            format!("{e}; steps never grow beyond the first, so raise time.initial_increment or time.max_steps")
        }
        _ => e.to_string(),
    }
}
