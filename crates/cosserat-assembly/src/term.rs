//! The energy-term interface: one implementation per kind of contribution to the incremental
//! potential (shell elasticity, inertia, boundary penalties, ...).
//!
//! A term is evaluated at an unknown vector `u` (end-of-step velocities and angular velocities) with the
//! start-of-step state. Each evaluation shares the nodal rotation data computed once for all terms
//! ([`NodeRotations`]). Only active terms are ever constructed; the list of their names goes into the
//! run summary.

use crate::dofs::DofLayout;
use crate::error::AssemblyError;
use crate::parallel::Parallelism;
use crate::pattern::SparsityPattern;
use crate::state::SystemState;
use cosserat_geometry::rotation::RotationJet;
use nalgebra::Matrix3;

/// End-of-step nodal rotations `R(Φ(qₖ, ωₖ, Δt))`, with derivatives when gradients are needed.
#[derive(Debug, Clone)]
pub enum NodeRotations {
    /// Rotation matrices only (energy evaluations).
    Matrices(Vec<Matrix3<f64>>),
    /// Rotation jets (gradient and Hessian evaluations; their second derivatives are kept in factored
    /// form and cost next to nothing where they are not read).
    Jets(Vec<RotationJet>),
}

impl NodeRotations {
    /// The rotation matrix of node `k`.
    #[inline]
    pub fn matrix(&self, k: usize) -> &Matrix3<f64> {
        match self {
            NodeRotations::Matrices(m) => &m[k],
            NodeRotations::Jets(j) => &j[k].r,
        }
    }

    /// The jet of node `k`.
    ///
    /// # Panics
    /// If only matrices were computed (a programmer error: gradients need jets).
    #[inline]
    #[track_caller]
    pub fn jet(&self, k: usize) -> &RotationJet {
        match self {
            NodeRotations::Jets(j) => &j[k],
            NodeRotations::Matrices(_) => panic!("rotation jets were not computed for this evaluation"),
        }
    }
}

/// Everything a term needs to evaluate itself.
#[derive(Debug, Clone, Copy)]
pub struct Evaluation<'a> {
    /// State at the start of the step.
    pub state: &'a SystemState,
    /// Layout of the unknowns.
    pub layout: &'a DofLayout,
    /// The unknowns.
    pub u: &'a [f64],
    /// Time step \[s\].
    pub dt: f64,
    /// End-of-step nodal rotations.
    pub rotations: &'a NodeRotations,
    /// Whether element kernels may run in parallel.
    pub parallelism: Parallelism,
}

/// Access to a term as [`std::any::Any`], so that a [`crate::potential::TermHandle`] can return the
/// concrete type it was created with. Implemented for every `'static` type.
pub trait AsAny: std::any::Any {
    /// `self` as `Any`.
    fn as_any(&self) -> &dyn std::any::Any;
    /// `self` as mutable `Any`.
    fn as_any_mut(&mut self) -> &mut dyn std::any::Any;
}

impl<T: std::any::Any> AsAny for T {
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
    fn as_any_mut(&mut self) -> &mut dyn std::any::Any {
        self
    }
}

/// One contribution to the incremental potential.
pub trait PotentialTerm: Send + Sync + AsAny {
    /// A short name for summaries and error messages.
    fn name(&self) -> String;

    /// Groups of blocks coupled by this term (e.g. the nodes of each element), for the sparsity
    /// pattern. Terms that only touch diagonal blocks return nothing.
    fn coupling_groups(&self) -> Vec<Vec<usize>> {
        Vec::new()
    }

    /// Called once with the final pattern, to precompute scatter positions.
    fn bind(&mut self, _pattern: &SparsityPattern) {}

    /// Energy.
    ///
    /// # Errors
    /// [`AssemblyError::NonFinite`] if any contribution is not finite.
    fn value(&self, eval: &Evaluation<'_>) -> Result<f64, AssemblyError>;

    /// Energy; adds the gradient into `grad`.
    ///
    /// # Errors
    /// As [`PotentialTerm::value`].
    fn gradient(&self, eval: &Evaluation<'_>, grad: &mut [f64]) -> Result<f64, AssemblyError>;

    /// Energy; adds the gradient into `grad` and the Hessian into the upper-triangular `values` of
    /// `pattern`.
    ///
    /// # Errors
    /// As [`PotentialTerm::value`].
    fn hessian(
        &self,
        eval: &Evaluation<'_>,
        grad: &mut [f64],
        pattern: &SparsityPattern,
        values: &mut [f64],
    ) -> Result<f64, AssemblyError>;

    /// Whether the evaluated state lies in the term's domain
    /// ([`IncrementalPotential::check_state`](crate::IncrementalPotential::check_state), which the
    /// solvers call for their iterates and solutions). Default: every state.
    ///
    /// # Errors
    /// [`AssemblyError::Infeasible`] naming what is invalid.
    fn check_state(&self, _eval: &Evaluation<'_>) -> Result<(), AssemblyError> {
        Ok(())
    }

    /// Advances the term's own per-step state after an accepted step (e.g. quadrature-point
    /// rotations), with the converged unknowns.
    fn commit(&mut self, _state: &mut SystemState, _layout: &DofLayout, _u: &[f64], _dt: f64) {}

    /// Moves the term's own rotation history (e.g. quadrature-point rotations) to the rotations that
    /// the unknowns `u` reach, within a step and without advancing anything else
    /// ([`IncrementalPotential::rebase_rotations`](crate::IncrementalPotential::rebase_rotations)).
    /// The default keeps no rotation history.
    fn rebase_rotations(&mut self, _state: &mut SystemState, _layout: &DofLayout, _u: &[f64], _dt: f64) {}

    /// Energy terms of the material model that this term evaluates, for the run summary.
    fn active_energy_terms(&self) -> Vec<String> {
        vec![self.name()]
    }

    /// Whether the term is (part of) the elastic energy of the body, which
    /// [`crate::IncrementalPotential::elastic_energy`] reports.
    fn is_elastic(&self) -> bool {
        false
    }

    /// Whether the term's coupling groups may change from step to step (contact pairs). Dynamic terms
    /// assemble into a pattern of their own, merged with the fixed one before a solve, so the fixed
    /// pattern and every element scatter stay untouched when contacts come and go.
    fn is_dynamic(&self) -> bool {
        false
    }

    /// Called before each step's Newton solve with the start-of-step state, the time step and Newton's
    /// initial guess. Returns whether the coupling groups changed (dynamic terms only).
    ///
    /// # Errors
    /// An infeasible start state.
    fn begin_step(
        &mut self,
        _state: &SystemState,
        _layout: &DofLayout,
        _dt: f64,
        _u: &[f64],
    ) -> Result<bool, AssemblyError> {
        Ok(false)
    }

    /// Whether a converged solution `eval.u` left the set of couplings prepared by
    /// [`PotentialTerm::begin_step`] (a contact came within reach that was not a candidate); the step is
    /// then prepared again from `eval.u` and re-solved.
    fn needs_resolve(&self, _eval: &Evaluation<'_>) -> bool {
        false
    }

    /// The largest fraction `α ∈ (0, 1]` of the Newton step `du` from `eval.u` that keeps the state
    /// valid (continuous collision detection). Default: the full step.
    fn max_step_fraction(&self, _eval: &Evaluation<'_>, _du: &[f64]) -> f64 {
        1.0
    }
}

/// Returns an error unless `x` is finite.
#[inline]
pub(crate) fn finite(
    x: f64,
    term: &dyn Fn() -> String,
    location: &'static str,
    index: usize,
) -> Result<f64, AssemblyError> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(AssemblyError::NonFinite {
            term: term(),
            location,
            index,
        })
    }
}
