//! Errors of the Kirchhoff–Love model: invalid parameters, unusable meshes and rest states that the
//! thickness integration cannot handle. All are detected when a model is built, before any evaluation.

use cosserat_fem::MeshError;
use thiserror::Error;

/// A Kirchhoff–Love shell that cannot be built.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum KlError {
    /// A material, shell or system parameter is non-finite or out of range.
    #[error("invalid parameter `{name}` = {value}: {reason}")]
    InvalidParameter {
        /// The parameter's name (`youngs_modulus`, `poisson_ratio`, `thickness`, ...).
        name: &'static str,
        /// The rejected value.
        value: f64,
        /// The admissible range.
        reason: &'static str,
    },
    /// The rest mesh is invalid (bad indices, degenerate or non-manifold elements, ...).
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// The shell is thicker than twice the smallest rest radius of curvature of a face, so the rest volume
    /// folds over itself (`det(I − ξ ā⁻¹ b̄)` vanishes inside the thickness).
    #[error("face {elem_idx}: thickness {thickness} exceeds twice the smallest rest radius of curvature {radius}")]
    ThickerThanCurvature {
        /// Index of the face.
        elem_idx: usize,
        /// The thickness \[m\].
        thickness: f64,
        /// The smallest principal radius of curvature of the face's rest state \[m\].
        radius: f64,
    },
    /// A force couple joins a vertex to itself or to a vertex out of range.
    #[error("couple `{label}`: pair {pair_idx} = ({a}, {b}) is not a pair of distinct vertices below {n_vertices}")]
    InvalidPair {
        /// The couple's label.
        label: String,
        /// Index of the pair.
        pair_idx: usize,
        /// First vertex.
        a: usize,
        /// Second vertex.
        b: usize,
        /// Number of vertices of the system.
        n_vertices: usize,
    },
}

/// Checks that `value` is finite and satisfies `ok`.
pub(crate) fn check_parameter(name: &'static str, value: f64, ok: bool, reason: &'static str) -> Result<(), KlError> {
    if value.is_finite() && ok {
        Ok(())
    } else {
        Err(KlError::InvalidParameter { name, value, reason })
    }
}
