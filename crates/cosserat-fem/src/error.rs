//! Errors of the element and mesh layer: invalid meshes, failed normal fields and bad generator input.

use thiserror::Error;

/// A mesh, normal field or generator request that cannot be used for simulation.
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
    /// An element has (numerically) zero area: coincident or collinear nodes, or a curved element
    /// whose area element vanishes or changes sign somewhere.
    #[error("element {elem_idx} is degenerate (area {area:e}): {}", degenerate_cause(*area, "nodes"))]
    DegenerateElement {
        /// Index of the element.
        elem_idx: usize,
        /// Its area (or area element at the worst point), in squared length units.
        area: f64,
    },
    /// A node position has a NaN or infinite coordinate.
    #[error("node {node_idx} has a non-finite coordinate")]
    NonFiniteNode {
        /// Index of the node.
        node_idx: usize,
    },
    /// A node is not used by any element.
    #[error("node {node_idx} is not referenced by any element")]
    UnreferencedNode {
        /// Index of the node.
        node_idx: usize,
    },
    /// An edge is shared by more than two elements.
    #[error("edge ({a}, {b}) is shared by {n_faces} elements; at most two are allowed")]
    NonManifoldEdge {
        /// The smaller vertex index of the edge.
        a: usize,
        /// The larger vertex index of the edge.
        b: usize,
        /// The number of elements sharing it.
        n_faces: usize,
    },
    /// Two elements with the same three corners: a doubled triangle. Its edges have two faces each,
    /// so the edge count alone does not catch it, yet the two faces bound no surface between them and
    /// would double the triangle's mass and stiffness.
    #[error("elements {first} and {second} have the same three corners (a doubled triangle)")]
    DuplicateElement {
        /// Index of the earlier element.
        first: usize,
        /// Index of the later element that repeats its corners.
        second: usize,
    },
    /// A field was evaluated at a point outside the reference triangle.
    #[error("element {elem_idx}: point ({}, {}) lies outside the reference triangle", xi[0], xi[1])]
    OutsideReferenceTriangle {
        /// Index of the element.
        elem_idx: usize,
        /// The reference point.
        xi: [f64; 2],
    },
    /// Two meshes that must describe the same triangles do not.
    #[error("the rotation (corner) mesh does not match the element mesh: {reason}")]
    CornerMeshMismatch {
        /// What differs (element count, or the element whose corners differ).
        reason: String,
    },
    /// A mesh generator got a parameter outside its valid range.
    #[error("{generator}: parameter `{parameter}` = {value} is invalid: {reason}")]
    InvalidParameter {
        /// The generator's name.
        generator: &'static str,
        /// The parameter's name.
        parameter: &'static str,
        /// The value given.
        value: f64,
        /// The valid range or the reason for rejection.
        reason: &'static str,
    },
    /// An operation removed every element of a mesh.
    #[error("{operation} left a mesh without elements")]
    EmptyMesh {
        /// The operation.
        operation: &'static str,
    },
}

/// Why an element of this area (or worst area element) is degenerate, naming its points `nodes`
/// ("nodes", "vertices", "corners"): coincident or collinear points, unless the area is not finite,
/// which only coordinates too large to multiply give (their products overflow), and saying
/// "collinear" there would send the reader looking for a defect the mesh does not have.
pub fn degenerate_cause(area: f64, nodes: &str) -> String {
    if area.is_finite() {
        format!("its {nodes} are coincident or collinear")
    } else {
        format!(
            "its area overflows to {area}: its {nodes} lie too far apart or too far from the origin (coordinates beyond \
             about 1e150 cannot be multiplied in double precision); use smaller units or a transform scale"
        )
    }
}
