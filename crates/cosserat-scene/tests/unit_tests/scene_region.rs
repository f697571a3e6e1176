//! Regions select exactly the expected nodes on small meshes.

use cosserat_assembly::{ElementPair, ShellMesh};
use cosserat_fem::mesh::chord_placement;
use cosserat_fem::mesh::procedural::{AnnulusSettings, annulus, rectangle_grid};
use cosserat_scene::error::RegionError;
use cosserat_scene::expr::ExprContext;
use cosserat_scene::region::{Region, ShellNodes};
use nalgebra::Vector3;

/// The 4 × 2 grid on [−2, 2] × [−1, 1]: vertex (i, j) at (i − 2, j − 1) has index 3i + j.
fn grid(pair: ElementPair) -> ShellNodes {
    let mesh = ShellMesh::from_tri3(rectangle_grid(4.0, 2.0, 4, 2).unwrap().mesh, pair, chord_placement);
    ShellNodes::new("grid", &mesh, pair).unwrap()
}

fn boxed(center: [f64; 3], size: [f64; 3]) -> Region {
    Region::Box {
        center: Vector3::from(center),
        size: Vector3::from(size),
    }
}

#[test]
fn box_faces_are_included() {
    let nodes = grid(ElementPair::Tri3Tri3);
    // x ∈ [−3, −1]: the columns i = 0 and i = 1, the second exactly on the face.
    let s = boxed([-2.0, 0.0, 0.0], [2.0, 2.0, 0.0]).select(&nodes).unwrap();
    assert_eq!(s.disp_nodes, [0, 1, 2, 3, 4, 5]);
    assert_eq!(s.rot_nodes, s.disp_nodes);
    // A hair narrower and the face column drops out.
    let s = boxed([-2.0, 0.0, 0.0], [1.999_999, 2.0, 0.0]).select(&nodes).unwrap();
    assert_eq!(s.disp_nodes, [0, 1, 2]);
    // Nothing in a box beside the mesh (not an error here; the caller decides).
    let s = boxed([5.0, 0.0, 0.0], [1.0, 1.0, 1.0]).select(&nodes).unwrap();
    assert!(s.disp_nodes.is_empty() && s.rot_nodes.is_empty());
}

#[test]
fn displacement_and_rotation_nodes_are_resolved_by_their_own_positions() {
    let positions_in = |nodes: &[Vector3<f64>], selected: &[usize]| -> Vec<(f64, f64)> {
        selected.iter().map(|&i| (nodes[i].x, nodes[i].y)).collect()
    };
    let nodes = grid(ElementPair::Tri6Tri3);
    let s = boxed([-2.0, 0.0, 0.0], [2.0, 2.0, 0.0]).select(&nodes).unwrap();
    // Tri6 nodes with x ∈ {−2, −1.5, −1} and y ∈ {−1, −0.5, 0, 0.5, 1}.
    assert_eq!(s.disp_nodes.len(), 15);
    let mut xy = positions_in(nodes.disp_positions(), &s.disp_nodes);
    xy.sort_by(|a, b| a.partial_cmp(b).unwrap());
    let mut expected = Vec::new();
    for x in [-2.0, -1.5, -1.0] {
        for y in [-1.0, -0.5, 0.0, 0.5, 1.0] {
            expected.push((x, y));
        }
    }
    assert_eq!(xy, expected);
    // Rotation nodes are the corners only.
    assert_eq!(s.rot_nodes, [0, 1, 2, 3, 4, 5]);
    // Quadratic rotations: the rotation nodes are the Tri6 nodes.
    let nodes = grid(ElementPair::Tri6Tri6);
    let s = boxed([-2.0, 0.0, 0.0], [2.0, 2.0, 0.0]).select(&nodes).unwrap();
    assert_eq!(s.rot_nodes, s.disp_nodes);
    assert_eq!(s.rot_nodes.len(), 15);
}

#[test]
fn predicate_selects_where_it_is_true() {
    let nodes = grid(ElementPair::Tri3Tri3);
    let ctx = ExprContext::new();
    let region = Region::Predicate(ctx.predicate("x >= 1.5 - 1e-9 || y > 0.5").unwrap());
    let s = region.select(&nodes).unwrap();
    // Column i = 4 (12, 13, 14) and row j = 2 (2, 5, 8, 11, 14).
    assert_eq!(s.disp_nodes, [2, 5, 8, 11, 12, 13, 14]);
    let region = Region::Predicate(ctx.predicate("x").unwrap());
    assert!(matches!(region.select(&nodes), Err(RegionError::Predicate(_))));
}

#[test]
fn nearest_picks_one_node_with_ties_to_the_lowest_index() {
    let nodes = grid(ElementPair::Tri3Tri3);
    let s = Region::Nearest(Vector3::new(0.4, 0.1, 0.0)).select(&nodes).unwrap();
    assert_eq!((s.disp_nodes.as_slice(), s.rot_nodes.as_slice()), (&[7][..], &[7][..]));
    // (0.5, 0.5) is equally far from vertices 7, 8, 10 and 11.
    let s = Region::Nearest(Vector3::new(0.5, 0.5, 0.0)).select(&nodes).unwrap();
    assert_eq!(s.disp_nodes, [7]);
    // With Tri6 the displacement node is the mid-edge node at (0.5, 0.5); the rotation node a corner.
    let nodes = grid(ElementPair::Tri6Tri3);
    let s = Region::Nearest(Vector3::new(0.45, 0.45, 0.0)).select(&nodes).unwrap();
    let p = nodes.disp_positions()[s.disp_nodes[0]];
    assert_eq!((p.x, p.y), (0.5, 0.5));
    assert_eq!(s.rot_nodes, [7]);
}

#[test]
fn nearest_rejects_points_outside_the_grown_bounding_box() {
    let nodes = grid(ElementPair::Tri3Tri3);
    // Diagonal √20 ≈ 4.47: the box grows by 0.0447 on every side.
    assert!(Region::Nearest(Vector3::new(2.04, 0.0, 0.0)).select(&nodes).is_ok());
    assert!(Region::Nearest(Vector3::new(0.0, 0.0, -0.04)).select(&nodes).is_ok());
    let err = Region::Nearest(Vector3::new(2.05, 0.0, 0.0)).select(&nodes).unwrap_err();
    assert!(
        matches!(
            err,
            RegionError::PointOutsideMesh {
                point: [2.05, 0.0, 0.0],
                ..
            }
        ),
        "{err:?}"
    );
}

#[test]
fn boundary_loop_holds_the_perimeter() {
    let nodes = grid(ElementPair::Tri3Tri3);
    assert_eq!(nodes.n_boundary_loops(), 1);
    let s = Region::BoundaryLoop(0).select(&nodes).unwrap();
    // Every vertex but the interior ones (i = 1, 2, 3 at j = 1: 4, 7, 10).
    assert_eq!(s.disp_nodes, [0, 1, 2, 3, 5, 6, 8, 9, 11, 12, 13, 14]);
    // Tri6: 4 (nx + ny) = 24 perimeter nodes, all on the rectangle's outline.
    let nodes = grid(ElementPair::Tri6Tri3);
    let s = Region::BoundaryLoop(0).select(&nodes).unwrap();
    assert_eq!(s.disp_nodes.len(), 24);
    for &i in &s.disp_nodes {
        let p = nodes.disp_positions()[i];
        assert!(p.x.abs() == 2.0 || p.y.abs() == 1.0, "{p:?}");
    }
    assert_eq!(s.rot_nodes.len(), 12);
    let err = Region::BoundaryLoop(1).select(&nodes).unwrap_err();
    assert!(matches!(
        err,
        RegionError::LoopOutOfRange {
            index: 1,
            n_loops: 1,
            ..
        }
    ));
}

#[test]
fn an_annulus_has_an_inner_and_an_outer_loop() {
    let settings = AnnulusSettings {
        inner_radius: 0.5,
        outer_radius: 1.0,
        n_radial: 2,
        n_angular: 8,
        slit: false,
    };
    let pair = ElementPair::Tri6Tri3;
    let mesh = ShellMesh::from_tri3(annulus(&settings).unwrap().mesh, pair, chord_placement);
    let nodes = ShellNodes::new("annulus", &mesh, pair).unwrap();
    assert_eq!(nodes.n_boundary_loops(), 2);
    let mut radii = Vec::new();
    for k in 0..2 {
        let s = Region::BoundaryLoop(k).select(&nodes).unwrap();
        // 8 corners and 8 chord midpoints per circle.
        assert_eq!(s.disp_nodes.len(), 16);
        assert_eq!(s.rot_nodes.len(), 8);
        let r: Vec<f64> = s.rot_nodes.iter().map(|&i| nodes.rot_positions()[i].norm()).collect();
        assert!(r.iter().all(|&x| (x - r[0]).abs() < 1e-12));
        radii.push(r[0]);
    }
    radii.sort_by(f64::total_cmp);
    assert!((radii[0] - 0.5).abs() < 1e-12 && (radii[1] - 1.0).abs() < 1e-12);
}

#[test]
fn vertex_lists_and_all() {
    let nodes = grid(ElementPair::Tri6Tri3);
    let s = Region::Vertices(vec![14, 0, 14]).select(&nodes).unwrap();
    assert_eq!(
        (s.disp_nodes.as_slice(), s.rot_nodes.as_slice()),
        (&[0, 14][..], &[0, 14][..])
    );
    let err = Region::Vertices(vec![15]).select(&nodes).unwrap_err();
    assert!(matches!(
        err,
        RegionError::VertexOutOfRange {
            vertex: 15,
            n_vertices: 15,
            ..
        }
    ));
    let s = Region::All.select(&nodes).unwrap();
    assert_eq!((s.disp_nodes.len(), s.rot_nodes.len()), (45, 15));
}

#[test]
fn listed_vertices_of_an_edge_select_its_mid_edge_nodes() {
    // The left edge x = −2: vertices 0, 1, 2 (column by column) and, with Tri6, the two mid-edge
    // nodes between them, all at x = −2; the edge's own rotation nodes are the three vertices.
    for pair in [ElementPair::Tri6Tri3, ElementPair::Tri6Tri6] {
        let nodes = grid(pair);
        let s = Region::Vertices(vec![2, 0, 1]).select(&nodes).unwrap();
        assert_eq!(s.disp_nodes.len(), 5, "{pair:?}");
        assert!(
            s.disp_nodes.iter().all(|&i| nodes.disp_positions()[i].x == -2.0),
            "{pair:?}"
        );
        let expected_rot = if pair == ElementPair::Tri6Tri6 { 5 } else { 3 };
        assert_eq!(s.rot_nodes.len(), expected_rot, "{pair:?}");
        assert!(
            s.rot_nodes.iter().all(|&k| nodes.rot_positions()[k].x == -2.0),
            "{pair:?}"
        );
        // The same edge by a predicate: the same nodes.
        let ctx = ExprContext::new();
        let by_predicate = Region::Predicate(ctx.predicate("x <= -2 + 1e-9").unwrap())
            .select(&nodes)
            .unwrap();
        assert_eq!(by_predicate, s, "{pair:?}");
    }
    // Two vertices that share no edge select no mid-edge node.
    let nodes = grid(ElementPair::Tri6Tri3);
    let s = Region::Vertices(vec![0, 2]).select(&nodes).unwrap();
    assert_eq!(s.disp_nodes.len(), 2);
}

#[test]
fn line_loads_count_the_boundary_edges_inside_a_selection() {
    let nodes = grid(ElementPair::Tri3Tri3);
    // The right edge x = 2: vertices 12, 13, 14 and its two boundary edges.
    assert_eq!(nodes.count_boundary_edges(&[12, 13, 14], false), 2);
    // A single corner holds no edge; two opposite corners neither.
    assert_eq!(nodes.count_boundary_edges(&[12], false), 0);
    assert_eq!(nodes.count_boundary_edges(&[0, 14], false), 0);
}

#[test]
fn inconsistent_meshes_are_reported_not_panicked_on() {
    let grid = rectangle_grid(4.0, 2.0, 4, 2).unwrap().mesh;
    let mut mesh = ShellMesh::from_tri3(grid.clone(), ElementPair::Tri6Tri3, chord_placement);
    mesh.tri6.as_mut().unwrap().elements.pop();
    let err = ShellNodes::new("broken", &mesh, ElementPair::Tri6Tri3).unwrap_err();
    assert!(matches!(err, RegionError::Topology { .. }), "{err:?}");
    let tri3 = ShellMesh::from_tri3(grid.clone(), ElementPair::Tri3Tri3, chord_placement);
    assert!(ShellNodes::new("no tri6", &tri3, ElementPair::Tri6Tri3).is_err());
    let mut bad = ShellMesh::from_tri3(grid, ElementPair::Tri3Tri3, chord_placement);
    bad.corners.elements[0][0] = 99;
    assert!(ShellNodes::new("bad index", &bad, ElementPair::Tri3Tri3).is_err());
}

/// The two sides of a slit annulus lie at the same rest positions: only the generator's groups tell
/// them apart. With quadratic elements each side selects its vertices and the mid-edge nodes between
/// them, and a refined mesh has no groups (refinement would not follow them).
#[test]
fn the_groups_of_a_slit_annulus_select_one_side_each() {
    let text = |refine: usize| {
        format!(
            "name = \"slit\"\n[time]\nmode = \"quasi_static\"\nlevels = [1.0]\n\
             [mesh]\ngenerator = \"annulus\"\ninner_radius = 6.0\nradius = 10.0\nn_radial = 2\nn_angular = 24\n\
             slit = true\nelement = \"tri6\"\nrefine = {refine}\n\
             [material]\nmodel = \"plate\"\nthickness = 0.03\nyoungs_modulus = 21e6\npoisson_ratio = 0.0\ndensity = 1.0\nlength_scale = 1e-4\n\
             [[boundary]]\nname = \"clamped\"\nregion = {{ group = \"slit_end\" }}\nposition = {{ exact = true }}\n\
             [[load]]\nname = \"lift\"\nregion = {{ group = \"slit_start\" }}\nforce = [0.0, 0.0, 1.0]\n"
        )
    };
    let dir = std::env::temp_dir();
    let spec =
        cosserat_scene::spec::SceneSpec::from_str(&text(0), "slit.toml", &dir, &[]).unwrap_or_else(|e| panic!("{e}"));
    let nodes = &spec.shells[0].mesh.tri6.as_ref().unwrap().nodes;
    let clamped = &spec.boundaries[0].selection.disp_nodes;
    let lifted = &spec.loads[0].selection.disp_nodes;
    // Three vertices and two mid-edge nodes per side, on the +x axis from r = 6 to 10.
    for side in [clamped, lifted] {
        assert_eq!(side.len(), 5);
        assert!(side.iter().all(|&i| nodes[i].y == 0.0 && (6.0..=10.0).contains(&nodes[i].x)));
    }
    assert!(clamped.iter().all(|i| !lifted.contains(i)), "the sides share no node");
    let err = cosserat_scene::spec::SceneSpec::from_str(&text(1), "slit.toml", &dir, &[]).unwrap_err();
    assert!(err.to_string().contains("no group `slit_end`"), "{err}");
}
