//! Builders for the mechanics tests.

use cosserat_assembly::term::Evaluation;
use cosserat_assembly::{
    AssemblyError, ElementPair, PotentialTerm, ShellInput, ShellMesh, SparsityPattern, System, SystemOptions,
    build_system,
};
use cosserat_fem::mesh::{chord_placement, procedural};
use cosserat_material::rest::RestOptions;
use cosserat_material::{MaterialParameters, ModelOptions, ShellModel, StrainInterpolation};
use nalgebra::Vector3;
use std::sync::atomic::{AtomicUsize, Ordering};

/// A flat rectangular strip `[−lx/2, lx/2] × [−ly/2, ly/2]` in z = 0.
pub fn strip_system(
    pair: ElementPair,
    dims: (f64, f64),
    n: (usize, usize),
    material: MaterialParameters,
    gravity: Vector3<f64>,
    dynamic: bool,
    dt: f64,
) -> System {
    let input = strip_input(pair, dims, n, material, StrainInterpolation::Paper);
    let mut system = build_system(&[input], &SystemOptions { gravity, dynamic }).unwrap();
    system.potential.set_time_step(dt);
    system
}

/// The plate input of a flat rectangular strip `[−lx/2, lx/2] × [−ly/2, ly/2]` in z = 0.
pub fn strip_input(
    pair: ElementPair,
    (lx, ly): (f64, f64),
    (nx, ny): (usize, usize),
    material: MaterialParameters,
    interpolation: StrainInterpolation,
) -> ShellInput {
    let grid = procedural::rectangle_grid(lx, ly, nx, ny).unwrap();
    let mut rest = RestOptions::new(ModelOptions::new(ShellModel::Plate));
    rest.interpolation = interpolation;
    ShellInput {
        name: "strip".into(),
        mesh: ShellMesh::from_tri3(grid.mesh, pair, chord_placement),
        pair,
        material,
        rest,
        quadrature: None,
        damping: 0.0,
        angular_inertia_density: 0.0,
    }
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

/// A test term without energy whose `n`-th Hessian evaluation (counting from one) fails, as a
/// non-finite energy would; every other evaluation succeeds. It makes one Newton solve fail after
/// `n − 1` iterations.
pub struct FailsOnce {
    hessians: AtomicUsize,
    n: usize,
}

impl FailsOnce {
    /// Fails the `n`-th Hessian evaluation.
    pub fn at_hessian(n: usize) -> Self {
        Self {
            hessians: AtomicUsize::new(0),
            n,
        }
    }
}

impl PotentialTerm for FailsOnce {
    fn name(&self) -> String {
        "fails_once".into()
    }

    fn value(&self, _: &Evaluation<'_>) -> Result<f64, AssemblyError> {
        Ok(0.0)
    }

    fn gradient(&self, _: &Evaluation<'_>, _: &mut [f64]) -> Result<f64, AssemblyError> {
        Ok(0.0)
    }

    fn hessian(
        &self,
        _: &Evaluation<'_>,
        _: &mut [f64],
        _: &SparsityPattern,
        _: &mut [f64],
    ) -> Result<f64, AssemblyError> {
        if self.hessians.fetch_add(1, Ordering::Relaxed) + 1 == self.n {
            return Err(AssemblyError::NonFinite {
                term: self.name(),
                location: "term",
                index: 0,
            });
        }
        Ok(0.0)
    }
}
