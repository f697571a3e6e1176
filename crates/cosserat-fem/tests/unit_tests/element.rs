//! Shape functions: partition of unity, Kronecker property, polynomial reproduction and derivatives
//! against finite differences, for every element.

use super::{random_reference_point, rng};
use cosserat_fem::element::{ShapeFunctions, Tri3, Tri6, Tri10, barycentric, interpolate};
use nalgebra::{Matrix3x2, Vector3};

/// Monomials `x^a y^b` with `a + b ≤ degree`, with their exact first and second derivatives.
fn monomials(degree: usize) -> Vec<(i32, i32)> {
    (0..=degree as i32)
        .flat_map(|a| (0..=degree as i32 - a).map(move |b| (a, b)))
        .collect()
}

fn pow(x: f64, k: i32) -> f64 {
    if k <= 0 { 1.0 } else { x.powi(k) }
}

/// `[p, ∂x p, ∂y p, ∂xx p, ∂xy p, ∂yy p]` of `x^a y^b`.
fn monomial_jet(a: i32, b: i32, xi: [f64; 2]) -> [f64; 6] {
    let (x, y) = (xi[0], xi[1]);
    let (af, bf) = (a as f64, b as f64);
    [
        pow(x, a) * pow(y, b),
        af * pow(x, a - 1) * pow(y, b),
        bf * pow(x, a) * pow(y, b - 1),
        af * (af - 1.0) * pow(x, a - 2) * pow(y, b),
        af * bf * pow(x, a - 1) * pow(y, b - 1),
        bf * (bf - 1.0) * pow(x, a) * pow(y, b - 2),
    ]
}

fn check_partition_of_unity<E: ShapeFunctions<N>, const N: usize>(seed: u64) {
    let mut rng = rng(seed);
    for _ in 0..50 {
        let xi = random_reference_point(&mut rng);
        assert!(
            (E::values(xi).sum() - 1.0).abs() < 1e-13,
            "{:?}: Σ N ≠ 1 at {xi:?}",
            E::KIND
        );
        let g = E::gradients(xi);
        assert!(
            g.row(0).sum().abs() < 1e-12 && g.row(1).sum().abs() < 1e-12,
            "{:?}: Σ ∇N ≠ 0",
            E::KIND
        );
        let h = E::second_derivatives(xi);
        for row in 0..3 {
            assert!(h.row(row).sum().abs() < 1e-11, "{:?}: Σ ∇²N ≠ 0", E::KIND);
        }
    }
}

fn check_kronecker<E: ShapeFunctions<N>, const N: usize>() {
    for (j, &xi) in E::nodes().iter().enumerate() {
        let v = E::values(xi);
        for i in 0..N {
            let expected = if i == j { 1.0 } else { 0.0 };
            assert!(
                (v[i] - expected).abs() < 1e-14,
                "{:?}: N_{i}(node {j}) = {}",
                E::KIND,
                v[i]
            );
        }
    }
}

fn check_polynomial_reproduction<E: ShapeFunctions<N>, const N: usize>(seed: u64) {
    let mut rng = rng(seed);
    for (a, b) in monomials(E::DEGREE) {
        let nodal: Vec<f64> = E::nodes().iter().map(|&p| monomial_jet(a, b, p)[0]).collect();
        for _ in 0..20 {
            let xi = random_reference_point(&mut rng);
            let exact = monomial_jet(a, b, xi);
            let (v, g, h) = (E::values(xi), E::gradients(xi), E::second_derivatives(xi));
            let value: f64 = (0..N).map(|i| v[i] * nodal[i]).sum();
            let dx: f64 = (0..N).map(|i| g[(0, i)] * nodal[i]).sum();
            let dy: f64 = (0..N).map(|i| g[(1, i)] * nodal[i]).sum();
            let second: [f64; 3] = [0, 1, 2].map(|r| (0..N).map(|i| h[(r, i)] * nodal[i]).sum());
            let kind = E::KIND;
            assert!(
                (value - exact[0]).abs() < 1e-13,
                "{kind:?}: x^{a} y^{b} value at {xi:?}"
            );
            assert!(
                (dx - exact[1]).abs() < 1e-12 && (dy - exact[2]).abs() < 1e-12,
                "{kind:?}: x^{a} y^{b} gradient"
            );
            for r in 0..3 {
                assert!(
                    (second[r] - exact[3 + r]).abs() < 1e-11,
                    "{kind:?}: x^{a} y^{b} second derivative {r}"
                );
            }
        }
    }
}

/// The basis does not reproduce some monomial of degree + 1 (so `DEGREE` is not understated either).
fn check_degree_is_sharp<E: ShapeFunctions<N>, const N: usize>() {
    let degree = E::DEGREE as i32 + 1;
    let xi = [0.21, 0.37];
    let worst = (0..=degree)
        .map(|a| {
            let b = degree - a;
            let nodal: Vec<f64> = E::nodes().iter().map(|&p| monomial_jet(a, b, p)[0]).collect();
            let v = E::values(xi);
            ((0..N).map(|i| v[i] * nodal[i]).sum::<f64>() - monomial_jet(a, b, xi)[0]).abs()
        })
        .fold(0.0, f64::max);
    assert!(
        worst > 1e-4,
        "{:?} reproduces all monomials of degree {degree}",
        E::KIND
    );
}

/// Central differences of step h have error O(h²) ≈ 1e-10 relative to the O(1–10) derivatives;
/// 1e-7 leaves room for round-off (ε/h ≈ 2e-11 per value).
fn check_derivatives_by_finite_differences<E: ShapeFunctions<N>, const N: usize>(seed: u64) {
    let mut rng = rng(seed);
    let h = 1e-5;
    for _ in 0..20 {
        let xi = random_reference_point(&mut rng);
        let g = E::gradients(xi);
        let d2 = E::second_derivatives(xi);
        let shifted = |dx: f64, dy: f64| [xi[0] + dx, xi[1] + dy];
        let fd1 = (E::values(shifted(h, 0.0)) - E::values(shifted(-h, 0.0))) / (2.0 * h);
        let fd2 = (E::values(shifted(0.0, h)) - E::values(shifted(0.0, -h))) / (2.0 * h);
        assert!((g.row(0).transpose() - fd1).amax() < 1e-7, "{:?}: ∂₁N", E::KIND);
        assert!((g.row(1).transpose() - fd2).amax() < 1e-7, "{:?}: ∂₂N", E::KIND);
        let g11 = (E::gradients(shifted(h, 0.0)) - E::gradients(shifted(-h, 0.0))) / (2.0 * h);
        let g22 = (E::gradients(shifted(0.0, h)) - E::gradients(shifted(0.0, -h))) / (2.0 * h);
        assert!((d2.row(0) - g11.row(0)).amax() < 1e-7, "{:?}: ∂₁₁N", E::KIND);
        assert!((d2.row(1) - g11.row(1)).amax() < 1e-7, "{:?}: ∂₁₂N via ∂₁", E::KIND);
        assert!((d2.row(1) - g22.row(0)).amax() < 1e-7, "{:?}: ∂₁₂N via ∂₂", E::KIND);
        assert!((d2.row(2) - g22.row(1)).amax() < 1e-7, "{:?}: ∂₂₂N", E::KIND);
    }
}

/// For nodes on an affine map `X = A ξ + c`, the interpolated position is the map and the tangent is
/// `A` everywhere.
fn check_affine_geometry<E: ShapeFunctions<N>, const N: usize>(seed: u64) {
    let a = Matrix3x2::new(1.0, 0.3, -0.2, 2.0, 0.5, 0.7);
    let c = Vector3::new(0.1, -1.0, 3.0);
    let nodes: [Vector3<f64>; N] = E::nodes().map(|p| a * nalgebra::Vector2::from(p) + c);
    let mut rng = rng(seed);
    for _ in 0..10 {
        let xi = random_reference_point(&mut rng);
        let exact = a * nalgebra::Vector2::from(xi) + c;
        assert!((E::position(&nodes, xi) - exact).norm() < 1e-13);
        assert!((E::tangent(&nodes, xi) - a).amax() < 1e-12);
        for d in E::position_second_derivatives(&nodes, xi) {
            assert!(d.norm() < 1e-10);
        }
    }
}

fn check_all<E: ShapeFunctions<N>, const N: usize>(seed: u64) {
    assert_eq!(E::KIND.n_nodes(), N);
    assert_eq!(E::KIND.degree(), E::DEGREE);
    check_partition_of_unity::<E, N>(seed);
    check_kronecker::<E, N>();
    check_polynomial_reproduction::<E, N>(seed + 1);
    check_degree_is_sharp::<E, N>();
    check_derivatives_by_finite_differences::<E, N>(seed + 2);
    check_affine_geometry::<E, N>(seed + 3);
}

#[test]
fn tri3_basis() {
    check_all::<Tri3, 3>(10);
}

#[test]
fn tri6_basis() {
    check_all::<Tri6, 6>(20);
}

#[test]
fn tri10_basis() {
    check_all::<Tri10, 10>(30);
}

#[test]
fn tri6_matches_the_supplement_formulas() {
    // Supplement section 3, written out as printed there (expanded polynomials).
    let mut rng = rng(5);
    for _ in 0..20 {
        let [x, y] = random_reference_point(&mut rng);
        let expected = [
            2.0 * x * x + 4.0 * x * y - 3.0 * x + 2.0 * y * y - 3.0 * y + 1.0,
            x * (2.0 * x - 1.0),
            y * (2.0 * y - 1.0),
            4.0 * x * (1.0 - x - y),
            4.0 * x * y,
            4.0 * y * (1.0 - x - y),
        ];
        let v = Tri6::values([x, y]);
        for i in 0..6 {
            assert!((v[i] - expected[i]).abs() < 1e-14);
        }
    }
}

#[test]
fn node_orders_follow_the_conventions() {
    assert_eq!(Tri3::nodes(), [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]);
    assert_eq!(
        Tri6::nodes(),
        [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.5, 0.0], [0.5, 0.5], [0.0, 0.5]]
    );
    // VTK Lagrange order: corners, edges 0→1, 1→2, 2→0 from first to second vertex, centroid.
    let t = 1.0 / 3.0;
    let expected = [
        [0.0, 0.0],
        [1.0, 0.0],
        [0.0, 1.0],
        [t, 0.0],
        [2.0 * t, 0.0],
        [2.0 * t, t],
        [t, 2.0 * t],
        [0.0, 2.0 * t],
        [0.0, t],
        [t, t],
    ];
    for (p, q) in Tri10::nodes().iter().zip(expected.iter()) {
        assert!((p[0] - q[0]).abs() < 1e-15 && (p[1] - q[1]).abs() < 1e-15);
    }
}

#[test]
fn interpolate_and_barycentric() {
    let values = Tri3::values([0.2, 0.5]);
    let data = [
        Vector3::new(1.0, 0.0, 0.0),
        Vector3::new(0.0, 2.0, 0.0),
        Vector3::new(0.0, 0.0, 4.0),
    ];
    let x = interpolate(&values, &data);
    assert!((x - Vector3::new(0.3, 0.4, 2.0)).norm() < 1e-15);
    assert_eq!(barycentric([0.2, 0.5]), [1.0 - 0.2 - 0.5, 0.2, 0.5]);
    // Tangent of a generic Tri6 element equals the tangent built from the gradients by hand.
    let nodes: [Vector3<f64>; 6] =
        std::array::from_fn(|i| Vector3::new(i as f64, (i * i) as f64 * 0.1, 1.0 / (1.0 + i as f64)));
    let xi = [0.3, 0.2];
    let g = Tri6::gradients(xi);
    let mut by_hand = Matrix3x2::zeros();
    for i in 0..6 {
        by_hand.column_mut(0).axpy(g[(0, i)], &nodes[i], 1.0);
        by_hand.column_mut(1).axpy(g[(1, i)], &nodes[i], 1.0);
    }
    assert!((Tri6::tangent(&nodes, xi) - by_hand).amax() < 1e-14);
}
