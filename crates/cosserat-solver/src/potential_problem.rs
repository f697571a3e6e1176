//! The incremental potential of `cosserat-assembly` seen as a [`NewtonProblem`].

use crate::error::{NewtonError, ProblemError};
use crate::newton::{NewtonReport, NewtonSolver};
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
    /// Whether every evaluated state is checked against the terms' domains
    /// ([`IncrementalPotential::check_state`]), so that the line search backs off from an iterate that
    /// turns an element inside out.
    check_iterates: bool,
    /// The last state that passed the check: Newton assembles its Hessian at the iterate whose trial
    /// evaluation was checked, which needs no second check.
    checked: Vec<f64>,
    /// Iterates the check turned back.
    rejected: usize,
    /// [`Self::characteristic_length`], computed when first needed.
    length: std::cell::OnceCell<f64>,
}

impl<'a> PotentialProblem<'a> {
    /// Wraps a potential; `fixed` marks exactly eliminated unknowns.
    pub fn new(potential: &'a mut IncrementalPotential, fixed: Option<Vec<bool>>) -> Self {
        Self {
            potential,
            fixed,
            check_iterates: true,
            checked: Vec::new(),
            rejected: 0,
            length: std::cell::OnceCell::new(),
        }
    }

    /// The same problem with its iterates left unchecked: only the solution is to be checked
    /// ([`solve_in_domain`]).
    fn with_unchecked_iterates(mut self) -> Self {
        self.check_iterates = false;
        self
    }

    /// [`IncrementalPotential::check_state`] of an iterate, when iterates are checked.
    fn check(&mut self, x: &[f64]) -> Result<(), ProblemError> {
        if self.check_iterates && self.checked != x {
            if let Err(e) = self.potential.check_state(x) {
                self.rejected += 1;
                return Err(map_error(e));
            }
            self.checked.clear();
            self.checked.extend_from_slice(x);
        }
        Ok(())
    }

    /// The potential.
    pub(crate) fn potential(&self) -> &IncrementalPotential {
        self.potential
    }

    /// The median distance between two displacement nodes that share an element (two nodes coupled in
    /// the Hessian's pattern), at the start of the step: the mesh's edge length, which turns torques
    /// into forces for the residual. 1 for a model without couplings.
    fn characteristic_length(&self) -> f64 {
        *self.length.get_or_init(|| {
            let parts = &self.potential.parts;
            let n_disp = parts.layout.n_disp_nodes;
            let pattern = self.potential.pattern().symbolic();
            let (col_ptr, row_idx) = (pattern.col_ptr(), pattern.row_idx());
            let mut lengths: Vec<f64> = (0..n_disp)
                .flat_map(|j| {
                    let column = &row_idx[col_ptr[3 * j]..col_ptr[3 * j + 1]];
                    column
                        .iter()
                        .filter(move |&&i| i % 3 == 0 && i < 3 * j)
                        .map(move |&i| (parts.state.x[i / 3] - parts.state.x[j]).norm())
                })
                .filter(|d| *d > 0.0)
                .collect();
            if lengths.is_empty() {
                return 1.0;
            }
            let middle = lengths.len() / 2;
            *lengths.select_nth_unstable_by(middle, f64::total_cmp).1
        })
    }

    /// The potential, to change its loads and state.
    pub(crate) fn potential_mut(&mut self) -> &mut IncrementalPotential {
        self.potential
    }
}

/// Lets the dynamic terms of `potential` prepare around the step's starting displacements `u`; `true`
/// when their couplings grew the Hessian's pattern, so that the solver needs a new symbolic analysis.
pub(crate) fn begin_step(potential: &mut IncrementalPotential, u: &[f64]) -> Result<bool, NewtonError> {
    potential.begin_step(u).map_err(|e| NewtonError::Problem {
        iteration: 0,
        source: map_error(e),
        residuals: Vec::new(),
    })
}

/// Where a solve of [`solve_in_domain`] starts.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SolveStart<'a> {
    /// The step's own start, with the eliminated unknowns at their targets: the last equilibrium of a
    /// quasi-static level, rest over a time step. The guess is moved back towards it where it leaves
    /// the domain.
    pub origin: &'a [f64],
    /// Whether the guess is a prediction for [`NewtonSolver::solve_from_prediction`] from `origin`.
    pub predicted: bool,
}

/// Halvings of a guess outside the domain towards the step's start before the solve starts from the
/// start itself ([`solve_in_domain`]).
const GUESS_RETRACTIONS: usize = 4;

/// Newton's solve of `potential` (with the eliminated unknowns `fixed`) from the guess `x`, for a
/// solution in every term's domain: no element turned inside out. The energy of eqs. 1–7 has no
/// barrier against inversion, so without the check Newton's iterates, and its solutions, can pass
/// through states with a director on the wrong side of its surface, which no shell can reach.
/// - A guess outside the domain (an extrapolation that folds an element) is moved back towards the
///   step's start: halved while invalid, and the start itself after [`GUESS_RETRACTIONS`] halvings.
/// - The iterates are checked, and the line search backs off from invalid ones, which also spares
///   Newton its detours through such states.
/// - Where that blocks the way to a valid solution (the check turned iterates back and every step
///   from an iterate at the edge of the domain leaves it: [`NewtonError::InfeasibleStep`]), the
///   solve is repeated from the same guess with the iterates free and the solution alone checked.
///
/// # Errors
/// As [`NewtonSolver::solve`]; a solution outside the domain is [`NewtonError::Problem`] with
/// [`ProblemError::InvalidState`].
pub(crate) fn solve_in_domain(
    solver: &mut NewtonSolver,
    potential: &mut IncrementalPotential,
    fixed: Option<Vec<bool>>,
    x: &mut [f64],
    start: SolveStart<'_>,
) -> Result<NewtonReport, NewtonError> {
    let (valid, halvings) = retract_into_domain(potential, x, start.origin);
    solver.spend_on_domain(|d| d.retracted_guesses += halvings);
    // A guess moved back all the way is no prediction any more.
    let predicted = start.predicted && valid;
    let solve = |solver: &mut NewtonSolver, problem: &mut PotentialProblem<'_>, x: &mut [f64]| {
        if predicted {
            solver.solve_from_prediction(problem, x, start.origin)
        } else {
            solver.solve(problem, x)
        }
    };
    let guess = x.to_vec();
    let mut problem = PotentialProblem::new(potential, fixed.clone());
    if valid {
        problem.checked.clone_from(&guess);
    }
    let checked = solve(solver, &mut problem, x);
    solver.spend_on_domain(|d| d.rejected_iterates += problem.rejected);
    // Only a way blocked by the check itself is retried (contact's collision bounds end a step as
    // infeasible too, and the same again without the check would end the same).
    if !(problem.rejected > 0 && matches!(checked, Err(NewtonError::InfeasibleStep { .. }))) {
        return checked;
    }
    solver.spend_on_domain(|d| d.free_retries += 1);
    x.copy_from_slice(&guess);
    let report = solve(
        solver,
        &mut PotentialProblem::new(potential, fixed).with_unchecked_iterates(),
        x,
    )?;
    potential.check_state(x).map_err(|e| NewtonError::Problem {
        iteration: report.iterations,
        source: map_error(e),
        residuals: report.residuals.clone(),
    })?;
    Ok(report)
}

/// Moves `x` back towards `origin` while it leaves the potential's domain (see [`solve_in_domain`]);
/// returns whether `x` was checked to lie in it (`false` when it was set to `origin`, the step's
/// start, which is not checked) and how often it was halved.
fn retract_into_domain(potential: &mut IncrementalPotential, x: &mut [f64], origin: &[f64]) -> (bool, usize) {
    for halvings in 0..=GUESS_RETRACTIONS {
        if potential.check_state(x).is_ok() {
            return (true, halvings);
        }
        for (x, o) in x.iter_mut().zip(origin) {
            *x = o + 0.5 * (*x - o);
        }
    }
    x.copy_from_slice(origin);
    (false, GUESS_RETRACTIONS + 1)
}

pub(crate) fn map_error(e: AssemblyError) -> ProblemError {
    match e {
        AssemblyError::NonFinite {
            ref term,
            location,
            index,
        } => ProblemError::NonFiniteEnergy {
            index,
            part: format!("term `{term}` at {location} {index}"),
        },
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
        self.check(x)?;
        self.potential.value(x).map_err(map_error)
    }

    fn gradient(&mut self, x: &[f64], grad: &mut [f64]) -> Result<f64, ProblemError> {
        self.check(x)?;
        self.potential.gradient(x, grad).map_err(map_error)
    }

    fn hessian(&mut self, x: &[f64], grad: &mut [f64], hess_values: &mut [f64]) -> Result<f64, ProblemError> {
        self.check(x)?;
        // Newton's method zeroes both buffers before the call.
        self.potential.hessian_add(x, grad, hess_values).map_err(map_error)
    }

    fn fixed_dofs(&self) -> Option<&[bool]> {
        self.fixed.as_deref()
    }

    fn max_step_fraction(&mut self, x: &[f64], dx: &[f64]) -> f64 {
        self.potential.max_step_fraction(x, dx)
    }

    fn predicts_strains(&self) -> bool {
        !self.potential.parts.shells.is_empty()
    }

    fn linearize_strains(&mut self, x: &[f64], dx: &[f64]) -> Result<(), ProblemError> {
        self.potential.linearize_strains(x, dx).map_err(map_error)
    }

    fn advance_predicted_strains(&mut self, alpha: f64) {
        self.potential.advance_predicted_strains(alpha);
    }

    fn clear_predicted_strains(&mut self) {
        self.potential.clear_predicted_strains();
    }

    fn rebase(&mut self, x: &mut [f64]) -> bool {
        let rebased = self.potential.rebase_rotations(x);
        if rebased {
            // The unknowns now describe states from other rotations.
            self.checked.clear();
        }
        rebased
    }

    fn follow_iterate(&mut self, x: &[f64]) -> bool {
        self.potential.follow_tension(x)
    }

    fn abandon_solve(&mut self) {
        self.potential.restore_step_start();
    }

    /// A rotation node's update is the Cayley rotation `cay(Δt ω)`, whose angle `2 arctan(|Δt ω|/2)`
    /// approaches a half turn as `|Δt ω|` grows without bound: a rotation just beyond a half turn about
    /// `a` has its parameter at the far end of the opposite ray, `−a`. Massless rotations (no angular
    /// inertia) can have to turn that far in one step, where the rotation field snaps; the descent then
    /// runs out along `+a` for ever. Reflecting `Δt ω ← −Δt ω` when a step moves `|Δt ω|` outwards
    /// beyond 1000 (an angle of 179.885°) turns the rotation from `φ` to `2π − φ` about `a`: across the
    /// half turn by `2(π − φ)`, where the descent can reach the minimum. A step that moves
    /// inwards is left alone, so that an iterate just across can move on without being sent back.
    /// Where the rotations can be rebased ([`IncrementalPotential::rebase_rotations`]) a quarter turn
    /// rebases them long before; the reflection serves the potentials that cannot be.
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

    /// The largest external force (with gravity) times `Δt`, torque times `Δt / ℓ`, and in a dynamic
    /// step the largest momentum `m |vⁿ|` (angular momentum `J |ωⁿ|` over `ℓ`), in the weighted units
    /// of [`residual_weights`](NewtonProblem::residual_weights) (`ℓ` the mesh's characteristic edge
    /// length). `∂Π/∂v` of a load `f` is `−Δt f`, and the residual of a velocity unknown is an error in
    /// momentum: measured against the momenta of the step, a relative tolerance bounds each node's
    /// velocity error by that fraction of the fastest node's velocity, the error control of implicit
    /// integrators (relative to the state's size), where the step's first residual alone (the net force
    /// of a freely moving shell, small beside the forces its elements carry) would ask Newton for more
    /// digits than the time discretisation can use.
    fn load_scale(&self) -> f64 {
        let parts = &self.potential.parts;
        let loads = &parts.loads;
        let length = self.characteristic_length();
        let forces = loads.forces.iter().enumerate().map(|(i, f)| {
            let weight = loads.masses.get(i).map_or(0.0, |m| *m) * loads.gravity;
            (f + weight).amax()
        });
        let torques = loads.torques.iter().map(|t| t.amax() / length);
        let gravity = loads.masses.iter().map(|m| m * loads.gravity.amax());
        let largest = forces.chain(torques).chain(gravity).fold(0.0_f64, f64::max);
        let momentum = parts.inertia.as_ref().map_or(0.0, |inertia| {
            let linear = inertia.masses.iter().zip(&parts.state.v).map(|(m, v)| m * v.amax());
            let angular =
                (inertia.rotational_inertia.iter().zip(&parts.state.omega)).map(|(j, w)| j * w.amax() / length);
            linear.chain(angular).fold(0.0_f64, f64::max)
        });
        (largest * self.potential.dt()).max(momentum)
    }

    /// Forces count as they are, torques over the mesh's characteristic edge length `ℓ` (the torque of
    /// a force pair across one element), so that the test does not depend on the unit of length.
    fn residual_weights(&self, w: &mut [f64]) {
        let layout = self.potential.parts.layout;
        w.fill(1.0);
        if layout.n_rot_nodes > 0 {
            w[3 * layout.n_disp_nodes..].fill(1.0 / self.characteristic_length());
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_non_finite_term_is_named_in_the_solver_error() {
        let e = map_error(AssemblyError::NonFinite {
            term: "gravity".into(),
            location: "node",
            index: 3,
        });
        assert_eq!(
            e,
            ProblemError::NonFiniteEnergy {
                index: 3,
                part: "term `gravity` at node 3".into()
            }
        );
        assert_eq!(e.to_string(), "non-finite energy in term `gravity` at node 3");
    }
}
