//! The plate under load of the paper's Table 1 (100 mm × 10 mm aluminium strip, h = 2 mm, E = 70 GPa,
//! ν = 0.35, clamped at x = −50 mm, loaded at x = +50 mm), built once here for the profiling examples and
//! the step benches.
use cosserat_assembly::boundary::{PositionPenalty, RotationPenalty};
use cosserat_assembly::{ElementPair, ShellInput, ShellMesh, System, SystemOptions, build_system};
use cosserat_fem::mesh::{chord_placement, procedural};
use cosserat_material::rest::RestOptions;
use cosserat_material::{MaterialParameters, ModelOptions, ShellModel};
use nalgebra::{Matrix3, Vector3};

/// The dynamic plate system (no gravity, Δt = `dt`) on `nx × ny` quads of `pair` elements, with its
/// clamp (position and director penalties) and the displacement nodes of its loaded tip.
pub fn clamped_plate(nx: usize, ny: usize, pair: ElementPair, dt: f64) -> (System, Vec<usize>) {
    let grid = procedural::rectangle_grid(0.1, 0.01, nx, ny).expect("plate grid");
    let input = ShellInput {
        name: "plate".into(),
        mesh: ShellMesh::from_tri3(grid.mesh, pair, chord_placement),
        pair,
        material: MaterialParameters::new(2e-3, 70e9, 0.35, 2700.0, 2e-6),
        rest: RestOptions::new(ModelOptions::new(ShellModel::Plate)),
        quadrature: None,
        damping: 0.0,
        angular_inertia_density: 0.0,
    };
    let options = SystemOptions {
        gravity: Vector3::zeros(),
        dynamic: true,
    };
    let mut sys = build_system(&[input], &options).expect("plate system");
    sys.potential.set_time_step(dt);
    let tol = 0.05 * 0.1 / nx as f64;
    let layout = &sys.shells[0];
    let near =
        |p: &[Vector3<f64>], x: f64| -> Vec<usize> { (0..p.len()).filter(|&i| (p[i].x - x).abs() <= tol).collect() };
    let clamp = near(&layout.rest_disp_positions, -0.05);
    let clamp_rot = near(&layout.rest_rot_positions, -0.05);
    let tip = near(&layout.rest_disp_positions, 0.05);
    let parts = &mut sys.potential.parts;
    let targets = clamp.iter().map(|&i| parts.state.x[i]).collect();
    parts.position_penalties.push(PositionPenalty {
        label: "clamp".into(),
        nodes: clamp,
        targets,
        active: [true; 3],
        stiffness: 1e6,
    });
    let n_rot = clamp_rot.len();
    parts.rotation_penalties.push(RotationPenalty {
        label: "clamp".into(),
        nodes: clamp_rot,
        targets: vec![Matrix3::identity(); n_rot],
        columns: [false, false, true],
        stiffness: 1e4,
    });
    (sys, tip)
}
