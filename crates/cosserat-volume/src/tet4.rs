//! The linear tetrahedron: shape functions and the fixed data of its single quadrature point.
//!
//! Displacements and rotations use the same Tet4 nodes. `F = Σ_i x_i ⊗ ∇N_i` is constant over an element,
//! and so is the gradient of the interpolated rotation field, so the element is integrated with one
//! point at its centroid (weight = rest volume). The point carries its own rotation, advanced with the
//! interpolated angular velocity `ω_p = Σ_k N_k(centroid) ω_k` (the mean of the four nodal ones), as the
//! shell's quadrature points do; one point sees the whole linear field exactly, since its value and
//! gradient determine the four nodal values.

use crate::mesh::signed_volume;
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// The fixed data of a quadrature point of an element with `N` nodes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VolumePoint<const N: usize> {
    /// Column `i`: the rest gradient `∇N_i` of shape function `i` \[1/m\] (row `j` is `∂N_i/∂X_j`).
    pub grad: SMatrix<f64, 3, N>,
    /// Shape-function values at the point.
    pub values: SVector<f64, N>,
    /// Integration weight: quadrature weight times rest volume \[m³\].
    pub weight: f64,
}

/// The point of a Tet4 element with rest node positions `x`: gradients from `[X₁ − X₀, X₂ − X₀, X₃ − X₀]⁻¹`,
/// values `1/4`, weight the rest volume. Returns `None` for a degenerate element.
pub fn tet4_point(x: &[Vector3<f64>; 4]) -> Option<VolumePoint<4>> {
    let dm = Matrix3::from_columns(&[x[1] - x[0], x[2] - x[0], x[3] - x[0]]);
    let inv = dm.try_inverse()?;
    let volume = signed_volume(x);
    if !(volume > 0.0 && inv.iter().all(|v| v.is_finite())) {
        return None;
    }
    // Row a of Dm⁻¹ is ∇N_{a+1}; ∇N₀ = −Σ_a ∇N_{a+1}.
    let mut grad = SMatrix::<f64, 3, 4>::zeros();
    for a in 0..3 {
        let g = inv.row(a).transpose();
        grad.set_column(a + 1, &g);
        let g0 = grad.column(0) - g;
        grad.set_column(0, &g0);
    }
    Some(VolumePoint {
        grad,
        values: SVector::from_element(0.25),
        weight: volume,
    })
}

/// The deformation gradient columns `F e_j = Σ_i x_i ∂N_i/∂X_j` from current nodal positions.
#[inline]
pub fn deformation_gradient<const N: usize>(point: &VolumePoint<N>, x: &[Vector3<f64>; N]) -> [Vector3<f64>; 3] {
    let mut f = [Vector3::zeros(); 3];
    for (i, xi) in x.iter().enumerate() {
        for (j, fj) in f.iter_mut().enumerate() {
            *fj += xi * point.grad[(j, i)];
        }
    }
    f
}

/// The interpolated angular velocity `ω_p = Σ_k N_k ω_k` at the point.
#[inline]
pub fn point_omega<const N: usize>(point: &VolumePoint<N>, omega: &[Vector3<f64>; N]) -> Vector3<f64> {
    let mut w = Vector3::zeros();
    for (k, o) in omega.iter().enumerate() {
        w += o * point.values[k];
    }
    w
}
