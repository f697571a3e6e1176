//! Stencil topology: the vertices across each edge, boundary edges, invalid meshes.

use cosserat_fem::mesh::procedural;
use cosserat_fem::{MeshError, Tri3Mesh};
use cosserat_kl::{KlError, build_stencils};
use nalgebra::Vector3;

#[test]
fn each_neighbour_shares_the_opposite_edge_and_boundary_edges_have_none() {
    let grid = procedural::rectangle_grid(1.0, 1.0, 4, 3).unwrap().mesh;
    let stencils = build_stencils(&grid).unwrap();
    assert_eq!(stencils.len(), grid.n_elements());
    let mut n_boundary = 0;
    for (f, s) in stencils.iter().enumerate() {
        assert_eq!(s.face, grid.elements[f]);
        for i in 0..3 {
            let (a, b) = (s.face[(i + 1) % 3], s.face[(i + 2) % 3]);
            match s.opposite[i] {
                Some(p) => {
                    assert!(!s.face.contains(&p));
                    // The face (a, b, p) exists in the mesh.
                    assert!(grid.elements.iter().any(|e| e.contains(&a) && e.contains(&b) && e.contains(&p)));
                }
                None => n_boundary += 1,
            }
        }
        assert_eq!(s.present(), s.opposite.map(|p| p.is_some()));
        assert_eq!(&s.vertices()[..3], &s.face.map(Some)[..]);
    }
    // The boundary of a 4 × 3 grid has 2 (4 + 3) edges.
    assert_eq!(n_boundary, 14);
}

#[test]
fn a_closed_surface_has_no_boundary_edges() {
    let sphere = procedural::icosphere(1.0, 1).unwrap().mesh;
    assert!(build_stencils(&sphere).unwrap().iter().all(|s| s.present() == [true; 3]));
}

#[test]
fn invalid_meshes_are_rejected_with_their_reason() {
    let nodes = vec![
        Vector3::new(0.0, 0.0, 0.0),
        Vector3::new(1.0, 0.0, 0.0),
        Vector3::new(0.0, 1.0, 0.0),
        Vector3::new(0.0, -1.0, 0.0),
        Vector3::new(0.0, 0.0, 1.0),
    ];
    // Three faces on edge (0, 1).
    let fan = Tri3Mesh {
        nodes: nodes.clone(),
        elements: vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]],
    };
    assert!(matches!(
        build_stencils(&fan),
        Err(KlError::Mesh(MeshError::NonManifoldEdge { a: 0, b: 1, .. }))
    ));
    // Two faces with the same vertices: the stencil would name a vertex twice.
    let pillow = Tri3Mesh {
        nodes: nodes[..3].to_vec(),
        elements: vec![[0, 1, 2], [0, 2, 1]],
    };
    assert!(matches!(
        build_stencils(&pillow),
        Err(KlError::Mesh(MeshError::DuplicateElement { first: 0, second: 1 }))
    ));
    let bad_index = Tri3Mesh {
        nodes: nodes[..3].to_vec(),
        elements: vec![[0, 1, 7]],
    };
    assert!(matches!(build_stencils(&bad_index), Err(KlError::Mesh(_))));
}
