//! Times Hessian and gradient evaluations of the Tri6 plate-under-load potential (`-- <ny> <repetitions>`;
//! medians, since this machine is shared).
use cosserat_assembly::{ElementPair, ShellInput, ShellMesh, SystemOptions, build_system};
use cosserat_fem::mesh::{chord_placement, procedural};
use cosserat_material::rest::RestOptions;
use cosserat_material::{MaterialParameters, ModelOptions, ShellModel};
use nalgebra::Vector3;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let ny: usize = args.get(1).map_or(4, |s| s.parse().unwrap());
    let reps: usize = args.get(2).map_or(10, |s| s.parse().unwrap());
    let pair = ElementPair::Tri6Tri3;
    let nx = 10 * ny;
    let grid = procedural::rectangle_grid(0.1, 0.01, nx, ny).unwrap();
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
    let mut sys = build_system(
        &[input],
        Vec::new(),
        &SystemOptions {
            gravity: Vector3::zeros(),
            dynamic: true,
            dt: 0.01,
        },
    )
    .unwrap();
    let pot = &mut sys.potential;
    let n = pot.n_dofs();
    let u: Vec<f64> = (0..n).map(|i| 1e-3 * ((i as f64) * 0.7).sin()).collect();
    let mut g = vec![0.0; n];
    let mut h = vec![0.0; pot.pattern().nnz()];
    let mut th = Vec::new();
    let mut tg = Vec::new();
    for _ in 0..reps {
        g.fill(0.0);
        h.fill(0.0);
        let t = Instant::now();
        pot.hessian(&u, &mut g, &mut h).unwrap();
        th.push(t.elapsed().as_secs_f64());
        g.fill(0.0);
        let t = Instant::now();
        pot.gradient(&u, &mut g).unwrap();
        tg.push(t.elapsed().as_secs_f64());
    }
    th.sort_by(f64::total_cmp);
    tg.sort_by(f64::total_cmp);
    println!(
        "dofs {n}: hessian median {:.1} ms (min {:.1}), gradient median {:.1} ms (min {:.1})",
        1e3 * th[reps / 2],
        1e3 * th[0],
        1e3 * tg[reps / 2],
        1e3 * tg[0]
    );
}
