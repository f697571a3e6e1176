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
//! point-local product and one element-level product of rank at most twelve.

use crate::kernel::{
    PointInput, PointShape, density_times_jacobian, hessian_from_density_jacobian, local_hessian_from_strains,
    strain_vector,
};
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
    add_element_jacobian(shape, jac_t, qrt, dt, 1.0, &mut g);
    g
}

/// `out += G` for the transposed Jacobian `G` of a point's variable strains with respect to the
/// element's unknowns, with its displacement rows scaled by `f_disp` (`Δt`, times a weight) and its
/// rotation rows by `f_rot` (the weight): `∂Ê_γ,a/∂v_i,c = (QᵀRᵀ)_ac Δt ∂N_i/∂t_γ`, and the rotation
/// rows are those of `jac_t`. Only the first `C` strains are written: all twelve, or the six of `Ê`
/// (the only ones the displacement rows have).
pub(crate) fn add_element_jacobian<
    const NU: usize,
    const NR: usize,
    const NL: usize,
    const NE: usize,
    const C: usize,
>(
    shape: &PointShape<NU, NR>,
    jac_t: &SMatrix<f64, NL, 12>,
    qrt: &Matrix3<f64>,
    f_disp: f64,
    f_rot: f64,
    out: &mut SMatrix<f64, NE, C>,
) {
    for i in 0..NU {
        for gamma in 0..2 {
            let b = f_disp * shape.disp_grad[(gamma, i)];
            for c in 0..3 {
                for a in 0..3 {
                    out[(3 * i + c, 3 * gamma + a)] += qrt[(a, c)] * b;
                }
            }
        }
    }
    for s in 0..C {
        for r in 0..3 * NR {
            out[(3 * NU + r, s)] += f_rot * jac_t[(6 + r, s)];
        }
    }
}

/// The first-order (Gauss-Newton) part `Σ_p w_p G̃_pᵀ D_p G̃_p` of a projected element's Hessian,
/// gathered point by point. With `G̃_p = P G_p + B Ḡ` (`P = I − B`) it splits into
///
/// `Σ_p w_p (P G_p)ᵀ D_p (P G_p)  +  X Ĝᵀ + Ĝ Xᵀ  +  Ĝ D̄ Ĝᵀ`,
///
/// with `Ĝ = B Ḡ` (the six columns of `Ê` that `B` touches), `X = Σ_p w_p G_pᵀ P D_p` on those
/// columns and `D̄ = Σ_p w_p D_p` on their block. The first sum is a point-local product, formed in
/// each point's locals like the paper's kernel ([`Self::add_point`]); the rest is one element-level
/// product of rank at most twelve, where forming every `G̃_p` would cost a 27 × 27 × 12 product per
/// point.
///
/// Where `P` is diagonal (the default constants) it scales the rows of the point's strain Jacobian in
/// its locals, so the kernel's own product `D (P J)` gives both the point-local part and, mapped to
/// the element's unknowns, the point's share of `X`; no density is formed. Where `P` couples the
/// tangential pair, the point-local part reads the formed density `P D_p P` and `X` is gathered in
/// the element's unknowns. Where the points share one density that does not couple `Ê` to `Γ` (every
/// flat element), `X = W Ḡ₆ P D` and `D̄ = W D` follow from `Ḡ₆ = Σ_p w_p G_p / W` on the columns of
/// `Ê`, and the three element-level products are one, `W Ḡ₆ (D − P D P) Ḡ₆ᵀ` ([`Self::finish`]).
pub(crate) struct ProjectedFirstOrder<'a, const NE: usize> {
    projection: &'a StrainProjection,
    kept: Kept,
    /// The points' shared density, if it does not couple `Ê` to `Γ`: `X` and `D̄` follow from `Ḡ₆`.
    decoupled: Option<&'a DensityMatrix>,
    dt: f64,
    /// `Σ_p w_p G_p` on the columns of `Ê`, transposed (row = unknown, column = strain entry).
    g_sum: SMatrix<f64, NE, 6>,
    x: SMatrix<f64, NE, 6>,
    d_bar: Matrix6<f64>,
    total: f64,
}

/// How `P` enters the point-local part.
enum Kept {
    /// `P` is diagonal, with these factors on the strain entries 0–5.
    Diagonal([f64; 6]),
    /// `P` couples the tangential pair and the points share one density: `P D P`, formed once.
    SharedDensity(Box<DensityMatrix>),
    /// `P` couples the tangential pair: `P D_p P` is formed at each point.
    PointDensities,
}

impl<'a, const NE: usize> ProjectedFirstOrder<'a, NE> {
    /// An empty sum; `shared` is the density of every point, if they share one, and `dt` the factor of
    /// the displacement unknowns in `F̂`.
    pub(crate) fn new(projection: &'a StrainProjection, shared: Option<&'a DensityMatrix>, dt: f64) -> Self {
        let kept = match (projection.kept_diagonal(), shared) {
            (Some(p), _) => Kept::Diagonal(p),
            (None, Some(d)) => Kept::SharedDensity(Box::new(DensityMatrix::new(projection.kept_density(d.matrix())))),
            (None, None) => Kept::PointDensities,
        };
        Self {
            projection,
            kept,
            decoupled: shared.filter(|d| membrane_decoupled(d)),
            dt,
            g_sum: SMatrix::zeros(),
            x: SMatrix::zeros(),
            d_bar: Matrix6::zeros(),
            total: 0.0,
        }
    }

    /// Adds a point: writes its point-local part `(P J)ᵀ D (P J)` in its locals to `h` (every entry)
    /// and gathers its share of the element-level part; `jac_t` and `qrt` are the transposed Jacobian
    /// of its variable strains and `QᵀRᵀ` (see [`local_hessian_from_strains`]). Where `P` is diagonal,
    /// `jac_t` is left scaled by it (`P J`), which saves a copy per point.
    pub(crate) fn add_point<const NU: usize, const NR: usize, const NL: usize>(
        &mut self,
        shape: &PointShape<NU, NR>,
        jac_t: &mut SMatrix<f64, NL, 12>,
        qrt: &Matrix3<f64>,
        d: &DensityMatrix,
        h: &mut SMatrix<f64, NL, NL>,
    ) {
        let w = shape.weight;
        self.total += w;
        let gather = self.decoupled.is_none();
        if gather {
            let m = d.matrix();
            for k in 0..6 {
                for j in 0..6 {
                    self.d_bar[(j, k)] += w * m[(j, k)];
                }
            }
        }
        add_element_jacobian(shape, jac_t, qrt, w * self.dt, w, &mut self.g_sum);
        match &self.kept {
            Kept::Diagonal(p) => {
                // `P J`: the rows of `Ê_γ` scaled, the same factors for both γ.
                let pj = &mut *jac_t;
                for (s, f) in p.iter().enumerate() {
                    pj.column_mut(s).scale_mut(*f);
                }
                let pq = Matrix3::from_fn(|a, c| p[a] * qrt[(a, c)]);
                let dj_t = density_times_jacobian(pj, &pq, d.variable_entries().iter().copied());
                hessian_from_density_jacobian(pj, &pq, &dj_t, h);
                if gather {
                    // `X += w Gᵀ P D`: the columns 0–5 of `(D P J)ᵀ` mapped to the element's unknowns.
                    map_to_element(shape, &dj_t.fixed_columns::<6>(0), w * self.dt, w, &mut self.x);
                }
            }
            Kept::SharedDensity(kept) => {
                local_hessian_from_strains(jac_t, qrt, kept.variable_entries().iter().copied(), h);
            }
            Kept::PointDensities => {
                let kept = DensityMatrix::new(self.projection.kept_density(d.matrix()));
                local_hessian_from_strains(jac_t, qrt, kept.variable_entries().iter().copied(), h);
            }
        }
        if gather && !matches!(self.kept, Kept::Diagonal(_)) {
            let g = element_jacobian::<NU, NR, NL, NE>(shape, jac_t, qrt, self.dt);
            self.x += g * kept_columns(d, self.projection) * w;
        }
    }

    /// Adds the element-level part to the upper block triangle of `h`.
    pub(crate) fn finish(self, h: &mut SMatrix<f64, NE, NE>) {
        let inv_total = if self.total > 0.0 { 1.0 / self.total } else { 1.0 };
        let b = self.projection.removed_block();
        let g6 = &self.g_sum;
        if let Some(d) = self.decoupled {
            // A shared density without coupling of `Ê` to `Γ` (flat elements): `X = W Ḡ₆ P D` and
            // `D̄ = W D`, so the three products are one, `W Ḡ₆ (P D B + B D P + B D B) Ḡ₆ᵀ`, and with
            // `B = I − P` the middle factor is `D − P D P`.
            let dm = d.matrix().fixed_view::<6, 6>(0, 0);
            let s = match &self.kept {
                Kept::Diagonal(p) => Matrix6::from_fn(|j, k| dm[(j, k)] * (1.0 - p[j] * p[k]) * inv_total),
                _ => {
                    let p = Matrix6::identity() - b;
                    (dm - p * dm * p) * inv_total
                }
            };
            let mut gs = SMatrix::<f64, NE, 6>::zeros();
            add_columns_times(g6, &s, &mut gs);
            add_upper_products::<NE, 6>(h, &[(&gs, g6)]);
            return;
        }
        // `Ĝ = B Ḡ`, `Y = X + ½ Ĝ D̄`, and `Y Ĝᵀ + Ĝ Yᵀ`.
        let mut g_hat = SMatrix::<f64, NE, 6>::zeros();
        add_columns_times(g6, &(b * inv_total), &mut g_hat);
        let mut y = self.x;
        add_columns_times(&g_hat, &(self.d_bar * 0.5), &mut y);
        add_upper_products::<NE, 12>(h, &[(&y, &g_hat), (&g_hat, &y)]);
    }
}

/// Whether the variable block of `d` couples no entry of `Ê` to one of `Γ`.
fn membrane_decoupled(d: &DensityMatrix) -> bool {
    d.variable_entries().iter().all(|e| (e.row < 6) == (e.col < 6))
}

/// `out += a m` for a 6 × 6 matrix `m`, as sums of scaled contiguous columns over the nonzero entries
/// of `m`.
fn add_columns_times<const NE: usize>(a: &SMatrix<f64, NE, 6>, m: &Matrix6<f64>, out: &mut SMatrix<f64, NE, 6>) {
    for k in 0..6 {
        for j in 0..6 {
            let f = m[(j, k)];
            if f != 0.0 {
                let src = &a.as_slice()[j * NE..(j + 1) * NE];
                for (o, x) in out.as_mut_slice()[k * NE..(k + 1) * NE].iter_mut().zip(src) {
                    *o += f * x;
                }
            }
        }
    }
}

/// `h += Σ A Bᵀ` over the `pairs` on the upper block triangle of `h`: entry `(r, c)` is the dot product
/// of row `r` of `[A₁ A₂ …]` with row `c` of `[B₁ B₂ …]`, `K` = 6 × the number of pairs long, which
/// the compiler keeps in vector registers.
fn add_upper_products<const NE: usize, const K: usize>(
    h: &mut SMatrix<f64, NE, NE>,
    pairs: &[(&SMatrix<f64, NE, 6>, &SMatrix<f64, NE, 6>)],
) {
    let left: [[f64; K]; NE] = std::array::from_fn(|r| std::array::from_fn(|j| pairs[j / 6].0[(r, j % 6)]));
    let right: [[f64; K]; NE] = std::array::from_fn(|r| std::array::from_fn(|j| pairs[j / 6].1[(r, j % 6)]));
    for (c, dst) in h.as_mut_slice().chunks_exact_mut(NE).enumerate() {
        let rc = &right[c];
        for (o, lr) in dst[..3 * (c / 3) + 3].iter_mut().zip(&left) {
            *o += lr.iter().zip(rc).map(|(a, b)| a * b).sum::<f64>();
        }
    }
}

/// `out += Mᵀ v` for a matrix `v` in a point's locals (row = local) and the map `M` of the element's
/// unknowns to the locals: `F̂_γ = Σ_i ∂N_i/∂t_γ x_i` with the factor `f_disp` (`w Δt`), the rotation
/// locals one to one with the factor `f_rot` (`w`).
fn map_to_element<const NU: usize, const NR: usize, const NL: usize, const NE: usize, const C: usize, S>(
    shape: &PointShape<NU, NR>,
    v: &nalgebra::Matrix<f64, nalgebra::Const<NL>, nalgebra::Const<C>, S>,
    f_disp: f64,
    f_rot: f64,
    out: &mut SMatrix<f64, NE, C>,
) where
    S: nalgebra::storage::Storage<f64, nalgebra::Const<NL>, nalgebra::Const<C>>,
{
    for k in 0..C {
        for i in 0..NU {
            let (b0, b1) = (f_disp * shape.disp_grad[(0, i)], f_disp * shape.disp_grad[(1, i)]);
            for c in 0..3 {
                out[(3 * i + c, k)] += b0 * v[(c, k)] + b1 * v[(3 + c, k)];
            }
        }
        for r in 0..3 * NR {
            out[(3 * NU + r, k)] += f_rot * v[(6 + r, k)];
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

/// A point's share `w G̃ᵀ D G̃` of an element's first-order part, for the transposed Jacobian `G̃` of its
/// 12 variable strains with respect to the element's unknowns: its columns of `Ê` are `membrane`, those
/// of `Γ̂` are `curvature`.
pub(crate) struct FirstOrderPoint<'a, const NE: usize> {
    pub(crate) density: &'a DensityMatrix,
    pub(crate) membrane: &'a SMatrix<f64, NE, 6>,
    pub(crate) curvature: &'a SMatrix<f64, NE, 6>,
    pub(crate) weight: f64,
}

/// Adds `Σ_p w_p G̃_pᵀ D_p G̃_p` over the `points` to the upper block triangle of `h`.
///
/// Entry `(r, c)` is the dot product of row `r` of `[G̃₁ G̃₂ …]` with row `c` of `[w₁ G̃₁ D₁ w₂ G̃₂ D₂ …]`,
/// taken over up to three points at once. `Γ̂` does not depend on the displacements, so on the
/// displacement rows (before `first_rotation`) the columns of `Γ̂` are zero and only those of `Ê` enter.
pub(crate) fn add_first_order<const NE: usize>(
    points: &[FirstOrderPoint<'_, NE>],
    first_rotation: usize,
    h: &mut SMatrix<f64, NE, NE>,
) {
    for chunk in points.chunks(3) {
        match chunk {
            [a] => add_first_order_of::<NE, 1>([a], first_rotation, h),
            [a, b] => add_first_order_of::<NE, 2>([a, b], first_rotation, h),
            [a, b, c] => add_first_order_of::<NE, 3>([a, b, c], first_rotation, h),
            _ => unreachable!("chunks of one to three points"),
        }
    }
}

/// [`add_first_order`] over `P` points.
fn add_first_order_of<const NE: usize, const P: usize>(
    points: [&FirstOrderPoint<'_, NE>; P],
    first_rotation: usize,
    h: &mut SMatrix<f64, NE, NE>,
) {
    // `D G̃ᵀ` of each point, transposed (column `s` is row `s` of `D G̃ᵀ`), as sums of scaled contiguous
    // columns of `G̃`.
    let mut dg = [SMatrix::<f64, NE, 12>::zeros(); P];
    for (p, dg) in points.iter().zip(dg.iter_mut()) {
        for e in p.density.variable_entries() {
            let c = e.col as usize;
            let src = if c < 6 {
                p.membrane.column(c)
            } else {
                p.curvature.column(c - 6)
            };
            dg.column_mut(e.row as usize).axpy(e.value, &src, 1.0);
        }
    }
    // The rows of `G̃` and of `w G̃ D`, the points side by side, for `Ê` and `Γ̂` apart.
    let rows_of = |columns: [&SMatrix<f64, NE, 6>; P]| -> [[[f64; 6]; P]; NE] {
        std::array::from_fn(|r| {
            let mut row = [[0.0; 6]; P];
            for (x, m) in row.iter_mut().zip(columns) {
                for (s, v) in x.iter_mut().enumerate() {
                    *v = m[(r, s)];
                }
            }
            row
        })
    };
    let g_membrane = rows_of(points.map(|p| p.membrane));
    let g_curvature = rows_of(points.map(|p| p.curvature));
    let weighted = |c: usize, first: usize| -> [[f64; 6]; P] {
        let mut row = [[0.0; 6]; P];
        for ((x, p), dg) in row.iter_mut().zip(points).zip(&dg) {
            for (s, v) in x.iter_mut().enumerate() {
                *v = p.weight * dg[(c, first + s)];
            }
        }
        row
    };
    let dot = |a: &[[f64; 6]; P], b: &[[f64; 6]; P]| {
        a.as_flattened().iter().zip(b.as_flattened()).map(|(x, y)| x * y).sum::<f64>()
    };
    for (c, dst) in h.as_mut_slice().chunks_exact_mut(NE).enumerate() {
        let rows = 3 * (c / 3) + 3;
        let (dc_membrane, dc_curvature) = (weighted(c, 0), weighted(c, 6));
        let displacement = rows.min(first_rotation);
        for (o, gr) in dst[..displacement].iter_mut().zip(&g_membrane) {
            *o += dot(gr, &dc_membrane);
        }
        for ((o, gm), gc) in dst[displacement..rows]
            .iter_mut()
            .zip(&g_membrane[displacement..])
            .zip(&g_curvature[displacement..])
        {
            *o += dot(gm, &dc_membrane) + dot(gc, &dc_curvature);
        }
    }
}
