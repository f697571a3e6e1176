//! The elastic energy of a Cosserat shell as a potential term.
//!
//! One generic implementation serves every element pair; the pairs in use are named by aliases
//! ([`Tri3Tri3Shell`], [`Tri6Tri3Shell`], [`Tri6Tri6Shell`]). Per element it gathers the end-of-step
//! nodal positions and the shared nodal rotation jets, runs the point kernel of `cosserat-material` at
//! each quadrature point (advancing that point's own rotation with the interpolated angular velocity),
//! maps to the element's unknowns, and scatters through precomputed positions.

use crate::dofs::DofLayout;
use crate::element_assembly::{
    ElementAssembly, ElementKernel, angular_velocities, displacement_rotation_blocks, end_of_step_positions,
};
use crate::error::AssemblyError;
use crate::parallel::{Parallelism, first_non_positive};
use crate::pattern::SparsityPattern;
use crate::state::SystemState;
use crate::strain_prediction::StrainPrediction;
use crate::term::{Evaluation, PotentialTerm};
use cosserat_geometry::rotation::{RotationJet, quaternion_update, rotation_matrix};
use cosserat_material::assumed::TyingMap;
use cosserat_material::assumed_kernel;
use cosserat_material::coupled::Coupling;
use cosserat_material::element::{
    ElementDerivatives, accumulate_gradient, accumulate_upper, assign_upper, f_hat, point_omega,
};
use cosserat_material::kernel::{
    LocalDerivatives, PointInput, PointShape, add_node_second_derivatives, linearized_membrane_strains,
    linearized_strains, point_gradient, point_hessian_predicted_into, point_value,
};
use cosserat_material::projected::{self, ElementPoint, ValuePoint};
use cosserat_material::rest::ShellRest;
use cosserat_material::strain_space::{DensityMatrix, EnergyParts, StrainVector, strain_offset};
use cosserat_material::tension::{membrane_stretch, membrane_stretch_predicted, membrane_tension};
use cosserat_material::volume::{volume_density, volume_hessian};
use cosserat_material::{AxlVariant, Moduli};
use nalgebra::{Matrix3, Quaternion, SMatrix, Vector3};
use rayon::prelude::*;
use std::borrow::Cow;

/// Everything that defines a shell's elastic term: its rest state and where its nodes and points sit
/// in the global system.
#[derive(Debug, Clone)]
pub struct ShellDiscretization<const NU: usize, const NR: usize> {
    /// Rest state per quadrature point (shape data, frames, weights, density Hessians).
    pub rest: ShellRest<NU, NR>,
    /// Displacement element connectivity, in global displacement-node indices.
    pub disp_elements: Vec<[usize; NU]>,
    /// Rotation element connectivity (same elements), in global rotation-node indices.
    pub rot_elements: Vec<[usize; NR]>,
    /// Index of this shell's first point in [`SystemState::q_points`].
    pub first_point: usize,
    /// Moduli for the nonlinear volume term, if it is active.
    pub volume: Option<Moduli>,
    /// Axial-vector variant of the curvature tensor.
    pub axl: AxlVariant,
}

/// The elastic energy of one shell with `NU`-node displacement and `NR`-node rotation elements.
/// `NL = 6 + 3 NR` locals per point, `NE = 3 (NU + NR)` unknowns and `NB = NU + NR` blocks per element.
#[derive(Debug)]
pub struct ShellTerm<const NU: usize, const NR: usize, const NL: usize, const NE: usize, const NB: usize> {
    disc: ShellDiscretization<NU, NR>,
    /// Strain offsets per point when a rest metric or rest curvature is prescribed.
    offsets: Option<Vec<StrainVector>>,
    default_offsets: Vec<StrainVector>,
    layout: DofLayout,
    /// Project each element Hessian onto the positive semi-definite cone.
    pub project_pd: bool,
    /// The element loop; each element's scratch holds a point's local derivatives.
    elements: ElementAssembly<NE, NB, LocalDerivatives<NL>>,
    /// The predicted strains of the mixed-integration-point Newton method, per point.
    prediction: StrainPrediction,
    /// The membrane stress each element's stabilisation holds in the current step once an accepted
    /// iterate has stretched some element beyond what the step's start holds
    /// ([`Self::follow_tension`]); `None`: the stresses at the step's start.
    step_tension: Option<StepTension>,
}

/// The membrane stresses that a shell's stabilisation holds within a step
/// ([`ShellTerm::follow_tension`]).
#[derive(Debug, Clone)]
struct StepTension {
    /// The stress each element's factors hold at the step's start ([`ShellTerm::start_held`]).
    start: Vec<f64>,
    /// The stress each element's factors are raised for.
    held: Vec<f64>,
}

/// An element's factors fall back when an iterate's stress has fallen below this fraction of the
/// stress they were raised for (never below the step start's): the iterates of a thin shell far from
/// equilibrium carry transient stresses of their own error. Between this and the stress the factors
/// hold they stay, so that the energy changes only where the stress has moved by a factor.
const TENSION_RELEASE: f64 = 0.25;

/// Linear displacement and rotation elements.
pub type Tri3Tri3Shell = ShellTerm<3, 3, 15, 18, 6>;
/// Quadratic displacement, linear rotation elements (the paper's main discretisation).
pub type Tri6Tri3Shell = ShellTerm<6, 3, 15, 27, 9>;
/// Quadratic displacement and rotation elements.
pub type Tri6Tri6Shell = ShellTerm<6, 6, 24, 36, 12>;

impl<const NU: usize, const NR: usize, const NL: usize, const NE: usize, const NB: usize>
    ShellTerm<NU, NR, NL, NE, NB>
{
    /// The term of a discretised shell within a system of the given layout.
    pub fn new(disc: ShellDiscretization<NU, NR>, layout: DofLayout) -> Self {
        const {
            assert!(
                NL == 6 + 3 * NR && NE == 3 * (NU + NR) && NB == NU + NR,
                "inconsistent element sizes"
            )
        };
        let default_offsets = disc.rest.shapes.iter().map(|s| strain_offset(&s.frame, None, None)).collect();
        Self {
            disc,
            offsets: None,
            default_offsets,
            layout,
            project_pd: false,
            elements: ElementAssembly::new(),
            prediction: StrainPrediction::default(),
            step_tension: None,
        }
    }

    /// The discretisation.
    pub fn discretization(&self) -> &ShellDiscretization<NU, NR> {
        &self.disc
    }

    /// Number of elements.
    pub fn n_elements(&self) -> usize {
        self.disc.disp_elements.len()
    }

    /// Sets, at every quadrature point `p`, the rest-metric growth factor `g` (the rest metric becomes
    /// `g a₀`, `None` = 1) and the rest curvature `Γ_rest` (a world-frame 3×3 tensor, `None` = 0).
    pub fn set_rest_fields(&mut self, mut fields: impl FnMut(usize) -> (Option<f64>, Option<Matrix3<f64>>)) {
        let offsets = self
            .disc
            .rest
            .shapes
            .iter()
            .enumerate()
            .map(|(p, s)| {
                let (growth, curvature) = fields(p);
                let metric = growth.map(|g| {
                    let n = s.frame.column(2);
                    (Matrix3::identity() - n * n.transpose()) * g
                });
                strain_offset(&s.frame, metric.as_ref(), curvature.as_ref())
            })
            .collect();
        self.offsets = Some(offsets);
    }

    /// The smallest signed area ratio `(F̂₁ × F̂₂) · R n₀` over all quadrature points of a state (see
    /// [`crate::ShellEnergy::min_area_ratio`]).
    pub fn min_area_ratio(&self, state: &SystemState) -> f64 {
        let rest = &self.disc.rest;
        let mut min = f64::INFINITY;
        for (e, d) in self.disc.disp_elements.iter().enumerate() {
            let x: [Vector3<f64>; NU] = std::array::from_fn(|i| state.x[d[i]]);
            for p in (0..rest.quadrature_points_per_element).map(|g| e * rest.points_per_element + g) {
                let q = &state.q_points[self.disc.first_point + p];
                min = min.min(area_ratio(&rest.shapes[p], &x, q));
            }
        }
        min
    }

    /// The smallest signed area ratio of element `e`'s quadrature points at the end of the evaluated
    /// step (its tying points, where strains are only sampled, are left out).
    fn element_min_area_ratio(&self, e: usize, eval: &Evaluation<'_>) -> f64 {
        let x = self.positions(e, eval);
        let omega = self.omegas(e, eval);
        let rest = &self.disc.rest;
        (0..rest.quadrature_points_per_element)
            .map(|g| {
                let p = e * rest.points_per_element + g;
                let shape = &self.disc.rest.shapes[p];
                let q = &eval.state.q_points[self.disc.first_point + p];
                area_ratio(shape, &x, &unnormalised_update(q, &point_omega(shape, &omega), eval.dt))
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// Rejects a step that turns an element inside out: no elastic state of a shell has a director
    /// on the other side of its surface, while the energy of eqs. 1–7 has no barrier against it, so
    /// Newton's iterates and even converged steps could pass through such states unnoticed.
    fn check_orientation(&self, eval: &Evaluation<'_>) -> Result<(), AssemblyError> {
        let n = self.disc.disp_elements.len();
        match first_non_positive(n, eval.parallelism, |e| self.element_min_area_ratio(e, eval)) {
            None => Ok(()),
            Some((e, ratio)) => Err(AssemblyError::Infeasible {
                term: PotentialTerm::name(self),
                reason: format!("element {e} turned inside out (deformed-to-rest area ratio {ratio:.3})"),
            }),
        }
    }

    /// The strain-quadratic energy of a state (its end-of-step positions and rotations) split by strain
    /// part, with the strains of the shell's discretisation.
    pub fn energy_parts(&self, state: &SystemState) -> EnergyParts {
        let n_qp = self.disc.rest.points_per_element;
        let mut parts = EnergyParts::default();
        for (e, (d, r)) in self.disc.disp_elements.iter().zip(&self.disc.rot_elements).enumerate() {
            let x: [Vector3<f64>; NU] = std::array::from_fn(|i| state.x[d[i]]);
            let node_r: [Matrix3<f64>; NR] = std::array::from_fn(|k| rotation_matrix(&state.q[r[k]]));
            let points: Vec<ValuePoint<'_, NU, NR>> = (0..n_qp)
                .map(|g| {
                    let p = e * n_qp + g;
                    let shape = &self.disc.rest.shapes[p];
                    ValuePoint {
                        shape,
                        f_hat: f_hat(shape, &x),
                        r: rotation_matrix(&state.q_points[self.disc.first_point + p]),
                        offset: self.offset(p),
                        density: self.disc.rest.densities.get(p),
                    }
                })
                .collect();
            let node_r = std::array::from_fn(|k| &node_r[k]);
            let (strains, hourglass) = match self.tying_maps(e, state) {
                Some(maps) => assumed_kernel::element_strains_and_hourglass(
                    &points,
                    node_r,
                    &self.disc.rest.element_tying(e, &maps),
                    self.disc.axl,
                ),
                None => {
                    let projection = self.disc.rest.projections.get(e);
                    (
                        projected::element_strains(&points, node_r, projection, self.disc.axl),
                        0.0,
                    )
                }
            };
            for (p, s) in points.iter().zip(&strains) {
                parts.add(s, p.density.matrix(), p.shape.weight);
            }
            // The drilling hourglass term holds turns about the normal.
            parts.drilling += hourglass;
            parts.total += hourglass;
        }
        parts
    }

    /// The tying maps of element `e` (under assumed strains) for a step that starts at `state`: a
    /// stretched element's stabilisation is raised by its membrane stress, that of its mean stretch
    /// ([`ShellRest::element_tying_maps_in_tension`]) held at the step's start ([`Self::start_held`])
    /// or predicted at the iterate that raised it ([`Self::follow_tension`]), constant between raises.
    fn tying_maps(&self, e: usize, state: &SystemState) -> Option<Cow<'_, [TyingMap]>> {
        let rest = &self.disc.rest;
        let tension = match &self.step_tension {
            _ if rest.tying_stabilization.is_empty() => 0.0,
            Some(step) => step.held[e],
            None => self.start_held(e, state),
        };
        rest.element_tying_maps_in_tension(e, tension)
    }

    /// The stress element `e`'s factors hold at the start of a step from `state`: the step start's
    /// stress where it exceeds what the last committed step held or has fallen below a quarter of that
    /// ([`TENSION_RELEASE`]), else the committed step's. A sheet whose stress varies from step to step
    /// within that band (a vibrating, buckled sheet) keeps its factors, and so its energy.
    fn start_held(&self, e: usize, state: &SystemState) -> f64 {
        let now = self.start_tension(e, state);
        let held = state.held_tension[self.held_tension_index(e)];
        if now > held || now < TENSION_RELEASE * held {
            now
        } else {
            held
        }
    }

    /// Where element `e`'s held stress is kept in [`SystemState::held_tension`].
    fn held_tension_index(&self, e: usize) -> usize {
        self.disc.first_point + e * self.disc.rest.points_per_element
    }

    /// The membrane stress of element `e`'s mean stretch at the start of the step.
    fn start_tension(&self, e: usize, state: &SystemState) -> f64 {
        let x = self.disc.disp_elements[e].map(|i| state.x[i]);
        self.element_tension(e, |shape, offset| membrane_stretch(&f_hat(shape, &x), offset))
    }

    /// The membrane stress of element `e`'s mean stretch, `stretch` giving a point's.
    fn element_tension(&self, e: usize, stretch: impl Fn(&PointShape<NU, NR>, &StrainVector) -> [f64; 4]) -> f64 {
        let rest = &self.disc.rest;
        let first = e * rest.points_per_element;
        let mut mean = [0.0; 4];
        for p in first..first + rest.quadrature_points_per_element {
            let shape = &rest.shapes[p];
            for (m, s) in mean.iter_mut().zip(stretch(shape, self.offset(p))) {
                *m += shape.weight * s / rest.element_areas[e];
            }
        }
        membrane_tension(&mean, rest.densities.get(first))
    }

    /// Whether the stabilisation follows the membrane stresses (under
    /// [`StrainInterpolation::ReggeStabilized`](cosserat_material::StrainInterpolation::ReggeStabilized)).
    pub fn follows_tension(&self) -> bool {
        !self.disc.rest.tying_stabilization.is_empty()
    }

    /// Lets the stabilisation follow the membrane stresses of the iterate `eval.u` for the rest of the
    /// step: an element stretched beyond what its factors hold without the safety factor
    /// ([`StrainProjection::holds_tension`](cosserat_material::StrainProjection::holds_tension)) has
    /// them raised for the iterate's stress, and one raised whose stress has fallen below a quarter of
    /// that (`TENSION_RELEASE`) has them lowered to it (never below the step start's). The stress is
    /// that of the stretch predicted linearly along the step ([`membrane_stretch_predicted`]), so that
    /// the second-order stretch of iterates that rotate far does not count. A sheet pulled taut within
    /// one step thus stays stable. Returns whether the energy changed.
    pub fn follow_tension(&mut self, eval: &Evaluation<'_>) -> bool {
        if !self.follows_tension() {
            return false;
        }
        let rest = &self.disc.rest;
        let mut step = self.step_tension.take().unwrap_or_else(|| {
            let start: Vec<f64> = (0..self.n_elements()).map(|e| self.start_held(e, eval.state)).collect();
            StepTension {
                held: start.clone(),
                start,
            }
        });
        let mut changed = false;
        for (e, (held, start)) in step.held.iter_mut().zip(&step.start).enumerate() {
            let nodes = &self.disc.disp_elements[e];
            let x = nodes.map(|i| eval.state.x[i]);
            let dx = nodes.map(|i| eval.layout.velocity(eval.u, i) * eval.dt);
            let tension = self.element_tension(e, |shape, offset| {
                membrane_stretch_predicted(&f_hat(shape, &x), &f_hat(shape, &dx), offset)
            });
            let density = rest.densities.get(e * rest.points_per_element);
            let factors = rest.tying_stabilization[e].held_in_tension(*held, density);
            let target = if !factors.holds_tension(tension, density) {
                tension
            } else if *held > *start && tension < TENSION_RELEASE * *held {
                tension.max(*start)
            } else {
                continue;
            };
            changed |= target != *held;
            *held = target;
        }
        self.step_tension = Some(step);
        changed
    }

    /// The step was abandoned: the next takes its stabilisation from its own start.
    pub fn release_tension(&mut self) {
        self.step_tension = None;
    }

    /// The step was committed into `state`: the stresses its factors held are kept there, and the next
    /// step starts with them while its own start's stress lies between a quarter of them and them.
    pub fn commit_tension(&mut self, state: &mut SystemState) {
        if let Some(step) = self.step_tension.take() {
            for (e, held) in step.held.into_iter().enumerate() {
                let i = self.held_tension_index(e);
                state.held_tension[i] = held;
            }
        }
    }

    /// Clears prescribed rest fields.
    pub fn clear_rest_fields(&mut self) {
        self.offsets = None;
    }

    #[inline]
    fn offset(&self, p: usize) -> &StrainVector {
        match &self.offsets {
            Some(o) => &o[p],
            None => &self.default_offsets[p],
        }
    }

    /// Linearises every point's strains at `eval.u` along the step `du` (the mixed-integration-point
    /// Newton method; see [`Self::advance_predicted_strains`]).
    pub fn linearize_strains(&mut self, eval: &Evaluation<'_>, du: &[f64]) {
        let n_qp = self.disc.rest.points_per_element;
        let mut prediction = std::mem::take(&mut self.prediction);
        let (base, rate) = prediction.linearization_buffers(self.disc.rest.shapes.len());
        if n_qp > 0 {
            let this = &*self;
            let run = |(e, (b, r)): (usize, (&mut [StrainVector], &mut [StrainVector]))| {
                this.linearize_element(e, eval, du, b, r);
            };
            match eval.parallelism {
                Parallelism::Rayon => base
                    .par_chunks_mut(n_qp)
                    .zip(rate.par_chunks_mut(n_qp))
                    .enumerate()
                    .for_each(run),
                Parallelism::Sequential => base.chunks_mut(n_qp).zip(rate.chunks_mut(n_qp)).enumerate().for_each(run),
            }
        }
        self.prediction = prediction;
    }

    /// The step `α δu` along the last linearisation was taken: the next Hessians weight their
    /// second-order terms with the stresses of `s(u) + α (∂s/∂u) δu` at every point.
    pub fn advance_predicted_strains(&mut self, alpha: f64) {
        self.prediction.advance(alpha);
    }

    /// Forgets the predicted strains: Hessians use the points' own stresses again.
    pub fn clear_predicted_strains(&mut self) {
        self.prediction.clear();
    }

    /// The strains of element `e`'s points at `eval.u` and their derivatives along `du`.
    fn linearize_element(
        &self,
        e: usize,
        eval: &Evaluation<'_>,
        du: &[f64],
        base: &mut [StrainVector],
        rate: &mut [StrainVector],
    ) {
        let dx: [Vector3<f64>; NU] =
            std::array::from_fn(|i| eval.layout.velocity(du, self.disc.disp_elements[e][i]) * eval.dt);
        let d_omega: [Vector3<f64>; NR] = std::array::from_fn(|k| eval.layout.omega(du, self.disc.rot_elements[e][k]));
        // A tying point's curvature strains are never read, and one on a quadrature point takes that
        // point's strains.
        let rest = &self.disc.rest;
        let first_tying = rest.quadrature_points_per_element;
        let twin = |g: usize| g >= first_tying && rest.tying_twins.is_twin(g - first_tying);
        self.for_points_where(
            e,
            eval,
            |g| !twin(g),
            |g, shape, input, _| {
                let d_f_hat = f_hat(shape, &dx);
                (base[g], rate[g]) = if g < first_tying {
                    linearized_strains::<NU, NR>(shape, input, self.disc.axl, &d_f_hat, &d_omega)
                } else {
                    linearized_membrane_strains::<NU, NR>(shape, input, &d_f_hat, &d_omega)
                };
            },
        );
        for g in (first_tying..rest.points_per_element).filter(|&g| twin(g)) {
            let source = rest.tying_twins.source(g - first_tying, first_tying);
            (base[g], rate[g]) = (base[source], rate[source]);
        }
    }

    /// The predicted strains of element `e`'s points, if any.
    fn predicted(&self, e: usize) -> Option<&[StrainVector]> {
        let n_qp = self.disc.rest.points_per_element;
        self.prediction.points(e * n_qp, n_qp)
    }

    fn positions(&self, e: usize, eval: &Evaluation<'_>) -> [Vector3<f64>; NU] {
        end_of_step_positions(eval, &self.disc.disp_elements[e])
    }

    fn omegas(&self, e: usize, eval: &Evaluation<'_>) -> [Vector3<f64>; NR] {
        angular_velocities(eval, &self.disc.rot_elements[e])
    }

    /// Calls `f(shape, input, density)` at each point of element `e`.
    #[inline]
    fn for_each_point(
        &self,
        e: usize,
        eval: &Evaluation<'_>,
        mut f: impl FnMut(&PointShape<NU, NR>, &PointInput<'_, NR>, &DensityMatrix),
    ) {
        self.for_points_where(e, eval, |_| true, |_, shape, input, d| f(shape, input, d));
    }

    /// Calls `f(g, shape, input, density)` at each point `g` of element `e` for which `include(g)`.
    #[inline]
    fn for_points_where(
        &self,
        e: usize,
        eval: &Evaluation<'_>,
        include: impl Fn(usize) -> bool,
        mut f: impl FnMut(usize, &PointShape<NU, NR>, &PointInput<'_, NR>, &DensityMatrix),
    ) {
        let x = self.positions(e, eval);
        let omega = self.omegas(e, eval);
        let r = &self.disc.rot_elements[e];
        let node_jets: [&RotationJet; NR] = std::array::from_fn(|k| eval.rotations.jet(r[k]));
        for g in (0..self.disc.rest.points_per_element).filter(|&g| include(g)) {
            let p = e * self.disc.rest.points_per_element + g;
            let shape = &self.disc.rest.shapes[p];
            let q = &eval.state.q_points[self.disc.first_point + p];
            let omega_g = point_omega(shape, &omega);
            let point_jet = RotationJet::of_update(q, &omega_g, eval.dt);
            let input = PointInput {
                f_hat: f_hat(shape, &x),
                point_jet: &point_jet,
                node_jets,
                offset: self.offset(p),
            };
            f(g, shape, &input, self.disc.rest.densities.get(p));
        }
    }

    /// [`Self::element_derivatives`] under a strain projection or assumed strains: all points of the
    /// element at once.
    fn coupled_derivatives(
        &self,
        e: usize,
        eval: &Evaluation<'_>,
        coupling: Coupling<'_>,
        with_hessian: bool,
        out: &mut ElementDerivatives<NE>,
        local: &mut LocalDerivatives<NL>,
    ) {
        let x = self.positions(e, eval);
        let omega = self.omegas(e, eval);
        let r = &self.disc.rot_elements[e];
        let node_jets: [&RotationJet; NR] = std::array::from_fn(|k| eval.rotations.jet(r[k]));
        let n_qp = self.disc.rest.points_per_element;
        let jets: Vec<RotationJet> = (0..n_qp)
            .map(|g| {
                let p = e * n_qp + g;
                let q = &eval.state.q_points[self.disc.first_point + p];
                RotationJet::of_update(q, &point_omega(&self.disc.rest.shapes[p], &omega), eval.dt)
            })
            .collect();
        let points: Vec<ElementPoint<'_, NU, NR>> = jets
            .iter()
            .enumerate()
            .map(|(g, jet)| {
                let p = e * n_qp + g;
                let shape = &self.disc.rest.shapes[p];
                ElementPoint {
                    shape,
                    input: PointInput {
                        f_hat: f_hat(shape, &x),
                        point_jet: jet,
                        node_jets,
                        offset: self.offset(p),
                    },
                    density: self.disc.rest.densities.get(p),
                }
            })
            .collect();
        let volume = self.disc.volume.as_ref();
        let axl = self.disc.axl;
        if !with_hessian {
            coupling.element_gradient::<NU, NR, NL, NE>(&points, axl, volume, eval.dt, out);
            return;
        }
        if n_qp == 0 {
            out.hessian.fill(0.0);
        }
        let weights = coupling.element_hessian(&points, axl, volume, eval.dt, self.predicted(e), local, out);
        for (k, w) in weights.iter().enumerate() {
            add_node_second_derivatives(&mut out.hessian, 3 * (NU + k), node_jets[k], w);
        }
        if self.project_pd {
            out.fill_lower_from_upper();
            out.hessian = project_positive_semidefinite(&out.hessian);
            out.clear_below_block_diagonal();
        }
    }
}

/// What one shell element computes; the loop over the elements is [`ElementAssembly`]'s.
impl<const NU: usize, const NR: usize, const NL: usize, const NE: usize, const NB: usize> ElementKernel<NE, NB>
    for ShellTerm<NU, NR, NL, NE, NB>
{
    /// A point's local derivatives. The element Hessian's blocks below the block diagonal are zero from
    /// the slot's creation on and are never written (the points write the upper block triangle, the
    /// first of them by assignment, and the scatter reads only that), so a slot needs no clearing per
    /// element.
    type Scratch = LocalDerivatives<NL>;

    fn scratch() -> Self::Scratch {
        LocalDerivatives::zeros()
    }

    fn term_name(&self) -> String {
        self.name()
    }

    fn n_elements(&self) -> usize {
        self.disc.disp_elements.len()
    }

    fn blocks(&self, e: usize) -> [usize; NB] {
        displacement_rotation_blocks(&self.layout, &self.disc.disp_elements[e], &self.disc.rot_elements[e])
    }

    fn element_value(&self, e: usize, eval: &Evaluation<'_>) -> f64 {
        let x = self.positions(e, eval);
        let omega = self.omegas(e, eval);
        let r = &self.disc.rot_elements[e];
        let node_r: [&Matrix3<f64>; NR] = std::array::from_fn(|k| eval.rotations.matrix(r[k]));
        let maps = self.tying_maps(e, eval.state);
        let projection = self.disc.rest.projections.get(e);
        if maps.is_some() || projection.is_some() {
            let n_qp = self.disc.rest.points_per_element;
            let points: Vec<ValuePoint<'_, NU, NR>> = (0..n_qp)
                .map(|g| {
                    let p = e * n_qp + g;
                    let shape = &self.disc.rest.shapes[p];
                    let q = &eval.state.q_points[self.disc.first_point + p];
                    ValuePoint {
                        shape,
                        f_hat: f_hat(shape, &x),
                        r: rotation_matrix(&quaternion_update(q, &point_omega(shape, &omega), eval.dt)),
                        offset: self.offset(p),
                        density: self.disc.rest.densities.get(p),
                    }
                })
                .collect();
            let volume = self.disc.volume.as_ref();
            let coupling = match (maps.as_deref(), projection) {
                (Some(maps), _) => Coupling::Tying(self.disc.rest.element_tying(e, maps)),
                (None, Some(projection)) => Coupling::Projection(projection),
                (None, None) => unreachable!("checked above"),
            };
            return coupling.element_value(&points, node_r, self.disc.axl, volume);
        }
        let mut value = 0.0;
        for g in 0..self.disc.rest.points_per_element {
            let p = e * self.disc.rest.points_per_element + g;
            let shape = &self.disc.rest.shapes[p];
            let q = &eval.state.q_points[self.disc.first_point + p];
            let rp = rotation_matrix(&quaternion_update(q, &point_omega(shape, &omega), eval.dt));
            let f = f_hat(shape, &x);
            let mut psi = point_value(
                shape,
                &f,
                &rp,
                node_r,
                self.offset(p),
                self.disc.rest.densities.get(p),
                self.disc.axl,
            );
            if let Some(m) = &self.disc.volume {
                psi += volume_density(&f, m);
            }
            value += shape.weight * psi;
        }
        value
    }

    fn element_derivatives(
        &self,
        e: usize,
        eval: &Evaluation<'_>,
        with_hessian: bool,
        out: &mut ElementDerivatives<NE>,
        local: &mut LocalDerivatives<NL>,
    ) {
        if let Some(maps) = self.tying_maps(e, eval.state) {
            let coupling = Coupling::Tying(self.disc.rest.element_tying(e, &maps));
            self.coupled_derivatives(e, eval, coupling, with_hessian, out, local);
            return;
        }
        if let Some(projection) = self.disc.rest.projections.get(e) {
            self.coupled_derivatives(e, eval, Coupling::Projection(projection), with_hessian, out, local);
            return;
        }
        out.value = 0.0;
        out.gradient.fill(0.0);
        if !with_hessian {
            self.for_each_point(e, eval, |shape, input, d| {
                let (mut value, mut gradient) = point_gradient::<NU, NR, NL>(shape, input, d, self.disc.axl);
                if let Some(m) = &self.disc.volume {
                    let (v, gv, _) = volume_hessian(&input.f_hat, m);
                    value += v;
                    let mut gl = gradient.fixed_rows_mut::<6>(0);
                    gl += gv;
                }
                out.value += shape.weight * value;
                accumulate_gradient(shape, &gradient, eval.dt, shape.weight, &mut out.gradient);
            });
            return;
        }
        // The first point assigns the upper block triangle (see `Scratch`); without points nothing
        // would.
        if self.disc.rest.points_per_element == 0 {
            out.hessian.fill(0.0);
        }
        let mut first = true;
        // Σ_p w_p R U_k,p: the weights of the nodal rotations' second derivatives, contracted once per
        // node below (see `point_hessian_deferred_into`).
        let mut node_weights = [Matrix3::zeros(); NR];
        let predicted = self.predicted(e);
        let mut g = 0;
        self.for_each_point(e, eval, |shape, input, d| {
            let weights = point_hessian_predicted_into(shape, input, d, self.disc.axl, predicted.map(|p| &p[g]), local);
            g += 1;
            for (sum, w) in node_weights.iter_mut().zip(&weights) {
                *sum += w * shape.weight;
            }
            if let Some(m) = &self.disc.volume {
                let (v, gv, hv) = volume_hessian(&input.f_hat, m);
                local.value += v;
                let mut gl = local.gradient.fixed_rows_mut::<6>(0);
                gl += gv;
                let mut hl = local.hessian.fixed_view_mut::<6, 6>(0, 0);
                hl += hv;
            }
            if first {
                assign_upper(shape, local, eval.dt, shape.weight, out);
                first = false;
            } else {
                accumulate_upper(shape, local, eval.dt, shape.weight, out);
            }
        });
        let r = &self.disc.rot_elements[e];
        for (k, w) in node_weights.iter().enumerate() {
            add_node_second_derivatives(&mut out.hessian, 3 * (NU + k), eval.rotations.jet(r[k]), w);
        }
        // The scatter reads only the upper block triangle (`ElementScatter::add_hessian`), so the lower
        // triangle is filled only where the whole matrix is needed, and cleared again afterwards.
        if self.project_pd {
            out.fill_lower_from_upper();
            out.hessian = project_positive_semidefinite(&out.hessian);
            out.clear_below_block_diagonal();
        }
    }
}

/// The nearest positive semi-definite matrix: negative eigenvalues clamped to zero.
pub fn project_positive_semidefinite<const N: usize>(h: &SMatrix<f64, N, N>) -> SMatrix<f64, N, N> {
    let eig = nalgebra::DMatrix::from_column_slice(N, N, h.as_slice()).symmetric_eigen();
    if eig.eigenvalues.iter().all(|&l| l >= 0.0) {
        return *h;
    }
    let clamped = eig.eigenvalues.map(|l| l.max(0.0));
    let v = &eig.eigenvectors;
    let p = v * nalgebra::DMatrix::from_diagonal(&clamped) * v.transpose();
    SMatrix::<f64, N, N>::from_column_slice(p.as_slice())
}

impl<const NU: usize, const NR: usize, const NL: usize, const NE: usize, const NB: usize> PotentialTerm
    for ShellTerm<NU, NR, NL, NE, NB>
{
    fn is_elastic(&self) -> bool {
        true
    }

    fn name(&self) -> String {
        format!("shell_tri{NU}_tri{NR}")
    }

    fn coupling_groups(&self) -> Vec<Vec<usize>> {
        ElementAssembly::coupling_groups(self)
    }

    fn bind(&mut self, pattern: &SparsityPattern) {
        self.elements.bind(ElementAssembly::scatter(pattern, &*self));
    }

    fn value(&self, eval: &Evaluation<'_>) -> Result<f64, AssemblyError> {
        self.elements.value(self, eval)
    }

    fn gradient(&self, eval: &Evaluation<'_>, grad: &mut [f64]) -> Result<f64, AssemblyError> {
        self.elements.gradient(self, eval, grad)
    }

    fn hessian(
        &self,
        eval: &Evaluation<'_>,
        grad: &mut [f64],
        pattern: &SparsityPattern,
        values: &mut [f64],
    ) -> Result<f64, AssemblyError> {
        self.elements.hessian(self, eval, grad, pattern, values)
    }

    fn check_state(&self, eval: &Evaluation<'_>) -> Result<(), AssemblyError> {
        self.check_orientation(eval)
    }

    fn commit(&mut self, state: &mut SystemState, layout: &DofLayout, u: &[f64], dt: f64) {
        let n_qp = self.disc.rest.points_per_element;
        for (e, r) in self.disc.rot_elements.iter().enumerate() {
            let omega: [Vector3<f64>; NR] = std::array::from_fn(|k| layout.omega(u, r[k]));
            for g in 0..n_qp {
                let p = e * n_qp + g;
                let q = &mut state.q_points[self.disc.first_point + p];
                *q = quaternion_update(q, &point_omega(&self.disc.rest.shapes[p], &omega), dt);
            }
        }
    }

    fn rebase_rotations(&mut self, state: &mut SystemState, layout: &DofLayout, u: &[f64], dt: f64) {
        // The shell's commit advances its point rotations and nothing else.
        self.commit(state, layout, u, dt);
    }

    fn active_energy_terms(&self) -> Vec<String> {
        self.disc.rest.active_terms.clone()
    }
}

/// The signed area ratio `(F̂₁ × F̂₂) · R n₀` of a point at positions `x` with the point's rotation
/// `q / |q|` (`q` need not be a unit quaternion): the deformed area element over the rest one,
/// negative where the surface has folded over its director.
fn area_ratio<const NU: usize, const NR: usize>(
    shape: &PointShape<NU, NR>,
    x: &[Vector3<f64>; NU],
    q: &Quaternion<f64>,
) -> f64 {
    let f = f_hat(shape, x);
    // `q n̂₀ q* = (w² − |v|²) n₀ + 2 (v·n₀) v + 2 w (v × n₀)` is `|q|² R n₀` for `q = (w, v)`: the
    // rotation without the normalisation's square root.
    let (w, v, n0) = (q.w, q.imag(), shape.frame.column(2));
    let director = n0 * (w * w - v.norm_squared()) + v * (2.0 * v.dot(&n0)) + v.cross(&n0) * (2.0 * w);
    f[0].cross(&f[1]).dot(&director) / q.norm_squared()
}

/// [`quaternion_update`] before its normalisation: the same rotation, for [`area_ratio`].
fn unnormalised_update(q: &Quaternion<f64>, omega: &Vector3<f64>, dt: f64) -> Quaternion<f64> {
    q + Quaternion::from_imag(omega * (0.5 * dt)) * q
}
