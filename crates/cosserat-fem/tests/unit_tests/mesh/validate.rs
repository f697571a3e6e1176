//! Validation: degenerate elements, unreferenced nodes, non-manifold edges, non-finite coordinates.

use cosserat_fem::mesh::procedural;
use cosserat_fem::{MeshError, Tri3Mesh, Tri6Mesh};
use nalgebra::Vector3;

/// Four triangles in a row in the plane; `replace` swaps in a bad element at `bad_idx`.
fn strip_with(bad_idx: usize, bad: [usize; 3], nodes_extra: &[Vector3<f64>]) -> Tri3Mesh {
    let mut nodes: Vec<Vector3<f64>> = (0..3)
        .flat_map(|i| [Vector3::new(i as f64, 0.0, 0.0), Vector3::new(i as f64, 1.0, 0.0)])
        .collect();
    nodes.extend_from_slice(nodes_extra);
    let mut elements = vec![[0, 2, 3], [0, 3, 1], [2, 4, 5], [2, 5, 3]];
    elements[bad_idx] = bad;
    Tri3Mesh { nodes, elements }
}

#[test]
fn a_generated_grid_is_valid() {
    let grid = procedural::rectangle_grid(2.0, 1.0, 4, 3).unwrap();
    grid.mesh.validate().unwrap();
    grid.mesh.to_tri6().validate().unwrap();
    grid.mesh.to_tri10().validate().unwrap();
}

#[test]
fn collinear_nodes_are_degenerate() {
    // Node 6 lies on the segment from node 0 to node 4.
    let mesh = strip_with(2, [0, 6, 4], &[Vector3::new(1.0, 0.0, 0.0)]);
    match mesh.check_degenerate() {
        Err(MeshError::DegenerateElement { elem_idx, area }) => {
            assert_eq!(elem_idx, 2);
            assert!(area.abs() < 1e-15);
        }
        other => panic!("expected a degenerate element, got {other:?}"),
    }
}

#[test]
fn coincident_nodes_are_degenerate() {
    // Node 6 coincides with node 3.
    let mesh = strip_with(1, [0, 3, 6], &[Vector3::new(1.0, 1.0, 0.0)]);
    assert!(matches!(
        mesh.validate(),
        Err(MeshError::DegenerateElement { elem_idx: 1, .. })
    ));
    // A repeated index is the same failure.
    let mesh = strip_with(3, [2, 5, 5], &[]);
    assert!(matches!(
        mesh.check_degenerate(),
        Err(MeshError::DegenerateElement { elem_idx: 3, .. })
    ));
}

#[test]
fn an_element_whose_area_overflows_is_not_called_collinear() {
    // A proper triangle, but its edge vectors' cross product exceeds the largest double.
    let nodes = vec![
        Vector3::new(1e300, 0.0, 0.0),
        Vector3::new(0.0, 1e300, 0.0),
        Vector3::new(-1e300, -1e300, 0.0),
    ];
    let mesh = Tri3Mesh::try_new(nodes, vec![[0, 1, 2]]).unwrap();
    let err = mesh.check_degenerate().unwrap_err();
    assert!(
        matches!(err, MeshError::DegenerateElement { elem_idx: 0, area } if area.is_infinite()),
        "{err:?}"
    );
    let message = err.to_string();
    assert!(
        message.contains("overflows") && !message.contains("collinear"),
        "{message}"
    );
}

#[test]
fn a_tiny_but_proper_element_is_not_degenerate() {
    let nodes = vec![
        Vector3::zeros(),
        Vector3::new(1e-6, 0.0, 0.0),
        Vector3::new(0.0, 1e-6, 0.0),
    ];
    let mesh = Tri3Mesh::try_new(nodes, vec![[0, 1, 2]]).unwrap();
    mesh.validate().unwrap();
}

#[test]
fn a_folded_tri6_element_is_degenerate() {
    // Element 1 is [v00, v11, v01]; its edge 2 runs from v01 to v00 on the boundary. Its mid-edge node
    // moved from ½ to 0.9 along the edge makes the edge map x(s) = 2.6 s − 1.6 s² turn back
    // (x′(1) < 0), so the area element changes sign near corner 0.
    let mut tri6 = procedural::rectangle_grid(1.0, 1.0, 1, 1).unwrap().mesh.to_tri6();
    tri6.validate().unwrap();
    let [a, _, c, _, _, mid] = tri6.elements[1];
    tri6.nodes[mid] = tri6.nodes[c] * 0.1 + tri6.nodes[a] * 0.9;
    match tri6.check_degenerate() {
        Err(MeshError::DegenerateElement { elem_idx, area }) => {
            assert_eq!(elem_idx, 1);
            assert!(
                area < 0.0,
                "the worst signed area element should be negative, got {area}"
            );
        }
        other => panic!("expected a degenerate element, got {other:?}"),
    }
}

#[test]
fn a_mildly_curved_tri6_element_is_valid() {
    let sphere = procedural::icosphere(1.0, 0).unwrap();
    let tri6: Tri6Mesh = sphere.to_tri6_on_surface();
    tri6.validate().unwrap();
}

#[test]
fn unreferenced_nodes_are_reported() {
    let mut mesh = strip_with(0, [0, 2, 3], &[Vector3::new(5.0, 5.0, 0.0)]);
    assert_eq!(mesh.validate(), Err(MeshError::UnreferencedNode { node_idx: 6 }));
    mesh.nodes.pop();
    mesh.validate().unwrap();
}

#[test]
fn non_manifold_edges_are_reported() {
    // A third triangle on edge (2, 3), sticking out of the plane.
    let mut mesh = strip_with(0, [0, 2, 3], &[Vector3::new(1.0, 0.5, 1.0)]);
    mesh.elements.push([3, 2, 6]);
    assert_eq!(
        mesh.validate(),
        Err(MeshError::NonManifoldEdge { a: 2, b: 3, n_faces: 3 })
    );
    assert_eq!(
        mesh.check_manifold_edges(),
        Err(MeshError::NonManifoldEdge { a: 2, b: 3, n_faces: 3 })
    );
}

#[test]
fn doubled_elements_are_reported() {
    // A separate triangle beside the strip, then the same triangle again, once in the same order and
    // once reversed: each of its edges has two faces, so only the corner sets tell.
    let extra = [
        Vector3::new(5.0, 0.0, 0.0),
        Vector3::new(6.0, 0.0, 0.0),
        Vector3::new(5.0, 1.0, 0.0),
    ];
    for doubled in [[6, 7, 8], [8, 7, 6]] {
        let mut mesh = strip_with(0, [0, 2, 3], &extra);
        mesh.elements.push([6, 7, 8]);
        mesh.validate().unwrap();
        mesh.elements.push(doubled);
        let expected = MeshError::DuplicateElement { first: 4, second: 5 };
        assert_eq!(mesh.validate(), Err(expected.clone()));
        assert_eq!(mesh.check_manifold_edges(), Err(expected.clone()));
        assert_eq!(mesh.to_tri6().validate(), Err(expected));
    }
}

#[test]
fn non_finite_coordinates_are_reported() {
    let mut mesh = strip_with(0, [0, 2, 3], &[]);
    mesh.nodes[4].y = f64::NAN;
    assert_eq!(mesh.validate(), Err(MeshError::NonFiniteNode { node_idx: 4 }));
    mesh.nodes[4].y = f64::INFINITY;
    assert_eq!(mesh.check_degenerate(), Err(MeshError::NonFiniteNode { node_idx: 4 }));
}

#[test]
fn out_of_range_indices_are_reported_not_panicked() {
    let mut mesh = strip_with(0, [0, 2, 3], &[]);
    mesh.elements[2] = [2, 4, 17];
    let expected = MeshError::NodeIndexOutOfRange {
        elem_idx: 2,
        node_idx: 17,
        n_nodes: 6,
    };
    assert_eq!(mesh.validate(), Err(expected.clone()));
    assert_eq!(mesh.check_unreferenced(), Err(expected.clone()));
    assert_eq!(mesh.check_manifold_edges(), Err(expected));
}
