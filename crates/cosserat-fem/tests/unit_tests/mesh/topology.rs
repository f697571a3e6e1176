//! Topology: edge counts, boundary loops of the generators, orientation (including the Möbius band).

use super::super::rng;
use cosserat_fem::mesh::procedural::{self, AnnulusSettings};
use cosserat_fem::mesh::{Topology, TriMesh};
use cosserat_fem::{MeshError, Tri3Mesh};
use nalgebra::Vector3;
use rand::Rng;

fn loops(mesh: &Tri3Mesh) -> Vec<Vec<usize>> {
    Topology::new(mesh).boundary_loops().unwrap()
}

/// Every consecutive pair of a loop (cyclically) is a boundary edge, and the loops use every boundary
/// edge exactly once.
fn check_loops_cover_boundary(mesh: &Tri3Mesh) {
    let topology = Topology::new(mesh);
    let loops = topology.boundary_loops().unwrap();
    let mut used = Vec::new();
    for l in &loops {
        for k in 0..l.len() {
            let e = topology.find_edge(l[k], l[(k + 1) % l.len()]).expect("loop step is an edge");
            assert!(topology.is_boundary_edge(e));
            used.push(e);
        }
    }
    used.sort_unstable();
    assert_eq!(used, topology.boundary_edges());
}

#[test]
fn grid_edges_and_boundary() {
    let (nx, ny) = (4, 3);
    let mesh = procedural::rectangle_grid(2.0, 1.0, nx, ny).unwrap().mesh;
    let topology = Topology::new(&mesh);
    // Horizontal, vertical and one diagonal per quad.
    assert_eq!(topology.n_edges(), nx * (ny + 1) + ny * (nx + 1) + nx * ny);
    assert_eq!(topology.boundary_edges().len(), 2 * (nx + ny));
    assert_eq!(topology.euler_characteristic(), 1);
    let loops = loops(&mesh);
    assert_eq!(loops.len(), 1);
    assert_eq!(loops[0].len(), 2 * (nx + ny));
    check_loops_cover_boundary(&mesh);
    // Every edge has one or two faces, and each face lists its edges consistently.
    for f in 0..topology.n_faces() {
        let c = mesh.elements[f];
        for (k, e) in topology.face_edges(f).into_iter().enumerate() {
            let [a, b] = topology.edges()[e];
            assert_eq!([a, b], [c[k].min(c[(k + 1) % 3]), c[k].max(c[(k + 1) % 3])]);
            assert!(topology.edge_faces(e).contains(&f));
        }
    }
    // Vertex → faces agrees with a scan of the element list.
    for v in 0..mesh.n_nodes() {
        let expected: Vec<usize> = (0..mesh.n_elements()).filter(|&f| mesh.elements[f].contains(&v)).collect();
        assert_eq!(topology.vertex_faces(v), expected.as_slice());
    }
}

#[test]
fn boundary_loops_of_the_generators() {
    let annulus = |slit| {
        procedural::annulus(&AnnulusSettings {
            inner_radius: 0.5,
            outer_radius: 1.0,
            n_radial: 3,
            n_angular: 12,
            slit,
        })
        .unwrap()
        .mesh
    };
    let cases: Vec<(&str, Tri3Mesh, usize)> = vec![
        ("grid", procedural::rectangle_grid(1.0, 1.0, 3, 3).unwrap().mesh, 1),
        ("disk", procedural::disk(1.0, 3, 10).unwrap().mesh, 1),
        ("annulus", annulus(false), 2),
        ("slit annulus", annulus(true), 1),
        ("cylinder", procedural::cylinder(1.0, 2.0, 10, 4).unwrap().mesh, 2),
        ("icosphere", procedural::icosphere(1.0, 1).unwrap().mesh, 0),
        ("uv sphere", procedural::uv_sphere(1.0, 8, 5).unwrap().mesh, 0),
        ("hemisphere", procedural::uv_hemisphere(1.0, 8, 3).unwrap().mesh, 1),
        ("möbius", procedural::mobius_strip(1.0, 0.4, 20, 3).unwrap().mesh, 1),
    ];
    for (name, mesh, n_loops) in cases {
        assert_eq!(loops(&mesh).len(), n_loops, "{name}");
        check_loops_cover_boundary(&mesh);
    }
    // The cylinder's loops are its two end circles; the Möbius band's single loop runs twice around.
    let cyl = procedural::cylinder(1.0, 2.0, 10, 4).unwrap().mesh;
    let cyl_loops = loops(&cyl);
    assert!(cyl_loops.iter().all(|l| l.len() == 10));
    for l in &cyl_loops {
        let z = cyl.nodes[l[0]].z;
        assert!(l.iter().all(|&v| cyl.nodes[v].z == z));
    }
    let mobius = procedural::mobius_strip(1.0, 0.4, 20, 3).unwrap().mesh;
    assert_eq!(loops(&mobius)[0].len(), 40);
}

#[test]
fn mobius_band_is_not_orientable() {
    let mobius = procedural::mobius_strip(1.0, 0.4, 12, 2).unwrap().mesh;
    let topology = Topology::new(&mobius);
    assert_eq!(topology.consistent_orientation(), None);
    assert_eq!(topology.euler_characteristic(), 0);
}

/// Whether flipping the faces marked in `flips` makes every interior edge traversed in opposite
/// directions by its two faces.
fn is_consistent(mesh: &Tri3Mesh, flips: &[bool]) -> bool {
    let topology = Topology::new(mesh);
    let oriented: Vec<[usize; 3]> = mesh
        .elements
        .iter()
        .zip(flips)
        .map(|(&[a, b, c], &f)| if f { [a, c, b] } else { [a, b, c] })
        .collect();
    (0..topology.n_edges()).all(|e| {
        let faces = topology.edge_faces(e);
        if faces.len() != 2 {
            return true;
        }
        let [a, b] = topology.edges()[e];
        let forward = |f: usize| (0..3).any(|k| oriented[f][k] == a && oriented[f][(k + 1) % 3] == b);
        forward(faces[0]) != forward(faces[1])
    })
}

#[test]
fn a_tiny_mobius_band_has_no_consistent_orientation_by_exhaustion() {
    // Independent of the propagation: try all 2^6 flip patterns of the 6-triangle band.
    let mobius = procedural::mobius_strip(1.0, 0.4, 3, 1).unwrap().mesh;
    assert_eq!(mobius.n_elements(), 6);
    for pattern in 0u32..64 {
        let flips: Vec<bool> = (0..6).map(|i| pattern >> i & 1 == 1).collect();
        assert!(
            !is_consistent(&mobius, &flips),
            "pattern {pattern:06b} orients the band"
        );
    }
    assert_eq!(Topology::new(&mobius).consistent_orientation(), None);
    // An annulus with the same structure (no twist) is orientable.
    let cylinder = procedural::cylinder(1.0, 0.4, 3, 1).unwrap().mesh;
    assert!(is_consistent(&cylinder, &[false; 6]));
}

#[test]
fn orientation_repairs_randomly_flipped_faces() {
    let mut mesh = procedural::icosphere(1.0, 2).unwrap().mesh;
    assert_eq!(
        Topology::new(&mesh).consistent_orientation(),
        Some(vec![false; mesh.n_elements()])
    );
    let mut rng = rng(77);
    let flipped: Vec<bool> = (0..mesh.n_elements()).map(|_| rng.random_bool(0.3)).collect();
    for (elem, &f) in mesh.elements.iter_mut().zip(&flipped) {
        if f {
            elem.swap(1, 2);
        }
    }
    assert!(!is_consistent(&mesh, &vec![false; mesh.n_elements()]));
    let repair = Topology::new(&mesh).consistent_orientation().expect("a sphere is orientable");
    assert!(is_consistent(&mesh, &repair));
    // Face 0 keeps its orientation, so the repair undoes exactly the random flips relative to face 0.
    for (r, f) in repair.iter().zip(&flipped) {
        assert_eq!(*r, f ^ flipped[0]);
    }
}

#[test]
fn boundary_loops_need_manifold_edges() {
    let nodes = vec![
        Vector3::zeros(),
        Vector3::x(),
        Vector3::y(),
        -Vector3::y(),
        Vector3::z(),
    ];
    let mesh = TriMesh::try_new(nodes, vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]]).unwrap();
    assert_eq!(
        Topology::new(&mesh).boundary_loops(),
        Err(MeshError::NonManifoldEdge { a: 0, b: 1, n_faces: 3 })
    );
    assert_eq!(Topology::new(&mesh).consistent_orientation(), None);
}

#[test]
fn boundary_loops_reject_repeated_vertices() {
    let nodes = vec![
        Vector3::zeros(),
        Vector3::x(),
        Vector3::y(),
        Vector3::new(1.0, 1.0, 0.0),
    ];
    let mesh = TriMesh::try_new(nodes, vec![[0, 1, 2], [1, 3, 3]]).unwrap();
    assert_eq!(
        Topology::new(&mesh).boundary_loops(),
        Err(MeshError::DegenerateElement { elem_idx: 1, area: 0.0 })
    );
}

#[test]
fn a_bow_tie_vertex_splits_into_loops() {
    // Two triangles touching at vertex 0 only. The walk may join both triangles into one cycle through
    // vertex 0 twice; either way the loops cover all six boundary edges exactly once.
    let nodes = vec![
        Vector3::zeros(),
        Vector3::x(),
        Vector3::y(),
        -Vector3::x(),
        -Vector3::y(),
    ];
    let mesh = TriMesh::try_new(nodes, vec![[0, 1, 2], [0, 3, 4]]).unwrap();
    check_loops_cover_boundary(&mesh);
    let total: usize = loops(&mesh).iter().map(Vec::len).sum();
    assert_eq!(total, 6);
}
