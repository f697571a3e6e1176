//! Checks of `\[time\]`, `\[solver\]` and `\[output\]`.

use super::Ctx;
use crate::error::{Num, SceneError};
use crate::schema::{
    DomainSplitName, FrameFormatName, IndefiniteHessianName, InitialGuessName, LinearSolverName, OutputSection,
    SolverSection, TimeMode, TimeSection,
};
use crate::spec::{FrameFormats, OutputSpec, SolverSpec, TimeSpec};
use cosserat_solver::linear::{DomainSplit, LinearSolverKind};
use cosserat_solver::time_step::InitialGuess;
use cosserat_solver::{IndefiniteHessian, Tolerance};

/// Output rate when a dynamic scene gives none: the reference code's 30 frames per second.
const DEFAULT_OUTPUT_FPS: f64 = 30.0;

/// Number of equally spaced times at which scripted functions are checked (plus the end points).
const N_SAMPLE_TIMES: usize = 200;

/// Highest allowed frame subdivision level (each level multiplies the output triangles by 4).
const MAX_SUBDIVISION: usize = 4;

/// The most load levels of a quasi-static run, or steps of a path (each is a Newton solve and an
/// output).
const MAX_LEVELS: usize = 100_000;

/// The first load-factor increment of an arc-length path when the scene gives none.
const DEFAULT_INITIAL_INCREMENT: f64 = 0.05;

/// The most steps of an arc-length path when the scene gives none.
const DEFAULT_MAX_PATH_STEPS: usize = 1000;

/// The most time steps a dynamic run may ask for (`end / dt`): far beyond any run that finishes.
const MAX_STEPS: f64 = 1e9;

impl Ctx<'_> {
    pub(super) fn time(&mut self, time: &TimeSection) -> Result<TimeSpec, SceneError> {
        match time.mode.unwrap_or(TimeMode::Dynamic) {
            TimeMode::Dynamic => self.dynamic_time(time),
            TimeMode::QuasiStatic => self.quasi_static_time(time),
            TimeMode::ArcLength => self.arc_length_time(time),
        }
    }

    fn dynamic_time(&mut self, time: &TimeSection) -> Result<TimeSpec, SceneError> {
        self.refuse(
            time,
            &["levels", "n_levels", "initial_increment", "max_steps"],
            "dynamic",
        )?;
        let dt = time.dt.ok_or_else(|| self.invalid("time.dt", "required in dynamic mode"))?;
        let dt = self.positive("time.dt", dt)?;
        let end = time.end.ok_or_else(|| self.invalid("time.end", "required in dynamic mode"))?;
        if !(end.is_finite() && end >= 0.0) {
            return Err(self.invalid(
                "time.end",
                format!("must be finite and non-negative (got {})", Num(end)),
            ));
        }
        if end / dt > MAX_STEPS {
            return Err(self.invalid(
                "time.dt",
                format!(
                    "end / dt = {:.3e} steps is more than the limit of {MAX_STEPS:e}",
                    end / dt
                ),
            ));
        }
        let output_interval = match (time.output_fps, time.output_interval) {
            (Some(_), Some(_)) => {
                return Err(self.invalid(
                    "time.output_interval",
                    "give `output_fps` or `output_interval`, not both",
                ));
            }
            (Some(fps), None) => 1.0 / self.positive("time.output_fps", fps)?,
            (None, Some(interval)) => self.positive("time.output_interval", interval)?,
            (None, None) => 1.0 / DEFAULT_OUTPUT_FPS,
        };
        // The run's times go up to end + dt; an interval that vanishes next to them cannot
        // advance the output schedule.
        let latest = end + dt;
        if latest + output_interval == latest {
            let field = if time.output_fps.is_some() {
                "time.output_fps"
            } else {
                "time.output_interval"
            };
            return Err(self.invalid(
                field,
                format!(
                    "an output interval of {} s is below the resolution of the run's times \
                     (up to {} s); frames are written at most once per step, so an interval of \
                     time.dt = {} s already writes every step",
                    Num(output_interval),
                    Num(latest),
                    Num(dt)
                ),
            ));
        }
        // Scripts are evaluated at tⁿ or tⁿ + Δt, and the last step may pass the end by up to Δt.
        let last = end + dt;
        self.sample_times = (0..=N_SAMPLE_TIMES).map(|k| last * k as f64 / N_SAMPLE_TIMES as f64).collect();
        Ok(TimeSpec::Dynamic {
            dt,
            end,
            adaptive: time.adaptive.unwrap_or(true),
            output_interval,
        })
    }

    fn quasi_static_time(&mut self, time: &TimeSection) -> Result<TimeSpec, SceneError> {
        self.refuse(
            time,
            &[
                "dt",
                "end",
                "output_fps",
                "output_interval",
                "initial_increment",
                "max_steps",
            ],
            "quasi_static",
        )?;
        let levels = match (&time.levels, time.n_levels) {
            (Some(_), Some(_)) => {
                return Err(self.invalid("time.n_levels", "give `levels` or `n_levels`, not both"));
            }
            (None, None) => {
                return Err(self.invalid("time", "quasi-static mode needs `levels` or `n_levels`"));
            }
            (None, Some(0)) => return Err(self.invalid("time.n_levels", "must be at least 1")),
            (None, Some(n)) if n > MAX_LEVELS => {
                return Err(self.invalid("time.n_levels", format!("must be at most {MAX_LEVELS} (got {n})")));
            }
            (None, Some(n)) => (1..=n).map(|k| k as f64 / n as f64).collect(),
            (Some(levels), None) => {
                let valid = !levels.is_empty()
                    && levels.iter().all(|l| l.is_finite() && *l > 0.0 && *l <= 1.0)
                    && levels.windows(2).all(|w| w[0] < w[1])
                    && levels.last() == Some(&1.0);
                if !valid {
                    return Err(self.invalid(
                        "time.levels",
                        format!("must increase strictly within (0, 1] and end at 1 (got {levels:?})"),
                    ));
                }
                levels.clone()
            }
        };
        self.sample_times = std::iter::once(0.0).chain(levels.iter().copied()).collect();
        Ok(TimeSpec::QuasiStatic {
            levels,
            adaptive: time.adaptive.unwrap_or(true),
        })
    }

    /// `arc_length`: every equilibrium along the path is written; the load factor may fall below zero
    /// and rise beyond `end` on the way (scripts are checked from −2 `end` to 2 `end`).
    fn arc_length_time(&mut self, time: &TimeSection) -> Result<TimeSpec, SceneError> {
        self.refuse(
            time,
            &["dt", "output_fps", "output_interval", "adaptive", "levels", "n_levels"],
            "arc_length",
        )?;
        let end = time.end.unwrap_or(1.0);
        if !(end.is_finite() && end > 0.0) {
            return Err(self.invalid("time.end", format!("must be a positive load factor (got {})", Num(end))));
        }
        let initial_increment = time.initial_increment.unwrap_or(DEFAULT_INITIAL_INCREMENT);
        if !(initial_increment.is_finite() && initial_increment > 0.0 && initial_increment <= end) {
            return Err(self.invalid(
                "time.initial_increment",
                format!("must lie in (0, end = {}] (got {})", Num(end), Num(initial_increment)),
            ));
        }
        let max_steps = time.max_steps.unwrap_or(DEFAULT_MAX_PATH_STEPS);
        if max_steps == 0 || max_steps > MAX_LEVELS {
            return Err(self.invalid(
                "time.max_steps",
                format!("must lie between 1 and {MAX_LEVELS} (got {max_steps})"),
            ));
        }
        self.sample_times = (0..=N_SAMPLE_TIMES)
            .map(|k| end * (4.0 * k as f64 / N_SAMPLE_TIMES as f64 - 2.0))
            .collect();
        Ok(TimeSpec::ArcLength {
            initial_increment,
            end,
            max_steps,
        })
    }

    /// Refuses the `keys` of `[time]` that `mode` does not use.
    fn refuse(&self, time: &TimeSection, keys: &[&str], mode: &str) -> Result<(), SceneError> {
        let given = |key: &str| match key {
            "dt" => time.dt.is_some(),
            "end" => time.end.is_some(),
            "output_fps" => time.output_fps.is_some(),
            "output_interval" => time.output_interval.is_some(),
            "adaptive" => time.adaptive.is_some(),
            "levels" => time.levels.is_some(),
            "n_levels" => time.n_levels.is_some(),
            "initial_increment" => time.initial_increment.is_some(),
            "max_steps" => time.max_steps.is_some(),
            _ => false,
        };
        match keys.iter().find(|k| given(k)) {
            Some(key) => Err(self.invalid(&format!("time.{key}"), format!("not used in `{mode}` mode"))),
            None => Ok(()),
        }
    }

    pub(super) fn solver(&self, solver: Option<&SolverSection>, time: &TimeSpec) -> Result<SolverSpec, SceneError> {
        let d = default_solver(time);
        let Some(s) = solver else {
            return Ok(d);
        };
        let tolerance = match (s.tolerance, s.relative_tolerance) {
            (Some(_), Some(_)) => {
                return Err(self.invalid(
                    "solver.relative_tolerance",
                    "give an absolute `tolerance` or a `relative_tolerance`, not both",
                ));
            }
            (Some(t), None) => Tolerance::Absolute(self.positive("solver.tolerance", t)?),
            (None, Some(r)) if r.is_finite() && r > 0.0 && r < 1.0 => Tolerance::Relative(r),
            (None, Some(r)) => {
                return Err(self.invalid(
                    "solver.relative_tolerance",
                    format!("must lie in (0, 1) (got {})", Num(r)),
                ));
            }
            (None, None) => d.tolerance,
        };
        let reuse_factorisation = match s.reuse_factorisation {
            Some(r) if !(r.is_finite() && (0.0..1.0).contains(&r)) => {
                return Err(self.invalid(
                    "solver.reuse_factorisation",
                    format!(
                        "must lie in [0, 1): the residual reduction per iteration below which the \
                         factorisation is kept, 0 for none (got {})",
                        Num(r)
                    ),
                ));
            }
            Some(0.0) => None,
            Some(_) if matches!(time, TimeSpec::ArcLength { .. }) => {
                return Err(self.invalid(
                    "solver.reuse_factorisation",
                    "not used in `arc_length` mode (the corrector factorises the tangent every iteration)",
                ));
            }
            r => r,
        };
        let initial_guess = self.initial_guess(s.initial_guess, time)?;
        let max_newton_iterations = s.max_newton_iterations.unwrap_or(d.max_newton_iterations);
        if max_newton_iterations == 0 {
            return Err(self.invalid("solver.max_newton_iterations", "must be at least 1"));
        }
        Ok(SolverSpec {
            tolerance,
            max_newton_iterations,
            max_line_search_iterations: s.max_line_search_iterations.unwrap_or(d.max_line_search_iterations),
            linear_solver: match s.linear_solver {
                None | Some(LinearSolverName::Auto) => LinearSolverKind::Auto,
                Some(LinearSolverName::Cholesky) => LinearSolverKind::Cholesky,
                Some(LinearSolverName::Ldlt) => LinearSolverKind::Ldlt,
                Some(LinearSolverName::Lu) => LinearSolverKind::Lu,
                Some(LinearSolverName::Cg) => LinearSolverKind::Cg,
            },
            domain_split: match s.domain_split {
                None | Some(DomainSplitName::Auto) => DomainSplit::Auto,
                Some(DomainSplitName::Off) => DomainSplit::Off,
                Some(DomainSplitName::Always) => DomainSplit::Always,
            },
            initial_guess,
            project_pd: s.project_pd.unwrap_or(d.project_pd),
            indefinite_hessian: match s.indefinite_hessian {
                None => d.indefinite_hessian,
                Some(IndefiniteHessianName::Shift) => IndefiniteHessian::Shift,
                Some(IndefiniteHessianName::Adaptive) => IndefiniteHessian::Adaptive,
                Some(IndefiniteHessianName::Factorise) => IndefiniteHessian::Factorise,
            },
            max_step_reductions: s.max_step_reductions.unwrap_or(d.max_step_reductions),
            reuse_factorisation,
            mixed_integration_points: s.mixed_integration_points.unwrap_or(d.mixed_integration_points),
        })
    }

    /// Newton's start: a quasi-static level starts from an extrapolation or from the last equilibrium
    /// alone.
    fn initial_guess(&self, name: Option<InitialGuessName>, time: &TimeSpec) -> Result<InitialGuess, SceneError> {
        Ok(match name {
            Some(InitialGuessName::PreviousVelocity | InitialGuessName::LeastEnergy)
                if matches!(time, TimeSpec::QuasiStatic { .. }) =>
            {
                return Err(self.invalid(
                    "solver.initial_guess",
                    "in `quasi_static` mode a level starts from the last increments extrapolated \
                     (`\"extrapolated\"`, the default) or from the last equilibrium (`\"zero\"`)",
                ));
            }
            Some(InitialGuessName::PreviousVelocity) => InitialGuess::PreviousVelocity,
            Some(InitialGuessName::Zero) => InitialGuess::Zero,
            None | Some(InitialGuessName::Extrapolated) => InitialGuess::Extrapolated,
            Some(InitialGuessName::LeastEnergy) => InitialGuess::LeastEnergy,
        })
    }

    pub(super) fn output(&self, output: Option<&OutputSection>, time: &TimeSpec) -> Result<OutputSpec, SceneError> {
        let frames = output.and_then(|o| o.frames).unwrap_or(true);
        let subdivision = output.and_then(|o| o.subdivision).unwrap_or(1);
        if subdivision > MAX_SUBDIVISION {
            return Err(self.invalid(
                "output.subdivision",
                format!("must be at most {MAX_SUBDIVISION} (got {subdivision})"),
            ));
        }
        let formats = self.frame_formats(output.and_then(|o| o.formats.as_deref()))?;
        let checkpoint_every = output.and_then(|o| o.checkpoint_every);
        if checkpoint_every == Some(0) {
            return Err(self.invalid("output.checkpoint_every", "must be at least 1 step"));
        }
        if checkpoint_every.is_some() && matches!(time, TimeSpec::ArcLength { .. }) {
            return Err(self.invalid(
                "output.checkpoint_every",
                "arc-length runs cannot be checkpointed yet (the path tracer's state is not saved)",
            ));
        }
        if checkpoint_every.is_some() && frames && formats.usd {
            return Err(self.invalid(
                "output.checkpoint_every",
                "cannot be combined with USD frames (the stage is assembled at the end of a run); \
                 drop `usd` from `output.formats`",
            ));
        }
        Ok(OutputSpec {
            frames,
            subdivision,
            formats,
            checkpoint_every,
        })
    }

    /// The frame formats named by `output.formats` (default VTU), each at most once.
    fn frame_formats(&self, names: Option<&[FrameFormatName]>) -> Result<FrameFormats, SceneError> {
        let names = names.unwrap_or(&[FrameFormatName::Vtu]);
        if names.is_empty() {
            return Err(self.invalid(
                "output.formats",
                "lists no format; set `frames = false` to write no frames",
            ));
        }
        // A format named twice would still be written once: the repeat is more likely a slip for another
        // format than a request.
        for (k, name) in names.iter().enumerate() {
            if let Some(first) = names[..k].iter().position(|n| n == name) {
                return Err(self.invalid(
                    "output.formats",
                    format!(
                        "lists `{}` twice (entries {} and {}); name each format once",
                        name.as_str(),
                        first + 1,
                        k + 1
                    ),
                ));
            }
        }
        let has = |f: FrameFormatName| names.contains(&f);
        Ok(FrameFormats {
            vtu: has(FrameFormatName::Vtu),
            obj: has(FrameFormatName::Obj),
            ply: has(FrameFormatName::Ply),
            usd: has(FrameFormatName::Usd),
        })
    }
}

/// The solver's defaults (the paper's, experiments.md §1.5, where the reference has them), with a
/// relative tolerance instead of its absolute 1e-7 (which scenes can still give); the tolerance and
/// the treatment of indefinite Hessians depend on the kind of run (see
/// [`Tolerance::DEFAULT_RELATIVE_DYNAMIC`] and [`QuasiStaticSettings::newton`](cosserat_solver::QuasiStaticSettings::newton)).
fn default_solver(time: &TimeSpec) -> SolverSpec {
    let (relative, indefinite_hessian) = match time {
        TimeSpec::Dynamic { .. } => (Tolerance::DEFAULT_RELATIVE_DYNAMIC, IndefiniteHessian::Shift),
        TimeSpec::QuasiStatic { .. } => (Tolerance::DEFAULT_RELATIVE, IndefiniteHessian::Factorise),
        TimeSpec::ArcLength { .. } => (Tolerance::DEFAULT_RELATIVE, IndefiniteHessian::Shift),
    };
    SolverSpec {
        tolerance: Tolerance::Relative(relative),
        max_newton_iterations: 100,
        max_line_search_iterations: 20,
        linear_solver: LinearSolverKind::Auto,
        domain_split: DomainSplit::Auto,
        initial_guess: InitialGuess::Extrapolated,
        project_pd: false,
        indefinite_hessian,
        max_step_reductions: 8,
        reuse_factorisation: None,
        mixed_integration_points: matches!(time, TimeSpec::QuasiStatic { .. }),
    }
}
