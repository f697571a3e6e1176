//! Curved rest states: faceted (Tri3, straight-edged Tri6) and curved Tri6 meshes of a sphere and a
//! cylinder carry their curvature into the shell model, and the undeformed shell is at rest.

use cosserat_assembly::{ElementPair, ShellInput, ShellMesh, System, SystemOptions, build_system};
use cosserat_fem::mesh::procedural::GeneratedMesh;
use cosserat_fem::mesh::{chord_placement, procedural};
use cosserat_material::rest::RestOptions;
use cosserat_material::{MaterialParameters, ModelOptions, ShellModel};
use nalgebra::Vector3;

fn build(generated: &GeneratedMesh, pair: ElementPair, on_surface: bool) -> System {
    let mesh = if on_surface {
        ShellMesh::from_tri3(generated.mesh.clone(), pair, |n| generated.place(n))
    } else {
        ShellMesh::from_tri3(generated.mesh.clone(), pair, chord_placement)
    };
    let input = ShellInput {
        name: "curved".into(),
        mesh,
        pair,
        material: MaterialParameters::new(1e-2, 1e6, 0.3, 1000.0, 1e-2),
        rest: RestOptions::new(ModelOptions::new(ShellModel::Shell)),
        quadrature: None,
        damping: 0.0,
        angular_inertia_density: 0.0,
    };
    let mut system = build_system(
        &[input],
        &SystemOptions {
            gravity: Vector3::zeros(),
            dynamic: true,
        },
    )
    .unwrap();
    system.potential.set_time_step(0.01);
    system
}

#[test]
fn faceted_and_curved_meshes_carry_curvature_and_rest_at_zero_energy() {
    let sphere = procedural::icosphere(1.0, 2).unwrap();
    let cylinder = procedural::cylinder(0.5, 2.0, 24, 8).unwrap();
    for (label, generated) in [("sphere", &sphere), ("cylinder", &cylinder)] {
        for (pair, on_surface) in [
            (ElementPair::Tri3Tri3, false),
            (ElementPair::Tri6Tri3, false),
            (ElementPair::Tri6Tri3, true),
        ] {
            let mut sys = build(generated, pair, on_surface);
            let shell = &sys.shells[0];
            let n_points = shell.points.len();
            // Every point of a sphere or cylinder is curved, whether the elements are flat or not.
            assert_eq!(
                shell.n_curved_points, n_points,
                "{label} {pair:?} on_surface={on_surface}"
            );
            assert!(
                shell.active_terms.iter().any(|t| t == "curved_bending_2"),
                "{:?}",
                shell.active_terms
            );
            let u = vec![0.0; sys.potential.n_dofs()];
            let mut g = vec![0.0; u.len()];
            let e = sys.potential.gradient(&u, &mut g).unwrap();
            // Scales: E h A ≈ 1e6 · 1e-2 · 12 J for a unit strain; the rest state is zero to round-off.
            let g_max = g.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            assert!(e.abs() < 1e-20 * 1e5, "{label} {pair:?}: energy at rest {e:e}");
            assert!(g_max < 1e-12, "{label} {pair:?}: gradient at rest {g_max:e}");
        }
    }
}
