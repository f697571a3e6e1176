//! The element kernel of the strain treatments that couple an element's points: the stabilised
//! projection ([`crate::projected`]) and the assumed strains ([`crate::assumed_kernel`]). Both replace
//! the points' strains by linear combinations of the element's raw point strains, so the energy's
//! derivative with respect to each raw point strain is a stress `σ̂_q` that the point kernel turns into
//! the gradient and the second-order terms as it would `D s_q`; only `σ̂` and the first-order
//! (Gauss-Newton) part `Σ_p w_p G̃_pᵀ D_p G̃_p` differ between the treatments, and they live in their
//! modules.

use crate::assumed::{ElementTying, N_TYING};
use crate::assumed_kernel::TiedJacobians;
use crate::element::{
    ElementDerivatives, accumulate_gradient, accumulate_upper, accumulate_upper_without_stretch_block, assign_upper,
};
use crate::kernel::{
    LocalDerivatives, PointShape, Stress, add_curvature_free_second_order_terms_upper, add_second_order_terms,
    gradient_from_stress, membrane_strain_jacobian, point_strains, second_order_terms_into, strain_jacobian, stress_of,
};
use crate::model::AxlVariant;
use crate::parameters::Moduli;
use crate::projected::{ElementPoint, ProjectedFirstOrder, ValuePoint};
use crate::projection::StrainProjection;
use crate::strain_space::StrainVector;
use crate::volume::{volume_density, volume_hessian};
use crate::{assumed_kernel, projected};
use nalgebra::{Matrix3, SMatrix, SVector};

/// The first-order (Gauss-Newton) part of a coupled element's Hessian while its points are visited.
// One lives on the stack per element evaluation; boxing the larger variant would allocate in the
// element loop.
#[allow(clippy::large_enum_variant)]
enum FirstOrder<'a, const NE: usize> {
    /// The projection's point-local products and element-level sums.
    Projected(ProjectedFirstOrder<'a, NE>),
    /// The element's assumed strains and the points' Jacobians in its unknowns, combined at the end.
    Tied(ElementTying<'a>, TiedJacobians<NE>),
}

/// The Jacobian of a point's strains and `QᵀRᵀ`. A tying point's curvature strains are read by no map,
/// so only its membrane Jacobian is formed.
fn point_jacobian<const NU: usize, const NR: usize, const NL: usize>(
    p: &ElementPoint<'_, NU, NR>,
    x: &[Matrix3<f64>; 2],
    tying_point: bool,
    variant: AxlVariant,
) -> (SMatrix<f64, NL, 12>, Matrix3<f64>) {
    if tying_point {
        membrane_strain_jacobian::<NU, NR, NL>(p.shape, &p.input, x, variant)
    } else {
        strain_jacobian::<NU, NR, NL>(p.shape, &p.input, x, variant)
    }
}

/// A point's gradient from its stress `sigma`, into `local`, and the stress that weights its
/// second-order terms: `predicted`'s where the iteration matrix uses predicted stresses, its own
/// otherwise.
fn point_stress<const NU: usize, const NR: usize, const NL: usize>(
    p: &ElementPoint<'_, NU, NR>,
    x: [Matrix3<f64>; 2],
    sigma: &StrainVector,
    predicted: Option<&StrainVector>,
    variant: AxlVariant,
    local: &mut LocalDerivatives<NL>,
) -> Stress<NR> {
    let st = stress_of(p.shape, &p.input, x, sigma, variant);
    local.value = 0.0;
    local.gradient = gradient_from_stress(p.shape, &p.input, &st);
    match predicted {
        Some(sigma) => stress_of(p.shape, &p.input, x, sigma, variant),
        None => st,
    }
}

/// Maps a point's local derivatives into the element's: assigned for the `first` point, added
/// otherwise; without a `stretch` block (`F̂F̂`) the displacement blocks are left alone.
fn map_point<const NU: usize, const NR: usize, const NL: usize, const NE: usize>(
    shape: &PointShape<NU, NR>,
    local: &LocalDerivatives<NL>,
    dt: f64,
    weight: f64,
    first: bool,
    stretch: bool,
    out: &mut ElementDerivatives<NE>,
) {
    if !stretch {
        accumulate_upper_without_stretch_block(shape, local, dt, weight, first, out);
    } else if first {
        assign_upper(shape, local, dt, weight, out);
    } else {
        accumulate_upper(shape, local, dt, weight, out);
    }
}

/// How an element's points' strains are combined.
#[derive(Debug, Clone, Copy)]
pub enum Coupling<'a> {
    /// The stabilised projection: `s̃_p = s_p − B (s_p − s̄)` over the element's quadrature points.
    Projection(&'a StrainProjection),
    /// The assumed strains: the element's tied values and its quadrature points' tying maps; the
    /// element's points are its quadrature points followed by its tying points (weight zero), of which
    /// the twins take their quadrature points' strains.
    Tying(ElementTying<'a>),
}

impl Coupling<'_> {
    /// The energy of an element (weighted sum over its points, J), plus the nonlinear volume term.
    pub fn element_value<const NU: usize, const NR: usize>(
        self,
        points: &[ValuePoint<'_, NU, NR>],
        node_r: [&Matrix3<f64>; NR],
        variant: AxlVariant,
        volume: Option<&Moduli>,
    ) -> f64 {
        let (strains, hourglass) = match self {
            Self::Projection(p) => (projected::element_strains(points, node_r, Some(p), variant), 0.0),
            Self::Tying(tying) => assumed_kernel::element_strains_and_hourglass(points, node_r, &tying, variant),
        };
        let points_energy: f64 = points
            .iter()
            .zip(&strains)
            .map(|(p, s)| {
                let mut psi = 0.5 * s.dot(&p.density.mul_vector(s));
                if let Some(m) = volume {
                    psi += volume_density(&p.f_hat, m);
                }
                p.shape.weight * psi
            })
            .sum();
        points_energy + hourglass
    }

    /// Energy and gradient of an element with respect to its unknowns (`out.hessian` is not touched).
    pub fn element_gradient<const NU: usize, const NR: usize, const NL: usize, const NE: usize>(
        self,
        points: &[ElementPoint<'_, NU, NR>],
        variant: AxlVariant,
        volume: Option<&Moduli>,
        dt: f64,
        out: &mut ElementDerivatives<NE>,
    ) {
        let (value, sigma, xs) = self.stresses(points, variant);
        out.value = value;
        out.gradient.fill(0.0);
        let unused = self.unused_tying_points();
        let first_tying = points.len().saturating_sub(N_TYING);
        for (n, ((p, sg), x)) in points.iter().zip(&sigma).zip(xs).enumerate() {
            if self.is_unused(n, first_tying, &unused) {
                continue;
            }
            let st = stress_of(p.shape, &p.input, x, sg, variant);
            let mut g: SVector<f64, NL> = gradient_from_stress(p.shape, &p.input, &st);
            if let Some(m) = volume.filter(|_| p.shape.weight > 0.0) {
                let (v, gv, _) = volume_hessian(&p.input.f_hat, m);
                out.value += p.shape.weight * v;
                let mut gl = g.fixed_rows_mut::<6>(0);
                gl += gv * self.volume_factor(p);
            }
            accumulate_gradient(p.shape, &g, dt, self.stress_weight(p), &mut out.gradient);
        }
    }

    /// Energy, gradient and the upper block triangle of the exact Hessian of an element (blocks below
    /// the block diagonal are not written). Returns the weights of the nodal rotations' second
    /// derivatives, to be added once per node (see `kernel::point_hessian_deferred_into`).
    ///
    /// With `predicted` raw strains of the element's points, the second-order terms are weighted by
    /// their stresses instead (the mixed-integration-point iteration matrix, see
    /// `kernel::point_hessian_predicted_into`).
    #[allow(clippy::too_many_arguments)]
    pub fn element_hessian<const NU: usize, const NR: usize, const NL: usize, const NE: usize>(
        self,
        points: &[ElementPoint<'_, NU, NR>],
        variant: AxlVariant,
        volume: Option<&Moduli>,
        dt: f64,
        predicted: Option<&[StrainVector]>,
        local: &mut LocalDerivatives<NL>,
        out: &mut ElementDerivatives<NE>,
    ) -> [Matrix3<f64>; NR] {
        const { assert!(NL == 6 + 3 * NR && NE == 3 * (NU + NR), "inconsistent element sizes") };
        let (value, sigma, xs) = self.stresses(points, variant);
        let predicted_sigma = predicted.map(|s| self.stresses_of(points, s.to_vec()).1);
        out.value = 0.0;
        out.gradient.fill(0.0);
        let mut node_weights = [Matrix3::zeros(); NR];
        let mut first_order = self.first_order::<NU, NR, NE>(points, dt);
        let unused = self.unused_tying_points();
        let first_tying = points.len().saturating_sub(N_TYING);
        for (n, ((p, sg), x)) in points.iter().zip(&sigma).zip(xs).enumerate() {
            // A point no value reads (the centroid under moment ties, the twins of quadrature points) has
            // no stress, gradient or Hessian of its own: only its place in the Jacobian list is kept.
            if self.is_unused(n, first_tying, &unused) {
                if let FirstOrder::Tied(_, jacobians) = &mut first_order {
                    jacobians.skip();
                }
                continue;
            }
            let tying_point = self.is_tying_point(n, first_tying);
            let predicted = predicted_sigma.as_ref().map(|sigma| &sigma[n]);
            let (mut jac_t, qrt) = point_jacobian(p, &x, tying_point, variant);
            let st = point_stress(p, x, sg, predicted, variant, local);
            let weight = self.stress_weight(p);
            let volume = volume.filter(|_| p.shape.weight > 0.0);
            // The first-order term: point-local for the projection, gathered for the tying maps (see
            // `ProjectedFirstOrder`, `assumed_kernel`). So a tied point's local Hessian is its
            // second-order terms alone, without a `F̂F̂` block unless the volume term adds one.
            let stretch = match &mut first_order {
                FirstOrder::Projected(projected) => {
                    projected.add_point(p.shape, &mut jac_t, &qrt, p.density, &mut local.hessian);
                    add_second_order_terms(p.shape, &p.input, &st, &mut local.hessian);
                    true
                }
                FirstOrder::Tied(_, jacobians) => {
                    jacobians.push(p.shape, &jac_t, &qrt, dt, !tying_point);
                    // Without a curvature stress (every tying point) the terms are few enough to be
                    // added to the element directly; the first point assigns instead.
                    if n > 0 && volume.is_none() && st.curvature_free {
                        accumulate_gradient(p.shape, &local.gradient, dt, weight, &mut out.gradient);
                        add_curvature_free_second_order_terms_upper(
                            p.shape,
                            &p.input,
                            &st,
                            dt,
                            weight,
                            &mut out.hessian,
                        );
                        continue;
                    }
                    second_order_terms_into(p.shape, &p.input, &st, &mut local.hessian);
                    volume.is_some()
                }
            };
            if let Some(m) = volume {
                self.add_volume_term(p, m, local);
            }
            for (sum, w) in node_weights.iter_mut().zip(&st.ru) {
                *sum += w * weight;
            }
            map_point(p.shape, local, dt, weight, n == 0, stretch, out);
        }
        out.value += value;
        match first_order {
            FirstOrder::Projected(projected) => projected.finish(&mut out.hessian),
            FirstOrder::Tied(tying, jacobians) => {
                assumed_kernel::add_assumed_first_order(points, &jacobians, &tying, &mut out.hessian);
            }
        }
        node_weights
    }

    /// The first-order part of the element's Hessian, before its points are visited.
    fn first_order<'a, const NU: usize, const NR: usize, const NE: usize>(
        self,
        points: &[ElementPoint<'a, NU, NR>],
        dt: f64,
    ) -> FirstOrder<'a, NE>
    where
        Self: 'a,
    {
        // Flat elements share one density.
        let shared = points
            .first()
            .map(|p| p.density)
            .filter(|d| points.iter().all(|p| std::ptr::eq(p.density, *d)));
        match self {
            Self::Projection(projection) => {
                FirstOrder::Projected(ProjectedFirstOrder::<NE>::new(projection, shared, dt))
            }
            Self::Tying(tying) => FirstOrder::Tied(tying, TiedJacobians::with_capacity(points.len(), tying.maps.len())),
        }
    }

    /// Adds a point's nonlinear volume term to its local derivatives.
    fn add_volume_term<const NU: usize, const NR: usize, const NL: usize>(
        self,
        p: &ElementPoint<'_, NU, NR>,
        m: &Moduli,
        local: &mut LocalDerivatives<NL>,
    ) {
        let f = self.volume_factor(p);
        let (v, gv, hv) = volume_hessian(&p.input.f_hat, m);
        local.value += f * v;
        let mut gl = local.gradient.fixed_rows_mut::<6>(0);
        gl += gv * f;
        let mut hl = local.hessian.fixed_view_mut::<6, 6>(0, 0);
        hl += hv * f;
    }

    /// Which of the element's tying points are not evaluated: those no tied value reads and the twins
    /// of quadrature points (none under the projection).
    fn unused_tying_points(self) -> [bool; N_TYING] {
        match self {
            Self::Projection(_) => [false; N_TYING],
            Self::Tying(tying) => std::array::from_fn(|t| tying.twins.is_twin(t) || !tying.values.reads(t)),
        }
    }

    /// Point `n` of the element is a tying point that is not evaluated (never under the projection,
    /// whose `unused` is all false).
    fn is_unused(self, n: usize, first_tying: usize, unused: &[bool; N_TYING]) -> bool {
        n >= first_tying && unused[n - first_tying]
    }

    /// Point `n` of the element is a tying point (none under the projection).
    fn is_tying_point(self, n: usize, first_tying: usize) -> bool {
        matches!(self, Self::Tying(..)) && n >= first_tying
    }

    /// The derivatives `σ̂_q` of the element's strain-quadratic energy with respect to the raw strains of
    /// its points, that energy (J) and the points' rotation gradients.
    fn stresses<const NU: usize, const NR: usize>(
        self,
        points: &[ElementPoint<'_, NU, NR>],
        variant: AxlVariant,
    ) -> (f64, Vec<StrainVector>, Vec<[Matrix3<f64>; 2]>) {
        let (strains, xs): (Vec<StrainVector>, Vec<[Matrix3<f64>; 2]>) =
            points.iter().map(|p| point_strains(p.shape, &p.input, variant)).unzip();
        let (value, sigma) = self.stresses_of(points, strains);
        (value, sigma, xs)
    }

    /// The derivatives `σ̂_q` and the strain-quadratic energy for given raw strains of the points.
    fn stresses_of<const NU: usize, const NR: usize>(
        self,
        points: &[ElementPoint<'_, NU, NR>],
        strains: Vec<StrainVector>,
    ) -> (f64, Vec<StrainVector>) {
        match self {
            Self::Projection(projection) => projected::stresses(points, strains, projection),
            Self::Tying(tying) => assumed_kernel::stresses(points, &strains, &tying),
        }
    }

    /// The weight the point kernel's output is accumulated with: the projection's stresses are per
    /// unit weight, the assumed strains' carry their quadrature weights (a tying point has none of
    /// its own).
    fn stress_weight<const NU: usize, const NR: usize>(self, p: &ElementPoint<'_, NU, NR>) -> f64 {
        match self {
            Self::Projection(_) => p.shape.weight,
            Self::Tying(..) => 1.0,
        }
    }

    /// The factor of a point's volume term before it is accumulated with [`Self::stress_weight`]: its
    /// quadrature weight in all.
    fn volume_factor<const NU: usize, const NR: usize>(self, p: &ElementPoint<'_, NU, NR>) -> f64 {
        match self {
            Self::Projection(_) => 1.0,
            Self::Tying(..) => p.shape.weight,
        }
    }
}
