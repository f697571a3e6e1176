//! Mesh generators: counts, index conventions, orientation, exact-surface placement, bad parameters.

use cosserat_fem::element::{ShapeFunctions, Tri3};
use cosserat_fem::mesh::procedural::{self, AnnulusSettings, GeneratedMesh, Surface};
use cosserat_fem::mesh::{Topology, exact_normal};
use cosserat_fem::{MeshError, Tri3Mesh};
use nalgebra::Vector3;
use std::f64::consts::PI;

fn face_normal(mesh: &Tri3Mesh, f: usize) -> Vector3<f64> {
    exact_normal::<Tri3, 3>(&mesh.element_nodes(f), [0.0, 0.0]).unwrap().normal
}

fn centroid(mesh: &Tri3Mesh, f: usize) -> Vector3<f64> {
    Tri3::position(&mesh.element_nodes(f), [1.0 / 3.0, 1.0 / 3.0])
}

/// Every vertex and every new node of the curved upgrades lies on the surface.
fn check_on_surface(generated: &GeneratedMesh, tol: f64) {
    let tri6 = generated.to_tri6_on_surface();
    let tri10 = generated.to_tri10_on_surface();
    for p in generated.mesh.nodes.iter().chain(&tri6.nodes).chain(&tri10.nodes) {
        let q = generated.surface.project(p);
        assert!(
            (q - p).norm() < tol,
            "{:?}: {p:?} is {} off the surface",
            generated.surface,
            (q - p).norm()
        );
    }
    generated.mesh.validate().unwrap();
    tri6.validate().unwrap();
    tri10.validate().unwrap();
}

#[test]
fn rectangle_grid_follows_the_paper_convention() {
    let (lx, ly, nx, ny) = (3.0, 1.0, 3, 2);
    let grid = procedural::rectangle_grid(lx, ly, nx, ny).unwrap();
    assert_eq!(grid.surface, Surface::Plane);
    let mesh = &grid.mesh;
    assert_eq!(mesh.n_nodes(), (nx + 1) * (ny + 1));
    assert_eq!(mesh.n_elements(), 2 * nx * ny);
    assert_eq!(mesh.to_tri6().n_nodes(), (2 * nx + 1) * (2 * ny + 1));
    for i in 0..=nx {
        for j in 0..=ny {
            let p = mesh.nodes[i * (ny + 1) + j];
            let expected = Vector3::new(
                -lx / 2.0 + lx * i as f64 / nx as f64,
                -ly / 2.0 + ly * j as f64 / ny as f64,
                0.0,
            );
            assert!((p - expected).norm() < 1e-15);
        }
    }
    let idx = |i: usize, j: usize| i * (ny + 1) + j;
    for i in 0..nx {
        for j in 0..ny {
            let q = 2 * (i * ny + j);
            let has_edge = |a: usize, b: usize| {
                [q, q + 1]
                    .iter()
                    .all(|&f| mesh.elements[f].contains(&a) && mesh.elements[f].contains(&b))
            };
            if (i + j) % 2 == 0 {
                assert!(has_edge(idx(i, j), idx(i + 1, j + 1)), "quad ({i}, {j})");
            } else {
                assert!(has_edge(idx(i + 1, j), idx(i, j + 1)), "quad ({i}, {j})");
            }
        }
    }
    for f in 0..mesh.n_elements() {
        assert!((face_normal(mesh, f) - Vector3::z()).norm() < 1e-15);
    }
    check_on_surface(&grid, 1e-15);
}

#[test]
fn disk_and_annulus() {
    let disk = procedural::disk(2.0, 3, 12).unwrap();
    assert_eq!(disk.mesh.n_nodes(), 1 + 3 * 12);
    assert_eq!(disk.mesh.n_elements(), 12 + 2 * 2 * 12);
    let annulus = procedural::annulus(&AnnulusSettings {
        inner_radius: 1.0,
        outer_radius: 2.0,
        n_radial: 2,
        n_angular: 16,
        slit: false,
    })
    .unwrap();
    assert_eq!(annulus.mesh.n_nodes(), 3 * 16);
    assert_eq!(annulus.mesh.n_elements(), 2 * 2 * 16);
    for g in [&disk, &annulus] {
        for f in 0..g.mesh.n_elements() {
            assert!((face_normal(&g.mesh, f) - Vector3::z()).norm() < 1e-14);
        }
        for p in &g.mesh.nodes {
            let r = p.xy().norm();
            assert!(r <= 2.0 + 1e-14 && p.z == 0.0);
        }
        check_on_surface(g, 1e-15);
    }
    // Area of the polygonal annulus: 16 trapezoids per ring, exactly.
    let area: f64 = (0..annulus.mesh.n_elements())
        .map(|f| {
            let x = annulus.mesh.element_nodes(f);
            0.5 * (x[1] - x[0]).cross(&(x[2] - x[0])).norm()
        })
        .sum();
    let polygon = |r: f64| 0.5 * 16.0 * r * r * (2.0 * PI / 16.0).sin();
    assert!((area - (polygon(2.0) - polygon(1.0))).abs() < 1e-13);
}

#[test]
fn curved_upgrades_of_an_annulus_put_boundary_nodes_on_the_circles() {
    let settings = AnnulusSettings {
        inner_radius: 0.5,
        outer_radius: 1.5,
        n_radial: 2,
        n_angular: 10,
        slit: true,
    };
    let annulus = procedural::annulus(&settings).unwrap();
    let tri6 = annulus.to_tri6_on_surface();
    let topology = Topology::new(&annulus.mesh);
    for (e, &[a, b]) in topology.edges().iter().enumerate() {
        let m = tri6.nodes[annulus.mesh.n_nodes() + e];
        let (ra, rb) = (annulus.mesh.nodes[a].xy().norm(), annulus.mesh.nodes[b].xy().norm());
        if (ra - rb).abs() < 1e-12 && ((ra - 0.5).abs() < 1e-12 || (ra - 1.5).abs() < 1e-12) {
            assert!(
                (m.xy().norm() - ra).abs() < 1e-14,
                "edge ({a}, {b}) node not on its circle"
            );
        } else {
            assert!((m - (annulus.mesh.nodes[a] + annulus.mesh.nodes[b]) * 0.5).norm() < 1e-15);
        }
    }
    // The slit duplicates the vertices at angle 0: one boundary loop through both copies.
    assert_eq!(annulus.mesh.n_nodes(), 3 * 11);
    let loops = Topology::new(&annulus.mesh).boundary_loops().unwrap();
    assert_eq!(loops.len(), 1);
    // Both circles (10 edges each) and both sides of the slit (2 edges each).
    assert_eq!(loops[0].len(), 2 * 10 + 2 * 2);
    tri6.validate().unwrap();
}

#[test]
fn the_sides_of_a_slit_are_the_vertices_on_the_x_axis_of_the_elements_either_side() {
    for inner_radius in [0.5, 0.0] {
        let settings = AnnulusSettings {
            inner_radius,
            outer_radius: 1.5,
            n_radial: 3,
            n_angular: 12,
            slit: true,
        };
        let annulus = procedural::annulus(&settings).unwrap();
        let mesh = &annulus.mesh;
        let (start, end) = settings.slit_sides().unwrap();
        // Four rings of vertices, or the centre and three rings.
        let rings = 4;
        assert_eq!((start.len(), end.len()), (rings, rings));
        assert!(start.windows(2).all(|w| w[0] < w[1]) && end.windows(2).all(|w| w[0] < w[1]));
        for (&a, &b) in start.iter().zip(&end) {
            assert_eq!(mesh.nodes[a], mesh.nodes[b], "the two sides coincide at rest");
            assert!(mesh.nodes[a].y == 0.0 && mesh.nodes[a].x >= 0.0);
        }
        let radii: Vec<f64> = start.iter().map(|&v| mesh.nodes[v].x).collect();
        assert!(radii.windows(2).all(|w| w[0] < w[1]), "inside out: {radii:?}");
        assert!((radii[0] - inner_radius).abs() < 1e-15 && (radii[rings - 1] - 1.5).abs() < 1e-15);
        // An element touching a side lies on that side of the cut: above the x axis at angle 0, below
        // it at angle 2π; the centre vertex of a disk is on both.
        let off_centre = |side: &[usize], v: usize| side.contains(&v) && !(inner_radius == 0.0 && v == 0);
        for f in 0..mesh.n_elements() {
            let c = centroid(mesh, f);
            let touches = |side: &[usize]| mesh.elements[f].iter().any(|&v| off_centre(side, v));
            if touches(&start) {
                assert!(c.y > 0.0, "element {f} at the start side");
            }
            if touches(&end) {
                assert!(c.y < 0.0, "element {f} at the end side");
            }
        }
    }
    let closed = AnnulusSettings {
        inner_radius: 0.5,
        outer_radius: 1.5,
        n_radial: 3,
        n_angular: 12,
        slit: false,
    };
    assert_eq!(closed.slit_sides(), None);
}

#[test]
fn cylinder_is_outward_and_on_the_surface() {
    let cyl = procedural::cylinder(0.7, 2.0, 9, 4).unwrap();
    assert_eq!(cyl.mesh.n_nodes(), 9 * 5);
    assert_eq!(cyl.mesh.n_elements(), 2 * 9 * 4);
    for f in 0..cyl.mesh.n_elements() {
        let c = centroid(&cyl.mesh, f);
        assert!(face_normal(&cyl.mesh, f).dot(&Vector3::new(c.x, c.y, 0.0)) > 0.0);
    }
    for p in &cyl.mesh.nodes {
        assert!(p.z.abs() <= 1.0 + 1e-15);
    }
    check_on_surface(&cyl, 1e-14);
}

#[test]
fn icospheres_have_the_expected_counts_and_orientation() {
    for level in 0..3 {
        let s = procedural::icosphere(1.5, level).unwrap();
        let four = 4usize.pow(level as u32);
        assert_eq!(s.mesh.n_nodes(), 10 * four + 2);
        assert_eq!(s.mesh.n_elements(), 20 * four);
        assert_eq!(Topology::new(&s.mesh).euler_characteristic(), 2);
        for f in 0..s.mesh.n_elements() {
            assert!(face_normal(&s.mesh, f).dot(&centroid(&s.mesh, f)) > 0.0);
        }
        check_on_surface(&s, 1e-14);
    }
}

#[test]
fn uv_spheres_hemispheres_and_polar_holes() {
    let (n_lon, n_lat) = (10, 6);
    let s = procedural::uv_sphere(1.0, n_lon, n_lat).unwrap();
    assert_eq!(s.mesh.n_nodes(), 2 + (n_lat - 1) * n_lon);
    assert_eq!(s.mesh.n_elements(), 2 * n_lon * (n_lat - 1));
    assert_eq!(s.mesh.nodes[0], Vector3::z());
    assert_eq!(*s.mesh.nodes.last().unwrap(), -Vector3::z());
    for f in 0..s.mesh.n_elements() {
        assert!(face_normal(&s.mesh, f).dot(&centroid(&s.mesh, f)) > 0.0);
    }
    check_on_surface(&s, 1e-14);

    let h = procedural::uv_hemisphere(2.0, 8, 3).unwrap();
    assert_eq!(h.mesh.n_nodes(), 1 + 3 * 8);
    let equator: Vec<&Vector3<f64>> = h.mesh.nodes.iter().filter(|p| p.z == 0.0).collect();
    assert_eq!(equator.len(), 8);
    assert!(equator.iter().all(|p| (p.norm() - 2.0).abs() < 1e-15));
    assert!(h.mesh.nodes.iter().all(|p| p.z >= 0.0));
    let loops = Topology::new(&h.mesh).boundary_loops().unwrap();
    assert_eq!(loops.len(), 1);
    assert!(loops[0].iter().all(|&v| h.mesh.nodes[v].z == 0.0));
    check_on_surface(&h, 1e-14);

    // A hole at the first latitude ring removes exactly the pole fan.
    let holed = s.clone().with_polar_hole(PI / n_lat as f64).unwrap();
    assert_eq!(holed.mesh.n_elements(), s.mesh.n_elements() - n_lon);
    assert_eq!(holed.mesh.n_nodes(), s.mesh.n_nodes() - 1);
    let loops = Topology::new(&holed.mesh).boundary_loops().unwrap();
    assert_eq!(loops.len(), 1);
    assert_eq!(loops[0].len(), n_lon);
    holed.mesh.validate().unwrap();
    // A hole on an icosphere leaves a sphere with one boundary loop too.
    let ico_holed = procedural::icosphere(1.0, 2).unwrap().with_polar_hole(0.5).unwrap();
    assert_eq!(Topology::new(&ico_holed.mesh).boundary_loops().unwrap().len(), 1);
    assert_eq!(Topology::new(&ico_holed.mesh).euler_characteristic(), 1);
    ico_holed.mesh.validate().unwrap();
}

#[test]
fn mobius_strip_is_welded_and_on_its_surface() {
    let (n_along, n_across) = (30, 4);
    let m = procedural::mobius_strip(1.0, 0.5, n_along, n_across).unwrap();
    assert_eq!(m.mesh.n_nodes(), n_along * (n_across + 1));
    assert_eq!(m.mesh.n_elements(), 2 * n_along * n_across);
    let topology = Topology::new(&m.mesh);
    assert!(topology.non_manifold_edge().is_none());
    assert_eq!(topology.boundary_loops().unwrap().len(), 1);
    assert_eq!(topology.consistent_orientation(), None);
    // The centre line X(u, 0) lies on the circle of radius 1 in z = 0 (n_across even).
    for i in 0..n_along {
        let p = m.mesh.nodes[i * (n_across + 1) + n_across / 2];
        assert!((p.xy().norm() - 1.0).abs() < 1e-15 && p.z.abs() < 1e-15);
    }
    check_on_surface(&m, 1e-12);
}

#[test]
fn bad_parameters_are_errors() {
    let invalid = |r: Result<GeneratedMesh, MeshError>, param: &str| match r {
        Err(MeshError::InvalidParameter { parameter, .. }) => assert_eq!(parameter, param),
        other => panic!("expected an invalid `{param}`, got {other:?}"),
    };
    invalid(procedural::rectangle_grid(0.0, 1.0, 2, 2), "lx");
    invalid(procedural::rectangle_grid(1.0, f64::NAN, 2, 2), "ly");
    invalid(procedural::rectangle_grid(1.0, 1.0, 0, 2), "nx");
    invalid(procedural::disk(1.0, 2, 2), "n_angular");
    invalid(procedural::disk(-1.0, 2, 8), "outer_radius");
    invalid(
        procedural::annulus(&AnnulusSettings {
            inner_radius: 2.0,
            outer_radius: 1.0,
            n_radial: 1,
            n_angular: 8,
            slit: false,
        }),
        "inner_radius",
    );
    invalid(procedural::cylinder(1.0, 1.0, 2, 1), "n_around");
    invalid(procedural::cylinder(1.0, f64::INFINITY, 4, 1), "length");
    invalid(procedural::icosphere(0.0, 1), "radius");
    invalid(procedural::icosphere(1.0, 9), "level");
    invalid(procedural::uv_sphere(1.0, 8, 1), "n_lat");
    invalid(procedural::uv_hemisphere(1.0, 2, 2), "n_lon");
    invalid(procedural::mobius_strip(1.0, 2.0, 10, 2), "width");
    invalid(procedural::mobius_strip(1.0, 0.5, 2, 2), "n_along");
    invalid(
        procedural::uv_sphere(1.0, 8, 4).unwrap().with_polar_hole(-0.1),
        "polar_angle",
    );
    assert_eq!(
        procedural::uv_sphere(1.0, 8, 4).unwrap().retain_faces(|_, _| false),
        Err(MeshError::EmptyMesh {
            operation: "retain_faces"
        })
    );
}
