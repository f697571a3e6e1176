//! The discrete first and second fundamental forms of a face, generic over the scalar.
//!
//! Each face is parametrised affinely over the reference triangle with tangents `e₁ = q₁ − q₀` and
//! `e₂ = q₂ − q₀`, so its first fundamental form is `a = [eₐ · e_β]`.
//!
//! The second fundamental form uses mid-edge normals (Grinspun et al. 2006; Chen et al. 2018; Wen &
//! Barbič 2023): a normal field that is linear on the face with the values `mᵢ` at the edge midpoints
//! (the Crouzeix–Raviart interpolant `n = Σ (1 − 2λᵢ) mᵢ`). With `b = −∇n` (the sign convention of this
//! workspace, docs/model-notes.md) and the orthogonality of each `mᵢ` to its edge, this gives
//!
//! ```text
//! b = −[ II₀ + II₁   II₀       ]      IIᵢ = (qᵢ₊₁ + qᵢ₊₂ − 2 qᵢ) · mᵢ ,
//!      [ II₀         II₀ + II₂ ]
//! ```
//!
//! a symmetric form that is invariant under rigid motions. The mid-edge normal of an interior edge is
//! the bisector of the two unit face normals, `mᵢ = (n_f + n_g) / |n_f + n_g|`, with the neighbour's
//! normal oriented like the face's (so the formula also holds on non-orientable meshes). Since
//! `qᵢ₊₁ + qᵢ₊₂ − 2qᵢ` lies in the face plane, `IIᵢ = (qᵢ₊₁ + qᵢ₊₂ − 2qᵢ) · n_g / √(2 + 2 n_f · n_g)`.
//!
//! Boundary edges take the face normal as their mid-edge normal, so `IIᵢ = 0`: the face measures no
//! bending across a boundary edge. This is the natural free-edge rule of the mid-edge average
//! formulation (zero bending moment across the edge for `ν = 0`; for `ν ≠ 0` the free edge carries a
//! boundary layer of one element). Clamped edges are modelled by fixing two rows of vertices.

use cosserat_geometry::Real;
use cosserat_geometry::real::cst;
use nalgebra::{Matrix2, SVector, Vector3};

/// Number of strain locals of a face: `(a₁₁, a₁₂, a₂₂, II₀, II₁, II₂)`.
pub const N_LOCALS: usize = 6;

/// Vertex `k` of a stencil's coordinate vector.
#[inline]
pub fn vertex<T: Real>(x: &SVector<T, 18>, k: usize) -> Vector3<T> {
    Vector3::new(x[3 * k], x[3 * k + 1], x[3 * k + 2])
}

/// `(a₁₁, a₁₂, a₂₂)` of the face with corners `q`.
pub fn first_form_entries<T: Real>(q: &[Vector3<T>; 3]) -> [T; 3] {
    let e1 = q[1] - q[0];
    let e2 = q[2] - q[0];
    [e1.dot(&e1), e1.dot(&e2), e2.dot(&e2)]
}

/// The mid-edge bending measure `IIᵢ = (qⱼ + qₖ − 2qᵢ) · mᵢ` of the edge `(qⱼ, qₖ)` opposite `qᵢ`, where
/// `(qᵢ, qⱼ, qₖ)` is the face in cyclic mesh order and `p` the vertex across the edge (module docs).
pub fn mid_edge_measure<T: Real>(qi: &Vector3<T>, qj: &Vector3<T>, qk: &Vector3<T>, p: &Vector3<T>) -> T {
    let v = qj + qk - qi * cst::<T>(2.0);
    let nf = (qj - qi).cross(&(qk - qi));
    // The neighbour (qₖ, qⱼ, p) traverses the shared edge backwards, like a consistently oriented face.
    let ng = (qj - qk).cross(&(p - qk));
    let nf = nf / nf.norm();
    let ng = ng / ng.norm();
    v.dot(&ng) / ((nf.dot(&ng) + T::one()) * 2.0).sqrt()
}

/// The strain locals `(a₁₁, a₁₂, a₂₂, II₀, II₁, II₂)` of a stencil (`IIᵢ = 0` on boundary edges).
pub fn strain_locals<T: Real>(x: &SVector<T, 18>, present: [bool; 3]) -> SVector<T, N_LOCALS> {
    let q = [vertex(x, 0), vertex(x, 1), vertex(x, 2)];
    let [a11, a12, a22] = first_form_entries(&q);
    let ii = |i: usize| {
        if present[i] {
            mid_edge_measure(&q[i], &q[(i + 1) % 3], &q[(i + 2) % 3], &vertex(x, 3 + i))
        } else {
            T::zero()
        }
    };
    SVector::<T, N_LOCALS>::from([a11, a12, a22, ii(0), ii(1), ii(2)])
}

/// The first fundamental form `a` from the locals.
#[inline]
pub fn first_form<T: Real>(s: &SVector<T, N_LOCALS>) -> Matrix2<T> {
    Matrix2::new(s[0], s[1], s[1], s[2])
}

/// The second fundamental form `b = −[[II₀ + II₁, II₀], [II₀, II₀ + II₂]]` from the locals.
#[inline]
pub fn second_form<T: Real>(s: &SVector<T, N_LOCALS>) -> Matrix2<T> {
    -Matrix2::new(s[3] + s[4], s[3], s[3], s[3] + s[5])
}

/// The inverse of a 2×2 matrix by its adjugate (no pivoting: the metrics here are positive definite).
#[inline]
pub fn inverse2<T: Real>(m: &Matrix2<T>) -> Matrix2<T> {
    let det = m[(0, 0)] * m[(1, 1)] - m[(0, 1)] * m[(1, 0)];
    Matrix2::new(m[(1, 1)], -m[(0, 1)], -m[(1, 0)], m[(0, 0)]) / det
}

/// The metric `g(ξ) = a − 2ξ b + ξ² b a⁻¹ b` of the surface shifted by `ξ` along the normal.
#[inline]
pub fn shifted_metric<T: Real>(a: &Matrix2<T>, b: &Matrix2<T>, b_ainv_b: &Matrix2<T>, xi: f64) -> Matrix2<T> {
    a - b.map(|v| v * (2.0 * xi)) + b_ainv_b.map(|v| v * (xi * xi))
}
