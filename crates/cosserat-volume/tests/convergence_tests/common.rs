//! The clamped slab curled by a prescribed rest curvature, for the volume model and the shell.

use cosserat_assembly::boundary::{PositionConstraint, RotationPenalty};
use cosserat_assembly::{ElementPair, IncrementalPotential, ShellInput, ShellMesh, SystemOptions, build_system};
use cosserat_fem::mesh::{chord_placement, procedural};
use cosserat_material::rest::RestOptions;
use cosserat_material::{MaterialParameters, ModelOptions, ShellModel};
use cosserat_solver::{QuasiStaticSettings, solve_quasi_static};
use cosserat_volume::measure::fit_circle;
use cosserat_volume::mesh::slab;
use cosserat_volume::{ContinuumParameters, VolumeInput, build_volume_system};
use nalgebra::{Matrix3, Vector2, Vector3};

/// Slab length along x and width along y \[m\].
pub const LENGTH: f64 = 1.0;
pub const WIDTH: f64 = 0.125;
/// The prescribed curvature: half a circle over the length.
pub const KAPPA: f64 = std::f64::consts::PI;
const LEVELS: [f64; 4] = [0.25, 0.5, 0.75, 1.0];

pub fn material(lc: f64) -> ContinuumParameters {
    ContinuumParameters::new(1e6, 0.3, 1000.0, lc)
}

/// `Γ_rest,21 = λ κ`: rotation about y accumulating along x.
pub fn rest_curvature(lambda: f64) -> Matrix3<f64> {
    let mut g = Matrix3::zeros();
    g[(1, 0)] = KAPPA * lambda;
    g
}

/// Clamps positions (exactly) and rotations (stiff penalty on all directors) of the given nodes.
fn clamp(potential: &mut IncrementalPotential, rest: &[Vector3<f64>], disp: &[usize], rot: &[usize]) {
    let parts = &mut potential.parts;
    parts.position_constraints.push(PositionConstraint {
        label: "clamp".into(),
        nodes: disp.to_vec(),
        targets: disp.iter().map(|&i| rest[i]).collect(),
        active: [true; 3],
    });
    parts.rotation_penalties.push(RotationPenalty {
        label: "clamp".into(),
        nodes: rot.to_vec(),
        targets: vec![Matrix3::identity(); rot.len()],
        columns: [true; 3],
        stiffness: 1e6,
    });
}

/// The mid-surface of a slab `[−L/2, L/2] × [−W/2, W/2] × [−h/2, h/2]` of `cells` clamped at `x = −L/2`
/// after the rest curvature has been ramped to `κ` in four quasi-static levels, and its rest positions.
pub fn volume_coil(h: f64, cells: [usize; 3], lc: f64) -> (Vec<Vector3<f64>>, Vec<Vector3<f64>>) {
    let grid = slab([LENGTH, WIDTH, h], cells).unwrap();
    let input = VolumeInput {
        mesh: grid.mesh.clone(),
        material: material(lc),
        damping: 0.0,
        angular_inertia_density: 0.0,
    };
    let options = SystemOptions {
        gravity: Vector3::zeros(),
        dynamic: false,
    };
    let mut sys = build_volume_system(&input, &options).unwrap();
    let face: Vec<usize> = (0..sys.rest_positions.len())
        .filter(|&i| sys.rest_positions[i].x < -0.5 * LENGTH + 1e-9)
        .collect();
    clamp(&mut sys.potential, &sys.rest_positions, &face, &face);
    let handle = sys.rest_curvature.clone();
    solve_quasi_static(
        &mut sys.potential,
        &LEVELS,
        &QuasiStaticSettings::default(),
        &mut |_, lambda| handle.set_uniform(rest_curvature(lambda)),
        &mut |_, _| {},
    )
    .unwrap();
    (
        grid.mid_surface(&sys.potential.parts.state.x),
        grid.mid_surface(&grid.mesh.nodes),
    )
}

/// The nodes of a Tri6/Tri3 plate strip of `nx × ny` cells with the same material, clamp and loading.
pub fn shell_coil(h: f64, nx: usize, ny: usize, lc: f64) -> Vec<Vector3<f64>> {
    let grid = procedural::rectangle_grid(LENGTH, WIDTH, nx, ny).unwrap();
    let pair = ElementPair::Tri6Tri3;
    let input = ShellInput {
        name: "strip".into(),
        mesh: ShellMesh::from_tri3(grid.mesh, pair, chord_placement),
        pair,
        material: MaterialParameters::new(h, 1e6, 0.3, 1000.0, lc),
        rest: RestOptions::new(ModelOptions::new(ShellModel::Plate)),
        quadrature: None,
        damping: 0.0,
        angular_inertia_density: 0.0,
    };
    let options = SystemOptions {
        gravity: Vector3::zeros(),
        dynamic: false,
    };
    let mut sys = build_system(&[input], &options).unwrap();
    let s = &sys.shells[0];
    let on_clamp = |x: &Vector3<f64>| x.x < -0.5 * LENGTH + 1e-9;
    let disp: Vec<usize> = (0..s.rest_disp_positions.len())
        .filter(|&i| on_clamp(&s.rest_disp_positions[i]))
        .collect();
    let rot: Vec<usize> = (0..s.rest_rot_positions.len())
        .filter(|&k| on_clamp(&s.rest_rot_positions[k]))
        .collect();
    let rest = s.rest_disp_positions.clone();
    clamp(&mut sys.potential, &rest, &disp, &rot);
    solve_quasi_static(
        &mut sys.potential,
        &LEVELS,
        &QuasiStaticSettings::default(),
        &mut |p, lambda| {
            let g = rest_curvature(lambda);
            p.parts.shells[0].set_rest_fields_dyn(&mut |_| (None, Some(g)));
        },
        &mut |_, _| {},
    )
    .unwrap();
    sys.potential.parts.state.x.clone()
}

/// The curvature of the circle fitted to the points' (x, z) projections \[1/m\].
pub fn fitted_curvature(points: &[Vector3<f64>]) -> f64 {
    let xz: Vec<Vector2<f64>> = points.iter().map(|p| Vector2::new(p.x, p.z)).collect();
    1.0 / fit_circle(&xz).unwrap().1
}

/// The largest distance of the points from the arc of curvature `k` clamped at `x = −L/2` with tangent
/// `e_x`, curling towards −z, each point compared with the arc point at its rest arc length.
pub fn distance_to_arc(points: &[Vector3<f64>], rest: &[Vector3<f64>], k: f64) -> f64 {
    points
        .iter()
        .zip(rest)
        .map(|(p, x0)| {
            let s = x0.x + 0.5 * LENGTH;
            let arc = Vector3::new(-0.5 * LENGTH + (k * s).sin() / k, x0.y, -(1.0 - (k * s).cos()) / k);
            (p - arc).norm()
        })
        .fold(0.0, f64::max)
}
