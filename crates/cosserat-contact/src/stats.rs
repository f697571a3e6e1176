//! Counters and coverage reports of the contact term, for run summaries and step control.

use crate::candidate_cache::CacheCounters;
use std::time::Duration;

/// Counters of the contact term, for summaries.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactStats {
    /// Candidate pairs of the current step.
    pub n_candidates: usize,
    /// Pairs within the barrier's reach at the last evaluation.
    pub n_active: usize,
    /// Pairs with lagged friction in the current step.
    pub n_friction: usize,
    /// The smallest gap (distance minus thickness) among the candidates at the last evaluation \[m\]
    /// (`+∞` without candidates).
    pub min_gap: f64,
    /// Evaluations (value, gradient or Hessian) since construction.
    pub n_evaluations: usize,
    /// CCD queries (`max_step_fraction`, `obstacle_motion_fractions`) since construction.
    pub n_ccd_queries: usize,
    /// Step fractions returned by `max_step_fraction` since construction.
    pub n_step_limits: usize,
    /// Their sum (their mean is the mean CCD step fraction).
    pub step_fraction_sum: f64,
    /// Of those, the fractions below 1 (a step cut short by CCD).
    pub n_step_cuts: usize,
    /// Counters of the candidate cache that answers the broad phases.
    pub cache: CacheCounters,
    /// Time spent in broad phases since construction.
    pub broad_phase_time: Duration,
    /// Time spent in narrow-phase CCD since construction.
    pub ccd_time: Duration,
    /// Time spent evaluating energies and derivatives since construction.
    pub energy_time: Duration,
}

impl Default for ContactStats {
    fn default() -> Self {
        Self {
            n_candidates: 0,
            n_active: 0,
            n_friction: 0,
            min_gap: f64::INFINITY,
            n_evaluations: 0,
            n_ccd_queries: 0,
            n_step_limits: 0,
            step_fraction_sum: 0.0,
            n_step_cuts: 0,
            cache: CacheCounters::default(),
            broad_phase_time: Duration::ZERO,
            ccd_time: Duration::ZERO,
            energy_time: Duration::ZERO,
        }
    }
}

impl ContactStats {
    /// These counters continued from `earlier` ones (a run resumed from a checkpoint): the counts and
    /// times since construction are summed, the state of the current step is this one's.
    pub fn continuing(&self, earlier: &ContactStats) -> ContactStats {
        let (a, b) = (&self.cache, &earlier.cache);
        ContactStats {
            n_evaluations: self.n_evaluations + earlier.n_evaluations,
            n_ccd_queries: self.n_ccd_queries + earlier.n_ccd_queries,
            n_step_limits: self.n_step_limits + earlier.n_step_limits,
            step_fraction_sum: self.step_fraction_sum + earlier.step_fraction_sum,
            n_step_cuts: self.n_step_cuts + earlier.n_step_cuts,
            cache: CacheCounters {
                queries: a.queries + b.queries,
                requeries: a.requeries + b.requeries,
                builds: a.builds + b.builds,
                uncached: a.uncached + b.uncached,
            },
            broad_phase_time: self.broad_phase_time + earlier.broad_phase_time,
            ccd_time: self.ccd_time + earlier.ccd_time,
            energy_time: self.energy_time + earlier.energy_time,
            ..*self
        }
    }
}

/// Pairs within reach of a configuration, and whether the candidates cover them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Coverage {
    /// The smallest gap over all pairs within reach \[m\] (`+∞` if none).
    pub min_gap: f64,
    /// Pairs with a gap below the barrier width.
    pub n_active: usize,
    /// Of those, pairs that are not candidates of the current step (their barrier is missing).
    pub n_uncovered: usize,
}
