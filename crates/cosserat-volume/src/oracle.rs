//! The energy of an element written directly as a generic function of its unknowns.
//!
//! This is the plain composition "velocities and angular velocities → positions and rotations → `F`,
//! `E`, `Γ` → density", evaluated through [`density`] (not through its strain Hessian). Differentiated
//! with second-order dual numbers over all 24 unknowns of a Tet4 it is slow, and it is what the fast
//! kernel (`kernel`, `element`) is checked against: same value, same gradient, same Hessian.

use crate::density::density;
use crate::material::MicropolarModuli;
use crate::tet4::VolumePoint;
use cosserat_geometry::Real;
use cosserat_geometry::rotation::{axl, quaternion_update, rotation_matrix};
use nalgebra::{Matrix3, Quaternion, Vector3};

/// Everything an element's energy depends on besides its unknowns.
#[derive(Debug, Clone, Copy)]
pub struct ElementContext<'a, const N: usize> {
    /// Fixed data of the element's (single) point.
    pub point: &'a VolumePoint<N>,
    /// Nodal positions at the start of the step \[m\].
    pub x_start: [Vector3<f64>; N],
    /// Point rotation at the start of the step.
    pub point_quaternion: Quaternion<f64>,
    /// Nodal rotations at the start of the step.
    pub node_quaternions: [Quaternion<f64>; N],
    /// Time step \[s\].
    pub dt: f64,
    /// Prescribed rest curvature (world axes).
    pub rest_curvature: &'a Matrix3<f64>,
    /// Moduli.
    pub moduli: &'a MicropolarModuli,
}

/// The element's elastic energy \[J\] as a function of its nodal velocities `v_i` and angular
/// velocities `ω_k`, with `x_i = x_iⁿ + Δt v_i`.
pub fn element_energy<T: Real, const N: usize>(
    ctx: &ElementContext<'_, N>,
    velocity: &[Vector3<T>; N],
    omega: &[Vector3<T>; N],
) -> T {
    let p = ctx.point;
    let x: [Vector3<T>; N] = std::array::from_fn(|i| ctx.x_start[i].cast::<T>() + velocity[i] * T::from(ctx.dt));
    let mut omega_point = Vector3::<T>::zeros();
    for k in 0..N {
        omega_point += omega[k] * T::from(p.values[k]);
    }
    let r = rotation_matrix(&quaternion_update(&ctx.point_quaternion, &omega_point, ctx.dt));
    let node_r: [Matrix3<T>; N] =
        std::array::from_fn(|k| rotation_matrix(&quaternion_update(&ctx.node_quaternions[k], &omega[k], ctx.dt)));
    let rt = r.transpose();
    let mut e = Matrix3::<T>::zeros();
    let mut g = Matrix3::<T>::zeros();
    for j in 0..3 {
        let mut f = Vector3::<T>::zeros();
        let mut xj = Matrix3::<T>::zeros();
        for i in 0..N {
            f += x[i] * T::from(p.grad[(j, i)]);
            xj += node_r[i] * T::from(p.grad[(j, i)]);
        }
        e.set_column(j, &(rt * f));
        g.set_column(j, &axl(&(rt * xj)));
    }
    e -= Matrix3::identity();
    g -= ctx.rest_curvature.cast::<T>();
    density(&e, &g, ctx.moduli) * T::from(p.weight)
}
