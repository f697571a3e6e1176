//! Surface geometry on exact surfaces: tangents `G = ∂x/∂ξ` and normal gradients `∇_ξ n` are built
//! analytically from parametrisations written here (never from the crate's code), and the metric,
//! shape operator, second fundamental tensor and curvatures are checked against closed forms.
//!
//! Sign convention under test: `b = −∇_ξ n G⁺`, so the principal curvatures are the eigenvalues of
//! `S = −G⁺ ∇_ξ n`, and with the outward normal of a sphere of radius `R` one gets `H = −1/R`,
//! `K = 1/R²`. The sign of `H` follows the normal *field* that is fed in, not the orientation of the
//! parametrisation.

use super::{random_vector, rng};
use cosserat_geometry::surface::{
    Curvature, DEGENERACY_TOLERANCE, SurfaceMetric, first_fundamental_form, gaussian_curvature, mean_curvature,
    second_fundamental_form, second_fundamental_tensor, shape_operator, tangential_symmetric_part,
};
use cosserat_geometry::{GeometryError, Real};
use nalgebra::{Matrix2, Matrix3, Matrix3x2, Vector3};
use num_dual::{Dual2_64, Dual64};
use std::f64::consts::{FRAC_PI_2, PI};

/// Absolute tolerance on curvature-like quantities. The test surfaces have curvatures of order one
/// and tangents of lengths between 0.05 and 10, so round-off stays near 1e-15; 1e-11 leaves room for
/// the conditioning of the strongly anisotropic reparametrisation.
const TOL: f64 = 1e-11;

/// An exactly parametrised surface `x(ξ)` with an analytically known normal field.
#[derive(Debug, Clone, Copy)]
enum Surface {
    /// The plane `p + ξ₁ t₁ + ξ₂ t₂` with non-orthogonal, non-unit `t₁, t₂`.
    SkewedPlane {
        origin: Vector3<f64>,
        t1: Vector3<f64>,
        t2: Vector3<f64>,
    },
    /// A sphere in spherical coordinates `ξ = (θ, φ)`, away from the poles.
    SphereSpherical { radius: f64 },
    /// The upper hemisphere as a graph `(u, v, √(R² − u² − v²))`.
    SphereGraph { radius: f64 },
    /// A cylinder about the z axis, `ξ = (θ, z)`.
    Cylinder { radius: f64 },
    /// The saddle `z = (x² − y²)/2` as a graph, normal pointing up.
    Saddle,
    /// A torus with major radius `major` about the z axis and tube radius `minor`, `ξ = (u, v)`.
    Torus { major: f64, minor: f64 },
}

/// The exact geometry of one surface point.
#[derive(Debug, Clone, Copy)]
struct ExactPoint {
    tangent: Matrix3x2<f64>,
    /// The unit normal; it agrees with `a₁ × a₂` for every parametrisation used here.
    normal: Vector3<f64>,
    normal_gradient: Matrix3x2<f64>,
    /// The principal curvatures (eigenvalues of `S = −G⁺ ∇_ξ n`), ascending.
    principal: [f64; 2],
}

impl ExactPoint {
    /// The same point under the linear reparametrisation `ξ = A η` (`det A > 0` keeps the orientation).
    fn reparametrised(&self, a: &Matrix2<f64>) -> Self {
        Self {
            tangent: self.tangent * a,
            normal_gradient: self.normal_gradient * a,
            ..*self
        }
    }

    fn mean(&self) -> f64 {
        0.5 * (self.principal[0] + self.principal[1])
    }

    fn gaussian(&self) -> f64 {
        self.principal[0] * self.principal[1]
    }
}

fn sorted(a: f64, b: f64) -> [f64; 2] {
    if a <= b { [a, b] } else { [b, a] }
}

impl Surface {
    fn position(&self, [s, t]: [f64; 2]) -> Vector3<f64> {
        match *self {
            Surface::SkewedPlane { origin, t1, t2 } => origin + t1 * s + t2 * t,
            Surface::SphereSpherical { radius } => Vector3::new(s.sin() * t.cos(), s.sin() * t.sin(), s.cos()) * radius,
            Surface::SphereGraph { radius } => Vector3::new(s, t, (radius * radius - s * s - t * t).sqrt()),
            Surface::Cylinder { radius } => Vector3::new(radius * s.cos(), radius * s.sin(), t),
            Surface::Saddle => Vector3::new(s, t, 0.5 * (s * s - t * t)),
            Surface::Torus { major, minor } => {
                let rho = major + minor * t.cos();
                Vector3::new(rho * s.cos(), rho * s.sin(), minor * t.sin())
            }
        }
    }

    fn normal(&self, [s, t]: [f64; 2]) -> Vector3<f64> {
        match *self {
            Surface::SkewedPlane { t1, t2, .. } => t1.cross(&t2).normalize(),
            Surface::SphereSpherical { radius } | Surface::SphereGraph { radius } => self.position([s, t]) / radius,
            Surface::Cylinder { .. } => Vector3::new(s.cos(), s.sin(), 0.0),
            Surface::Saddle => Vector3::new(-s, t, 1.0) / (1.0 + s * s + t * t).sqrt(),
            Surface::Torus { .. } => Vector3::new(t.cos() * s.cos(), t.cos() * s.sin(), t.sin()),
        }
    }

    /// The analytic tangent, normal gradient and principal curvatures at `ξ`.
    fn exact(&self, xi: [f64; 2]) -> ExactPoint {
        let [s, t] = xi;
        let normal = self.normal(xi);
        let (tangent, normal_gradient, principal) = match *self {
            Surface::SkewedPlane { t1, t2, .. } => (Matrix3x2::from_columns(&[t1, t2]), Matrix3x2::zeros(), [0.0, 0.0]),
            Surface::SphereSpherical { radius } => {
                let g = Matrix3x2::from_columns(&[
                    Vector3::new(s.cos() * t.cos(), s.cos() * t.sin(), -s.sin()) * radius,
                    Vector3::new(-s.sin() * t.sin(), s.sin() * t.cos(), 0.0) * radius,
                ]);
                (g, g / radius, [-1.0 / radius; 2])
            }
            Surface::SphereGraph { radius } => {
                let h = (radius * radius - s * s - t * t).sqrt();
                let g = Matrix3x2::new(1.0, 0.0, 0.0, 1.0, -s / h, -t / h);
                (g, g / radius, [-1.0 / radius; 2])
            }
            Surface::Cylinder { radius } => {
                let g = Matrix3x2::new(-radius * s.sin(), 0.0, radius * s.cos(), 0.0, 0.0, 1.0);
                let dn = Matrix3x2::new(-s.sin(), 0.0, s.cos(), 0.0, 0.0, 0.0);
                (g, dn, [-1.0 / radius, 0.0])
            }
            Surface::Saddle => {
                let w2 = 1.0 + s * s + t * t;
                let w = w2.sqrt();
                let w3 = w * w2;
                let m = Vector3::new(-s, t, 1.0);
                let g = Matrix3x2::new(1.0, 0.0, 0.0, 1.0, s, -t);
                let dn = Matrix3x2::from_columns(&[
                    Vector3::new(-1.0, 0.0, 0.0) / w - m * (s / w3),
                    Vector3::new(0.0, 1.0, 0.0) / w - m * (t / w3),
                ]);
                // H = ½ div(∇f / W) = (y² − x²)/(2 W³), K = (f_xx f_yy − f_xy²)/W⁴ = −1/W⁴.
                let mean = (t * t - s * s) / (2.0 * w3);
                let gauss = -1.0 / (w2 * w2);
                let d = (mean * mean - gauss).sqrt();
                (g, dn, sorted(mean - d, mean + d))
            }
            Surface::Torus { major, minor } => {
                let rho = major + minor * t.cos();
                let g = Matrix3x2::from_columns(&[
                    Vector3::new(-s.sin(), s.cos(), 0.0) * rho,
                    Vector3::new(-t.sin() * s.cos(), -t.sin() * s.sin(), t.cos()) * minor,
                ]);
                let dn = Matrix3x2::from_columns(&[
                    Vector3::new(-t.cos() * s.sin(), t.cos() * s.cos(), 0.0),
                    Vector3::new(-t.sin() * s.cos(), -t.sin() * s.sin(), t.cos()),
                ]);
                (g, dn, sorted(-t.cos() / rho, -1.0 / minor))
            }
        };
        ExactPoint {
            tangent,
            normal,
            normal_gradient,
            principal,
        }
    }

    /// A few parameter points of the surface, away from coordinate singularities.
    fn sample_points(&self) -> Vec<[f64; 2]> {
        match *self {
            Surface::SkewedPlane { .. } => vec![[0.0, 0.0], [1.3, -0.7], [-4.0, 2.5]],
            Surface::SphereSpherical { .. } => vec![[0.4, 0.1], [1.2, 2.0], [2.5, -2.7], [FRAC_PI_2, 0.0]],
            Surface::SphereGraph { radius } => {
                vec![[0.0, 0.0], [0.3 * radius, -0.2 * radius], [-0.5 * radius, 0.4 * radius]]
            }
            Surface::Cylinder { .. } => vec![[0.0, -1.0], [1.0, 0.5], [4.0, 2.0]],
            Surface::Saddle => vec![[0.0, 0.0], [0.5, 0.2], [-1.0, 0.7], [0.3, -1.1]],
            Surface::Torus { .. } => vec![[0.3, 0.0], [2.0, FRAC_PI_2], [-1.0, 2.5], [0.7, PI]],
        }
    }
}

/// The surfaces under test (their principal curvatures come from [`Surface::exact`]).
fn surfaces() -> Vec<Surface> {
    vec![
        Surface::SkewedPlane {
            origin: Vector3::new(0.3, -1.0, 2.0),
            t1: Vector3::new(1.0, 0.2, -0.5),
            t2: Vector3::new(0.8, 1.1, 0.3),
        },
        Surface::SphereSpherical { radius: 2.5 },
        Surface::SphereGraph { radius: 0.8 },
        Surface::Cylinder { radius: 1.7 },
        Surface::Saddle,
        Surface::Torus { major: 2.0, minor: 0.6 },
    ]
}

/// Linear reparametrisations `ξ = A η` with `det A > 0`: identity, a shear and a strong anisotropy.
fn reparametrisations() -> [Matrix2<f64>; 3] {
    [
        Matrix2::identity(),
        Matrix2::new(1.0, 0.7, 0.2, 1.3),
        Matrix2::new(0.05, 0.0, 0.01, 3.0),
    ]
}

/// Every exact point of every surface in every reparametrisation, with a label for messages.
fn all_points() -> Vec<(String, ExactPoint)> {
    let mut out = Vec::new();
    for surface in surfaces() {
        for xi in surface.sample_points() {
            for (k, a) in reparametrisations().iter().enumerate() {
                out.push((
                    format!("{surface:?} at {xi:?}, reparametrisation {k}"),
                    surface.exact(xi).reparametrised(a),
                ));
            }
        }
    }
    out
}

/// The real eigenvalues of a 2×2 matrix with a real spectrum, ascending.
fn eigenvalues_2x2(m: &Matrix2<f64>) -> [f64; 2] {
    let half_trace = 0.5 * m.trace();
    let d = (half_trace * half_trace - m.determinant()).max(0.0).sqrt();
    [half_trace - d, half_trace + d]
}

#[test]
fn analytic_parametrisations_match_finite_differences() {
    // Checks the test's own closed forms (not the crate): G and ∇_ξ n against central differences
    // of x(ξ) and n(ξ), |n| = 1, n ⊥ G, and n along a₁ × a₂. With h = 1e-5 the truncation error
    // is ~h² |x'''| ≈ 1e-10 and the round-off ~1e-16/h ≈ 1e-11.
    let h = 1e-5;
    for surface in surfaces() {
        for xi in surface.sample_points() {
            let p = surface.exact(xi);
            for k in 0..2 {
                let (mut plus, mut minus) = (xi, xi);
                plus[k] += h;
                minus[k] -= h;
                let dx = (surface.position(plus) - surface.position(minus)) / (2.0 * h);
                let dn = (surface.normal(plus) - surface.normal(minus)) / (2.0 * h);
                assert!(
                    (dx - p.tangent.column(k)).amax() < 1e-8,
                    "{surface:?} at {xi:?}: ∂x/∂ξ_{k}"
                );
                assert!(
                    (dn - p.normal_gradient.column(k)).amax() < 1e-8,
                    "{surface:?} at {xi:?}: ∂n/∂ξ_{k}"
                );
            }
            assert!((p.normal.norm() - 1.0).abs() < 1e-15);
            assert!(
                (p.tangent.transpose() * p.normal).amax() < 1e-14,
                "{surface:?}: n not normal"
            );
            let cross = p.tangent.column(0).cross(&p.tangent.column(1));
            assert!(
                (cross.normalize() - p.normal).amax() < 1e-14,
                "{surface:?}: n is not a₁ × a₂ / |a₁ × a₂|"
            );
        }
    }
}

/// Checks one exact point against every identity of the surface module.
fn check_exact_point(label: &str, p: &ExactPoint) {
    let metric = SurfaceMetric::try_new(&p.tangent).unwrap_or_else(|e| panic!("{label}: {e}"));
    let g = p.tangent;
    let n = p.normal;
    let ntn = n * n.transpose();

    // Metric: normal, area element, first fundamental form.
    assert!((metric.normal - n).amax() < 1e-14, "{label}: normal");
    let first = g.transpose() * g;
    assert!((metric.first_fundamental_form() - first).amax() < 1e-14, "{label}: I");
    assert!((first_fundamental_form(&g) - first).amax() < 1e-14, "{label}: I");
    let area = first.determinant().sqrt();
    assert!(
        (metric.area_element - area).abs() < 1e-12 * area,
        "{label}: area element {} vs {area}",
        metric.area_element
    );

    // Pseudo-inverse: G⁺ G = I₂, a = G G⁺ = I − n nᵀ, contravariant rows tangential.
    assert!(
        (metric.pinv * g - Matrix2::identity()).amax() < 1e-12,
        "{label}: G⁺G ≠ I₂"
    );
    let a = metric.tangent_projector();
    assert!(
        (a - (Matrix3::identity() - ntn)).amax() < 1e-12,
        "{label}: a ≠ I − n nᵀ"
    );
    assert!((g * metric.pinv - a).amax() < 1e-15, "{label}: a ≠ G G⁺");
    assert!((a * n).amax() < 1e-12, "{label}: a n ≠ 0");
    assert!(
        (metric.pinv * n).amax() < 1e-12 / area.sqrt(),
        "{label}: a^α not tangential"
    );

    // Alternating tensor: c n = 0, c y = y × n, c = −[n]×.
    let c = metric.alternating_tensor();
    assert!((c * n).amax() < 1e-12, "{label}: c n ≠ 0");
    assert!((c + n.cross_matrix()).amax() < 1e-12, "{label}: c ≠ −[n]×");
    let mut rng = rng(7);
    for _ in 0..3 {
        let y = random_vector(&mut rng, 2.0);
        assert!((c * y - y.cross(&n)).amax() < 1e-12, "{label}: c y ≠ y × n");
    }

    // Orthonormal frame: a rotation with first column along a₁ and third column n.
    let frame = metric.orthonormal_frame();
    assert!(
        (frame.transpose() * frame - Matrix3::identity()).amax() < 1e-14,
        "{label}: frame not orthogonal"
    );
    assert!((frame.determinant() - 1.0).abs() < 1e-14, "{label}: frame det ≠ 1");
    assert!((frame.column(2) - n).amax() < 1e-14);
    assert!((frame.column(0) - g.column(0).normalize()).amax() < 1e-14);

    // Second fundamental form: symmetric, and consistent with S = I⁻¹ II.
    let ii = second_fundamental_form(&g, &p.normal_gradient);
    assert!((ii - ii.transpose()).amax() < TOL, "{label}: II not symmetric: {ii}");
    let s = shape_operator(&metric, &p.normal_gradient);
    assert!((first * s - ii).amax() < TOL, "{label}: I S ≠ II");

    // Shape operator: eigenvalues are the principal curvatures; H = ½ tr S, K = det S.
    let [k1, k2] = p.principal;
    if (k1 - k2).abs() > 1e-3 {
        let [e1, e2] = eigenvalues_2x2(&s);
        assert!(
            (e1 - k1).abs() < TOL && (e2 - k2).abs() < TOL,
            "{label}: eig S = ({e1}, {e2}), expected ({k1}, {k2})"
        );
    } else {
        // At an umbilic point S = κ I in every parametrisation (the closed-form eigenvalues would lose
        // half the digits to the square root of a vanishing discriminant).
        assert!(
            (s - Matrix2::identity() * k1).amax() < TOL,
            "{label}: S = {s}, expected {k1} I"
        );
    }
    assert!((0.5 * s.trace() - p.mean()).abs() < TOL, "{label}: ½ tr S");
    assert!((s.determinant() - p.gaussian()).abs() < TOL, "{label}: det S");

    // Second fundamental tensor: tangential, symmetric, H = ½ tr b, K from eq. 12.
    let b = second_fundamental_tensor(&metric, &p.normal_gradient);
    assert!((b * n).amax() < TOL, "{label}: b n ≠ 0");
    assert!((n.transpose() * b).amax() < TOL, "{label}: nᵀ b ≠ 0");
    assert!((b - b.transpose()).amax() < TOL, "{label}: b not symmetric");
    assert!((a * b * a - b).amax() < TOL, "{label}: a b a ≠ b");
    let (h, k) = (mean_curvature(&b), gaussian_curvature(&b));
    assert!((h - p.mean()).abs() < TOL, "{label}: H = {h}, expected {}", p.mean());
    assert!((h - 0.5 * b.trace()).abs() < 1e-15, "{label}: H ≠ ½ tr b");
    assert!(
        (k - p.gaussian()).abs() < TOL,
        "{label}: K = {k}, expected {}",
        p.gaussian()
    );

    // The energy's curvature record agrees (b is already symmetric and tangential).
    let curvature = Curvature::from_normal_gradient(&metric, &p.normal_gradient);
    assert!((curvature.b - b).amax() < TOL, "{label}: Curvature::b");
    assert!((curvature.mean - p.mean()).abs() < TOL, "{label}: Curvature::mean");
    assert!(
        (curvature.gaussian - p.gaussian()).abs() < TOL,
        "{label}: Curvature::gaussian"
    );
}

#[test]
fn every_exact_point_satisfies_the_surface_identities() {
    let points = all_points();
    assert!(points.len() > 60);
    for (label, p) in &points {
        check_exact_point(label, p);
    }
}

#[test]
fn skewed_plane_has_zero_curvature() {
    let plane = surfaces()[0];
    for xi in plane.sample_points() {
        for a in reparametrisations() {
            let p = plane.exact(xi).reparametrised(&a);
            let metric = SurfaceMetric::try_new(&p.tangent).unwrap();
            // The tangents are not orthogonal: G⁺ is not Gᵀ up to scaling, yet G⁺G = I₂.
            assert!(p.tangent.column(0).dot(&p.tangent.column(1)).abs() > 0.1);
            assert!((metric.pinv * p.tangent - Matrix2::identity()).amax() < 1e-13);
            let b = second_fundamental_tensor(&metric, &p.normal_gradient);
            assert_eq!(b, Matrix3::zeros());
            assert_eq!(mean_curvature(&b), 0.0);
            assert_eq!(gaussian_curvature(&b), 0.0);
        }
    }
}

#[test]
fn sphere_has_mean_curvature_minus_one_over_radius_with_the_outward_normal() {
    for (surface, radius) in [
        (Surface::SphereSpherical { radius: 2.5 }, 2.5),
        (Surface::SphereGraph { radius: 0.8 }, 0.8),
    ] {
        for xi in surface.sample_points() {
            for a in reparametrisations() {
                let p = surface.exact(xi).reparametrised(&a);
                // Outward: the normal points away from the centre.
                assert!(p.normal.dot(&surface.position(xi)) > 0.0);
                let metric = SurfaceMetric::try_new(&p.tangent).unwrap();
                let b = second_fundamental_tensor(&metric, &p.normal_gradient);
                assert!((mean_curvature(&b) + 1.0 / radius).abs() < TOL, "{surface:?}: H ≠ −1/R");
                assert!(
                    (gaussian_curvature(&b) - 1.0 / (radius * radius)).abs() < TOL,
                    "{surface:?}: K ≠ 1/R²"
                );
                // b = −a/R: the sphere is umbilic.
                assert!(
                    (b + metric.tangent_projector() / radius).amax() < TOL,
                    "{surface:?}: b ≠ −a/R"
                );
            }
        }
    }
}

#[test]
fn cylinder_has_half_the_inverse_radius_as_mean_curvature_and_no_gaussian_curvature() {
    let radius = 1.7;
    let cylinder = Surface::Cylinder { radius };
    for xi in cylinder.sample_points() {
        for a in reparametrisations() {
            let p = cylinder.exact(xi).reparametrised(&a);
            let metric = SurfaceMetric::try_new(&p.tangent).unwrap();
            let b = second_fundamental_tensor(&metric, &p.normal_gradient);
            assert!((mean_curvature(&b) + 0.5 / radius).abs() < TOL, "H ≠ −1/(2R) at {xi:?}");
            assert!(gaussian_curvature(&b).abs() < TOL, "K ≠ 0 at {xi:?}");
            // The axis is a principal direction with curvature 0.
            assert!((b * Vector3::z()).amax() < TOL);
        }
    }
}

#[test]
fn saddle_at_the_origin_is_minimal_with_gaussian_curvature_minus_one() {
    for a in reparametrisations() {
        let p = Surface::Saddle.exact([0.0, 0.0]).reparametrised(&a);
        let metric = SurfaceMetric::try_new(&p.tangent).unwrap();
        let b = second_fundamental_tensor(&metric, &p.normal_gradient);
        assert!(mean_curvature(&b).abs() < TOL);
        assert!((gaussian_curvature(&b) + 1.0).abs() < TOL);
        assert!(
            (b - Matrix3::from_diagonal(&Vector3::new(1.0, -1.0, 0.0))).amax() < TOL,
            "b = {b}"
        );
    }
    // Away from the origin: H = (y² − x²)/(2 W³), K = −1/W⁴ with W² = 1 + x² + y².
    let (x, y) = (0.5, 0.2);
    let w2: f64 = 1.0 + x * x + y * y;
    let p = Surface::Saddle.exact([x, y]);
    let metric = SurfaceMetric::try_new(&p.tangent).unwrap();
    let b = second_fundamental_tensor(&metric, &p.normal_gradient);
    assert!((mean_curvature(&b) - (y * y - x * x) / (2.0 * w2.powf(1.5))).abs() < TOL);
    assert!((gaussian_curvature(&b) + 1.0 / (w2 * w2)).abs() < TOL);
}

#[test]
fn torus_curvatures_change_sign_with_the_tube_angle() {
    let (major, minor) = (2.0, 0.6);
    let torus = Surface::Torus { major, minor };
    for v in [0.0, FRAC_PI_2, PI] {
        let p = torus.exact([0.4, v]);
        let metric = SurfaceMetric::try_new(&p.tangent).unwrap();
        let b = second_fundamental_tensor(&metric, &p.normal_gradient);
        let rho = major + minor * v.cos();
        let expected_k = v.cos() / (minor * rho);
        let expected_h = -0.5 * (1.0 / minor + v.cos() / rho);
        assert!((gaussian_curvature(&b) - expected_k).abs() < TOL, "K at v = {v}");
        assert!((mean_curvature(&b) - expected_h).abs() < TOL, "H at v = {v}");
    }
}

#[test]
fn curvature_sign_follows_the_normal_field_not_the_parametrisation_orientation() {
    let radius = 2.5;
    let sphere = Surface::SphereSpherical { radius };
    let swap = Matrix2::new(0.0, 1.0, 1.0, 0.0);
    for xi in sphere.sample_points() {
        let outward = sphere.exact(xi);
        // Swapping ξ₁ and ξ₂ reverses the metric's normal and c, but b depends only on the normal field.
        let swapped = outward.reparametrised(&swap);
        let metric = SurfaceMetric::try_new(&swapped.tangent).unwrap();
        assert!((metric.normal + outward.normal).amax() < 1e-14);
        let c = metric.alternating_tensor();
        assert!(
            (c - outward.normal.cross_matrix()).amax() < 1e-12,
            "c = −[n₀]× with the reversed n₀"
        );
        let b_out = second_fundamental_tensor(&metric, &swapped.normal_gradient);
        assert!(
            (mean_curvature(&b_out) + 1.0 / radius).abs() < TOL,
            "outward field: H = −1/R"
        );
        // The inward normal field −n flips b and H and keeps K.
        let b_in = second_fundamental_tensor(&metric, &(-swapped.normal_gradient));
        assert!(
            (mean_curvature(&b_in) - 1.0 / radius).abs() < TOL,
            "inward field: H = +1/R"
        );
        assert!((gaussian_curvature(&b_in) - 1.0 / (radius * radius)).abs() < TOL);
    }
}

#[test]
fn pseudo_inverse_of_random_tangents() {
    let mut rng = rng(11);
    for _ in 0..100 {
        let g = Matrix3x2::from_columns(&[random_vector(&mut rng, 3.0), random_vector(&mut rng, 3.0)]);
        let metric = SurfaceMetric::try_new(&g).unwrap();
        let n = metric.normal;
        let a1: Vector3<f64> = g.column(0).into();
        let a2: Vector3<f64> = g.column(1).into();
        let cross = a1.cross(&a2);
        // Condition number of GᵀG bounds the error of G⁺ G.
        let cond = (a1.norm() * a2.norm() / cross.norm()).powi(2);
        let tol = 1e-15 * cond.max(10.0);
        assert!((metric.pinv * g - Matrix2::identity()).amax() < tol, "G⁺G ≠ I₂");
        assert!((metric.tangent_projector() - (Matrix3::identity() - n * n.transpose())).amax() < tol);
        // Contravariant basis: a^α · a_β = δ and a^α ⊥ n.
        let (r1, r2) = (metric.pinv.row(0).transpose(), metric.pinv.row(1).transpose());
        assert!((r1.dot(&a1) - 1.0).abs() < tol && r1.dot(&a2).abs() < tol);
        assert!(r2.dot(&a1).abs() < tol && (r2.dot(&a2) - 1.0).abs() < tol);
        assert!(r1.dot(&n).abs() < tol && r2.dot(&n).abs() < tol);
        assert!((n - cross / cross.norm()).amax() < 1e-14);
    }
}

#[test]
fn tangential_symmetric_part_removes_normal_and_skew_parts() {
    let sphere = Surface::SphereSpherical { radius: 2.5 };
    let p = sphere.exact([1.2, 2.0]).reparametrised(&reparametrisations()[1]);
    let metric = SurfaceMetric::try_new(&p.tangent).unwrap();
    let a = metric.tangent_projector();
    let b = second_fundamental_tensor(&metric, &p.normal_gradient);
    let n = metric.normal;
    let (t1, t2) = (p.tangent.column(0).into_owned(), p.tangent.column(1).into_owned());
    let w = Vector3::new(0.3, -0.7, 1.1);
    let perturbed = b + n * w.transpose() + w * n.transpose() * 0.5 + (t1 * t2.transpose() - t2 * t1.transpose()) * 0.3;
    let cleaned = tangential_symmetric_part(&perturbed, &a);
    assert!((cleaned - b).amax() < TOL, "sym(a b a) did not recover b");
    // The curvatures of the raw perturbed tensor differ, those of the cleaned one do not.
    assert!((mean_curvature(&perturbed) - mean_curvature(&b)).abs() > 0.1);
    let from_b = Curvature::from_b(cleaned);
    assert!((from_b.mean + 0.4).abs() < TOL && (from_b.gaussian - 0.16).abs() < TOL);
}

#[test]
fn flat_curvature_is_zero() {
    let flat = Curvature::<f64>::flat();
    assert_eq!(flat.b, Matrix3::zeros());
    assert_eq!((flat.mean, flat.gaussian), (0.0, 0.0));
}

/// The tangent of a sphere of radius `radius` in spherical coordinates, generic in the scalar.
fn sphere_tangent<T: Real>(radius: T, theta: f64, phi: f64) -> Matrix3x2<T> {
    let (st, ct, sp, cp) = (theta.sin(), theta.cos(), phi.sin(), phi.cos());
    Matrix3x2::new(ct * cp, -st * sp, ct * sp, st * cp, -st, 0.0).map(|x| radius * x)
}

#[test]
fn mean_curvature_differentiates_with_respect_to_the_radius() {
    // The normal n = x/R does not depend on R, so ∇_ξ n is constant; only G carries R.
    // H = −1/R ⇒ dH/dR = 1/R², d²H/dR² = −2/R³; K = 1/R² ⇒ dK/dR = −2/R³, d²K/dR² = 6/R⁴.
    for radius in [0.5, 1.0, 2.5] {
        for (theta, phi) in [(0.4, 0.1), (1.2, 2.0), (2.5, -2.7)] {
            let dn = sphere_tangent(1.0, theta, phi);

            let r = Dual64::new(radius, 1.0);
            let metric = SurfaceMetric::try_new(&sphere_tangent(r, theta, phi)).unwrap();
            let b = second_fundamental_tensor(&metric, &dn.map(Dual64::from_re));
            let (h, k) = (mean_curvature(&b), gaussian_curvature(&b));
            assert!((h.re + 1.0 / radius).abs() < 1e-14);
            assert!((h.eps - 1.0 / radius.powi(2)).abs() < 1e-13, "dH/dR = {}", h.eps);
            assert!((k.eps + 2.0 / radius.powi(3)).abs() < 1e-12, "dK/dR = {}", k.eps);
            let curvature = Curvature::from_normal_gradient(&metric, &dn.map(Dual64::from_re));
            assert!((curvature.mean.eps - 1.0 / radius.powi(2)).abs() < 1e-13);

            let r2 = Dual2_64::new(radius, 1.0, 0.0);
            let metric = SurfaceMetric::try_new(&sphere_tangent(r2, theta, phi)).unwrap();
            let b = second_fundamental_tensor(&metric, &dn.map(Dual2_64::from_re));
            let (h, k) = (mean_curvature(&b), gaussian_curvature(&b));
            assert!((h.v1 - 1.0 / radius.powi(2)).abs() < 1e-13);
            assert!((h.v2 + 2.0 / radius.powi(3)).abs() < 1e-12, "d²H/dR² = {}", h.v2);
            assert!((k.v2 - 6.0 / radius.powi(4)).abs() < 1e-11, "d²K/dR² = {}", k.v2);
        }
    }
}

fn assert_degenerate<T: Real>(tangent: Matrix3x2<T>, what: &str) -> (f64, f64, f64) {
    match SurfaceMetric::try_new(&tangent) {
        Err(GeometryError::DegenerateTangent {
            area_element,
            len1,
            len2,
        }) => (area_element, len1, len2),
        Err(e) => panic!("{what}: unexpected error {e}"),
        Ok(m) => panic!("{what}: accepted with normal {:?}", m.normal.map(|x| x.re())),
    }
}

#[test]
fn degenerate_tangents_are_rejected() {
    let a1: Vector3<f64> = Vector3::new(0.3, -1.2, 0.8);
    let perp = Vector3::new(1.2, 0.3, 0.0);
    assert!(a1.dot(&perp).abs() < 1e-15);
    let finite_cases = [
        ("zero", Matrix3x2::zeros()),
        ("first column zero", Matrix3x2::from_columns(&[Vector3::zeros(), a1])),
        ("second column zero", Matrix3x2::from_columns(&[a1, Vector3::zeros()])),
        ("parallel", Matrix3x2::from_columns(&[a1, a1 * 2.5])),
        ("antiparallel", Matrix3x2::from_columns(&[a1, -a1 * 0.1])),
        (
            "parallel within tolerance",
            Matrix3x2::from_columns(&[a1, a1 + perp * 1e-14]),
        ),
    ];
    for (what, g) in finite_cases {
        let (area, len1, len2) = assert_degenerate(g, what);
        assert!(area.is_finite() && len1.is_finite() && len2.is_finite(), "{what}");
        assert!((len1 - g.column(0).norm()).abs() < 1e-15, "{what}: len1");
        assert!((len2 - g.column(1).norm()).abs() < 1e-15, "{what}: len2");
        assert!(area <= DEGENERACY_TOLERANCE * len1 * len2, "{what}: area {area}");
    }
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        for (row, col) in [(0, 0), (2, 1)] {
            let mut g = Matrix3x2::from_columns(&[a1, perp]);
            g[(row, col)] = bad;
            assert_degenerate(g, &format!("{bad} at ({row}, {col})"));
        }
    }
    // The dual-number path rejects the same inputs.
    let g = Matrix3x2::from_columns(&[a1, a1 * 2.5]).map(|x| Dual64::new(x, 1.0));
    assert_degenerate(g, "parallel dual");
    // The message names the failure and the lengths.
    let err = SurfaceMetric::try_new(&Matrix3x2::from_columns(&[a1, Vector3::zeros()])).unwrap_err();
    let text = err.to_string();
    assert!(text.contains("degenerate tangent") && text.contains("0e0"), "{text}");
}

#[test]
fn nearly_parallel_tangent_above_the_tolerance_gives_finite_geometry() {
    let a1: Vector3<f64> = Vector3::new(0.3, -1.2, 0.8);
    let perp = Vector3::new(1.2, 0.3, 0.0);
    let g = Matrix3x2::from_columns(&[a1, a1 + perp * 1e-9]);
    let metric = SurfaceMetric::try_new(&g).unwrap();
    assert!(metric.pinv.iter().all(|x| x.is_finite()));
    assert!(metric.area_element > 0.0 && metric.area_element.is_finite());
    assert!((metric.normal.norm() - 1.0).abs() < 1e-12);
    assert!(metric.normal.dot(&a1).abs() < 1e-6);
    let b = second_fundamental_tensor(&metric, &Matrix3x2::zeros());
    assert!(b.iter().all(|x| x.is_finite()));
    assert!(metric.alternating_tensor().iter().all(|x| x.is_finite()));
}
