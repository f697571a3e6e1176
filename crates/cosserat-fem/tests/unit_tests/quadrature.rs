//! Quadrature rules: exactness up to their degree against `∫ ξ₁^a ξ₂^b = a! b! / (a + b + 2)!`, failure
//! one degree higher, weights and points.

use cosserat_fem::QuadratureRule;
use cosserat_fem::element::ElementKind;

fn factorial(n: u32) -> f64 {
    (1..=n).map(f64::from).product()
}

/// The exact integral of `ξ₁^a ξ₂^b` over the reference triangle.
fn exact_monomial_integral(a: u32, b: u32) -> f64 {
    factorial(a) * factorial(b) / factorial(a + b + 2)
}

fn monomial_error(rule: &QuadratureRule, a: u32, b: u32) -> f64 {
    let approx = rule.integrate(|xi| xi[0].powi(a as i32) * xi[1].powi(b as i32));
    (approx - exact_monomial_integral(a, b)).abs()
}

#[test]
fn every_rule_is_exact_up_to_its_degree() {
    for rule in QuadratureRule::all() {
        let d = rule.degree() as u32;
        for a in 0..=d {
            for b in 0..=d - a {
                let err = monomial_error(&rule, a, b);
                assert!(err <= 1e-14, "{}: ξ₁^{a} ξ₂^{b} error {err:e}", rule.name());
            }
        }
    }
}

#[test]
fn every_rule_fails_one_degree_higher() {
    for rule in QuadratureRule::all() {
        let d = rule.degree() as u32 + 1;
        let worst = (0..=d).map(|a| monomial_error(&rule, a, d - a)).fold(0.0, f64::max);
        assert!(
            worst > 1e-10,
            "{} integrates all monomials of degree {d} (worst error {worst:e})",
            rule.name()
        );
    }
}

#[test]
fn weights_sum_to_the_reference_area_and_points_are_interior() {
    for rule in QuadratureRule::all() {
        assert_eq!(rule.points().len(), rule.weights().len());
        assert_eq!(rule.n_points(), rule.points().len());
        let sum: f64 = rule.weights().iter().sum();
        assert!((sum - 0.5).abs() < 1e-15, "{}: Σw = {sum}", rule.name());
        for (&[x, y], &w) in rule.points().iter().zip(rule.weights()) {
            assert!(w > 0.0, "{}: non-positive weight", rule.name());
            assert!(
                x > 0.0 && y > 0.0 && x + y < 1.0,
                "{}: point ({x}, {y}) not interior",
                rule.name()
            );
        }
    }
}

#[test]
fn rules_are_symmetric_under_vertex_permutations() {
    // Each rule must map to itself under the barycentric permutation (l1, l2, l3) -> (l2, l3, l1).
    for rule in QuadratureRule::all() {
        for (&[x, y], &w) in rule.points().iter().zip(rule.weights()) {
            let rotated = [y, 1.0 - x - y];
            let found = rule
                .iter()
                .any(|(p, v)| (p[0] - rotated[0]).abs() < 1e-15 && (p[1] - rotated[1]).abs() < 1e-15 && v == w);
            assert!(found, "{}: ({x}, {y}) has no rotated partner", rule.name());
        }
    }
}

#[test]
fn the_supplement_rule_is_as_printed() {
    let rule = QuadratureRule::interior_p2();
    let t = 1.0 / 6.0;
    assert_eq!(rule.points(), &[[t, t], [t, 2.0 / 3.0], [2.0 / 3.0, t]]);
    assert_eq!(rule.weights(), &[t, t, t]);
}

#[test]
fn the_degree_4_rule_has_the_published_points() {
    // Dunavant (1985), degree 4, to the 15 digits given there.
    let rule = QuadratureRule::dunavant_p4();
    for expected in [
        [0.445948490915965, 0.108103018168070],
        [0.091576213509771, 0.816847572980459],
    ] {
        assert!(
            rule.points()
                .iter()
                .any(|p| (p[0] - expected[0]).abs() < 1e-14 && (p[1] - expected[1]).abs() < 1e-14),
            "{expected:?} missing"
        );
    }
}

#[test]
fn for_degree_picks_the_smallest_sufficient_rule() {
    let expected_points = [1, 1, 3, 6, 6, 7, 12, 16, 16];
    for (d, &n) in expected_points.iter().enumerate() {
        let rule = QuadratureRule::for_degree(d).expect("rule exists");
        assert!(rule.degree() >= d);
        assert_eq!(rule.n_points(), n, "degree {d}");
    }
    assert_eq!(QuadratureRule::for_degree(QuadratureRule::MAX_DEGREE + 1), None);
}

#[test]
fn element_pairs_use_the_model_rules() {
    use ElementKind::{Tri3, Tri6, Tri10};
    assert_eq!(
        QuadratureRule::for_element_pair(Tri3, Tri3),
        QuadratureRule::interior_p2()
    );
    assert_eq!(
        QuadratureRule::for_element_pair(Tri6, Tri3),
        QuadratureRule::interior_p2()
    );
    assert_eq!(QuadratureRule::for_element_pair(Tri6, Tri6).degree(), 4);
    assert_eq!(QuadratureRule::for_element_pair(Tri6, Tri6).n_points(), 6);
    assert_eq!(QuadratureRule::for_element_pair(Tri10, Tri3).degree(), 6);
    assert_eq!(QuadratureRule::for_element_pair(Tri10, Tri6).degree(), 6);
}
