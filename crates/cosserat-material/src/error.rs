//! Errors of the material layer.

use thiserror::Error;

/// Invalid material parameters or an unsupported model combination, detected before any computation.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum MaterialError {
    /// A parameter is non-finite or outside its admissible range.
    #[error("invalid material parameter `{name}` = {value}: {reason}")]
    InvalidParameter {
        /// The parameter's name as in the scene files (`thickness`, `poisson_ratio`, ...).
        name: &'static str,
        /// The rejected value.
        value: f64,
        /// Why it is rejected.
        reason: &'static str,
    },
    /// A combination of model options that has no meaning in this model.
    #[error("unsupported model combination: {0}")]
    Unsupported(&'static str),
}

/// A rest state that cannot be built from a mesh.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum RestStateError {
    /// The mesh is unusable (degenerate element, bad indices, mismatched rotation mesh).
    #[error(transparent)]
    Mesh(#[from] cosserat_fem::MeshError),
    /// The material or model is invalid.
    #[error(transparent)]
    Material(#[from] MaterialError),
    /// The displacement and rotation meshes do not describe the same elements.
    #[error("the rotation mesh has {rot} elements, the displacement mesh {disp}")]
    ElementCountMismatch {
        /// Displacement elements.
        disp: usize,
        /// Rotation elements.
        rot: usize,
    },
}
