//! Perturbed ensembles of the stability matrix's cells: whether a cell completes by margin or by
//! luck. Each variant perturbs the clamps' rotation penalty and the time step by relative amounts
//! between 1e-7 and 1e-3 (either sign, log-uniform magnitude) and runs on one or two threads, which
//! changes the order of the parallel sums. A cell that passes by luck (a snap that Newton gets through
//! only for some roundings) fails for some of its variants.

use crate::runner::Runner;
use crate::stability::{CellResult, Settings, run_cell};
use anyhow::{Context, Result};
use std::path::Path;

/// Variants per cell.
pub const ENSEMBLE_SIZE: usize = 20;

/// One perturbed variant of a cell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Perturbation {
    /// Relative change of the clamps' rotation penalty.
    pub clamp: f64,
    /// Relative change of the time step.
    pub dt: f64,
    /// Threads of the variant's pool.
    pub threads: usize,
}

impl Perturbation {
    /// The settings of this variant of `settings`.
    pub fn apply(&self, settings: &Settings) -> Settings {
        Settings {
            clamp_factor: settings.clamp_factor * (1.0 + self.clamp),
            dt: settings.dt * (1.0 + self.dt),
            ..settings.clone()
        }
    }
}

/// The ensemble's first `n` perturbations, the same on every call and machine: magnitudes
/// log-uniform in \[1e-7, 1e-3\] with either sign, drawn from a fixed-seed SplitMix64 (a dozen lines;
/// `rand` is not a dependency of this crate and reproducibility across its versions is not promised), and
/// one and two threads alternating.
pub fn perturbations(n: usize) -> Vec<Perturbation> {
    let mut rng = SplitMix64(0x0022_5eed);
    (0..n)
        .map(|i| Perturbation {
            clamp: rng.relative_change(),
            dt: rng.relative_change(),
            threads: 1 + i % 2,
        })
        .collect()
}

/// Sebastiano Vigna's SplitMix64 generator.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in \[0, 1).
    fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    fn relative_change(&mut self) -> f64 {
        let magnitude = 10f64.powf(-7.0 + 4.0 * self.unit());
        if self.next_u64() & 1 == 0 {
            magnitude
        } else {
            -magnitude
        }
    }
}

/// Runs one variant in this process, on a thread pool of the variant's size.
///
/// # Errors
/// I/O failures of the output directory, or a thread pool that cannot be created.
pub fn run_variant(settings: &Settings, p: &Perturbation, dir: &Path) -> Result<CellResult> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(p.threads)
        .build()
        .context("creating the variant's thread pool")?;
    pool.install(|| run_cell(&Runner::InProcess, &p.apply(settings), dir))
}

/// What an ensemble of one cell showed.
#[derive(Debug, Clone, Default)]
pub struct EnsembleResult {
    /// Variants run.
    pub total: usize,
    /// Variants that completed with finite values.
    pub completed: usize,
    /// Completed variants with an inverted element.
    pub inverted: usize,
    /// Largest Newton iterations of a step over all variants.
    pub max_newton: u64,
    /// Average Newton iterations per step, averaged over the completed variants.
    pub avg_newton: f64,
    /// The failed variants.
    pub failures: Vec<VariantFailure>,
}

/// A variant that did not complete.
#[derive(Debug, Clone)]
pub struct VariantFailure {
    /// The variant's index in the ensemble.
    pub index: usize,
    /// Its perturbation.
    pub perturbation: Perturbation,
    /// Why it stopped.
    pub reason: String,
    /// The time of the last complete step, if the run got as far as to write its summary.
    pub stopped_at: Option<f64>,
}

impl EnsembleResult {
    /// Whether every variant completed.
    pub fn all_completed(&self) -> bool {
        self.completed == self.total
    }

    /// `completed/total`.
    pub fn rate(&self) -> String {
        format!("{}/{}", self.completed, self.total)
    }
}

/// Whether a run reached its end with finite values (inverted elements are counted apart).
pub fn completed(r: &CellResult) -> bool {
    r.outcome.is_ok() && !r.non_finite
}

/// The reason a variant did not complete.
pub fn failure_reason(r: &CellResult) -> String {
    if r.non_finite {
        "non-finite value".into()
    } else {
        r.outcome.reason()
    }
}

/// Runs `settings` with each of `perturbations`, the outputs under `dir/variant_NN` (removed after a
/// completed run, so that an ensemble does not fill the disk).
///
/// # Errors
/// As [`run_variant`].
pub fn run_ensemble(settings: &Settings, perturbations: &[Perturbation], dir: &Path) -> Result<EnsembleResult> {
    let mut e = EnsembleResult {
        total: perturbations.len(),
        ..EnsembleResult::default()
    };
    let mut newton_sum = 0.0;
    for (i, p) in perturbations.iter().enumerate() {
        let vdir = dir.join(format!("variant_{i:02}"));
        let r = run_variant(settings, p, &vdir)?;
        if let Some((avg, max)) = r.newton {
            e.max_newton = e.max_newton.max(max);
            if completed(&r) {
                newton_sum += avg;
            }
        }
        if completed(&r) {
            e.completed += 1;
            e.inverted += usize::from(r.inverted());
            std::fs::remove_dir_all(&vdir).ok();
        } else {
            e.failures.push(VariantFailure {
                index: i,
                perturbation: *p,
                reason: failure_reason(&r),
                stopped_at: r.outcome.summary.as_ref().and_then(|s| s.stopped_at),
            });
        }
    }
    e.avg_newton = newton_sum / e.completed.max(1) as f64;
    Ok(e)
}
