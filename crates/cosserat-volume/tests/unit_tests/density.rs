//! The micropolar density: the shell's `W_mp + W_curv`, its constant strain Hessian, isotropy and
//! closed forms.

use super::common::{mat3, material, rng};
use cosserat_geometry::rotation::exp_map;
use cosserat_volume::MicropolarModuli;
use cosserat_volume::density::{curvature_density, density, pack, strain_hessian, stretch_density};
use nalgebra::{Matrix3, Vector3};

#[test]
fn density_is_the_shell_supplements_w_mp_plus_w_curv() {
    let m = material();
    let shell = cosserat_material::MaterialParameters::with_continuum(0.01, m).moduli().unwrap();
    let moduli = MicropolarModuli::of(&m).unwrap();
    let mut r = rng(1);
    for _ in 0..5 {
        let (e, g) = (mat3(&mut r, 0.1), mat3(&mut r, 3.0));
        let ours = density(&e, &g, &moduli);
        let theirs = cosserat_material::density::w_mp(&e, &shell) + cosserat_material::density::w_curv(&g, &shell);
        assert!((ours - theirs).abs() <= 1e-13 * theirs.abs(), "{ours} vs {theirs}");
    }
}

#[test]
fn closed_forms_of_pure_strains() {
    let m = MicropolarModuli::of(&material()).unwrap();
    let eps = 1e-3;
    // Pure dilatation E = ε I: μ 3ε² + λ/2 (3ε)².
    let w: f64 = stretch_density(&(Matrix3::identity() * eps), &m);
    let expected = m.mu * 3.0 * eps * eps + 0.5 * m.lambda * 9.0 * eps * eps;
    assert!((w - expected).abs() <= 1e-14 * expected);
    // Pure skew E = [θ]×: μ_c |[θ]×|² = 2 μ_c |θ|².
    let theta = Vector3::new(1e-3, -2e-3, 5e-4);
    let w: f64 = stretch_density(&cosserat_geometry::rotation::skew(&theta), &m);
    assert!((w - 2.0 * m.mu_c * theta.norm_squared()).abs() <= 1e-14 * w);
    // Bending Γ = k e_y ⊗ e_x: μ L_c² (b₁ + b₂) k²/2.
    let k = 2.0;
    let mut g = Matrix3::zeros();
    g[(1, 0)] = k;
    let [b1, b2, _] = m.curvature_coefficients;
    let expected = m.mu * m.length_scale * m.length_scale * (b1 + b2) * k * k / 2.0;
    assert!((curvature_density(&g, &m) - expected).abs() <= 1e-14 * expected);
}

#[test]
fn the_constant_strain_hessian_reproduces_the_density() {
    let m = MicropolarModuli::of(&material()).unwrap();
    let d = strain_hessian(&m);
    assert_eq!(d, d.transpose());
    let mut r = rng(2);
    for _ in 0..5 {
        let (e, g) = (mat3(&mut r, 0.1), mat3(&mut r, 3.0));
        let s = pack(&e, &g);
        let w = density(&e, &g, &m);
        assert!((0.5 * s.dot(&(d * s)) - w).abs() <= 1e-12 * w);
    }
}

#[test]
fn density_is_isotropic() {
    let m = MicropolarModuli::of(&material()).unwrap();
    let mut r = rng(3);
    let q = exp_map(&Vector3::new(0.3, -1.1, 2.0));
    for _ in 0..3 {
        let (e, g) = (mat3(&mut r, 0.1), mat3(&mut r, 3.0));
        let w = density(&e, &g, &m);
        let wq = density(&(q * e * q.transpose()), &(q * g * q.transpose()), &m);
        assert!((w - wq).abs() <= 1e-12 * w);
    }
}
