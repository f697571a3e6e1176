//! The quadratic triangle: the paper's main displacement element (supplement section 3).

use super::{ElementKind, ShapeFunctions};
use nalgebra::{SMatrix, SVector};

/// Quadratic Lagrange triangle with nodes `(0,0), (1,0), (0,1)` (corners), then `(½,0), (½,½), (0,½)`
/// (mid-edge nodes of the edges 0–1, 1–2, 2–0).
///
/// With `x = ξ₁`, `y = ξ₂` the basis is the supplement's (section 3; its labels `p₂` and `p₃` are
/// swapped, the functions are right, model.md §1.2):
/// `N₁ = (1−x−y)(1−2x−2y)`, `N₂ = x(2x−1)`, `N₃ = y(2y−1)`, `N₄ = 4x(1−x−y)`, `N₅ = 4xy`,
/// `N₆ = 4y(1−x−y)`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Tri6;

impl ShapeFunctions<6> for Tri6 {
    const DEGREE: usize = 2;
    const KIND: ElementKind = ElementKind::Tri6;

    fn nodes() -> [[f64; 2]; 6] {
        [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.5, 0.0], [0.5, 0.5], [0.0, 0.5]]
    }

    fn values(xi: [f64; 2]) -> SVector<f64, 6> {
        let (x, y) = (xi[0], xi[1]);
        let l = 1.0 - x - y;
        SVector::<f64, 6>::from([
            l * (1.0 - 2.0 * x - 2.0 * y),
            x * (2.0 * x - 1.0),
            y * (2.0 * y - 1.0),
            4.0 * x * l,
            4.0 * x * y,
            4.0 * y * l,
        ])
    }

    fn gradients(xi: [f64; 2]) -> SMatrix<f64, 2, 6> {
        let (x, y) = (xi[0], xi[1]);
        let d1 = 4.0 * x + 4.0 * y - 3.0;
        #[rustfmt::skip]
        let g = SMatrix::<f64, 2, 6>::new(
            d1, 4.0 * x - 1.0, 0.0,           4.0 - 8.0 * x - 4.0 * y, 4.0 * y, -4.0 * y,
            d1, 0.0,           4.0 * y - 1.0, -4.0 * x,                4.0 * x, 4.0 - 4.0 * x - 8.0 * y,
        );
        g
    }

    fn second_derivatives(_xi: [f64; 2]) -> SMatrix<f64, 3, 6> {
        #[rustfmt::skip]
        let h = SMatrix::<f64, 3, 6>::new(
            4.0, 4.0, 0.0, -8.0, 0.0, 0.0,
            4.0, 0.0, 0.0, -4.0, 4.0, -4.0,
            4.0, 0.0, 4.0, 0.0,  0.0, -8.0,
        );
        h
    }
}
