//! The energy of a point written directly as a generic function of its unknowns.
//!
//! This is the plain composition "unknowns → rotations → strains → density", with the density evaluated
//! term by term (not through its strain Hessian). It is slow when differentiated with dual numbers, and
//! it is what the fast kernel (`kernel`) is checked against: same value, same gradient, same Hessian.

use crate::density::{PointGeometry, density};
use crate::kernel::{PointShape, axial};
use crate::model::{AxlVariant, TermSet};
use crate::parameters::Moduli;
use crate::strain_space::{StrainMatrix, StrainVector, unpack};
use crate::volume::volume_density;
use cosserat_geometry::Real;
use cosserat_geometry::rotation::{quaternion_update, rotation_matrix};
use nalgebra::{Matrix3, Quaternion, SVector, Vector3};
use num_dual::Dual2SVec64;

/// Everything a point's energy depends on besides its unknowns.
#[derive(Debug, Clone, Copy)]
pub struct PointContext<'a, const NU: usize, const NR: usize> {
    /// Fixed shape data of the point.
    pub shape: &'a PointShape<NU, NR>,
    /// Point rotation at the start of the step.
    pub point_quaternion: Quaternion<f64>,
    /// Nodal rotations at the start of the step.
    pub node_quaternions: [Quaternion<f64>; NR],
    /// Time step \[s\].
    pub dt: f64,
    /// Strain offset `(Â, Γ̂_rest)`.
    pub offset: &'a StrainVector,
    /// Rest curvature data in the point's frame.
    pub geometry: &'a PointGeometry,
    /// Active terms.
    pub terms: &'a TermSet,
    /// Moduli.
    pub moduli: &'a Moduli,
    /// Axial-vector variant.
    pub axl: AxlVariant,
}

/// The strains `(Ê, Γ̂)` of a point in its rest frame (offset subtracted) as functions of its locals.
pub fn local_strains<T: Real, const NU: usize, const NR: usize>(
    ctx: &PointContext<'_, NU, NR>,
    f_hat: &[Vector3<T>; 2],
    omega: &[Vector3<T>; NR],
) -> (Matrix3<T>, Matrix3<T>) {
    let shape = ctx.shape;
    let mut omega_point = Vector3::<T>::zeros();
    for k in 0..NR {
        omega_point += omega[k] * T::from(shape.rot_values[k]);
    }
    let r = rotation_matrix(&quaternion_update(&ctx.point_quaternion, &omega_point, ctx.dt));
    let node_r: [Matrix3<T>; NR] =
        std::array::from_fn(|k| rotation_matrix(&quaternion_update(&ctx.node_quaternions[k], &omega[k], ctx.dt)));
    let qt = shape.frame.transpose().cast::<T>();
    let rt = r.transpose();
    let mut e = Matrix3::<T>::zeros();
    let mut g = Matrix3::<T>::zeros();
    for gamma in 0..2 {
        let mut x = Matrix3::<T>::zeros();
        for k in 0..NR {
            x += node_r[k] * T::from(shape.rot_grad[(gamma, k)]);
        }
        e.set_column(gamma, &(qt * (rt * f_hat[gamma])));
        g.set_column(gamma, &(qt * axial(&(rt * x), ctx.axl)));
    }
    for c in 0..3 {
        for a in 0..3 {
            e[(a, c)] -= T::from(ctx.offset[3 * c + a]);
            g[(a, c)] -= T::from(ctx.offset[9 + 3 * c + a]);
        }
    }
    (e, g)
}

/// The energy density of a point as a function of its locals `F̂` and `ω_k` (per unit rest area).
pub fn local_energy<T: Real, const NU: usize, const NR: usize>(
    ctx: &PointContext<'_, NU, NR>,
    f_hat: &[Vector3<T>; 2],
    omega: &[Vector3<T>; NR],
) -> T {
    let (e, g) = local_strains(ctx, f_hat, omega);
    let mut psi = density(ctx.terms, &e, &g, ctx.geometry, ctx.moduli);
    if ctx.terms.contains(crate::model::EnergyTerm::NonlinearVolume) {
        psi += volume_density(f_hat, ctx.moduli);
    }
    psi
}

/// `F̂_γ = Σ_i x_i ∂N_i/∂t_γ` from the element's current nodal positions.
pub fn f_hat_of<T: Real, const NU: usize, const NR: usize>(
    shape: &PointShape<NU, NR>,
    positions: &[Vector3<T>; NU],
) -> [Vector3<T>; 2] {
    std::array::from_fn(|gamma| {
        let mut f = Vector3::<T>::zeros();
        for (i, x) in positions.iter().enumerate() {
            f += *x * T::from(shape.disp_grad[(gamma, i)]);
        }
        f
    })
}

/// The energy of a point (density times its integration weight) as a function of the element's
/// unknowns: nodal velocities `v_i` and nodal angular velocities `ω_k`, with `x_i = x_iⁿ + Δt v_i`.
pub fn element_point_energy<T: Real, const NU: usize, const NR: usize>(
    ctx: &PointContext<'_, NU, NR>,
    x_start: &[Vector3<f64>; NU],
    velocity: &[Vector3<T>; NU],
    omega: &[Vector3<T>; NR],
) -> T {
    let positions: [Vector3<T>; NU] = std::array::from_fn(|i| x_start[i].cast::<T>() + velocity[i] * T::from(ctx.dt));
    local_energy(ctx, &f_hat_of(ctx.shape, &positions), omega) * T::from(ctx.shape.weight)
}

/// The Hessian of [`density`] with respect to the strain vector, by differentiating it with num-dual:
/// the check of the closed form [`crate::strain_space::strain_hessian`], which does not go through
/// [`density`].
pub fn density_hessian(terms: &TermSet, geom: &PointGeometry, moduli: &Moduli) -> StrainMatrix {
    let zero = SVector::<f64, 18>::zeros();
    let (_, _, h) = num_dual::hessian(
        |s: SVector<Dual2SVec64<18>, 18>| {
            let (e, g) = unpack(&s);
            density(terms, &e, &g, geom, moduli)
        },
        &zero,
    );
    h
}
