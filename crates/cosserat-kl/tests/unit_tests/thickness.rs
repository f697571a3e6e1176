//! Gauss–Legendre rules through the thickness.

use cosserat_kl::{KlError, ThicknessRule};

#[test]
fn rules_integrate_monomials_up_to_degree_2n_minus_1_exactly() {
    let h = 0.3;
    for n in 2..=5 {
        let rule = ThicknessRule::try_new(n).unwrap();
        assert_eq!(rule.n_points(), n);
        let pts: Vec<(f64, f64)> = rule.points(h).collect();
        assert_eq!(pts.len(), n);
        for degree in 0..=2 * n {
            let quad: f64 = pts.iter().map(|(x, w)| w * x.powi(degree as i32)).sum();
            // ∫_{−h/2}^{h/2} ξ^k dξ = 0 for odd k, 2 (h/2)^{k+1}/(k+1) for even k.
            let exact = if degree % 2 == 1 {
                0.0
            } else {
                2.0 * (0.5 * h).powi(degree as i32 + 1) / (degree as f64 + 1.0)
            };
            let err = (quad - exact).abs();
            if degree < 2 * n {
                assert!(err < 1e-16, "n = {n}, degree {degree}: {quad} vs {exact}");
            } else {
                // Degree 2n is not integrated exactly by an n-point Gauss rule.
                assert!(err > 1e-3 * exact, "n = {n}: degree {degree} integrated exactly?");
            }
        }
    }
    assert_eq!(ThicknessRule::default().n_points(), 3);
}

#[test]
fn one_point_and_more_than_five_are_rejected() {
    for n in [0, 1, 6] {
        assert!(matches!(
            ThicknessRule::try_new(n),
            Err(KlError::InvalidParameter {
                name: "thickness_points",
                ..
            })
        ));
    }
}
