//! Errors of the volumetric model: invalid materials and meshes, and a system that would be ill-posed.
//! Solver failures are those of `cosserat-solver` (`NewtonError`, `StepError`, `StaticError`).

use thiserror::Error;

/// An invalid material parameter: the shell material's error, since the volumetric material validates
/// the parameters the two share with the shell's checks ([`cosserat_material::ContinuumParameters`]).
pub use cosserat_material::MaterialError;

/// An invalid tetrahedral mesh or mesh request.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum MeshError {
    /// A generator parameter outside its range.
    #[error("mesh generator parameter `{name}` = {value}: {reason}")]
    InvalidParameter {
        /// The parameter's name.
        name: &'static str,
        /// Its value.
        value: f64,
        /// The admissible range.
        reason: &'static str,
    },
    /// An element refers to a node that does not exist.
    #[error("element {elem_idx} refers to node {node}, but the mesh has {n_nodes} nodes")]
    NodeOutOfRange {
        /// The element.
        elem_idx: usize,
        /// The missing node.
        node: usize,
        /// Number of nodes.
        n_nodes: usize,
    },
    /// A node position is NaN or infinite.
    #[error("node {node_idx} has a non-finite position")]
    NonFiniteNode {
        /// The node.
        node_idx: usize,
    },
    /// An element with (numerically) zero or negative volume: flat, or with its nodes in the wrong
    /// order (the volume `det[x₁ − x₀, x₂ − x₀, x₃ − x₀]/6` must be positive).
    #[error("element {elem_idx} has volume {volume} (relative {relative:e}); it must be positive")]
    DegenerateElement {
        /// The element.
        elem_idx: usize,
        /// Its signed volume \[m³\].
        volume: f64,
        /// The volume over the cube of its longest edge.
        relative: f64,
    },
    /// A mesh without elements.
    #[error("the mesh has no elements")]
    Empty,
}

/// A failure to build a volumetric system.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum BuildError {
    /// The material is invalid.
    #[error(transparent)]
    Material(#[from] MaterialError),
    /// The mesh is invalid.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// An input outside its range that is not a material parameter.
    #[error("`{name}` = {value}: {reason}")]
    InvalidInput {
        /// The field's name.
        name: &'static str,
        /// Its value.
        value: f64,
        /// The admissible range.
        reason: &'static str,
    },
    /// The rotation unknowns would have a singular Hessian at rest: without rotational inertia the
    /// energy alone must fix them, which needs `μ_c > 0` (the uniform rotation mode) and
    /// `μ L_c² b₁ > 0`, `μ L_c² b₂ > 0` (rotation fields whose element averages vanish).
    #[error("rotations are not determined without rotational inertia: {reason}")]
    IllPosedRotations {
        /// Which modulus vanishes.
        reason: &'static str,
    },
}
