//! The simulation of a scene: builds the system from a [`SceneSpec`], advances it in time (or through
//! load levels), and writes frames, probes and the run summary.
//!
//! [`Simulation`] composes independently built parts — the system (potential and shell layouts), the
//! scripts, the probes, the output sampling — and only orchestrates them.

use crate::contact_run::{ContactMonitor, build_contact_term, contact_parts};
use crate::convergence::ConvergenceStats;
use crate::error::SimulationError;
use crate::frames::{OutputMesh, append_obstacles};
use crate::kl_model::{self, KlModel};
use crate::memory::{MemoryEstimate, MemoryLimit};
use crate::probes::Probes;
use crate::scripts::Scripts;
use crate::stop::{StopReason, StopRequest};
use crate::volume_model::{self, VolumeModel};
use cosserat_assembly::term::{Evaluation, NodeRotations};
use cosserat_assembly::{
    ElementPair, IncrementalPotential, Parallelism, PotentialTerm, ShellInput, System, SystemOptions, build_system,
};
use cosserat_contact::ContactTerm;
use cosserat_scene::output::VtuFrame;
use cosserat_scene::output::{
    Attempt, BoundingBox, FailedStep, RunStatus, RunSummary, RunWriter, write_failure_summary,
};
use cosserat_scene::spec::{ModelKind, SceneSpec, SolverSpec, SurfaceMesh, TimeSpec};
use cosserat_solver::{
    LevelFailure, LoadLevelReport, QuasiStaticSettings, QuasiStaticStepper, StaticError, StepError, StepReport,
    TimeStepSettings, TimeStepper,
};
use nalgebra::Vector3;
use serde_json::json;
use std::path::Path;
use std::time::Instant;

mod arc_length;

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

/// Counters collected over a run, for the summary.
#[derive(Debug, Clone, Default)]
struct RunStats {
    steps: usize,
    newton_iterations: usize,
    max_newton_iterations: usize,
    wasted_iterations: usize,
    reductions: usize,
    assembly_seconds: f64,
    solve_seconds: f64,
    /// The part of `solve_seconds` spent in numerical factorisations.
    factorisation_seconds: f64,
    step_seconds: f64,
    min_area_ratio: f64,
    frames: usize,
    /// `(t, kinetic, elastic)` at every output time.
    energies: Vec<(f64, f64, f64)>,
    /// Numeric factorisations performed.
    factorisations: usize,
    /// Conjugate-gradient iterations (CG linear solver only).
    cg_iterations: usize,
    /// Structure of the symmetric factor (last symbolic analysis).
    factor: Option<cosserat_solver::FactorStats>,
    /// Tolerances and residuals of the converged solves.
    convergence: ConvergenceStats,
}

/// A scene ready to run.
pub struct Simulation {
    name: String,
    time: TimeSpec,
    solver: SolverSpec,
    system: System,
    scripts: Scripts,
    probes: Probes,
    output_mesh: OutputMesh,
    write_frames: bool,
    rest_bbox: BoundingBox,
    elements: (String, String),
    stats: RunStats,
    /// Index of the contact term in the potential's extra terms, and its run statistics.
    contact: Option<(usize, ContactMonitor)>,
    /// Warnings about settings that physics or the discretisation limits ([`crate::advice`]).
    advice: Vec<String>,
    /// The mechanical model and what it needs beyond the system.
    model: Model,
    /// The time (or load factor) of the last committed state.
    t_reached: f64,
}

/// The mechanical model of a scene: the Cosserat shells of `cosserat-assembly`, or one of the
/// comparison models, which bring their own frames, rest-field scripts and elastic energy.
enum Model {
    Cosserat,
    KirchhoffLove(KlModel),
    Volume(VolumeModel),
}

impl Model {
    /// Sets what the model scripts itself (the volume's rest curvature) for the step from `t`.
    fn apply(&mut self, t: f64, dt: f64) {
        if let Model::Volume(v) = self {
            v.apply(t, dt);
        }
    }

    /// The output frame of a state.
    fn frame(
        &self,
        mesh: &OutputMesh,
        shells: &[cosserat_assembly::ShellLayout],
        state: &cosserat_assembly::SystemState,
        t: f64,
    ) -> VtuFrame {
        match self {
            Model::Cosserat => mesh.frame(shells, state, t),
            Model::KirchhoffLove(m) => m.frame(state, t),
            Model::Volume(m) => m.frame(state, t),
        }
    }
}

fn element_names(pairs: &[ElementPair]) -> (String, String) {
    let name = |k: cosserat_fem::ElementKind| format!("{k:?}").to_lowercase();
    let mut d: Vec<String> = pairs.iter().map(|p| name(p.displacement())).collect();
    let mut r: Vec<String> = pairs.iter().map(|p| name(p.rotation())).collect();
    d.dedup();
    r.dedup();
    (d.join(","), r.join(","))
}

impl Simulation {
    /// Builds the system, boundary conditions, loads, rest fields and probes of a scene, after checking
    /// that it fits into the machine's available memory ([`MemoryLimit::of_machine`]).
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
        let inputs: Vec<ShellInput> = spec
            .shells
            .iter()
            .map(|s| ShellInput {
                name: s.name.clone(),
                mesh: s.mesh.clone(),
                pair: s.pair,
                material: s.material,
                rest: s.rest,
                quadrature: s.quadrature,
                damping: s.damping,
                angular_inertia_density: s.angular_inertia_density,
            })
            .collect();
        let (dynamic, dt) = match &spec.time {
            TimeSpec::Dynamic { dt, .. } => (true, *dt),
            TimeSpec::QuasiStatic { .. } | TimeSpec::ArcLength { .. } => (false, 1.0),
        };
        let options = SystemOptions {
            gravity: spec.gravity,
            dynamic,
            dt,
        };
        let (mut system, model, spec) = match spec.shells.first().map(|s| s.model) {
            Some(ModelKind::KirchhoffLove(law)) => {
                let (system, m) = kl_model::build(&spec.shells[0], law, &options)?;
                (system, Model::KirchhoffLove(m), spec)
            }
            Some(ModelKind::MicropolarVolume { layers }) => {
                let (system, m, spec) = volume_model::build(spec, layers, &options)?;
                (system, Model::Volume(m), spec)
            }
            _ => (build_system(&inputs, Vec::new(), &options)?, Model::Cosserat, spec),
        };
        let contact = match &spec.contact {
            None => None,
            Some(c) => {
                // The term needs the final node layout, and the pattern must know it is there: rebuild
                // the potential around the same parts with the term added.
                let term = build_contact_term(c, &system.shells, &system.potential.parts.state.x)?;
                let System { potential, shells } = system;
                let (dt, parallelism) = (potential.dt, potential.parallelism);
                let mut parts = potential.parts;
                parts.extra.push(Box::new(term));
                let index = parts.extra.len() - 1;
                let mut potential = IncrementalPotential::new(parts, dt);
                potential.parallelism = parallelism;
                system = System { potential, shells };
                Some((index, ContactMonitor::default()))
            }
        };
        for (shell, layout) in spec.shells.iter().zip(&system.shells) {
            if let Some(x0) = &shell.initial_positions {
                system.potential.parts.state.x[layout.disp_nodes.clone()].copy_from_slice(x0);
            }
        }
        if let Some((index, _)) = &contact {
            check_initial_gaps(&mut system.potential, *index)?;
        }
        for s in &mut system.potential.parts.shells {
            s.set_project_pd(spec.solver.project_pd);
        }
        let scripts = Scripts::build(&spec, &system.shells, &mut system.potential)?;
        let probes = Probes::new(&spec.probes, &system.shells);
        let output_mesh = OutputMesh::new(&system.shells, spec.output.subdivision);
        let rest_points: Vec<[f64; 3]> = system
            .shells
            .iter()
            .flat_map(|l| l.rest_disp_positions.iter().map(|x| [x.x, x.y, x.z]))
            .collect();
        let rest_bbox = BoundingBox::of_points(&rest_points).unwrap_or(BoundingBox {
            min: [0.0; 3],
            max: [0.0; 3],
        });
        let pairs: Vec<ElementPair> = spec.shells.iter().map(|s| s.pair).collect();
        let elements = match &model {
            Model::Cosserat => element_names(&pairs),
            Model::KirchhoffLove(_) => ("tri3".into(), "-".into()),
            Model::Volume(_) => ("tet4".into(), "tet4".into()),
        };
        Ok(Self {
            name: spec.name.clone(),
            time: spec.time.clone(),
            solver: spec.solver,
            system,
            scripts,
            probes,
            output_mesh,
            write_frames: spec.output.frames,
            rest_bbox,
            elements,
            stats: RunStats {
                min_area_ratio: f64::INFINITY,
                ..RunStats::default()
            },
            contact,
            advice,
            model,
            t_reached: 0.0,
        })
    }

    /// Warnings about the scene's settings (also in `summary.json` under `extra.warnings`).
    pub fn advice(&self) -> &[String] {
        &self.advice
    }

    /// The contact term, when the scene has contact.
    pub fn contact_term_mut(&mut self) -> Option<&mut ContactTerm> {
        let index = self.contact.as_ref()?.0;
        contact_parts(&mut self.system.potential, index).map(|(term, ..)| term)
    }

    /// The contact statistics of the steps so far, when the scene has contact.
    pub fn contact_monitor(&self) -> Option<&ContactMonitor> {
        self.contact.as_ref().map(|c| &c.1)
    }

    /// Positions of the contact vertices in the current state (shell nodes, then obstacle vertices at
    /// their start-of-step positions) and the contact triangles over them, when the scene has contact.
    pub fn contact_geometry(&mut self) -> Option<SurfaceMesh> {
        let index = self.contact.as_ref()?.0;
        let (term, state, _) = contact_parts(&mut self.system.potential, index)?;
        let mesh = term.mesh();
        let positions = mesh.positions(|i| state.x[i], |o, v| term.obstacle_positions(o)[v]);
        let triangles = mesh.triangles().iter().map(|t| t.map(|v| v as usize)).collect();
        Some((positions, triangles))
    }

    /// All contact pairs within reach of the current state: the smallest gap, the number of pairs
    /// within the barrier (a broad phase over every primitive); `None` without contact.
    pub fn contact_coverage(&mut self) -> Option<cosserat_contact::Coverage> {
        let index = self.contact.as_ref()?.0;
        let dt = self.system.potential.dt;
        let (term, state, layout) = contact_parts(&mut self.system.potential, index)?;
        let u = vec![0.0; layout.n_dofs()];
        Some(term.coverage(state, layout, &u, dt))
    }

    /// Pairs of contact triangles (shells split into flat triangles, and obstacles) that intersect in
    /// the current state, by an exact-sign test over the whole mesh; `None` without contact.
    pub fn contact_intersections(&mut self) -> Option<Vec<(usize, usize)>> {
        let (positions, triangles) = self.contact_geometry()?;
        Some(cosserat_contact::intersecting_pairs(&triangles, &positions))
    }

    /// The contact force on every displacement node in the current state \[N\] (minus the gradient of
    /// the barrier energy with respect to the positions; friction acts over a step and is zero for a
    /// state at rest), or `None` without contact.
    ///
    /// # Errors
    /// [`SimulationError::Evaluation`] if the current state is infeasible for the barrier.
    pub fn contact_forces(&mut self) -> Result<Option<Vec<Vector3<f64>>>, SimulationError> {
        let Some((index, _)) = self.contact else {
            return Ok(None);
        };
        let dt = self.system.potential.dt;
        let Some((term, state, &layout)) = contact_parts(&mut self.system.potential, index) else {
            return Ok(None);
        };
        let u = vec![0.0; layout.n_dofs()];
        let rotations = NodeRotations::Matrices(vec![nalgebra::Matrix3::identity(); layout.n_rot_nodes]);
        let eval = Evaluation {
            state,
            layout: &layout,
            u: &u,
            dt,
            rotations: &rotations,
            parallelism: Parallelism::Sequential,
        };
        let mut grad = vec![0.0; layout.n_dofs()];
        PotentialTerm::gradient(&*term, &eval, &mut grad)?;
        // The term's gradient is with respect to the velocity unknowns: Δt times the positional one.
        Ok(Some(
            (0..layout.n_disp_nodes).map(|i| -layout.velocity(&grad, i) / dt).collect(),
        ))
    }

    /// A time stepper with the scene's time-step and solver settings, starting at `t = 0`.
    ///
    /// # Errors
    /// [`SimulationError::Setup`] for a quasi-static scene; a symbolic analysis failure.
    pub fn time_stepper(&self) -> Result<TimeStepper, SimulationError> {
        match &self.time {
            TimeSpec::Dynamic { dt, adaptive, .. } => Ok(TimeStepper::new(
                &self.system.potential,
                self.time_step_settings(*dt, *adaptive),
            )?),
            TimeSpec::QuasiStatic { .. } | TimeSpec::ArcLength { .. } => Err(SimulationError::Setup(
                "a quasi-static scene has no time stepper; use `run`".into(),
            )),
        }
    }

    /// Advances one time step with `stepper` (from [`Simulation::time_stepper`]): scripts, the Newton
    /// solve with its retries, and the run statistics (contact included). Writes no output.
    ///
    /// # Errors
    /// [`StepError`] when every allowed attempt failed or a script value was not finite; the state is
    /// then unchanged.
    pub fn step(&mut self, stepper: &mut TimeStepper) -> Result<StepReport, StepError> {
        let t0 = Instant::now();
        let (scripts, model) = (&mut self.scripts, &mut self.model);
        let result = stepper.try_step(&mut self.system.potential, &mut |p, t, dt| {
            scripts.apply(p, t, dt)?;
            model.apply(t, dt);
            Ok(())
        });
        let report = match result {
            Ok(report) => report,
            Err(e) => {
                self.stats.reductions += e.attempts().len();
                self.stats.wasted_iterations += e
                    .attempts()
                    .iter()
                    .map(|a| a.error.residuals().len().saturating_sub(1))
                    .sum::<usize>();
                return Err(e);
            }
        };
        self.record_contact();
        self.record_step(&report, t0.elapsed().as_secs_f64());
        Ok(report)
    }

    /// Adds the contact term's statistics of the committed state to the run's, when the scene has
    /// contact.
    fn record_contact(&mut self) {
        if let Some((index, monitor)) = &mut self.contact
            && let Some((term, ..)) = contact_parts(&mut self.system.potential, *index)
        {
            monitor.record(term);
        }
    }

    /// The system (potential, state and shell layouts).
    pub fn system(&self) -> &System {
        &self.system
    }

    /// Mutable access to the system, e.g. to change the parallelism.
    pub fn system_mut(&mut self) -> &mut System {
        &mut self.system
    }

    /// The scene name.
    pub fn name(&self) -> &str {
        &self.name
    }

    fn time_step_settings(&self, dt: f64, adaptive: bool) -> TimeStepSettings {
        let mut s = TimeStepSettings::fixed(dt);
        s.adaptive = adaptive;
        s.max_reductions = self.solver.max_step_reductions;
        s.initial_guess = self.solver.initial_guess;
        s.newton.tolerance = self.solver.tolerance;
        s.newton.max_iterations = self.solver.max_newton_iterations;
        s.newton.max_line_search_iterations = self.solver.max_line_search_iterations;
        s.newton.linear_solver.kind = self.solver.linear_solver;
        s.newton.linear_solver.domains = self.solver.domain_split;
        s
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

    fn record_output(&mut self, writer: &mut RunWriter, t: f64) -> Result<(), SimulationError> {
        let elastic = match self.model {
            Model::Cosserat => self.system.potential.elastic_energy().ok(),
            _ => kl_model::extra_elastic_energy(&self.system.potential).ok(),
        }
        .unwrap_or(f64::NAN);
        self.stats.energies.push((t, self.system.potential.kinetic_energy(), elastic));
        let state = &self.system.potential.parts.state;
        for s in &self.system.potential.parts.shells {
            self.stats.min_area_ratio = self.stats.min_area_ratio.min(s.min_area_ratio(state));
        }
        if self.write_frames {
            let mut frame = self.model.frame(&self.output_mesh, &self.system.shells, state, t);
            append_obstacles(&mut frame, &self.scripts.obstacles());
            writer.write_frame(&frame)?;
            self.stats.frames += 1;
        }
        let mut row = self.probes.values(&self.system.shells, state);
        if matches!(self.time, TimeSpec::ArcLength { .. }) {
            row.insert(0, self.t_reached);
        }
        writer.write_probes(t, &row)?;
        Ok(())
    }

    /// Adds a reached load level to the run's statistics (a level counts as a step).
    fn record_level(&mut self, r: &LoadLevelReport, seconds: f64) {
        let s = &mut self.stats;
        s.steps += 1;
        s.newton_iterations += r.total_iterations;
        s.max_newton_iterations = s.max_newton_iterations.max(r.total_iterations);
        s.reductions += r.bisections;
        s.assembly_seconds += r.newton.assembly_seconds;
        s.solve_seconds += r.newton.linear_solve_seconds;
        s.factorisation_seconds += r.newton.factorisation_seconds;
        s.step_seconds += seconds;
        let f = &r.newton.factorisations;
        s.factorisations += f.llt + f.lblt + f.lu;
        s.cg_iterations += r.newton.cg_iterations;
        s.convergence.record_newton(&r.newton);
    }

    fn record_step(&mut self, r: &StepReport, seconds: f64) {
        let s = &mut self.stats;
        s.steps += 1;
        s.newton_iterations += r.newton.iterations;
        s.max_newton_iterations = s.max_newton_iterations.max(r.newton.iterations);
        s.wasted_iterations += r.wasted_iterations;
        s.reductions += r.reductions;
        s.assembly_seconds += r.newton.assembly_seconds;
        s.solve_seconds += r.newton.linear_solve_seconds;
        s.factorisation_seconds += r.newton.factorisation_seconds;
        s.step_seconds += seconds;
        let f = &r.newton.factorisations;
        s.factorisations += f.llt + f.lblt + f.lu;
        s.cg_iterations += r.newton.cg_iterations;
        s.convergence.record_newton(&r.newton);
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
        let start = Instant::now();
        let mut writer = RunWriter::create(dir, &self.probe_columns())?;
        let outcome = match self.record_output(&mut writer, 0.0) {
            Ok(()) => match self.time.clone() {
                TimeSpec::Dynamic {
                    dt,
                    end,
                    adaptive,
                    output_interval,
                } => self.run_dynamic(&mut writer, dt, end, adaptive, output_interval, progress, stop),
                TimeSpec::QuasiStatic { levels } => self.run_quasi_static(&mut writer, &levels, progress, stop),
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
        let summary = self.summary(start.elapsed().as_secs_f64(), outcome);
        writer.finish(&summary)?;
        Ok(summary)
    }

    fn run_dynamic(
        &mut self,
        writer: &mut RunWriter,
        dt: f64,
        end: f64,
        adaptive: bool,
        output_interval: f64,
        progress: &mut dyn FnMut(&StepInfo),
        stop: &StopRequest,
    ) -> Result<Outcome, SimulationError> {
        let mut stepper = TimeStepper::new(&self.system.potential, self.time_step_settings(dt, adaptive))?;
        let mut schedule = OutputSchedule::new(output_interval, dt);
        // Fixed steps end exactly at `end` up to round-off; half a step of slack avoids an extra step.
        while stepper.time() < end - 0.5 * stepper.dt().min(dt) {
            if let Some(reason) = stop.reason() {
                return Ok(Outcome::Interrupted(stepper.time(), reason));
            }
            let result = self.step(&mut stepper);
            self.stats.factor = stepper.solver().linear_solver().symmetric_stats();
            let report = match result {
                Ok(report) => report,
                Err(e) => return Ok(Outcome::failed_step(&e)),
            };
            self.t_reached = report.t;
            progress(&StepInfo {
                step: self.stats.steps,
                t: report.t,
                end,
                dt: report.dt,
                newton_iterations: report.newton.iterations,
                residual: report.newton.residual(),
            });
            if schedule.due(report.t) {
                self.record_output(writer, report.t)?;
            }
        }
        Ok(Outcome::Completed)
    }

    fn run_quasi_static(
        &mut self,
        writer: &mut RunWriter,
        levels: &[f64],
        progress: &mut dyn FnMut(&StepInfo),
        stop: &StopRequest,
    ) -> Result<Outcome, SimulationError> {
        let settings = QuasiStaticSettings {
            newton: self.time_step_settings(1.0, false).newton,
            ..QuasiStaticSettings::default()
        };
        let mut stepper = QuasiStaticStepper::new(&mut self.system.potential, &settings)?;
        let end = levels.last().copied().unwrap_or(1.0);
        let mut previous = 0.0;
        for &target in levels {
            if let Some(reason) = stop.reason() {
                return Ok(Outcome::Interrupted(stepper.load_factor(), reason));
            }
            let t0 = Instant::now();
            let (scripts, model) = (&mut self.scripts, &mut self.model);
            let result = stepper.advance(&mut self.system.potential, target, &mut |p, lambda| {
                scripts.apply(p, lambda, 0.0)?;
                model.apply(lambda, 0.0);
                Ok(())
            });
            self.stats.factor = stepper.solver().linear_solver().symmetric_stats();
            let report = match result {
                Ok(report) => report,
                Err(e) => {
                    self.stats.reductions += e.bisections;
                    return Ok(Outcome::failed_level(&e));
                }
            };
            self.record_contact();
            self.record_level(&report, t0.elapsed().as_secs_f64());
            self.t_reached = target;
            progress(&StepInfo {
                step: self.stats.steps,
                t: target,
                end,
                dt: target - previous,
                newton_iterations: report.total_iterations,
                residual: report.newton.residual(),
            });
            self.record_output(writer, target)?;
            previous = target;
        }
        Ok(Outcome::Completed)
    }

    fn summary(&mut self, wall: f64, outcome: Outcome) -> RunSummary {
        let step_seconds = self.stats.step_seconds;
        let contact = self.contact.as_ref().map(|c| c.1.clone()).and_then(|monitor| {
            let term = self.contact_term_mut()?;
            Some(monitor.summary(term, step_seconds))
        });
        let s = &self.stats;
        let layouts = &self.system.shells;
        let potential = &self.system.potential;
        let (status, reason, stopped_at, failed_step) = match outcome {
            Outcome::Completed => (RunStatus::Ok, None, None, None),
            Outcome::Interrupted(t, why) => (RunStatus::Interrupted, Some(why.describe().to_string()), Some(t), None),
            Outcome::Failed { t, reason, step } => (RunStatus::Error, Some(reason), Some(t), step),
        };
        let dt = match &self.time {
            TimeSpec::Dynamic { dt, .. } => *dt,
            TimeSpec::QuasiStatic { .. } | TimeSpec::ArcLength { .. } => 1.0,
        };
        let steps = s.steps.max(1) as f64;
        let mut extra = std::collections::BTreeMap::new();
        extra.insert("max_newton_iterations".into(), json!(s.max_newton_iterations));
        let mut warnings = self.advice.clone();
        warnings.extend(s.convergence.warning());
        if s.min_area_ratio <= 0.0 {
            warnings.push(format!(
                "an element turned inside out during the run (smallest deformed-to-rest area ratio {:.3}): \
                 the steps converged, but the result is not to be trusted; refine the mesh or reduce the time step",
                s.min_area_ratio
            ));
        }
        if !warnings.is_empty() {
            extra.insert("warnings".into(), json!(warnings));
        }
        extra.insert("wasted_newton_iterations".into(), json!(s.wasted_iterations));
        extra.insert("n_frames".into(), json!(s.frames));
        extra.insert("n_shells".into(), json!(layouts.len()));
        extra.insert(
            "n_curved_points".into(),
            json!(layouts.iter().map(|l| l.n_curved_points).sum::<usize>()),
        );
        if s.min_area_ratio.is_finite() {
            extra.insert("min_area_ratio".into(), json!(s.min_area_ratio));
        }
        extra.insert("hessian_nnz".into(), json!(potential.pattern().nnz()));
        match &self.model {
            Model::Cosserat => {
                extra.insert("model".into(), json!("cosserat"));
            }
            Model::KirchhoffLove(m) => {
                extra.insert("model".into(), json!("kirchhoff_love"));
                extra.insert("law".into(), json!(m.law_name()));
            }
            Model::Volume(m) => {
                extra.insert("model".into(), json!("micropolar_volume"));
                extra.insert("n_tetrahedra".into(), json!(m.n_elements()));
            }
        }
        if s.cg_iterations > 0 {
            extra.insert("cg_iterations".into(), json!(s.cg_iterations));
            extra.insert(
                "cg_iterations_per_newton".into(),
                json!(s.cg_iterations as f64 / s.newton_iterations.max(1) as f64),
            );
        }
        extra.insert("factorisations".into(), json!(s.factorisations));
        if let Some(factor) = s.factor {
            let flops = factor.flops;
            extra.insert("factor_nnz".into(), json!(factor.nnz_l));
            extra.insert("factor_flops".into(), json!(flops));
            // 2: the two-domain Cholesky (cosserat_solver::DomainSplit) factorised this run's systems.
            extra.insert("factor_domains".into(), json!(factor.domains));
            if s.factorisation_seconds > 0.0 && s.factorisations > 0 {
                // The achieved rate of the numerical factorisations (their wall-clock time only).
                extra.insert("factorisation_seconds".into(), json!(s.factorisation_seconds));
                extra.insert(
                    "factor_gflops_per_s".into(),
                    json!(flops * s.factorisations as f64 / s.factorisation_seconds / 1e9),
                );
            }
        }
        if let Some(contact) = contact {
            extra.insert("contact".into(), contact);
            extra.insert("max_obstacle_lag".into(), json!(self.scripts.max_obstacle_lag()));
            extra.insert("final_obstacle_lag".into(), json!(self.scripts.last_obstacle_lag()));
        }
        if let Some(mb) = peak_memory_mb() {
            extra.insert("peak_memory_mb".into(), json!(mb));
        }
        // Energies at the output times (finite values only; JSON has no NaN).
        let finite: Vec<&(f64, f64, f64)> = s.energies.iter().filter(|e| e.1.is_finite() && e.2.is_finite()).collect();
        extra.insert(
            "energy".into(),
            json!({
                "t": finite.iter().map(|e| e.0).collect::<Vec<_>>(),
                "kinetic": finite.iter().map(|e| e.1).collect::<Vec<_>>(),
                "elastic": finite.iter().map(|e| e.2).collect::<Vec<_>>(),
            }),
        );
        RunSummary {
            scene: self.name.clone(),
            displacement_element: self.elements.0.clone(),
            rotation_element: self.elements.1.clone(),
            n_cells: layouts.iter().map(|l| l.disp_elements.len()).sum(),
            n_displacement_dofs: 3 * potential.parts.layout.n_disp_nodes,
            n_rotation_dofs: 3 * potential.parts.layout.n_rot_nodes,
            active_terms: potential.active_terms(),
            dt,
            n_steps: s.steps,
            avg_newton_iterations: s.newton_iterations as f64 / steps,
            wall_seconds: wall,
            avg_step_ms: 1e3 * s.step_seconds / steps,
            // Shares of the time in steps, not of the whole run, whose set-up, symbolic analysis and
            // output lie outside the steps.
            assembly_share: share(s.assembly_seconds, s.step_seconds),
            linear_solve_share: share(s.solve_seconds, s.step_seconds),
            n_step_reductions: s.reductions,
            rest_bbox: self.rest_bbox,
            status,
            reason,
            stopped_at,
            failed_step,
            convergence: s.convergence.summary(self.solver.tolerance),
            extra,
        }
    }
}

/// The process's peak resident memory (VmHWM) in MB, where the OS reports it.
fn peak_memory_mb() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

/// How a run ended.
enum Outcome {
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
    fn failed_step(e: &StepError) -> Self {
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
    fn failed_level(e: &StaticError) -> Self {
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
struct OutputSchedule {
    interval: f64,
    /// Slack for round-off in the step times.
    slack: f64,
    next: f64,
}

impl OutputSchedule {
    fn new(interval: f64, dt: f64) -> Self {
        Self {
            interval,
            slack: 1e-9 * dt,
            next: interval,
        }
    }

    /// Whether a frame is due at time `t`; if so, the schedule moves to the next multiple after `t`.
    fn due(&mut self, t: f64) -> bool {
        if t < self.next - self.slack {
            return false;
        }
        let index = ((t + self.slack) / self.interval).floor() + 1.0;
        self.next = (index * self.interval).max(t + self.slack);
        true
    }
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

/// Fails setup if a contact pair starts closer than its thickness (or crossing).
fn check_initial_gaps(potential: &mut IncrementalPotential, index: usize) -> Result<(), SimulationError> {
    let dt = potential.dt;
    let Some((term, state, layout)) = contact_parts(potential, index) else {
        return Ok(());
    };
    let u = vec![0.0; layout.n_dofs()];
    let coverage = term.coverage(state, layout, &u, dt);
    if coverage.min_gap.is_nan() || coverage.min_gap <= 0.0 {
        return Err(SimulationError::Setup(format!(
            "contact: the initial state has a pair of contact primitives closer than their thicknesses \
             (smallest gap {:e} m); move the bodies apart or reduce the thicknesses",
            coverage.min_gap
        )));
    }
    Ok(())
}

/// `part / whole`, zero when nothing was timed.
fn share(part: f64, whole: f64) -> f64 {
    if whole > 0.0 { part / whole } else { 0.0 }
}
