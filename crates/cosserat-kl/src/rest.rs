//! The rest state of a face: its rest fundamental forms and, per thickness point, the inverse rest metric
//! and the integration weight.
//!
//! The rest forms `ā`, `b̄` come from the rest positions through the same discrete formulas as the
//! current ones, so a curved rest mesh (a sphere patch, the bunny) is stress-free at rest. The shell
//! volume above a face at thickness `ξ` has the area element `√det ḡ(ξ)` with
//! `ḡ(ξ) = ā − 2ξ b̄ + ξ² b̄ ā⁻¹ b̄ = (ā − ξ b̄) ā⁻¹ (ā − ξ b̄)`, so `√(det ḡ(ξ) / det ā) = det(I − ξ S̄)`
//! with the rest shape operator `S̄ = ā⁻¹ b̄`: `1 − 2H̄ξ + K̄ξ²`. The weights include this factor, so the
//! energy is the integral over the exact rest volume of the (constant-curvature) face. It stays positive
//! across the thickness exactly when `h/2` is below every principal radius of curvature `1/|κᵢ|`.
//! [`RestVolume::MidSurface`] is the thin-shell approximation for meshes locally more curved than that:
//! weights without the factor, and the stretch `M = I + ā⁻¹ (g(ξ) − ḡ(ξ))` measured in the mid-surface
//! metric (equal to `ḡ(ξ)⁻¹ g(ξ)` up to relative order `ξ κ`, odd in `ξ`, so energies differ at order
//! `(h κ)²`), which stays defined at any curvature.

use crate::error::{KlError, check_parameter};
use crate::fundamental_form::{first_form, inverse2, second_form, shifted_metric, strain_locals};
use crate::thickness::{MAX_THICKNESS_POINTS, RestVolume, ThicknessRule};
use cosserat_fem::MeshError;
use nalgebra::{Matrix2, SVector};

/// One point of the thickness rule on a face.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThicknessPoint {
    /// Thickness coordinate `ξ` \[m\].
    pub xi: f64,
    /// Integration weight \[m³\]: rule weight × rest face area × `det(I − ξ S̄) = √(det ḡ(ξ) / det ā)`.
    pub weight: f64,
    /// The inverse rest metric `ḡ(ξ)⁻¹` in the face's parameter coordinates ([`RestVolume::Exact`]), or
    /// the inverse mid-surface metric `ā⁻¹` ([`RestVolume::MidSurface`]).
    pub inverse_metric: Matrix2<f64>,
    /// The constant added to the current metric before `inverse_metric` applies: zero
    /// ([`RestVolume::Exact`], so the stretch is `M = ḡ(ξ)⁻¹ g(ξ)`), or `ā − ḡ(ξ)`
    /// ([`RestVolume::MidSurface`], so `M = I + ā⁻¹ (g(ξ) − ḡ(ξ))`: the Green strain of the fibre at `ξ`
    /// measured in the mid-surface metric, which needs no inverse of `ḡ(ξ)`).
    pub metric_offset: Matrix2<f64>,
}

/// The rest data of one stencil.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StencilRest {
    present: [bool; 3],
    area: f64,
    first_form: Matrix2<f64>,
    second_form: Matrix2<f64>,
    points: [ThicknessPoint; MAX_THICKNESS_POINTS],
    n_points: usize,
}

impl StencilRest {
    /// The rest state of face `elem_idx` from the rest coordinates of its stencil (absent neighbours'
    /// coordinates are ignored), for a shell of thickness `h` \[m\] integrated with `rule`.
    ///
    /// # Errors
    /// [`KlError::InvalidParameter`] for a non-positive thickness, [`KlError::Mesh`] with
    /// [`MeshError::DegenerateElement`] for a face of zero area (or a neighbour folded onto it), and
    /// [`KlError::ThickerThanCurvature`] when `h/2` reaches a principal radius of curvature (with
    /// [`RestVolume::Exact`] only).
    pub fn try_new(
        elem_idx: usize,
        x: &SVector<f64, 18>,
        present: [bool; 3],
        thickness: f64,
        rule: &ThicknessRule,
    ) -> Result<Self, KlError> {
        check_parameter("thickness", thickness, thickness > 0.0, "must be finite and positive")?;
        let s = strain_locals(x, present);
        let a = first_form(&s);
        let b = second_form(&s);
        let det_a = a.determinant();
        if !(det_a.is_finite() && det_a > 0.0) {
            return Err(MeshError::DegenerateElement {
                elem_idx,
                area: 0.5 * det_a.max(0.0).sqrt(),
            }
            .into());
        }
        if !b.iter().all(|v| v.is_finite()) {
            // A neighbour folded onto the face (zero normal) gives no mid-edge normal.
            return Err(MeshError::DegenerateElement { elem_idx, area: 0.0 }.into());
        }
        let area = 0.5 * det_a.sqrt();
        let shape = inverse2(&a) * b;
        // Principal curvatures: the eigenvalues of S̄, real because S̄ is self-adjoint with respect to ā.
        let (mean, gauss) = (0.5 * shape.trace(), shape.determinant());
        let kappa_max = mean.abs() + (mean * mean - gauss).max(0.0).sqrt();
        let exact = rule.rest_volume() == RestVolume::Exact;
        if exact && 0.5 * thickness * kappa_max >= 1.0 {
            return Err(KlError::ThickerThanCurvature {
                elem_idx,
                thickness,
                radius: 1.0 / kappa_max,
            });
        }
        let b_ainv_b = b * shape;
        let empty = ThicknessPoint {
            xi: 0.0,
            weight: 0.0,
            inverse_metric: Matrix2::zeros(),
            metric_offset: Matrix2::zeros(),
        };
        let mut points = [empty; MAX_THICKNESS_POINTS];
        for (q, (xi, w)) in rule.points(thickness).enumerate() {
            let g = shifted_metric(&a, &b, &b_ainv_b, xi);
            points[q] = if exact {
                ThicknessPoint {
                    xi,
                    weight: w * area * (1.0 - 2.0 * mean * xi + gauss * xi * xi),
                    inverse_metric: inverse2(&g),
                    metric_offset: Matrix2::zeros(),
                }
            } else {
                ThicknessPoint {
                    xi,
                    weight: w * area,
                    inverse_metric: inverse2(&a),
                    metric_offset: a - g,
                }
            };
        }
        Ok(Self {
            present,
            area,
            first_form: a,
            second_form: b,
            points,
            n_points: rule.n_points(),
        })
    }

    /// Which neighbours of the face exist.
    pub fn present(&self) -> [bool; 3] {
        self.present
    }

    /// Rest area of the face \[m²\].
    pub fn area(&self) -> f64 {
        self.area
    }

    /// The rest first fundamental form `ā` (parameter coordinates).
    pub fn first_form(&self) -> &Matrix2<f64> {
        &self.first_form
    }

    /// The rest second fundamental form `b̄` (parameter coordinates).
    pub fn second_form(&self) -> &Matrix2<f64> {
        &self.second_form
    }

    /// The thickness points.
    pub fn points(&self) -> &[ThicknessPoint] {
        &self.points[..self.n_points]
    }
}
