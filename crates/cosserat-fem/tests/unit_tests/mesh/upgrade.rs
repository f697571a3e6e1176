//! Tri3 → Tri6/Tri10 upgrades and corner meshes.

use super::super::{random_reference_point, rng};
use cosserat_fem::element::{ShapeFunctions, Tri3, Tri6, Tri10};
use cosserat_fem::mesh::{NewNode, Topology, procedural};
use cosserat_fem::{Tri3Mesh, Tri6Mesh, TriMesh};
use nalgebra::Vector3;
use rand::seq::SliceRandom;

/// A small non-planar test mesh: the cylinder has interior and boundary edges and wraps around.
fn base() -> Tri3Mesh {
    procedural::cylinder(1.0, 1.5, 7, 3).unwrap().mesh
}

#[test]
fn tri6_upgrade_shares_one_node_per_edge() {
    let mesh = base();
    let topology = Topology::new(&mesh);
    let (v, e) = (mesh.n_nodes(), topology.n_edges());
    let tri6 = mesh.to_tri6();
    assert_eq!(tri6.n_nodes(), v + e);
    assert_eq!(tri6.n_elements(), mesh.n_elements());
    assert_eq!(&tri6.nodes[..v], mesh.nodes.as_slice());
    // Each edge node is used by exactly the faces of its edge.
    let mut uses = vec![0; tri6.n_nodes()];
    for (f, elem) in tri6.elements.iter().enumerate() {
        assert_eq!(elem[..3], mesh.elements[f]);
        for k in 0..3 {
            let (a, b) = (elem[k], elem[(k + 1) % 3]);
            let m = elem[3 + k];
            assert!(m >= v);
            assert_eq!(tri6.nodes[m], (mesh.nodes[a] + mesh.nodes[b]) * 0.5);
            uses[m] += 1;
        }
    }
    for (edge_idx, [a, b]) in topology.edges().iter().enumerate() {
        assert_eq!(
            uses[v + edge_idx],
            topology.edge_faces(edge_idx).len(),
            "edge ({a}, {b})"
        );
    }
    tri6.validate().unwrap();
}

#[test]
fn flat_upgrades_reproduce_the_tri3_geometry() {
    let mesh = base();
    let (tri6, tri10) = (mesh.to_tri6(), mesh.to_tri10());
    let mut rng = rng(3);
    for f in 0..mesh.n_elements() {
        let x3 = mesh.element_nodes(f);
        let (x6, x10) = (tri6.element_nodes(f), tri10.element_nodes(f));
        for _ in 0..5 {
            let xi = random_reference_point(&mut rng);
            let p = Tri3::position(&x3, xi);
            assert!((Tri6::position(&x6, xi) - p).norm() < 1e-14);
            assert!((Tri10::position(&x10, xi) - p).norm() < 1e-14);
            assert!((Tri6::tangent(&x6, xi) - Tri3::tangent(&x3, xi)).amax() < 1e-13);
            assert!((Tri10::tangent(&x10, xi) - Tri3::tangent(&x3, xi)).amax() < 1e-13);
        }
    }
}

#[test]
fn tri10_upgrade_orders_edge_nodes_per_element() {
    let mesh = base();
    let topology = Topology::new(&mesh);
    let (v, e, f) = (mesh.n_nodes(), topology.n_edges(), mesh.n_elements());
    let tri10 = mesh.to_tri10();
    assert_eq!(tri10.n_nodes(), v + 2 * e + f);
    assert_eq!(&tri10.nodes[..v], mesh.nodes.as_slice());
    let third = 1.0 / 3.0;
    for (face, elem) in tri10.elements.iter().enumerate() {
        assert_eq!(elem[..3], mesh.elements[face]);
        let x = mesh.element_nodes(face);
        for k in 0..3 {
            // Seen from this element, edge k runs from corner k to corner k+1.
            let (from, to) = (x[k], x[(k + 1) % 3]);
            let near = tri10.nodes[elem[3 + 2 * k]];
            let far = tri10.nodes[elem[4 + 2 * k]];
            assert!(
                (near - (from * (2.0 * third) + to * third)).norm() < 1e-15,
                "face {face} edge {k}"
            );
            assert!(
                (far - (from * third + to * (2.0 * third))).norm() < 1e-15,
                "face {face} edge {k}"
            );
        }
        assert!((tri10.nodes[elem[9]] - (x[0] + x[1] + x[2]) * third).norm() < 1e-15);
        assert_eq!(elem[9], v + 2 * e + face);
    }
    // Neighbours share the same two node indices on their common edge, in opposite local order when
    // they traverse it in opposite directions.
    for edge_idx in 0..e {
        let faces = topology.edge_faces(edge_idx);
        if faces.len() != 2 {
            continue;
        }
        let nodes_of = |face: usize| {
            let k = topology.face_edges(face).iter().position(|&x| x == edge_idx).unwrap();
            let elem = tri10.elements[face];
            (elem[k], [elem[3 + 2 * k], elem[4 + 2 * k]])
        };
        let (start0, pair0) = nodes_of(faces[0]);
        let (start1, pair1) = nodes_of(faces[1]);
        if start0 == start1 {
            assert_eq!(pair0, pair1);
        } else {
            assert_eq!(pair0, [pair1[1], pair1[0]]);
        }
    }
    tri10.validate().unwrap();
}

#[test]
fn placement_hooks_see_every_new_node_once() {
    let mesh = base();
    let topology = Topology::new(&mesh);
    let n_edges = topology.n_edges();
    let mut edge_calls = 0;
    let tri6 = mesh.to_tri6_with(|node| match node {
        NewNode::Edge { vertices, t, chord } => {
            assert!(vertices[0] < vertices[1]);
            assert_eq!(t, 0.5);
            assert_eq!(chord, (mesh.nodes[vertices[0]] + mesh.nodes[vertices[1]]) * 0.5);
            edge_calls += 1;
            chord + Vector3::z()
        }
        NewNode::Interior { .. } => panic!("Tri6 has no interior nodes"),
    });
    assert_eq!(edge_calls, n_edges);
    for (edge_idx, &[a, b]) in topology.edges().iter().enumerate() {
        let expected = (mesh.nodes[a] + mesh.nodes[b]) * 0.5 + Vector3::z();
        assert_eq!(tri6.nodes[mesh.n_nodes() + edge_idx], expected);
    }
    let (mut edges, mut interiors) = (0, 0);
    let _ = mesh.to_tri10_with(|node| {
        match node {
            NewNode::Edge { t, .. } => {
                assert!((t - 1.0 / 3.0).abs() < 1e-15 || (t - 2.0 / 3.0).abs() < 1e-15);
                edges += 1;
            }
            NewNode::Interior {
                face,
                vertices,
                barycentric,
                chord,
            } => {
                assert_eq!(vertices, mesh.elements[face]);
                assert_eq!(barycentric, [1.0 / 3.0; 3]);
                assert_eq!(chord, node.chord());
                interiors += 1;
            }
        }
        node.chord()
    });
    assert_eq!((edges, interiors), (2 * n_edges, mesh.n_elements()));
}

#[test]
fn upgraded_sphere_nodes_lie_on_the_sphere() {
    let sphere = procedural::icosphere(2.0, 1).unwrap();
    for p in sphere
        .to_tri6_on_surface()
        .nodes
        .iter()
        .chain(sphere.to_tri10_on_surface().nodes.iter())
    {
        assert!((p.norm() - 2.0).abs() < 1e-14);
    }
}

#[test]
fn corner_mesh_of_an_upgrade_is_the_original() {
    let mesh = base();
    let (corners, map) = mesh.to_tri6().corner_mesh();
    assert_eq!(corners, mesh);
    assert_eq!(map, (0..mesh.n_nodes()).collect::<Vec<_>>());
    let (corners10, _) = mesh.to_tri10().corner_mesh();
    assert_eq!(corners10, mesh);
}

#[test]
fn corner_mesh_of_a_shuffled_tri6_mesh() {
    let tri6 = base().to_tri6();
    // Renumber the nodes randomly, as a Tri6 file would.
    let mut perm: Vec<usize> = (0..tri6.n_nodes()).collect();
    perm.shuffle(&mut rng(11));
    let mut nodes = vec![Vector3::zeros(); tri6.n_nodes()];
    for (old, &new) in perm.iter().enumerate() {
        nodes[new] = tri6.nodes[old];
    }
    let elements = tri6.elements.iter().map(|e| e.map(|i| perm[i])).collect();
    let shuffled: Tri6Mesh = TriMesh::try_new(nodes, elements).unwrap();
    let (corners, map) = shuffled.corner_mesh();
    assert_eq!(corners.n_nodes(), base().n_nodes());
    assert_eq!(corners.n_elements(), shuffled.n_elements());
    assert!(map.windows(2).all(|w| w[0] < w[1]));
    for (v, &node) in map.iter().enumerate() {
        assert_eq!(corners.nodes[v], shuffled.nodes[node]);
    }
    for f in 0..shuffled.n_elements() {
        assert_eq!(corners.elements[f].map(|v| map[v]), shuffled.element_corners(f));
    }
    corners.validate().unwrap();
}
