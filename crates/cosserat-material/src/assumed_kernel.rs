//! The assumed strains' part of the coupled element kernel ([`crate::coupled`]): the stresses and the
//! first-order Hessian of an element whose quadrature points' strains are `s̃_p = (M_p z + K_p s_p, Γ̂_p)`, with `z` the tied
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
//! weights are zero. A tying point that lies on a quadrature point ([`TyingTwins`]) takes that point's
//! strains, so its stress is added to the quadrature point's and its Jacobian is the quadrature point's.

use crate::assumed::{N_TIED, N_TYING, TIED, TyingMap, TyingTwins};
use crate::kernel::strain_vector;
use crate::model::AxlVariant;
use crate::projected::{ElementPoint, ValuePoint, add_first_order};
use crate::strain_space::StrainVector;
use nalgebra::{Matrix3, SMatrix, SVector};

/// The tied strains of an element from the raw strains of its points (tying points last).
fn tied(strains: &[StrainVector], twins: &TyingTwins) -> SVector<f64, N_TIED> {
    let first = strains.len() - N_TYING;
    SVector::from_fn(|i, _| strains[twins.source(i / TIED, first)][i % TIED])
}

/// The assumed strains of the quadrature points from the raw strains of all points.
fn assumed(strains: &[StrainVector], maps: &[TyingMap], twins: &TyingTwins) -> Vec<StrainVector> {
    let z = tied(strains, twins);
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
    twins: &TyingTwins,
    variant: AxlVariant,
) -> Vec<StrainVector> {
    let first = points.len() - N_TYING;
    let strains: Vec<StrainVector> = points
        .iter()
        .enumerate()
        .map(|(n, p)| {
            // A twin's strains are read at its quadrature point.
            if n >= first && twins.is_twin(n - first) {
                return StrainVector::zeros();
            }
            strain_vector(p.shape, &p.f_hat, &p.r, node_r, p.offset, variant)
        })
        .collect();
    assumed(&strains, maps, twins)
}

/// The derivatives `σ̂_q` of the element energy with respect to the raw `strains` of all its points,
/// and the energy (J, strain-quadratic part).
pub(crate) fn stresses<const NU: usize, const NR: usize>(
    points: &[ElementPoint<'_, NU, NR>],
    strains: &[StrainVector],
    maps: &[TyingMap],
    twins: &TyingTwins,
) -> (f64, Vec<StrainVector>) {
    let smoothed = assumed(strains, maps, twins);
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
    for t in 0..N_TYING {
        let mut out = sigma[twins.source(t, first)].fixed_rows_mut::<TIED>(0);
        out += tied_stress.fixed_rows::<TIED>(TIED * t);
    }
    (value, sigma)
}

/// Adds `Σ_p w_p G̃_pᵀ D_p G̃_p` to the upper block triangle of `h`.
pub(crate) fn add_assumed_first_order<const NU: usize, const NR: usize, const NE: usize>(
    points: &[ElementPoint<'_, NU, NR>],
    jacobians: &[SMatrix<f64, NE, 12>],
    maps: &[TyingMap],
    twins: &TyingTwins,
    h: &mut SMatrix<f64, NE, NE>,
) {
    let first = points.len() - N_TYING;
    for ((p, g), m) in points.iter().zip(jacobians).zip(maps) {
        // `Ê` columns of G̃_p: Σ_t J_t M_pt^T over the tying points t, plus the point's own through
        // `K_p`. A tying point that the map does not use (the centroid under moment ties) costs nothing.
        let mut tied = g.fixed_columns::<TIED>(0) * m.own.transpose();
        // The maps' blocks are sparse (a membrane tie reads only the tangential entries, a shear or
        // drilling mean only its own), so they are applied entry by entry.
        for t in 0..N_TYING {
            let jt = &jacobians[twins.source(t, first)];
            let block = m.tied.fixed_columns::<TIED>(TIED * t);
            for j in 0..TIED {
                for i in 0..TIED {
                    let v = block[(i, j)];
                    if v != 0.0 {
                        tied.column_mut(i).axpy(v, &jt.column(j), 1.0);
                    }
                }
            }
        }
        let mut gt = *g;
        gt.fixed_columns_mut::<TIED>(0).copy_from(&tied);
        add_first_order(p.density, &gt, p.shape.weight, h);
    }
}
