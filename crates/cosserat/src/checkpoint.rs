//! Checkpoints: the complete state of a run between two steps, written every
//! `output.checkpoint_every` steps into `DIR/checkpoint/`, from which [`crate::Simulation`] continues
//! the run so that it ends bit for bit as a run that was never stopped.
//!
//! What the next step depends on, and so what a checkpoint holds:
//! - the system state: positions, velocities, node and quadrature-point rotations, angular velocities,
//!   and the membrane stresses a stretched shell's stabilisation held;
//! - the stepper: time and the time step after reductions (dynamic), the load factor, the level
//!   reached and the predictor's memory (quasi-static), whether the next Newton solve
//!   starts with the Hessian and where its search for a shift of an indefinite Hessian starts, and the
//!   last step's velocities that the next initial guess extrapolates from (dynamic);
//! - the output schedule, the probe rows and frames written so far, and the run's counters;
//! - contact: the couplings in the Hessian's pattern, the obstacles' positions and the statistics.
//!
//! The scripts, rest fields and loads are functions of time and the scene, so the scene itself (its
//! fingerprint) stands for them; a controller's overrides set through [`crate::scripts::Scripts`]
//! are the caller's to set again. `DIR/checkpoint/scene.toml` is a copy of the scene file.

use crate::contact_run::ContactState;
use crate::error::SimulationError;
use crate::record::RunStats;
use cosserat_assembly::SystemState;
use cosserat_contact::{CacheCounters, ContactStats};
use cosserat_io::OutputError;
use cosserat_io::checkpoint::{Decoder, Encoder};
use cosserat_scene::spec::SceneSpec;
use cosserat_solver::{CarriedState, LastStep, LevelIncrement, PredictorMemory};
use nalgebra::{Quaternion, Vector3};
use std::path::{Path, PathBuf};
use std::time::Duration;

/// The folder of a run's output directory that holds its checkpoint.
pub const CHECKPOINT_DIR: &str = "checkpoint";
/// The checkpoint's state file in [`CHECKPOINT_DIR`].
pub const STATE_FILE: &str = "state.bin";
/// The copy of the scene file in [`CHECKPOINT_DIR`].
pub const SCENE_COPY: &str = "scene.toml";

/// `DIR/checkpoint/state.bin`.
pub fn state_path(dir: &Path) -> PathBuf {
    dir.join(CHECKPOINT_DIR).join(STATE_FILE)
}

/// Where a run's scene came from: the file and the command-line overrides, so that `cosserat resume`
/// can build the same scene again.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct SceneOrigin {
    /// The scene file.
    pub path: PathBuf,
    /// Overrides `KEY=VALUE` applied to it.
    pub overrides: Vec<String>,
}

/// The fingerprint of a scene: the CRC-32 of its complete description (meshes, materials, scripts'
/// expressions, settings), without where it was read from and how often it is checkpointed.
pub fn scene_fingerprint(spec: &SceneSpec) -> u32 {
    let mut spec = spec.clone();
    spec.source = None;
    spec.output.checkpoint_every = None;
    cosserat_io::checkpoint::fingerprint(format!("{spec:?}").as_bytes())
}

/// Where the stepper of a run stood.
#[derive(Debug, Clone, PartialEq)]
pub enum StepperState {
    /// A time-stepping run.
    Dynamic {
        /// Time reached \[s\].
        t: f64,
        /// The time step the next step tries \[s\].
        dt: f64,
        /// The time of the next frame \[s\].
        next_output: f64,
        /// What the last Newton solve left for the next.
        newton: CarriedState,
        /// The last step, from which the next step's initial guess is built.
        last_step: Option<LastStep>,
    },
    /// A run through load levels.
    QuasiStatic {
        /// Levels reached.
        levels_done: usize,
        /// The load factor of the last equilibrium.
        load_factor: f64,
        /// The predictor's memory.
        predictor: PredictorMemory,
        /// The largest load increment of the next solve (`None`: the whole next level).
        increment_limit: Option<f64>,
        /// What the last Newton solve left for the next.
        newton: CarriedState,
    },
}

/// The complete state of a run between two steps.
#[derive(Debug, Clone)]
pub struct Checkpoint {
    /// The scene's name.
    pub scene: String,
    /// [`scene_fingerprint`] of the scene.
    pub fingerprint: u32,
    /// Where the scene came from (absent for a scene built by a program).
    pub origin: Option<SceneOrigin>,
    /// Wall-clock time of the run until the checkpoint \[s\].
    pub wall_seconds: f64,
    /// Time (load factor) of the last committed state.
    pub t_reached: f64,
    /// The stepper.
    pub stepper: StepperState,
    /// The system state.
    pub state: SystemState,
    /// The run's counters.
    pub stats: RunStats,
    /// Rows of `probes.csv` written.
    pub probe_rows: usize,
    /// Times of the frames written.
    pub frame_times: Vec<f64>,
    /// The contact (absent without contact).
    pub contact: Option<ContactState>,
}

impl Checkpoint {
    /// The steps (load levels) the run had completed.
    pub fn step(&self) -> usize {
        self.stats.steps
    }

    /// Writes the checkpoint to `DIR/checkpoint/state.bin` atomically; returns its size in bytes.
    ///
    /// # Errors
    /// I/O errors naming the path.
    pub fn write(&self, dir: &Path) -> Result<usize, OutputError> {
        let folder = dir.join(CHECKPOINT_DIR);
        std::fs::create_dir_all(&folder).map_err(|source| OutputError::Io {
            operation: "create",
            path: folder.clone(),
            source,
        })?;
        let mut out = Encoder::new();
        out.str(&self.scene);
        out.usize(self.fingerprint as usize);
        out.bool(self.origin.is_some());
        if let Some(origin) = &self.origin {
            out.str(&origin.path.to_string_lossy());
            out.usize(origin.overrides.len());
            origin.overrides.iter().for_each(|o| out.str(o));
        }
        out.f64(self.wall_seconds);
        out.f64(self.t_reached);
        save_stepper(&self.stepper, &mut out);
        save_state(&self.state, &mut out);
        self.stats.save(&mut out);
        out.usize(self.probe_rows);
        out.f64s(&self.frame_times);
        out.bool(self.contact.is_some());
        if let Some(contact) = &self.contact {
            save_contact(contact, &mut out);
        }
        out.write(&folder.join(STATE_FILE))
    }

    /// Reads the checkpoint of the run in `dir`.
    ///
    /// # Errors
    /// [`SimulationError::Output`] naming the file and the reason: missing, unreadable, not a
    /// checkpoint, of another version, truncated or damaged.
    pub fn read(dir: &Path) -> Result<Self, SimulationError> {
        let path = state_path(dir);
        if !path.exists() {
            let reason = if dir.is_dir() {
                "the run wrote no checkpoint there (a run writes one only with `output.checkpoint_every`)"
            } else {
                "no such output directory"
            };
            return Err(SimulationError::Resume {
                path,
                reason: reason.into(),
            });
        }
        let mut input = Decoder::open(&path)?;
        let scene = input.string()?;
        let fingerprint = u32::try_from(input.usize()?).map_err(|_| input.error("the scene fingerprint is invalid"))?;
        let origin = if input.bool()? {
            let path = PathBuf::from(input.string()?);
            let n = input.usize()?;
            let overrides = (0..n).map(|_| input.string()).collect::<Result<_, _>>()?;
            Some(SceneOrigin { path, overrides })
        } else {
            None
        };
        let wall_seconds = input.f64()?;
        let t_reached = input.f64()?;
        let stepper = load_stepper(&mut input)?;
        let state = load_state(&mut input)?;
        let stats = RunStats::load(&mut input)?;
        let probe_rows = input.usize()?;
        let frame_times = input.f64s()?;
        let contact = if input.bool()? {
            Some(load_contact(&mut input)?)
        } else {
            None
        };
        input.finish()?;
        Ok(Self {
            scene,
            fingerprint,
            origin,
            wall_seconds,
            t_reached,
            stepper,
            state,
            stats,
            probe_rows,
            frame_times,
            contact,
        })
    }
}

fn save_stepper(stepper: &StepperState, out: &mut Encoder) {
    match stepper {
        StepperState::Dynamic {
            t,
            dt,
            next_output,
            newton,
            last_step,
        } => {
            out.usize(0);
            out.f64s(&[*t, *dt, *next_output]);
            save_newton(newton, out);
            out.bool(last_step.is_some());
            if let Some(last) = last_step {
                out.f64s(&last.start_velocities);
                out.f64(last.dt);
                out.bool(last.smooth);
            }
        }
        StepperState::QuasiStatic {
            levels_done,
            load_factor,
            predictor,
            increment_limit,
            newton,
        } => {
            out.usize(1);
            out.usize(*levels_done);
            out.f64(*load_factor);
            out.usize(predictor.increments().len());
            for increment in predictor.increments() {
                out.f64s(&increment.du);
                out.f64(increment.step);
            }
            out.bool(increment_limit.is_some());
            if let Some(limit) = increment_limit {
                out.f64(*limit);
            }
            save_newton(newton, out);
        }
    }
}

fn save_newton(newton: &CarriedState, out: &mut Encoder) {
    out.bool(newton.starts_with_hessian);
    out.f64(newton.last_shift);
}

fn load_newton(input: &mut Decoder) -> Result<CarriedState, OutputError> {
    Ok(CarriedState {
        starts_with_hessian: input.bool()?,
        last_shift: input.f64()?,
    })
}

fn load_stepper(input: &mut Decoder) -> Result<StepperState, OutputError> {
    match input.usize()? {
        0 => {
            let values = input.f64s()?;
            let &[t, dt, next_output] = values.as_slice() else {
                return Err(input.error("the time stepper's state has the wrong length"));
            };
            let newton = load_newton(input)?;
            let last_step = if input.bool()? {
                Some(LastStep {
                    start_velocities: input.f64s()?,
                    dt: input.f64()?,
                    smooth: input.bool()?,
                })
            } else {
                None
            };
            Ok(StepperState::Dynamic {
                t,
                dt,
                next_output,
                newton,
                last_step,
            })
        }
        1 => {
            let levels_done = input.usize()?;
            let load_factor = input.f64()?;
            let increments = (0..input.usize()?)
                .map(|_| {
                    Ok(LevelIncrement {
                        du: input.f64s()?,
                        step: input.f64()?,
                    })
                })
                .collect::<Result<Vec<_>, OutputError>>()?;
            let predictor = PredictorMemory::new(increments);
            let increment_limit = if input.bool()? { Some(input.f64()?) } else { None };
            Ok(StepperState::QuasiStatic {
                levels_done,
                load_factor,
                predictor,
                increment_limit,
                newton: load_newton(input)?,
            })
        }
        kind => Err(input.error(format!("unknown stepper kind {kind}"))),
    }
}

fn save_state(state: &SystemState, out: &mut Encoder) {
    let quaternions = |q: &[Quaternion<f64>]| -> Vec<f64> { q.iter().flat_map(|q| q.coords.iter().copied()).collect() };
    out.f64s(&flatten(&state.x));
    out.f64s(&flatten(&state.v));
    out.f64s(&quaternions(&state.q));
    out.f64s(&flatten(&state.omega));
    out.f64s(&quaternions(&state.q_points));
    out.f64s(&state.held_tension);
}

fn load_state(input: &mut Decoder) -> Result<SystemState, OutputError> {
    let mut points = || -> Result<_, OutputError> {
        let c = input.f64s()?;
        Ok(c.len().is_multiple_of(3).then(|| unflatten(&c)))
    };
    let (x, v) = (points()?, points()?);
    let quaternions = |c: Vec<f64>| -> Option<Vec<Quaternion<f64>>> {
        c.len()
            .is_multiple_of(4)
            .then(|| c.chunks_exact(4).map(|c| Quaternion::new(c[3], c[0], c[1], c[2])).collect())
    };
    let q = quaternions(input.f64s()?);
    let omega = {
        let c = input.f64s()?;
        c.len().is_multiple_of(3).then(|| unflatten(&c))
    };
    let q_points = quaternions(input.f64s()?);
    let held_tension = input.f64s()?;
    match (x, v, q, omega, q_points) {
        (Some(x), Some(v), Some(q), Some(omega), Some(q_points))
            if x.len() == v.len() && q.len() == omega.len() && held_tension.len() == q_points.len() =>
        {
            Ok(SystemState {
                x,
                v,
                q,
                omega,
                q_points,
                held_tension,
            })
        }
        _ => Err(input.error("the system state's arrays do not fit together")),
    }
}

fn save_contact(contact: &ContactState, out: &mut Encoder) {
    let pairs: Vec<usize> = contact.block_pairs.iter().flat_map(|&(a, b)| [a, b]).collect();
    out.usizes(&pairs);
    out.usize(contact.obstacles.len());
    for (start, current) in &contact.obstacles {
        out.f64s(&flatten(start));
        out.f64s(&flatten(current));
    }
    let (steps, active_sum, active_max, min_gap) = contact.monitor;
    out.usizes(&[steps, active_sum, active_max]);
    out.f64s(&[min_gap, contact.lags.0, contact.lags.1]);
    save_contact_totals(&contact.totals, out);
}

/// The contact term's counters, read back by `load_contact_totals`.
fn save_contact_totals(t: &ContactStats, out: &mut Encoder) {
    out.usizes(&[
        t.n_evaluations,
        t.n_ccd_queries,
        t.n_step_limits,
        t.n_step_cuts,
        t.cache.queries,
        t.cache.requeries,
        t.cache.builds,
        t.cache.uncached,
    ]);
    out.f64s(&[
        t.step_fraction_sum,
        t.broad_phase_time.as_secs_f64(),
        t.ccd_time.as_secs_f64(),
        t.energy_time.as_secs_f64(),
    ]);
}

fn load_contact(input: &mut Decoder) -> Result<ContactState, OutputError> {
    let pairs = input.usizes()?;
    if !pairs.len().is_multiple_of(2) {
        return Err(input.error("the contact couplings have an odd length"));
    }
    let n = input.usize()?;
    let mut obstacles = Vec::new();
    for _ in 0..n {
        obstacles.push((unflatten(&input.f64s()?), unflatten(&input.f64s()?)));
    }
    let counts = input.usizes()?;
    let values = input.f64s()?;
    let (&[steps, active_sum, active_max], &[min_gap, max_lag, last_lag]) = (counts.as_slice(), values.as_slice())
    else {
        return Err(input.error("the contact statistics have the wrong length"));
    };
    let totals = load_contact_totals(input)?;
    Ok(ContactState {
        block_pairs: pairs.chunks_exact(2).map(|p| (p[0], p[1])).collect(),
        obstacles,
        monitor: (steps, active_sum, active_max, min_gap),
        lags: (max_lag, last_lag),
        totals,
    })
}

/// The contact term's counters saved by `save_contact`.
fn load_contact_totals(input: &mut Decoder) -> Result<ContactStats, OutputError> {
    let counts = input.usizes()?;
    let values = input.f64s()?;
    let (
        &[
            n_evaluations,
            n_ccd_queries,
            n_step_limits,
            n_step_cuts,
            queries,
            requeries,
            builds,
            uncached,
        ],
        &[step_fraction_sum, broad, ccd, energy],
    ) = (counts.as_slice(), values.as_slice())
    else {
        return Err(input.error("the contact counters have the wrong length"));
    };
    let time = |s: f64| Duration::try_from_secs_f64(s).map_err(|_| input.error("a contact time is not a duration"));
    Ok(ContactStats {
        n_evaluations,
        n_ccd_queries,
        n_step_limits,
        step_fraction_sum,
        n_step_cuts,
        cache: CacheCounters {
            queries,
            requeries,
            builds,
            uncached,
        },
        broad_phase_time: time(broad)?,
        ccd_time: time(ccd)?,
        energy_time: time(energy)?,
        ..ContactStats::default()
    })
}

/// Points as a flat list of coordinates (checkpoints).
fn flatten(points: &[Vector3<f64>]) -> Vec<f64> {
    points.iter().flat_map(|p| [p.x, p.y, p.z]).collect()
}

/// The inverse of [`flatten`] (a trailing partial point is dropped; callers check the count).
fn unflatten(coords: &[f64]) -> Vec<Vector3<f64>> {
    coords.chunks_exact(3).map(|c| Vector3::new(c[0], c[1], c[2])).collect()
}
