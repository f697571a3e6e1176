//! The elastic energy of one stencil, written once over the scalar, and its exact derivatives.
//!
//! The energy of a face is
//!
//! ```text
//! Ψ = Σ_q w_q W_ps(ḡ_q⁻¹ g(ξ_q)),      g(ξ) = a − 2ξ b + ξ² b a⁻¹ b,
//! ```
//!
//! where `a` and `b` are the face's current fundamental forms ([`crate::fundamental_form`]), and
//! `ḡ_q⁻¹` and `w_q` the rest data of its thickness points ([`crate::rest`]). It depends on the 18
//! stencil coordinates only through six strain locals `s = (a₁₁, a₁₂, a₂₂, II₀, II₁, II₂)`:
//! `a` is quadratic in the face's corners and each `IIᵢ` depends on 12 coordinates (the face and `pᵢ`).
//!
//! [`stencil_hessian`] uses this structure: num-dual differentiates the density at each thickness point
//! as a function of the three entries of `g(ξ)` and the one nonlinear map `B = b a⁻¹ b` of the locals,
//! the quadratic `a` is differentiated by hand, each `IIᵢ` is chained through the unit normals it is
//! built from (closed forms in the private module `mid_edge`), and the chain rule gives the exact Hessian
//! `Jᵀ ∇²ψ J + Σₖ ∂ψ/∂sₖ ∇²sₖ`. [`stencil_hessian_oracle`] differentiates the same
//! composed function with one 18-direction second-order dual; the tests compare the two, and the
//! benchmark `kl_benches` measures both.

use crate::fundamental_form::{N_LOCALS, strain_locals, vertex};
use crate::material::{MaterialConstants, plane_stress_density};
use crate::mid_edge::{add_edge_hessian, measure_jet, set_edge_jacobian, unit_normal_jet, weighted_normal_hessian};
use crate::rest::{StencilRest, ThicknessPoint};
use cosserat_assembly::finite::all_finite;
use cosserat_geometry::Real;
use nalgebra::{Matrix2, Matrix3, SMatrix, SVector, Vector3};
use num_dual::{Dual2SVec64, DualSVec64};

/// Number of coordinates of a stencil (6 vertices × 3).
pub const N_STENCIL: usize = 18;

/// Value, gradient and Hessian of a stencil energy with respect to its 18 coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StencilDerivatives {
    /// Energy \[J\].
    pub value: f64,
    /// Gradient \[N\].
    pub gradient: SVector<f64, N_STENCIL>,
    /// Hessian \[N/m\].
    pub hessian: SMatrix<f64, N_STENCIL, N_STENCIL>,
}

impl StencilDerivatives {
    /// All zeros.
    pub fn zeros() -> Self {
        Self {
            value: 0.0,
            gradient: SVector::zeros(),
            hessian: SMatrix::zeros(),
        }
    }

    /// Whether every entry is finite.
    pub fn is_finite(&self) -> bool {
        self.value.is_finite() && all_finite(self.gradient.as_slice()) && all_finite(self.hessian.as_slice())
    }
}

/// `B = b a⁻¹ b` of the strain locals, as its entries `(B₁₁, B₁₂, B₂₂)`.
///
/// Written out in scalars, `B = (b adj(a) b) / det a`: its derivatives are taken with second-order duals
/// at every stencil, and generic 2×2 matrix products of duals spend most of their time copying them.
pub fn bending_product<T: Real>(s: &SVector<T, N_LOCALS>) -> SVector<T, 3> {
    let (a11, a12, a22) = (s[0], s[1], s[2]);
    // b = −[[II₀ + II₁, II₀], [II₀, II₀ + II₂]] (`fundamental_form::second_form`).
    let (b11, b12, b22) = (-(s[3] + s[4]), -s[3], -(s[3] + s[5]));
    let inv_det = (a11 * a22 - a12 * a12).recip();
    // The rows of b adj(a).
    let (r11, r12) = (b11 * a22 - b12 * a12, b12 * a11 - b11 * a12);
    let (r21, r22) = (b12 * a22 - b22 * a12, b22 * a11 - b12 * a12);
    SVector::<T, 3>::new(
        (r11 * b11 + r12 * b12) * inv_det,
        (r11 * b12 + r12 * b22) * inv_det,
        (r21 * b12 + r22 * b22) * inv_det,
    )
}

/// The entries `(g₁₁, g₁₂, g₂₂)` of `g(ξ) = a − 2ξ b + ξ² B` from the locals and `B = b a⁻¹ b`.
fn metric_entries<T: Real>(s: &SVector<T, N_LOCALS>, bab: &SVector<T, 3>, xi: f64) -> SVector<T, 3> {
    // a = (s₀, s₁, s₂) and b = −(s₃ + s₄, s₃, s₃ + s₅) (`fundamental_form::second_form`).
    let b = [-(s[3] + s[4]), -s[3], -(s[3] + s[5])];
    SVector::<T, 3>::from_fn(|k, _| s[k] - b[k] * (2.0 * xi) + bab[k] * (xi * xi))
}

/// The plane-stress density \[J/m³\] at a thickness point, as a function of the entries
/// `(g₁₁, g₁₂, g₂₂)` of the current metric `g(ξ)`: `W_ps(G (g + O))` with the point's inverse metric `G`
/// and metric offset `O` (`W_ps(ḡ⁻¹ g)` for the exact rest volume).
pub fn point_density<T: Real>(g: &SVector<T, 3>, point: &ThicknessPoint, c: &MaterialConstants) -> T {
    // `G (g + O)` with f64 coefficients: scalings instead of dual products.
    let o = &point.metric_offset;
    let gm = [
        [g[0] + o[(0, 0)], g[1] + o[(0, 1)]],
        [g[1] + o[(1, 0)], g[2] + o[(1, 1)]],
    ];
    let gi = &point.inverse_metric;
    let m = Matrix2::from_fn(|r, col| gm[0][col] * gi[(r, 0)] + gm[1][col] * gi[(r, 1)]);
    plane_stress_density(&m, c)
}

/// The energy \[J\] of a face as a function of its strain locals `s` (module docs):
/// `Σ_q w_q` [`point_density`] of `g(ξ_q)`.
///
/// Returns a non-finite value for a degenerate current face (`det a = 0`) or where the neo-Hookean
/// plane-stress condition has no solution.
pub fn local_energy<T: Real>(s: &SVector<T, N_LOCALS>, rest: &StencilRest, c: &MaterialConstants) -> T {
    let bab = bending_product(s);
    let mut total = T::zero();
    for p in rest.points() {
        total += point_density(&metric_entries(s, &bab, p.xi), p, c) * p.weight;
    }
    total
}

/// Value, gradient and (if asked) Hessian of [`local_energy`] with respect to the locals, chained through
/// the three entries of `g(ξ_q)` at each thickness point: `g` is linear in the locals except for
/// `B = b a⁻¹ b`, so `∇²ψ = Σ_q w_q J_qᵀ ∇²W_q J_q + Σₖ cₖ ∇²Bₖ` with `c = Σ_q w_q ξ_q² ∇W_q`.
fn local_derivatives(
    s: &SVector<f64, N_LOCALS>,
    rest: &StencilRest,
    c: &MaterialConstants,
    with_hessian: bool,
) -> (f64, SVector<f64, N_LOCALS>, SMatrix<f64, N_LOCALS, N_LOCALS>) {
    let (bab, jb) = num_dual::jacobian(|s: SVector<DualSVec64<N_LOCALS>, N_LOCALS>| bending_product(&s), s);
    // ∂(a − 2ξ b)/∂s for the entries (11, 12, 22).
    let linear = |xi: f64| {
        let t = 2.0 * xi;
        SMatrix::<f64, 3, N_LOCALS>::from_row_slice(&[
            1.0, 0.0, 0.0, t, t, 0.0, //
            0.0, 1.0, 0.0, t, 0.0, 0.0, //
            0.0, 0.0, 1.0, t, 0.0, t,
        ])
    };
    let mut value = 0.0;
    let mut gradient = SVector::<f64, N_LOCALS>::zeros();
    let mut hessian = SMatrix::<f64, N_LOCALS, N_LOCALS>::zeros();
    let mut weights_b = SVector::<f64, 3>::zeros();
    for p in rest.points() {
        let g = metric_entries(s, &bab, p.xi);
        let (w, gw, hw) = if with_hessian {
            num_dual::hessian(|g: SVector<Dual2SVec64<3>, 3>| point_density(&g, p, c), &g)
        } else {
            let (w, gw) = num_dual::gradient(|g: SVector<DualSVec64<3>, 3>| point_density(&g, p, c), &g);
            (w, gw, SMatrix::zeros())
        };
        let jq = linear(p.xi) + jb * (p.xi * p.xi);
        value += p.weight * w;
        gradient += jq.transpose() * gw * p.weight;
        if with_hessian {
            hessian += jq.transpose() * (hw * p.weight) * jq;
            weights_b += gw * (p.weight * p.xi * p.xi);
        }
    }
    if with_hessian {
        let (_, _, hb) = num_dual::hessian(
            |s: SVector<Dual2SVec64<N_LOCALS>, N_LOCALS>| {
                let m = bending_product(&s);
                m[0] * weights_b[0] + m[1] * weights_b[1] + m[2] * weights_b[2]
            },
            s,
        );
        hessian += hb;
    }
    (value, gradient, hessian)
}

/// The energy \[J\] of a stencil as a function of its 18 coordinates: [`local_energy`] of
/// [`strain_locals`]. This is the single definition every derivative path differentiates.
pub fn stencil_energy<T: Real>(x: &SVector<T, N_STENCIL>, rest: &StencilRest, c: &MaterialConstants) -> T {
    local_energy(&strain_locals(x, rest.present()), rest, c)
}

/// The coordinates an edge's measure depends on: the face's three corners and the vertex across the
/// edge, 12 of the stencil's 18.
const N_EDGE: usize = 12;

/// What the chain rule needs of one mid-edge measure `IIᵢ = φ(yᵢ)`, `yᵢ = (vᵢ, n_f, n_gᵢ)`.
struct EdgeJet {
    /// `∂yᵢ/∂x` (9 × 12) with respect to the coordinates of `(q₀, q₁, q₂, pᵢ)`.
    y_jac: SMatrix<f64, 9, N_EDGE>,
    /// The stencil vertex of each block of three columns of `y_jac`.
    slots: [usize; 4],
    /// `∇φ(yᵢ)`.
    g_phi: SVector<f64, 9>,
    /// `∇²φ(yᵢ)` (zero when only gradients are wanted).
    h_phi: SMatrix<f64, 9, 9>,
    /// The neighbour's edge vectors `(qⱼ − qₖ, pᵢ − qₖ)` and their vertices `(qₖ, qⱼ, pᵢ)`.
    f: (Vector3<f64>, Vector3<f64>),
    verts: [usize; 3],
}

/// The strain locals, their Jacobian, and the per-edge data of the mid-edge measures.
fn strain_jets(
    x: &SVector<f64, N_STENCIL>,
    present: [bool; 3],
    with_hessian: bool,
) -> (
    SVector<f64, N_LOCALS>,
    SMatrix<f64, N_LOCALS, N_STENCIL>,
    [Option<EdgeJet>; 3],
) {
    let q = [vertex(x, 0), vertex(x, 1), vertex(x, 2)];
    let mut s = strain_locals(x, [false; 3]);
    let mut jac = SMatrix::<f64, N_LOCALS, N_STENCIL>::zeros();
    first_form_jacobian(x, &mut jac);
    let face = unit_normal_jet(&(q[1] - q[0]), &(q[2] - q[0]));
    let mut edges = [None, None, None];
    for i in (0..3).filter(|&i| present[i]) {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        let p = vertex(x, 3 + i);
        let f = (q[j] - q[k], p - q[k]);
        let neighbour = unit_normal_jet(&f.0, &f.1);
        let v = q[j] + q[k] - q[i] * 2.0;
        let y = SVector::<f64, 9>::from_fn(|r, _| match r / 3 {
            0 => v[r % 3],
            1 => face.n[r % 3],
            _ => neighbour.n[r % 3],
        });
        let (phi, g_phi, h_phi) = measure_jet(&y, with_hessian);
        // Columns: q₀, q₁, q₂ in their stencil order, then pᵢ in the fourth block.
        let slots = [0, 1, 2, 3 + i];
        let mut y_jac = SMatrix::<f64, 9, N_EDGE>::zeros();
        for c in 0..3 {
            y_jac[(c, 3 * i + c)] = -2.0;
            y_jac[(c, 3 * j + c)] = 1.0;
            y_jac[(c, 3 * k + c)] = 1.0;
        }
        set_edge_jacobian(&mut y_jac, 3, [0, 1, 2], &face.jac);
        set_edge_jacobian(&mut y_jac, 6, [k, j, 3], &neighbour.jac);
        s[3 + i] = phi;
        let row = y_jac.transpose() * g_phi;
        for (slot, &v) in slots.iter().enumerate() {
            for c in 0..3 {
                jac[(3 + i, 3 * v + c)] = row[3 * slot + c];
            }
        }
        let verts = [k, j, 3 + i];
        edges[i] = Some(EdgeJet {
            y_jac,
            slots,
            g_phi,
            h_phi,
            f,
            verts,
        });
    }
    (s, jac, edges)
}

/// The Jacobian rows of `(a₁₁, a₁₂, a₂₂)` with respect to the stencil coordinates.
fn first_form_jacobian(x: &SVector<f64, N_STENCIL>, jac: &mut SMatrix<f64, N_LOCALS, N_STENCIL>) {
    let q0 = vertex(x, 0);
    let e1 = vertex(x, 1) - q0;
    let e2 = vertex(x, 2) - q0;
    let rows: [[Vector3<f64>; 3]; 3] = [
        [-e1 * 2.0, e1 * 2.0, Vector3::zeros()],
        [-(e1 + e2), e2, e1],
        [-e2 * 2.0, Vector3::zeros(), e2 * 2.0],
    ];
    for (k, row) in rows.iter().enumerate() {
        for (v, d) in row.iter().enumerate() {
            for c in 0..3 {
                jac[(k, 3 * v + c)] = d[c];
            }
        }
    }
}

/// The energy and its gradient: a first-order dual on the density, the mid-edge measures chained
/// through their unit normals.
pub fn stencil_gradient(
    x: &SVector<f64, N_STENCIL>,
    rest: &StencilRest,
    c: &MaterialConstants,
) -> (f64, SVector<f64, N_STENCIL>) {
    let (s, jac, _) = strain_jets(x, rest.present(), false);
    let (value, gs, _) = local_derivatives(&s, rest, c, false);
    (value, jac.transpose() * gs)
}

/// The energy, gradient and exact Hessian by the chain rule through the strain locals (module docs).
pub fn stencil_hessian(x: &SVector<f64, N_STENCIL>, rest: &StencilRest, c: &MaterialConstants) -> StencilDerivatives {
    let (s, jac, edges) = strain_jets(x, rest.present(), true);
    let (value, gs, hs) = local_derivatives(&s, rest, c, true);
    let gradient = jac.transpose() * gs;
    let mut hessian = jac.transpose() * (hs * jac);
    // Σₖ ∂ψ/∂aₖ ∇²aₖ = Pᵀ (2G) P ⊗ I₃ on the corners, with eₐ = Σ P_αk q_k and G = [[ψ₁₁, ψ₁₂/2], [ψ₁₂/2, ψ₂₂]].
    let p = SMatrix::<f64, 2, 3>::new(-1.0, 1.0, 0.0, -1.0, 0.0, 1.0);
    let g2 = Matrix2::new(2.0 * gs[0], gs[1], gs[1], 2.0 * gs[2]);
    let k: Matrix3<f64> = p.transpose() * g2 * p;
    for r in 0..3 {
        for col in 0..3 {
            for d in 0..3 {
                hessian[(3 * r + d, 3 * col + d)] += k[(r, col)];
            }
        }
    }
    // Σᵢ ∂ψ/∂IIᵢ ∇²IIᵢ, with ∇²IIᵢ = Jᵀ ∇²φ J + Σ ∂φ/∂n ∇²n over the face and neighbour normals.
    let mut face_weights = Vector3::zeros();
    for (i, edge) in edges.iter().enumerate() {
        let Some(e) = edge else { continue };
        let w = gs[3 + i];
        let local = e.y_jac.transpose() * ((e.h_phi * w) * e.y_jac);
        for (r, &vr) in e.slots.iter().enumerate() {
            for (col, &vc) in e.slots.iter().enumerate() {
                let mut target = hessian.fixed_view_mut::<3, 3>(3 * vr, 3 * vc);
                target += local.fixed_view::<3, 3>(3 * r, 3 * col);
            }
        }
        face_weights += e.g_phi.fixed_rows::<3>(3) * w;
        let c_neighbour: Vector3<f64> = e.g_phi.fixed_rows::<3>(6) * w;
        add_edge_hessian(
            &mut hessian,
            e.verts,
            &weighted_normal_hessian(&e.f.0, &e.f.1, &c_neighbour),
        );
    }
    if face_weights != Vector3::zeros() {
        let (q0, q1, q2) = (vertex(x, 0), vertex(x, 1), vertex(x, 2));
        add_edge_hessian(
            &mut hessian,
            [0, 1, 2],
            &weighted_normal_hessian(&(q1 - q0), &(q2 - q0), &face_weights),
        );
    }
    StencilDerivatives {
        value,
        gradient,
        hessian,
    }
}

/// The energy, gradient and Hessian from one 18-direction second-order dual pass through
/// [`stencil_energy`]: the test oracle for [`stencil_hessian`] (tens of times slower).
pub fn stencil_hessian_oracle(
    x: &SVector<f64, N_STENCIL>,
    rest: &StencilRest,
    c: &MaterialConstants,
) -> StencilDerivatives {
    let (value, gradient, hessian) = num_dual::hessian(
        |v: SVector<Dual2SVec64<N_STENCIL>, N_STENCIL>| stencil_energy(&v, rest, c),
        x,
    );
    StencilDerivatives {
        value,
        gradient,
        hessian,
    }
}
