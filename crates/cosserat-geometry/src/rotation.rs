//! Rotations: unit quaternions, rotation matrices, `axl`/`skew`, exponential and Cayley maps, and the
//! quaternion time update of the model.
//!
//! Conventions (model.md §0, §1.5):
//! - Quaternions are nalgebra [`Quaternion`]s built with `Quaternion::new(w, x, y, z)`, scalar first.
//! - Angular velocities are *spatial* (world-frame): `Ṙ = [ω]× R`, so updates multiply from the left.
//! - `axl` is the standard axial vector: `axl([θ]×) = θ` and `[θ]× y = θ × y`.
//!
//! All functions are generic over [`Real`] so that they can be differentiated with dual numbers.
//! [`RotationJet`] does exactly that for the update map `ω ↦ R(Φ(q, ω, Δt))`, the only nonlinearity of
//! the rotation field inside the energy.

use crate::real::Real;
use nalgebra::{Const, Matrix3, Quaternion, SVector, Vector3};
use num_dual::{Derivative, Dual2SVec64};

/// The rotation matrix of a unit quaternion (scalar first).
///
/// This is the standard polynomial formula; it does **not** normalise, so `q` must be a unit
/// quaternion for the result to be orthogonal.
#[inline]
pub fn rotation_matrix<T: Real>(q: &Quaternion<T>) -> Matrix3<T> {
    let (w, x, y, z) = (q.w, q.i, q.j, q.k);
    let one = T::one();
    let two = T::from(2.0);
    Matrix3::new(
        one - two * (y * y + z * z),
        two * (x * y - w * z),
        two * (x * z + w * y),
        two * (x * y + w * z),
        one - two * (x * x + z * z),
        two * (y * z - w * x),
        two * (x * z - w * y),
        two * (y * z + w * x),
        one - two * (x * x + y * y),
    )
}

/// The unit quaternion (with non-negative scalar part) of a rotation matrix.
///
/// Uses Shepperd's method, which picks the numerically largest component first. The input must be a
/// rotation matrix (orthogonal, determinant +1); no projection is done.
pub fn quaternion_from_matrix(m: &Matrix3<f64>) -> Quaternion<f64> {
    let tr = m.trace();
    let q = if tr > 0.0 {
        let s = (tr + 1.0).sqrt() * 2.0;
        Quaternion::new(
            0.25 * s,
            (m[(2, 1)] - m[(1, 2)]) / s,
            (m[(0, 2)] - m[(2, 0)]) / s,
            (m[(1, 0)] - m[(0, 1)]) / s,
        )
    } else if m[(0, 0)] > m[(1, 1)] && m[(0, 0)] > m[(2, 2)] {
        let s = (1.0 + m[(0, 0)] - m[(1, 1)] - m[(2, 2)]).sqrt() * 2.0;
        Quaternion::new(
            (m[(2, 1)] - m[(1, 2)]) / s,
            0.25 * s,
            (m[(0, 1)] + m[(1, 0)]) / s,
            (m[(0, 2)] + m[(2, 0)]) / s,
        )
    } else if m[(1, 1)] > m[(2, 2)] {
        let s = (1.0 + m[(1, 1)] - m[(0, 0)] - m[(2, 2)]).sqrt() * 2.0;
        Quaternion::new(
            (m[(0, 2)] - m[(2, 0)]) / s,
            (m[(0, 1)] + m[(1, 0)]) / s,
            0.25 * s,
            (m[(1, 2)] + m[(2, 1)]) / s,
        )
    } else {
        let s = (1.0 + m[(2, 2)] - m[(0, 0)] - m[(1, 1)]).sqrt() * 2.0;
        Quaternion::new(
            (m[(1, 0)] - m[(0, 1)]) / s,
            (m[(0, 2)] + m[(2, 0)]) / s,
            (m[(1, 2)] + m[(2, 1)]) / s,
            0.25 * s,
        )
    };
    let q = q.normalize();
    if q.w < 0.0 { -q } else { q }
}

/// The cross-product matrix `\[v\]×`, with `\[v\]× y = v × y`.
#[inline]
pub fn skew<T: Real>(v: &Vector3<T>) -> Matrix3<T> {
    let z = T::zero();
    Matrix3::new(z, -v.z, v.y, v.z, z, -v.x, -v.y, v.x, z)
}

/// The standard axial vector of the skew-symmetric part of `m`: `axl(skew m)`.
///
/// For a skew matrix `[θ]×` it returns `θ`. For a general matrix it is
/// `½ (m₃₂ − m₂₃, m₁₃ − m₃₁, m₂₁ − m₁₂)` (1-based).
#[inline]
pub fn axl<T: Real>(m: &Matrix3<T>) -> Vector3<T> {
    let h = T::from(0.5);
    Vector3::new(
        (m[(2, 1)] - m[(1, 2)]) * h,
        (m[(0, 2)] - m[(2, 0)]) * h,
        (m[(1, 0)] - m[(0, 1)]) * h,
    )
}

/// The axial vector read from the negated upper triangle, `(−m₂₃, −m₃₁, −m₁₂)` (1-based).
///
/// This is the variant of the authors' reference code (model.md §2.3). It agrees with [`axl`] on skew
/// matrices and differs by the non-skewness of `m` otherwise.
#[inline]
pub fn axl_upper<T: Real>(m: &Matrix3<T>) -> Vector3<T> {
    Vector3::new(-m[(1, 2)], -m[(2, 0)], -m[(0, 1)])
}

/// The rotation `exp(\[v\]×)` by the angle `|v|` about `v/|v|` (Rodrigues' formula).
///
/// Near `v = 0` the coefficients switch to their Taylor series, so the map and its dual-number
/// derivatives stay exact there. Above the switch, `(1 − cos θ)/θ²` is evaluated as
/// `2 (sin(θ/2)/θ)²`: the form `1 − cos θ` would carry an absolute rounding error of `ε` into a
/// quantity of size `θ²`, which leaves the value accurate but costs the dual-number derivatives about
/// `ε/θ²` (second derivatives off by ~5e-9 just above the switch).
pub fn exp_map<T: Real>(v: &Vector3<T>) -> Matrix3<T> {
    let theta2 = v.norm_squared();
    let (a, b) = if theta2.re() < 1e-8 {
        // sin θ / θ and (1 − cos θ) / θ² to O(θ⁴).
        (
            T::one() - theta2 / 6.0 + theta2 * theta2 / 120.0,
            T::from(0.5) - theta2 / 24.0 + theta2 * theta2 / 720.0,
        )
    } else {
        let theta = theta2.sqrt();
        let half = (theta * 0.5).sin() / theta;
        (theta.sin() / theta, half * half * 2.0)
    };
    let k = skew(v);
    Matrix3::identity() + k * a + k * k * b
}

/// The Cayley map `cay(v) = (I − \[v\]×/2)⁻¹ (I + \[v\]×/2)`: a rotation by `2 arctan(|v|/2)` about `v`.
///
/// The quaternion update of the model is exactly `R(Φ(q, ω, Δt)) = cay(Δt ω) R(q)` (model.md §1.5).
pub fn cayley<T: Real>(v: &Vector3<T>) -> Matrix3<T> {
    let s = T::from(4.0) / (T::from(4.0) + v.norm_squared());
    let k = skew(v);
    Matrix3::identity() + (k + k * k * T::from(0.5)) * s
}

/// The Hamilton product `p ⊗ q` of quaternions.
#[inline]
pub fn quaternion_product<T: Real>(p: &Quaternion<T>, q: &Quaternion<T>) -> Quaternion<T> {
    Quaternion::new(
        p.w * q.w - p.i * q.i - p.j * q.j - p.k * q.k,
        p.w * q.i + p.i * q.w + p.j * q.k - p.k * q.j,
        p.w * q.j - p.i * q.k + p.j * q.w + p.k * q.i,
        p.w * q.k + p.i * q.j - p.j * q.i + p.k * q.w,
    )
}

/// The time update of a unit quaternion by a spatial angular velocity (model.md §1.5):
///
/// `Φ(q, ω, Δt) = (q + Δt/2 ω̂ ⊗ q) / |q + Δt/2 ω̂ ⊗ q|`, with `ω̂ = (0, ω)`.
///
/// The quaternion `q` is data (`f64`); only `ω` carries the scalar type, because in the energy the
/// angular velocity is the unknown. The result is a unit quaternion for any `ω`.
#[inline]
pub fn quaternion_update<T: Real>(q: &Quaternion<f64>, omega: &Vector3<T>, dt: f64) -> Quaternion<T> {
    let h = dt * 0.5;
    let (w, x, y, z) = (q.w, q.i, q.j, q.k);
    let (ox, oy, oz) = (omega.x * h, omega.y * h, omega.z * h);
    // (0, o) ⊗ (w, x, y, z) with o = Δt ω / 2.
    let nw = -(ox * x + oy * y + oz * z) + w;
    let nx = ox * w + oy * z - oz * y + x;
    let ny = -(ox * z) + oy * w + oz * x + y;
    let nz = ox * y - oy * x + oz * w + z;
    let inv = (nw * nw + nx * nx + ny * ny + nz * nz).sqrt().recip();
    Quaternion::new(nw * inv, nx * inv, ny * inv, nz * inv)
}

/// The same rotation as `q`, with the sign chosen so that `q · reference ≥ 0`.
///
/// `q` and `−q` are one rotation. Linear interpolation of quaternions needs neighbours in the same
/// hemisphere (model.md §8.12); this is the guard.
#[inline]
pub fn same_hemisphere(q: &Quaternion<f64>, reference: &Quaternion<f64>) -> Quaternion<f64> {
    if q.dot(reference) < 0.0 { -q } else { *q }
}

/// `E_i M` with `E_i = [e_i]×`: the cross product of the unit vector `e_i` with each column of `M`.
#[inline(always)]
fn unit_cross(i: usize, m: &Matrix3<f64>) -> Matrix3<f64> {
    let mut out = Matrix3::zeros();
    let (a, b) = ((i + 1) % 3, (i + 2) % 3);
    for c in 0..3 {
        out[(b, c)] = m[(a, c)];
        out[(a, c)] = -m[(b, c)];
    }
    out
}

/// `E_i E_j + E_j E_i = e_j e_iᵀ + e_i e_jᵀ − 2 δ_ij I` for the unit skew matrices `E_i = [e_i]×`.
#[inline(always)]
fn unit_anticommutator(i: usize, j: usize) -> Matrix3<f64> {
    let mut out = Matrix3::zeros();
    out[(j, i)] += 1.0;
    out[(i, j)] += 1.0;
    if i == j {
        out -= Matrix3::identity() * 2.0;
    }
    out
}

/// The value and the first and second derivatives of `ω ↦ R(Φ(q, ω, Δt))` at one `ω`.
///
/// This is where the nonlinearity of a rotation sits inside the energy. Computing its derivatives in
/// closed form and chaining everything else (bilinear strain maps and a quadratic density) by hand gives
/// the exact Hessian at a fraction of the cost of differentiating the whole energy (see
/// `docs/performance.md`).
///
/// The second derivatives are kept in factored form. The kernels never need the nine matrices
/// `∂²R/∂ω_i∂ω_j` themselves, only their inner products with one matrix `W`
/// ([`RotationJet::second_contraction`]): one matrix product and four inner products, where forming
/// the matrices takes nine products.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RotationJet {
    /// `R`.
    pub r: Matrix3<f64>,
    /// `∂R/∂ω_i` for `i = 0, 1, 2`.
    pub d1: [Matrix3<f64>; 3],
    /// `Ξ = Δt s (I + ½ [v]×)`, whose columns `ξ_i` are the spatial angular velocities of the first
    /// derivatives: `∂R/∂ω_i = [ξ_i]× R`. Kernels contract with `ξ_i` where a product with `∂R/∂ω_i`
    /// would cost a matrix product.
    pub generators: Matrix3<f64>,
    second: SecondFactors,
}

/// The factors of `∂²R/∂ω_i∂ω_j = Δt² (a s_ij + B_j s_i + B_i s_j + ½ s (E_i E_j + E_j E_i)) R(q)` with
/// `a = [v]× + ½ [v]×²`, `B_i = ∂a/∂v_i`, `s_i = ∂s/∂v_i` and `s_ij = ∂²s/∂v_i∂v_j` (see
/// [`RotationJet::of_update`]).
#[derive(Debug, Clone, Copy, PartialEq)]
struct SecondFactors {
    /// `R(q)`, the rotation at the start of the step.
    r0: Matrix3<f64>,
    a: Matrix3<f64>,
    b: [Matrix3<f64>; 3],
    /// `s_i`.
    ds: [f64; 3],
    /// `s_ij`.
    dds: [[f64; 3]; 3],
    /// `½ s`.
    half_s: f64,
    /// `Δt²`; zero for a constant jet.
    dt2: f64,
}

impl RotationJet {
    /// Evaluates the jet of `ω ↦ R(Φ(q, ω, Δt))` in closed form.
    ///
    /// Uses `R(Φ(q, ω, Δt)) = cay(v) R(q)` with `v = Δt ω` and
    /// `cay(v) = I + s (\[v\]× + ½ \[v\]×²)`, `s = 4/(4 + |v|²)`, whose first and second derivatives are
    /// short matrix polynomials. Agrees with [`RotationJet::of_update_dual`] (num-dual through the
    /// quaternion update) to round-off and costs a fraction of it.
    #[inline]
    pub fn of_update(q: &Quaternion<f64>, omega: &Vector3<f64>, dt: f64) -> Self {
        let r0 = rotation_matrix(q);
        let v = omega * dt;
        let s = 4.0 / (4.0 + v.norm_squared());
        let k = skew(&v);
        let k2 = k * k;
        let a = k + k2 * 0.5;
        let e = [skew(&Vector3::x()), skew(&Vector3::y()), skew(&Vector3::z())];
        // B_i = ∂a/∂v_i = E_i + ½ (E_i K + K E_i), with K E_i = (E_i K)ᵀ for skew K and E_i. The products
        // with the unit skew matrices E_i only move and negate entries, so they are formed without
        // multiplications (and exactly, as the matrix products were).
        let mut b = [Matrix3::zeros(); 3];
        for i in 0..3 {
            let ek = unit_cross(i, &k);
            b[i] = e[i] + (ek + ek.transpose()) * 0.5;
        }
        // ∂s/∂v_i = −s²/2 v_i; ∂²s/∂v_i∂v_j = −s²/2 δ_ij + s³/2 v_i v_j.
        let ds = [-0.5 * s * s * v[0], -0.5 * s * s * v[1], -0.5 * s * s * v[2]];
        // Explicit loops rather than `array::from_fn`, whose closures were not inlined in this hot path.
        let mut dds = [[0.0; 3]; 3];
        let mut d1 = [Matrix3::zeros(); 3];
        for i in 0..3 {
            for j in 0..3 {
                dds[i][j] = 0.5 * s * s * s * v[i] * v[j] - if i == j { 0.5 * s * s } else { 0.0 };
            }
            d1[i] = (a * ds[i] + b[i] * s) * r0 * dt;
        }
        Self {
            r: (Matrix3::identity() + a * s) * r0,
            d1,
            // ∂cay/∂v_i cayᵀ = [s (I + ½ [v]×) e_i]× (the right-trivialised derivative of the Cayley map).
            generators: (Matrix3::identity() + k * 0.5) * (dt * s),
            second: SecondFactors {
                r0,
                a,
                b,
                ds,
                dds,
                half_s: 0.5 * s,
                dt2: dt * dt,
            },
        }
    }

    /// `∂²R/∂ω_i∂ω_j` (symmetric in `i, j`), formed from the factors.
    ///
    /// For tests and for callers that need the matrices; the kernels use
    /// [`RotationJet::second_contraction`].
    pub fn second_derivative(&self, i: usize, j: usize) -> Matrix3<f64> {
        let f = &self.second;
        (f.a * f.dds[i][j] + f.b[j] * f.ds[i] + f.b[i] * f.ds[j] + unit_anticommutator(i, j) * f.half_s) * f.r0 * f.dt2
    }

    /// The inner products `⟨∂²R/∂ω_i∂ω_j, W⟩` for all `i, j` (a symmetric 3 × 3 array).
    ///
    /// With `M_ij` the matrix polynomial of the factors, `⟨M_ij R(q), W⟩ = ⟨M_ij, W R(q)ᵀ⟩`: one matrix
    /// product and four inner products instead of nine matrix products.
    #[inline]
    pub fn second_contraction(&self, w: &Matrix3<f64>) -> [[f64; 3]; 3] {
        let f = &self.second;
        let z = w * f.r0.transpose();
        let za = f.a.component_mul(&z).sum();
        let zb = [
            f.b[0].component_mul(&z).sum(),
            f.b[1].component_mul(&z).sum(),
            f.b[2].component_mul(&z).sum(),
        ];
        let trace = z.trace();
        let mut c = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in i..3 {
                // ⟨E_i E_j + E_j E_i, Z⟩ = Z_ij + Z_ji − 2 δ_ij tr Z (see `unit_anticommutator`).
                let anti = z[(i, j)] + z[(j, i)] - if i == j { 2.0 * trace } else { 0.0 };
                let x = f.dt2 * (f.dds[i][j] * za + f.ds[i] * zb[j] + f.ds[j] * zb[i] + f.half_s * anti);
                c[i][j] = x;
                c[j][i] = x;
            }
        }
        c
    }

    /// The same jet as [`RotationJet::of_update`] with every derivative formed as a matrix, computed
    /// with a three-direction second-order dual number through [`quaternion_update`] and
    /// [`rotation_matrix`] (the reference for tests).
    pub fn of_update_dual(q: &Quaternion<f64>, omega: &Vector3<f64>, dt: f64) -> DenseRotationJet {
        type D = Dual2SVec64<3>;
        let w: Vector3<D> = Vector3::from_fn(|i, _| {
            let mut d = D::from_re(omega[i]);
            d.v1 = Derivative::some(SVector::<f64, 3>::ith(i, 1.0).transpose());
            d
        });
        let rd = rotation_matrix(&quaternion_update(q, &w, dt));
        DenseRotationJet::from_dual_matrix(&rd)
    }

    /// The jet of a constant rotation (all derivatives zero).
    pub fn constant(r: Matrix3<f64>) -> Self {
        Self {
            r,
            d1: [Matrix3::zeros(); 3],
            generators: Matrix3::zeros(),
            second: SecondFactors {
                r0: r,
                a: Matrix3::zeros(),
                b: [Matrix3::zeros(); 3],
                ds: [0.0; 3],
                dds: [[0.0; 3]; 3],
                half_s: 0.0,
                dt2: 0.0,
            },
        }
    }

    /// Every derivative as a matrix (the six distinct second derivatives formed once, the other three
    /// copied).
    pub fn dense(&self) -> DenseRotationJet {
        let mut d2 = [[Matrix3::zeros(); 3]; 3];
        for i in 0..3 {
            for j in i..3 {
                d2[i][j] = self.second_derivative(i, j);
                d2[j][i] = d2[i][j];
            }
        }
        DenseRotationJet {
            r: self.r,
            d1: self.d1,
            d2,
        }
    }
}

/// A rotation jet with its second derivatives formed as matrices: the form of the dual-number
/// reference, and of [`RotationJet::dense`] for tests and for callers that want the matrices.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DenseRotationJet {
    /// `R`.
    pub r: Matrix3<f64>,
    /// `∂R/∂ω_i`.
    pub d1: [Matrix3<f64>; 3],
    /// `∂²R/∂ω_i∂ω_j`.
    pub d2: [[Matrix3<f64>; 3]; 3],
}

impl DenseRotationJet {
    fn from_dual_matrix(rd: &Matrix3<Dual2SVec64<3>>) -> Self {
        let mut jet = Self {
            r: rd.map(|x| x.re),
            d1: [Matrix3::zeros(); 3],
            d2: [[Matrix3::zeros(); 3]; 3],
        };
        for (idx, x) in rd.iter().enumerate() {
            let (row, col) = (idx % 3, idx / 3);
            let g = x.v1.unwrap_generic(Const::<1>, Const::<3>);
            let h = x.v2.unwrap_generic(Const::<3>, Const::<3>);
            for i in 0..3 {
                jet.d1[i][(row, col)] = g[i];
                for j in 0..3 {
                    jet.d2[i][j][(row, col)] = h[(i, j)];
                }
            }
        }
        jet
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closed_form_jet_matches_the_dual_jet() {
        let q = Quaternion::new(0.8, -0.3, 0.4, 0.1).normalize();
        for (omega, dt) in [
            (Vector3::new(0.3, -2.0, 1.1), 0.05),
            (Vector3::zeros(), 0.01),
            (Vector3::new(1.0, 2.0, -3.0), 1.0),
        ] {
            let a = RotationJet::of_update(&q, &omega, dt).dense();
            let b = RotationJet::of_update_dual(&q, &omega, dt);
            assert!((a.r - b.r).amax() < 1e-14);
            for i in 0..3 {
                assert!((a.d1[i] - b.d1[i]).amax() < 1e-14 * (1.0 + dt), "d1 {i}");
                for j in 0..3 {
                    assert!((a.d2[i][j] - b.d2[i][j]).amax() < 1e-14 * (1.0 + dt * dt), "d2 {i} {j}");
                }
            }
        }
    }

    #[test]
    fn second_contraction_is_the_inner_product_with_the_second_derivatives() {
        let q = Quaternion::new(0.3, 0.5, -0.7, 0.2).normalize();
        let w = Matrix3::new(0.4, -1.3, 2.2, 0.7, 0.05, -0.9, 1.6, -0.2, 0.8);
        for (omega, dt) in [(Vector3::new(-1.2, 0.4, 2.5), 0.1), (Vector3::zeros(), 0.5)] {
            let jet = RotationJet::of_update(&q, &omega, dt);
            let c = jet.second_contraction(&w);
            let scale = w.amax() * dt * dt;
            for i in 0..3 {
                for j in 0..3 {
                    let expected = jet.second_derivative(i, j).component_mul(&w).sum();
                    assert!((c[i][j] - expected).abs() < 1e-14 * scale, "({i}, {j})");
                }
            }
        }
        let constant = RotationJet::constant(rotation_matrix(&q));
        assert_eq!(constant.second_contraction(&w), [[0.0; 3]; 3]);
    }

    #[test]
    fn first_derivatives_are_the_generators_times_the_rotation() {
        let q = Quaternion::new(-0.2, 0.6, 0.1, 0.7).normalize();
        for (omega, dt) in [(Vector3::new(2.0, -0.7, 1.4), 0.3), (Vector3::zeros(), 0.01)] {
            let jet = RotationJet::of_update(&q, &omega, dt);
            for i in 0..3 {
                let xi = jet.generators.column(i).into_owned();
                assert!((skew(&xi) * jet.r - jet.d1[i]).amax() < 1e-15 * (1.0 + dt), "{i}");
            }
        }
    }

    #[test]
    fn unit_skew_helpers_match_the_matrix_products() {
        let e = [skew(&Vector3::x()), skew(&Vector3::y()), skew(&Vector3::z())];
        let k = skew(&Vector3::new(0.3, -1.7, 2.9e-3));
        for i in 0..3 {
            assert_eq!(unit_cross(i, &k), e[i] * k);
            assert_eq!(unit_cross(i, &k).transpose(), k * e[i]);
            for j in 0..3 {
                assert_eq!(unit_anticommutator(i, j), e[i] * e[j] + e[j] * e[i]);
            }
        }
    }

    #[test]
    fn axl_variants_agree_on_skew_matrices() {
        let v = Vector3::new(0.3, -1.2, 2.5);
        let k = skew(&v);
        assert!((axl(&k) - v).norm() < 1e-15);
        assert!((axl_upper(&k) - v).norm() < 1e-15);
    }
}
