//! The stabilised strain projection's part of the coupled element kernel ([`crate::coupled`]): the
//! stresses and the first-order Hessian of an element whose points' strains are
//! `s̃_p = s_p − B (s_p − s̄)` ([`crate::projection`]), and the point types of both coupled kernels.
//!
//! **Derivation.** With `σ̃_p = D_p s̃_p` the energy is `Σ_p w_p ½ s̃_p · σ̃_p`. Since `B` is symmetric
//! and `s̄` the weighted mean, `∂E/∂s_q = w_q σ̂_q` with `σ̂_q = σ̃_q − B (σ̃_q − σ̄)` and `σ̄` the
//! weighted mean of the `σ̃_p`. So the gradient and the second-order terms of each point's strain map
//! are the paper's point kernel with `σ̂_q` in place of `D s_q`. The first-order (Gauss-Newton) part
//! couples the points: with `G_p` the Jacobian of `s_p` with respect to the element's unknowns,
//! `G̃_p = G_p − B (G_p − Ḡ)`, it is `Σ_p w_p G̃_pᵀ D_p G̃_p`, split by `ProjectedFirstOrder` into a
//! point-local product and one element-level product of rank six.

use crate::kernel::{PointInput, PointShape, strain_vector};
use crate::model::AxlVariant;
use crate::projection::StrainProjection;
use crate::strain_space::{DensityMatrix, StrainVector, VARIABLE_STRAINS};
use nalgebra::{Matrix3, Matrix6, SMatrix, Vector3};

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

/// The derivatives `σ̂_q` of the element's strain-quadratic energy with respect to its points' raw
/// `strains`, and that energy (J).
pub(crate) fn stresses<const NU: usize, const NR: usize>(
    points: &[ElementPoint<'_, NU, NR>],
    mut strains: Vec<StrainVector>,
    projection: &StrainProjection,
) -> (f64, Vec<StrainVector>) {
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
    (value, sigma)
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

/// The first-order (Gauss-Newton) part `Σ_p w_p G̃_pᵀ D_p G̃_p` of a projected element's Hessian,
/// gathered point by point. With `G̃_p = P G_p + B Ḡ` (`P = I − B`) it splits into
///
/// `Σ_p w_p G_pᵀ (P D_p P) G_p  +  X Ĝᵀ + Ĝ Xᵀ  +  Ĝ D̄ Ĝᵀ`,
///
/// with `Ĝ = B Ḡ` (the six columns of `Ê` that `B` touches), `X = Σ_p w_p G_pᵀ (P D_p)` on those
/// columns and `D̄ = Σ_p w_p D_p` on their block. The first sum is a point-local product, formed in
/// each point's locals like the paper's kernel with the density `P D_p P`
/// ([`StrainProjection::kept_density`]); the rest is one element-level product of rank six, where
/// forming every `G̃_p` would cost a 27 × 27 × 12 product per point.
///
/// Where all points share one density (every flat element), `X = (Σ_p w_p G_p)ᵀ (P D)` and
/// `D̄ = W D` follow from the sum of the Jacobians at the end, and each point adds only its Jacobian.
pub(crate) struct ProjectedFirstOrder<'a, const NE: usize> {
    shared: Option<&'a DensityMatrix>,
    g_sum: SMatrix<f64, NE, 12>,
    x: SMatrix<f64, NE, 6>,
    d_bar: Matrix6<f64>,
    total: f64,
}

impl<'a, const NE: usize> ProjectedFirstOrder<'a, NE> {
    /// An empty sum; `shared` is the density of every point, if they share one.
    pub(crate) fn new(shared: Option<&'a DensityMatrix>) -> Self {
        Self {
            shared,
            g_sum: SMatrix::zeros(),
            x: SMatrix::zeros(),
            d_bar: Matrix6::zeros(),
            total: 0.0,
        }
    }

    /// Adds a point of weight `w`, density `d` and transposed element Jacobian `g` (row = unknown,
    /// column = variable strain).
    pub(crate) fn add(&mut self, g: &SMatrix<f64, NE, 12>, d: &DensityMatrix, projection: &StrainProjection, w: f64) {
        self.g_sum.zip_apply(g, |s, x| *s += w * x);
        self.total += w;
        if self.shared.is_none() {
            self.x += g * kept_columns(d, projection) * w;
            self.d_bar += d.matrix().fixed_view::<6, 6>(0, 0) * w;
        }
    }

    /// Adds the element-level part to the upper block triangle of `h`.
    pub(crate) fn finish(mut self, projection: &StrainProjection, h: &mut SMatrix<f64, NE, NE>) {
        if let Some(d) = self.shared {
            self.x = self.g_sum * kept_columns(d, projection);
            self.d_bar = d.matrix().fixed_view::<6, 6>(0, 0) * self.total;
        }
        let g_bar = if self.total > 0.0 {
            self.g_sum / self.total
        } else {
            self.g_sum
        };
        let g_hat = g_bar.fixed_columns::<6>(0) * projection.removed_block();
        let y = self.x + g_hat * self.d_bar * 0.5;
        let m = y * g_hat.transpose();
        for c in 0..NE {
            for r in 0..3 * (c / 3) + 3 {
                h[(r, c)] += m[(r, c)] + m[(c, r)];
            }
        }
    }
}

/// `P D` on the variable strains (rows) and the strain entries 0–5 (columns), `P = I − B`.
fn kept_columns(d: &DensityMatrix, projection: &StrainProjection) -> SMatrix<f64, 12, 6> {
    let keep = Matrix6::identity() - projection.removed_block();
    let m = d.matrix();
    let mut pd = SMatrix::<f64, 12, 6>::from_fn(|r, c| m[(VARIABLE_STRAINS[r], c)]);
    let top = keep * pd.fixed_rows::<6>(0);
    pd.fixed_rows_mut::<6>(0).copy_from(&top);
    pd
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
