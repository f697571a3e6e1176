//! Errors of the element and mesh layer.

use thiserror::Error;

/// A mesh that cannot be used for simulation.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum MeshError {
    /// An element refers to a node index that does not exist.
    #[error("element {elem_idx} refers to node {node_idx}, but the mesh has {n_nodes} nodes")]
    NodeIndexOutOfRange {
        /// Index of the element.
        elem_idx: usize,
        /// The offending node index.
        node_idx: usize,
        /// Number of nodes of the mesh.
        n_nodes: usize,
    },
    /// An element has (numerically) zero area: coincident or collinear nodes.
    #[error("element {elem_idx} is degenerate (area {area:e}): its nodes are coincident or collinear")]
    DegenerateElement {
        /// Index of the element.
        elem_idx: usize,
        /// Its area (or area element at the worst point), in squared length units.
        area: f64,
    },
}
