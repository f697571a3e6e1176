//! Errors of the geometry layer.

use thiserror::Error;

/// A failure of a geometric construction at a point.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum GeometryError {
    /// The two tangent vectors are (numerically) parallel or zero, so the surface has no normal and
    /// no metric inverse at this point.
    #[error(
        "degenerate tangent: area element {area_element:e} for tangent lengths {len1:e} and {len2:e} \
         (collinear or coincident nodes)"
    )]
    DegenerateTangent {
        /// `|a₁ × a₂|`, the area element.
        area_element: f64,
        /// `|a₁|`.
        len1: f64,
        /// `|a₂|`.
        len2: f64,
    },
}
