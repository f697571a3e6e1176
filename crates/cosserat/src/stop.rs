//! [`StopRequest`]: asks a running simulation to stop after its current step, from a signal handler,
//! another thread or a controller between steps.

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Why a run was asked to stop.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StopReason {
    /// SIGINT (Ctrl-C).
    Interrupt,
    /// SIGTERM (a scheduler or `kill` asking the process to end).
    Terminate,
    /// A request from the program itself ([`StopRequest::request`]).
    Requested,
}

impl StopReason {
    /// The conventional exit status of a process that ended for this reason: 128 + the signal number
    /// for signals (130 for SIGINT, 143 for SIGTERM), 130 for a request.
    pub fn exit_code(self) -> i32 {
        match self {
            StopReason::Interrupt | StopReason::Requested => 130,
            StopReason::Terminate => 143,
        }
    }

    /// A sentence for the run summary.
    pub fn describe(self) -> &'static str {
        match self {
            StopReason::Interrupt => "interrupted by SIGINT (Ctrl-C)",
            StopReason::Terminate => "interrupted by SIGTERM",
            StopReason::Requested => "stopped on request",
        }
    }

    fn code(self) -> usize {
        match self {
            StopReason::Interrupt => SIGINT,
            StopReason::Terminate => SIGTERM,
            StopReason::Requested => REQUESTED,
        }
    }
}

/// The signal numbers stored in the flag (as `signal_hook::flag::register_usize` writes them).
const SIGINT: usize = 2;
const SIGTERM: usize = 15;
const REQUESTED: usize = usize::MAX;

/// A shared stop flag. Cloning shares the flag. The run loops check it between steps, so a stop takes
/// effect after the current step; every complete step stays in the outputs.
#[derive(Debug, Clone, Default)]
pub struct StopRequest {
    flag: Arc<AtomicUsize>,
}

impl StopRequest {
    /// A request that is not set.
    pub fn new() -> Self {
        Self::default()
    }

    /// Asks the run to stop after its current step (the first reason given wins).
    pub fn request(&self, reason: StopReason) {
        let _ = self.flag.compare_exchange(0, reason.code(), Ordering::SeqCst, Ordering::SeqCst);
    }

    /// Why a stop was requested, if it was.
    pub fn reason(&self) -> Option<StopReason> {
        match self.flag.load(Ordering::SeqCst) {
            0 => None,
            SIGINT => Some(StopReason::Interrupt),
            SIGTERM => Some(StopReason::Terminate),
            _ => Some(StopReason::Requested),
        }
    }

    /// The flag itself, for signal handlers that store the signal number into it: 0 means "run on",
    /// 2 SIGINT, 15 SIGTERM, any other value a request.
    pub fn flag(&self) -> Arc<AtomicUsize> {
        self.flag.clone()
    }
}
