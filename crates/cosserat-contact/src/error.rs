//! Errors of the contact layer: invalid parameters and meshes at construction, and states that violate
//! the contact constraint (a gap at or below zero) when a step begins.

use thiserror::Error;

/// A failure to build or update the contact model.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum ContactError {
    /// A parameter is outside its valid range.
    #[error("contact parameter `{name}` = {value}: {reason}")]
    InvalidParameter {
        /// The parameter's name.
        name: &'static str,
        /// The given value.
        value: f64,
        /// Why it is invalid.
        reason: &'static str,
    },
    /// A triangle of a surface or obstacle names a vertex that does not exist.
    #[error("{body} {body_idx}: triangle {tri_idx} names vertex {vertex}, but only {n_vertices} exist")]
    VertexOutOfRange {
        /// "surface" or "obstacle".
        body: &'static str,
        /// Index of the surface or obstacle.
        body_idx: usize,
        /// Index of the triangle in its body.
        tri_idx: usize,
        /// The offending vertex index.
        vertex: usize,
        /// Number of vertices available.
        n_vertices: usize,
    },
    /// A triangle repeats a vertex.
    #[error("{body} {body_idx}: triangle {tri_idx} repeats a vertex {vertices:?}")]
    RepeatedVertex {
        /// "surface" or "obstacle".
        body: &'static str,
        /// Index of the surface or obstacle.
        body_idx: usize,
        /// Index of the triangle in its body.
        tri_idx: usize,
        /// Its vertices.
        vertices: [usize; 3],
    },
    /// A displacement node belongs to two contact surfaces (its thickness would be ambiguous).
    #[error("node {node} belongs to contact surfaces {first} and {second}")]
    NodeInTwoSurfaces {
        /// The global displacement node.
        node: usize,
        /// The first surface.
        first: usize,
        /// The second surface.
        second: usize,
    },
    /// A position array has the wrong length.
    #[error("{what}: {got} positions given, expected {expected}")]
    WrongLength {
        /// What the positions are for.
        what: &'static str,
        /// Expected length.
        expected: usize,
        /// Given length.
        got: usize,
    },
    /// An obstacle index out of range.
    #[error("obstacle {obstacle} does not exist ({n_obstacles} obstacles)")]
    NoSuchObstacle {
        /// The index given.
        obstacle: usize,
        /// Number of obstacles.
        n_obstacles: usize,
    },
    /// A position or velocity is not finite.
    #[error("{what}: non-finite value at vertex {vertex}")]
    NonFinite {
        /// What the values are.
        what: &'static str,
        /// The offending displacement node (for states and unknowns) or obstacle vertex.
        vertex: usize,
    },
    /// Two primitives are at or within their contact thickness: the barrier is infinite there.
    #[error(
        "{kind} pair ({first}, {second}) has gap {gap:e} m ≤ 0 (distance {distance:e} m, thickness {thickness:e} m)"
    )]
    Intersection {
        /// "point-triangle" or "edge-edge".
        kind: &'static str,
        /// The point (contact vertex) or first edge.
        first: usize,
        /// The triangle or second edge.
        second: usize,
        /// Distance minus thickness \[m\].
        gap: f64,
        /// Euclidean distance \[m\].
        distance: f64,
        /// Sum of the two thicknesses \[m\].
        thickness: f64,
    },
}
