//! Rest geometry at quadrature points: source selection, flat and curved cases, mismatch errors.

use cosserat_fem::element::{Tri6, Tri10};
use cosserat_fem::mesh::{
    CurvatureSettings, CurvatureSource, NormalField, NormalWeighting, deviation_from_affine, procedural, rest_geometry,
};
use cosserat_fem::{MeshError, QuadratureRule, Tri3Mesh};

fn settings(source: CurvatureSource) -> CurvatureSettings {
    CurvatureSettings {
        source,
        ..CurvatureSettings::default()
    }
}

#[test]
fn defaults() {
    let s = CurvatureSettings::default();
    assert_eq!(s.source, CurvatureSource::Auto);
    assert_eq!(s.weighting, NormalWeighting::Max);
    assert_eq!(s.curved_tolerance, 1e-9);
}

#[test]
fn a_flat_grid_has_zero_curvature_with_every_source() {
    let grid = procedural::rectangle_grid(2.0, 1.0, 4, 2).unwrap().mesh;
    let tri6 = grid.to_tri6();
    let rule = QuadratureRule::interior_p2();
    for source in [
        CurvatureSource::ExactElement,
        CurvatureSource::AveragedNodalNormals,
        CurvatureSource::Auto,
    ] {
        let g3 = rest_geometry(&grid, &grid, &rule, &settings(source)).unwrap();
        let g6 = rest_geometry(&tri6, &grid, &rule, &settings(source)).unwrap();
        for g in [&g3, &g6] {
            assert_eq!(g.n_points(), 3);
            assert_eq!(g.n_elements(), grid.n_elements());
            assert_eq!(g.points().len(), 3 * grid.n_elements());
            for p in g.points() {
                assert!(p.curvature.b.amax() < 1e-14);
                // Right triangles with legs 0.5: area element J = 2 · area = 0.25.
                assert!((p.metric.area_element - 0.25).abs() < 1e-14);
            }
        }
    }
}

#[test]
fn auto_picks_the_exact_normal_only_for_curved_elements() {
    let sphere = procedural::icosphere(1.0, 1).unwrap();
    let rule = QuadratureRule::for_degree(4).unwrap();
    let curved = sphere.to_tri6_on_surface();
    let straight = sphere.mesh.to_tri6();
    let g_curved = rest_geometry(&curved, &sphere.mesh, &rule, &CurvatureSettings::default()).unwrap();
    let g_straight = rest_geometry(&straight, &sphere.mesh, &rule, &CurvatureSettings::default()).unwrap();
    assert!(g_curved.normal_fields().iter().all(|&f| f == NormalField::ExactElement));
    assert!(
        g_straight
            .normal_fields()
            .iter()
            .all(|&f| f == NormalField::AveragedNodalNormals)
    );
    for f in 0..curved.n_elements() {
        assert!(deviation_from_affine::<Tri6, 6>(&curved.element_nodes(f)) > 1e-3);
        assert!(deviation_from_affine::<Tri6, 6>(&straight.element_nodes(f)) < 1e-15);
    }
    assert!(deviation_from_affine::<Tri10, 10>(&sphere.mesh.to_tri10().element_nodes(0)) < 1e-15);
    // Both fields see the sphere's curvature: H ≈ −1, K ≈ 1 at level 1.
    for g in [&g_curved, &g_straight] {
        for p in g.points() {
            assert!((p.curvature.mean + 1.0).abs() < 0.2, "H = {}", p.curvature.mean);
            assert!((p.curvature.gaussian - 1.0).abs() < 0.4, "K = {}", p.curvature.gaussian);
        }
    }
    // The exact normal of flat elements carries no curvature (model.md §8.3).
    let g_exact_flat = rest_geometry(&straight, &sphere.mesh, &rule, &settings(CurvatureSource::ExactElement)).unwrap();
    assert!(g_exact_flat.points().iter().all(|p| p.curvature.b.amax() < 1e-13));
    // Per-point access agrees with the flat layout.
    assert_eq!(g_curved.at(3, 2), &g_curved.points()[3 * rule.n_points() + 2]);
}

#[test]
fn cylinder_curvature_sign_and_size() {
    // Outward normal: b = −(1/R) e_θ ⊗ e_θ, H = −1/(2R), K = 0.
    let radius = 0.5;
    let cyl = procedural::cylinder(radius, 1.0, 32, 8).unwrap();
    let tri10 = cyl.to_tri10_on_surface();
    let rule = QuadratureRule::dunavant_p6();
    let g = rest_geometry(&tri10, &cyl.mesh, &rule, &CurvatureSettings::default()).unwrap();
    let (mut worst_h, mut worst_k) = (0.0_f64, 0.0_f64);
    for p in g.points() {
        worst_h = worst_h.max((p.curvature.mean + 0.5 / radius).abs());
        worst_k = worst_k.max(p.curvature.gaussian.abs());
    }
    // Measured: 2.9e-3 and round-off; the H error is O(h²) (see the convergence tests).
    assert!(worst_h < 5e-3, "H error {worst_h}");
    assert!(worst_k < 1e-10, "K error {worst_k}");
}

#[test]
fn mismatched_corner_meshes_are_rejected() {
    let grid = procedural::rectangle_grid(1.0, 1.0, 2, 2).unwrap().mesh;
    let other = procedural::rectangle_grid(1.0, 1.0, 2, 3).unwrap().mesh;
    let rule = QuadratureRule::interior_p2();
    let s = CurvatureSettings::default();
    assert!(matches!(
        rest_geometry(&grid.to_tri6(), &other, &rule, &s),
        Err(MeshError::CornerMeshMismatch { .. })
    ));
    let mut moved: Tri3Mesh = grid.clone();
    moved.nodes[4].z = 0.1;
    match rest_geometry(&grid.to_tri6(), &moved, &rule, &s) {
        Err(MeshError::CornerMeshMismatch { reason }) => assert!(reason.contains("element")),
        other => panic!("expected a mismatch, got {other:?}"),
    }
}

#[test]
fn degenerate_elements_are_reported() {
    let mut grid = procedural::rectangle_grid(1.0, 1.0, 2, 2).unwrap().mesh;
    // Collapse vertex 4 (the centre) onto vertex 0: the elements around it degenerate.
    grid.nodes[4] = grid.nodes[0];
    let rule = QuadratureRule::interior_p2();
    let result = rest_geometry(&grid, &grid, &rule, &settings(CurvatureSource::ExactElement));
    assert!(matches!(result, Err(MeshError::DegenerateElement { .. })), "{result:?}");
}
