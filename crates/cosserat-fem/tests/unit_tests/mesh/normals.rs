//! Normal fields: the exact element normal and averaged nodal normals.

use super::super::{random_reference_point, rng};
use cosserat_fem::element::{ShapeFunctions, Tri3, Tri6, Tri10};
use cosserat_fem::mesh::{AveragedNodalNormals, NormalWeighting, Topology, exact_normal, procedural};
use cosserat_fem::{MeshError, Tri3Mesh};
use cosserat_geometry::surface::{SurfaceMetric, second_fundamental_tensor};
use nalgebra::{Matrix3x2, Vector3};
use rand::Rng;

/// A curved element: the flat reference triangle mapped to 3D with every node moved randomly.
fn random_curved_element<E: ShapeFunctions<N>, const N: usize>(seed: u64) -> [Vector3<f64>; N] {
    let mut rng = rng(seed);
    E::nodes()
        .map(|[x, y]| Vector3::new(x + 0.5 * y, y, 0.2 * x) + Vector3::from_fn(|_, _| rng.random_range(-0.05..0.05)))
}

/// Central differences of the normal with step 1e-6: truncation O(h²) ≈ 1e-12, round-off ε/h ≈ 1e-10.
fn check_exact_normal_gradient<E: ShapeFunctions<N>, const N: usize>(seed: u64) {
    let nodes = random_curved_element::<E, N>(seed);
    let mut rng = rng(seed + 1);
    let h = 1e-6;
    for _ in 0..10 {
        let [x, y] = random_reference_point(&mut rng);
        let sample = exact_normal::<E, N>(&nodes, [x, y]).unwrap();
        assert!((sample.normal.norm() - 1.0).abs() < 1e-14);
        let t = E::tangent(&nodes, [x, y]);
        assert!((sample.normal - t.column(0).cross(&t.column(1)).normalize()).norm() < 1e-14);
        let n = |p: [f64; 2]| exact_normal::<E, N>(&nodes, p).unwrap().normal;
        let fd = Matrix3x2::from_columns(&[
            (n([x + h, y]) - n([x - h, y])) / (2.0 * h),
            (n([x, y + h]) - n([x, y - h])) / (2.0 * h),
        ]);
        assert!(
            (sample.gradient - fd).amax() < 1e-7,
            "{:?}: {}",
            E::KIND,
            (sample.gradient - fd).amax()
        );
        assert!((sample.gradient.transpose() * sample.normal).amax() < 1e-13);
    }
}

#[test]
fn exact_tri6_normal_gradient_matches_finite_differences() {
    check_exact_normal_gradient::<Tri6, 6>(1);
}

#[test]
fn exact_tri10_normal_gradient_matches_finite_differences() {
    check_exact_normal_gradient::<Tri10, 10>(2);
}

#[test]
fn exact_tri3_normal_is_constant() {
    let nodes = random_curved_element::<Tri3, 3>(3);
    let a = exact_normal::<Tri3, 3>(&nodes, [0.1, 0.2]).unwrap();
    let b = exact_normal::<Tri3, 3>(&nodes, [0.7, 0.2]).unwrap();
    assert_eq!(a.normal, b.normal);
    assert_eq!(a.gradient, Matrix3x2::zeros());
}

#[test]
fn exact_normal_of_a_degenerate_element_is_an_error() {
    let nodes = [Vector3::zeros(), Vector3::x(), Vector3::x() * 2.0];
    assert!(exact_normal::<Tri3, 3>(&nodes, [0.2, 0.2]).is_err());
}

#[test]
fn exact_normal_on_a_sphere_gives_tangential_symmetric_b() {
    // Raw b = −∇n G⁺ of the exact normal is tangential and symmetric by construction; with nodes on a
    // sphere of radius 2 it approximates −a/2 (outward normal).
    let radius = 2.0;
    let sphere = procedural::icosphere(radius, 2).unwrap();
    let tri6 = sphere.to_tri6_on_surface();
    let tri10 = sphere.to_tri10_on_surface();
    for (f, xi) in [(0, [0.2, 0.3]), (17, [0.6, 0.1]), (200, [1.0 / 3.0, 1.0 / 3.0])] {
        let (nodes6, nodes10) = (tri6.element_nodes(f), tri10.element_nodes(f));
        // Relative tolerances on H and K at this coarse level (edges of about 0.27 R): the measured
        // errors are up to 1.8 % / 3.7 % for Tri6 and 1.2 % / 2.3 % for Tri10. Their decay under
        // refinement is checked in the convergence tests.
        for (tangent, grad, tol_h, tol_k) in [
            (
                Tri6::tangent(&nodes6, xi),
                exact_normal::<Tri6, 6>(&nodes6, xi).unwrap().gradient,
                0.03,
                0.06,
            ),
            (
                Tri10::tangent(&nodes10, xi),
                exact_normal::<Tri10, 10>(&nodes10, xi).unwrap().gradient,
                0.02,
                0.04,
            ),
        ] {
            let metric = SurfaceMetric::try_new(&tangent).unwrap();
            let b = second_fundamental_tensor(&metric, &grad);
            assert!((b - b.transpose()).amax() < 1e-12);
            assert!((b * metric.normal).norm() < 1e-12 && (b.transpose() * metric.normal).norm() < 1e-12);
            let h = 0.5 * b.trace();
            let k = 0.5 * (b.trace().powi(2) - (b * b).trace());
            assert!((h * radius + 1.0).abs() < tol_h, "H = {h}");
            assert!((k * radius * radius - 1.0).abs() < tol_k, "K = {k}");
        }
    }
}

#[test]
fn averaged_normals_of_the_icosahedron_are_radial() {
    // Every vertex of the icosahedron has five congruent faces around it, so any symmetric weighting
    // gives the radial direction exactly.
    let ico = procedural::icosphere(1.0, 0).unwrap().mesh;
    for weighting in [
        NormalWeighting::Uniform,
        NormalWeighting::Area,
        NormalWeighting::Angle,
        NormalWeighting::Max,
    ] {
        let normals = AveragedNodalNormals::try_new(&ico, weighting).unwrap();
        assert_eq!(normals.weighting(), weighting);
        assert_eq!(normals.n_elements(), 20);
        for f in 0..ico.n_elements() {
            for (k, &v) in ico.elements[f].iter().enumerate() {
                assert!((normals.corner_normals(f)[k] - ico.nodes[v]).norm() < 1e-14);
            }
        }
    }
}

#[test]
fn averaged_normals_agree_across_elements_of_an_oriented_mesh() {
    let mesh = procedural::icosphere(1.0, 2).unwrap().mesh;
    let normals = AveragedNodalNormals::try_new(&mesh, NormalWeighting::Angle).unwrap();
    let max_normals = AveragedNodalNormals::try_new(&mesh, NormalWeighting::Max).unwrap();
    let topology = Topology::new(&mesh);
    for v in 0..mesh.n_nodes() {
        let at = |f: usize| {
            let k = mesh.elements[f].iter().position(|&c| c == v).unwrap();
            normals.corner_normals(f)[k]
        };
        let faces = topology.vertex_faces(v);
        for &f in faces {
            assert!((at(f) - at(faces[0])).norm() < 1e-15);
        }
        // And they are close to the exact (radial) normal: the worst vertex is off by about 0.14 h²
        // (h ≈ 0.27 at level 2).
        assert!((at(faces[0]) - mesh.nodes[v]).norm() < 2e-2);
        // Max's weights are exact when the vertex and its neighbours lie on a sphere.
        for &f in faces {
            let k = mesh.elements[f].iter().position(|&c| c == v).unwrap();
            assert!((max_normals.corner_normals(f)[k] - mesh.nodes[v]).norm() < 1e-14);
        }
    }
}

/// A vertex at the origin with a fan of five faces to a non-planar ring.
fn umbrella() -> Tri3Mesh {
    let mut nodes = vec![Vector3::zeros()];
    let heights = [0.3, -0.1, 0.2, 0.0, -0.25];
    let angles: [f64; 5] = [0.0, 1.1, 2.5, 3.6, 5.0];
    for (t, z) in angles.iter().zip(heights) {
        nodes.push(Vector3::new(t.cos(), t.sin(), z));
    }
    let elements = (0..5).map(|k| [0, 1 + k, 1 + (k + 1) % 5]).collect();
    Tri3Mesh { nodes, elements }
}

#[test]
fn angle_and_area_weights_do_not_depend_on_splitting_a_face() {
    let mesh = umbrella();
    // Split face 0 = [0, 1, 2] at the midpoint of its far edge: two coplanar halves.
    let mut split = mesh.clone();
    split.nodes.push((mesh.nodes[1] + mesh.nodes[2]) * 0.5);
    split.elements[0] = [0, 1, 6];
    split.elements.push([0, 6, 2]);
    let corner = |m: &Tri3Mesh, w| AveragedNodalNormals::try_new(m, w).unwrap().corner_normals(2)[0];
    for w in [NormalWeighting::Angle, NormalWeighting::Area] {
        assert!((corner(&mesh, w) - corner(&split, w)).norm() < 1e-14, "{w:?}");
    }
    assert!((corner(&mesh, NormalWeighting::Uniform) - corner(&split, NormalWeighting::Uniform)).norm() > 1e-3);
}

#[test]
fn averaged_normals_are_oriented_per_element_on_a_mobius_band() {
    let mesh = procedural::mobius_strip(1.0, 0.3, 24, 3).unwrap().mesh;
    let normals = AveragedNodalNormals::try_new(&mesh, NormalWeighting::Angle).unwrap();
    for f in 0..mesh.n_elements() {
        let own = exact_normal::<Tri3, 3>(&mesh.element_nodes(f), [0.0, 0.0]).unwrap().normal;
        for n in normals.corner_normals(f) {
            assert!((n.norm() - 1.0).abs() < 1e-14);
            assert!(n.dot(&own) > 0.8, "element {f}");
        }
        let sample = normals.evaluate(f, [1.0 / 3.0, 1.0 / 3.0]).unwrap();
        assert!(sample.normal.dot(&own) > 0.8);
    }
}

#[test]
fn interpolated_averaged_normal_is_unit_with_the_right_gradient() {
    let mesh = procedural::cylinder(1.0, 1.0, 9, 2).unwrap().mesh;
    let normals = AveragedNodalNormals::try_new(&mesh, NormalWeighting::Angle).unwrap();
    let mut rng = rng(9);
    let h = 1e-6;
    for f in [0, 5, 20] {
        let [x, y] = random_reference_point(&mut rng);
        let s = normals.evaluate(f, [x, y]).unwrap();
        assert!((s.normal.norm() - 1.0).abs() < 1e-14);
        let n = |p: [f64; 2]| normals.evaluate(f, p).unwrap().normal;
        let fd = Matrix3x2::from_columns(&[
            (n([x + h, y]) - n([x - h, y])) / (2.0 * h),
            (n([x, y + h]) - n([x, y - h])) / (2.0 * h),
        ]);
        assert!((s.gradient - fd).amax() < 1e-7);
    }
}

#[test]
fn averaged_normals_of_a_plane_are_constant() {
    let grid = procedural::rectangle_grid(1.0, 1.0, 3, 3).unwrap().mesh;
    let normals = AveragedNodalNormals::try_new(&grid, NormalWeighting::Uniform).unwrap();
    for f in 0..grid.n_elements() {
        let s = normals.evaluate(f, [0.2, 0.2]).unwrap();
        assert!((s.normal - Vector3::z()).norm() < 1e-15);
        assert!(s.gradient.amax() < 1e-15);
    }
}

#[test]
fn averaged_normal_errors() {
    let flat = Tri3Mesh::try_new(
        vec![Vector3::zeros(), Vector3::x(), Vector3::x() * 2.0],
        vec![[0, 1, 2]],
    )
    .unwrap();
    assert!(matches!(
        AveragedNodalNormals::try_new(&flat, NormalWeighting::Angle),
        Err(MeshError::DegenerateElement { elem_idx: 0, .. })
    ));
    let grid = procedural::rectangle_grid(1.0, 1.0, 2, 2).unwrap().mesh;
    let normals = AveragedNodalNormals::try_new(&grid, NormalWeighting::Angle).unwrap();
    assert_eq!(
        normals.evaluate(3, [0.8, 0.5]),
        Err(MeshError::OutsideReferenceTriangle {
            elem_idx: 3,
            xi: [0.8, 0.5]
        })
    );
    assert!(normals.evaluate(3, [f64::NAN, 0.5]).is_err());
    // The closed triangle, corners included, is fine.
    for xi in [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.5, 0.5]] {
        normals.evaluate(3, xi).unwrap();
    }
}
