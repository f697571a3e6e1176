//! Closed-form gradients and Hessians of the three nonlinear maps behind every contact distance, with
//! respect to their difference locals: the squared point–plane (and line–line) distance
//! `(r·n)²/|n|²` with `n = a × b`, the squared point–line distance `|r × e|²/|e|²`, and the squared
//! cross-product norm `|a × b|²` of the edge–edge mollifier.
//!
//! A second-order dual pass over 9 locals costs microseconds per pair; these hand-derived forms are
//! more than an order of magnitude cheaper, which matters because every active pair needs them in every
//! Newton iteration.
//! They are checked against the dual-number pass of the same generic closed forms (the oracle) in this
//! module's tests and, through the pair jets, in the crate's unit tests.
//!
//! Building blocks: `p = r·(a × b)` is trilinear with gradient `(a × b, b × r, r × a)` and constant
//! Hessian blocks `∂²p/∂r∂a = −[b]ₓ`, `∂²p/∂r∂b = [a]ₓ`, `∂²p/∂a∂b = −[r]ₓ`; `q = |a × b|²` has
//! gradient `2 Jᵀ n` with `J = (−[b]ₓ, [a]ₓ)` and Hessian `2 JᵀJ` plus the block `∂²q/∂a∂b = −2 [n]ₓ`.

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    v.cross_matrix()
}

/// `|a × b|²` with gradient and Hessian with respect to `(a, b)`.
pub fn cross_squared(a: &Vector3<f64>, b: &Vector3<f64>) -> (f64, SVector<f64, 6>, SMatrix<f64, 6, 6>) {
    let n = a.cross(b);
    let (ja, jb) = (-skew(b), skew(a));
    let mut g = SVector::<f64, 6>::zeros();
    g.fixed_rows_mut::<3>(0).copy_from(&(ja.transpose() * n * 2.0));
    g.fixed_rows_mut::<3>(3).copy_from(&(jb.transpose() * n * 2.0));
    let mut h = SMatrix::<f64, 6, 6>::zeros();
    let hab = ja.transpose() * jb * 2.0 - skew(&n) * 2.0;
    h.fixed_view_mut::<3, 3>(0, 0).copy_from(&(ja.transpose() * ja * 2.0));
    h.fixed_view_mut::<3, 3>(3, 3).copy_from(&(jb.transpose() * jb * 2.0));
    h.fixed_view_mut::<3, 3>(0, 3).copy_from(&hab);
    h.fixed_view_mut::<3, 3>(3, 0).copy_from(&hab.transpose());
    (n.norm_squared(), g, h)
}

/// `(r·n)²/|n|²`, `n = a × b`, with gradient and Hessian with respect to `(r, a, b)`.
pub fn point_plane(r: &Vector3<f64>, a: &Vector3<f64>, b: &Vector3<f64>) -> (f64, SVector<f64, 9>, SMatrix<f64, 9, 9>) {
    let n = a.cross(b);
    let p = r.dot(&n);
    let mut gp = SVector::<f64, 9>::zeros();
    gp.fixed_rows_mut::<3>(0).copy_from(&n);
    gp.fixed_rows_mut::<3>(3).copy_from(&b.cross(r));
    gp.fixed_rows_mut::<3>(6).copy_from(&r.cross(a));
    let mut hp = SMatrix::<f64, 9, 9>::zeros();
    for (i, j, m) in [(0, 3, -skew(b)), (0, 6, skew(a)), (3, 6, -skew(r))] {
        hp.fixed_view_mut::<3, 3>(i, j).copy_from(&m);
        hp.fixed_view_mut::<3, 3>(j, i).copy_from(&m.transpose());
    }
    let (q, gq6, hq6) = cross_squared(a, b);
    let mut gq = SVector::<f64, 9>::zeros();
    gq.fixed_rows_mut::<6>(3).copy_from(&gq6);
    let mut hq = SMatrix::<f64, 9, 9>::zeros();
    hq.fixed_view_mut::<6, 6>(3, 3).copy_from(&hq6);
    let f = p * p / q;
    let g = gp * (2.0 * p / q) - gq * (p * p / (q * q));
    let cross = gp * gq.transpose();
    let h = gp * gp.transpose() * (2.0 / q) + hp * (2.0 * p / q) - (cross + cross.transpose()) * (2.0 * p / (q * q))
        + gq * gq.transpose() * (2.0 * p * p / (q * q * q))
        - hq * (p * p / (q * q));
    (f, g, h)
}

/// `|r × e|²/|e|²` with gradient and Hessian with respect to `(r, e)`.
pub fn point_line(r: &Vector3<f64>, e: &Vector3<f64>) -> (f64, SVector<f64, 6>, SMatrix<f64, 6, 6>) {
    let (p, gp, hp) = cross_squared(r, e);
    let q = e.norm_squared();
    let mut gq = SVector::<f64, 6>::zeros();
    gq.fixed_rows_mut::<3>(3).copy_from(&(e * 2.0));
    let mut hq = SMatrix::<f64, 6, 6>::zeros();
    hq.fixed_view_mut::<3, 3>(3, 3).copy_from(&(Matrix3::identity() * 2.0));
    let f = p / q;
    let g = gp / q - gq * (p / (q * q));
    let cross = gp * gq.transpose();
    let h = hp / q - (cross + cross.transpose()) / (q * q) + gq * gq.transpose() * (2.0 * p / (q * q * q))
        - hq * (p / (q * q));
    (f, g, h)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::jet::{local, local_hessian};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn random(rng: &mut ChaCha8Rng) -> Vector3<f64> {
        Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0))
    }

    #[test]
    fn closed_forms_match_the_dual_oracle() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        for _ in 0..50 {
            let (r, a, b) = (random(&mut rng), random(&mut rng), random(&mut rng));
            let y9 = SVector::<f64, 9>::from_iterator(r.iter().chain(a.iter()).chain(b.iter()).copied());
            let (v, g, h) = point_plane(&r, &a, &b);
            let (vd, gd, hd) = local_hessian(
                |y| {
                    let n = local(&y, 1).cross(&local(&y, 2));
                    let p = local(&y, 0).dot(&n);
                    p * p / n.norm_squared()
                },
                &y9,
            );
            let scale = hd.amax().max(1.0);
            assert!((v - vd).abs() < 1e-13 * vd.abs().max(1.0));
            assert!((g - gd).amax() < 1e-12 * gd.amax().max(1.0));
            assert!(
                (h - hd).amax() < 1e-11 * scale,
                "point-plane Hessian {:e}",
                (h - hd).amax() / scale
            );
            let y6 = SVector::<f64, 6>::from_iterator(r.iter().chain(a.iter()).copied());
            let (v, g, h) = point_line(&r, &a);
            let (vd, gd, hd) = local_hessian(
                |y| local(&y, 0).cross(&local(&y, 1)).norm_squared() / local(&y, 1).norm_squared(),
                &y6,
            );
            assert!((v - vd).abs() < 1e-13 * vd.abs().max(1.0));
            assert!((g - gd).amax() < 1e-12 * gd.amax().max(1.0));
            assert!((h - hd).amax() < 1e-11 * hd.amax().max(1.0));
            let (v, g, h) = cross_squared(&r, &a);
            let (vd, gd, hd) = local_hessian(|y| local(&y, 0).cross(&local(&y, 1)).norm_squared(), &y6);
            assert!((v - vd).abs() < 1e-13 * vd.abs().max(1.0));
            assert!((g - gd).amax() < 1e-12 * gd.amax().max(1.0));
            assert!((h - hd).amax() < 1e-12 * hd.amax().max(1.0));
        }
    }
}
