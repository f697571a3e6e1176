//! How a run ended ([`Outcome`]) and when it writes its frames ([`OutputSchedule`]).

use cosserat_io::{Attempt, FailedStep};
use cosserat_solver::{LevelFailure, StaticError, StepError};

use crate::stop::StopReason;

/// How a run ended.
pub(crate) enum Outcome {
    Completed,
    /// Stopped on request at this time (or load factor).
    Interrupted(f64, StopReason),
    /// A step failed (`step` has its attempts) or an output could not be written.
    Failed {
        t: f64,
        reason: String,
        step: Option<FailedStep>,
    },
}

impl Outcome {
    /// The outcome of a time step that failed.
    pub(crate) fn failed_step(e: &StepError) -> Self {
        let reason = e.to_string();
        Outcome::Failed {
            t: e.t(),
            step: Some(FailedStep {
                t: e.t(),
                attempts: e.attempts().iter().map(|a| attempt(a.dt, &a.error)).collect(),
                reason: reason.clone(),
            }),
            reason,
        }
    }

    /// The outcome of a load level that could not be reached.
    pub(crate) fn failed_level(e: &StaticError) -> Self {
        let reason = e.to_string();
        let attempts = match &e.error {
            LevelFailure::Newton(error) => vec![attempt(e.to - e.from, error)],
            LevelFailure::Scripts(_) => Vec::new(),
        };
        Outcome::Failed {
            t: e.from,
            step: Some(FailedStep {
                t: e.from,
                attempts,
                reason: reason.clone(),
            }),
            reason,
        }
    }
}

/// The summary's record of a failed Newton attempt.
fn attempt(dt: f64, error: &cosserat_solver::NewtonError) -> Attempt {
    Attempt {
        dt,
        reason: error.to_string(),
        residuals: error.residuals().iter().copied().filter(|r| r.is_finite()).collect(),
    }
}

/// When a dynamic run writes its frames: at multiples of the output interval, the first step at or
/// after each. The next output time comes from the index of the last one, not from repeated
/// additions, so it always moves past the current time and the schedule cannot stall.
pub(crate) struct OutputSchedule {
    interval: f64,
    /// Slack for round-off in the step times.
    slack: f64,
    next: f64,
}

impl OutputSchedule {
    pub(crate) fn new(interval: f64, dt: f64) -> Self {
        Self {
            interval,
            slack: 1e-9 * dt,
            next: interval,
        }
    }

    /// The time of the next frame (saved in checkpoints).
    pub(crate) fn next(&self) -> f64 {
        self.next
    }

    /// Continues a schedule whose next frame is due at `next` (a run resumed from a checkpoint).
    pub(crate) fn resume_at(&mut self, next: f64) {
        self.next = next;
    }

    /// Whether a frame is due at time `t`; if so, the schedule moves to the next multiple after `t`.
    pub(crate) fn due(&mut self, t: f64) -> bool {
        if t < self.next - self.slack {
            return false;
        }
        let index = ((t + self.slack) / self.interval).floor() + 1.0;
        self.next = (index * self.interval).max(t + self.slack);
        true
    }
}
