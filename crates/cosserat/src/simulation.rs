//! The simulation of a scene: builds the model's system with the scene's scripts, contact and probes,
//! advances it in time (or through load levels), and writes frames, probes and the run record.
//!
//! [`Simulation`] composes independently built parts — the [`Model`], the [`Scripts`], the optional
//! [`ContactRun`], the [`Probes`] — and only orchestrates them: before a step the scripts, the model's
//! rest fields and the contact's obstacles are set; after it the contact records its statistics; at
//! output times the model draws the frame and the contact adds its obstacles.

use crate::checkpoint::{Checkpoint, SceneOrigin, StepperState};
use crate::contact_run::ContactRun;
use crate::error::SimulationError;
use crate::memory::{MemoryEstimate, MemoryLimit};
use crate::model::{BuiltModel, Model};
use crate::outcome::{Outcome, OutputSchedule};
use crate::placement::ShellPlacement;
use crate::probes::Probes;
use crate::record::{RunStats, peak_memory_mb};
use crate::scripts::Scripts;
use crate::stop::StopRequest;
use cosserat_assembly::{IncrementalPotential, PSEUDO_TIME_STEP, SystemOptions};
use cosserat_io::{BoundingBox, RunStatus, RunSummary, RunWriter, VtuFrame, write_failure_summary};
use cosserat_scene::spec::{ModelKind, SceneSpec, SolverSpec, TimeSpec};
use cosserat_solver::{
    InitialGuess, QuasiStaticSettings, QuasiStaticStepper, ScriptError, StepError, StepReport, TimeStepSettings,
    TimeStepper,
};
use std::path::Path;
use std::time::Instant;

mod arc_length;
mod resume;

/// What the run loop reports after every step (for progress displays).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepInfo {
    /// Steps (or load levels) completed.
    pub step: usize,
    /// Time (or load factor) reached.
    pub t: f64,
    /// End time (or final load factor).
    pub end: f64,
    /// Time step used \[s\] (load increment in quasi-static runs).
    pub dt: f64,
    /// Newton iterations of the step.
    pub newton_iterations: usize,
    /// Final residual of the step \[N or N·m\].
    pub residual: f64,
}

/// A scene ready to run.
pub struct Simulation {
    name: String,
    time: TimeSpec,
    solver: SolverSpec,
    potential: IncrementalPotential,
    model: Box<dyn Model>,
    scripts: Scripts,
    contact: Option<ContactRun>,
    probes: Probes,
    write_frames: bool,
    frame_formats: cosserat_io::FrameFormats,
    rest_bbox: BoundingBox,
    /// Warnings about settings that physics or the discretisation limits ([`crate::advice`]) and about
    /// the inputs.
    advice: Vec<String>,
    /// The Cosserat shells' discretisation, for the summary.
    discretisation: DiscretisationNames,
    stats: RunStats,
    /// The time (or load factor) of the last committed state.
    t_reached: f64,
    /// Checkpoints and resuming.
    restart: Restart,
}

/// What a simulation needs to write checkpoints and to continue from one.
struct Restart {
    /// Steps between checkpoints (`output.checkpoint_every`).
    every: Option<usize>,
    /// [`crate::checkpoint::scene_fingerprint`] of the scene.
    fingerprint: u32,
    /// Where the scene came from.
    origin: Option<SceneOrigin>,
    /// The checkpoint the next run continues from.
    pending: Option<Checkpoint>,
    /// The step the run was resumed from.
    resumed_from: Option<usize>,
    /// Wall-clock time of the run before it was resumed \[s\].
    wall_before: f64,
    /// When the current part of the run started.
    started: Instant,
}

/// How a scene's Cosserat shells are discretised, as the summary names it: each field lists the
/// shells' values in shell order without repeats (`"-"` without Cosserat shells).
struct DiscretisationNames {
    /// Strain interpolations, e.g. `"regge_stabilized"`.
    strain_interpolation: String,
    /// Quadrature points per element, e.g. `"3"`.
    quadrature_points: String,
}

fn discretisation_names(spec: &SceneSpec) -> DiscretisationNames {
    let cosserat = || spec.shells.iter().filter(|s| matches!(s.model, ModelKind::Cosserat));
    let distinct = |names: Vec<String>| {
        let mut kept: Vec<String> = Vec::new();
        for name in names {
            if !kept.contains(&name) {
                kept.push(name);
            }
        }
        if kept.is_empty() { "-".into() } else { kept.join(",") }
    };
    let points = |s: &cosserat_scene::spec::ShellSpec| s.quadrature_rule().n_points().to_string();
    DiscretisationNames {
        strain_interpolation: distinct(cosserat().map(|s| s.rest.interpolation.name().to_string()).collect()),
        quadrature_points: distinct(cosserat().map(points).collect()),
    }
}

impl Simulation {
    /// Builds the model's system, boundary conditions, loads, rest fields, contact and probes of a
    /// scene, after checking that it fits into the machine's available memory
    /// ([`MemoryLimit::of_machine`]).
    ///
    /// # Errors
    /// Invalid meshes or materials (named by shell), unusable loads, a scene too large for the memory.
    pub fn new(spec: SceneSpec) -> Result<Self, SimulationError> {
        Self::with_memory_limit(spec, MemoryLimit::of_machine(None))
    }

    /// [`Simulation::new`] with the memory check against `limit` (`None`: no check).
    ///
    /// # Errors
    /// As [`Simulation::new`].
    pub fn with_memory_limit(spec: SceneSpec, limit: Option<MemoryLimit>) -> Result<Self, SimulationError> {
        if let Some(limit) = &limit {
            MemoryEstimate::of_scene(&spec).check(limit)?;
        }
        let mut advice = crate::advice::advise(&spec);
        advice.extend(spec.warnings.iter().cloned());
        let options = SystemOptions {
            gravity: spec.gravity,
            dynamic: matches!(spec.time, TimeSpec::Dynamic { .. }),
        };
        let BuiltModel { mut potential, model } = crate::model::build(&spec, &options)?;
        let contact = match &spec.contact {
            Some(c) => Some(ContactRun::build(c, model.as_ref(), &mut potential)?),
            None => None,
        };
        let scripts = Scripts::build(&spec, model.placements(), &mut potential)?;
        advice.extend(scripts.warnings().iter().cloned());
        let probes = Probes::new(&spec.probes, model.placements(), model.rest_positions());
        let rest_points: Vec<[f64; 3]> = model.rest_positions().iter().map(|x| [x.x, x.y, x.z]).collect();
        Ok(Self {
            name: spec.name.clone(),
            time: spec.time.clone(),
            solver: spec.solver,
            potential,
            model,
            scripts,
            contact,
            probes,
            write_frames: spec.output.frames,
            frame_formats: cosserat_io::FrameFormats {
                vtu: spec.output.formats.vtu,
                obj: spec.output.formats.obj,
                ply: spec.output.formats.ply,
                usd: spec.output.formats.usd,
            },
            rest_bbox: BoundingBox::of_points(&rest_points).unwrap_or_default(),
            advice,
            discretisation: discretisation_names(&spec),
            stats: RunStats::default(),
            t_reached: 0.0,
            restart: Restart {
                every: spec.output.checkpoint_every,
                fingerprint: crate::checkpoint::scene_fingerprint(&spec),
                origin: spec.source.clone().map(|path| SceneOrigin {
                    path,
                    overrides: Vec::new(),
                }),
                pending: None,
                resumed_from: None,
                wall_before: 0.0,
                started: Instant::now(),
            },
        })
    }

    /// Warnings about the scene's settings and inputs (also in `summary.json` under `warnings`).
    pub fn advice(&self) -> &[String] {
        &self.advice
    }

    /// The scene name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The incremental potential: state, parts and terms.
    pub fn potential(&self) -> &IncrementalPotential {
        &self.potential
    }

    /// The incremental potential, mutably (e.g. to change the parallelism or the state).
    pub fn potential_mut(&mut self) -> &mut IncrementalPotential {
        &mut self.potential
    }

    /// Where each shell of the scene is in the system.
    pub fn placements(&self) -> &[ShellPlacement] {
        self.model.placements()
    }

    /// Rest positions of all displacement nodes of the system \[m\].
    pub fn rest_positions(&self) -> &[nalgebra::Vector3<f64>] {
        self.model.rest_positions()
    }

    /// The scripted boundary conditions and loads.
    pub fn scripts(&self) -> &Scripts {
        &self.scripts
    }

    /// The scripted boundary conditions and loads, mutably: a controller sets targets and load scales
    /// between steps ([`Scripts::set_motion`], [`Scripts::set_load_scale`]).
    pub fn scripts_mut(&mut self) -> &mut Scripts {
        &mut self.scripts
    }

    /// The time (or load factor) of the last completed step.
    pub fn time(&self) -> f64 {
        self.t_reached
    }

    /// The output frame of the current state, as [`Simulation::run`] writes it at this time.
    pub fn frame(&self) -> VtuFrame {
        let mut frame = self.model.frame(&self.potential.parts.state, self.t_reached);
        if let Some(contact) = &self.contact {
            contact.decorate_frame(&mut frame);
        }
        frame
    }

    /// The contact of the run, when the scene has contact.
    pub fn contact(&self) -> Option<&ContactRun> {
        self.contact.as_ref()
    }

    /// A time stepper with the scene's time-step and solver settings, starting at `t = 0`.
    ///
    /// # Errors
    /// [`SimulationError::Setup`] for a quasi-static scene; a symbolic analysis failure.
    pub fn time_stepper(&self) -> Result<TimeStepper, SimulationError> {
        match &self.time {
            TimeSpec::Dynamic { dt, adaptive, .. } => Ok(TimeStepper::new(
                &self.potential,
                self.time_step_settings(*dt, *adaptive),
            )?),
            TimeSpec::QuasiStatic { .. } | TimeSpec::ArcLength { .. } => Err(SimulationError::Setup(
                "a quasi-static scene has no time stepper; use `run`".into(),
            )),
        }
    }

    /// Advances one time step with `stepper` (from [`Simulation::time_stepper`]): the step's scripts,
    /// rest fields and obstacles, the Newton solve with its retries, and the run statistics (contact
    /// included). Writes no output.
    ///
    /// # Errors
    /// [`StepError`] when every allowed attempt failed or a script value was not finite; the state is
    /// then unchanged.
    pub fn step(&mut self, stepper: &mut TimeStepper) -> Result<StepReport, StepError> {
        let t0 = Instant::now();
        let (scripts, model, contact) = (&mut self.scripts, &mut self.model, &mut self.contact);
        let result = stepper.try_step(&mut self.potential, &mut |p, t, dt| {
            prepare_step(scripts, model.as_mut(), contact.as_mut(), p, t, dt)
        });
        match result {
            Ok(report) => {
                if let Some(contact) = &mut self.contact {
                    contact.after_step(&self.potential);
                }
                self.stats.record_step(&report, t0.elapsed().as_secs_f64());
                self.t_reached = report.t;
                Ok(report)
            }
            Err(e) => {
                self.stats.reductions += e.attempts().len();
                self.stats.wasted_iterations += e
                    .attempts()
                    .iter()
                    .map(|a| a.error.residuals().len().saturating_sub(1))
                    .sum::<usize>();
                Err(e)
            }
        }
    }

    /// The columns of `probes.csv` after `t`: the probes', and first the load factor on an arc-length
    /// path, `path.load_factor` (where `t` counts the steps, since the load factor falls and rises).
    fn probe_columns(&self) -> Vec<String> {
        let mut columns = self.probes.columns();
        if matches!(self.time, TimeSpec::ArcLength { .. }) {
            columns.insert(0, "path.load_factor".into());
        }
        columns
    }

    /// Runs the scene and writes its outputs into `dir` (frames, `probes.csv`, `summary.json`).
    ///
    /// `progress` is called after every step (or load level). A `stop` request ends the run after the
    /// current step with status `interrupted`; a failed step (Newton failure after all reductions, a
    /// script value that is not finite) ends it with status `error`. Either way every complete step's
    /// frame and probe row stays, and the summary says where and why the run ended.
    ///
    /// # Errors
    /// Only I/O failures of the outputs that leave no summary written; physics failures are reported
    /// in the returned summary.
    pub fn run(
        &mut self,
        dir: &Path,
        progress: &mut dyn FnMut(&StepInfo),
        stop: &StopRequest,
    ) -> Result<RunSummary, SimulationError> {
        self.run_controlled(dir, &mut |info, _| progress(info), stop)
    }

    /// [`Simulation::run`] with a controller: `controller` is called after every step (or load level)
    /// with the scripts, whose targets and load scales it may set for the next step.
    ///
    /// # Errors
    /// As [`Simulation::run`].
    pub fn run_controlled(
        &mut self,
        dir: &Path,
        progress: &mut dyn FnMut(&StepInfo, &mut Scripts),
        stop: &StopRequest,
    ) -> Result<RunSummary, SimulationError> {
        self.restart.started = Instant::now();
        let resume = self.restart.pending.take();
        let mut writer = self.open_outputs(dir, resume.as_ref())?;
        let first = match resume {
            Some(_) => Ok(()),
            None => self.record_output(&mut writer, 0.0),
        };
        let outcome = match first {
            Ok(()) => match self.time.clone() {
                TimeSpec::Dynamic {
                    dt,
                    end,
                    adaptive,
                    output_interval,
                } => self.run_dynamic(
                    &mut writer,
                    (dt, end, adaptive, output_interval),
                    resume.as_ref(),
                    progress,
                    stop,
                ),
                TimeSpec::QuasiStatic { levels, adaptive } => {
                    self.run_quasi_static(&mut writer, (&levels, adaptive), resume.as_ref(), progress, stop)
                }
                TimeSpec::ArcLength {
                    initial_increment,
                    end,
                    max_steps,
                } => self.run_arc_length(&mut writer, initial_increment, end, max_steps, progress, stop),
            },
            Err(e) => Err(e),
        };
        // An output failure ends the run like a failed step: what was written stays, and the summary
        // says why the run stopped.
        let outcome = outcome.unwrap_or_else(|e| Outcome::Failed {
            t: self.t_reached,
            reason: format!("writing outputs: {e}"),
            step: None,
        });
        let summary = self.summary(self.wall_seconds(), outcome);
        writer.finish(&summary)?;
        Ok(summary)
    }

    /// The time loop: `(dt, end, adaptive, output interval)` from the scene.
    fn run_dynamic(
        &mut self,
        writer: &mut RunWriter,
        (dt, end, adaptive, output_interval): (f64, f64, bool, f64),
        resume: Option<&Checkpoint>,
        progress: &mut dyn FnMut(&StepInfo, &mut Scripts),
        stop: &StopRequest,
    ) -> Result<Outcome, SimulationError> {
        let mut stepper = TimeStepper::new(&self.potential, self.time_step_settings(dt, adaptive))?;
        let mut schedule = OutputSchedule::new(output_interval, dt);
        if let Some(checkpoint) = resume {
            self.resume_dynamic(checkpoint, &mut stepper, &mut schedule)?;
        }
        // Steps end at `end` up to round-off, which must not add a step of its own.
        while stepper.time() < end - 1e-9 * stepper.dt().min(dt) {
            if let Some(reason) = stop.reason() {
                return Ok(Outcome::Interrupted(stepper.time(), reason));
            }
            // A halved step shifts the time grid: the last step is shortened to end at `end` (steps
            // on the grid are left alone, so that their round-off does not change their length).
            let remaining = end - stepper.time();
            if remaining < stepper.dt() * (1.0 - 1e-9) {
                stepper.set_dt(remaining);
            }
            let result = self.step(&mut stepper);
            self.stats.factor = stepper.solver().linear_solver().symmetric_stats();
            let report = match result {
                Ok(report) => report,
                Err(e) => return Ok(Outcome::failed_step(&e)),
            };
            self.t_reached = report.t;
            let info = StepInfo {
                step: self.stats.steps,
                t: report.t,
                end,
                dt: report.dt,
                newton_iterations: report.iterations(),
                residual: report.newton.residual(),
            };
            progress(&info, &mut self.scripts);
            if schedule.due(report.t) {
                self.record_output(writer, report.t)?;
            }
            if self.checkpoint_due() {
                let state = StepperState::Dynamic {
                    t: stepper.time(),
                    dt: stepper.dt(),
                    next_output: schedule.next(),
                    newton: stepper.solver().carried(),
                    last_step: stepper.last_step().cloned(),
                };
                self.write_checkpoint(writer, state)?;
            }
        }
        Ok(Outcome::Completed)
    }

    /// The load levels, one equilibrium after the other.
    fn run_quasi_static(
        &mut self,
        writer: &mut RunWriter,
        (levels, adaptive): (&[f64], bool),
        resume: Option<&Checkpoint>,
        progress: &mut dyn FnMut(&StepInfo, &mut Scripts),
        stop: &StopRequest,
    ) -> Result<Outcome, SimulationError> {
        let defaults = QuasiStaticSettings::default();
        let settings = QuasiStaticSettings {
            newton: self.time_step_settings(PSEUDO_TIME_STEP, false).newton,
            increment_control: defaults.increment_control.filter(|_| adaptive),
            extrapolate: self.solver.initial_guess != InitialGuess::Zero,
            ..defaults
        };
        let (mut stepper, first) = match resume {
            Some(checkpoint) => self.resume_quasi_static(checkpoint, &settings, levels.len())?,
            None => (QuasiStaticStepper::new(&mut self.potential, &settings)?, 0),
        };
        let end = levels.last().copied().unwrap_or(1.0);
        let mut previous = stepper.load_factor();
        for (index, &target) in levels.iter().enumerate().skip(first) {
            if let Some(reason) = stop.reason() {
                return Ok(Outcome::Interrupted(stepper.load_factor(), reason));
            }
            let t0 = Instant::now();
            let (scripts, model, contact) = (&mut self.scripts, &mut self.model, &mut self.contact);
            let result = stepper.advance(&mut self.potential, target, &mut |p, lambda| {
                prepare_step(scripts, model.as_mut(), contact.as_mut(), p, lambda, 0.0)
            });
            self.stats.factor = stepper.solver().linear_solver().symmetric_stats();
            let report = match result {
                Ok(report) => report,
                Err(e) => {
                    self.stats.reductions += e.bisections;
                    self.stats.intermediate_levels += e.sub_levels;
                    return Ok(Outcome::failed_level(&e));
                }
            };
            if let Some(contact) = &mut self.contact {
                contact.after_step(&self.potential);
            }
            self.stats.record_level(&report, t0.elapsed().as_secs_f64());
            self.t_reached = target;
            let info = StepInfo {
                step: self.stats.steps,
                t: target,
                end,
                dt: target - previous,
                newton_iterations: report.total_iterations,
                residual: report.newton.residual(),
            };
            progress(&info, &mut self.scripts);
            self.record_output(writer, target)?;
            if self.checkpoint_due() {
                let state = StepperState::QuasiStatic {
                    levels_done: index + 1,
                    load_factor: stepper.load_factor(),
                    predictor: stepper.predictor().clone(),
                    increment_limit: stepper.increment_limit(),
                    newton: stepper.solver().carried(),
                };
                self.write_checkpoint(writer, state)?;
            }
            previous = target;
        }
        Ok(Outcome::Completed)
    }

    fn time_step_settings(&self, dt: f64, adaptive: bool) -> TimeStepSettings {
        let mut s = TimeStepSettings::fixed(dt);
        s.adaptive = adaptive;
        s.max_reductions = self.solver.max_step_reductions;
        s.initial_guess = self.solver.initial_guess;
        s.newton.tolerance = self.solver.tolerance;
        s.newton.max_iterations = self.solver.max_newton_iterations;
        s.newton.max_line_search_iterations = self.solver.max_line_search_iterations;
        s.newton.indefinite_hessian = self.solver.indefinite_hessian;
        s.newton.linear_solver.kind = self.solver.linear_solver;
        s.newton.linear_solver.domains = self.solver.domain_split;
        s.newton.reuse_max_ratio = self.solver.reuse_factorisation;
        s.newton.mixed_integration_points = self.solver.mixed_integration_points;
        s
    }

    /// Writes the frame and the probe row of the current state at time `t`, with its energies.
    fn record_output(&mut self, writer: &mut RunWriter, t: f64) -> Result<(), SimulationError> {
        let elastic = self.potential.elastic_energy().unwrap_or(f64::NAN);
        self.stats.energy.push(t, self.potential.kinetic_energy(), elastic);
        let state = &self.potential.parts.state;
        for s in &self.potential.parts.shells {
            self.stats.min_area_ratio = self.stats.min_area_ratio.min(s.min_area_ratio(state));
        }
        if self.write_frames {
            let mut frame = self.model.frame(state, t);
            if let Some(contact) = &self.contact {
                contact.decorate_frame(&mut frame);
            }
            writer.write_frame(&frame)?;
            self.stats.frames += 1;
        }
        let mut row = self.probes.values(state);
        if matches!(self.time, TimeSpec::ArcLength { .. }) {
            row.insert(0, self.t_reached);
        }
        writer.write_probes(t, &row)?;
        Ok(())
    }

    /// The run record.
    fn summary(&self, wall: f64, outcome: Outcome) -> RunSummary {
        let s = &self.stats;
        let (status, reason, stopped_at, failed_step) = match outcome {
            Outcome::Completed => (RunStatus::Ok, None, None, None),
            Outcome::Interrupted(t, why) => (RunStatus::Interrupted, Some(why.describe().to_string()), Some(t), None),
            Outcome::Failed { t, reason, step } => (RunStatus::Error, Some(reason), Some(t), step),
        };
        let mut warnings = self.advice.clone();
        warnings.extend(s.convergence.warning());
        if s.min_area_ratio <= 0.0 {
            warnings.push(format!(
                "an element turned inside out during the run (smallest deformed-to-rest area ratio {:.3}): \
                 the steps converged, but the result is not to be trusted; refine the mesh or reduce the time step",
                s.min_area_ratio
            ));
        }
        let (displacement_element, rotation_element) = self.model.element_names();
        let layout = &self.potential.parts.layout;
        RunSummary {
            scene: self.name.clone(),
            status,
            reason,
            stopped_at,
            failed_step,
            resumed_from: self.restart.resumed_from,
            model: self.model.record(),
            displacement_element,
            rotation_element,
            strain_interpolation: self.discretisation.strain_interpolation.clone(),
            quadrature_points: self.discretisation.quadrature_points.clone(),
            n_shells: self.model.placements().len(),
            n_cells: self.model.n_cells(),
            n_displacement_dofs: 3 * layout.n_disp_nodes,
            n_rotation_dofs: 3 * layout.n_rot_nodes,
            n_curved_points: self.model.n_curved_points(),
            active_terms: self.potential.active_terms(),
            hessian_nnz: self.potential.pattern().nnz(),
            dt: match &self.time {
                TimeSpec::Dynamic { dt, .. } => *dt,
                TimeSpec::QuasiStatic { .. } | TimeSpec::ArcLength { .. } => PSEUDO_TIME_STEP,
            },
            n_steps: s.steps,
            n_frames: s.frames,
            avg_newton_iterations: s.avg_newton_iterations(),
            max_newton_iterations: s.max_newton_iterations,
            wasted_newton_iterations: s.wasted_iterations,
            n_step_reductions: s.reductions,
            n_intermediate_levels: s.intermediate_levels,
            wall_seconds: wall,
            avg_step_ms: s.avg_step_ms(),
            // Shares of the time in steps, not of the whole run, whose set-up, symbolic analysis and
            // output lie outside the steps.
            assembly_share: s.share_of_steps(s.assembly_seconds),
            linear_solve_share: s.share_of_steps(s.solve_seconds),
            peak_memory_mb: peak_memory_mb(),
            linear_solver: s.linear_solver(),
            min_area_ratio: s.min_area_ratio.is_finite().then_some(s.min_area_ratio),
            contact: self.contact.as_ref().map(|c| c.record(&self.potential, s.step_seconds)),
            warnings,
            energy: s.energy.clone(),
            rest_bbox: self.rest_bbox,
            convergence: s.convergence.summary(self.solver.tolerance),
        }
    }
}

/// Sets everything a step (or load level) from `t` over `dt` needs before its solve: the scripted
/// targets and loads, the model's rest fields, and the contact's obstacles at the end of the step.
fn prepare_step(
    scripts: &mut Scripts,
    model: &mut dyn Model,
    contact: Option<&mut ContactRun>,
    potential: &mut IncrementalPotential,
    t: f64,
    dt: f64,
) -> Result<(), ScriptError> {
    if let Some(contact) = contact {
        contact.before_step(potential, t + dt);
    }
    scripts.apply(potential, t, dt)?;
    model.apply_rest_fields(potential, t, dt)
}

/// Writes a summary for a scene that could not even be set up (invalid input): `dir` then holds only
/// `summary.json` with status `error`.
///
/// # Errors
/// I/O failures.
pub fn write_setup_failure(dir: &Path, scene: &str, reason: &str) -> Result<(), SimulationError> {
    write_failure_summary(dir, &RunSummary::failed(scene, RunStatus::Error, reason))?;
    Ok(())
}
