//! The simulation of a scene: builds the system from a [`SceneSpec`], advances it in time (or through
//! load levels), and writes frames, probes and the run summary.
//!
//! [`Simulation`] composes independently built parts — the system (potential and shell layouts), the
//! scripts, the probes, the output sampling — and only orchestrates them.

use crate::error::SimulationError;
use crate::frames::OutputMesh;
use crate::probes::Probes;
use crate::scripts::Scripts;
use cosserat_assembly::{ElementPair, ShellInput, System, SystemOptions, build_system};
use cosserat_scene::output::{BoundingBox, RunStatus, RunSummary, RunWriter, write_failure_summary};
use cosserat_scene::spec::{SceneSpec, SolverSpec, TimeSpec};
use cosserat_solver::{QuasiStaticSettings, StepReport, TimeStepSettings, TimeStepper, solve_quasi_static};
use serde_json::json;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

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
    step_seconds: f64,
    min_area_ratio: f64,
    frames: usize,
    /// `(t, kinetic, elastic)` at every output time.
    energies: Vec<(f64, f64, f64)>,
    /// Numeric factorisations performed.
    factorisations: usize,
    /// Structure of the symmetric factor (last symbolic analysis): `(nnz of L, flops per factorisation)`.
    factor: Option<(usize, f64)>,
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
    /// Builds the system, boundary conditions, loads, rest fields and probes of a scene.
    ///
    /// # Errors
    /// Invalid meshes or materials (named by shell), unusable loads.
    pub fn new(spec: SceneSpec) -> Result<Self, SimulationError> {
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
            TimeSpec::QuasiStatic { .. } => (false, 1.0),
        };
        let mut system = build_system(
            &inputs,
            Vec::new(),
            &SystemOptions {
                gravity: spec.gravity,
                dynamic,
                dt,
            },
        )?;
        for (shell, layout) in spec.shells.iter().zip(&system.shells) {
            if let Some(x0) = &shell.initial_positions {
                system.potential.parts.state.x[layout.disp_nodes.clone()].copy_from_slice(x0);
            }
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
            elements: element_names(&pairs),
            stats: RunStats {
                min_area_ratio: f64::INFINITY,
                ..RunStats::default()
            },
        })
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
        s.newton.residual_tolerance = self.solver.tolerance;
        s.newton.max_iterations = self.solver.max_newton_iterations;
        s.newton.max_line_search_iterations = self.solver.max_line_search_iterations;
        s.newton.linear_solver.kind = self.solver.linear_solver;
        s
    }

    fn record_output(&mut self, writer: &mut RunWriter, t: f64) -> Result<(), SimulationError> {
        let elastic = self.system.potential.elastic_energy().unwrap_or(f64::NAN);
        self.stats.energies.push((t, self.system.potential.kinetic_energy(), elastic));
        let state = &self.system.potential.parts.state;
        for s in &self.system.potential.parts.shells {
            self.stats.min_area_ratio = self.stats.min_area_ratio.min(s.min_area_ratio(state));
        }
        if self.write_frames {
            writer.write_frame(&self.output_mesh.frame(&self.system.shells, state, t))?;
            self.stats.frames += 1;
        }
        writer.write_probes(t, &self.probes.values(&self.system.shells, state))?;
        Ok(())
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
        s.step_seconds += seconds;
        let f = &r.newton.factorisations;
        s.factorisations += f.llt + f.lblt + f.lu;
    }

    /// Runs the scene and writes its outputs into `dir` (frames, `probes.csv`, `summary.json`).
    ///
    /// `progress` is called after every step; setting `stop` ends the run after the current step with
    /// status `interrupted`. A failed step (Newton failure after all reductions) ends the run with status
    /// `error`; then `dir` holds only `summary.json` with the diagnostic.
    ///
    /// # Errors
    /// Only I/O failures of the outputs; physics failures are reported in the returned summary.
    pub fn run(
        &mut self,
        dir: &Path,
        progress: &mut dyn FnMut(&StepInfo),
        stop: &AtomicBool,
    ) -> Result<RunSummary, SimulationError> {
        let start = Instant::now();
        let mut writer = RunWriter::create(dir, &self.probes.columns())?;
        self.record_output(&mut writer, 0.0)?;
        let outcome = match self.time.clone() {
            TimeSpec::Dynamic {
                dt,
                end,
                adaptive,
                output_interval,
            } => self.run_dynamic(&mut writer, dt, end, adaptive, output_interval, progress, stop)?,
            TimeSpec::QuasiStatic { levels } => self.run_quasi_static(&mut writer, &levels, progress)?,
        };
        let wall = start.elapsed().as_secs_f64();
        let summary = self.summary(wall, outcome);
        if summary.status == RunStatus::Error {
            writer.fail(&summary)?;
        } else {
            writer.finish(&summary)?;
        }
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
        stop: &AtomicBool,
    ) -> Result<Outcome, SimulationError> {
        let mut stepper = TimeStepper::new(&self.system.potential, self.time_step_settings(dt, adaptive))?;
        let mut next_output = output_interval;
        // Fixed steps end exactly at `end` up to round-off; half a step of slack avoids an extra step.
        while stepper.time() < end - 0.5 * stepper.dt().min(dt) {
            if stop.load(Ordering::Relaxed) {
                return Ok(Outcome::Interrupted(stepper.time()));
            }
            let t0 = Instant::now();
            let scripts = &mut self.scripts;
            let result = stepper.step(&mut self.system.potential, &mut |p, t, dt| scripts.apply(p, t, dt));
            match result {
                Ok(report) => {
                    self.record_step(&report, t0.elapsed().as_secs_f64());
                    progress(&StepInfo {
                        step: self.stats.steps,
                        t: report.t,
                        end,
                        dt: report.dt,
                        newton_iterations: report.newton.iterations,
                        residual: report.newton.residual(),
                    });
                    if report.t >= next_output - 1e-9 * dt {
                        self.record_output(writer, report.t)?;
                        while next_output <= report.t + 1e-9 * dt {
                            next_output += output_interval;
                        }
                    }
                }
                Err(e) => return Ok(Outcome::Failed(stepper.time(), e.to_string())),
            }
            self.stats.factor = stepper.solver().linear_solver().symmetric_stats().map(|s| (s.nnz_l, s.flops));
        }
        Ok(Outcome::Completed)
    }

    fn run_quasi_static(
        &mut self,
        writer: &mut RunWriter,
        levels: &[f64],
        progress: &mut dyn FnMut(&StepInfo),
    ) -> Result<Outcome, SimulationError> {
        let settings = QuasiStaticSettings {
            newton: self.time_step_settings(1.0, false).newton,
            ..QuasiStaticSettings::default()
        };
        let end = levels.last().copied().unwrap_or(1.0);
        let scripts = &mut self.scripts;
        let output_mesh = &self.output_mesh;
        let (probes, shells, write_frames) = (&self.probes, &self.system.shells, self.write_frames);
        let mut output_error = None;
        let mut frames = 0;
        let mut min_area = f64::INFINITY;
        let mut step = 0;
        let t0 = Instant::now();
        let result = solve_quasi_static(
            &mut self.system.potential,
            levels,
            &settings,
            &mut |p, lambda| scripts.apply(p, lambda, 0.0),
            &mut |p, lambda| {
                let state = &p.parts.state;
                for s in &p.parts.shells {
                    min_area = min_area.min(s.min_area_ratio(state));
                }
                let mut write = || -> Result<(), SimulationError> {
                    if write_frames {
                        writer.write_frame(&output_mesh.frame(shells, state, lambda))?;
                        frames += 1;
                    }
                    writer.write_probes(lambda, &probes.values(shells, state))?;
                    Ok(())
                };
                if output_error.is_none()
                    && let Err(e) = write()
                {
                    output_error = Some(e);
                }
                step += 1;
                progress(&StepInfo {
                    step,
                    t: lambda,
                    end,
                    dt: 0.0,
                    newton_iterations: 0,
                    residual: 0.0,
                });
            },
        );
        if let Some(e) = output_error {
            return Err(e);
        }
        self.stats.frames += frames;
        self.stats.min_area_ratio = self.stats.min_area_ratio.min(min_area);
        match result {
            Ok(reports) => {
                for r in &reports {
                    let s = &mut self.stats;
                    s.steps += 1;
                    s.newton_iterations += r.total_iterations;
                    s.max_newton_iterations = s.max_newton_iterations.max(r.total_iterations);
                    s.reductions += r.bisections;
                    s.assembly_seconds += r.newton.assembly_seconds;
                    s.solve_seconds += r.newton.linear_solve_seconds;
                }
                self.stats.step_seconds += t0.elapsed().as_secs_f64();
                Ok(Outcome::Completed)
            }
            Err(e) => Ok(Outcome::Failed(e.from, e.to_string())),
        }
    }

    fn summary(&self, wall: f64, outcome: Outcome) -> RunSummary {
        let s = &self.stats;
        let layouts = &self.system.shells;
        let potential = &self.system.potential;
        let (status, reason, stopped_at) = match outcome {
            Outcome::Completed => (RunStatus::Ok, None, None),
            Outcome::Interrupted(t) => (
                RunStatus::Interrupted,
                Some("interrupted by the user".to_string()),
                Some(t),
            ),
            Outcome::Failed(t, reason) => (RunStatus::Error, Some(reason), Some(t)),
        };
        let dt = match &self.time {
            TimeSpec::Dynamic { dt, .. } => *dt,
            TimeSpec::QuasiStatic { .. } => 1.0,
        };
        let steps = s.steps.max(1) as f64;
        let mut extra = std::collections::BTreeMap::new();
        extra.insert("max_newton_iterations".into(), json!(s.max_newton_iterations));
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
        extra.insert("factorisations".into(), json!(s.factorisations));
        if let Some((nnz_l, flops)) = s.factor {
            extra.insert("factor_nnz".into(), json!(nnz_l));
            extra.insert("factor_flops".into(), json!(flops));
            if s.solve_seconds > 0.0 && s.factorisations > 0 {
                // Factorisation dominates the solve time; this is the achieved rate of the linear solves.
                extra.insert(
                    "factor_gflops_per_s".into(),
                    json!(flops * s.factorisations as f64 / s.solve_seconds / 1e9),
                );
            }
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
            assembly_share: if wall > 0.0 { s.assembly_seconds / wall } else { 0.0 },
            linear_solve_share: if wall > 0.0 { s.solve_seconds / wall } else { 0.0 },
            n_step_reductions: s.reductions,
            rest_bbox: self.rest_bbox,
            status,
            reason,
            stopped_at,
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
    Interrupted(f64),
    Failed(f64, String),
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
