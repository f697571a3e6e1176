//! Builders for the mechanics tests.

use cosserat_assembly::{ElementPair, ShellInput, ShellMesh, System, SystemOptions, build_system};
use cosserat_fem::mesh::{chord_placement, procedural};
use cosserat_material::rest::RestOptions;
use cosserat_material::{MaterialParameters, ModelOptions, ShellModel};
use nalgebra::Vector3;

/// A flat rectangular strip `[−lx/2, lx/2] × [−ly/2, ly/2]` in z = 0.
pub fn strip_system(
    pair: ElementPair,
    (lx, ly): (f64, f64),
    (nx, ny): (usize, usize),
    material: MaterialParameters,
    gravity: Vector3<f64>,
    dynamic: bool,
    dt: f64,
) -> System {
    let grid = procedural::rectangle_grid(lx, ly, nx, ny).unwrap();
    let input = ShellInput {
        name: "strip".into(),
        mesh: ShellMesh::from_tri3(grid.mesh, pair, chord_placement),
        pair,
        material,
        rest: RestOptions::new(ModelOptions::new(ShellModel::Plate)),
        quadrature: None,
        damping: 0.0,
        angular_inertia_density: 0.0,
    };
    let mut system = build_system(&[input], &SystemOptions { gravity, dynamic }).unwrap();
    system.potential.set_time_step(dt);
    system
}

/// Local displacement nodes of the first shell whose rest x satisfies `pred`.
pub fn disp_nodes_where(system: &System, pred: impl Fn(&Vector3<f64>) -> bool) -> Vec<usize> {
    let s = &system.shells[0];
    (0..s.rest_disp_positions.len())
        .filter(|&i| pred(&s.rest_disp_positions[i]))
        .map(|i| s.disp_nodes.start + i)
        .collect()
}

/// Global rotation nodes of the first shell whose rest position satisfies `pred`.
pub fn rot_nodes_where(system: &System, pred: impl Fn(&Vector3<f64>) -> bool) -> Vec<usize> {
    let s = &system.shells[0];
    (0..s.rest_rot_positions.len())
        .filter(|&k| pred(&s.rest_rot_positions[k]))
        .map(|k| s.rot_nodes.start + k)
        .collect()
}
