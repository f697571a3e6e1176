//! Arc-length runs (`time.mode = "arc_length"`): equilibria along the load path, through limit points
//! of the load and of the deflection.

use super::{Outcome, Simulation, StepInfo};
use crate::error::SimulationError;
use crate::stop::StopRequest;
use cosserat_scene::output::{FailedStep, RunWriter};
use cosserat_solver::{ArcLengthSettings, PathError, PathPoint, PathStepper};
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
        progress: &mut dyn FnMut(&StepInfo),
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
        let mut stepper = PathStepper::new(&mut self.system.potential, &settings)
            .map_err(|e| SimulationError::Setup(e.to_string()))?;
        let mut previous = 0.0;
        while !stepper.finished() {
            if let Some(reason) = stop.reason() {
                return Ok(Outcome::Interrupted(stepper.load_factor(), reason));
            }
            let t0 = Instant::now();
            let (scripts, model) = (&mut self.scripts, &mut self.model);
            let result = stepper.step(&mut self.system.potential, &mut |p, lambda| {
                scripts.apply(p, lambda, 0.0)?;
                model.apply(lambda, 0.0);
                Ok(())
            });
            let point = match result {
                Ok(point) => point,
                Err(e) => return Ok(failed_path(&e, stepper.load_factor())),
            };
            self.record_point(&point, t0.elapsed().as_secs_f64());
            self.t_reached = point.load_factor;
            progress(&StepInfo {
                step: point.step,
                t: point.load_factor,
                end,
                dt: point.load_factor - previous,
                newton_iterations: point.iterations + point.wasted_iterations,
                residual: point.residual,
            });
            self.record_output(writer, point.step as f64)?;
            previous = point.load_factor;
        }
        Ok(Outcome::Completed)
    }

    /// Adds an equilibrium of the path to the run's statistics (a step of the path counts as a step;
    /// its iterations include those of attempts with a longer arc length).
    fn record_point(&mut self, p: &PathPoint, seconds: f64) {
        let s = &mut self.stats;
        let iterations = p.iterations + p.wasted_iterations;
        s.steps += 1;
        s.newton_iterations += iterations;
        s.max_newton_iterations = s.max_newton_iterations.max(iterations);
        s.wasted_iterations += p.wasted_iterations;
        s.reductions += p.cuts;
        s.assembly_seconds += p.assembly_seconds;
        s.solve_seconds += p.linear_solve_seconds;
        s.step_seconds += seconds;
        s.convergence.record_point(p);
    }
}

/// The outcome of a path that could not go on from load factor `lambda`.
fn failed_path(e: &PathError, lambda: f64) -> Outcome {
    let reason = e.to_string();
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
