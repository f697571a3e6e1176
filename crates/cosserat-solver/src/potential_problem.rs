//! The incremental potential of `cosserat-assembly` seen as a [`NewtonProblem`].

use crate::error::ProblemError;
use crate::problem::NewtonProblem;
use cosserat_assembly::{AssemblyError, IncrementalPotential};
use faer::sparse::SymbolicSparseColMatRef;

/// Adapts an [`IncrementalPotential`] (with its eliminated unknowns) to Newton's method.
pub struct PotentialProblem<'a> {
    potential: &'a mut IncrementalPotential,
    fixed: Option<Vec<bool>>,
}

impl<'a> PotentialProblem<'a> {
    /// Wraps a potential; `fixed` marks exactly eliminated unknowns.
    pub fn new(potential: &'a mut IncrementalPotential, fixed: Option<Vec<bool>>) -> Self {
        Self { potential, fixed }
    }

    /// The potential.
    pub(crate) fn potential(&self) -> &IncrementalPotential {
        self.potential
    }

    /// The potential, to change its loads and state.
    pub(crate) fn potential_mut(&mut self) -> &mut IncrementalPotential {
        self.potential
    }
}

pub(crate) fn map_error(e: AssemblyError) -> ProblemError {
    match e {
        AssemblyError::NonFinite { index, .. } => ProblemError::NonFiniteEnergy { index },
        other => ProblemError::InvalidState {
            reason: other.to_string(),
        },
    }
}

impl NewtonProblem for PotentialProblem<'_> {
    fn n_dofs(&self) -> usize {
        self.potential.n_dofs()
    }

    fn hessian_pattern(&self) -> SymbolicSparseColMatRef<'_, usize> {
        self.potential.pattern().symbolic()
    }

    fn value(&mut self, x: &[f64]) -> Result<f64, ProblemError> {
        self.potential.value(x).map_err(map_error)
    }

    fn gradient(&mut self, x: &[f64], grad: &mut [f64]) -> Result<f64, ProblemError> {
        self.potential.gradient(x, grad).map_err(map_error)
    }

    fn hessian(&mut self, x: &[f64], grad: &mut [f64], hess_values: &mut [f64]) -> Result<f64, ProblemError> {
        // Newton's method zeroes both buffers before the call.
        self.potential.hessian_add(x, grad, hess_values).map_err(map_error)
    }

    fn fixed_dofs(&self) -> Option<&[bool]> {
        self.fixed.as_deref()
    }

    fn max_step_fraction(&mut self, x: &[f64], dx: &[f64]) -> f64 {
        self.potential.max_step_fraction(x, dx)
    }

    /// The largest external force (with gravity) or torque times `Δt`: `∂Π/∂v` of a load `f` is `−Δt f`.
    fn load_scale(&self) -> f64 {
        let loads = &self.potential.parts.loads;
        let forces = loads.forces.iter().enumerate().map(|(i, f)| {
            let weight = loads.masses.get(i).map_or(0.0, |m| *m) * loads.gravity;
            (f + weight).amax()
        });
        let torques = loads.torques.iter().map(|t| t.amax());
        let gravity = loads.masses.iter().map(|m| m * loads.gravity.amax());
        let largest = forces.chain(torques).chain(gravity).fold(0.0_f64, f64::max);
        largest * self.potential.dt
    }

    /// A velocity unknown's magnitude is its node's distance from the origin over `Δt` (positions are
    /// `xⁿ + Δt v`, and elements difference them); an angular velocity's is `1/Δt` (rotations by
    /// angles of order one).
    fn unknown_magnitudes(&self, _x: &[f64], m: &mut [f64]) {
        let parts = &self.potential.parts;
        let dt = self.potential.dt;
        for (i, x) in parts.state.x.iter().enumerate() {
            let b = 3 * parts.layout.disp_block(i);
            m[b..b + 3].fill(x.norm() / dt);
        }
        for k in 0..parts.layout.n_rot_nodes {
            let b = 3 * parts.layout.rot_block(k);
            m[b..b + 3].fill(1.0 / dt);
        }
    }
}
