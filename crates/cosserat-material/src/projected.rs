//! The element kernel of the stabilised strain projection ([`crate::projection`]): energy, gradient
//! and exact Hessian of an element whose points' strains are `s̃_p = s_p − B (s_p − s̄)`.
//!
//! **Derivation.** With `σ̃_p = D_p s̃_p` the energy is `Σ_p w_p ½ s̃_p · σ̃_p`. Since `B` is symmetric
//! and `s̄` the weighted mean, `∂E/∂s_q = w_q σ̂_q` with `σ̂_q = σ̃_q − B (σ̃_q − σ̄)` and `σ̄` the
//! weighted mean of the `σ̃_p`. So the gradient and the second-order terms of each point's strain map
//! are today's point kernel with `σ̂_q` in place of `D s_q`. The first-order (Gauss-Newton) part couples
//! the points: with `G_p` the Jacobian of `s_p` with respect to the element's unknowns,
//! `G̃_p = G_p − B (G_p − Ḡ)`, it is `Σ_p w_p G̃_pᵀ D_p G̃_p`, formed here in element unknowns.

use crate::element::{ElementDerivatives, accumulate_gradient, accumulate_upper, assign_upper};
use crate::kernel::{
    LocalDerivatives, PointInput, PointShape, add_second_order_terms, gradient_from_stress, point_strains,
    strain_jacobian, strain_vector, stress_of,
};
use crate::model::AxlVariant;
use crate::parameters::Moduli;
use crate::projection::StrainProjection;
use crate::strain_space::{DensityMatrix, StrainVector};
use crate::volume::{volume_density, volume_hessian};
use nalgebra::{Matrix3, SMatrix, Vector3};

/// One point of an element as the projected kernels need it.
#[derive(Debug, Clone, Copy)]
pub struct ElementPoint<'a, const NU: usize, const NR: usize> {
    /// Fixed shape data.
    pub shape: &'a PointShape<NU, NR>,
    /// Current state.
    pub input: PointInput<'a, NR>,
    /// Density Hessian.
    pub density: &'a DensityMatrix,
}

/// One point for the energy alone.
#[derive(Debug, Clone, Copy)]
pub struct ValuePoint<'a, const NU: usize, const NR: usize> {
    /// Fixed shape data.
    pub shape: &'a PointShape<NU, NR>,
    /// `F̂₁, F̂₂`.
    pub f_hat: [Vector3<f64>; 2],
    /// The point rotation.
    pub r: Matrix3<f64>,
    /// The strain offset.
    pub offset: &'a StrainVector,
    /// Density Hessian.
    pub density: &'a DensityMatrix,
}

/// The weighted mean `Σ w_p v_p / Σ w_p`.
fn mean(values: &[StrainVector], weights: impl Iterator<Item = f64>) -> StrainVector {
    let mut sum = StrainVector::zeros();
    let mut total = 0.0;
    for (v, w) in values.iter().zip(weights) {
        sum += v * w;
        total += w;
    }
    if total > 0.0 { sum / total } else { sum }
}

/// The projected strains of an element's points from their own strains.
fn project(strains: &mut [StrainVector], weights: impl Iterator<Item = f64>, projection: &StrainProjection) {
    let bar = mean(strains, weights);
    for s in strains.iter_mut() {
        *s -= projection.removed(&(*s - bar));
    }
}

/// The projected strains of an element's points (the strains its energy is a density of).
pub fn element_strains<const NU: usize, const NR: usize>(
    points: &[ValuePoint<'_, NU, NR>],
    node_r: [&Matrix3<f64>; NR],
    projection: Option<&StrainProjection>,
    variant: AxlVariant,
) -> Vec<StrainVector> {
    let mut strains: Vec<StrainVector> = points
        .iter()
        .map(|p| strain_vector(p.shape, &p.f_hat, &p.r, node_r, p.offset, variant))
        .collect();
    if let Some(projection) = projection {
        project(&mut strains, points.iter().map(|p| p.shape.weight), projection);
    }
    strains
}

/// The energy of an element (weighted sum over its points, J), plus the nonlinear volume term.
pub fn element_value<const NU: usize, const NR: usize>(
    points: &[ValuePoint<'_, NU, NR>],
    node_r: [&Matrix3<f64>; NR],
    projection: &StrainProjection,
    variant: AxlVariant,
    volume: Option<&Moduli>,
) -> f64 {
    let strains = element_strains(points, node_r, Some(projection), variant);
    points
        .iter()
        .zip(&strains)
        .map(|(p, s)| {
            let mut psi = 0.5 * s.dot(&p.density.mul_vector(s));
            if let Some(m) = volume {
                psi += volume_density(&p.f_hat, m);
            }
            p.shape.weight * psi
        })
        .sum()
}

/// The projected strains' stresses `σ̂_p` and the element energy (J, strain-quadratic part).
fn stresses<const NU: usize, const NR: usize>(
    points: &[ElementPoint<'_, NU, NR>],
    projection: &StrainProjection,
    variant: AxlVariant,
) -> (f64, Vec<StrainVector>, Vec<[Matrix3<f64>; 2]>) {
    let (mut strains, xs): (Vec<StrainVector>, Vec<[Matrix3<f64>; 2]>) =
        points.iter().map(|p| point_strains(p.shape, &p.input, variant)).unzip();
    let weights = || points.iter().map(|p| p.shape.weight);
    project(&mut strains, weights(), projection);
    let mut value = 0.0;
    let mut sigma: Vec<StrainVector> = Vec::with_capacity(points.len());
    for (p, s) in points.iter().zip(&strains) {
        let sg = p.density.mul_vector(s);
        value += p.shape.weight * 0.5 * s.dot(&sg);
        sigma.push(sg);
    }
    project(&mut sigma, weights(), projection);
    (value, sigma, xs)
}

/// Energy and gradient of an element with respect to its unknowns (`out.hessian` is not touched).
pub fn element_gradient<const NU: usize, const NR: usize, const NL: usize, const NE: usize>(
    points: &[ElementPoint<'_, NU, NR>],
    projection: &StrainProjection,
    variant: AxlVariant,
    volume: Option<&Moduli>,
    dt: f64,
    out: &mut ElementDerivatives<NE>,
) {
    let (value, sigma, xs) = stresses(points, projection, variant);
    out.value = value;
    out.gradient.fill(0.0);
    for ((p, sg), x) in points.iter().zip(&sigma).zip(xs) {
        let st = stress_of(p.shape, &p.input, x, sg, variant);
        let mut g: nalgebra::SVector<f64, NL> = gradient_from_stress(p.shape, &p.input, &st);
        if let Some(m) = volume {
            let (v, gv, _) = volume_hessian(&p.input.f_hat, m);
            out.value += p.shape.weight * v;
            let mut gl = g.fixed_rows_mut::<6>(0);
            gl += gv;
        }
        accumulate_gradient(p.shape, &g, dt, p.shape.weight, &mut out.gradient);
    }
}

/// Energy, gradient and the upper block triangle of the exact Hessian of an element (blocks below the
/// block diagonal are not written). Returns the weights `Σ_p w_p R U_k,p` of the nodal rotations'
/// second derivatives, to be added once per node (see `kernel::point_hessian_deferred_into`).
pub fn element_hessian<const NU: usize, const NR: usize, const NL: usize, const NE: usize>(
    points: &[ElementPoint<'_, NU, NR>],
    projection: &StrainProjection,
    variant: AxlVariant,
    volume: Option<&Moduli>,
    dt: f64,
    local: &mut LocalDerivatives<NL>,
    out: &mut ElementDerivatives<NE>,
) -> [Matrix3<f64>; NR] {
    const { assert!(NL == 6 + 3 * NR && NE == 3 * (NU + NR), "inconsistent element sizes") };
    let (value, sigma, xs) = stresses(points, projection, variant);
    out.value = 0.0;
    out.gradient.fill(0.0);
    let mut node_weights = [Matrix3::zeros(); NR];
    let mut jacobians: Vec<SMatrix<f64, NE, 12>> = Vec::with_capacity(points.len());
    for (n, ((p, sg), x)) in points.iter().zip(&sigma).zip(xs).enumerate() {
        let st = stress_of(p.shape, &p.input, x, sg, variant);
        local.value = 0.0;
        local.gradient = gradient_from_stress(p.shape, &p.input, &st);
        local.hessian.fill(0.0);
        add_second_order_terms(p.shape, &p.input, &st, &mut local.hessian);
        if let Some(m) = volume {
            let (v, gv, hv) = volume_hessian(&p.input.f_hat, m);
            local.value += v;
            let mut gl = local.gradient.fixed_rows_mut::<6>(0);
            gl += gv;
            let mut hl = local.hessian.fixed_view_mut::<6, 6>(0, 0);
            hl += hv;
        }
        for (sum, w) in node_weights.iter_mut().zip(&st.ru) {
            *sum += w * p.shape.weight;
        }
        if n == 0 {
            assign_upper(p.shape, local, dt, p.shape.weight, out);
        } else {
            accumulate_upper(p.shape, local, dt, p.shape.weight, out);
        }
        let (jac_t, qrt) = strain_jacobian::<NU, NR, NL>(p.shape, &p.input, &st, variant);
        jacobians.push(element_jacobian(p.shape, &jac_t, &qrt, dt));
    }
    out.value += value;
    add_coupled_first_order(points, &jacobians, projection, &mut out.hessian);
    node_weights
}

/// The transposed Jacobian of a point's 12 variable strains with respect to the element's unknowns
/// (row = unknown, column = strain), from its Jacobian with respect to its locals.
pub(crate) fn element_jacobian<const NU: usize, const NR: usize, const NL: usize, const NE: usize>(
    shape: &PointShape<NU, NR>,
    jac_t: &SMatrix<f64, NL, 12>,
    qrt: &Matrix3<f64>,
    dt: f64,
) -> SMatrix<f64, NE, 12> {
    let mut g = SMatrix::<f64, NE, 12>::zeros();
    // ∂Ê_γ,a/∂v_i,c = (QᵀRᵀ)_ac Δt ∂N_i/∂t_γ.
    for i in 0..NU {
        for gamma in 0..2 {
            let b = dt * shape.disp_grad[(gamma, i)];
            for c in 0..3 {
                for a in 0..3 {
                    g[(3 * i + c, 3 * gamma + a)] = qrt[(a, c)] * b;
                }
            }
        }
    }
    for r in 0..3 * NR {
        for s in 0..12 {
            g[(3 * NU + r, s)] = jac_t[(6 + r, s)];
        }
    }
    g
}

/// Adds `Σ_p w_p G̃_pᵀ D_p G̃_p` to the upper block triangle of `h`.
fn add_coupled_first_order<const NU: usize, const NR: usize, const NE: usize>(
    points: &[ElementPoint<'_, NU, NR>],
    jacobians: &[SMatrix<f64, NE, 12>],
    projection: &StrainProjection,
    h: &mut SMatrix<f64, NE, NE>,
) {
    let mut bar = SMatrix::<f64, NE, 12>::zeros();
    let mut total = 0.0;
    for (p, g) in points.iter().zip(jacobians) {
        bar += g * p.shape.weight;
        total += p.shape.weight;
    }
    if total > 0.0 {
        bar /= total;
    }
    for (p, g) in points.iter().zip(jacobians) {
        let gt = g - projection.removed_columns(&(g - bar));
        add_first_order(p.density, &gt, p.shape.weight, h);
    }
}

/// Adds `w G̃ᵀ D G̃` to the upper block triangle of `h`, for the transposed Jacobian `G̃` of a point's
/// 12 variable strains with respect to the element's unknowns.
pub(crate) fn add_first_order<const NE: usize>(
    density: &DensityMatrix,
    gt: &SMatrix<f64, NE, 12>,
    w: f64,
    h: &mut SMatrix<f64, NE, NE>,
) {
    // Column `r` of `dg` is row `r` of `D G̃`.
    let mut dg = SMatrix::<f64, NE, 12>::zeros();
    for e in density.variable_entries() {
        let (r, c) = (e.row as usize, e.col as usize);
        let mut col = dg.column_mut(r);
        col.axpy(e.value, &gt.column(c), 1.0);
    }
    for c in 0..NE {
        let rows = 3 * (c / 3) + 3;
        for s in 0..12 {
            let f = w * dg[(c, s)];
            if f == 0.0 {
                continue;
            }
            for r in 0..rows {
                h[(r, c)] += f * gt[(r, s)];
            }
        }
    }
}
