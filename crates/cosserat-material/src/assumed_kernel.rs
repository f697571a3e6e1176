//! The element kernel of the assumed strains ([`crate::assumed`]): energy, gradient and exact Hessian
//! of an element whose quadrature points' strains are `s̃_p = (M_p z + K_p s_p, Γ̂_p)`, with `z` the tied
//! strains (`Ê` entries 0–5 of every tying point), `M_p` and `K_p` the point's [`TyingMap`] (`K_p`
//! keeps the point's own values of the parts that are not assumed).
//!
//! **Derivation.** The energy is `Σ_p w_p ½ s̃_p · D_p s̃_p` over the quadrature points. Its derivative
//! with respect to the raw strains `s_q` of every point of the element (quadrature and tying points) is
//! `σ̂_q`: at a quadrature point, the `Γ̂` part of `w_q D_q s̃_q` and `K_qᵀ` of its `Ê` part; at a tying
//! point, its slice of `Σ_p M_pᵀ (w_p D_p s̃_p)`. So the gradient and the second-order terms of each point's strain map
//! are the point kernel with `σ̂_q` (integration weight one). The first-order part is
//! `Σ_p w_p G̃_pᵀ D_p G̃_p`, where `G̃_p` takes its `Ê` columns from the tying points' Jacobians through
//! `M_p` plus its own through `K_p`, and its `Γ̂` columns from its own.
//!
//! The element's points are its quadrature points followed by its [`N_TYING`] tying points, whose
//! weights are zero.

use crate::assumed::{N_TIED, N_TYING, TIED, TyingMap};
use crate::element::{ElementDerivatives, accumulate_gradient, accumulate_upper, assign_upper};
use crate::kernel::{
    LocalDerivatives, add_second_order_terms, gradient_from_stress, point_strains, strain_jacobian, strain_vector,
    stress_of,
};
use crate::model::AxlVariant;
use crate::parameters::Moduli;
use crate::projected::{ElementPoint, ValuePoint, add_first_order, element_jacobian};
use crate::strain_space::StrainVector;
use crate::volume::{volume_density, volume_hessian};
use nalgebra::{Matrix3, SMatrix, SVector};

/// The tied strains of an element from the raw strains of its points (tying points last).
fn tied(strains: &[StrainVector]) -> SVector<f64, N_TIED> {
    let first = strains.len() - N_TYING;
    SVector::from_fn(|i, _| strains[first + i / TIED][i % TIED])
}

/// The assumed strains of the quadrature points from the raw strains of all points.
fn assumed(strains: &[StrainVector], maps: &[TyingMap]) -> Vec<StrainVector> {
    let z = tied(strains);
    strains
        .iter()
        .zip(maps)
        .map(|(s, m)| {
            let mut out = *s;
            let own = m.own * s.fixed_rows::<TIED>(0);
            out.fixed_rows_mut::<TIED>(0).copy_from(&(m.tied * z + own));
            out
        })
        .collect()
}

/// The strains its energy is a density of, at each quadrature point of an element (`maps.len()`
/// points, then the tying points).
pub fn element_strains<const NU: usize, const NR: usize>(
    points: &[ValuePoint<'_, NU, NR>],
    node_r: [&Matrix3<f64>; NR],
    maps: &[TyingMap],
    variant: AxlVariant,
) -> Vec<StrainVector> {
    let strains: Vec<StrainVector> = points
        .iter()
        .map(|p| strain_vector(p.shape, &p.f_hat, &p.r, node_r, p.offset, variant))
        .collect();
    assumed(&strains, maps)
}

/// The energy of an element (J), plus the nonlinear volume term at its quadrature points.
pub fn element_value<const NU: usize, const NR: usize>(
    points: &[ValuePoint<'_, NU, NR>],
    node_r: [&Matrix3<f64>; NR],
    maps: &[TyingMap],
    variant: AxlVariant,
    volume: Option<&Moduli>,
) -> f64 {
    let strains = element_strains(points, node_r, maps, variant);
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

/// The derivatives `σ̂_q` of the element energy with respect to the raw strains of all its points, the
/// energy (J, strain-quadratic part) and the points' rotation gradients.
fn stresses<const NU: usize, const NR: usize>(
    points: &[ElementPoint<'_, NU, NR>],
    maps: &[TyingMap],
    variant: AxlVariant,
) -> (f64, Vec<StrainVector>, Vec<[Matrix3<f64>; 2]>) {
    let (strains, xs): (Vec<StrainVector>, Vec<[Matrix3<f64>; 2]>) =
        points.iter().map(|p| point_strains(p.shape, &p.input, variant)).unzip();
    let smoothed = assumed(&strains, maps);
    let mut value = 0.0;
    let mut sigma = vec![StrainVector::zeros(); points.len()];
    let mut tied_stress = SVector::<f64, N_TIED>::zeros();
    for ((p, s), (m, out)) in points.iter().zip(&smoothed).zip(maps.iter().zip(sigma.iter_mut())) {
        let ws = p.density.mul_vector(s) * p.shape.weight;
        value += 0.5 * s.dot(&ws);
        tied_stress += m.tied.tr_mul(&ws.fixed_rows::<TIED>(0));
        *out = ws;
        out.fixed_rows_mut::<TIED>(0)
            .copy_from(&m.own.tr_mul(&ws.fixed_rows::<TIED>(0)));
    }
    let first = points.len() - N_TYING;
    for (t, out) in sigma[first..].iter_mut().enumerate() {
        out.fixed_rows_mut::<TIED>(0)
            .copy_from(&tied_stress.fixed_rows::<TIED>(TIED * t));
    }
    (value, sigma, xs)
}

/// Energy and gradient of an element with respect to its unknowns (`out.hessian` is not touched).
pub fn element_gradient<const NU: usize, const NR: usize, const NL: usize, const NE: usize>(
    points: &[ElementPoint<'_, NU, NR>],
    maps: &[TyingMap],
    variant: AxlVariant,
    volume: Option<&Moduli>,
    dt: f64,
    out: &mut ElementDerivatives<NE>,
) {
    let (value, sigma, xs) = stresses(points, maps, variant);
    out.value = value;
    out.gradient.fill(0.0);
    for ((p, sg), x) in points.iter().zip(&sigma).zip(xs) {
        let st = stress_of(p.shape, &p.input, x, sg, variant);
        let mut g: SVector<f64, NL> = gradient_from_stress(p.shape, &p.input, &st);
        if let Some(m) = volume.filter(|_| p.shape.weight > 0.0) {
            let (v, gv, _) = volume_hessian(&p.input.f_hat, m);
            out.value += p.shape.weight * v;
            let mut gl = g.fixed_rows_mut::<6>(0);
            gl += gv * p.shape.weight;
        }
        accumulate_gradient(p.shape, &g, dt, 1.0, &mut out.gradient);
    }
}

/// Energy, gradient and the upper block triangle of the exact Hessian of an element (blocks below the
/// block diagonal are not written). Returns the weights of the nodal rotations' second derivatives, to
/// be added once per node (see `kernel::point_hessian_deferred_into`).
pub fn element_hessian<const NU: usize, const NR: usize, const NL: usize, const NE: usize>(
    points: &[ElementPoint<'_, NU, NR>],
    maps: &[TyingMap],
    variant: AxlVariant,
    volume: Option<&Moduli>,
    dt: f64,
    local: &mut LocalDerivatives<NL>,
    out: &mut ElementDerivatives<NE>,
) -> [Matrix3<f64>; NR] {
    const { assert!(NL == 6 + 3 * NR && NE == 3 * (NU + NR), "inconsistent element sizes") };
    let (value, sigma, xs) = stresses(points, maps, variant);
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
        if let Some(m) = volume.filter(|_| p.shape.weight > 0.0) {
            let w = p.shape.weight;
            let (v, gv, hv) = volume_hessian(&p.input.f_hat, m);
            local.value += w * v;
            let mut gl = local.gradient.fixed_rows_mut::<6>(0);
            gl += gv * w;
            let mut hl = local.hessian.fixed_view_mut::<6, 6>(0, 0);
            hl += hv * w;
        }
        for (sum, w) in node_weights.iter_mut().zip(&st.ru) {
            *sum += w;
        }
        if n == 0 {
            assign_upper(p.shape, local, dt, 1.0, out);
        } else {
            accumulate_upper(p.shape, local, dt, 1.0, out);
        }
        let (jac_t, qrt) = strain_jacobian::<NU, NR, NL>(p.shape, &p.input, &st, variant);
        jacobians.push(element_jacobian(p.shape, &jac_t, &qrt, dt));
    }
    out.value += value;
    add_assumed_first_order(points, &jacobians, maps, &mut out.hessian);
    node_weights
}

/// Adds `Σ_p w_p G̃_pᵀ D_p G̃_p` to the upper block triangle of `h`.
fn add_assumed_first_order<const NU: usize, const NR: usize, const NE: usize>(
    points: &[ElementPoint<'_, NU, NR>],
    jacobians: &[SMatrix<f64, NE, 12>],
    maps: &[TyingMap],
    h: &mut SMatrix<f64, NE, NE>,
) {
    let first = points.len() - N_TYING;
    // The tied strains' Jacobian, column `TIED t + k` = column `k` of tying point `t`'s.
    let mut tied_jacobian = SMatrix::<f64, NE, N_TIED>::zeros();
    for (t, g) in jacobians[first..].iter().enumerate() {
        tied_jacobian
            .fixed_columns_mut::<TIED>(TIED * t)
            .copy_from(&g.fixed_columns::<TIED>(0));
    }
    for ((p, g), m) in points.iter().zip(jacobians).zip(maps) {
        let mut gt = *g;
        let own = g.fixed_columns::<TIED>(0) * m.own.transpose();
        gt.fixed_columns_mut::<TIED>(0)
            .copy_from(&(tied_jacobian * m.tied.transpose() + own));
        add_first_order(p.density, &gt, p.shape.weight, h);
    }
}
