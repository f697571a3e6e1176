//! Compares fill and flops of AMD and nested dissection on plate-under-load patterns (scratch).
use cosserat_assembly::{ElementPair, ShellInput, ShellMesh, SystemOptions, build_system};
use cosserat_fem::mesh::{chord_placement, procedural};
use cosserat_material::rest::RestOptions;
use cosserat_material::{MaterialParameters, ModelOptions, ShellModel};
use cosserat_solver::{FillOrdering, LinearSolverSettings, SparseSolver};
use nalgebra::Vector3;
fn main() {
    let ny: usize = std::env::args().nth(1).map_or(16, |s| s.parse().unwrap());
    let grid = procedural::rectangle_grid(0.1, 0.01, 10 * ny, ny).unwrap();
    let input = ShellInput {
        name: "p".into(),
        mesh: ShellMesh::from_tri3(grid.mesh, ElementPair::Tri6Tri3, chord_placement),
        pair: ElementPair::Tri6Tri3,
        material: MaterialParameters::new(2e-3, 70e9, 0.35, 2700.0, 2e-6),
        rest: RestOptions::new(ModelOptions::new(ShellModel::Plate)),
        quadrature: None,
        damping: 0.0,
        angular_inertia_density: 0.0,
    };
    let sys = build_system(
        &[input],
        Vec::new(),
        &SystemOptions {
            gravity: Vector3::zeros(),
            dynamic: true,
            dt: 0.01,
        },
    )
    .unwrap();
    for ord in [FillOrdering::Amd, FillOrdering::NestedDissection { block: 3 }] {
        let t = std::time::Instant::now();
        let s = SparseSolver::try_new(
            sys.potential.pattern().symbolic(),
            LinearSolverSettings {
                ordering: ord,
                ..Default::default()
            },
        )
        .unwrap();
        let st = s.symmetric_stats().unwrap();
        println!(
            "{ord:?}: nnz_l {} flops {:.2e} supernodes {} ({:.2} s)",
            st.nnz_l,
            st.flops,
            st.n_supernodes,
            t.elapsed().as_secs_f64()
        );
    }
}
