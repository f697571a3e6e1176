//! Uniform refinement.

use cosserat_fem::Tri3Mesh;
use cosserat_fem::mesh::{Topology, procedural};

fn area(mesh: &Tri3Mesh) -> f64 {
    (0..mesh.n_elements())
        .map(|f| {
            let x = mesh.element_nodes(f);
            0.5 * (x[1] - x[0]).cross(&(x[2] - x[0])).norm()
        })
        .sum()
}

#[test]
fn refinement_counts_and_flat_geometry() {
    let mesh = procedural::rectangle_grid(2.0, 1.0, 3, 2).unwrap().mesh;
    let e = Topology::new(&mesh).n_edges();
    let fine = mesh.refine_uniform();
    assert_eq!(fine.n_nodes(), mesh.n_nodes() + e);
    assert_eq!(fine.n_elements(), 4 * mesh.n_elements());
    assert_eq!(&fine.nodes[..mesh.n_nodes()], mesh.nodes.as_slice());
    assert!((area(&fine) - 2.0).abs() < 1e-14);
    // Orientation is kept: every child has normal +z like its parent.
    for f in 0..fine.n_elements() {
        let x = fine.element_nodes(f);
        assert!((x[1] - x[0]).cross(&(x[2] - x[0])).z > 0.0);
    }
    fine.validate().unwrap();
    // Refining equals upgrading to Tri6 and splitting: the new vertices are the Tri6 edge nodes.
    assert_eq!(fine.nodes, mesh.to_tri6().nodes);
}

#[test]
fn the_dumpling_hemisphere_refines_to_the_paper_counts() {
    // experiments.md §2.10: the 8×4 UV hemisphere (17 vertices, 24 triangles) refined three times has
    // 801 vertices and 1536 triangles, and its Tri6 upgrade 3137 nodes.
    let mut hemisphere = procedural::uv_hemisphere(1.0, 8, 2).unwrap();
    assert_eq!((hemisphere.mesh.n_nodes(), hemisphere.mesh.n_elements()), (17, 24));
    for _ in 0..3 {
        hemisphere = hemisphere.refine_on_surface();
    }
    assert_eq!((hemisphere.mesh.n_nodes(), hemisphere.mesh.n_elements()), (801, 1536));
    assert_eq!(hemisphere.to_tri6_on_surface().n_nodes(), 3137);
    for p in &hemisphere.mesh.nodes {
        assert!((p.norm() - 1.0).abs() < 1e-14);
        assert!(p.z >= 0.0);
    }
    assert_eq!(Topology::new(&hemisphere.mesh).boundary_loops().unwrap().len(), 1);
    hemisphere.mesh.validate().unwrap();
}
