//! An independent check of the curved-shell terms (supplement eqs. 2–3) that does not go through the
//! kinematics or the strain Hessian of the kernels: a known deformation of a curved surface (a
//! non-umbilic graph, displaced and rotated by smooth fields) is turned into a 3D body
//! `Φ(x, z) = m(x) + z R(x) n₀(x)` over the rest body `Ψ(x, z) = x + z n₀(x)`. Its micropolar strain
//! `Rᵀ ∇Φ (∇Ψ)⁻¹ − I` and wryness `Γ (1 − z b)⁻¹` are formed by finite differences of the 3D maps, and
//! the energy `∫ W(ε(z)) det(1 − z b) dz` over the thickness is integrated numerically. The 2D density
//! (`density`, with `E`, `Γ`, `b`, `H`, `K` and `c = −[n₀]×` of the surface) must agree with it to the
//! order of its expansion: they differ from `h⁵` on, while a wrong sign in any `h³` piece (`K h³/12`,
//! `E b + cΓ`, `cΓ b − 2H cΓ`, the curvature terms' `Γ b` and `K`) would change the energy by twice that
//! piece.

use cosserat_geometry::rotation::{axl, exp_map, skew};
use cosserat_material::density::{PointGeometry, density, w_curv, w_m, w_mixt};
use cosserat_material::{MaterialParameters, ModelOptions, ShellModel, TermSet};
use nalgebra::{Matrix3, Matrix3x2, Vector3};

fn material() -> MaterialParameters {
    let mut m = MaterialParameters::new(0.01, 1e6, 0.3, 1000.0, 0.3);
    m.curvature_coefficients = [1.0, 0.7, 0.2];
    m.mu_c_factor = 0.8;
    m
}

/// The rest surface: a non-umbilic graph.
fn rest(u: f64, v: f64) -> Vector3<f64> {
    Vector3::new(u, v, 0.3 * u * u + 0.1 * u * v - 0.2 * v * v + 0.05 * u * u * u)
}

/// The deformed mid-surface.
fn mid(u: f64, v: f64) -> Vector3<f64> {
    rest(u, v) + Vector3::new(0.02 * u * v, -0.03 * u + 0.01 * v * v, 0.04 * u * u - 0.02 * v)
}

/// The rotation field.
fn rotation(u: f64, v: f64) -> Matrix3<f64> {
    exp_map(&Vector3::new(
        0.2 + 0.3 * u,
        -0.1 + 0.2 * v + 0.1 * u * u,
        0.15 * u * v + 0.05,
    ))
}

const STEP: f64 = 1e-5;

fn d<T: std::ops::Sub<Output = T> + std::ops::Mul<f64, Output = T>>(f: impl Fn(f64) -> T, x: f64) -> T {
    (f(x + STEP) - f(x - STEP)) * (0.5 / STEP)
}

/// The rest normal, analytic (nested finite differences would amplify round-off).
fn normal(u: f64, v: f64) -> Vector3<f64> {
    let fu = 0.6 * u + 0.1 * v + 0.15 * u * u;
    let fv = 0.1 * u - 0.4 * v;
    Vector3::new(-fu, -fv, 1.0).normalize()
}

fn tangent(f: impl Fn(f64, f64) -> Vector3<f64>, u: f64, v: f64) -> Matrix3x2<f64> {
    Matrix3x2::from_columns(&[d(|s| f(s, v), u), d(|s| f(u, s), v)])
}

/// Jacobian of a 3D map of `(u, v, z)`.
fn jacobian(f: impl Fn(f64, f64, f64) -> Vector3<f64>, u: f64, v: f64, z: f64) -> Matrix3<f64> {
    Matrix3::from_columns(&[d(|s| f(s, v, z), u), d(|s| f(u, s, z), v), d(|s| f(u, v, s), z)])
}

/// The 2D strains and rest geometry at `(u, v)`, all in world components.
struct Surface {
    e: Matrix3<f64>,
    gamma: Matrix3<f64>,
    b: Matrix3<f64>,
    n: Vector3<f64>,
}

fn surface(u: f64, v: f64) -> Surface {
    let g = tangent(rest, u, v);
    let g_pinv = (g.transpose() * g).try_inverse().unwrap() * g.transpose();
    let n = normal(u, v);
    let r = rotation(u, v);
    let f = tangent(mid, u, v) * g_pinv;
    let a = Matrix3::identity() - n * n.transpose();
    let b = -tangent(normal, u, v) * g_pinv;
    let mut gamma = Matrix3::zeros();
    for alpha in 0..2 {
        let dr = if alpha == 0 {
            d(|s| rotation(s, v), u)
        } else {
            d(|s| rotation(u, s), v)
        };
        gamma += axl(&(r.transpose() * dr)) * g_pinv.row(alpha);
    }
    Surface {
        e: r.transpose() * f - a,
        gamma,
        b,
        n,
    }
}

/// `W_m` (supplement eq. 5) and `W_curv` (eq. 7), written here again.
fn w_m_3d(a: &Matrix3<f64>, mu: f64, mu_c: f64, plane_lambda: f64) -> f64 {
    let s = (a + a.transpose()) * 0.5;
    let k = (a - a.transpose()) * 0.5;
    mu * s.norm_squared() + mu_c * k.norm_squared() + plane_lambda * a.trace().powi(2)
}

fn three_d_energy(u: f64, v: f64, h: f64) -> f64 {
    let m = material().moduli().unwrap();
    let s = surface(u, v);
    let r = rotation(u, v);
    let body = |x: f64, y: f64, z: f64| rest(x, y) + normal(x, y) * z;
    let deformed = |x: f64, y: f64, z: f64| mid(x, y) + rotation(x, y) * normal(x, y) * z;
    let [b1, b2, b3] = m.curvature_coefficients;
    let l2 = m.mu * m.length_scale * m.length_scale;
    // Gauss–Legendre, 5 points per interval on 8 intervals: exact far beyond the orders compared.
    let (nodes, weights) = (
        [
            -0.906_179_845_938_664,
            -0.538_469_310_105_683,
            0.0,
            0.538_469_310_105_683,
            0.906_179_845_938_664,
        ],
        [
            0.236_926_885_056_189,
            0.478_628_670_499_366,
            0.568_888_888_888_889,
            0.478_628_670_499_366,
            0.236_926_885_056_189,
        ],
    );
    let n_int = 8;
    let mut total = 0.0;
    for k in 0..n_int {
        let (lo, hi) = (
            -0.5 * h + h * k as f64 / n_int as f64,
            -0.5 * h + h * (k + 1) as f64 / n_int as f64,
        );
        for (x, w) in nodes.iter().zip(weights) {
            let z = 0.5 * (lo + hi) + 0.5 * (hi - lo) * x;
            let shifter = jacobian(body, u, v, z);
            let strain =
                r.transpose() * jacobian(deformed, u, v, z) * shifter.try_inverse().unwrap() - Matrix3::identity();
            // The rest volume element over the mid-surface's area element: det(1 − z b).
            let volume = shifter.determinant() / jacobian(body, u, v, 0.0).determinant();
            let wry = s.gamma * (Matrix3::identity() - s.b * z).try_inverse().unwrap();
            let ws = (wry + wry.transpose()) * 0.5;
            let wk = (wry - wry.transpose()) * 0.5;
            let curv = l2 * (b1 * ws.norm_squared() + b2 * wk.norm_squared() + b3 * wry.trace().powi(2));
            total += 0.5 * (hi - lo) * w * (w_m_3d(&strain, m.mu, m.mu_c, m.plane_lambda) + curv) * volume;
        }
    }
    total
}

fn two_d_energy(u: f64, v: f64, h: f64) -> f64 {
    let mut params = material();
    params.thickness = h;
    let m = params.moduli().unwrap();
    let s = surface(u, v);
    let t = s.b.trace();
    let geometry = PointGeometry {
        b: s.b,
        mean: 0.5 * t,
        gaussian: 0.5 * (t * t - (s.b * s.b).trace()),
        c: -skew(&s.n),
    };
    let terms = TermSet::select(&ModelOptions::new(ShellModel::Shell), &m, true).unwrap();
    density(&terms, &s.e, &s.gamma, &geometry, &m)
}

#[test]
fn the_3d_reconstruction_has_the_strains_of_the_2d_model() {
    // ε(z) = (E + z cΓ)(1 − z b)⁻¹: the kinematic identity behind eqs. 2–3 (signs of c, b and axl).
    let (u, v) = (0.1, -0.2);
    let s = surface(u, v);
    let r = rotation(u, v);
    let c = -skew(&s.n);
    let body = |x: f64, y: f64, z: f64| rest(x, y) + normal(x, y) * z;
    let deformed = |x: f64, y: f64, z: f64| mid(x, y) + rotation(x, y) * normal(x, y) * z;
    for z in [-0.05, 0.03] {
        let strain = r.transpose() * jacobian(deformed, u, v, z) * jacobian(body, u, v, z).try_inverse().unwrap()
            - Matrix3::identity();
        let model = (s.e + c * s.gamma * z) * (Matrix3::identity() - s.b * z).try_inverse().unwrap();
        assert!((strain - model).amax() < 1e-8, "z = {z}: {strain} vs {model}");
    }
}

/// The `h³` pieces of eqs. 2–3 at thickness `h`: a sign error in any of them changes the energy by
/// twice that piece.
fn third_order_pieces(u: f64, v: f64, h: f64) -> [f64; 5] {
    let m = material().moduli().unwrap();
    let s = surface(u, v);
    let c = -skew(&s.n);
    let t = s.b.trace();
    let (mean, gaussian) = (0.5 * t, 0.5 * (t * t - (s.b * s.b).trace()));
    let h3 = h * h * h;
    let cg = c * s.gamma;
    [
        gaussian * h3 / 12.0 * w_m(&s.e, &m),
        h3 / 12.0 * w_m(&(s.e * s.b + cg), &m),
        h3 / 6.0 * w_mixt(&s.e, &(cg * s.b - cg * (2.0 * mean)), &m),
        h3 / 12.0 * w_curv(&(s.gamma * s.b), &m),
        gaussian * h3 / 12.0 * w_curv(&s.gamma, &m),
    ]
}

#[test]
fn curved_terms_agree_with_the_thickness_integral_to_their_order() {
    // The 2D density and the thickness integral differ from h⁵ on (relative 1e-9 at h = 0.16 here,
    // below round-off under h = 0.04); the h³ pieces are 1e-4 to 1e-2 of the energy, so each is
    // resolved (a wrong sign changes the energy by twice its piece).
    let (u, v) = (0.1, -0.2);
    for h in [0.16, 0.08] {
        let difference = (two_d_energy(u, v, h) - three_d_energy(u, v, h)).abs();
        let pieces = third_order_pieces(u, v, h);
        let smallest = pieces.iter().fold(f64::INFINITY, |a, p| a.min(p.abs()));
        assert!(
            difference < 1e-2 * smallest,
            "h = {h}: 2D − 3D = {difference:e}, h³ pieces {pieces:?}"
        );
    }
}
