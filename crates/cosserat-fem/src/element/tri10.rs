//! The cubic triangle, for curvature studies and as a higher-order displacement element.

use super::{AffineProduct, ElementKind, ShapeFunctions};
use nalgebra::{SMatrix, SVector};

/// Cubic Lagrange triangle in VTK Lagrange order.
///
/// Nodes: corners `(0,0), (1,0), (0,1)`; then two nodes per edge for the edges 0→1, 1→2, 2→0, each
/// pair ordered from the edge's first to its second vertex (at 1/3 and 2/3); then the centroid.
///
/// With barycentric coordinates `L₁ = 1 − ξ₁ − ξ₂`, `L₂ = ξ₁`, `L₃ = ξ₂` the basis is
/// `½ Lᵢ (3Lᵢ − 1)(3Lᵢ − 2)` at corner `i`, `9/2 Lᵢ Lⱼ (3Lᵢ − 1)` at the edge node next to corner `i`
/// on edge `ij`, and `27 L₁ L₂ L₃` at the centroid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Tri10;

const THIRD: f64 = 1.0 / 3.0;

/// Affine factors `[constant, ∂/∂ξ₁, ∂/∂ξ₂]`.
const L1: [f64; 3] = [1.0, -1.0, -1.0];
const L2: [f64; 3] = [0.0, 1.0, 0.0];
const L3: [f64; 3] = [0.0, 0.0, 1.0];
/// `3Lᵢ − 1` and `3Lᵢ − 2`.
const L1_M1: [f64; 3] = [2.0, -3.0, -3.0];
const L1_M2: [f64; 3] = [1.0, -3.0, -3.0];
const L2_M1: [f64; 3] = [-1.0, 3.0, 0.0];
const L2_M2: [f64; 3] = [-2.0, 3.0, 0.0];
const L3_M1: [f64; 3] = [-1.0, 0.0, 3.0];
const L3_M2: [f64; 3] = [-2.0, 0.0, 3.0];

const fn term(scale: f64, factors: [[f64; 3]; 3]) -> AffineProduct<3> {
    AffineProduct { scale, factors }
}

const BASIS: [AffineProduct<3>; 10] = [
    term(0.5, [L1, L1_M1, L1_M2]),
    term(0.5, [L2, L2_M1, L2_M2]),
    term(0.5, [L3, L3_M1, L3_M2]),
    term(4.5, [L1, L2, L1_M1]),
    term(4.5, [L1, L2, L2_M1]),
    term(4.5, [L2, L3, L2_M1]),
    term(4.5, [L2, L3, L3_M1]),
    term(4.5, [L3, L1, L3_M1]),
    term(4.5, [L3, L1, L1_M1]),
    term(27.0, [L1, L2, L3]),
];

impl ShapeFunctions<10> for Tri10 {
    const DEGREE: usize = 3;
    const KIND: ElementKind = ElementKind::Tri10;

    fn nodes() -> [[f64; 2]; 10] {
        [
            [0.0, 0.0],
            [1.0, 0.0],
            [0.0, 1.0],
            [THIRD, 0.0],
            [2.0 * THIRD, 0.0],
            [2.0 * THIRD, THIRD],
            [THIRD, 2.0 * THIRD],
            [0.0, 2.0 * THIRD],
            [0.0, THIRD],
            [THIRD, THIRD],
        ]
    }

    fn values(xi: [f64; 2]) -> SVector<f64, 10> {
        SVector::<f64, 10>::from_fn(|i, _| BASIS[i].value(xi))
    }

    fn gradients(xi: [f64; 2]) -> SMatrix<f64, 2, 10> {
        let mut g = SMatrix::<f64, 2, 10>::zeros();
        for (i, b) in BASIS.iter().enumerate() {
            let d = b.gradient(xi);
            g[(0, i)] = d[0];
            g[(1, i)] = d[1];
        }
        g
    }

    fn second_derivatives(xi: [f64; 2]) -> SMatrix<f64, 3, 10> {
        let mut h = SMatrix::<f64, 3, 10>::zeros();
        for (i, b) in BASIS.iter().enumerate() {
            let d = b.second_derivatives(xi);
            for row in 0..3 {
                h[(row, i)] = d[row];
            }
        }
        h
    }
}
