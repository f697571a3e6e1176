//! How a run's Newton solves met their tolerance, collected step by step for the summary.

use cosserat_io::checkpoint::{Decoder, Encoder};
use cosserat_io::{ConvergenceRecord, OutputError, ToleranceMode};
use cosserat_solver::{Convergence, Criterion, NewtonReport, PathPoint, Tolerance};

/// The run's convergence record: the largest tolerance, residual and relative residual of a step, the
/// steps accepted at the round-off floor, and the shifted iterations.
#[derive(Debug, Clone, Default)]
pub struct ConvergenceStats {
    steps: usize,
    max_step_tolerance: f64,
    max_residual: f64,
    max_relative_residual: f64,
    stagnated_steps: usize,
    /// The largest residual and its load scale of a stagnated step.
    worst_stagnated: Option<(f64, f64)>,
    shifted_iterations: usize,
}

impl ConvergenceStats {
    /// Records the converged Newton solve of a time step or a load level, whose solves shifted the
    /// Hessian in `shifted_iterations` iterations in all.
    pub(crate) fn record_newton(&mut self, report: &NewtonReport, shifted_iterations: usize) {
        self.shifted_iterations += shifted_iterations;
        self.record(&report.convergence, report.residual());
    }

    /// Records an equilibrium of an arc-length path.
    pub(crate) fn record_point(&mut self, point: &PathPoint) {
        self.record(&point.convergence, point.residual);
    }

    fn record(&mut self, convergence: &Convergence, residual: f64) {
        self.steps += 1;
        self.max_step_tolerance = self.max_step_tolerance.max(convergence.tolerance);
        self.max_residual = self.max_residual.max(residual);
        let relative = convergence.relative_residual(residual);
        if relative.is_finite() {
            self.max_relative_residual = self.max_relative_residual.max(relative);
        }
        if convergence.criterion == Criterion::Stagnated {
            self.stagnated_steps += 1;
            if self.worst_stagnated.is_none_or(|(r, _)| residual > r) {
                self.worst_stagnated = Some((residual, convergence.load_scale));
            }
        }
    }

    /// Saves the record into a checkpoint.
    pub(crate) fn save(&self, out: &mut Encoder) {
        out.usizes(&[self.steps, self.stagnated_steps, self.shifted_iterations]);
        out.f64s(&[self.max_step_tolerance, self.max_residual, self.max_relative_residual]);
        out.bool(self.worst_stagnated.is_some());
        let (residual, load) = self.worst_stagnated.unwrap_or_default();
        out.f64s(&[residual, load]);
    }

    /// Reads a record saved by [`ConvergenceStats::save`].
    pub(crate) fn load(input: &mut Decoder) -> Result<Self, OutputError> {
        let counts = input.usizes()?;
        let maxima = input.f64s()?;
        let stagnated = input.bool()?;
        let worst = input.f64s()?;
        let (
            &[steps, stagnated_steps, shifted_iterations],
            &[max_step_tolerance, max_residual, max_relative_residual],
            &[residual, load],
        ) = (counts.as_slice(), maxima.as_slice(), worst.as_slice())
        else {
            return Err(input.error("the convergence record has the wrong length"));
        };
        Ok(Self {
            steps,
            max_step_tolerance,
            max_residual,
            max_relative_residual,
            stagnated_steps,
            worst_stagnated: stagnated.then_some((residual, load)),
            shifted_iterations,
        })
    }

    /// The summary's record, if any step converged.
    pub(crate) fn summary(&self, tolerance: Tolerance) -> Option<ConvergenceRecord> {
        let (tolerance_mode, value) = match tolerance {
            Tolerance::Relative(v) => (ToleranceMode::Relative, v),
            Tolerance::Absolute(v) => (ToleranceMode::Absolute, v),
        };
        (self.steps > 0).then_some(ConvergenceRecord {
            tolerance_mode,
            tolerance: value,
            max_step_tolerance: self.max_step_tolerance,
            max_residual: self.max_residual,
            max_relative_residual: self.max_relative_residual,
            stagnated_steps: self.stagnated_steps,
            shifted_iterations: self.shifted_iterations,
        })
    }

    /// The warning about steps accepted at the round-off floor, if there were any.
    pub(crate) fn warning(&self) -> Option<String> {
        let (residual, load) = self.worst_stagnated?;
        Some(format!(
            "{} step(s) stopped at the residual's round-off floor above the tolerance (largest residual {residual:.2e}, \
             {:.1e} of the load scale {load:.2e}): Newton could not improve them further; a tighter tolerance is \
             not attainable in double precision for this problem",
            self.stagnated_steps,
            residual / load
        ))
    }
}
