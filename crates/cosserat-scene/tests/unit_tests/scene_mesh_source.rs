//! The mesh pipeline: generators, OBJ input, refinement, projections, transforms, initial positions.

use cosserat_assembly::ElementPair;
use cosserat_fem::MeshError;
use cosserat_fem::mesh::Topology;
use cosserat_scene::error::MeshSourceError;
use cosserat_scene::mesh_source::{
    Generator, MAX_ELEMENTS, MeshRecipe, MeshSource, RigidMotion, Scaling, SphereProjection, Transform, build_mesh,
};
use nalgebra::{Matrix3, Rotation3, Vector3};
use std::path::Path;

fn recipe(source: MeshSource, pair: ElementPair) -> MeshRecipe {
    MeshRecipe {
        source,
        pair,
        refine: 0,
        weld: None,
        project_to_sphere: None,
        flatten_cap: None,
        transform: None,
        initial: None,
    }
}

fn fixture(name: &str) -> MeshSource {
    MeshSource::Obj(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data").join(name))
}

#[test]
fn icosphere_cap_reproduces_the_buckling_circles_input_mesh() {
    // experiments.md §2.8: 71 vertices, 120 triangles, 20 boundary edges; Tri6/Tri3: 261 nodes.
    let cap = Generator::IcosphereCap {
        radius: 1.0,
        frequency: 4,
        min_z: 0.25,
    };
    let built = build_mesh(&recipe(MeshSource::Generator(cap), ElementPair::Tri6Tri3)).unwrap();
    let corners = &built.mesh.corners;
    assert_eq!((corners.n_nodes(), corners.n_elements()), (71, 120));
    assert_eq!(Topology::new(corners).boundary_edges().len(), 20);
    let tri6 = built.mesh.tri6.as_ref().unwrap();
    assert_eq!(tri6.n_nodes(), 261);
    // Curved Tri6: every node, mid-edge ones included, on the unit sphere, and within the cap.
    assert!(tri6.nodes.iter().all(|p| (p.norm() - 1.0).abs() < 1e-14));
    assert!(corners.nodes.iter().all(|p| p.z >= 0.25));
    assert!(corners.nodes.iter().any(|p| (p - Vector3::z()).norm() < 1e-14));
}

#[test]
fn an_icosphere_cap_above_every_triangle_names_min_z() {
    let cap = Generator::IcosphereCap {
        radius: 1.0,
        frequency: 4,
        min_z: 2.0,
    };
    let err = build_mesh(&recipe(MeshSource::Generator(cap), ElementPair::Tri6Tri3)).unwrap_err();
    assert!(
        matches!(
            err,
            MeshSourceError::Generator(MeshError::InvalidParameter { parameter: "min_z", .. })
        ),
        "{err:?}"
    );
    assert!(err.to_string().contains("keeps no triangle"), "{err}");
}

#[test]
fn flatten_cap_gives_a_disk_with_nodes_on_the_circle() {
    let cap = Generator::IcosphereCap {
        radius: 1.0,
        frequency: 4,
        min_z: 0.25,
    };
    let mut r = recipe(MeshSource::Generator(cap), ElementPair::Tri6Tri3);
    r.flatten_cap = Some(0.025);
    let built = build_mesh(&r).unwrap();
    let tri6 = built.mesh.tri6.as_ref().unwrap();
    assert!(tri6.nodes.iter().all(|p| p.z == 0.0));
    for (v, p) in built.mesh.corners.nodes.iter().enumerate() {
        // Corner vertices and their Tri6 nodes stay identical.
        assert_eq!(*p, tri6.nodes[built.mesh.corner_nodes[v]]);
    }
    // Interior nodes keep their projected radius 0.025·sin(θ) < 0.025·√(1 − 0.25²) = 0.0242;
    // perimeter nodes sit on the circle.
    let mut radii: Vec<f64> = tri6.nodes.iter().map(|p| p.norm()).collect();
    radii.sort_by(f64::total_cmp);
    let on_circle = radii.iter().filter(|&&r| (r - 0.025).abs() < 1e-15).count();
    assert_eq!(on_circle, 40);
    assert!(radii[radii.len() - 41] < 0.025 * (1.0 - 0.25_f64 * 0.25).sqrt());
}

#[test]
fn obj_meshes_refine_on_chords_and_project_to_a_sphere() {
    let mut r = recipe(fixture("octahedron.obj"), ElementPair::Tri6Tri3);
    r.refine = 2;
    let flat = build_mesh(&r).unwrap();
    // Each refinement: V ← V + E, F ← 4F (octahedron: 6 + 12 = 18, then 18 + 48 = 66).
    assert_eq!((flat.mesh.corners.n_nodes(), flat.mesh.corners.n_elements()), (66, 128));
    // Chord refinement keeps the new vertices on the flat faces: |x| + |y| + |z| = 1.
    assert!(flat.mesh.corners.nodes.iter().all(|p| (p.abs().sum() - 1.0).abs() < 1e-15));
    r.project_to_sphere = Some(SphereProjection {
        center: Vector3::new(0.0, 0.0, 0.5),
        radius: 2.0,
    });
    let round = build_mesh(&r).unwrap();
    let tri6 = round.mesh.tri6.as_ref().unwrap();
    assert!(
        tri6.nodes
            .iter()
            .all(|p| ((p - Vector3::new(0.0, 0.0, 0.5)).norm() - 2.0).abs() < 1e-14)
    );
}

#[test]
fn obj_tri6_nodes_sit_at_chord_midpoints() {
    let built = build_mesh(&recipe(fixture("square_with_attributes.obj"), ElementPair::Tri6Tri3)).unwrap();
    let tri6 = built.mesh.tri6.as_ref().unwrap();
    for element in &tri6.elements {
        for (k, (a, b)) in [(0, 1), (1, 2), (2, 0)].into_iter().enumerate() {
            let mid = (tri6.nodes[element[a]] + tri6.nodes[element[b]]) * 0.5;
            assert_eq!(tri6.nodes[element[3 + k]], mid);
        }
    }
    let tri3 = build_mesh(&recipe(fixture("square_with_attributes.obj"), ElementPair::Tri3Tri3)).unwrap();
    assert!(tri3.mesh.tri6.is_none());
}

#[test]
fn generated_tri6_nodes_lie_on_the_exact_surface() {
    let cylinder = Generator::Cylinder {
        radius: 0.3,
        length: 1.0,
        n_around: 8,
        n_along: 2,
    };
    let built = build_mesh(&recipe(MeshSource::Generator(cylinder), ElementPair::Tri6Tri3)).unwrap();
    let tri6 = built.mesh.tri6.as_ref().unwrap();
    assert!(tri6.nodes.iter().all(|p| (p.xy().norm() - 0.3).abs() < 1e-15));
}

#[test]
fn transform_rotates_centres_and_scales_to_a_height() {
    let mut r = recipe(fixture("octahedron.obj"), ElementPair::Tri6Tri3);
    let rotation = *Rotation3::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_2).matrix();
    r.transform = Some(Transform {
        rotation,
        center: true,
        scaling: Some(Scaling::Height(0.2)),
        translation: Vector3::new(1.0, 0.0, 0.0),
    });
    let built = build_mesh(&r).unwrap();
    let nodes = &built.mesh.tri6.as_ref().unwrap().nodes;
    // The octahedron's y axis becomes z: vertex (0, 1, 0) goes to (0, 0, 1), then scaled by 0.1 and moved.
    assert!(
        (nodes[2] - Vector3::new(1.0, 0.0, 0.1)).norm() < 1e-15,
        "{:?}",
        nodes[2]
    );
    assert!(
        (nodes[4] - Vector3::new(1.0, -0.1, 0.0)).norm() < 1e-15,
        "{:?}",
        nodes[4]
    );
}

#[test]
fn initial_positions_are_a_rigid_motion_of_the_rest_positions() {
    let mut r = recipe(
        MeshSource::Generator(Generator::Rectangle {
            lx: 2.0,
            ly: 1.0,
            nx: 2,
            ny: 1,
        }),
        ElementPair::Tri6Tri3,
    );
    let rotation = *Rotation3::from_axis_angle(&Vector3::z_axis(), std::f64::consts::FRAC_PI_2).matrix();
    r.initial = Some(RigidMotion {
        rotation,
        about: Vector3::new(1.0, 0.0, 0.0),
        translation: Vector3::new(0.0, 0.0, 0.5),
    });
    let built = build_mesh(&r).unwrap();
    let rest = &built.mesh.tri6.as_ref().unwrap().nodes;
    let initial = built.initial_positions.unwrap();
    assert_eq!(initial.len(), rest.len());
    for (x, q) in rest.iter().zip(&initial) {
        // A quarter turn about the vertical line through (1, 0): (x, y) ↦ (1 − y, x − 1), then z + 0.5.
        let expected = Vector3::new(1.0 - x.y, x.x - 1.0, x.z + 0.5);
        assert!((q - expected).norm() < 1e-15);
    }
    assert!(
        build_mesh(&recipe(
            MeshSource::Generator(Generator::Rectangle {
                lx: 2.0,
                ly: 1.0,
                nx: 2,
                ny: 1
            }),
            ElementPair::Tri6Tri3
        ))
        .unwrap()
        .initial_positions
        .is_none()
    );
}

#[test]
fn impossible_steps_are_errors() {
    let flat = MeshSource::Generator(Generator::Rectangle {
        lx: 1.0,
        ly: 1.0,
        nx: 2,
        ny: 2,
    });
    let mut r = recipe(flat.clone(), ElementPair::Tri3Tri3);
    r.transform = Some(Transform {
        rotation: Matrix3::identity(),
        center: true,
        scaling: Some(Scaling::Height(1.0)),
        translation: Vector3::zeros(),
    });
    assert!(matches!(
        build_mesh(&r),
        Err(MeshSourceError::Invalid {
            step: "transform.height",
            ..
        })
    ));
    // The grid's centre vertex is the sphere's centre.
    let mut r = recipe(flat, ElementPair::Tri3Tri3);
    r.project_to_sphere = Some(SphereProjection {
        center: Vector3::zeros(),
        radius: 1.0,
    });
    assert!(matches!(
        build_mesh(&r),
        Err(MeshSourceError::Invalid {
            step: "project_to_sphere",
            ..
        })
    ));
    let bad = Generator::Rectangle {
        lx: -1.0,
        ly: 1.0,
        nx: 2,
        ny: 2,
    };
    assert!(matches!(
        build_mesh(&recipe(MeshSource::Generator(bad), ElementPair::Tri3Tri3)),
        Err(MeshSourceError::Generator(_))
    ));
    assert!(matches!(
        build_mesh(&recipe(fixture("quad_face.obj"), ElementPair::Tri3Tri3)),
        Err(MeshSourceError::Obj(_))
    ));
    // Requests beyond the element limit are refused before any allocation.
    let huge = Generator::Rectangle {
        lx: 1.0,
        ly: 1.0,
        nx: 100_000,
        ny: 100_000,
    };
    assert!(huge.element_count() > MAX_ELEMENTS);
    let err = build_mesh(&recipe(MeshSource::Generator(huge), ElementPair::Tri3Tri3)).unwrap_err();
    assert!(matches!(err, MeshSourceError::Invalid { step: "nx", .. }), "{err:?}");
    let mut r = recipe(fixture("octahedron.obj"), ElementPair::Tri3Tri3);
    r.refine = 12; // 8 · 4¹² ≈ 1.3e8 triangles
    assert!(matches!(
        build_mesh(&r),
        Err(MeshSourceError::Invalid { step: "refine", .. })
    ));
}
