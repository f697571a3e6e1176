//! The incremental potential of `cosserat-assembly` seen as a [`NewtonProblem`].

use crate::error::ProblemError;
use crate::problem::NewtonProblem;
use cosserat_assembly::{AssemblyError, IncrementalPotential};
use faer::sparse::SymbolicSparseColMatRef;

/// The Cayley parameter `|Δt ω|` beyond which a rotation update counts as a half turn: 1000, an angle
/// of 179.885°. Rotations in a time step are far smaller unless a massless rotation field snaps; close
/// enough to the half turn that an iterate there is as good as one at it (the residual of the other
/// unknowns does not see the difference), and the crossing moves the rotation by only 0.23°.
const HALF_TURN_PARAMETER: f64 = 1e3;

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

    /// A rotation node's update is the Cayley rotation `cay(Δt ω)`, whose angle `2 arctan(|Δt ω|/2)`
    /// approaches a half turn as `|Δt ω|` grows without bound: a rotation just beyond a half turn about
    /// `a` has its parameter at the far end of the opposite ray, `−a`. Massless rotations (no angular
    /// inertia) can have to turn that far in one step, where the rotation field snaps; the descent then
    /// runs out along `+a` for ever. Reflecting `Δt ω ← −Δt ω` when a step moves `|Δt ω|` outwards
    /// beyond 1000 (an angle of 179.885°) turns the rotation from `φ` to `2π − φ` about `a`: across the
    /// half turn by `2(π − φ)`, where the descent can reach the minimum. A step that moves
    /// inwards is left alone, so that an iterate just across can move on without being sent back.
    fn cross_singularities(&self, from: &[f64], x: &mut [f64]) {
        let parts = &self.potential.parts;
        let dt = self.potential.dt();
        let norm = |w: &[f64]| dt * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
        for k in 0..parts.layout.n_rot_nodes {
            let b = 3 * parts.layout.rot_block(k);
            let (before, after) = (norm(&from[b..b + 3]), norm(&x[b..b + 3]));
            if after > HALF_TURN_PARAMETER && after >= before {
                x[b..b + 3].iter_mut().for_each(|w| *w = -*w);
            }
        }
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
        largest * self.potential.dt()
    }

    /// A velocity unknown's magnitude is its node's distance from the origin over `Δt` (positions are
    /// `xⁿ + Δt v`, and elements difference them); an angular velocity's is `1/Δt` (rotations by
    /// angles of order one).
    fn unknown_magnitudes(&self, _x: &[f64], m: &mut [f64]) {
        let parts = &self.potential.parts;
        let dt = self.potential.dt();
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
