//! Small systems for the tests.

use cosserat_assembly::{ElementPair, ShellInput, ShellMesh, System, SystemOptions, build_system};
use cosserat_fem::mesh::{chord_placement, procedural};
use cosserat_material::rest::RestOptions;
use cosserat_material::{MaterialParameters, ModelOptions, ShellModel, StrainInterpolation};
use nalgebra::Vector3;

pub fn strip(pair: ElementPair, nx: usize, ny: usize, model: ShellModel, dynamic: bool) -> System {
    strip_with(pair, nx, ny, model, dynamic, StrainInterpolation::Paper)
}

pub fn strip_with(
    pair: ElementPair,
    nx: usize,
    ny: usize,
    model: ShellModel,
    dynamic: bool,
    interpolation: StrainInterpolation,
) -> System {
    let mut rest = RestOptions::new(ModelOptions::new(model));
    rest.interpolation = interpolation;
    let grid = procedural::rectangle_grid(0.1, 0.02, nx, ny).unwrap();
    let mut material = MaterialParameters::new(1e-3, 1e6, 0.3, 1000.0, 1e-3);
    material.mu_c_factor = 0.7;
    let input = ShellInput {
        name: "strip".into(),
        mesh: ShellMesh::from_tri3(grid.mesh, pair, chord_placement),
        pair,
        material,
        rest,
        quadrature: None,
        damping: 0.5,
        angular_inertia_density: 0.0,
    };
    let options = SystemOptions {
        gravity: Vector3::new(0.0, 0.0, -9.81),
        dynamic,
    };
    let mut system = build_system(&[input], &options).unwrap();
    system.potential.set_time_step(0.01);
    system
}
