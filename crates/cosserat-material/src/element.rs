//! From a point's local derivatives to the element's unknowns.
//!
//! The element unknowns are the nodal velocities `v_i` (`NU` displacement nodes) followed by the nodal
//! angular velocities `ω_k` (`NR` rotation nodes), three components each: `NE = 3 (NU + NR)` numbers.
//! The locals of a point are `F̂_γ = Σ_i (x_iⁿ + Δt v_i) ∂N_i/∂t_γ` and the `ω_k` themselves, so the map
//! is linear and constant: `∂F̂_γ/∂v_i = Δt ∂N_i/∂t_γ · I₃`. Gradient and Hessian are therefore mapped
//! exactly by `Lᵀ g` and `Lᵀ H L`, done here block by block without forming `L`.

use crate::kernel::{LocalDerivatives, PointShape};
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// Energy, gradient and Hessian of an element with respect to its `NE` unknowns.
#[derive(Debug, Clone, PartialEq)]
pub struct ElementDerivatives<const NE: usize> {
    /// Energy \[J\].
    pub value: f64,
    /// Gradient.
    pub gradient: SVector<f64, NE>,
    /// Hessian (symmetric).
    pub hessian: SMatrix<f64, NE, NE>,
}

impl<const NE: usize> ElementDerivatives<NE> {
    /// All zero.
    pub fn zeros() -> Self {
        Self {
            value: 0.0,
            gradient: SVector::zeros(),
            hessian: SMatrix::zeros(),
        }
    }

    /// Sets the Hessian's blocks below the block diagonal to zero: the part that [`accumulate_upper`]
    /// and [`assign_upper`] never write.
    pub fn clear_below_block_diagonal(&mut self) {
        for (c, column) in self.hessian.as_mut_slice().chunks_exact_mut(NE).enumerate() {
            column[3 * (c / 3 + 1)..].fill(0.0);
        }
    }

    /// Copies the upper triangle of the Hessian onto its lower triangle.
    pub fn fill_lower_from_upper(&mut self) {
        // Column-major: entry (r, c) is at c NE + r.
        let h = self.hessian.as_mut_slice();
        for c in 0..NE {
            for r in c + 1..NE {
                h[c * NE + r] = h[r * NE + c];
            }
        }
    }
}

/// `F̂ = [F̂₁ F̂₂]` of a point from the element's current nodal positions.
#[inline]
pub fn f_hat<const NU: usize, const NR: usize>(
    shape: &PointShape<NU, NR>,
    positions: &[Vector3<f64>; NU],
) -> [Vector3<f64>; 2] {
    let mut f = [Vector3::zeros(); 2];
    for (i, x) in positions.iter().enumerate() {
        f[0] += x * shape.disp_grad[(0, i)];
        f[1] += x * shape.disp_grad[(1, i)];
    }
    f
}

/// The interpolated angular velocity `ω_g = Σ_k M_k ω_k` of a point.
#[inline]
pub fn point_omega<const NU: usize, const NR: usize>(
    shape: &PointShape<NU, NR>,
    omega: &[Vector3<f64>; NR],
) -> Vector3<f64> {
    let mut w = Vector3::zeros();
    for (k, o) in omega.iter().enumerate() {
        w += o * shape.rot_values[k];
    }
    w
}

/// The 3×3 block of `m` starting at row `r` and column `c`.
#[inline]
pub fn block<const R: usize, const C: usize>(m: &SMatrix<f64, R, C>, r: usize, c: usize) -> Matrix3<f64> {
    m.fixed_view::<3, 3>(r, c).into_owned()
}

/// Adds `b` to the 3×3 block of `m` starting at row `r` and column `c`.
#[inline]
pub fn add_block<const N: usize>(m: &mut SMatrix<f64, N, N>, r: usize, c: usize, b: &Matrix3<f64>) {
    let mut v = m.fixed_view_mut::<3, 3>(r, c);
    v += b;
}

/// Adds `weight ×` a point's local gradient to an element gradient.
pub fn accumulate_gradient<const NU: usize, const NR: usize, const NL: usize, const NE: usize>(
    shape: &PointShape<NU, NR>,
    local_gradient: &SVector<f64, NL>,
    dt: f64,
    weight: f64,
    out: &mut SVector<f64, NE>,
) {
    const { assert!(NL == 6 + 3 * NR && NE == 3 * (NU + NR), "inconsistent element sizes") };
    let gf0 = local_gradient.fixed_rows::<3>(0) * (dt * weight);
    let gf1 = local_gradient.fixed_rows::<3>(3) * (dt * weight);
    for i in 0..NU {
        let g = gf0 * shape.disp_grad[(0, i)] + gf1 * shape.disp_grad[(1, i)];
        let mut o = out.fixed_rows_mut::<3>(3 * i);
        o += g;
    }
    for k in 0..NR {
        let mut o = out.fixed_rows_mut::<3>(3 * (NU + k));
        o += local_gradient.fixed_rows::<3>(6 + 3 * k) * weight;
    }
}

/// Adds `weight ×` a point's local derivatives to an element's energy, gradient and the upper block
/// triangle of its Hessian (blocks below the block diagonal are left untouched).
///
/// The element Hessian is symmetric, so the lower triangle is filled once per element
/// ([`ElementDerivatives::fill_lower_from_upper`]) where the whole matrix is needed, instead of once per
/// quadrature point; the assembly's scatter reads only the upper block triangle and skips it.
pub fn accumulate_upper<const NU: usize, const NR: usize, const NL: usize, const NE: usize>(
    shape: &PointShape<NU, NR>,
    local: &LocalDerivatives<NL>,
    dt: f64,
    weight: f64,
    out: &mut ElementDerivatives<NE>,
) {
    map_upper::<NU, NR, NL, NE, false, true>(shape, local, dt, weight, out);
}

/// [`accumulate_upper`] for an element's first point: the upper block triangle of the Hessian is
/// overwritten instead of added to (the energy and the gradient are still added to), which saves
/// clearing the element Hessian before its points are added.
pub fn assign_upper<const NU: usize, const NR: usize, const NL: usize, const NE: usize>(
    shape: &PointShape<NU, NR>,
    local: &LocalDerivatives<NL>,
    dt: f64,
    weight: f64,
    out: &mut ElementDerivatives<NE>,
) {
    map_upper::<NU, NR, NL, NE, true, true>(shape, local, dt, weight, out);
}

/// [`accumulate_upper`] (or, with `assign`, [`assign_upper`]) for local derivatives whose `F̂F̂` block is
/// zero (a point's second-order terms alone): the blocks of the displacements are left untouched (set
/// to zero with `assign`), which saves mapping a zero block to each of them.
pub fn accumulate_upper_without_stretch_block<const NU: usize, const NR: usize, const NL: usize, const NE: usize>(
    shape: &PointShape<NU, NR>,
    local: &LocalDerivatives<NL>,
    dt: f64,
    weight: f64,
    assign: bool,
    out: &mut ElementDerivatives<NE>,
) {
    if assign {
        map_upper::<NU, NR, NL, NE, true, false>(shape, local, dt, weight, out);
    } else {
        map_upper::<NU, NR, NL, NE, false, false>(shape, local, dt, weight, out);
    }
}

/// The map of [`accumulate_upper`] (`ASSIGN` for [`assign_upper`]); without `STRETCH`, the local
/// Hessian's `F̂F̂` block is taken as zero.
#[inline]
fn map_upper<
    const NU: usize,
    const NR: usize,
    const NL: usize,
    const NE: usize,
    const ASSIGN: bool,
    const STRETCH: bool,
>(
    shape: &PointShape<NU, NR>,
    local: &LocalDerivatives<NL>,
    dt: f64,
    weight: f64,
    out: &mut ElementDerivatives<NE>,
) {
    const { assert!(NL == 6 + 3 * NR && NE == 3 * (NU + NR), "inconsistent element sizes") };
    out.value += weight * local.value;
    accumulate_gradient(shape, &local.gradient, dt, weight, &mut out.gradient);
    let put = |m: &mut SMatrix<f64, NE, NE>, r: usize, c: usize, b: &Matrix3<f64>| {
        if ASSIGN {
            m.fixed_view_mut::<3, 3>(r, c).copy_from(b);
        } else {
            add_block(m, r, c, b);
        }
    };
    let h = &local.hessian;
    let b = &shape.disp_grad;
    // K_iδ = Σ_γ B_iγ H[F̂_γ, F̂_δ] and P_ik = Σ_γ B_iγ H[F̂_γ, ω_k].
    let hff = [[block(h, 0, 0), block(h, 0, 3)], [block(h, 3, 0), block(h, 3, 3)]];
    let mut hfw = [[Matrix3::zeros(); NR]; 2];
    for (gamma, row) in hfw.iter_mut().enumerate() {
        for (k, m) in row.iter_mut().enumerate() {
            *m = block(h, 3 * gamma, 6 + 3 * k);
        }
    }
    let s2 = dt * dt * weight;
    let s1 = dt * weight;
    for i in 0..NU {
        let k0 = (hff[0][0] * b[(0, i)] + hff[1][0] * b[(1, i)]) * s2;
        let k1 = (hff[0][1] * b[(0, i)] + hff[1][1] * b[(1, i)]) * s2;
        for j in i..NU {
            if STRETCH {
                let blk = k0 * b[(0, j)] + k1 * b[(1, j)];
                put(&mut out.hessian, 3 * i, 3 * j, &blk);
            } else if ASSIGN {
                put(&mut out.hessian, 3 * i, 3 * j, &Matrix3::zeros());
            }
        }
        let (b0, b1) = (b[(0, i)] * s1, b[(1, i)] * s1);
        for k in 0..NR {
            let blk = hfw[0][k] * b0 + hfw[1][k] * b1;
            put(&mut out.hessian, 3 * i, 3 * (NU + k), &blk);
        }
    }
    for k in 0..NR {
        for l in k..NR {
            let blk = block(h, 6 + 3 * k, 6 + 3 * l) * weight;
            put(&mut out.hessian, 3 * (NU + k), 3 * (NU + l), &blk);
        }
    }
}
