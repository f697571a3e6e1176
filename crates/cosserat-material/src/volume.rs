//! The optional nonlinear membrane volume term (model.md §3.4).
//!
//! `h ½ λμ/(λ+2μ) ((J − 1)² + (1/J − 1)²)` with the area ratio `J = |F̂₁ × F̂₂|` (the current area element
//! over the rest one, because `F̂` is taken on orthonormal rest tangents). It replaces the trace term of
//! the membrane energy; for small strains both agree, and this one grows without bound as an element's
//! area goes to zero. It depends on `F̂` only, through the scalar `J`, so its derivatives follow by the
//! chain rule from those of `ψ(J)` and of `J(F̂)`; the tests check them against a num-dual oracle.

use crate::parameters::Moduli;
use cosserat_geometry::Real;
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// The volume term's density (per unit rest area).
pub fn volume_density<T: Real>(f_hat: &[Vector3<T>; 2], m: &Moduli) -> T {
    let j = f_hat[0].cross(&f_hat[1]).norm();
    let a = j - T::one();
    let b = j.recip() - T::one();
    (a * a + b * b) * (0.5 * m.thickness * m.plane_lambda)
}

/// Value, gradient and Hessian of the volume density with respect to `(F̂₁, F̂₂)`.
///
/// With `n = F̂₁ × F̂₂`, `J = |n|` and `n̂ = n / J`: `∂J/∂F̂₁ = F̂₂ × n̂`, `∂J/∂F̂₂ = n̂ × F̂₁`, and
/// `∂²J = (1/J) Dnᵀ (I − n̂n̂ᵀ) Dn + B`, where `Dn = [−[F̂₂]ₓ  [F̂₁]ₓ]` is the Jacobian of `n` and `B`
/// holds the bilinear part of `n` (`−[n̂]ₓ` in the `F̂₁F̂₂` block). Then `∇ψ = ψ′ ∇J` and
/// `∇²ψ = ψ″ ∇J ∇Jᵀ + ψ′ ∇²J`.
pub fn volume_hessian(f_hat: &[Vector3<f64>; 2], m: &Moduli) -> (f64, SVector<f64, 6>, SMatrix<f64, 6, 6>) {
    let c = 0.5 * m.thickness * m.plane_lambda;
    let [f1, f2] = f_hat;
    let n = f1.cross(f2);
    let j = n.norm();
    let inv = j.recip();
    let n_hat = n * inv;
    let (a, b) = (j - 1.0, inv - 1.0);
    let value = c * (a * a + b * b);
    let d_psi = 2.0 * c * (a - b * inv * inv);
    let dd_psi = c * (2.0 + (6.0 * inv - 4.0) * inv * inv * inv);

    let mut grad_j = SVector::<f64, 6>::zeros();
    grad_j.fixed_rows_mut::<3>(0).copy_from(&f2.cross(&n_hat));
    grad_j.fixed_rows_mut::<3>(3).copy_from(&n_hat.cross(f1));

    let mut dn = SMatrix::<f64, 3, 6>::zeros();
    dn.fixed_columns_mut::<3>(0).copy_from(&(-f2.cross_matrix()));
    dn.fixed_columns_mut::<3>(3).copy_from(&f1.cross_matrix());
    let projector = Matrix3::identity() - n_hat * n_hat.transpose();
    let mut hess_j = dn.transpose() * projector * dn * inv;
    let bilinear = n_hat.cross_matrix();
    let mut upper = hess_j.fixed_view_mut::<3, 3>(0, 3);
    upper -= bilinear;
    let mut lower = hess_j.fixed_view_mut::<3, 3>(3, 0);
    lower += bilinear;

    let gradient = grad_j * d_psi;
    let hessian = grad_j * grad_j.transpose() * dd_psi + hess_j * d_psi;
    (value, gradient, hessian)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parameters::MaterialParameters;
    use num_dual::Dual2SVec64;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn moduli() -> Moduli {
        MaterialParameters::new(0.01, 2.0e5, 0.3, 1000.0, 0.005)
            .moduli()
            .expect("valid parameters")
    }

    /// The oracle: the density's Hessian by forward-mode second-order duals.
    fn dual_hessian(f_hat: &[Vector3<f64>; 2], m: &Moduli) -> (f64, SVector<f64, 6>, SMatrix<f64, 6, 6>) {
        let x = SVector::<f64, 6>::from_fn(|i, _| f_hat[i / 3][i % 3]);
        num_dual::hessian(
            |v: SVector<Dual2SVec64<6>, 6>| {
                let f = [Vector3::new(v[0], v[1], v[2]), Vector3::new(v[3], v[4], v[5])];
                volume_density(&f, m)
            },
            &x,
        )
    }

    /// Deformation gradients from near-rest to strongly stretched, sheared and compressed elements.
    fn samples() -> Vec<[Vector3<f64>; 2]> {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let mut out = vec![
            [Vector3::x(), Vector3::y()],
            [Vector3::x() * 0.2, Vector3::new(0.3, 0.05, 0.1)],
        ];
        for scale in [0.01, 0.3, 1.0] {
            for _ in 0..20 {
                let mut v = || Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0) * scale);
                out.push([Vector3::x() + v(), Vector3::y() + v()]);
            }
        }
        out
    }

    #[test]
    fn closed_form_matches_the_dual_oracle() {
        let m = moduli();
        for f in samples() {
            let (v, g, h) = volume_hessian(&f, &m);
            let (vo, go, ho) = dual_hessian(&f, &m);
            let scale = ho.abs().max().max(1e-300);
            assert!((v - vo).abs() <= 1e-12 * vo.abs().max(1e-300), "value {v} vs {vo}");
            assert!(
                (g - go).abs().max() <= 1e-11 * go.abs().max().max(scale),
                "gradient at {f:?}"
            );
            assert!(
                (h - ho).abs().max() <= 1e-11 * scale,
                "Hessian at {f:?}: {}",
                (h - ho).abs().max()
            );
        }
    }

    #[test]
    fn derivatives_match_central_differences_and_the_hessian_is_symmetric() {
        let m = moduli();
        let eps = 1e-6;
        for f in samples() {
            let (_, g, h) = volume_hessian(&f, &m);
            // Central differences err by O(ε²) times the third and fourth derivatives, which are of the
            // Hessian's order here.
            let scale = g.abs().max() + h.abs().max();
            assert!((h - h.transpose()).abs().max() <= 1e-14 * h.abs().max());
            let perturbed = |i: usize, s: f64| {
                let mut p = f;
                p[i / 3][i % 3] += s;
                p
            };
            for i in 0..6 {
                let (vp, gp, _) = volume_hessian(&perturbed(i, eps), &m);
                let (vm, gm, _) = volume_hessian(&perturbed(i, -eps), &m);
                let fd_g = (vp - vm) / (2.0 * eps);
                assert!(
                    (fd_g - g[i]).abs() <= 1e-6 * scale,
                    "gradient {i}: {fd_g} vs {} at {f:?}",
                    g[i]
                );
                let fd_h = (gp - gm) / (2.0 * eps);
                let err = (fd_h - h.column(i)).abs().max();
                assert!(err <= 1e-6 * scale, "Hessian column {i}: {err}");
            }
        }
    }

    #[test]
    fn rotating_the_deformation_leaves_the_density_and_rotates_its_gradient() {
        let m = moduli();
        let r = nalgebra::Rotation3::from_scaled_axis(Vector3::new(0.4, -1.1, 0.7));
        for f in samples() {
            let (v, g, _) = volume_hessian(&f, &m);
            let (vr, gr, _) = volume_hessian(&[r * f[0], r * f[1]], &m);
            assert!((v - vr).abs() <= 1e-12 * v.abs().max(1e-300));
            let rotated = [
                r * g.fixed_rows::<3>(0).into_owned(),
                r * g.fixed_rows::<3>(3).into_owned(),
            ];
            let err = (rotated[0] - gr.fixed_rows::<3>(0))
                .abs()
                .max()
                .max((rotated[1] - gr.fixed_rows::<3>(3)).abs().max());
            assert!(err <= 1e-11 * g.abs().max().max(1e-300));
        }
    }
}
