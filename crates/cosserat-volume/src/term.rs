//! The elastic energy of a micropolar solid as a term of the incremental potential, and the shared
//! handle through which scripts prescribe its rest curvature.
//!
//! Per element the term gathers the end-of-step nodal positions and the shared nodal rotation jets,
//! advances the element's point rotation with the interpolated angular velocity, runs the point kernel
//! (`kernel`), maps to the element's unknowns (`element`) and scatters through precomputed positions.
//! The loop over the elements is the shell's ([`cosserat_assembly::element_assembly`]): elements are
//! evaluated in parallel and consumed in element order, so results are bit-identical for any number of
//! threads.

use crate::density::StrainMatrix;
use crate::element::{ElementDerivatives, accumulate, accumulate_gradient};
use crate::kernel::{PointState, point_gradient, point_hessian, point_value};
use crate::material::MicropolarModuli;
use crate::tet4::{VolumePoint, deformation_gradient, point_omega};
use cosserat_assembly::dofs::DofLayout;
use cosserat_assembly::element_assembly::{
    ElementAssembly, ElementKernel, angular_velocities, displacement_rotation_blocks, end_of_step_positions,
};
use cosserat_assembly::parallel::first_non_positive;
use cosserat_assembly::shell::project_positive_semidefinite;
use cosserat_assembly::state::SystemState;
use cosserat_assembly::term::{Evaluation, PotentialTerm};
use cosserat_assembly::{AssemblyError, SparsityPattern};
use cosserat_geometry::rotation::{RotationJet, quaternion_update, rotation_matrix};
use nalgebra::{Matrix3, Vector3};
use std::sync::{Arc, RwLock, RwLockReadGuard};

/// The prescribed rest curvature `Γ_rest` of every quadrature point (world axes; row = axial component,
/// column = direction of differentiation), shared between a [`VolumeTerm`] and the scripts that change
/// it between steps.
///
/// The term sits in the potential as a `Box<dyn PotentialTerm>`, so scripts reach its rest state
/// through this handle instead: clones share the same values. The term takes a read lock once per
/// evaluation; set values between Newton solves.
#[derive(Debug, Clone)]
pub struct RestCurvature {
    values: Arc<RwLock<Vec<Matrix3<f64>>>>,
}

impl RestCurvature {
    /// Zero rest curvature at `n_points` points.
    pub fn zeros(n_points: usize) -> Self {
        Self {
            values: Arc::new(RwLock::new(vec![Matrix3::zeros(); n_points])),
        }
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.read().len()
    }

    /// Whether there are no points.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Sets `Γ_rest` at every point `p` to `field(p)`.
    pub fn set(&self, mut field: impl FnMut(usize) -> Matrix3<f64>) {
        let mut values = self.values.write().unwrap_or_else(|e| e.into_inner());
        for (p, v) in values.iter_mut().enumerate() {
            *v = field(p);
        }
    }

    /// Sets the same `Γ_rest` at every point.
    pub fn set_uniform(&self, gamma: Matrix3<f64>) {
        self.set(|_| gamma);
    }

    /// Resets every point to zero rest curvature.
    pub fn clear(&self) {
        self.set_uniform(Matrix3::zeros());
    }

    /// The rest curvature of point `p`.
    ///
    /// # Panics
    /// If `p` is out of range.
    #[track_caller]
    pub fn get(&self, p: usize) -> Matrix3<f64> {
        self.read()[p]
    }

    fn read(&self) -> RwLockReadGuard<'_, Vec<Matrix3<f64>>> {
        self.values.read().unwrap_or_else(|e| e.into_inner())
    }
}

/// Everything that defines a micropolar solid's elastic term: its rest data and where its nodes and
/// points sit in the global system.
#[derive(Debug, Clone)]
pub struct VolumeDiscretization<const N: usize> {
    /// One quadrature point per element (element order).
    pub points: Vec<VolumePoint<N>>,
    /// Displacement connectivity in global displacement-node indices.
    pub disp_elements: Vec<[usize; N]>,
    /// Rotation connectivity (same elements) in global rotation-node indices.
    pub rot_elements: Vec<[usize; N]>,
    /// Index of this solid's first point in [`SystemState::q_points`].
    pub first_point: usize,
    /// The moduli.
    pub moduli: MicropolarModuli,
    /// The density's constant Hessian `D` on the 18 strains (`density::strain_hessian`).
    pub strain_hessian: StrainMatrix,
}

/// The elastic energy of a micropolar solid of `N`-node elements with `NL = 9 + 3N` point locals,
/// `NE = 6N` element unknowns and `NB = 2N` blocks per element.
#[derive(Debug)]
pub struct VolumeTerm<const N: usize, const NL: usize, const NE: usize, const NB: usize> {
    disc: VolumeDiscretization<N>,
    rest_curvature: RestCurvature,
    layout: DofLayout,
    /// Project each element Hessian onto the positive semi-definite cone (off by default). Needed only
    /// when the linear solver requires a positive definite matrix far from equilibrium.
    pub project_pd: bool,
    /// The element loop; the elements need no scratch beyond their results.
    elements: ElementAssembly<NE, NB, ()>,
}

/// Linear tetrahedra for displacements and rotations.
pub type Tet4Volume = VolumeTerm<4, 21, 24, 8>;

impl<const N: usize, const NL: usize, const NE: usize, const NB: usize> VolumeTerm<N, NL, NE, NB> {
    /// The term of a discretised solid within a system of the given layout, reading its rest curvature
    /// from `rest_curvature` (one value per point).
    ///
    /// # Panics
    /// If the element lists and points differ in length or `rest_curvature` has the wrong length
    /// (programmer error: the builder makes them consistent).
    #[track_caller]
    pub fn new(disc: VolumeDiscretization<N>, layout: DofLayout, rest_curvature: RestCurvature) -> Self {
        const {
            assert!(
                NL == 9 + 3 * N && NE == 6 * N && NB == 2 * N,
                "inconsistent element sizes"
            )
        };
        assert!(
            disc.points.len() == disc.disp_elements.len() && disc.points.len() == disc.rot_elements.len(),
            "one point per element"
        );
        assert_eq!(rest_curvature.len(), disc.points.len(), "one rest curvature per point");
        Self {
            disc,
            rest_curvature,
            layout,
            project_pd: false,
            elements: ElementAssembly::new(),
        }
    }

    /// The discretisation.
    pub fn discretization(&self) -> &VolumeDiscretization<N> {
        &self.disc
    }

    /// The rest-curvature handle (a clone shares the values).
    pub fn rest_curvature(&self) -> &RestCurvature {
        &self.rest_curvature
    }

    /// Number of elements.
    pub fn n_elements(&self) -> usize {
        self.disc.points.len()
    }

    /// The smallest volume ratio `det F` over all elements in a state; negative means an inverted
    /// element.
    pub fn min_volume_ratio(&self, state: &SystemState) -> f64 {
        let mut min = f64::INFINITY;
        for (e, d) in self.disc.disp_elements.iter().enumerate() {
            let x: [Vector3<f64>; N] = std::array::from_fn(|i| state.x[d[i]]);
            let f = deformation_gradient(&self.disc.points[e], &x);
            min = min.min(Matrix3::from_columns(&f).determinant());
        }
        min
    }

    /// The term's elements with the rest curvature read for one evaluation.
    fn elements_with<'a>(&'a self, rest: &'a [Matrix3<f64>]) -> VolumeElements<'a, N, NL, NE, NB> {
        VolumeElements { term: self, rest }
    }

    fn positions(&self, e: usize, eval: &Evaluation<'_>) -> [Vector3<f64>; N] {
        end_of_step_positions(eval, &self.disc.disp_elements[e])
    }

    fn omegas(&self, e: usize, eval: &Evaluation<'_>) -> [Vector3<f64>; N] {
        angular_velocities(eval, &self.disc.rot_elements[e])
    }

    fn element_value(&self, e: usize, eval: &Evaluation<'_>, rest: &[Matrix3<f64>]) -> f64 {
        let point = &self.disc.points[e];
        let x = self.positions(e, eval);
        let omega = self.omegas(e, eval);
        let r = &self.disc.rot_elements[e];
        let node_r: [&Matrix3<f64>; N] = std::array::from_fn(|k| eval.rotations.matrix(r[k]));
        let q = &eval.state.q_points[self.disc.first_point + e];
        let rp = rotation_matrix(&quaternion_update(q, &point_omega(point, &omega), eval.dt));
        let f = deformation_gradient(point, &x);
        point.weight * point_value(point, &f, &rp, node_r, &rest[e], &self.disc.strain_hessian)
    }

    fn element_derivatives(
        &self,
        e: usize,
        eval: &Evaluation<'_>,
        rest: &[Matrix3<f64>],
        with_hessian: bool,
        out: &mut ElementDerivatives<NE>,
    ) {
        let point = &self.disc.points[e];
        let x = self.positions(e, eval);
        let omega = self.omegas(e, eval);
        let r = &self.disc.rot_elements[e];
        let node_jets: [&RotationJet; N] = std::array::from_fn(|k| eval.rotations.jet(r[k]));
        let q = &eval.state.q_points[self.disc.first_point + e];
        let omega_g = point_omega(point, &omega);
        let point_jet = RotationJet::of_update(q, &omega_g, eval.dt);
        let state = PointState {
            f: deformation_gradient(point, &x),
            point_jet: &point_jet,
            node_jets,
            rest_curvature: &rest[e],
        };
        out.value = 0.0;
        out.gradient.fill(0.0);
        let d = &self.disc.strain_hessian;
        if with_hessian {
            out.hessian.as_mut_slice().fill(0.0);
            let local = point_hessian::<N, NL>(point, &state, d);
            accumulate(point, &local, eval.dt, point.weight, out);
            if self.project_pd {
                out.hessian = project_positive_semidefinite(&out.hessian);
            }
        } else {
            let (value, gradient) = point_gradient::<N, NL>(point, &state, d);
            out.value = point.weight * value;
            accumulate_gradient(point, &gradient, eval.dt, point.weight, &mut out.gradient);
        }
    }
}

/// A [`VolumeTerm`] during one evaluation: its elements, with the rest curvature read once for all of
/// them (a read lock per element would make the threads contend for it).
struct VolumeElements<'a, const N: usize, const NL: usize, const NE: usize, const NB: usize> {
    term: &'a VolumeTerm<N, NL, NE, NB>,
    rest: &'a [Matrix3<f64>],
}

/// What one element computes; the loop over the elements is [`ElementAssembly`]'s.
impl<const N: usize, const NL: usize, const NE: usize, const NB: usize> ElementKernel<NE, NB>
    for VolumeElements<'_, N, NL, NE, NB>
{
    /// Nothing: the element has one point, whose local derivatives are returned by value.
    type Scratch = ();

    fn scratch() -> Self::Scratch {}

    fn term_name(&self) -> String {
        self.term.name()
    }

    fn n_elements(&self) -> usize {
        self.term.n_elements()
    }

    fn blocks(&self, e: usize) -> [usize; NB] {
        let disc = &self.term.disc;
        displacement_rotation_blocks(&self.term.layout, &disc.disp_elements[e], &disc.rot_elements[e])
    }

    fn element_value(&self, e: usize, eval: &Evaluation<'_>) -> f64 {
        self.term.element_value(e, eval, self.rest)
    }

    fn element_derivatives(
        &self,
        e: usize,
        eval: &Evaluation<'_>,
        with_hessian: bool,
        out: &mut ElementDerivatives<NE>,
        _scratch: &mut (),
    ) {
        self.term.element_derivatives(e, eval, self.rest, with_hessian, out);
    }
}

impl<const N: usize, const NL: usize, const NE: usize, const NB: usize> PotentialTerm for VolumeTerm<N, NL, NE, NB> {
    fn is_elastic(&self) -> bool {
        true
    }

    fn name(&self) -> String {
        format!("micropolar_tet{N}")
    }

    fn coupling_groups(&self) -> Vec<Vec<usize>> {
        let rest = self.rest_curvature.read();
        ElementAssembly::coupling_groups(&self.elements_with(&rest))
    }

    fn bind(&mut self, pattern: &SparsityPattern) {
        let rest = self.rest_curvature.read();
        let scatter = ElementAssembly::scatter(pattern, &self.elements_with(&rest));
        drop(rest);
        self.elements.bind(scatter);
    }

    fn value(&self, eval: &Evaluation<'_>) -> Result<f64, AssemblyError> {
        let rest = self.rest_curvature.read();
        self.elements.value(&self.elements_with(&rest), eval)
    }

    fn gradient(&self, eval: &Evaluation<'_>, grad: &mut [f64]) -> Result<f64, AssemblyError> {
        let rest = self.rest_curvature.read();
        self.elements.gradient(&self.elements_with(&rest), eval, grad)
    }

    fn hessian(
        &self,
        eval: &Evaluation<'_>,
        grad: &mut [f64],
        pattern: &SparsityPattern,
        values: &mut [f64],
    ) -> Result<f64, AssemblyError> {
        let rest = self.rest_curvature.read();
        self.elements.hessian(&self.elements_with(&rest), eval, grad, pattern, values)
    }

    /// No elastic state of a solid turns an element inside out, while the micropolar energy has no
    /// barrier against it: the solvers keep their iterates and solutions out of such states.
    fn check_state(&self, eval: &Evaluation<'_>) -> Result<(), AssemblyError> {
        let volume_ratio = |e: usize| {
            let f = deformation_gradient(&self.disc.points[e], &self.positions(e, eval));
            Matrix3::from_columns(&f).determinant()
        };
        match first_non_positive(self.n_elements(), eval.parallelism, volume_ratio) {
            None => Ok(()),
            Some((e, ratio)) => Err(AssemblyError::Infeasible {
                term: self.name(),
                reason: format!("element {e} turned inside out (deformed-to-rest volume ratio {ratio:.3})"),
            }),
        }
    }

    fn commit(&mut self, state: &mut SystemState, layout: &DofLayout, u: &[f64], dt: f64) {
        for (e, r) in self.disc.rot_elements.iter().enumerate() {
            let omega: [Vector3<f64>; N] = std::array::from_fn(|k| layout.omega(u, r[k]));
            let q = &mut state.q_points[self.disc.first_point + e];
            *q = quaternion_update(q, &point_omega(&self.disc.points[e], &omega), dt);
        }
    }

    fn rebase_rotations(&mut self, state: &mut SystemState, layout: &DofLayout, u: &[f64], dt: f64) {
        // The commit advances the point rotations and nothing else.
        self.commit(state, layout, u, dt);
    }

    fn active_energy_terms(&self) -> Vec<String> {
        let mut names = vec!["micropolar_stretch".to_string()];
        if self.disc.moduli.length_scale > 0.0 && self.disc.moduli.curvature_coefficients.iter().any(|&b| b > 0.0) {
            names.push("micropolar_curvature".to_string());
        }
        names
    }
}
