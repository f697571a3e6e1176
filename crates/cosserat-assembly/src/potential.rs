//! The incremental potential of one time step: the sum of all active terms, with the sparsity pattern
//! and the per-evaluation nodal rotation data.
//!
//! This is the object the Newton solver minimises. It is composed of independently built parts (shell
//! energies, inertia, loads, boundary penalties, exact position constraints) and of further terms
//! inserted by their owners (another model's elastic energy, contact), who keep a typed
//! [`TermHandle`] to reach them. It holds no physics itself: it evaluates the terms, owns the buffers
//! they share, and advances the state after an accepted step.
//!
//! The time step of the next evaluation belongs to whoever advances the potential (the time stepper,
//! the quasi-static stepper), which sets it with [`IncrementalPotential::set_time_step`] before each
//! solve; until then it is [`PSEUDO_TIME_STEP`].

use crate::boundary::{AngularVelocityPenalty, PositionConstraint, PositionPenalty, RotationPenalty};
use crate::dofs::DofLayout;
use crate::error::AssemblyError;
use crate::inertia::{InertiaTerm, LoadTerm};
use crate::parallel::Parallelism;
use crate::pattern::SparsityPattern;
use crate::state::SystemState;
use crate::term::{Evaluation, NodeRotations, PotentialTerm};
use cosserat_geometry::rotation::{RotationJet, quaternion_update, rotation_matrix};
use nalgebra::{Matrix3, Quaternion};
use rayon::prelude::*;
use std::marker::PhantomData;

/// The time step of quasi-static loading, where the unknowns are displacement increments and the
/// residual a force: the pseudo time advances by one per load level.
pub const PSEUDO_TIME_STEP: f64 = 1.0;

/// A term inserted into a potential, by its type: [`IncrementalPotential::term`] and
/// [`IncrementalPotential::term_mut`] return it as a `T`. Handles are cheap to copy; a handle belongs
/// to the potential that issued it.
pub struct TermHandle<T> {
    index: usize,
    _term: PhantomData<fn() -> T>,
}

impl<T> Clone for TermHandle<T> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<T> Copy for TermHandle<T> {}

impl<T> std::fmt::Debug for TermHandle<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "TermHandle({})", self.index)
    }
}

/// A shell's elastic energy, with the controls scripts need (rest fields).
pub trait ShellEnergy: PotentialTerm {
    /// Number of quadrature points.
    fn n_points(&self) -> usize;
    /// Sets the rest-metric growth factor and the rest curvature (world frame) per point; `None` = default.
    fn set_rest_fields_dyn(&mut self, fields: &mut dyn FnMut(usize) -> (Option<f64>, Option<Matrix3<f64>>));
    /// Clears prescribed rest fields.
    fn clear_rest_fields_dyn(&mut self);
    /// Projects element Hessians onto the positive semi-definite cone when set.
    fn set_project_pd(&mut self, on: bool);
    /// The smallest signed area ratio over all quadrature points in a state: the current area element
    /// over the rest one, negative where the element is folded over relative to its directors
    /// (`(F̂₁ × F̂₂) · R n₀`). Below zero means an inverted element.
    fn min_area_ratio(&self, state: &SystemState) -> f64;
    /// The strain-quadratic elastic energy of a state split by strain part (membrane, drilling,
    /// transverse shear, bending).
    fn energy_parts(&self, state: &SystemState) -> cosserat_material::strain_space::EnergyParts;
    /// Linearises the strains at `eval.u` along the Newton direction `du` (the mixed-integration-point
    /// Newton method).
    fn linearize_strains(&mut self, eval: &Evaluation<'_>, du: &[f64]);
    /// A step `α du` along the last linearised direction was taken: the next Hessians weight their
    /// second-order terms with the stresses of the linearly predicted strains.
    fn advance_predicted_strains(&mut self, alpha: f64);
    /// Hessians use the points' own stresses again.
    fn clear_predicted_strains(&mut self);
    /// Whether the stabilisation follows the membrane stresses ([`Self::follow_tension`]).
    fn follows_tension(&self) -> bool;
    /// Lets the stabilisation follow the membrane stresses of the iterate `eval.u` for the rest of the
    /// step; returns whether the energy changed.
    fn follow_tension(&mut self, eval: &Evaluation<'_>) -> bool;
    /// The step was abandoned: the next takes its stabilisation from its own start.
    fn release_tension(&mut self);
    /// The step was committed into `state`: the stresses its stabilisation held carry over to the
    /// next step.
    fn commit_tension(&mut self, state: &mut SystemState);
}

impl<const NU: usize, const NR: usize, const NL: usize, const NE: usize, const NB: usize> ShellEnergy
    for crate::shell::ShellTerm<NU, NR, NL, NE, NB>
{
    fn n_points(&self) -> usize {
        self.discretization().rest.shapes.len()
    }

    fn set_rest_fields_dyn(&mut self, fields: &mut dyn FnMut(usize) -> (Option<f64>, Option<Matrix3<f64>>)) {
        self.set_rest_fields(fields);
    }

    fn clear_rest_fields_dyn(&mut self) {
        self.clear_rest_fields();
    }

    fn set_project_pd(&mut self, on: bool) {
        self.project_pd = on;
    }

    fn min_area_ratio(&self, state: &SystemState) -> f64 {
        self.min_area_ratio(state)
    }

    fn energy_parts(&self, state: &SystemState) -> cosserat_material::strain_space::EnergyParts {
        self.energy_parts(state)
    }

    fn linearize_strains(&mut self, eval: &Evaluation<'_>, du: &[f64]) {
        self.linearize_strains(eval, du);
    }

    fn advance_predicted_strains(&mut self, alpha: f64) {
        self.advance_predicted_strains(alpha);
    }

    fn clear_predicted_strains(&mut self) {
        self.clear_predicted_strains();
    }

    fn follows_tension(&self) -> bool {
        self.follows_tension()
    }

    fn follow_tension(&mut self, eval: &Evaluation<'_>) -> bool {
        self.follow_tension(eval)
    }

    fn release_tension(&mut self) {
        self.release_tension();
    }

    fn commit_tension(&mut self, state: &mut SystemState) {
        self.commit_tension(state);
    }
}

/// The parts of an incremental potential.
pub struct PotentialParts {
    /// Layout of the unknowns.
    pub layout: DofLayout,
    /// Start-of-step state.
    pub state: SystemState,
    /// Shell energies.
    pub shells: Vec<Box<dyn ShellEnergy>>,
    /// Inertia (absent in quasi-static runs).
    pub inertia: Option<InertiaTerm>,
    /// Gravity, forces and torques.
    pub loads: LoadTerm,
    /// Position penalties.
    pub position_penalties: Vec<PositionPenalty>,
    /// Rotation penalties.
    pub rotation_penalties: Vec<RotationPenalty>,
    /// Angular-velocity penalties.
    pub omega_penalties: Vec<AngularVelocityPenalty>,
    /// Exactly eliminated positions.
    pub position_constraints: Vec<PositionConstraint>,
}

/// The lumped masses of a model's nodes, from which every model's inertia and gravity are built.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct NodalMasses {
    /// Mass per displacement node \[kg\].
    pub masses: Vec<f64>,
    /// Rotational inertia per rotation node \[kg·m²\].
    pub rotational_inertia: Vec<f64>,
    /// Mass-proportional damping per displacement node \[1/s\].
    pub damping: Vec<f64>,
}

impl PotentialParts {
    /// The parts every model shares: the state, the model's shell energies (if any), inertia from the
    /// lumped masses (dynamic runs only), gravity on those masses, zero nodal forces and torques, and
    /// no boundary terms yet (scripts add them).
    pub fn with_inertia_and_loads(
        layout: DofLayout,
        state: SystemState,
        shells: Vec<Box<dyn ShellEnergy>>,
        nodal: NodalMasses,
        options: &crate::system::SystemOptions,
    ) -> Self {
        let loads = LoadTerm {
            masses: nodal.masses.clone(),
            gravity: options.gravity,
            forces: vec![nalgebra::Vector3::zeros(); layout.n_disp_nodes],
            torques: vec![nalgebra::Vector3::zeros(); layout.n_rot_nodes],
        };
        let inertia = options.dynamic.then_some(InertiaTerm {
            masses: nodal.masses,
            rotational_inertia: nodal.rotational_inertia,
            damping: nodal.damping,
        });
        Self {
            layout,
            state,
            shells,
            inertia,
            loads,
            position_penalties: Vec::new(),
            rotation_penalties: Vec::new(),
            omega_penalties: Vec::new(),
            position_constraints: Vec::new(),
        }
    }
}

/// The incremental potential `Π(v, ω)` of a time step.
pub struct IncrementalPotential {
    /// The parts; scripts change targets, forces and rest fields through them between steps.
    pub parts: PotentialParts,
    /// Whether element kernels run in parallel.
    pub parallelism: Parallelism,
    /// Terms inserted by their owners ([`IncrementalPotential::insert`]).
    terms: Vec<Box<dyn PotentialTerm>>,
    /// Time step of the next evaluation \[s\].
    dt: f64,
    pattern: SparsityPattern,
    rotations: NodeRotations,
    /// The buffer of the other kind (matrices or jets), kept so that switching between energy and
    /// gradient evaluations reuses storage instead of allocating megabytes per evaluation.
    spare_rotations: NodeRotations,
    /// Present only when a dynamic term (contact) exists.
    dynamic: Option<DynamicPattern>,
    /// The step's start rotations while rebased ones stand in for them
    /// ([`IncrementalPotential::rebase_rotations`]).
    step_start_rotations: Option<StartRotations>,
}

/// The rotations of the nodes and of the quadrature points at the start of a step.
struct StartRotations {
    nodes: Vec<Quaternion<f64>>,
    points: Vec<Quaternion<f64>>,
}

/// The Cayley parameter `Δt |ω|` of a node's rotation update beyond which the rotations are rebased:
/// a quarter turn. The Cayley map reaches a half turn only as its parameter grows without bound, and
/// its derivative, hence every rotation's residual and Newton step, shrinks with the square of the
/// parameter; rebased, each update starts again from zero.
const REBASE_PARAMETER: f64 = 2.0;

/// The pattern of the dynamic terms and its merge with the fixed pattern.
struct DynamicPattern {
    /// Pattern of the dynamic terms' couplings (plus all diagonal blocks).
    own: SparsityPattern,
    /// Union of the fixed and the dynamic pattern: what the solver sees.
    union: SparsityPattern,
    /// Position in `union` of every entry of the fixed pattern, and of every entry of `own`.
    map_fixed: Vec<u32>,
    map_own: Vec<u32>,
    fixed_values: Vec<f64>,
    own_values: Vec<f64>,
}

impl DynamicPattern {
    fn build(n_blocks: usize, fixed: &SparsityPattern, groups: &[Vec<usize>]) -> Self {
        let own = SparsityPattern::from_groups(n_blocks, groups.iter().map(|g| g.as_slice()));
        let union = SparsityPattern::union(fixed, &own);
        let map = |p: &SparsityPattern| -> Vec<u32> {
            let sym = p.symbolic();
            let mut m = Vec::with_capacity(p.nnz());
            for j in 0..p.n_dofs() {
                for k in sym.col_ptr()[j]..sym.col_ptr()[j + 1] {
                    let i = sym.row_idx()[k];
                    m.push(union.entry(i, j).expect("the union contains both patterns") as u32);
                }
            }
            m
        };
        let (map_fixed, map_own) = (map(fixed), map(&own));
        let (nf, no) = (fixed.nnz(), own.nnz());
        Self {
            own,
            union,
            map_fixed,
            map_own,
            fixed_values: vec![0.0; nf],
            own_values: vec![0.0; no],
        }
    }
}

impl IncrementalPotential {
    /// Builds the pattern of all parts and binds them to it; the time step is [`PSEUDO_TIME_STEP`]
    /// until a stepper sets it.
    pub fn new(parts: PotentialParts) -> Self {
        let n_rot = parts.layout.n_rot_nodes;
        let mut potential = Self {
            parts,
            parallelism: Parallelism::Rayon,
            terms: Vec::new(),
            dt: PSEUDO_TIME_STEP,
            pattern: SparsityPattern::from_groups(0, std::iter::empty::<&[usize]>()),
            rotations: NodeRotations::Matrices(vec![Matrix3::identity(); n_rot]),
            spare_rotations: NodeRotations::Jets(Vec::new()),
            step_start_rotations: None,
            dynamic: None,
        };
        potential.rebuild_fixed();
        potential
    }

    /// Adds a term and returns its handle. A term whose couplings are fixed extends the Hessian's
    /// pattern (every term is bound again); a dynamic one (contact) gets its own pattern, merged with
    /// the fixed one.
    pub fn insert<T: PotentialTerm + 'static>(&mut self, term: T) -> TermHandle<T> {
        let dynamic = term.is_dynamic();
        self.terms.push(Box::new(term));
        if dynamic {
            self.rebuild_dynamic();
        } else {
            self.rebuild_fixed();
        }
        TermHandle {
            index: self.terms.len() - 1,
            _term: PhantomData,
        }
    }

    /// The term of a handle.
    ///
    /// # Panics
    /// If the handle was issued by another potential.
    pub fn term<T: PotentialTerm + 'static>(&self, handle: TermHandle<T>) -> &T {
        self.terms
            .get(handle.index)
            .and_then(|t| t.as_any().downcast_ref())
            .expect("a handle names a term of its own type in the potential that issued it")
    }

    /// The term of a handle, mutably.
    ///
    /// # Panics
    /// If the handle was issued by another potential.
    pub fn term_mut<T: PotentialTerm + 'static>(&mut self, handle: TermHandle<T>) -> &mut T {
        self.term_and_state_mut(handle).0
    }

    /// The term of a handle, mutably, beside the start-of-step state and the layout (for owners that
    /// update a term from the state, e.g. moving contact obstacles).
    ///
    /// # Panics
    /// If the handle was issued by another potential.
    pub fn term_and_state_mut<T: PotentialTerm + 'static>(
        &mut self,
        handle: TermHandle<T>,
    ) -> (&mut T, &SystemState, &DofLayout) {
        let term = self
            .terms
            .get_mut(handle.index)
            .and_then(|t| t.as_any_mut().downcast_mut())
            .expect("a handle names a term of its own type in the potential that issued it");
        (term, &self.parts.state, &self.parts.layout)
    }

    /// The time step of the next evaluation \[s\].
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// Sets the time step of the next evaluations \[s\]: the steppers call this before every attempt.
    pub fn set_time_step(&mut self, dt: f64) {
        self.dt = dt;
    }

    /// Rebuilds the fixed pattern from the shells and the fixed inserted terms and binds them to it.
    fn rebuild_fixed(&mut self) {
        let n_blocks = self.parts.layout.n_blocks();
        let mut groups: Vec<Vec<usize>> = Vec::new();
        for s in &self.parts.shells {
            groups.extend(s.coupling_groups());
        }
        for t in self.terms.iter().filter(|t| !t.is_dynamic()) {
            groups.extend(t.coupling_groups());
        }
        self.pattern = SparsityPattern::from_groups(n_blocks, groups.iter().map(|g| g.as_slice()));
        for s in &mut self.parts.shells {
            s.bind(&self.pattern);
        }
        for t in self.terms.iter_mut().filter(|t| !t.is_dynamic()) {
            t.bind(&self.pattern);
        }
        self.rebuild_dynamic();
    }

    /// Rebuilds the dynamic terms' pattern and its merge map (only if dynamic terms exist).
    /// Rebuilds the dynamic terms' pattern from their couplings now (a run resumed from a checkpoint
    /// restores the contact couplings of the run so far, which no step has announced).
    pub fn rebuild_dynamic_pattern(&mut self) {
        self.rebuild_dynamic();
    }

    fn rebuild_dynamic(&mut self) {
        if !self.has_dynamic_terms() {
            self.dynamic = None;
            return;
        }
        let groups: Vec<Vec<usize>> = self
            .terms
            .iter()
            .filter(|t| t.is_dynamic())
            .flat_map(|t| t.coupling_groups())
            .collect();
        let dynamic = DynamicPattern::build(self.parts.layout.n_blocks(), &self.pattern, &groups);
        for t in self.terms.iter_mut().filter(|t| t.is_dynamic()) {
            t.bind(&dynamic.own);
        }
        self.dynamic = Some(dynamic);
    }

    /// Whether any dynamic term exists (contact).
    pub fn has_dynamic_terms(&self) -> bool {
        self.terms.iter().any(|t| t.is_dynamic())
    }

    /// Prepares the dynamic terms for a step from the current state with Newton's initial guess `u`.
    /// Returns whether the Hessian's pattern changed (the solver must then redo its symbolic analysis).
    ///
    /// # Errors
    /// An infeasible start state.
    pub fn begin_step(&mut self, u: &[f64]) -> Result<bool, AssemblyError> {
        let (state, layout, dt) = (&self.parts.state, &self.parts.layout, self.dt);
        let mut changed = false;
        for t in self.terms.iter_mut().filter(|t| t.is_dynamic()) {
            changed |= t.begin_step(state, layout, dt, u)?;
        }
        if changed {
            self.rebuild_dynamic();
        }
        Ok(changed)
    }

    /// Whether a converged `u` needs the dynamic terms prepared again and another solve.
    pub fn needs_resolve(&mut self, u: &[f64]) -> bool {
        if !self.has_dynamic_terms() {
            return false;
        }
        self.update_rotations(u, false);
        let eval = self.evaluation(u);
        self.terms.iter().any(|t| t.needs_resolve(&eval))
    }

    /// The largest fraction of the step `du` from `u` that keeps every term's state valid.
    pub fn max_step_fraction(&mut self, u: &[f64], du: &[f64]) -> f64 {
        if !self.has_dynamic_terms() {
            return 1.0;
        }
        self.update_rotations(u, false);
        let eval = self.evaluation(u);
        self.terms.iter().map(|t| t.max_step_fraction(&eval, du)).fold(1.0, f64::min)
    }

    /// Linearises the shells' strains at `u` along the Newton direction `du` (the mixed-integration-point
    /// Newton method: see [`Self::advance_predicted_strains`]).
    ///
    /// # Errors
    /// A wrong length of `u` or `du`.
    pub fn linearize_strains(&mut self, u: &[f64], du: &[f64]) -> Result<(), AssemblyError> {
        self.check_len(u)?;
        self.check_len(du)?;
        let (shells, eval) = self.shells_at(u, true);
        for shell in shells {
            shell.linearize_strains(&eval, du);
        }
        Ok(())
    }

    /// The shells, to change, beside the evaluation at `u` (rotations updated, with their jets when
    /// `jets`).
    fn shells_at<'a>(&'a mut self, u: &'a [f64], jets: bool) -> (&'a mut [Box<dyn ShellEnergy>], Evaluation<'a>) {
        self.update_rotations(u, jets);
        let eval = Evaluation {
            state: &self.parts.state,
            layout: &self.parts.layout,
            u,
            dt: self.dt,
            rotations: &self.rotations,
            parallelism: self.parallelism,
        };
        (&mut self.parts.shells, eval)
    }

    /// The step `α du` along the last linearised direction was taken: until
    /// [`Self::clear_predicted_strains`], the shells' Hessians weight their second-order terms with the
    /// stresses of the strains predicted linearly along the steps, not with the stresses at the
    /// current point (the gradient and the energy stay exact).
    pub fn advance_predicted_strains(&mut self, alpha: f64) {
        for shell in &mut self.parts.shells {
            shell.advance_predicted_strains(alpha);
        }
    }

    /// The shells' Hessians use the stresses at the current point again.
    pub fn clear_predicted_strains(&mut self) {
        for shell in &mut self.parts.shells {
            shell.clear_predicted_strains();
        }
    }

    /// The Hessian's sparsity pattern (upper triangle): the fixed pattern, merged with the dynamic terms'
    /// couplings when there are any.
    pub fn pattern(&self) -> &SparsityPattern {
        self.dynamic.as_ref().map_or(&self.pattern, |d| &d.union)
    }

    /// Number of unknowns.
    pub fn n_dofs(&self) -> usize {
        self.parts.layout.n_dofs()
    }

    fn terms(&self) -> impl Iterator<Item = &dyn PotentialTerm> {
        let p = &self.parts;
        p.shells
            .iter()
            .map(|s| s.as_ref() as &dyn PotentialTerm)
            .chain(p.inertia.iter().map(|t| t as &dyn PotentialTerm))
            .chain(std::iter::once(&p.loads as &dyn PotentialTerm))
            .chain(p.position_penalties.iter().map(|t| t as &dyn PotentialTerm))
            .chain(p.rotation_penalties.iter().map(|t| t as &dyn PotentialTerm))
            .chain(p.omega_penalties.iter().map(|t| t as &dyn PotentialTerm))
            .chain(self.terms.iter().map(|t| t.as_ref()))
    }

    /// Names of the active energy terms, for the run summary.
    pub fn active_terms(&self) -> Vec<String> {
        let mut names: Vec<String> = Vec::new();
        for t in self.terms() {
            if std::ptr::addr_eq(t as *const dyn PotentialTerm, &self.parts.loads as *const LoadTerm)
                && !self.parts.loads.is_active()
            {
                continue;
            }
            for n in t.active_energy_terms() {
                if !names.contains(&n) {
                    names.push(n);
                }
            }
        }
        names
    }

    /// Fills the nodal rotations of `u`: their jets when `jets` (gradients and Hessians), else their
    /// matrices (energies).
    fn update_rotations(&mut self, u: &[f64], jets: bool) {
        if matches!(self.rotations, NodeRotations::Jets(_)) != jets {
            std::mem::swap(&mut self.rotations, &mut self.spare_rotations);
        }
        let layout = self.parts.layout;
        let (q, dt, par) = (&self.parts.state.q, self.dt, self.parallelism);
        let omega = |k: usize| layout.omega(u, k);
        match &mut self.rotations {
            NodeRotations::Jets(buf) => {
                buf.resize(q.len(), RotationJet::constant(Matrix3::identity()));
                fill(buf, par, |k| RotationJet::of_update(&q[k], &omega(k), dt));
            }
            NodeRotations::Matrices(buf) => {
                buf.resize(q.len(), Matrix3::identity());
                fill(buf, par, |k| rotation_matrix(&quaternion_update(&q[k], &omega(k), dt)));
            }
        }
    }

    fn check_len(&self, u: &[f64]) -> Result<(), AssemblyError> {
        if u.len() == self.n_dofs() {
            Ok(())
        } else {
            Err(AssemblyError::WrongLength {
                expected: self.n_dofs(),
                got: u.len(),
            })
        }
    }

    /// Whether `u` leads to a state in every term's domain ([`PotentialTerm::check_state`]: no element
    /// turned inside out, for example). The energy's evaluations do not check it: the solver checks
    /// its iterates and solutions.
    ///
    /// # Errors
    /// The first term's [`AssemblyError::Infeasible`], or a wrong length of `u`.
    pub fn check_state(&mut self, u: &[f64]) -> Result<(), AssemblyError> {
        self.check_len(u)?;
        self.update_rotations(u, false);
        let eval = self.evaluation(u);
        self.terms().try_for_each(|t| t.check_state(&eval))
    }

    /// `Π(u)`.
    ///
    /// # Errors
    /// A non-finite contribution, or a wrong length of `u`.
    pub fn value(&mut self, u: &[f64]) -> Result<f64, AssemblyError> {
        self.check_len(u)?;
        self.update_rotations(u, false);
        let eval = self.evaluation(u);
        self.terms().try_fold(0.0, |acc, t| Ok(acc + t.value(&eval)?))
    }

    /// `Π(u)` and `∇Π(u)` (overwrites `grad`).
    ///
    /// # Errors
    /// As [`IncrementalPotential::value`].
    pub fn gradient(&mut self, u: &[f64], grad: &mut [f64]) -> Result<f64, AssemblyError> {
        self.check_len(u)?;
        self.update_rotations(u, true);
        grad.fill(0.0);
        let eval = self.evaluation(u);
        self.terms().try_fold(0.0, |acc, t| Ok(acc + t.gradient(&eval, grad)?))
    }

    /// `Π(u)`, `∇Π(u)` and the upper triangle of `∇²Π(u)` in the order of [`IncrementalPotential::pattern`]
    /// (overwrites both).
    ///
    /// # Errors
    /// As [`IncrementalPotential::value`].
    pub fn hessian(&mut self, u: &[f64], grad: &mut [f64], values: &mut [f64]) -> Result<f64, AssemblyError> {
        grad.fill(0.0);
        values.fill(0.0);
        self.hessian_add(u, grad, values)
    }

    /// [`IncrementalPotential::hessian`] added into `grad` and `values` instead of overwriting them.
    ///
    /// For callers whose buffers are zero already (Newton's method zeroes them before every call): it
    /// saves a pass over the Hessian's values, 34 MB at 157k unknowns.
    ///
    /// # Errors
    /// As [`IncrementalPotential::value`].
    pub fn hessian_add(&mut self, u: &[f64], grad: &mut [f64], values: &mut [f64]) -> Result<f64, AssemblyError> {
        self.check_len(u)?;
        self.update_rotations(u, true);
        let Some(mut dynamic) = self.dynamic.take() else {
            let eval = self.evaluation(u);
            let pattern = &self.pattern;
            return self
                .terms()
                .try_fold(0.0, |acc, t| Ok(acc + t.hessian(&eval, grad, pattern, values)?));
        };
        dynamic.fixed_values.fill(0.0);
        dynamic.own_values.fill(0.0);
        let result = {
            let eval = self.evaluation(u);
            let (fixed, own) = (&self.pattern, &dynamic.own);
            self.terms().try_fold(0.0, |acc, t| {
                let e = if t.is_dynamic() {
                    t.hessian(&eval, grad, own, &mut dynamic.own_values)?
                } else {
                    t.hessian(&eval, grad, fixed, &mut dynamic.fixed_values)?
                };
                Ok(acc + e)
            })
        };
        for (v, &k) in dynamic.fixed_values.iter().zip(&dynamic.map_fixed) {
            values[k as usize] += v;
        }
        for (v, &k) in dynamic.own_values.iter().zip(&dynamic.map_own) {
            values[k as usize] += v;
        }
        self.dynamic = Some(dynamic);
        result
    }

    fn evaluation<'a>(&'a self, u: &'a [f64]) -> Evaluation<'a> {
        Evaluation {
            state: &self.parts.state,
            layout: &self.parts.layout,
            u,
            dt: self.dt,
            rotations: &self.rotations,
            parallelism: self.parallelism,
        }
    }

    /// The elastic energy of the start-of-step state (no motion over the step), in J: the sum of the
    /// terms that are [`PotentialTerm::is_elastic`].
    ///
    /// # Errors
    /// A non-finite contribution.
    pub fn elastic_energy(&mut self) -> Result<f64, AssemblyError> {
        let u = vec![0.0; self.n_dofs()];
        self.update_rotations(&u, false);
        let eval = self.evaluation(&u);
        self.terms()
            .filter(|t| t.is_elastic())
            .try_fold(0.0, |acc, t| Ok(acc + t.value(&eval)?))
    }

    /// The kinetic energy `½ Σ m |v|² + ½ Σ I |ω|²` of the start-of-step state, in J (zero without inertia).
    pub fn kinetic_energy(&self) -> f64 {
        let Some(inertia) = &self.parts.inertia else { return 0.0 };
        let st = &self.parts.state;
        let translational: f64 = inertia.masses.iter().zip(&st.v).map(|(m, v)| 0.5 * m * v.norm_squared()).sum();
        let rotational: f64 = inertia
            .rotational_inertia
            .iter()
            .zip(&st.omega)
            .map(|(i, w)| 0.5 * i * w.norm_squared())
            .sum();
        translational + rotational
    }

    /// Eliminated unknowns and their values for the current targets and `Δt`: `(mask, values)`.
    pub fn fixed_dofs(&self) -> Option<(Vec<bool>, Vec<f64>)> {
        if self.parts.position_constraints.is_empty() {
            return None;
        }
        let n = self.n_dofs();
        let (mut mask, mut values) = (vec![false; n], vec![0.0; n]);
        for c in &self.parts.position_constraints {
            for (n_idx, &i) in c.nodes.iter().enumerate() {
                for a in (0..3).filter(|&a| c.active[a]) {
                    let dof = 3 * self.parts.layout.disp_block(i) + a;
                    mask[dof] = true;
                    values[dof] = (c.targets[n_idx][a] - self.parts.state.x[i][a]) / self.dt;
                }
            }
        }
        Some((mask, values))
    }

    /// Re-expresses the unknowns `u` of a step in which some node's rotation update `cay(Δt ω)` has
    /// turned by more than a quarter turn: the rotations the nodes and quadrature points reach become
    /// the step's start rotations and the angular velocities zero, the same configuration in unknowns
    /// far from the Cayley map's singularity at a half turn. A massless rotation field that snaps
    /// within a step needs this to get past a half turn. Returns whether it rebased.
    ///
    /// The energy is unchanged only where no term reads the angular velocities themselves, so nothing
    /// is rebased under rotational inertia, torque loads or angular-velocity penalties. The start
    /// rotations are kept for [`Self::restore_step_start`] until [`Self::commit`]; the quadrature
    /// points' rotations, interpolated from the nodes' updates, then follow the path of the rebased
    /// updates (as after two shorter steps).
    pub fn rebase_rotations(&mut self, u: &mut [f64]) -> bool {
        let (layout, dt) = (self.parts.layout, self.dt);
        let parameter = |k: usize| dt * layout.omega(u, k).norm();
        if !(0..layout.n_rot_nodes).any(|k| parameter(k) > REBASE_PARAMETER) || !self.rotations_are_configuration_only()
        {
            return false;
        }
        let state = &mut self.parts.state;
        if self.step_start_rotations.is_none() {
            self.step_start_rotations = Some(StartRotations {
                nodes: state.q.clone(),
                points: state.q_points.clone(),
            });
        }
        for s in &mut self.parts.shells {
            s.rebase_rotations(state, &layout, u, dt);
        }
        for t in &mut self.terms {
            t.rebase_rotations(state, &layout, u, dt);
        }
        for k in 0..layout.n_rot_nodes {
            state.q[k] = quaternion_update(&state.q[k], &layout.omega(u, k), dt);
            let b = 3 * layout.rot_block(k);
            u[b..b + 3].fill(0.0);
        }
        self.clear_predicted_strains();
        true
    }

    /// Whether the energy depends on the rotation unknowns only through the rotations they reach.
    fn rotations_are_configuration_only(&self) -> bool {
        let parts = &self.parts;
        let inertia = parts
            .inertia
            .as_ref()
            .is_some_and(|i| i.rotational_inertia.iter().any(|j| *j != 0.0));
        let torques = parts.loads.torques.iter().any(|t| *t != nalgebra::Vector3::zeros());
        !inertia && !torques && parts.omega_penalties.is_empty()
    }

    /// Lets the shells' stabilisation follow the membrane stresses of the iterate `u` where they have
    /// grown beyond what the step's start holds (a sheet pulled taut within the step), until
    /// [`Self::commit`] or [`Self::restore_step_start`]. Returns whether the energy changed: the iterate
    /// must then be evaluated anew.
    pub fn follow_tension(&mut self, u: &[f64]) -> bool {
        // The paper's strains and the other interpolations hold no stress: no rotations to update.
        if !self.parts.shells.iter().any(|s| s.follows_tension()) {
            return false;
        }
        let (shells, eval) = self.shells_at(u, false);
        let mut changed = false;
        for shell in shells {
            changed |= shell.follow_tension(&eval);
        }
        if changed {
            self.clear_predicted_strains();
        }
        changed
    }

    /// Puts back the step's start rotations after [`Self::rebase_rotations`] and the stabilisation of
    /// the step's start after [`Self::follow_tension`] (a solve that failed and is retried from the
    /// start of the step).
    pub fn restore_step_start(&mut self) {
        for shell in &mut self.parts.shells {
            shell.release_tension();
        }
        if let Some(start) = self.step_start_rotations.take() {
            self.parts.state.q = start.nodes;
            self.parts.state.q_points = start.points;
        }
    }

    /// Advances the state with converged unknowns `u` (model.md §1.7): positions, velocities, nodal and
    /// quadrature-point rotations, angular velocities. After a rebase the angular velocities are those
    /// of the update since the rebase: they start the next step's Newton iteration, and a snap's half
    /// turn repeated there would send it the wrong way.
    pub fn commit(&mut self, u: &[f64]) {
        let layout = self.parts.layout;
        let dt = self.dt;
        self.step_start_rotations = None;
        for s in &mut self.parts.shells {
            s.commit(&mut self.parts.state, &layout, u, dt);
            s.commit_tension(&mut self.parts.state);
        }
        for t in &mut self.terms {
            t.commit(&mut self.parts.state, &layout, u, dt);
        }
        let st = &mut self.parts.state;
        for i in 0..layout.n_disp_nodes {
            let v = layout.velocity(u, i);
            st.x[i] += v * dt;
            st.v[i] = v;
        }
        for k in 0..layout.n_rot_nodes {
            let w = layout.omega(u, k);
            st.q[k] = quaternion_update(&st.q[k], &w, dt);
            st.omega[k] = w;
        }
    }
}

fn fill<T: Send>(buf: &mut [T], par: Parallelism, f: impl Fn(usize) -> T + Sync) {
    match par {
        Parallelism::Sequential => buf.iter_mut().enumerate().for_each(|(k, x)| *x = f(k)),
        Parallelism::Rayon => buf.par_iter_mut().enumerate().with_min_len(256).for_each(|(k, x)| *x = f(k)),
    }
}
