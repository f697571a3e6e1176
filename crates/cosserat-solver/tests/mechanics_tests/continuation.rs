//! Arc-length continuation on a shell: the snap-through of a shallow sinusoidal arch under a
//! sinusoidal load, against the closed form of shallow-arch theory.

use cosserat_assembly::boundary::PositionConstraint;
use cosserat_assembly::{ElementPair, ShellInput, ShellMesh, System, SystemOptions, build_system};
use cosserat_fem::mesh::{chord_placement, procedural};
use cosserat_material::rest::RestOptions;
use cosserat_material::{MaterialParameters, ModelOptions, ShellModel};
use cosserat_solver::{ArcLengthSettings, trace_quasi_static};
use nalgebra::Vector3;
use std::f64::consts::PI;

/// A pinned arch `z = e cos(πx/L)` over `x ∈ [−L/2, L/2]`, a strip of width `b` on `nx × 1` Tri6/Tri3
/// quads with its nodes on the curve (curved elements), both ends' positions held (hinges about y).
fn pinned_arch(l: f64, b: f64, e: f64, nx: usize, material: MaterialParameters) -> System {
    let grid = procedural::rectangle_grid(l, b, nx, 1).unwrap();
    let pair = ElementPair::Tri6Tri3;
    let mut mesh = ShellMesh::from_tri3(grid.mesh, pair, chord_placement);
    let lift = |x: &mut Vector3<f64>| x.z += e * (PI * x.x / l).cos();
    mesh.corners.nodes.iter_mut().for_each(lift);
    mesh.tri6.as_mut().expect("a Tri6 mesh").nodes.iter_mut().for_each(lift);
    let input = ShellInput {
        name: "arch".into(),
        mesh,
        pair,
        material,
        rest: RestOptions::new(ModelOptions::new(ShellModel::Shell)),
        quadrature: None,
        damping: 0.0,
        angular_inertia_density: 0.0,
    };
    let options = SystemOptions {
        gravity: Vector3::zeros(),
        dynamic: false,
    };
    let mut sys = build_system(&[input], &options).unwrap();
    let parts = &mut sys.potential.parts;
    let nodes: Vec<usize> = (0..parts.state.x.len())
        .filter(|&i| parts.state.x[i].x.abs() >= 0.5 * l - 1e-9)
        .collect();
    let targets = nodes.iter().map(|&i| parts.state.x[i]).collect();
    parts.position_constraints.push(PositionConstraint {
        label: "hinges".into(),
        nodes,
        targets,
        active: [true; 3],
    });
    sys
}

/// The consistent nodal loads of a uniform unit load on Tri6 elements: a third of each element's area
/// on each of its mid-edge nodes, none on its corners.
fn unit_load_weights(sys: &System) -> Vec<f64> {
    let shell = &sys.shells[0];
    let mut w = vec![0.0; sys.potential.parts.state.x.len()];
    for (nodes, area) in shell.disp_elements.iter().zip(&shell.element_areas) {
        for &i in &nodes[3..6] {
            w[i] += area / 3.0;
        }
    }
    w
}

#[test]
fn a_shallow_arch_snaps_through_at_the_limit_load_of_shallow_arch_theory() {
    // Shallow-arch theory (Euler–Bernoulli with the axial force of the mean stretch): for the rise
    // w = A cos(πx/L) of an arch with rest rise e under q₀ cos(πx/L) per length, equilibrium is
    // p = (ē − a) + a (ē² − a²)/4 with a = A/r, ē = e/r, r² = B/(E h) and p = q₀ L⁴/(π⁴ B r) (B the
    // bending stiffness per width). At ē = 4 it has a limit point at a = 2, p = 8, and a minimum at
    // a = −2, p = 0; the antisymmetric mode bifurcates only at a² = ē² − 16 = 0, past the limit point.
    let (l, b, h) = (1.0, 0.05, 0.01);
    // ν = 0: a strip bends like a beam.
    let material = MaterialParameters::new(h, 1e7, 0.0, 1000.0, 1e-3 * h);
    let bending = material.strip_bending_stiffness();
    let r = (bending / (material.youngs_modulus * h)).sqrt();
    let e = 4.0 * r;
    let mut sys = pinned_arch(l, b, e, 40, material);
    let weights = unit_load_weights(&sys);
    let rest: Vec<Vector3<f64>> = sys.potential.parts.state.x.clone();
    // λ = 1 is the theory's limit load: q₀ = 8 π⁴ B r / L⁴ per length, over the width b.
    let q_ref = 8.0 * PI.powi(4) * bending * r / l.powi(4);
    let crown: Vec<usize> = (0..rest.len()).filter(|&i| rest[i].x.abs() < 1e-9).collect();
    let settings = ArcLengthSettings {
        initial_increment: 0.05,
        end: 1.5,
        ..ArcLengthSettings::default()
    };
    let mut path = Vec::new();
    let points = trace_quasi_static(
        &mut sys.potential,
        &settings,
        &mut |p, lambda| {
            for (i, f) in p.parts.loads.forces.iter_mut().enumerate() {
                *f = Vector3::new(0.0, 0.0, -lambda * q_ref * (PI * rest[i].x / l).cos() * weights[i]);
            }
            Ok(())
        },
        &mut |p, point| {
            let rise = crown.iter().map(|&i| p.parts.state.x[i].z).sum::<f64>() / crown.len() as f64;
            path.push((rise / r, point.load_factor));
        },
    )
    .unwrap();
    assert_eq!(path.last().unwrap().1, 1.5);
    // The first limit point: the largest load before the crown passes the rest chord (a > 0).
    let (a_max, l_max) = path
        .iter()
        .filter(|p| p.0 > 0.0)
        .copied()
        .fold((f64::NAN, f64::NEG_INFINITY), |m, p| if p.1 > m.1 { p } else { m });
    // The second: the smallest load before the arch has passed its mirror image's limit (a > −ē).
    let (a_min, l_min) = path
        .iter()
        .filter(|p| p.0 > -4.0)
        .copied()
        .fold((f64::NAN, f64::INFINITY), |m, p| if p.1 < m.1 { p } else { m });
    let iterations: usize = points.iter().map(|p| p.iterations).sum();
    eprintln!(
        "shallow arch: {} steps, {:.2} corrector iterations per step; limit λ = {l_max:.4} at a = {a_max:.3} \
         (theory 1 at 2), minimum λ = {l_min:.4} at a = {a_min:.3} (theory 0 at −2)",
        points.len(),
        iterations as f64 / points.len() as f64,
    );
    assert!((l_max - 1.0).abs() < 0.02, "limit load ratio {l_max}");
    assert!((a_max - 2.0).abs() < 0.15, "crown rise at the limit point {a_max} r");
    assert!(l_min.abs() < 0.02, "minimum load ratio {l_min}");
    assert!((a_min + 2.0).abs() < 0.15, "crown rise at the minimum {a_min} r");
    // The crown moves down monotonically along the whole path (snap-through, no snap-back).
    assert!(path.windows(2).all(|w| w[1].0 < w[0].0));
}
