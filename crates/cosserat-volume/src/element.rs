//! From a point's local derivatives to the element's unknowns.
//!
//! The element unknowns are the nodal velocities `v_i` followed by the nodal angular velocities `ω_k`
//! of the same `N` nodes, three components each: `NE = 6N` numbers (24 for Tet4). The locals are
//! `F e_j = Σ_i (x_iⁿ + Δt v_i) ∂_j N_i` and the `ω_k` themselves, so the map is linear and constant,
//! `∂(F e_j)/∂v_i = Δt ∂_j N_i I₃`, and gradient and Hessian map exactly by `Lᵀ g` and `Lᵀ H L`,
//! done here block by block without forming `L`.

use crate::kernel::LocalDerivatives;
use crate::tet4::VolumePoint;
pub use cosserat_material::element::ElementDerivatives;
use cosserat_material::element::{add_block, block};
use nalgebra::{Matrix3, SVector};

/// Adds `weight ×` a point's local gradient to an element gradient.
pub fn accumulate_gradient<const N: usize, const NL: usize, const NE: usize>(
    point: &VolumePoint<N>,
    local_gradient: &SVector<f64, NL>,
    dt: f64,
    weight: f64,
    out: &mut SVector<f64, NE>,
) {
    const { assert!(NL == 9 + 3 * N && NE == 6 * N, "inconsistent element sizes") };
    let gf: [SVector<f64, 3>; 3] = std::array::from_fn(|j| local_gradient.fixed_rows::<3>(3 * j) * (dt * weight));
    for i in 0..N {
        let g = gf[0] * point.grad[(0, i)] + gf[1] * point.grad[(1, i)] + gf[2] * point.grad[(2, i)];
        let mut o = out.fixed_rows_mut::<3>(3 * i);
        o += g;
    }
    for k in 0..N {
        let mut o = out.fixed_rows_mut::<3>(3 * (N + k));
        o += local_gradient.fixed_rows::<3>(9 + 3 * k) * weight;
    }
}

/// Adds `weight ×` a point's local derivatives to an element's derivatives.
pub fn accumulate<const N: usize, const NL: usize, const NE: usize>(
    point: &VolumePoint<N>,
    local: &LocalDerivatives<NL>,
    dt: f64,
    weight: f64,
    out: &mut ElementDerivatives<NE>,
) {
    const { assert!(NL == 9 + 3 * N && NE == 6 * N, "inconsistent element sizes") };
    out.value += weight * local.value;
    accumulate_gradient(point, &local.gradient, dt, weight, &mut out.gradient);
    let h = &local.hessian;
    let b = &point.grad;
    let hff: [[Matrix3<f64>; 3]; 3] = std::array::from_fn(|j| std::array::from_fn(|m| block(h, 3 * j, 3 * m)));
    let (s1, s2) = (dt * weight, dt * dt * weight);
    for i in 0..N {
        // K_m = Σ_j ∂_j N_i H[F_j, F_m].
        let km: [Matrix3<f64>; 3] =
            std::array::from_fn(|m| hff[0][m] * b[(0, i)] + hff[1][m] * b[(1, i)] + hff[2][m] * b[(2, i)]);
        for l in i..N {
            let blk = (km[0] * b[(0, l)] + km[1] * b[(1, l)] + km[2] * b[(2, l)]) * s2;
            add_block(&mut out.hessian, 3 * i, 3 * l, &blk);
            if l != i {
                add_block(&mut out.hessian, 3 * l, 3 * i, &blk.transpose());
            }
        }
        for k in 0..N {
            let c = 9 + 3 * k;
            let blk = (block(h, 0, c) * b[(0, i)] + block(h, 3, c) * b[(1, i)] + block(h, 6, c) * b[(2, i)]) * s1;
            add_block(&mut out.hessian, 3 * i, 3 * (N + k), &blk);
            add_block(&mut out.hessian, 3 * (N + k), 3 * i, &blk.transpose());
        }
    }
    for k in 0..N {
        for l in 0..N {
            let blk = block(h, 9 + 3 * k, 9 + 3 * l) * weight;
            add_block(&mut out.hessian, 3 * (N + k), 3 * (N + l), &blk);
        }
    }
}
