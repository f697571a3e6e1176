//! `cosserat.Simulation`: a scene ready to run, stepped or run from Python.

use crate::array;
use crate::error::{StepFailed, simulation_error, type_error};
use crate::frame::PyFrame;
use crate::scene;
use crate::summary::PyRunSummary;
use cosserat::placement::NodeMap;
use cosserat::scene::spec::TimeSpec;
use cosserat::scripts::{RigidMotion, ScriptTargetError, Scripts};
use cosserat::solver::TimeStepper;
use cosserat::{Simulation, StepInfo, StopReason, StopRequest};
use nalgebra::{Matrix3, Vector3};
use numpy::{PyArray2, PyArray3};
use pyo3::exceptions::{PyKeyError, PyOverflowError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyList};
use std::path::PathBuf;
use std::sync::{Mutex, MutexGuard, TryLockError};

/// What a step or run reports.
#[pyclass(name = "StepInfo", module = "cosserat", frozen, get_all)]
#[derive(Debug, Clone, Copy)]
pub struct PyStepInfo {
    /// Steps (or load levels) completed.
    step: usize,
    /// Time (or load factor) reached.
    t: f64,
    /// End time (or final load factor) of the scene.
    end: f64,
    /// Time step used \[s\] (load increment in quasi-static runs).
    dt: f64,
    /// Newton iterations of the step.
    newton_iterations: usize,
    /// Final residual of the step.
    residual: f64,
}

impl From<&StepInfo> for PyStepInfo {
    fn from(i: &StepInfo) -> Self {
        Self {
            step: i.step,
            t: i.t,
            end: i.end,
            dt: i.dt,
            newton_iterations: i.newton_iterations,
            residual: i.residual,
        }
    }
}

#[pymethods]
impl PyStepInfo {
    fn __repr__(&self) -> String {
        format!(
            "StepInfo(step={}, t={}, dt={}, newton_iterations={}, residual={:.3e})",
            self.step, self.t, self.dt, self.newton_iterations, self.residual
        )
    }
}

/// A script target set from Python, applied before the next step.
#[derive(Debug, Clone)]
enum Command {
    Motion(String, Option<RigidMotion>),
    LoadScale(String, Option<f64>),
}

/// How far the simulation has come: a simulation is either stepped from Python or run once.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Mode {
    Fresh,
    Stepping,
    Ran,
}

struct Inner {
    sim: Simulation,
    stepper: Option<TimeStepper>,
    mode: Mode,
    /// Steps taken with `step`.
    steps: usize,
    /// The pool of the last `step(threads = n)`, kept for the next call with the same `n`.
    pool: Option<(usize, rayon::ThreadPool)>,
}

/// A scene ready to run: load it with `Simulation.load(path)` or `Simulation.from_dict(scene)`.
///
/// Step it (`step`, `run_until`) and read its state as NumPy arrays between steps, set boundary motions
/// and load scales from a controller, or `run` it to the end writing the same outputs as
/// `cosserat run`. Steps release the GIL; Ctrl-C stops a run after its current step.
#[pyclass(name = "Simulation", module = "cosserat", frozen)]
pub struct PySimulation {
    inner: Mutex<Inner>,
    /// Targets set while the simulation is busy (from a run's `on_step`), applied before the next step.
    pending: Mutex<Vec<Command>>,
    name: String,
    end: f64,
    /// The scene's time step, for dynamic scenes (the others have no time stepper).
    dt: Option<f64>,
    boundary_names: Vec<String>,
    load_names: Vec<String>,
}

impl PySimulation {
    fn build(py: Python<'_>, spec: cosserat::scene::SceneSpec) -> PyResult<Self> {
        let name = spec.name.clone();
        let end = match &spec.time {
            TimeSpec::Dynamic { end, .. } | TimeSpec::ArcLength { end, .. } => *end,
            TimeSpec::QuasiStatic { levels, .. } => levels.last().copied().unwrap_or(1.0),
        };
        let dt = match &spec.time {
            TimeSpec::Dynamic { dt, .. } => Some(*dt),
            TimeSpec::QuasiStatic { .. } | TimeSpec::ArcLength { .. } => None,
        };
        let sim = py.detach(|| Simulation::new(spec)).map_err(|e| simulation_error(py, &e))?;
        Ok(Self {
            boundary_names: sim.scripts().boundary_names().map(str::to_owned).collect(),
            load_names: sim.scripts().load_names().map(str::to_owned).collect(),
            inner: Mutex::new(Inner {
                sim,
                stepper: None,
                mode: Mode::Fresh,
                steps: 0,
                pool: None,
            }),
            pending: Mutex::new(Vec::new()),
            name,
            end,
            dt,
        })
    }

    /// The simulation, unless another thread is stepping or running it.
    fn lock(&self) -> PyResult<MutexGuard<'_, Inner>> {
        match self.inner.try_lock() {
            Ok(guard) => Ok(guard),
            // A panic inside a step leaves the state of the last completed step.
            Err(TryLockError::Poisoned(e)) => Ok(e.into_inner()),
            Err(TryLockError::WouldBlock) => Err(PyRuntimeError::new_err(
                "the simulation is running (a step or run in progress); inside `on_step` read the arrays \
                 through views taken before the run",
            )),
        }
    }

    /// Queues a target for the next step. After a run there is no next step, and a target that would
    /// silently never apply is refused; during one (`on_step`) the simulation is locked and the target
    /// goes to the run's next step.
    fn queue(&self, command: Command) -> PyResult<()> {
        let ran = match self.inner.try_lock() {
            Ok(inner) => inner.mode == Mode::Ran,
            Err(TryLockError::Poisoned(e)) => e.into_inner().mode == Mode::Ran,
            Err(TryLockError::WouldBlock) => false,
        };
        if ran {
            return Err(PyRuntimeError::new_err(
                "this simulation has run, so a target would never apply; load the scene again",
            ));
        }
        self.pending.lock().unwrap_or_else(|e| e.into_inner()).push(command);
        Ok(())
    }

    /// Applies the targets set since the last step.
    fn apply_pending(&self, scripts: &mut Scripts) -> Result<(), ScriptTargetError> {
        let commands = std::mem::take(&mut *self.pending.lock().unwrap_or_else(|e| e.into_inner()));
        for command in commands {
            match command {
                Command::Motion(name, motion) => scripts.set_motion(&name, motion)?,
                Command::LoadScale(name, scale) => scripts.set_load_scale(&name, scale)?,
            }
        }
        Ok(())
    }

    /// Refuses a target time that `run_until` could only step towards forever (NaN, infinity) or far
    /// past the scene's end, where a mistyped unit would step for hours.
    fn check_target_time(&self, t: f64) -> PyResult<()> {
        let slack = 0.5 * self.dt.unwrap_or(0.0);
        if t.is_finite() && t <= self.end + slack {
            return Ok(());
        }
        Err(PyValueError::new_err(format!(
            "t must be a finite time up to the scene's end {} (got {t}); to step further, raise `time.end` \
             with an override or call `step`",
            self.end
        )))
    }

    /// Whether the time is within half a step of `t`. A simulation that cannot step (quasi-static, or
    /// run) has not reached it, so that `step_once` says why.
    fn reached(&self, inner: &Inner, t: f64) -> bool {
        let (time, dt) = match (&inner.stepper, self.dt) {
            (Some(stepper), _) => (stepper.time(), stepper.dt()),
            (None, Some(dt)) if inner.mode == Mode::Fresh => (inner.sim.time(), dt),
            _ => return false,
        };
        time >= t - 0.5 * dt
    }

    fn check_boundary(&self, name: &str) -> PyResult<()> {
        check_name(name, &self.boundary_names, "boundary")
    }

    /// One step with the GIL released, on a pool of `threads` threads (the global pool if `None`).
    fn step_once(&self, py: Python<'_>, inner: &mut Inner, threads: Option<usize>) -> PyResult<PyStepInfo> {
        if inner.mode == Mode::Ran {
            return Err(PyRuntimeError::new_err(
                "this simulation has run; load the scene again to step it",
            ));
        }
        if inner.stepper.is_none() {
            inner.stepper = Some(inner.sim.time_stepper().map_err(|e| simulation_error(py, &e))?);
            inner.mode = Mode::Stepping;
        }
        self.apply_pending(inner.sim.scripts_mut())
            .map_err(|e| crate::error::SimulationError::new_err(e.to_string()))?;
        if let Some(n) = threads
            && inner.pool.as_ref().is_none_or(|(m, _)| *m != n)
        {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| PyRuntimeError::new_err(format!("creating the thread pool: {e}")))?;
            inner.pool = Some((n, pool));
        }
        let Inner {
            sim,
            stepper,
            steps,
            pool,
            ..
        } = inner;
        let stepper = stepper.as_mut().expect("set above");
        let pool = threads.and(pool.as_ref()).map(|(_, p)| p);
        let report = py
            .detach(|| match pool {
                Some(pool) => pool.install(|| sim.step(stepper)),
                None => sim.step(stepper),
            })
            .map_err(|e| StepFailed::new_err(e.to_string()))?;
        *steps += 1;
        Ok(PyStepInfo {
            step: *steps,
            t: report.t,
            end: self.end,
            dt: report.dt,
            newton_iterations: report.iterations(),
            residual: report.newton.residual(),
        })
    }
}

/// Checks what `run` cannot check once it has started: a misspelt callback would end the run at its
/// first step, and an empty `out_dir` would scatter the outputs over the current directory.
fn check_run_args(py: Python<'_>, out_dir: &std::path::Path, on_step: Option<&Py<PyAny>>) -> PyResult<()> {
    if out_dir.as_os_str().is_empty() {
        return Err(PyValueError::new_err(
            "out_dir is empty; name the directory of the outputs (\".\" for the current one)",
        ));
    }
    match on_step.map(|f| f.bind(py)) {
        Some(f) if !f.is_callable() => Err(type_error("on_step must be callable, taking a StepInfo", f)),
        _ => Ok(()),
    }
}

/// The most threads a step or run takes: more than any machine's cores, and few enough that a count
/// mistyped by orders of magnitude fails at once instead of spawning that many threads.
const MAX_THREADS: i64 = 1024;

/// The `threads` argument: `None` (all cores) or a count from 1 to [`MAX_THREADS`]. Zero is refused
/// rather than read as "all cores", which `None` says.
fn thread_count(threads: Option<&Bound<'_, PyAny>>) -> PyResult<Option<usize>> {
    let Some(threads) = threads.filter(|t| !t.is_none()) else {
        return Ok(None);
    };
    let not_an_int = || type_error("threads must be an int or None", threads);
    if threads.is_instance_of::<PyBool>() {
        return Err(not_an_int());
    }
    let n = match threads.extract::<i64>() {
        Ok(n) => n,
        // Larger than any count: refused below with the same message.
        Err(e) if e.is_instance_of::<PyOverflowError>(threads.py()) => i64::MAX,
        Err(_) => return Err(not_an_int()),
    };
    if (1..=MAX_THREADS).contains(&n) {
        Ok(usize::try_from(n).ok())
    } else {
        Err(PyValueError::new_err(format!(
            "threads must be from 1 to {MAX_THREADS}, or None for all cores (got {threads})"
        )))
    }
}

fn check_name(name: &str, known: &[String], what: &str) -> PyResult<()> {
    if known.iter().any(|n| n == name) {
        Ok(())
    } else {
        Err(PyKeyError::new_err(format!(
            "no {what} named `{name}` (the scene has: {})",
            known.join(", ")
        )))
    }
}

fn vector(v: [f64; 3]) -> Vector3<f64> {
    Vector3::new(v[0], v[1], v[2])
}

#[pymethods]
impl PySimulation {
    /// Loads a scene file.
    ///
    /// `overrides` change scene fields like `cosserat run --set`: a dict such as `{"mesh.nx": 8}` or a
    /// list of `"key=value"` strings. Raises `SceneError` (with `file`, `line`, `field`, `reason`) for
    /// an invalid scene, `SimulationError` for one that cannot be built.
    #[staticmethod]
    #[pyo3(signature = (path, overrides = None))]
    fn load(py: Python<'_>, path: PathBuf, overrides: Option<&Bound<'_, PyAny>>) -> PyResult<Self> {
        let overrides = scene::override_texts(overrides)?;
        let spec = scene::from_file(py, &path, &overrides)?;
        Self::build(py, spec)
    }

    /// Builds a scene from a dict of the scene file's structure; relative paths in it (meshes) are
    /// relative to `base_dir`. Errors name the field and the reason (there is no file or line).
    #[staticmethod]
    #[pyo3(signature = (scene, base_dir = PathBuf::from("."), overrides = None))]
    fn from_dict(
        py: Python<'_>,
        scene: &Bound<'_, PyDict>,
        base_dir: PathBuf,
        overrides: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let overrides = scene::override_texts(overrides)?;
        let spec = scene::from_dict(py, scene, &base_dir, &overrides)?;
        Self::build(py, spec)
    }

    /// The scene name.
    #[getter]
    fn name(&self) -> &str {
        &self.name
    }

    /// The scene's end time (or final load factor).
    #[getter]
    fn end(&self) -> f64 {
        self.end
    }

    /// The time (or load factor) of the last completed step.
    #[getter]
    fn time(&self) -> PyResult<f64> {
        Ok(self.lock()?.sim.time())
    }

    /// Warnings about the scene's settings and inputs.
    #[getter]
    fn advice(&self) -> PyResult<Vec<String>> {
        Ok(self.lock()?.sim.advice().to_vec())
    }

    /// The names of the scene's boundary conditions.
    #[getter]
    fn boundary_names(&self) -> Vec<String> {
        self.boundary_names.clone()
    }

    /// The names of the scene's loads.
    #[getter]
    fn load_names(&self) -> Vec<String> {
        self.load_names.clone()
    }

    /// Advances one time step (dynamic scenes) with the GIL released; returns its `StepInfo`.
    ///
    /// Raises `StepFailed` when the step failed after every allowed reduction (the state is that of
    /// the last completed step). `threads`: the number of threads of this step, 1 to 1024 (default:
    /// the process's pool, all cores); results are the same for any number.
    #[pyo3(signature = (threads = None))]
    fn step(&self, py: Python<'_>, threads: Option<&Bound<'_, PyAny>>) -> PyResult<PyStepInfo> {
        let threads = thread_count(threads)?;
        let mut inner = self.lock()?;
        self.step_once(py, &mut inner, threads)
    }

    /// Steps until the time reaches `t` (within half a step); returns the number of steps taken, none
    /// if the time is there already. `t` must be finite and at most the scene's end. Ctrl-C raises `KeyboardInterrupt` after the current step. `threads` as for `step`.
    #[pyo3(signature = (t, threads = None))]
    fn run_until(&self, py: Python<'_>, t: f64, threads: Option<&Bound<'_, PyAny>>) -> PyResult<usize> {
        let threads = thread_count(threads)?;
        self.check_target_time(t)?;
        let mut inner = self.lock()?;
        let mut n = 0;
        while !self.reached(&inner, t) {
            self.step_once(py, &mut inner, threads)?;
            n += 1;
            py.check_signals()?;
        }
        Ok(n)
    }

    /// Runs the scene to its end and writes its outputs into `out_dir`, the same files as
    /// `cosserat run --out out_dir` (frames, `probes.csv`, `summary.json`); returns the `RunSummary`.
    ///
    /// `on_step(info)` is called after every step (or load level) with a `StepInfo`; it may set targets
    /// for the next step (`set_motion`, `set_load_scale`) and read views taken before the run. Returning
    /// `False` stops the run after that step (status `"interrupted"`); an exception stops it and is
    /// raised after the outputs are written. It is called from the run's own thread, while the calling
    /// thread watches for Ctrl-C. Ctrl-C stops the run after its current step, writes the
    /// summary (status `"interrupted"`) and raises `KeyboardInterrupt`.
    ///
    /// `threads`: the number of threads of the run, 1 to 1024 (default: all cores, like the CLI). An
    /// `out_dir` that cannot be created raises `SimulationError` and leaves the simulation runnable.
    #[pyo3(signature = (out_dir, on_step = None, threads = None))]
    fn run(
        &self,
        py: Python<'_>,
        out_dir: PathBuf,
        on_step: Option<Py<PyAny>>,
        threads: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<PyRunSummary> {
        let threads = thread_count(threads)?;
        check_run_args(py, &out_dir, on_step.as_ref())?;
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads.unwrap_or(0))
            .build()
            .map_err(|e| PyRuntimeError::new_err(format!("creating the thread pool: {e}")))?;
        let mut inner = self.lock()?;
        if inner.mode != Mode::Fresh {
            return Err(PyRuntimeError::new_err(
                "`run` starts from the scene's initial state, and this simulation has been stepped or run; \
                 load the scene again",
            ));
        }
        inner.mode = Mode::Ran;
        let sim = &mut inner.sim;
        self.apply_pending(sim.scripts_mut())
            .map_err(|e| crate::error::SimulationError::new_err(e.to_string()))?;
        let stop = StopRequest::new();
        let raised: Mutex<Option<PyErr>> = Mutex::new(None);
        let raise = |e: PyErr| {
            raised.lock().unwrap_or_else(|p| p.into_inner()).get_or_insert(e);
        };
        let result = py.detach(|| {
            let mut controller = |info: &StepInfo, scripts: &mut Scripts| {
                Python::attach(|py| {
                    if let Some(on_step) = &on_step {
                        match on_step.call1(py, (PyStepInfo::from(info),)) {
                            Ok(r) if r.bind(py).is(&*pyo3::types::PyBool::new(py, false)) => {
                                stop.request(StopReason::Requested)
                            }
                            Ok(_) => {}
                            Err(e) => {
                                stop.request(StopReason::Requested);
                                raise(e);
                            }
                        }
                    }
                    if let Err(e) = self.apply_pending(scripts) {
                        stop.request(StopReason::Requested);
                        raise(crate::error::SimulationError::new_err(e.to_string()));
                    }
                })
            };
            watching_signals(&stop, &raise, || {
                pool.install(|| sim.run_controlled(&out_dir, &mut controller, &stop))
            })
        });
        let summary = result.map_err(|e| {
            // Outputs that could not be set up leave the state as built: another `run` may try again.
            if inner.sim.time() == 0.0 {
                inner.mode = Mode::Fresh;
            }
            simulation_error(py, &e)
        })?;
        match raised.into_inner().unwrap_or_else(|p| p.into_inner()) {
            Some(e) => Err(e),
            None => Ok(PyRunSummary { inner: summary }),
        }
    }

    /// Prescribes the motion of boundary `name` from the next step on, in place of the scene's: its
    /// nodes go to `R (X - center) + center + translation` from their positions `X` when the scene was
    /// built, and its rotations to `R`. `R` is `rotation` (a 3 × 3 rotation matrix) or the rotation by
    /// `angle` [rad] (default 0) about `axis` (default z), not both. Stiffnesses, axes and timing stay
    /// as the scene sets them.
    #[pyo3(signature = (name, *, angle = None, axis = None, center = [0.0; 3], translation = [0.0; 3], rotation = None))]
    fn set_motion(
        &self,
        name: &str,
        angle: Option<f64>,
        axis: Option<[f64; 3]>,
        center: [f64; 3],
        translation: [f64; 3],
        rotation: Option<[[f64; 3]; 3]>,
    ) -> PyResult<()> {
        self.check_boundary(name)?;
        let invalid = |e: ScriptTargetError| PyValueError::new_err(format!("boundary `{name}`: {e}"));
        if rotation.is_some() && (angle.is_some() || axis.is_some()) {
            return Err(PyValueError::new_err(format!(
                "boundary `{name}`: give either `rotation` or `angle` and `axis`, not both"
            )));
        }
        let mut motion = match rotation {
            Some(r) => RigidMotion {
                rotation: Matrix3::from_fn(|i, j| r[i][j]),
                center: vector(center),
                translation: Vector3::zeros(),
            },
            None => {
                let axis = vector(axis.unwrap_or([0.0, 0.0, 1.0]));
                RigidMotion::about_axis(axis, angle.unwrap_or(0.0), vector(center)).map_err(invalid)?
            }
        };
        motion.translation = vector(translation);
        motion.check().map_err(invalid)?;
        self.queue(Command::Motion(name.into(), Some(motion)))
    }

    /// Gives boundary `name` back its scene motion from the next step on.
    fn reset_motion(&self, name: &str) -> PyResult<()> {
        self.check_boundary(name)?;
        self.queue(Command::Motion(name.into(), None))
    }

    /// Sets the scale of load `name` from the next step on, in place of the scene's scale function
    /// (`None`: back to the scene's).
    fn set_load_scale(&self, name: &str, scale: Option<f64>) -> PyResult<()> {
        check_name(name, &self.load_names, "load")?;
        if let Some(s) = scale.filter(|s| !s.is_finite()) {
            return Err(PyValueError::new_err(format!(
                "load `{name}`: the scale must be finite (got {s})"
            )));
        }
        self.queue(Command::LoadScale(name.into(), scale))
    }

    /// Positions of the displacement nodes (n × 3) [m]: a read-only view of the simulation's memory
    /// that follows every step (copy it to keep a snapshot).
    #[getter]
    fn positions<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let inner = slf.get().lock()?;
        array::view(&inner.sim.potential().parts.state.x, slf.as_any())
    }

    /// Velocities of the displacement nodes (n × 3) [m/s]: a read-only view, like `positions`.
    #[getter]
    fn velocities<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let inner = slf.get().lock()?;
        array::view(&inner.sim.potential().parts.state.v, slf.as_any())
    }

    /// Rest positions of the displacement nodes (n × 3) [m]: a read-only view.
    #[getter]
    fn rest_positions<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let inner = slf.get().lock()?;
        array::view(inner.sim.rest_positions(), slf.as_any())
    }

    /// Displacements `positions - rest_positions` (n × 3) [m]: a new array.
    #[getter]
    fn displacements<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let inner = slf.get().lock()?;
        let x = &inner.sim.potential().parts.state.x;
        let rest = inner.sim.rest_positions();
        Ok(array::vectors(
            slf.py(),
            x.iter().zip(rest).map(|(x, r)| (x - r).into()),
        ))
    }

    /// Rotations of the rotation nodes as unit quaternions (n × 4, order x, y, z, w), relative to the
    /// rest state: a read-only view.
    #[getter]
    fn quaternions<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let inner = slf.get().lock()?;
        array::view(&inner.sim.potential().parts.state.q, slf.as_any())
    }

    /// The three directors of the rotation nodes (3 × n × 3): `d1, d2, d3 = sim.directors`, the columns
    /// of each node's rotation, as in the output frames. A new array.
    #[getter]
    fn directors<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray3<f64>>> {
        let inner = slf.get().lock()?;
        Ok(array::directors(slf.py(), &inner.sim.potential().parts.state.q))
    }

    /// Angular velocities of the rotation nodes (n × 3) [rad/s]: a read-only view.
    #[getter]
    fn angular_velocities<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let inner = slf.get().lock()?;
        array::view(&inner.sim.potential().parts.state.omega, slf.as_any())
    }

    /// The shells of the scene, one dict each: `name`; `displacement_nodes` and `rotation_nodes`, the
    /// system nodes of the shell's nodes (1-D, or 2-D columns for the volumetric model);
    /// `displacement_elements` and `rotation_elements` (m × 3 or m × 6) in shell numbering, so that
    /// `displacement_nodes[displacement_elements]` indexes `positions`.
    #[getter]
    fn shells<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let inner = self.lock()?;
        let list = PyList::empty(py);
        for p in inner.sim.placements() {
            let d = PyDict::new(py);
            d.set_item("name", &p.name)?;
            d.set_item("displacement_nodes", node_array(py, &p.disp, p.rest_disp.len())?)?;
            d.set_item("rotation_nodes", node_array(py, &p.rot, p.rest_rot.len())?)?;
            d.set_item("displacement_elements", elements(py, &p.disp_elements)?)?;
            d.set_item("rotation_elements", elements(py, &p.rot_elements)?)?;
            list.append(d)?;
        }
        Ok(list)
    }

    /// The output frame of the current state, exactly as `run` writes it to a `.vtu` file at this time.
    fn frame(&self, py: Python<'_>) -> PyResult<PyFrame> {
        let frame = self.lock()?.sim.frame();
        PyFrame::new(py, frame)
    }

    fn __repr__(&self) -> String {
        format!("Simulation({:?})", self.name)
    }
}

/// Runs `work` on a thread of its own while this thread (the caller's, without the GIL) watches for
/// Ctrl-C: Python runs its signal handlers on the main thread only, and a run's steps and `on_step`
/// calls happen on other threads (the run's thread pool). A signal requests the stop, and the
/// `KeyboardInterrupt` goes to `raise`.
fn watching_signals<R: Send>(stop: &StopRequest, raise: &(dyn Fn(PyErr) + Sync), work: impl FnOnce() -> R + Send) -> R {
    let (done, finished) = std::sync::mpsc::channel::<()>();
    std::thread::scope(|scope| {
        let worker = scope.spawn(move || {
            let result = work();
            let _ = done.send(());
            result
        });
        // How often the signals are checked: short against a person's reaction, long against the
        // cost of taking the GIL.
        let poll = std::time::Duration::from_millis(20);
        while let Err(std::sync::mpsc::RecvTimeoutError::Timeout) = finished.recv_timeout(poll) {
            if let Err(e) = Python::attach(|py| py.check_signals()) {
                stop.request(StopReason::Interrupt);
                raise(e);
            }
        }
        match worker.join() {
            Ok(result) => result,
            Err(panic) => std::panic::resume_unwind(panic),
        }
    })
}

/// The system nodes of `n` shell nodes.
fn node_array<'py>(py: Python<'py>, map: &NodeMap, n: usize) -> PyResult<Bound<'py, PyAny>> {
    use numpy::IntoPyArray;
    match map {
        NodeMap::Offset(start) => Ok((*start as i64..(start + n) as i64)
            .collect::<Vec<_>>()
            .into_pyarray(py)
            .into_any()),
        NodeMap::Columns(columns) => {
            let rows: Vec<Vec<i64>> = columns.iter().map(|c| c.iter().map(|&i| i as i64).collect()).collect();
            Ok(PyArray2::from_vec2(py, &rows)
                .map_err(|e| PyValueError::new_err(e.to_string()))?
                .into_any())
        }
    }
}

fn elements<'py>(py: Python<'py>, elements: &[Vec<usize>]) -> PyResult<Bound<'py, PyArray2<i64>>> {
    let rows: Vec<Vec<i64>> = elements.iter().map(|e| e.iter().map(|&i| i as i64).collect()).collect();
    if rows.is_empty() {
        return Ok(PyArray2::zeros(py, [0, 3], false));
    }
    PyArray2::from_vec2(py, &rows).map_err(|e| PyValueError::new_err(e.to_string()))
}
