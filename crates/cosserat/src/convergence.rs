//! How a run's Newton solves met their tolerance, collected step by step for the summary.

use cosserat_io::checkpoint::{Decoder, Encoder};
use cosserat_io::{ConvergenceRecord, OutputError, ToleranceMode};
use cosserat_solver::{Convergence, Criterion, DomainCost, NewtonReport, PathPoint, SolveCost, Tolerance};

/// The run's convergence record: the largest tolerance, residual and relative residual of a step, the
/// steps accepted at the round-off floor, the shifted iterations and the domain check's work.
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
    domain: DomainCost,
}

impl ConvergenceStats {
    /// Records the converged Newton solve of a time step or a load level, whose solves cost `cost` in
    /// all (failed attempts included).
    pub(crate) fn record_newton(&mut self, report: &NewtonReport, cost: &SolveCost) {
        self.shifted_iterations += cost.shifted_iterations;
        self.domain.rejected_iterates += cost.domain.rejected_iterates;
        self.domain.retracted_guesses += cost.domain.retracted_guesses;
        self.domain.free_retries += cost.domain.free_retries;
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
        let d = &self.domain;
        out.usizes(&[
            self.steps,
            self.stagnated_steps,
            self.shifted_iterations,
            d.rejected_iterates,
            d.retracted_guesses,
            d.free_retries,
        ]);
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
        // A checkpoint written before the domain check was counted has three counts.
        let (
            &[steps, stagnated_steps, shifted_iterations, ref domain @ ..],
            &[max_step_tolerance, max_residual, max_relative_residual],
            &[residual, load],
        ) = (counts.as_slice(), maxima.as_slice(), worst.as_slice())
        else {
            return Err(input.error("the convergence record has the wrong length"));
        };
        let domain = match *domain {
            [] => DomainCost::default(),
            [rejected_iterates, retracted_guesses, free_retries] => DomainCost {
                rejected_iterates,
                retracted_guesses,
                free_retries,
            },
            _ => return Err(input.error("the convergence record has the wrong length")),
        };
        Ok(Self {
            steps,
            max_step_tolerance,
            max_residual,
            max_relative_residual,
            stagnated_steps,
            worst_stagnated: stagnated.then_some((residual, load)),
            shifted_iterations,
            domain,
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
            rejected_iterates: self.domain.rejected_iterates,
            retracted_guesses: self.domain.retracted_guesses,
            free_retries: self.domain.free_retries,
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The record `write` saves, loaded back through a checkpoint file.
    fn through_file(name: &str, write: impl FnOnce(&mut Encoder)) -> ConvergenceStats {
        let path = std::env::temp_dir().join(format!("cosserat-convergence-{name}-{}", std::process::id()));
        let mut out = Encoder::new();
        write(&mut out);
        out.write(&path).expect("checkpoint written");
        let mut input = Decoder::open(&path).expect("checkpoint read");
        let stats = ConvergenceStats::load(&mut input).expect("a convergence record");
        std::fs::remove_file(&path).ok();
        stats
    }

    #[test]
    fn the_domain_checks_work_survives_a_checkpoint() {
        let stats = ConvergenceStats {
            steps: 5,
            shifted_iterations: 2,
            domain: DomainCost {
                rejected_iterates: 7,
                retracted_guesses: 3,
                free_retries: 1,
            },
            ..Default::default()
        };
        let loaded = through_file("domain", |out| stats.save(out));
        assert_eq!(loaded.domain, stats.domain);
        assert_eq!((loaded.steps, loaded.shifted_iterations), (5, 2));
    }

    #[test]
    fn a_checkpoint_from_before_the_domain_counts_loads_without_them() {
        let loaded = through_file("three-counts", |out| {
            out.usizes(&[5, 1, 2]);
            out.f64s(&[1e-6, 2e-6, 3e-7]);
            out.bool(false);
            out.f64s(&[0.0, 0.0]);
        });
        assert_eq!(loaded.domain, DomainCost::default());
        assert_eq!(
            (loaded.steps, loaded.stagnated_steps, loaded.shifted_iterations),
            (5, 1, 2)
        );
        assert_eq!(loaded.max_residual, 2e-6);
    }
}
