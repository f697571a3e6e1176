//! The quasi-static incremental potential of `cosserat-assembly` on a load path, one step at a time.

use super::corrector::Tracer;
use super::{ArcLengthSettings, PathError, PathPoint, PathProblem};
use crate::error::{ProblemError, ScriptError};
use crate::potential_problem::PotentialProblem;
use crate::problem::NewtonProblem;
use cosserat_assembly::IncrementalPotential;
use faer::sparse::SymbolicSparseColMatRef;

/// Sets the loads and targets of a potential for a load factor (the scene's scripts).
pub type LoadScript<'a> = dyn FnMut(&mut IncrementalPotential, f64) -> Result<(), ScriptError> + 'a;

/// Follows the equilibrium path of a quasi-static potential from its state at `λ = 0`, one
/// equilibrium per [`step`](Self::step), by arc-length continuation ([`super::trace_path`]).
///
/// The potential must be built without inertia; `Δt` is set to 1, so the unknowns are displacement
/// increments and the residual is a force in N (torque in N·m).
pub struct PathStepper {
    tracer: Tracer,
    settings: ArcLengthSettings,
    steps: usize,
    load_factor: f64,
}

impl PathStepper {
    /// A stepper at load factor 0.
    ///
    /// # Errors
    /// [`PathError::Setup`] for invalid settings or a pattern the linear solver rejects, and
    /// [`PathError::Unsupported`] for a potential with terms whose pattern changes during a step
    /// (contact).
    pub fn new(potential: &mut IncrementalPotential, settings: &ArcLengthSettings) -> Result<Self, PathError> {
        if potential.has_dynamic_terms() {
            return Err(PathError::Unsupported("contact"));
        }
        settings.validate().map_err(PathError::Setup)?;
        potential.set_time_step(cosserat_assembly::PSEUDO_TIME_STEP);
        let fixed = potential.fixed_dofs().map(|(mask, _)| mask);
        let n = potential.n_dofs();
        let path = PotentialPath {
            problem: PotentialProblem::new(potential, fixed),
            apply: &mut |_, _| Ok(()),
            prescribed: vec![0.0; n],
            script_error: None,
        };
        let tracer = Tracer::new(&path, settings).map_err(PathError::Setup)?;
        Ok(Self {
            tracer,
            settings: *settings,
            steps: 0,
            load_factor: 0.0,
        })
    }

    /// The load factor of the last equilibrium.
    pub fn load_factor(&self) -> f64 {
        self.load_factor
    }

    /// Whether the path has reached its end load factor.
    pub fn finished(&self) -> bool {
        self.steps > 0 && super::reached_end(self.load_factor, self.settings.end, self.tracer.last_increment())
    }

    /// The next equilibrium along the path; `apply(potential, λ)` sets loads and targets for every
    /// load factor tried. The potential is committed at the new equilibrium.
    ///
    /// # Errors
    /// [`PathError::StepFailed`] when the step fails with every allowed arc length,
    /// [`PathError::NoFirstArc`] when the first step's predictor moves nothing,
    /// [`PathError::TooManySteps`] past `max_steps`, and [`PathError::Scripts`] when `apply` fails; the
    /// potential then holds the last equilibrium.
    pub fn step(
        &mut self,
        potential: &mut IncrementalPotential,
        apply: &mut LoadScript<'_>,
    ) -> Result<PathPoint, PathError> {
        if self.steps == self.settings.max_steps {
            return Err(PathError::TooManySteps {
                end: self.settings.end,
                steps: self.steps,
                load_factor: self.load_factor,
            });
        }
        let fixed = potential.fixed_dofs().map(|(mask, _)| mask);
        let n = potential.n_dofs();
        let mut path = PotentialPath {
            problem: PotentialProblem::new(potential, fixed),
            apply,
            prescribed: vec![0.0; n],
            script_error: None,
        };
        let result = self.tracer.step(&mut path, self.steps + 1, self.load_factor);
        if let Some(error) = path.script_error {
            return Err(PathError::Scripts(error));
        }
        let point = result?;
        self.steps += 1;
        self.load_factor = point.load_factor;
        Ok(point)
    }
}

/// Follows the equilibrium path of a quasi-static potential from its current state at `λ = 0` to
/// `λ = settings.end` with a [`PathStepper`], calling `reached(potential, point)` at every equilibrium.
///
/// # Errors
/// As [`PathStepper::new`] and [`PathStepper::step`]; the potential then holds the last equilibrium.
pub fn trace_quasi_static(
    potential: &mut IncrementalPotential,
    settings: &ArcLengthSettings,
    apply: &mut LoadScript<'_>,
    reached: &mut dyn FnMut(&IncrementalPotential, &PathPoint),
) -> Result<Vec<PathPoint>, PathError> {
    let mut stepper = PathStepper::new(potential, settings)?;
    let mut points = Vec::new();
    while !stepper.finished() {
        let point = stepper.step(potential, apply)?;
        reached(potential, &point);
        points.push(point);
    }
    Ok(points)
}

/// An [`IncrementalPotential`] without inertia whose loads and targets `apply` sets.
struct PotentialPath<'a, 'b, 'c> {
    problem: PotentialProblem<'a>,
    apply: &'b mut LoadScript<'c>,
    /// The fixed unknowns' increments for the current load factor.
    prescribed: Vec<f64>,
    /// The first failure of `apply` (the path cannot go on: no shorter step helps).
    script_error: Option<ScriptError>,
}

impl NewtonProblem for PotentialPath<'_, '_, '_> {
    fn n_dofs(&self) -> usize {
        self.problem.n_dofs()
    }
    fn hessian_pattern(&self) -> SymbolicSparseColMatRef<'_, usize> {
        self.problem.hessian_pattern()
    }
    fn value(&mut self, x: &[f64]) -> Result<f64, ProblemError> {
        self.problem.value(x)
    }
    fn gradient(&mut self, x: &[f64], grad: &mut [f64]) -> Result<f64, ProblemError> {
        self.problem.gradient(x, grad)
    }
    fn hessian(&mut self, x: &[f64], grad: &mut [f64], hess_values: &mut [f64]) -> Result<f64, ProblemError> {
        self.problem.hessian(x, grad, hess_values)
    }
    fn fixed_dofs(&self) -> Option<&[bool]> {
        self.problem.fixed_dofs()
    }
    fn load_scale(&self) -> f64 {
        self.problem.load_scale()
    }
    fn unknown_magnitudes(&self, x: &[f64], m: &mut [f64]) {
        self.problem.unknown_magnitudes(x, m);
    }
    fn residual_weights(&self, w: &mut [f64]) {
        self.problem.residual_weights(w);
    }
    fn follow_iterate(&mut self, x: &[f64]) -> bool {
        self.problem.follow_iterate(x)
    }
    fn abandon_solve(&mut self) {
        self.problem.abandon_solve();
    }
}

impl PathProblem for PotentialPath<'_, '_, '_> {
    fn set_load_factor(&mut self, lambda: f64) -> Result<(), ProblemError> {
        if let Some(e) = &self.script_error {
            return Err(ProblemError::InvalidState { reason: e.0.clone() });
        }
        let potential = self.problem.potential_mut();
        if let Err(e) = (self.apply)(potential, lambda) {
            let reason = e.0.clone();
            self.script_error = Some(e);
            return Err(ProblemError::InvalidState { reason });
        }
        if let Some((_, values)) = potential.fixed_dofs() {
            self.prescribed = values;
        }
        Ok(())
    }

    fn prescribe(&self, x: &mut [f64]) {
        if let Some(mask) = self.problem.fixed_dofs() {
            for ((x, v), _) in x.iter_mut().zip(&self.prescribed).zip(mask).filter(|(_, m)| **m) {
                *x = *v;
            }
        }
    }

    fn commit(&mut self, x: &[f64]) {
        self.problem.potential_mut().commit(x);
    }

    /// Displacement increments count, rotation increments do not: the arc length is a length.
    fn arc_length_weights(&self, w: &mut [f64]) {
        let layout = self.problem.potential().parts.layout;
        w.fill(0.0);
        w[..3 * layout.n_disp_nodes].fill(1.0);
    }
}
