//! Construction and bookkeeping of `TriMesh`.

use cosserat_fem::{MeshError, Tri3Mesh, Tri6Mesh};
use nalgebra::Vector3;

fn square() -> Tri3Mesh {
    let nodes = vec![
        Vector3::zeros(),
        Vector3::x(),
        Vector3::new(1.0, 1.0, 0.0),
        Vector3::y(),
    ];
    Tri3Mesh::try_new(nodes, vec![[0, 1, 2], [0, 2, 3]]).unwrap()
}

#[test]
fn try_new_rejects_out_of_range_indices() {
    let nodes = vec![Vector3::zeros(), Vector3::x(), Vector3::y()];
    let err = Tri3Mesh::try_new(nodes, vec![[0, 1, 2], [0, 2, 3]]).unwrap_err();
    assert_eq!(
        err,
        MeshError::NodeIndexOutOfRange {
            elem_idx: 1,
            node_idx: 3,
            n_nodes: 3
        }
    );
}

#[test]
fn accessors() {
    let mesh = square();
    assert_eq!(mesh.n_nodes(), 4);
    assert_eq!(mesh.n_elements(), 2);
    assert_eq!(
        mesh.element_nodes(1),
        [Vector3::zeros(), Vector3::new(1.0, 1.0, 0.0), Vector3::y()]
    );
    assert_eq!(mesh.element_corners(1), [0, 2, 3]);
    let tri6 = Tri6Mesh {
        nodes: vec![Vector3::zeros(); 6],
        elements: vec![[5, 4, 3, 2, 1, 0]],
    };
    assert_eq!(tri6.element_corners(0), [5, 4, 3]);
}

#[test]
fn unreferenced_nodes_are_dropped_in_order() {
    let mut mesh = square();
    mesh.nodes.insert(1, Vector3::new(9.0, 9.0, 9.0));
    mesh.elements = vec![[0, 2, 3], [0, 3, 4]];
    let (compact, map) = mesh.without_unreferenced_nodes();
    assert_eq!(map, vec![Some(0), None, Some(1), Some(2), Some(3)]);
    assert_eq!(compact, square());
}
