//! The quasi-static incremental potential of `cosserat-assembly` on a load path.

use super::{ArcLengthSettings, PathError, PathPoint, PathProblem, trace_path};
use crate::error::ProblemError;
use crate::potential_problem::PotentialProblem;
use crate::problem::NewtonProblem;
use cosserat_assembly::IncrementalPotential;
use faer::sparse::SymbolicSparseColMatRef;

/// An [`IncrementalPotential`] without inertia (`Δt = 1`, the unknowns are displacement increments)
/// whose loads and targets `apply(potential, λ)` sets.
struct PotentialPath<'a, 'b> {
    problem: PotentialProblem<'a>,
    apply: &'b mut dyn FnMut(&mut IncrementalPotential, f64),
    /// The fixed unknowns' increments for the current load factor.
    prescribed: Vec<f64>,
}

impl NewtonProblem for PotentialPath<'_, '_> {
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
}

impl PathProblem for PotentialPath<'_, '_> {
    fn set_load_factor(&mut self, lambda: f64) -> Result<(), ProblemError> {
        let potential = self.problem.potential_mut();
        (self.apply)(potential, lambda);
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

/// Follows the equilibrium path of a quasi-static potential from its current state at `λ = 0` to
/// `λ = settings.end` by arc-length continuation ([`trace_path`]), calling `apply(potential, λ)` to set
/// loads and targets and `reached(potential, point)` at every equilibrium.
///
/// The potential must be built without inertia; `Δt` is set to 1, so the unknowns are displacement
/// increments and the residual is a force in N (torque in N·m). Terms whose pattern changes during a
/// step (contact) are not supported.
///
/// # Errors
/// [`PathError`] as [`trace_path`], and [`PathError::Unsupported`] for a potential with contact.
pub fn trace_quasi_static(
    potential: &mut IncrementalPotential,
    settings: &ArcLengthSettings,
    apply: &mut dyn FnMut(&mut IncrementalPotential, f64),
    reached: &mut dyn FnMut(&IncrementalPotential, &PathPoint),
) -> Result<Vec<PathPoint>, PathError> {
    if potential.has_dynamic_terms() {
        return Err(PathError::Unsupported("contact"));
    }
    potential.dt = 1.0;
    let fixed = potential.fixed_dofs().map(|(mask, _)| mask);
    let n = potential.n_dofs();
    let mut path = PotentialPath {
        problem: PotentialProblem::new(potential, fixed),
        apply,
        prescribed: vec![0.0; n],
    };
    trace_path(&mut path, settings, &mut |p, point| {
        reached(p.problem.potential(), point)
    })
}
