//! Quadrature rules on the reference triangle `{ξ₁, ξ₂ ≥ 0, ξ₁ + ξ₂ ≤ 1}` (area ½).
//!
//! Rules are plain data: `[f64; 2]` points and weights that already include the area factor, so
//! `Σ wᵢ f(ξᵢ) ≈ ∫ f dξ` and the weights sum to ½. All rules are fully symmetric with positive weights
//! and interior points, which keeps per-point rest data well defined on every element.
//!
//! [`QuadratureRule::for_element_pair`] gives the pairing of the model (model.md §1.1): the
//! supplement's 3-point rule for Tri3/Tri3 and Tri6/Tri3, degree 4 for Tri6/Tri6 and degree 6 for
//! Tri10.

mod table;

use crate::element::ElementKind;
use table::*;

/// A quadrature rule on the reference triangle.
///
/// The point order is part of the per-point state layout of a simulation (rest tensors and point
/// rotations are stored per (element, point)), so the constructors always return the same order.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QuadratureRule {
    points: &'static [[f64; 2]],
    weights: &'static [f64],
    degree: usize,
    name: &'static str,
}

impl QuadratureRule {
    /// The highest degree for which [`QuadratureRule::for_degree`] has a rule.
    pub const MAX_DEGREE: usize = 8;

    /// The 1-point centroid rule, degree 1.
    pub fn centroid() -> Self {
        Self::from_table(&CENTROID_POINTS, &CENTROID_WEIGHTS, 1, "centroid_p1")
    }

    /// The supplement's 3-point interior rule, degree 2: points `(1/6, 1/6), (1/6, 2/3), (2/3, 1/6)`,
    /// weights `1/6` (supplement section 3; Dunavant 1985, degree 2 with interior points).
    pub fn interior_p2() -> Self {
        Self::from_table(&INTERIOR_P2_POINTS, &INTERIOR_P2_WEIGHTS, 2, "interior_p2")
    }

    /// The 6-point rule of degree 3 with equal positive weights (Strang & Fix 1973, one orbit of
    /// points `(a, b, 1 − a − b)` and permutations). Dunavant's 4-point degree-3 rule has a negative
    /// weight and is not used.
    pub fn strang_fix_p3() -> Self {
        Self::from_table(&STRANG_FIX_P3_POINTS, &STRANG_FIX_P3_WEIGHTS, 3, "strang_fix_p3")
    }

    /// Dunavant's 6-point rule of degree 4 (Dunavant 1985, two 3-point orbits).
    pub fn dunavant_p4() -> Self {
        Self::from_table(&DUNAVANT_P4_POINTS, &DUNAVANT_P4_WEIGHTS, 4, "dunavant_p4")
    }

    /// The 7-point rule of degree 5 (Radon 1948; Dunavant 1985): the centroid and two 3-point orbits,
    /// `a = (6 ∓ √15)/21`, weights `(155 ∓ √15)/2400` and `9/80`.
    pub fn dunavant_p5() -> Self {
        Self::from_table(&DUNAVANT_P5_POINTS, &DUNAVANT_P5_WEIGHTS, 5, "dunavant_p5")
    }

    /// Dunavant's 12-point rule of degree 6 (two 3-point orbits and one 6-point orbit).
    pub fn dunavant_p6() -> Self {
        Self::from_table(&DUNAVANT_P6_POINTS, &DUNAVANT_P6_WEIGHTS, 6, "dunavant_p6")
    }

    /// Dunavant's 16-point rule of degree 8 (the centroid, three 3-point orbits and one 6-point
    /// orbit). It also serves degree 7, whose Dunavant rule has a negative weight.
    pub fn dunavant_p8() -> Self {
        Self::from_table(&DUNAVANT_P8_POINTS, &DUNAVANT_P8_WEIGHTS, 8, "dunavant_p8")
    }

    /// Every rule of this module, by increasing degree.
    pub fn all() -> [Self; 7] {
        [
            Self::centroid(),
            Self::interior_p2(),
            Self::strang_fix_p3(),
            Self::dunavant_p4(),
            Self::dunavant_p5(),
            Self::dunavant_p6(),
            Self::dunavant_p8(),
        ]
    }

    /// The rule with the fewest points that integrates every polynomial of degree `degree` exactly,
    /// or `None` above [`QuadratureRule::MAX_DEGREE`]. Degree 0 gives the centroid rule.
    pub fn for_degree(degree: usize) -> Option<Self> {
        Self::all().into_iter().find(|rule| rule.degree >= degree)
    }

    /// The rule the model uses for a displacement/rotation element pair (model.md §1.1): the
    /// supplement's 3-point rule for Tri3/Tri3 and Tri6/Tri3, otherwise the rule of degree
    /// `2 · max(p_u, p_θ)` (Tri6/Tri6 → degree 4, Tri10/anything → degree 6).
    pub fn for_element_pair(displacement: ElementKind, rotation: ElementKind) -> Self {
        match (displacement, rotation) {
            (ElementKind::Tri3 | ElementKind::Tri6, ElementKind::Tri3) => Self::interior_p2(),
            _ => {
                let degree = 2 * displacement.degree().max(rotation.degree());
                // Degrees up to 6 always have a rule.
                Self::for_degree(degree).unwrap_or_else(Self::dunavant_p8)
            }
        }
    }

    fn from_table(points: &'static [[f64; 2]], weights: &'static [f64], degree: usize, name: &'static str) -> Self {
        Self {
            points,
            weights,
            degree,
            name,
        }
    }

    /// The points `(ξ₁, ξ₂)`.
    pub fn points(&self) -> &'static [[f64; 2]] {
        self.points
    }

    /// The weights (summing to the reference area ½).
    pub fn weights(&self) -> &'static [f64] {
        self.weights
    }

    /// The polynomial degree integrated exactly.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The number of points.
    pub fn n_points(&self) -> usize {
        self.points.len()
    }

    /// A short identifier such as `"dunavant_p4"`, for summaries and logs.
    pub fn name(&self) -> &'static str {
        self.name
    }

    /// Iterates over `(point, weight)` pairs.
    pub fn iter(&self) -> impl Iterator<Item = ([f64; 2], f64)> + '_ {
        self.points.iter().copied().zip(self.weights.iter().copied())
    }

    /// `Σ wᵢ f(ξᵢ)`, the rule's approximation of `∫ f dξ` over the reference triangle.
    pub fn integrate(&self, mut f: impl FnMut([f64; 2]) -> f64) -> f64 {
        self.iter().map(|(xi, w)| w * f(xi)).sum()
    }
}
