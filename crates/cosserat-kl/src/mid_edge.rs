//! Exact derivatives of the mid-edge measures by the chain rule through unit normals.
//!
//! `IIᵢ = φ(vᵢ, n_f, n_gᵢ)` with `φ(v, u, w) = v · w / √(2 + 2 u · w)` (see
//! [`crate::fundamental_form::mid_edge_measure`]), where `vᵢ = qᵢ₊₁ + qᵢ₊₂ − 2qᵢ` is linear, `n_f` is the
//! face's unit normal and `n_gᵢ` the neighbour's. Each unit normal `n̂(e₁, e₂) = e₁ × e₂ / |e₁ × e₂|`
//! depends on the two edge vectors of its triangle (6 numbers); its Jacobian has the closed form
//! `(I − n nᵀ)/|N| [−[e₂]×, [e₁]×]`; the Hessian of `c · n̂` for a constant `c` and the derivatives of
//! `φ` are written out too. (Duals of 9 and 6 directions gave the same numbers at several times the cost,
//! mostly copying; the inline tests compare with them, and the crate tests compare the whole stencil
//! Hessian with the 18-direction dual oracle.) Only weighted sums of normal Hessians are ever needed, so
//! the face normal's Hessian is formed once per stencil with the weights of all three edges.

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// A unit normal and its Jacobian with respect to the edge vectors `(e₁, e₂)` of its triangle.
#[derive(Debug, Clone, Copy)]
pub(crate) struct NormalJet {
    pub n: Vector3<f64>,
    pub jac: SMatrix<f64, 3, 6>,
}

fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// The unit normal of `e₁ × e₂` and its Jacobian (module docs).
pub(crate) fn unit_normal_jet(e1: &Vector3<f64>, e2: &Vector3<f64>) -> NormalJet {
    let big = e1.cross(e2);
    let r = big.norm();
    let n = big / r;
    let projector = (Matrix3::identity() - n * n.transpose()) / r;
    let mut jac = SMatrix::<f64, 3, 6>::zeros();
    jac.fixed_view_mut::<3, 3>(0, 0).copy_from(&(projector * -skew(e2)));
    jac.fixed_view_mut::<3, 3>(0, 3).copy_from(&(projector * skew(e1)));
    NormalJet { n, jac }
}

/// The Hessian of `c · n̂(e₁, e₂)` with respect to `(e₁, e₂)`, in closed form: with `N = e₁ × e₂`,
/// `r = |N|`, `n = N/r` and `h(N) = c · N / r`,
/// `∇_N h = (c − (c·n) n)/r`, `∇²_N h = (3 (c·n) n nᵀ − (c·n) I − c nᵀ − n cᵀ)/r²`, and the bilinear
/// `N` adds `∇²(g · N) = [[0, −[g]×], [[g]×, 0]]` for `g = ∇_N h`.
pub(crate) fn weighted_normal_hessian(e1: &Vector3<f64>, e2: &Vector3<f64>, c: &Vector3<f64>) -> SMatrix<f64, 6, 6> {
    let big = e1.cross(e2);
    let r = big.norm();
    let n = big / r;
    let cn = c.dot(&n);
    let g = (c - n * cn) / r;
    let h_nn =
        (n * n.transpose() * (3.0 * cn) - Matrix3::identity() * cn - c * n.transpose() - n * c.transpose()) / (r * r);
    let mut jn = SMatrix::<f64, 3, 6>::zeros();
    jn.fixed_view_mut::<3, 3>(0, 0).copy_from(&-skew(e2));
    jn.fixed_view_mut::<3, 3>(0, 3).copy_from(&skew(e1));
    let mut h = jn.transpose() * h_nn * jn;
    let sg = skew(&g);
    let mut upper = h.fixed_view_mut::<3, 3>(0, 3);
    upper -= sg;
    let mut lower = h.fixed_view_mut::<3, 3>(3, 0);
    lower += sg;
    h
}

/// Value, gradient and (if asked) Hessian of `φ(v, u, w) = v · w / √(2 + 2 u · w)` at `y = (v, u, w)`, in
/// closed form: with `A = v · w` and `f(t) = (2 + 2t)^{−1/2}` at `t = u · w`, `φ = A f`, `∇_v φ = f w`,
/// `∇_u φ = A f′ w`, `∇_w φ = f v + A f′ u`, and the second derivatives follow by differentiating these
/// once more.
pub(crate) fn measure_jet(y: &SVector<f64, 9>, with_hessian: bool) -> (f64, SVector<f64, 9>, SMatrix<f64, 9, 9>) {
    let v = Vector3::new(y[0], y[1], y[2]);
    let u = Vector3::new(y[3], y[4], y[5]);
    let w = Vector3::new(y[6], y[7], y[8]);
    let a = v.dot(&w);
    let q = 2.0 + 2.0 * u.dot(&w);
    let f = q.sqrt().recip();
    let f1 = -f / q;
    let f2 = -3.0 * f1 / q;
    let mut g = SVector::<f64, 9>::zeros();
    g.fixed_rows_mut::<3>(0).copy_from(&(w * f));
    g.fixed_rows_mut::<3>(3).copy_from(&(w * (a * f1)));
    g.fixed_rows_mut::<3>(6).copy_from(&(v * f + u * (a * f1)));
    let mut h = SMatrix::<f64, 9, 9>::zeros();
    if with_hessian {
        let id = Matrix3::identity();
        let wwt = w * w.transpose();
        let blocks = [
            (0, 3, wwt * f1),
            (0, 6, id * f + w * u.transpose() * f1),
            (3, 3, wwt * (a * f2)),
            (
                3,
                6,
                w * v.transpose() * f1 + w * u.transpose() * (a * f2) + id * (a * f1),
            ),
            (
                6,
                6,
                (v * u.transpose() + u * v.transpose()) * f1 + u * u.transpose() * (a * f2),
            ),
        ];
        for (r, c, b) in blocks {
            h.fixed_view_mut::<3, 3>(r, c).copy_from(&b);
            if r != c {
                h.fixed_view_mut::<3, 3>(c, r).copy_from(&b.transpose());
            }
        }
    }
    (a * f, g, h)
}

/// `P = [[−1, 1, 0], [−1, 0, 1]]`: edge vectors `(e₁, e₂) = (x_b − x_a, x_c − x_a)` of vertices `(a, b, c)`.
const EDGE_MAP: [[f64; 3]; 2] = [[-1.0, 1.0, 0.0], [-1.0, 0.0, 1.0]];

/// Adds `Eᵀ h E` to the blocks of stencil vertices `(a, b, c)`, where `E` maps their coordinates to the
/// edge vectors `(x_b − x_a, x_c − x_a)` and `h` is a Hessian with respect to those.
pub(crate) fn add_edge_hessian(out: &mut SMatrix<f64, 18, 18>, verts: [usize; 3], h: &SMatrix<f64, 6, 6>) {
    for (r, &vr) in verts.iter().enumerate() {
        for (c, &vc) in verts.iter().enumerate() {
            let mut block = Matrix3::zeros();
            for alpha in 0..2 {
                for beta in 0..2 {
                    let coef = EDGE_MAP[alpha][r] * EDGE_MAP[beta][c];
                    if coef != 0.0 {
                        block += h.fixed_view::<3, 3>(3 * alpha, 3 * beta) * coef;
                    }
                }
            }
            let mut target = out.fixed_view_mut::<3, 3>(3 * vr, 3 * vc);
            target += block;
        }
    }
}

/// Writes the Jacobian `J E` of a function of the edge vectors of vertices `(a, b, c)` into `rows` of
/// the Jacobian `out` (which must be zero there), whose columns are the coordinates of the vertices
/// (the stencil's, or a subset of them).
pub(crate) fn set_edge_jacobian<const R: usize, const C: usize>(
    out: &mut SMatrix<f64, R, C>,
    first_row: usize,
    verts: [usize; 3],
    jac: &SMatrix<f64, 3, 6>,
) {
    for (r, &v) in verts.iter().enumerate() {
        let mut block = out.fixed_view_mut::<3, 3>(first_row, 3 * v);
        for alpha in 0..2 {
            let coef = EDGE_MAP[alpha][r];
            if coef != 0.0 {
                block += jac.fixed_view::<3, 3>(0, 3 * alpha) * coef;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use cosserat_geometry::Real;
    use num_dual::Dual2SVec64;

    fn phi<T: Real>(y: &SVector<T, 9>) -> T {
        let v = Vector3::new(y[0], y[1], y[2]);
        let u = Vector3::new(y[3], y[4], y[5]);
        let w = Vector3::new(y[6], y[7], y[8]);
        v.dot(&w) / ((u.dot(&w) + T::one()) * 2.0).sqrt()
    }

    fn rel(a: &[f64], b: &[f64]) -> f64 {
        let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        a.iter().zip(b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs())) / scale
    }

    #[test]
    fn closed_forms_match_second_order_duals() {
        let e1 = Vector3::new(0.9, 0.1, -0.2);
        let e2 = Vector3::new(0.2, 1.1, 0.3);
        let c = Vector3::new(0.3, -0.7, 1.3);
        let x = SVector::<f64, 6>::from([e1.x, e1.y, e1.z, e2.x, e2.y, e2.z]);
        let (v, g, h) = num_dual::hessian(
            |e: SVector<Dual2SVec64<6>, 6>| {
                let n = Vector3::new(e[0], e[1], e[2]).cross(&Vector3::new(e[3], e[4], e[5]));
                let n = n / n.norm();
                n.x * c.x + n.y * c.y + n.z * c.z
            },
            &x,
        );
        let jet = unit_normal_jet(&e1, &e2);
        assert!((jet.n.dot(&c) - v).abs() < 1e-15);
        assert!(rel((jet.jac.transpose() * c).as_slice(), g.as_slice()) < 1e-14);
        assert!(rel(weighted_normal_hessian(&e1, &e2, &c).as_slice(), h.as_slice()) < 1e-13);

        let n = jet.n;
        let w = (n + Vector3::new(0.2, -0.1, 0.05)).normalize();
        let y = SVector::<f64, 9>::from_fn(|i, _| [Vector3::new(1.0, 0.4, -0.3), n, w][i / 3][i % 3]);
        let (v, g, h) = num_dual::hessian(|y: SVector<Dual2SVec64<9>, 9>| phi(&y), &y);
        let (v2, g2, h2) = measure_jet(&y, true);
        assert!((v - v2).abs() < 1e-15);
        assert!(rel(g2.as_slice(), g.as_slice()) < 1e-14 && rel(h2.as_slice(), h.as_slice()) < 1e-13);
    }
}
