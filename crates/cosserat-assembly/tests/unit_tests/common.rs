//! Small systems for the tests.

use cosserat_assembly::IncrementalPotential;
use cosserat_assembly::{ElementPair, ShellInput, ShellMesh, System, SystemOptions, build_system};
use cosserat_fem::QuadratureRule;
use cosserat_fem::mesh::{chord_placement, procedural};
use cosserat_material::rest::RestOptions;
use cosserat_material::{MaterialParameters, ModelOptions, ShellModel, StrainInterpolation};
use nalgebra::{DMatrix, Vector3};

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

/// A free square patch of side 0.1 in `cells × cells` squares (two triangles each), quasi-static and
/// without gravity.
pub struct FreePatch {
    pub pair: ElementPair,
    pub model: ShellModel,
    pub interpolation: StrainInterpolation,
    /// Quadrature degree; `None`: the pair's default with the interpolation.
    pub degree: Option<usize>,
    pub cells: usize,
    pub material: MaterialParameters,
}

impl FreePatch {
    pub fn build(&self) -> System {
        let mut rest = RestOptions::new(ModelOptions::new(self.model));
        rest.interpolation = self.interpolation;
        let grid = procedural::rectangle_grid(0.1, 0.1, self.cells, self.cells).unwrap();
        let input = ShellInput {
            name: "patch".into(),
            mesh: ShellMesh::from_tri3(grid.mesh, self.pair, chord_placement),
            pair: self.pair,
            material: self.material,
            rest,
            quadrature: self.degree.map(|d| QuadratureRule::for_degree(d).unwrap()),
            damping: 0.0,
            angular_inertia_density: 0.0,
        };
        let options = SystemOptions {
            gravity: Vector3::zeros(),
            dynamic: false,
        };
        build_system(&[input], &options).unwrap()
    }
}

/// The dense Hessian of a potential at `u` (both triangles).
pub fn dense_hessian(p: &mut IncrementalPotential, u: &[f64]) -> DMatrix<f64> {
    let n = p.n_dofs();
    let mut g = vec![0.0; n];
    let mut values = vec![0.0; p.pattern().nnz()];
    p.hessian(u, &mut g, &mut values).unwrap();
    let sym = p.pattern().symbolic();
    let mut h = DMatrix::zeros(n, n);
    for j in 0..n {
        for k in sym.col_ptr()[j]..sym.col_ptr()[j + 1] {
            let i = sym.row_idx()[k];
            h[(i, j)] = values[k];
            h[(j, i)] = values[k];
        }
    }
    h
}
