//! The counters a run collects step by step, from which the simulation makes its typed run record
//! ([`cosserat_io::RunSummary`]) when the run ends.

use crate::convergence::ConvergenceStats;
use cosserat_io::checkpoint::{Decoder, Encoder};
use cosserat_io::{EnergyHistory, FactorRecord, LinearSolverRecord, OutputError};
use cosserat_solver::{FactorStats, LoadLevelReport, NewtonReport, PathPoint, SolveCost, StepReport};

/// Counters collected over a run.
#[derive(Debug, Clone)]
pub struct RunStats {
    /// Completed steps (load levels).
    pub steps: usize,
    /// Newton iterations of the completed steps.
    pub newton_iterations: usize,
    /// Most Newton iterations of one step.
    pub max_newton_iterations: usize,
    /// Newton iterations of failed attempts.
    pub wasted_iterations: usize,
    /// Time-step halvings and load bisections.
    pub reductions: usize,
    /// Intermediate load levels of quasi-static runs (solved, not written).
    pub intermediate_levels: usize,
    /// Time in assembly \[s\].
    pub assembly_seconds: f64,
    /// Time in linear solves \[s\].
    pub solve_seconds: f64,
    /// The part of `solve_seconds` spent in numerical factorisations \[s\].
    pub factorisation_seconds: f64,
    /// Time in steps \[s\].
    pub step_seconds: f64,
    /// Smallest deformed-to-rest area ratio at the output times.
    pub min_area_ratio: f64,
    /// Frames written.
    pub frames: usize,
    /// Energies at the output times.
    pub energy: EnergyHistory,
    /// Numeric factorisations performed.
    pub factorisations: usize,
    /// Conjugate-gradient iterations (CG linear solver only).
    pub cg_iterations: usize,
    /// Structure of the symmetric factor (last symbolic analysis).
    pub factor: Option<FactorStats>,
    /// Tolerances and residuals of the converged solves.
    pub convergence: ConvergenceStats,
}

impl Default for RunStats {
    fn default() -> Self {
        Self {
            steps: 0,
            newton_iterations: 0,
            max_newton_iterations: 0,
            wasted_iterations: 0,
            reductions: 0,
            intermediate_levels: 0,
            assembly_seconds: 0.0,
            solve_seconds: 0.0,
            factorisation_seconds: 0.0,
            step_seconds: 0.0,
            min_area_ratio: f64::INFINITY,
            frames: 0,
            energy: EnergyHistory::default(),
            factorisations: 0,
            cg_iterations: 0,
            factor: None,
            convergence: ConvergenceStats::default(),
        }
    }
}

impl RunStats {
    /// Adds a completed time step.
    pub fn record_step(&mut self, r: &StepReport, seconds: f64) {
        self.add_step(&r.newton, &r.cost, r.iterations(), seconds);
        self.wasted_iterations += r.wasted_iterations;
        self.reductions += r.reductions;
    }

    /// Adds a reached load level (a level counts as a step).
    pub fn record_level(&mut self, r: &LoadLevelReport, seconds: f64) {
        self.add_step(&r.newton, &r.cost, r.total_iterations, seconds);
        self.wasted_iterations += r.wasted_iterations;
        self.reductions += r.bisections;
        self.intermediate_levels += r.sub_levels;
    }

    /// Adds a step whose last solve `newton` converged, after solves that cost `cost` in all
    /// (`iterations` of them count as the step's).
    fn add_step(&mut self, newton: &NewtonReport, cost: &SolveCost, iterations: usize, seconds: f64) {
        self.steps += 1;
        self.newton_iterations += iterations;
        self.max_newton_iterations = self.max_newton_iterations.max(iterations);
        self.assembly_seconds += cost.assembly_seconds;
        self.solve_seconds += cost.linear_solve_seconds;
        self.factorisation_seconds += cost.factorisation_seconds;
        self.step_seconds += seconds;
        self.factorisations += cost.factorisations.factorised();
        self.cg_iterations += cost.cg_iterations;
        self.convergence.record_newton(newton, cost);
    }

    /// Adds an equilibrium of an arc-length path (a step of the path counts as a step; its iterations
    /// include those of attempts with a longer arc length).
    pub fn record_point(&mut self, p: &PathPoint, seconds: f64) {
        let iterations = p.iterations + p.wasted_iterations;
        self.steps += 1;
        self.newton_iterations += iterations;
        self.max_newton_iterations = self.max_newton_iterations.max(iterations);
        self.wasted_iterations += p.wasted_iterations;
        self.reductions += p.cuts;
        self.assembly_seconds += p.assembly_seconds;
        self.solve_seconds += p.linear_solve_seconds;
        self.step_seconds += seconds;
        self.convergence.record_point(p);
    }

    /// Saves the counters into a checkpoint (the factor's structure is measured again by the resumed
    /// run's first step).
    pub(crate) fn save(&self, out: &mut Encoder) {
        out.usizes(&[
            self.steps,
            self.newton_iterations,
            self.max_newton_iterations,
            self.wasted_iterations,
            self.reductions,
            self.intermediate_levels,
            self.frames,
            self.factorisations,
            self.cg_iterations,
        ]);
        out.f64s(&[
            self.assembly_seconds,
            self.solve_seconds,
            self.factorisation_seconds,
            self.step_seconds,
            self.min_area_ratio,
        ]);
        out.f64s(&self.energy.t);
        out.f64s(&self.energy.kinetic);
        out.f64s(&self.energy.elastic);
        self.convergence.save(out);
    }

    /// Reads counters saved by [`RunStats::save`].
    pub(crate) fn load(input: &mut Decoder) -> Result<Self, OutputError> {
        let counts = input.usizes()?;
        let times = input.f64s()?;
        let energy = EnergyHistory {
            t: input.f64s()?,
            kinetic: input.f64s()?,
            elastic: input.f64s()?,
        };
        let convergence = ConvergenceStats::load(input)?;
        let (
            &[
                steps,
                newton_iterations,
                max_newton_iterations,
                wasted_iterations,
                reductions,
                intermediate_levels,
                frames,
                factorisations,
                cg_iterations,
            ],
            &[
                assembly_seconds,
                solve_seconds,
                factorisation_seconds,
                step_seconds,
                min_area_ratio,
            ],
        ) = (counts.as_slice(), times.as_slice())
        else {
            return Err(input.error("the run's counters have the wrong length"));
        };
        Ok(Self {
            steps,
            newton_iterations,
            max_newton_iterations,
            wasted_iterations,
            reductions,
            intermediate_levels,
            assembly_seconds,
            solve_seconds,
            factorisation_seconds,
            step_seconds,
            min_area_ratio,
            frames,
            energy,
            factorisations,
            cg_iterations,
            factor: None,
            convergence,
        })
    }

    /// Average Newton iterations per completed step.
    pub fn avg_newton_iterations(&self) -> f64 {
        self.newton_iterations as f64 / self.steps.max(1) as f64
    }

    /// Average time per completed step \[ms\].
    pub fn avg_step_ms(&self) -> f64 {
        1e3 * self.step_seconds / self.steps.max(1) as f64
    }

    /// `part / whole` of the steps' time, zero when nothing was timed.
    pub fn share_of_steps(&self, part: f64) -> f64 {
        if self.step_seconds > 0.0 {
            part / self.step_seconds
        } else {
            0.0
        }
    }

    /// The record of the linear solves.
    pub fn linear_solver(&self) -> LinearSolverRecord {
        let factor = self.factor.map(|f| FactorRecord {
            nnz: f.nnz_l,
            flops: f.flops,
            domains: f.domains,
            seconds: self.factorisation_seconds,
            gflops_per_s: (self.factorisation_seconds > 0.0 && self.factorisations > 0)
                .then(|| f.flops * self.factorisations as f64 / self.factorisation_seconds / 1e9),
        });
        let cg = self.cg_iterations > 0;
        LinearSolverRecord {
            factorisations: self.factorisations,
            factor,
            cg_iterations: cg.then_some(self.cg_iterations),
            cg_iterations_per_newton: cg.then(|| self.cg_iterations as f64 / self.newton_iterations.max(1) as f64),
        }
    }
}

/// The process's peak resident memory (VmHWM) in MB, where the OS reports it.
pub fn peak_memory_mb() -> Option<f64> {
    peak_memory_kib().map(|kib| kib as f64 / 1024.0)
}

/// The process's peak resident set size \[KiB\] (`VmHWM` of `/proc/self/status`), where the OS
/// reports it.
pub fn peak_memory_kib() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find_map(|l| l.strip_prefix("VmHWM:"))?;
    line.split_whitespace().next()?.parse().ok()
}
