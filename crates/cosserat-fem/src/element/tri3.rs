//! The linear triangle: the rotation element of every pair, and the Tri3 displacement element.

use super::{ElementKind, ShapeFunctions};
use nalgebra::{SMatrix, SVector};

/// Linear Lagrange triangle, nodes `(0,0), (1,0), (0,1)`:
/// `N₁ = 1 − ξ₁ − ξ₂`, `N₂ = ξ₁`, `N₃ = ξ₂` (model.md §1.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Tri3;

impl ShapeFunctions<3> for Tri3 {
    const DEGREE: usize = 1;
    const KIND: ElementKind = ElementKind::Tri3;

    fn nodes() -> [[f64; 2]; 3] {
        [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]
    }

    fn values(xi: [f64; 2]) -> SVector<f64, 3> {
        SVector::<f64, 3>::new(1.0 - xi[0] - xi[1], xi[0], xi[1])
    }

    fn gradients(_xi: [f64; 2]) -> SMatrix<f64, 2, 3> {
        SMatrix::<f64, 2, 3>::new(-1.0, 1.0, 0.0, -1.0, 0.0, 1.0)
    }

    fn second_derivatives(_xi: [f64; 2]) -> SMatrix<f64, 3, 3> {
        SMatrix::<f64, 3, 3>::zeros()
    }
}
