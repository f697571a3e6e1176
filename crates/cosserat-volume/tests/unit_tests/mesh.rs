//! Slab generation (counts, volume, orientation, conformity) and mesh validation errors.

use cosserat_volume::MeshError;
use cosserat_volume::mesh::{TetMesh, signed_volume, slab};
use nalgebra::Vector3;
use std::collections::HashMap;

#[test]
fn slab_counts_volume_and_orientation() {
    let (size, cells) = ([1.0, 0.125, 0.01], [8, 2, 2]);
    let grid = slab(size, cells).unwrap();
    let m = &grid.mesh;
    assert_eq!(m.n_nodes(), 9 * 3 * 3);
    assert_eq!(m.n_elements(), 6 * 8 * 2 * 2);
    m.validate().unwrap();
    let volumes = m.volumes();
    assert!(volumes.iter().all(|&v| v > 0.0));
    let total: f64 = volumes.iter().sum();
    assert!((total - 1.0 * 0.125 * 0.01).abs() < 1e-15);
    // Grid indexing.
    let x = m.nodes[grid.node(8, 2, 2)];
    assert!((x - Vector3::new(0.5, 0.0625, 0.005)).norm() < 1e-15);
    let mid = grid.mid_surface(&m.nodes);
    assert_eq!(mid.len(), 9 * 3);
    assert!(mid.iter().all(|p| p.z.abs() < 1e-15));
}

#[test]
fn slab_faces_are_conforming() {
    // Every triangular face is shared by two tetrahedra inside and owned by one on the boundary; the
    // boundary of an nx × ny × nz box has 4 (nx ny + ny nz + nz nx) triangles.
    let cells = [3, 2, 2];
    let grid = slab([0.3, 0.2, 0.2], cells).unwrap();
    let mut faces: HashMap<[usize; 3], usize> = HashMap::new();
    for el in &grid.mesh.elements {
        for skip in 0..4 {
            let mut f: Vec<usize> = (0..4).filter(|&a| a != skip).map(|a| el[a]).collect();
            f.sort_unstable();
            *faces.entry([f[0], f[1], f[2]]).or_default() += 1;
        }
    }
    assert!(faces.values().all(|&c| c == 1 || c == 2));
    let boundary = faces.values().filter(|&&c| c == 1).count();
    let [nx, ny, nz] = cells;
    assert_eq!(boundary, 4 * (nx * ny + ny * nz + nz * nx));
}

#[test]
fn invalid_meshes_and_parameters_are_reported() {
    assert!(matches!(
        slab([1.0, 0.0, 0.1], [1, 1, 1]),
        Err(MeshError::InvalidParameter { name: "ly", .. })
    ));
    assert!(matches!(
        slab([1.0, 1.0, 0.1], [1, 1, 0]),
        Err(MeshError::InvalidParameter { name: "nz", .. })
    ));
    let nodes = vec![Vector3::zeros(), Vector3::x(), Vector3::y(), Vector3::z()];
    let ok = TetMesh {
        nodes: nodes.clone(),
        elements: vec![[0, 1, 2, 3]],
    };
    ok.validate().unwrap();
    assert!(signed_volume(&ok.element_positions(0)) > 0.0);
    let out_of_range = TetMesh {
        nodes: nodes.clone(),
        elements: vec![[0, 1, 2, 3], [0, 1, 2, 4]],
    };
    assert_eq!(
        out_of_range.validate(),
        Err(MeshError::NodeOutOfRange {
            elem_idx: 1,
            node: 4,
            n_nodes: 4
        })
    );
    let inverted = TetMesh {
        nodes: nodes.clone(),
        elements: vec![[0, 2, 1, 3]],
    };
    assert!(matches!(
        inverted.validate(),
        Err(MeshError::DegenerateElement { elem_idx: 0, .. })
    ));
    let mut bad = nodes.clone();
    bad[3].z = f64::NAN;
    assert_eq!(
        TetMesh {
            nodes: bad,
            elements: vec![[0, 1, 2, 3]]
        }
        .validate(),
        Err(MeshError::NonFiniteNode { node_idx: 3 })
    );
    assert_eq!(
        TetMesh {
            nodes,
            elements: vec![]
        }
        .validate(),
        Err(MeshError::Empty)
    );
}
