//! The fast exact kernel of one quadrature point: energy, gradient and Hessian with respect to the
//! point's compact local unknowns.
//!
//! **Locals.** At a quadrature point the energy depends on
//! - the current deformation gradient on the orthonormal rest tangents, `F̂ = [F̂₁ F̂₂] = g G⁺ [t₁ t₂]`
//!   (6 numbers, linear in the nodal velocities), and
//! - the angular velocities `ω_k` of the `NR` rotation nodes (the point rotation is advanced with the
//!   interpolated `ω_g = Σ_k M_k ω_k`, model.md §1.5–1.6).
//!
//! So there are `NL = 6 + 3 NR` locals: 15 for linear and 24 for quadratic rotation elements.
//!
//! **Structure.** With `R` the point rotation and `R_k` the nodal rotations at the end of the step, the
//! strains in the rest frame `Q` are
//! `Ê_γ = Qᵀ Rᵀ F̂_γ − Â_γ` and `Γ̂_γ = Qᵀ axl(Rᵀ Σ_k C_kγ R_k) − Γ̂_rest,γ`,
//! where `C_kγ` is the derivative of the rotation shape function `k` along `t_γ`. They are bilinear in
//! `(R, F̂)` and `(R, R_k)`; the density is a quadratic form `½ sᵀ D s` of the strains (see
//! `strain_space`); the only other nonlinearity is each rotation map `ω ↦ R(Φ(q, ω, Δt))`, whose first
//! and second derivatives come from num-dual ([`RotationJet`]). The chain rule then gives the exact
//! Hessian as `Jᵀ D J` plus the second-order terms of the bilinear maps weighted by `σ = D s`:
//! microseconds per point instead of the hundreds of microseconds of an 18-direction second-order dual
//! pass (the latter is kept as the test oracle, see `oracle`).

use crate::element::{add_block, point_omega};
use crate::model::AxlVariant;
use crate::strain_space::{DensityMatrix, Entry, StrainVector};
use cosserat_geometry::rotation::{RotationJet, axl, axl_upper, skew};
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// The parts of a quadrature point that stay fixed during a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointShape<const NU: usize, const NR: usize> {
    /// Row `γ`: derivatives of the displacement shape functions along the rest tangent `t_γ`
    /// (`(G⁺ [t₁ t₂])ᵀ ∇N`), in 1/m.
    pub disp_grad: SMatrix<f64, 2, NU>,
    /// Values of the rotation shape functions at the point.
    pub rot_values: SVector<f64, NR>,
    /// Row `γ`: derivatives of the rotation shape functions along `t_γ`, in 1/m.
    pub rot_grad: SMatrix<f64, 2, NR>,
    /// The orthonormal rest frame `Q = [t₁ t₂ n₀]`.
    pub frame: Matrix3<f64>,
    /// Integration weight: quadrature weight times rest area element, in m².
    pub weight: f64,
}

/// Energy, gradient and Hessian of a point with respect to its `NL` locals `(F̂₁, F̂₂, ω₁, …, ω_NR)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalDerivatives<const NL: usize> {
    /// Energy density at the point (per unit rest area).
    pub value: f64,
    /// Gradient.
    pub gradient: SVector<f64, NL>,
    /// Hessian (symmetric).
    pub hessian: SMatrix<f64, NL, NL>,
}

impl<const NL: usize> LocalDerivatives<NL> {
    /// All zero.
    pub fn zeros() -> Self {
        Self {
            value: 0.0,
            gradient: SVector::zeros(),
            hessian: SMatrix::zeros(),
        }
    }
}

/// The current state of a point as the kernels need it.
#[derive(Debug, Clone, Copy)]
pub struct PointInput<'a, const NR: usize> {
    /// `F̂₁, F̂₂`: the current tangent map on the rest tangents.
    pub f_hat: [Vector3<f64>; 2],
    /// Jet of the point rotation with respect to the interpolated angular velocity.
    pub point_jet: &'a RotationJet,
    /// Jets of the nodal rotations, each with respect to its own node's angular velocity.
    pub node_jets: [&'a RotationJet; NR],
    /// The constant strain offset `(Â, Γ̂_rest)`.
    pub offset: &'a StrainVector,
}

/// `axl` of a matrix in the chosen variant.
#[inline]
pub fn axial<T: cosserat_geometry::Real>(m: &Matrix3<T>, variant: AxlVariant) -> Vector3<T> {
    match variant {
        AxlVariant::SkewPart => axl(m),
        AxlVariant::UpperTriangle => axl_upper(m),
    }
}

/// The matrix `T` with `⟨T, M⟩ = τ · axl(M)` for all `M` (the adjoint of the axial map).
#[inline]
fn axial_adjoint(tau: &Vector3<f64>, variant: AxlVariant) -> Matrix3<f64> {
    match variant {
        AxlVariant::SkewPart => skew(tau) * 0.5,
        AxlVariant::UpperTriangle => {
            let mut t = Matrix3::zeros();
            t[(1, 2)] = -tau.x;
            t[(2, 0)] = -tau.y;
            t[(0, 1)] = -tau.z;
            t
        }
    }
}

#[inline]
fn frob(a: &Matrix3<f64>, b: &Matrix3<f64>) -> f64 {
    a.component_mul(b).sum()
}

/// The vector `m` with `⟨[ξ]×, A Bᵀ⟩ = ξ · m` for every `ξ` (twice the axial vector of the skew part of
/// `A Bᵀ`), from the six off-diagonal entries of `A Bᵀ` only.
///
/// With a rotation derivative `∂R/∂ω_i = [ξ_i]× R`, inner products `⟨∂R/∂ω_i M, N⟩` for all `i` are
/// `Ξᵀ m(N, R M)`: one such vector instead of three matrix products.
#[inline]
fn skew_pairing(a: &Matrix3<f64>, b: &Matrix3<f64>) -> Vector3<f64> {
    let row = |m: &Matrix3<f64>, r: usize| Vector3::new(m[(r, 0)], m[(r, 1)], m[(r, 2)]);
    let (a0, a1, a2) = (row(a, 0), row(a, 1), row(a, 2));
    let (b0, b1, b2) = (row(b, 0), row(b, 1), row(b, 2));
    Vector3::new(
        a2.dot(&b1) - a1.dot(&b2),
        a0.dot(&b2) - a2.dot(&b0),
        a1.dot(&b0) - a0.dot(&b1),
    )
}

/// The 18 strain numbers of a point from its rotations (offset already subtracted).
#[inline]
pub fn strain_vector<const NU: usize, const NR: usize>(
    shape: &PointShape<NU, NR>,
    f_hat: &[Vector3<f64>; 2],
    r: &Matrix3<f64>,
    node_r: [&Matrix3<f64>; NR],
    offset: &StrainVector,
    variant: AxlVariant,
) -> StrainVector {
    let x = rotation_gradients(shape, node_r);
    strains_from_rotation_gradients(shape, f_hat, r, &x, offset, variant)
}

/// The interpolated rotation gradients `X_γ = Σ_k C_kγ R_k`.
#[inline]
fn rotation_gradients<const NU: usize, const NR: usize>(
    shape: &PointShape<NU, NR>,
    node_r: [&Matrix3<f64>; NR],
) -> [Matrix3<f64>; 2] {
    let mut x = [Matrix3::zeros(); 2];
    for (gamma, xg) in x.iter_mut().enumerate() {
        for (k, rk) in node_r.iter().enumerate() {
            *xg += *rk * shape.rot_grad[(gamma, k)];
        }
    }
    x
}

/// [`strain_vector`] given the rotation gradients `X_γ`.
#[inline]
fn strains_from_rotation_gradients<const NU: usize, const NR: usize>(
    shape: &PointShape<NU, NR>,
    f_hat: &[Vector3<f64>; 2],
    r: &Matrix3<f64>,
    x: &[Matrix3<f64>; 2],
    offset: &StrainVector,
    variant: AxlVariant,
) -> StrainVector {
    let qrt = shape.frame.transpose() * r.transpose();
    let mut s = -offset;
    for gamma in 0..2 {
        let e = qrt * f_hat[gamma];
        let g = shape.frame.transpose() * axial(&(r.transpose() * x[gamma]), variant);
        for a in 0..3 {
            s[3 * gamma + a] += e[a];
            s[9 + 3 * gamma + a] += g[a];
        }
    }
    s
}

/// Energy density of a point (f64 path for line searches).
#[inline]
pub fn point_value<const NU: usize, const NR: usize>(
    shape: &PointShape<NU, NR>,
    f_hat: &[Vector3<f64>; 2],
    r: &Matrix3<f64>,
    node_r: [&Matrix3<f64>; NR],
    offset: &StrainVector,
    d: &DensityMatrix,
    variant: AxlVariant,
) -> f64 {
    let s = strain_vector(shape, f_hat, r, node_r, offset, variant);
    0.5 * s.dot(&d.mul_vector(&s))
}

/// The σ-dependent intermediate quantities shared by gradient and Hessian.
pub(crate) struct Stress<const NR: usize> {
    pub(crate) value: f64,
    /// `w_γ = Q σ_Ê,γ` (world frame).
    w: [Vector3<f64>; 2],
    /// `R U_k`, the weights of the nodal rotations' derivatives, with `U_k = Σ_γ C_kγ T_γ` and `T_γ` the
    /// axial adjoint of `Q σ_Γ̂,γ`.
    pub(crate) ru: [Matrix3<f64>; NR],
    /// `Y + Z = Σ_k R_k U_kᵀ + Σ_γ F̂_γ w_γᵀ`: `⟨R_i, Y + Z⟩` is the gradient along the point rotation.
    yz: Matrix3<f64>,
    /// The interpolated rotation gradients `X_γ = Σ_k C_kγ R_k`.
    x: [Matrix3<f64>; 2],
    /// The stress has no `Γ̂` part, so every `R U_k` is zero.
    pub(crate) curvature_free: bool,
}

#[inline]
fn stress<const NU: usize, const NR: usize>(
    shape: &PointShape<NU, NR>,
    input: &PointInput<'_, NR>,
    d: &DensityMatrix,
    variant: AxlVariant,
) -> Stress<NR> {
    let node_r = input.node_jets.map(|j| &j.r);
    let x = rotation_gradients(shape, node_r);
    let s = strains_from_rotation_gradients(shape, &input.f_hat, &input.point_jet.r, &x, input.offset, variant);
    let sigma = d.mul_vector(&s);
    let mut st = stress_of(shape, input, x, &sigma, variant);
    st.value = 0.5 * s.dot(&sigma);
    st
}

/// The strains of a point from its input (offset subtracted), with its rotation gradients `X_γ`.
#[inline]
pub(crate) fn point_strains<const NU: usize, const NR: usize>(
    shape: &PointShape<NU, NR>,
    input: &PointInput<'_, NR>,
    variant: AxlVariant,
) -> (StrainVector, [Matrix3<f64>; 2]) {
    let x = rotation_gradients(shape, input.node_jets.map(|j| &j.r));
    let s = strains_from_rotation_gradients(shape, &input.f_hat, &input.point_jet.r, &x, input.offset, variant);
    (s, x)
}

/// The intermediate quantities of a given stress `σ = ∂Ψ/∂s` (its `value` is left zero).
#[inline]
pub(crate) fn stress_of<const NU: usize, const NR: usize>(
    shape: &PointShape<NU, NR>,
    input: &PointInput<'_, NR>,
    x: [Matrix3<f64>; 2],
    sigma: &StrainVector,
    variant: AxlVariant,
) -> Stress<NR> {
    let q = &shape.frame;
    let r = &input.point_jet.r;
    let node_r = input.node_jets.map(|j| &j.r);
    let w = [q * sigma.fixed_rows::<3>(0), q * sigma.fixed_rows::<3>(3)];
    let tau = [q * sigma.fixed_rows::<3>(9), q * sigma.fixed_rows::<3>(12)];
    let mut yz = input.f_hat[0] * w[0].transpose() + input.f_hat[1] * w[1].transpose();
    let mut ru = [Matrix3::zeros(); NR];
    match variant {
        // T_γ = ½ [τ_γ]×, so U_k = [ν_k]× with ν_k = ½ Σ_γ C_kγ τ_γ: the products with U_k are
        // products with a skew matrix, two columns per column.
        AxlVariant::SkewPart => {
            for k in 0..NR {
                let nu = (tau[0] * shape.rot_grad[(0, k)] + tau[1] * shape.rot_grad[(1, k)]) * 0.5;
                // R_k U_kᵀ = −R_k [ν_k]×.
                yz -= times_skew(node_r[k], &nu);
                ru[k] = times_skew(r, &nu);
            }
        }
        AxlVariant::UpperTriangle => {
            let t = [axial_adjoint(&tau[0], variant), axial_adjoint(&tau[1], variant)];
            for k in 0..NR {
                let u = t[0] * shape.rot_grad[(0, k)] + t[1] * shape.rot_grad[(1, k)];
                yz += node_r[k] * u.transpose();
                ru[k] = r * u;
            }
        }
    }
    Stress {
        value: 0.0,
        w,
        ru,
        yz,
        x,
        curvature_free: sigma.fixed_rows::<6>(9).iter().all(|&s| s == 0.0),
    }
}

/// `M [ν]×`: column `j` is `M (ν × e_j)`, a combination of the other two columns of `M`.
#[inline]
fn times_skew(m: &Matrix3<f64>, nu: &Vector3<f64>) -> Matrix3<f64> {
    let (c0, c1, c2) = (m.column(0), m.column(1), m.column(2));
    Matrix3::from_columns(&[c1 * nu.z - c2 * nu.y, c2 * nu.x - c0 * nu.z, c0 * nu.y - c1 * nu.x])
}

/// Energy density and its gradient with respect to the locals.
pub fn point_gradient<const NU: usize, const NR: usize, const NL: usize>(
    shape: &PointShape<NU, NR>,
    input: &PointInput<'_, NR>,
    d: &DensityMatrix,
    variant: AxlVariant,
) -> (f64, SVector<f64, NL>) {
    const { assert!(NL == 6 + 3 * NR, "NL must be 6 + 3 NR") };
    let st = stress(shape, input, d, variant);
    (st.value, gradient_from_stress(shape, input, &st))
}

pub(crate) fn gradient_from_stress<const NU: usize, const NR: usize, const NL: usize>(
    shape: &PointShape<NU, NR>,
    input: &PointInput<'_, NR>,
    st: &Stress<NR>,
) -> SVector<f64, NL> {
    let jet = input.point_jet;
    let mut grad = SVector::<f64, NL>::zeros();
    for gamma in 0..2 {
        grad.fixed_rows_mut::<3>(3 * gamma).copy_from(&(jet.r * st.w[gamma]));
    }
    // ⟨∂R/∂ω_i, Y + Z⟩ = ξ_i · m(Y + Z, R).
    let gp = jet.generators.tr_mul(&skew_pairing(&st.yz, &jet.r));
    for k in 0..NR {
        let mk = shape.rot_values[k];
        for i in 0..3 {
            grad[6 + 3 * k + i] = mk * gp[i] + frob(&st.ru[k], &input.node_jets[k].d1[i]);
        }
    }
    grad
}

/// `Jᵀ D J` for the strain Jacobian `J` of a point, given the transpose of its rotation columns
/// (`jac_t`, row `c` = column `c` of `J`; its `F̂` rows are ignored) and `QᵀRᵀ`.
///
/// The `F̂_γ` columns of `J` are `QᵀRᵀ` on the rows of `Ê_γ` and zero elsewhere, so `D J` needs a
/// 3-column product for them, and the `F̂` rows of `Jᵀ (D J)` are `RQ (D J)` restricted to the rows of
/// `Ê_γ`. Only the rotation columns are dense. `D J` runs over the nonzero entries of `D` (see
/// [`DensityMatrix`]), given as `entries` (positions in [`crate::strain_space::VARIABLE_STRAINS`]), so that
/// a caller can scale them on the fly.
///
/// Both `J` and `D J` are held transposed, so that every product here is a sum of scaled contiguous
/// columns: each entry of the result is a short sum of independent products that the compiler keeps
/// in vector registers, where dot products of strain columns would each be one long chain of
/// dependent additions.
#[inline]
pub(crate) fn local_hessian_from_strains<const NL: usize>(
    jac_t: &SMatrix<f64, NL, 12>,
    qrt: &Matrix3<f64>,
    entries: impl IntoIterator<Item = Entry>,
    h: &mut SMatrix<f64, NL, NL>,
) {
    let dj_t = density_times_jacobian(jac_t, qrt, entries);
    hessian_from_density_jacobian(jac_t, qrt, &dj_t, h);
}

/// `D J` in the locals, transposed (column `r` is row `r` of `D J`), for the `jac_t`, `qrt` and
/// `entries` of [`local_hessian_from_strains`].
#[inline]
pub(crate) fn density_times_jacobian<const NL: usize>(
    jac_t: &SMatrix<f64, NL, 12>,
    qrt: &Matrix3<f64>,
    entries: impl IntoIterator<Item = Entry>,
) -> SMatrix<f64, NL, 12> {
    let mut dj_t = SMatrix::<f64, NL, 12>::zeros();
    {
        let js = jac_t.as_slice();
        let ds = dj_t.as_mut_slice();
        for e in entries {
            let (r, b, v) = (e.row as usize, e.col as usize, e.value);
            let dst = &mut ds[r * NL..(r + 1) * NL];
            if b < 6 {
                let (gamma, a) = (b / 3, b % 3);
                for c in 0..3 {
                    dst[3 * gamma + c] += v * qrt[(a, c)];
                }
            }
            let src = &js[b * NL..(b + 1) * NL];
            for (o, x) in dst[6..].iter_mut().zip(&src[6..]) {
                *o += v * x;
            }
        }
    }
    dj_t
}

/// `Jᵀ (D J)` into every entry of `h`, from `D J` ([`density_times_jacobian`]).
#[inline]
pub(crate) fn hessian_from_density_jacobian<const NL: usize>(
    jac_t: &SMatrix<f64, NL, 12>,
    qrt: &Matrix3<f64>,
    dj_t: &SMatrix<f64, NL, 12>,
    h: &mut SMatrix<f64, NL, NL>,
) {
    // Every entry of `h` is written below. Columns `3γ + a` (and by symmetry rows): `Jᵀ D J` on the `F̂`
    // side is `RQ` applied to the rows of `Ê_γ` of `D J`.
    for gamma in 0..2 {
        for a in 0..3 {
            let mut col = SVector::<f64, NL>::zeros();
            for m in 0..3 {
                col.axpy(qrt[(m, a)], &dj_t.column(3 * gamma + m), 1.0);
            }
            h.set_column(3 * gamma + a, &col);
        }
    }
    for c in 6..NL {
        for r in 0..6 {
            h[(r, c)] = h[(c, r)];
        }
        // Column `c` of the rotation block, `Σ_s (D J)[s, c] J[s, ·]`, of which rows `6..=c` are kept
        // (and mirrored), so that the result is exactly symmetric. The whole column costs less than its
        // upper part: a fixed length keeps the loop in vector registers.
        let mut col = [0.0; NL];
        let js = jac_t.as_slice();
        for s in 0..12 {
            let w = dj_t[(c, s)];
            let src = &js[s * NL..(s + 1) * NL];
            for (o, x) in col[6..].iter_mut().zip(&src[6..]) {
                *o += w * x;
            }
        }
        for r in 6..=c {
            h[(r, c)] = col[r];
            h[(c, r)] = col[r];
        }
    }
}

/// Energy density, gradient and exact Hessian with respect to the locals.
pub fn point_hessian<const NU: usize, const NR: usize, const NL: usize>(
    shape: &PointShape<NU, NR>,
    input: &PointInput<'_, NR>,
    d: &DensityMatrix,
    variant: AxlVariant,
) -> LocalDerivatives<NL> {
    let mut out = LocalDerivatives::zeros();
    point_hessian_into(shape, input, d, variant, &mut out);
    out
}

/// [`point_hessian`] written into `out` (every entry is overwritten). Element loops reuse one `out`,
/// which saves moving the 15 × 15 result at every point.
pub fn point_hessian_into<const NU: usize, const NR: usize, const NL: usize>(
    shape: &PointShape<NU, NR>,
    input: &PointInput<'_, NR>,
    d: &DensityMatrix,
    variant: AxlVariant,
    out: &mut LocalDerivatives<NL>,
) {
    let weights = point_hessian_deferred_into(shape, input, d, variant, out);
    for (k, (w, jet)) in weights.iter().zip(input.node_jets).enumerate() {
        add_node_second_derivatives(&mut out.hessian, 6 + 3 * k, jet, w);
    }
}

/// Adds the terms of a nodal rotation's second derivatives, `⟨W, ∂²R_k/∂ω_k,i∂ω_k,j⟩` for the weight
/// `W` returned by [`point_hessian_deferred_into`] (or a weighted sum of such weights), to the 3 × 3
/// diagonal block of `m` whose first row and column are `at`.
#[inline]
pub fn add_node_second_derivatives<const N: usize>(
    m: &mut SMatrix<f64, N, N>,
    at: usize,
    jet: &RotationJet,
    weight: &Matrix3<f64>,
) {
    let c = jet.second_contraction(weight);
    for i in 0..3 {
        for j in 0..3 {
            m[(at + i, at + j)] += c[i][j];
        }
    }
}

/// [`point_hessian_into`] without the terms of the nodal rotations' second derivatives,
/// `⟨R U_k, ∂²R_k/∂ω_k,i∂ω_k,j⟩` in the diagonal block of node `k`; returns their weights `R U_k`
/// instead.
///
/// Those terms are linear in the weight, and a node's jet is the same at every point of an element, so
/// an element adds them once per node from `Σ_p w_p R U_k,p` (see [`RotationJet::second_contraction`])
/// instead of once per point.
pub fn point_hessian_deferred_into<const NU: usize, const NR: usize, const NL: usize>(
    shape: &PointShape<NU, NR>,
    input: &PointInput<'_, NR>,
    d: &DensityMatrix,
    variant: AxlVariant,
    out: &mut LocalDerivatives<NL>,
) -> [Matrix3<f64>; NR] {
    point_hessian_predicted_into(shape, input, d, variant, None, out)
}

/// [`point_hessian_deferred_into`] whose second-order terms are weighted by the stress `D s̃` of
/// predicted strains `s̃` instead of the point's own (`None`: its own). The energy, the gradient and
/// the first-order part `Jᵀ D J` are the point's.
///
/// This is the iteration matrix of the mixed-integration-point Newton method (see
/// `cosserat_solver::NewtonSettings::mixed_stresses`): `s̃` is the previous iterate's strain
/// advanced along its step by the strains' linearisation ([`linearized_strains`]), which leaves out
/// the step's second-order strain error that makes the stresses of thin shells swing wildly from
/// one iterate to the next.
pub fn point_hessian_predicted_into<const NU: usize, const NR: usize, const NL: usize>(
    shape: &PointShape<NU, NR>,
    input: &PointInput<'_, NR>,
    d: &DensityMatrix,
    variant: AxlVariant,
    predicted: Option<&StrainVector>,
    out: &mut LocalDerivatives<NL>,
) -> [Matrix3<f64>; NR] {
    const { assert!(NL == 6 + 3 * NR, "NL must be 6 + 3 NR") };
    let st = stress(shape, input, d, variant);
    out.value = st.value;
    out.gradient = gradient_from_stress(shape, input, &st);
    let (jac_t, qrt) = strain_jacobian(shape, input, &st.x, variant);
    local_hessian_from_strains(&jac_t, &qrt, d.variable_entries().iter().copied(), &mut out.hessian);
    let second = match predicted {
        Some(s) => stress_of(shape, input, st.x, &d.mul_vector(s), variant),
        None => st,
    };
    add_second_order_terms(shape, input, &second, &mut out.hessian);
    second.ru
}

/// The strains of a point (offset subtracted) and their derivative along a change of its locals:
/// `d_f_hat` of `F̂₁, F̂₂` and `d_omega` of the nodal angular velocities.
///
/// The derivative is formed directly rather than as the strain Jacobian times the change: with the
/// spins `v = Ξ ω̇` of the point's and the nodes' rotations (`∂R/∂ω_i = [ξ_i]× R`),
/// `δÊ_γ = QᵀRᵀ (δF̂_γ + F̂_γ × v_p)` and `δΓ̂_γ = Qᵀ axl(Rᵀ (Σ_k C_γk [v_k]× R_k − [v_p]× X_γ))`, a
/// few matrix products where the Jacobian takes three per node.
pub fn linearized_strains<const NU: usize, const NR: usize>(
    shape: &PointShape<NU, NR>,
    input: &PointInput<'_, NR>,
    variant: AxlVariant,
    d_f_hat: &[Vector3<f64>; 2],
    d_omega: &[Vector3<f64>; NR],
) -> (StrainVector, StrainVector) {
    let (s, x) = point_strains(shape, input, variant);
    let qt = shape.frame.transpose();
    let rt = input.point_jet.r.transpose();
    let qrt = qt * rt;
    let v_p = point_spin(shape, input, d_omega);
    let node_spins: [Matrix3<f64>; NR] =
        std::array::from_fn(|k| skew(&(input.node_jets[k].generators * d_omega[k])) * input.node_jets[k].r);
    let mut ds = StrainVector::zeros();
    for gamma in 0..2 {
        let de = qrt * (d_f_hat[gamma] + input.f_hat[gamma].cross(&v_p));
        let mut dx = -(skew(&v_p) * x[gamma]);
        for (k, spin) in node_spins.iter().enumerate() {
            dx += spin * shape.rot_grad[(gamma, k)];
        }
        let dg = qt * axial(&(rt * dx), variant);
        for a in 0..3 {
            ds[3 * gamma + a] = de[a];
            ds[9 + 3 * gamma + a] = dg[a];
        }
    }
    (s, ds)
}

/// [`linearized_strains`] of the membrane strains `Ê_γ` alone, every other entry zero: for a tying point
/// of the assumed strains, whose other strains nothing reads.
pub fn linearized_membrane_strains<const NU: usize, const NR: usize>(
    shape: &PointShape<NU, NR>,
    input: &PointInput<'_, NR>,
    d_f_hat: &[Vector3<f64>; 2],
    d_omega: &[Vector3<f64>; NR],
) -> (StrainVector, StrainVector) {
    let qrt = shape.frame.transpose() * input.point_jet.r.transpose();
    let v_p = point_spin(shape, input, d_omega);
    let (mut s, mut ds) = (StrainVector::zeros(), StrainVector::zeros());
    for gamma in 0..2 {
        let e = qrt * input.f_hat[gamma];
        let de = qrt * (d_f_hat[gamma] + input.f_hat[gamma].cross(&v_p));
        for a in 0..3 {
            s[3 * gamma + a] = e[a] - input.offset[3 * gamma + a];
            ds[3 * gamma + a] = de[a];
        }
    }
    (s, ds)
}

/// The spin `v = Ξ Σ_k M_k ω̇_k` of a point's rotation along the nodal angular velocities `d_omega`
/// (`δR = [v]× R`).
fn point_spin<const NU: usize, const NR: usize>(
    shape: &PointShape<NU, NR>,
    input: &PointInput<'_, NR>,
    d_omega: &[Vector3<f64>; NR],
) -> Vector3<f64> {
    input.point_jet.generators * point_omega(shape, d_omega)
}

/// The Jacobian of a point's 12 variable strains with respect to its locals, transposed (row `c` =
/// derivative along local `c`), and `QᵀRᵀ`.
///
/// Its `F̂` columns are `QᵀRᵀ` on the rows of `Ê_γ` and zero elsewhere; they are left out (zero rows of
/// the result) and used in that form by [`local_hessian_from_strains`].
pub(crate) fn strain_jacobian<const NU: usize, const NR: usize, const NL: usize>(
    shape: &PointShape<NU, NR>,
    input: &PointInput<'_, NR>,
    x: &[Matrix3<f64>; 2],
    variant: AxlVariant,
) -> (SMatrix<f64, NL, 12>, Matrix3<f64>) {
    strain_jacobian_columns::<NU, NR, NL, true>(shape, input, x, variant)
}

/// [`strain_jacobian`] on the columns of `Ê` only (those of `Γ̂` are left zero), for a point whose
/// curvature strains nothing reads (a tying point of the assumed strains).
pub(crate) fn membrane_strain_jacobian<const NU: usize, const NR: usize, const NL: usize>(
    shape: &PointShape<NU, NR>,
    input: &PointInput<'_, NR>,
    x: &[Matrix3<f64>; 2],
    variant: AxlVariant,
) -> (SMatrix<f64, NL, 12>, Matrix3<f64>) {
    strain_jacobian_columns::<NU, NR, NL, false>(shape, input, x, variant)
}

/// [`strain_jacobian`], with the columns of `Γ̂` if `CURVATURE` (zero otherwise).
#[inline]
fn strain_jacobian_columns<const NU: usize, const NR: usize, const NL: usize, const CURVATURE: bool>(
    shape: &PointShape<NU, NR>,
    input: &PointInput<'_, NR>,
    x: &[Matrix3<f64>; 2],
    variant: AxlVariant,
) -> (SMatrix<f64, NL, 12>, Matrix3<f64>) {
    let jet = input.point_jet;
    let qt = shape.frame.transpose();
    let rt = jet.r.transpose();
    let mut jac_t = SMatrix::<f64, NL, 12>::zeros();
    let qrt = qt * rt;
    // Strain derivatives along the point rotation (the factor M_k is applied per node below).
    let mut de_dp = [[Vector3::zeros(); 3]; 2];
    let mut dg_dp = [[Vector3::zeros(); 3]; 2];
    for i in 0..3 {
        let rit = jet.d1[i].transpose();
        let xi = jet.generators.column(i);
        for gamma in 0..2 {
            // Qᵀ (∂R/∂ω_i)ᵀ F̂_γ = QᵀRᵀ [ξ_i]×ᵀ F̂_γ = QᵀRᵀ (F̂_γ × ξ_i).
            de_dp[gamma][i] = qrt * input.f_hat[gamma].cross(&xi);
            if CURVATURE {
                dg_dp[gamma][i] = qt * axial(&(rit * x[gamma]), variant);
            }
        }
    }
    for k in 0..NR {
        let mk = shape.rot_values[k];
        let nj = input.node_jets[k];
        for i in 0..3 {
            let col = 6 + 3 * k + i;
            // Derivative of axl(Rᵀ R_k) along ω_k,i, shared by both columns γ.
            let dn = if CURVATURE {
                qt * axial(&(rt * nj.d1[i]), variant)
            } else {
                Vector3::zeros()
            };
            for gamma in 0..2 {
                let de = de_dp[gamma][i] * mk;
                let dg = dg_dp[gamma][i] * mk + dn * shape.rot_grad[(gamma, k)];
                for a in 0..3 {
                    jac_t[(col, 3 * gamma + a)] = de[a];
                    if CURVATURE {
                        jac_t[(col, 6 + 3 * gamma + a)] = dg[a];
                    }
                }
            }
        }
    }
    (jac_t, qrt)
}

/// Adds the second-order terms of the bilinear strain maps, weighted by the stress of `st`, to a
/// point's local Hessian (without the nodal rotations' own second derivatives, whose weights are
/// `st.ru`; see [`point_hessian_deferred_into`]).
pub(crate) fn add_second_order_terms<const NU: usize, const NR: usize, const NL: usize>(
    shape: &PointShape<NU, NR>,
    input: &PointInput<'_, NR>,
    st: &Stress<NR>,
    hessian: &mut SMatrix<f64, NL, NL>,
) {
    second_order_terms::<NU, NR, NL, false>(shape, input, st, hessian);
}

/// [`add_second_order_terms`] written into every entry of a point's local Hessian (its `F̂F̂` block,
/// which the bilinear maps do not reach, is zero): the local Hessian of a point whose first-order
/// part is gathered elsewhere (the assumed strains).
pub(crate) fn second_order_terms_into<const NU: usize, const NR: usize, const NL: usize>(
    shape: &PointShape<NU, NR>,
    input: &PointInput<'_, NR>,
    st: &Stress<NR>,
    hessian: &mut SMatrix<f64, NL, NL>,
) {
    hessian.fixed_view_mut::<6, 6>(0, 0).fill(0.0);
    second_order_terms::<NU, NR, NL, true>(shape, input, st, hessian);
}

/// Adds `weight ×` the second-order terms of a point whose stress has no `Γ̂` part
/// ([`Stress::curvature_free`]) to the upper block triangle of an element Hessian `h`, without forming
/// the point's local Hessian: they are the coupling of `F̂` to the point rotation and the point
/// rotation's second derivatives, mapped as [`crate::element::accumulate_upper`] maps the local Hessian
/// of [`second_order_terms_into`] (blocks of the displacements untouched, since its `F̂F̂` block is zero).
pub(crate) fn add_curvature_free_second_order_terms_upper<const NU: usize, const NR: usize, const NE: usize>(
    shape: &PointShape<NU, NR>,
    input: &PointInput<'_, NR>,
    st: &Stress<NR>,
    dt: f64,
    weight: f64,
    h: &mut SMatrix<f64, NE, NE>,
) {
    debug_assert!(st.curvature_free, "a stress without curvature part");
    let jet = input.point_jet;
    // Column i of d1w[γ] is (∂R/∂ω_i) w_γ = ξ_i × R w_γ.
    let d1w = st.w.map(|w| {
        let rw = jet.r * w;
        Matrix3::from_columns(&[0, 1, 2].map(|i| jet.generators.column(i).cross(&rw)))
    });
    let b = &shape.disp_grad;
    let s1 = dt * weight;
    for i in 0..NU {
        let (b0, b1) = (b[(0, i)] * s1, b[(1, i)] * s1);
        for k in 0..NR {
            let mk = shape.rot_values[k];
            let blk = (d1w[0] * mk) * b0 + (d1w[1] * mk) * b1;
            add_block(h, 3 * i, 3 * (NU + k), &blk);
        }
    }
    // ⟨R_ij, Y + Z⟩, symmetric in i, j.
    let hpp = Matrix3::from(jet.second_contraction(&st.yz)).transpose();
    for k in 0..NR {
        for l in k..NR {
            let mkml = shape.rot_values[k] * shape.rot_values[l];
            add_block(h, 3 * (NU + k), 3 * (NU + l), &((hpp * mkml) * weight));
        }
    }
}

/// The second-order terms, added to the blocks of `hessian` they reach or, with `ASSIGN`, written into
/// them (each of their entries receives one term).
#[inline]
fn second_order_terms<const NU: usize, const NR: usize, const NL: usize, const ASSIGN: bool>(
    shape: &PointShape<NU, NR>,
    input: &PointInput<'_, NR>,
    st: &Stress<NR>,
    hessian: &mut SMatrix<f64, NL, NL>,
) {
    let put = |h: &mut SMatrix<f64, NL, NL>, r: usize, c: usize, v: f64| {
        if ASSIGN {
            h[(r, c)] = v;
        } else {
            h[(r, c)] += v;
        }
    };
    let jet = input.point_jet;
    let r = &jet.r;
    // (∂R/∂ω_i) w_γ = ξ_i × R w_γ.
    let rw = [r * st.w[0], r * st.w[1]];
    let mut d1w = [[Vector3::zeros(); 2]; 3];
    for (i, d) in d1w.iter_mut().enumerate() {
        let xi = jet.generators.column(i);
        *d = [xi.cross(&rw[0]), xi.cross(&rw[1])];
    }
    for k in 0..NR {
        let mk = shape.rot_values[k];
        for i in 0..3 {
            let col = 6 + 3 * k + i;
            for gamma in 0..2 {
                let v = d1w[i][gamma] * mk;
                for a in 0..3 {
                    put(hessian, 3 * gamma + a, col, v[a]);
                    put(hessian, col, 3 * gamma + a, v[a]);
                }
            }
        }
    }
    // ⟨R_ij, Y + Z⟩, symmetric in i, j.
    let hpp = jet.second_contraction(&st.yz);
    // A stress without curvature part (at a tying point, whose curvature strains nothing reads) has no
    // nodal rotation weights, so the point rotation couples to the nodal rotations through `hpp` only.
    if st.curvature_free {
        for k in 0..NR {
            for l in 0..NR {
                let mkml = shape.rot_values[k] * shape.rot_values[l];
                for i in 0..3 {
                    for j in 0..3 {
                        put(hessian, 6 + 3 * k + i, 6 + 3 * l + j, mkml * hpp[i][j]);
                    }
                }
            }
        }
        return;
    }
    // cross[k][i][j] = ⟨R_i U_k, R_k,j⟩: point rotation direction i, node k direction j. With
    // R_i = [ξ_i]× R this is ξ_i · m(R_k,j, R U_k).
    let mut cross = [[[0.0; 3]; 3]; NR];
    for k in 0..NR {
        let nj = input.node_jets[k];
        for j in 0..3 {
            let c = jet.generators.tr_mul(&skew_pairing(&nj.d1[j], &st.ru[k]));
            for i in 0..3 {
                cross[k][i][j] = c[i];
            }
        }
    }
    for k in 0..NR {
        let mk = shape.rot_values[k];
        for l in 0..NR {
            let ml = shape.rot_values[l];
            let mkml = mk * ml;
            for i in 0..3 {
                for j in 0..3 {
                    let v = mkml * hpp[i][j] + mk * cross[l][i][j] + ml * cross[k][j][i];
                    put(hessian, 6 + 3 * k + i, 6 + 3 * l + j, v);
                }
            }
        }
    }
}
