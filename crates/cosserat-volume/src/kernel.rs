//! The fast exact kernel of one quadrature point: energy density, gradient and Hessian with respect to
//! the point's compact locals.
//!
//! **Locals.** At a point of an `N`-node element the density depends on
//! - the three columns `F_j = F e_j` of the deformation gradient (9 numbers, linear in the nodal
//!   velocities), and
//! - the angular velocities `ω_k` of the `N` nodes: they move the nodal rotations `R_k`, and through the
//!   interpolated `ω_p = Σ_k N_k ω_k` the point's own rotation `R`.
//!
//! So there are `NL = 9 + 3N` locals (21 for Tet4).
//!
//! **Structure.** The strains are `E_j = Rᵀ F_j − e_j` and `Γ_j = axl(Rᵀ X_j) − Γ_rest e_j` with
//! `X_j = Σ_k ∂_j N_k R_k`: bilinear in `(R, F)` and in `(R, R_k)`. The density is the quadratic form
//! `½ sᵀ D s` of the 18 strain numbers (`density`), and the only other nonlinearity is each rotation
//! map `ω ↦ R(Φ(q, ω, Δt))`, whose derivatives come from [`RotationJet`]. The chain rule gives the
//! exact Hessian as `Jᵀ D J` plus the bilinear maps' second-order terms weighted by `σ = D s`. This is
//! the shell kernel of `cosserat-material` with three directions of differentiation instead of two and
//! the world axes as the rest frame; the whole-element dual-number energy (`oracle`) checks it.

use crate::density::{StrainMatrix, StrainVector};
use crate::tet4::VolumePoint;
use cosserat_geometry::rotation::{RotationJet, axl, skew};
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// Energy density, gradient and Hessian of a point with respect to its `NL` locals
/// `(F e₀, F e₁, F e₂, ω₀, …, ω_{N−1})`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalDerivatives<const NL: usize> {
    /// Energy density at the point \[J/m³\].
    pub value: f64,
    /// Gradient.
    pub gradient: SVector<f64, NL>,
    /// Hessian (symmetric).
    pub hessian: SMatrix<f64, NL, NL>,
}

/// The current state of a point as the kernels need it.
#[derive(Debug, Clone, Copy)]
pub struct PointState<'a, const N: usize> {
    /// The columns `F e_j` of the deformation gradient.
    pub f: [Vector3<f64>; 3],
    /// Jet of the point rotation with respect to the interpolated angular velocity.
    pub point_jet: &'a RotationJet,
    /// Jets of the nodal rotations, each with respect to its own node's angular velocity.
    pub node_jets: [&'a RotationJet; N],
    /// The prescribed rest curvature `Γ_rest` (world axes; row = axial component, column = direction of
    /// differentiation).
    pub rest_curvature: &'a Matrix3<f64>,
}

#[inline]
fn frob(a: &Matrix3<f64>, b: &Matrix3<f64>) -> f64 {
    a.component_mul(b).sum()
}

/// The 18 strain numbers `(vec E, vec (Γ − Γ_rest))` of a point from its rotations.
#[inline]
pub fn strain_vector<const N: usize>(
    point: &VolumePoint<N>,
    f: &[Vector3<f64>; 3],
    r: &Matrix3<f64>,
    node_r: [&Matrix3<f64>; N],
    rest_curvature: &Matrix3<f64>,
) -> StrainVector {
    let rt = r.transpose();
    let mut s = StrainVector::zeros();
    for j in 0..3 {
        let mut x = Matrix3::zeros();
        for (k, rk) in node_r.iter().enumerate() {
            x += *rk * point.grad[(j, k)];
        }
        let e = rt * f[j];
        let g = axl(&(rt * x));
        for a in 0..3 {
            s[3 * j + a] = e[a] - if a == j { 1.0 } else { 0.0 };
            s[9 + 3 * j + a] = g[a] - rest_curvature[(a, j)];
        }
    }
    s
}

/// Energy density of a point \[J/m³\] (the `f64` path of line searches).
#[inline]
pub fn point_value<const N: usize>(
    point: &VolumePoint<N>,
    f: &[Vector3<f64>; 3],
    r: &Matrix3<f64>,
    node_r: [&Matrix3<f64>; N],
    rest_curvature: &Matrix3<f64>,
    d: &StrainMatrix,
) -> f64 {
    let s = strain_vector(point, f, r, node_r, rest_curvature);
    0.5 * s.dot(&(d * s))
}

/// The σ-dependent intermediate quantities shared by gradient and Hessian.
struct Stress<const N: usize> {
    value: f64,
    /// `w_j = σ_E e_j`.
    w: [Vector3<f64>; 3],
    /// `U_k = Σ_j ∂_j N_k T_j`, with `T_j = ½ [σ_Γ e_j]×` the adjoint of `axl` applied to `σ_Γ e_j`.
    u: [Matrix3<f64>; N],
    /// `Σ_j F_j w_jᵀ + Σ_k R_k U_kᵀ`: `⟨R_i, yz⟩` is the gradient along the point rotation.
    yz: Matrix3<f64>,
    /// `X_j = Σ_k ∂_j N_k R_k`.
    x: [Matrix3<f64>; 3],
}

#[inline]
fn stress<const N: usize>(point: &VolumePoint<N>, state: &PointState<'_, N>, d: &StrainMatrix) -> Stress<N> {
    let node_r = state.node_jets.map(|j| &j.r);
    let s = strain_vector(point, &state.f, &state.point_jet.r, node_r, state.rest_curvature);
    let sigma = d * s;
    let value = 0.5 * s.dot(&sigma);
    let w: [Vector3<f64>; 3] = std::array::from_fn(|j| sigma.fixed_rows::<3>(3 * j).into_owned());
    let t: [Matrix3<f64>; 3] = std::array::from_fn(|j| skew(&sigma.fixed_rows::<3>(9 + 3 * j).into_owned()) * 0.5);
    let mut u = [Matrix3::zeros(); N];
    let mut yz = Matrix3::zeros();
    for j in 0..3 {
        yz += state.f[j] * w[j].transpose();
    }
    let mut x = [Matrix3::zeros(); 3];
    for k in 0..N {
        for j in 0..3 {
            u[k] += t[j] * point.grad[(j, k)];
            x[j] += node_r[k] * point.grad[(j, k)];
        }
        yz += node_r[k] * u[k].transpose();
    }
    Stress { value, w, u, yz, x }
}

fn gradient_from_stress<const N: usize, const NL: usize>(
    point: &VolumePoint<N>,
    state: &PointState<'_, N>,
    st: &Stress<N>,
) -> SVector<f64, NL> {
    let jet = state.point_jet;
    let mut grad = SVector::<f64, NL>::zeros();
    for j in 0..3 {
        grad.fixed_rows_mut::<3>(3 * j).copy_from(&(jet.r * st.w[j]));
    }
    let gp: [f64; 3] = std::array::from_fn(|i| frob(&jet.d1[i], &st.yz));
    for k in 0..N {
        let ru = jet.r * st.u[k];
        let mk = point.values[k];
        for i in 0..3 {
            grad[9 + 3 * k + i] = mk * gp[i] + frob(&ru, &state.node_jets[k].d1[i]);
        }
    }
    grad
}

/// Energy density and its gradient with respect to the locals.
pub fn point_gradient<const N: usize, const NL: usize>(
    point: &VolumePoint<N>,
    state: &PointState<'_, N>,
    d: &StrainMatrix,
) -> (f64, SVector<f64, NL>) {
    const { assert!(NL == 9 + 3 * N, "NL must be 9 + 3 N") };
    let st = stress(point, state, d);
    (st.value, gradient_from_stress(point, state, &st))
}

/// Energy density, gradient and exact Hessian with respect to the locals.
pub fn point_hessian<const N: usize, const NL: usize>(
    point: &VolumePoint<N>,
    state: &PointState<'_, N>,
    d: &StrainMatrix,
) -> LocalDerivatives<NL> {
    const { assert!(NL == 9 + 3 * N, "NL must be 9 + 3 N") };
    let st = stress(point, state, d);
    let gradient = gradient_from_stress(point, state, &st);
    let jac = strain_jacobian::<N, NL>(point, state, &st);
    let mut hessian = jac.transpose() * (d * jac);
    add_bilinear_terms(point, state, &st, &mut hessian);
    add_rotation_terms(point, state, &st, &mut hessian);
    LocalDerivatives {
        value: st.value,
        gradient,
        hessian,
    }
}

/// The Jacobian of the 18 strains with respect to the locals (the deformation gradient's columns,
/// then the nodes' angular velocities).
fn strain_jacobian<const N: usize, const NL: usize>(
    point: &VolumePoint<N>,
    state: &PointState<'_, N>,
    st: &Stress<N>,
) -> SMatrix<f64, 18, NL> {
    let jet = state.point_jet;
    let rt = jet.r.transpose();
    let mut jac = SMatrix::<f64, 18, NL>::zeros();
    for j in 0..3 {
        jac.fixed_view_mut::<3, 3>(3 * j, 3 * j).copy_from(&rt);
    }
    // Strain derivatives along the point rotation (the factor N_k is applied per node below).
    let mut de_dp = [[Vector3::zeros(); 3]; 3];
    let mut dg_dp = [[Vector3::zeros(); 3]; 3];
    for i in 0..3 {
        let rit = jet.d1[i].transpose();
        for j in 0..3 {
            de_dp[j][i] = rit * state.f[j];
            dg_dp[j][i] = axl(&(rit * st.x[j]));
        }
    }
    for k in 0..N {
        let mk = point.values[k];
        let nj = state.node_jets[k];
        for i in 0..3 {
            let col = 9 + 3 * k + i;
            // Derivative of axl(Rᵀ R_k) along ω_k,i, shared by the three columns j.
            let dn = axl(&(rt * nj.d1[i]));
            for j in 0..3 {
                let de = de_dp[j][i] * mk;
                let dg = dg_dp[j][i] * mk + dn * point.grad[(j, k)];
                for a in 0..3 {
                    jac[(3 * j + a, col)] = de[a];
                    jac[(9 + 3 * j + a, col)] = dg[a];
                }
            }
        }
    }
    jac
}

/// Second-order terms of the bilinear strain maps (deformation gradient against rotation), weighted
/// by the stress.
fn add_bilinear_terms<const N: usize, const NL: usize>(
    point: &VolumePoint<N>,
    state: &PointState<'_, N>,
    st: &Stress<N>,
    hessian: &mut SMatrix<f64, NL, NL>,
) {
    let jet = state.point_jet;
    for k in 0..N {
        let mk = point.values[k];
        for i in 0..3 {
            let col = 9 + 3 * k + i;
            for j in 0..3 {
                let v = jet.d1[i] * st.w[j] * mk;
                for a in 0..3 {
                    hessian[(3 * j + a, col)] += v[a];
                    hessian[(col, 3 * j + a)] += v[a];
                }
            }
        }
    }
}

/// Second-order terms of the rotations: the point rotation's second derivatives, the node rotations'
/// own, and their cross terms.
fn add_rotation_terms<const N: usize, const NL: usize>(
    point: &VolumePoint<N>,
    state: &PointState<'_, N>,
    st: &Stress<N>,
    hessian: &mut SMatrix<f64, NL, NL>,
) {
    let jet = state.point_jet;
    let hpp = jet.second_contraction(&st.yz);
    // cross[k][i][j] = ⟨R_i U_k, R_k,j⟩: point rotation direction i, node k direction j.
    let mut cross = [[[0.0; 3]; 3]; N];
    for k in 0..N {
        let nj = state.node_jets[k];
        for i in 0..3 {
            let riu = jet.d1[i] * st.u[k];
            for j in 0..3 {
                cross[k][i][j] = frob(&riu, &nj.d1[j]);
            }
        }
    }
    for k in 0..N {
        let mk = point.values[k];
        // ⟨R U_k, R_k,ij⟩.
        let node_second = state.node_jets[k].second_contraction(&(jet.r * st.u[k]));
        for l in 0..N {
            let ml = point.values[l];
            for i in 0..3 {
                for j in 0..3 {
                    let mut v = mk * ml * hpp[i][j] + mk * cross[l][i][j] + ml * cross[k][j][i];
                    if k == l {
                        v += node_second[i][j];
                    }
                    hessian[(9 + 3 * k + i, 9 + 3 * l + j)] += v;
                }
            }
        }
    }
}
