//! Strips clamped at one end, with the checkerboard grid of `cosserat_fem::mesh::procedural`.

use cosserat_assembly::boundary::PositionConstraint;
use cosserat_assembly::{IncrementalPotential, SystemOptions};
use cosserat_fem::mesh::procedural;
use cosserat_kl::{ForceCouple, KlShell, KlSystem, build_kl_system};
use cosserat_solver::{NewtonSettings, QuasiStaticSettings};
use nalgebra::Vector3;

/// Where the clamped edge lies relative to the two fixed vertex columns.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ClampLine {
    /// The fixed columns sit at `x = ±Δx/2`: the clamp line `x = 0` is midway between them, where their
    /// difference quotient (the clamped slope) is centred.
    Centred,
    /// The fixed columns sit at `x = 0` and `x = Δx`.
    FirstColumn,
}

/// A strip along x from the clamp line `x = 0` to the free end `x = l`, `nx × ny` quads.
pub struct Strip {
    pub system: KlSystem,
    pub ny: usize,
}

impl Strip {
    /// Vertex indices of grid column `i` (`0 ≤ i ≤ nx`), in increasing y.
    pub fn column(&self, i: usize) -> Vec<usize> {
        column(self.ny, i)
    }

    /// Mean position of a column.
    pub fn column_mean(&self, i: usize) -> Vector3<f64> {
        mean(&self.system.potential, &self.column(i))
    }
}

pub fn column(ny: usize, i: usize) -> Vec<usize> {
    (0..=ny).map(|j| i * (ny + 1) + j).collect()
}

pub fn mean(p: &IncrementalPotential, nodes: &[usize]) -> Vector3<f64> {
    nodes.iter().map(|&i| p.parts.state.x[i]).sum::<Vector3<f64>>() / nodes.len() as f64
}

/// Trapezoidal weights of the vertices of a column (a uniform line load or moment along the edge).
pub fn edge_weights(ny: usize) -> Vec<f64> {
    (0..=ny).map(|j| if j == 0 || j == ny { 0.5 } else { 1.0 }).collect()
}

/// Grid spacing along x for `nx` quads and a clamp line.
pub fn spacing(l: f64, nx: usize, clamp: ClampLine) -> f64 {
    match clamp {
        ClampLine::Centred => l / (nx as f64 - 0.5),
        ClampLine::FirstColumn => l / nx as f64,
    }
}

/// A quasi-static flat strip (no inertia, Δt = 1), clamped by eliminating the positions of the first two
/// vertex columns, with a force couple at the free end if given.
pub fn strip(
    l: f64,
    w: f64,
    n: (usize, usize),
    shell: &KlShell,
    clamp: ClampLine,
    couple: Option<ForceCouple>,
) -> Strip {
    shaped_strip(l, w, n, shell, clamp, couple, |x| x)
}

/// As [`strip`], with the rest positions of the flat strip mapped by `shape` (a curved rest state).
pub fn shaped_strip(
    l: f64,
    w: f64,
    (nx, ny): (usize, usize),
    shell: &KlShell,
    clamp: ClampLine,
    couple: Option<ForceCouple>,
    shape: impl Fn(Vector3<f64>) -> Vector3<f64>,
) -> Strip {
    let dx = spacing(l, nx, clamp);
    let lx = dx * nx as f64;
    let x0 = match clamp {
        ClampLine::Centred => -0.5 * dx,
        ClampLine::FirstColumn => 0.0,
    };
    let mut grid = procedural::rectangle_grid(lx, w, nx, ny).unwrap();
    for x in &mut grid.mesh.nodes {
        x.x += 0.5 * lx + x0;
        *x = shape(*x);
    }
    let options = SystemOptions {
        gravity: Vector3::zeros(),
        dynamic: false,
    };
    let mut system = build_kl_system(&grid.mesh, shell, &options).unwrap();
    if let Some(couple) = couple {
        system.potential.insert(couple);
    }
    let nodes: Vec<usize> = column(ny, 0).into_iter().chain(column(ny, 1)).collect();
    let targets = nodes.iter().map(|&i| system.rest_positions[i]).collect();
    system.potential.parts.position_constraints.push(PositionConstraint {
        label: "clamp".into(),
        nodes,
        targets,
        active: [true; 3],
    });
    Strip { system, ny }
}

/// Quasi-static settings with an absolute force tolerance.
pub fn settings(force_tolerance: f64) -> QuasiStaticSettings {
    QuasiStaticSettings {
        newton: NewtonSettings {
            tolerance: cosserat_solver::Tolerance::Absolute(force_tolerance),
            ..NewtonSettings::default()
        },
        ..QuasiStaticSettings::default()
    }
}

/// Least-squares slope of `ln e` against `ln h`.
pub fn observed_order(h: &[f64], e: &[f64]) -> f64 {
    let n = h.len() as f64;
    let (lx, ly): (Vec<f64>, Vec<f64>) = (h.iter().map(|v| v.ln()).collect(), e.iter().map(|v| v.ln()).collect());
    let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
    let sxy: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = lx.iter().map(|x| (x - mx) * (x - mx)).sum();
    sxy / sxx
}
