//! The system builder: masses, inertia, loads, validation, and a dynamic step.

use cosserat_assembly::SystemOptions;
use cosserat_fem::mesh::procedural;
use cosserat_kl::{HyperelasticModel, KlError, KlMaterial, KlShell, build_kl_system};
use cosserat_solver::{TimeStepSettings, TimeStepper};
use nalgebra::Vector3;

fn shell() -> KlShell {
    KlShell::new(
        KlMaterial::new(HyperelasticModel::StVenantKirchhoff, 1e5, 0.3),
        2e-3,
        800.0,
    )
}

#[test]
fn masses_are_a_third_of_each_face_and_sum_to_the_shell_mass() {
    let grid = procedural::rectangle_grid(0.4, 0.3, 4, 3).unwrap().mesh;
    let options = SystemOptions {
        gravity: Vector3::zeros(),
        dynamic: true,
    };
    let sys = build_kl_system(&grid, &shell(), &options).unwrap();
    let total: f64 = sys.masses.iter().sum();
    assert!((total - 800.0 * 2e-3 * 0.4 * 0.3).abs() < 1e-14 * total);
    // The corner (0, 0) lies in one (even) quad and in both its triangles: a third of the quad's mass.
    let quad = 0.1 * 0.1;
    assert!((sys.masses[0] - 800.0 * 2e-3 * quad / 3.0).abs() < 1e-14 * sys.masses[0]);
    assert_eq!(
        sys.active_terms,
        vec!["inertia".to_string(), "kirchhoff_love_stvk".to_string()]
    );
    assert_eq!(sys.rest_positions, grid.nodes);
    let quasi = build_kl_system(
        &grid,
        &shell(),
        &SystemOptions {
            dynamic: false,
            ..options
        },
    )
    .unwrap();
    assert!(quasi.potential.parts.inertia.is_none());
    assert_eq!(quasi.potential.parts.layout.n_rot_nodes, 0);
}

#[test]
fn a_free_shell_falls_without_deforming() {
    // Backward Euler from rest under gravity: a rigid translation is exact, v = g Δt after one step and
    // x = x₀ + g Δt² (1 + 2) after two; the elastic energy stays zero.
    let grid = procedural::icosphere(0.1, 1).unwrap().mesh;
    let g = Vector3::new(0.0, 0.0, -9.81);
    let dt = 0.01;
    let mut sys = build_kl_system(
        &grid,
        &shell(),
        &SystemOptions {
            gravity: g,
            dynamic: true,
        },
    )
    .unwrap();
    let mut stepper = TimeStepper::new(&sys.potential, TimeStepSettings::fixed(dt)).unwrap();
    for _ in 0..2 {
        stepper.step(&mut sys.potential, &mut |_, _, _| {}).unwrap();
    }
    for (i, x) in sys.potential.parts.state.x.iter().enumerate() {
        let expected = sys.rest_positions[i] + g * (3.0 * dt * dt);
        assert!((x - expected).norm() < 1e-10, "vertex {i}: {x} vs {expected}");
        assert!((sys.potential.parts.state.v[i] - g * (2.0 * dt)).norm() < 1e-8);
    }
    assert!(sys.elastic_energy().unwrap().abs() < 1e-15);
}

#[test]
fn invalid_shells_and_options_are_rejected_by_name() {
    let grid = procedural::rectangle_grid(0.4, 0.3, 4, 3).unwrap().mesh;
    let options = SystemOptions {
        gravity: Vector3::zeros(),
        dynamic: true,
    };
    let cases = [
        (
            KlShell {
                density: 0.0,
                ..shell()
            },
            options,
            "density",
        ),
        (
            KlShell {
                damping: -1.0,
                ..shell()
            },
            options,
            "damping",
        ),
        (
            KlShell {
                thickness: f64::NAN,
                ..shell()
            },
            options,
            "thickness",
        ),
        (
            shell(),
            SystemOptions {
                gravity: Vector3::new(0.0, f64::INFINITY, 0.0),
                ..options
            },
            "gravity.y",
        ),
    ];
    for (s, o, name) in cases {
        match build_kl_system(&grid, &s, &o) {
            Err(KlError::InvalidParameter { name: n, .. }) => assert_eq!(n, name),
            Err(other) => panic!("{name}: {other}"),
            Ok(_) => panic!("{name}: accepted"),
        }
    }
}
