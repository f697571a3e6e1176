//! The numbers of `docs/micropolar-volume.md`: a clamped 1 m × 0.125 m slab curled by the prescribed
//! rest curvature `Γ_rest,21 = κ`, for several thicknesses and meshes, against the closed form
//! `k = κ C/(C + D)` and the Cosserat shell (Tri6/Tri3 plate model with the same material), with the
//! cost of each solve. Run with `cargo run --release -p cosserat-volume --example slab_study`; further
//! modes: `-- --explore` (refinement through the thickness), `-- --kernel` (cost per element of the
//! energy, the chained Hessian and the dual oracle), `-- --lotus N T_END` (the Lotus flower on an
//! N × N × 1 slab against the N/2 × N/2 shell up to `T_END` seconds).

use cosserat_assembly::boundary::{PositionConstraint, RotationPenalty};
use cosserat_assembly::{ElementPair, IncrementalPotential, ShellInput, ShellMesh, SystemOptions, build_system};
use cosserat_fem::mesh::{chord_placement, procedural};
use cosserat_material::rest::RestOptions;
use cosserat_material::{MaterialParameters, ModelOptions, ShellModel};
use cosserat_solver::{
    LinearSolverKind, LinearSolverSettings, NewtonSettings, QuasiStaticSettings, TimeStepSettings, TimeStepper,
    solve_quasi_static,
};
use cosserat_volume::measure::{fit_circle, hausdorff_distance};
use cosserat_volume::mesh::{SlabGrid, slab};
use cosserat_volume::{ContinuumParameters, MicropolarModuli, Slab, VolumeInput, build_volume_system};
use nalgebra::{Matrix3, Vector2, Vector3};
use std::time::Instant;

const LENGTH: f64 = 1.0;
const WIDTH: f64 = 0.125;
const KAPPA: f64 = std::f64::consts::PI;
const LEVELS: [f64; 4] = [0.25, 0.5, 0.75, 1.0];

fn material(lc: f64) -> ContinuumParameters {
    ContinuumParameters::new(1e6, 0.3, 1000.0, lc)
}

/// Newton settings with block-Jacobi CG steps and the reference's forcing sequence.
fn cg_newton() -> NewtonSettings {
    NewtonSettings {
        linear_solver: LinearSolverSettings {
            kind: LinearSolverKind::Cg,
            ..Default::default()
        },
        ..Default::default()
    }
}

fn rest_curvature(lambda: f64) -> Matrix3<f64> {
    let mut g = Matrix3::zeros();
    g[(1, 0)] = KAPPA * lambda;
    g
}

fn clamp(potential: &mut IncrementalPotential, rest: &[Vector3<f64>], rot_nodes: &[usize], disp_nodes: &[usize]) {
    let parts = &mut potential.parts;
    parts.position_constraints.push(PositionConstraint {
        label: "clamp".into(),
        nodes: disp_nodes.to_vec(),
        targets: disp_nodes.iter().map(|&i| rest[i]).collect(),
        active: [true; 3],
    });
    parts.rotation_penalties.push(RotationPenalty {
        label: "clamp".into(),
        nodes: rot_nodes.to_vec(),
        targets: vec![Matrix3::identity(); rot_nodes.len()],
        columns: [true; 3],
        stiffness: 1e6,
    });
}

struct Outcome {
    mid_surface: Vec<Vector3<f64>>,
    iterations: usize,
    seconds: f64,
    assembly_seconds: f64,
    solve_seconds: f64,
    n_dofs: usize,
    cg_iterations: usize,
}

fn volume_coil(h: f64, cells: [usize; 3], lc: f64, cg: bool) -> (SlabGrid, Outcome) {
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
    let n_dofs = sys.potential.n_dofs();
    let start = Instant::now();
    let settings = QuasiStaticSettings {
        newton: if cg { cg_newton() } else { NewtonSettings::default() },
        ..Default::default()
    };
    let reports = solve_quasi_static(
        &mut sys.potential,
        &LEVELS,
        &settings,
        &mut |_, lambda| handle.set_uniform(rest_curvature(lambda)),
        &mut |_, _| {},
    )
    .unwrap();
    let iterations = reports.iter().map(|r| r.total_iterations).sum();
    let assembly_seconds = reports.iter().map(|r| r.newton.assembly_seconds).sum();
    let solve_seconds = reports.iter().map(|r| r.newton.linear_solve_seconds).sum();
    let cg_iterations = reports.iter().map(|r| r.newton.cg_iterations).sum();
    let seconds = start.elapsed().as_secs_f64();
    let mid_surface = grid.mid_surface(&sys.potential.parts.state.x);
    (
        grid,
        Outcome {
            mid_surface,
            iterations,
            seconds,
            assembly_seconds,
            solve_seconds,
            n_dofs,
            cg_iterations,
        },
    )
}

fn shell_coil(h: f64, nx: usize, ny: usize, lc: f64) -> Outcome {
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
    let disp: Vec<usize> = (0..s.rest_disp_positions.len())
        .filter(|&i| s.rest_disp_positions[i].x < -0.5 * LENGTH + 1e-9)
        .collect();
    let rot: Vec<usize> = (0..s.rest_rot_positions.len())
        .filter(|&k| s.rest_rot_positions[k].x < -0.5 * LENGTH + 1e-9)
        .collect();
    let rest = s.rest_disp_positions.clone();
    clamp(&mut sys.potential, &rest, &rot, &disp);
    let n_dofs = sys.potential.n_dofs();
    let start = Instant::now();
    let reports = solve_quasi_static(
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
    Outcome {
        mid_surface: sys.potential.parts.state.x.clone(),
        iterations: reports.iter().map(|r| r.total_iterations).sum(),
        seconds: start.elapsed().as_secs_f64(),
        assembly_seconds: reports.iter().map(|r| r.newton.assembly_seconds).sum(),
        solve_seconds: reports.iter().map(|r| r.newton.linear_solve_seconds).sum(),
        n_dofs,
        cg_iterations: 0,
    }
}

/// The fitted curvature of the mid-line and the largest distance of the mid-surface from the exact arc
/// of curvature `k` clamped at `x = −L/2` (tangent `e_x`, curling towards −z).
fn measure(mid: &[Vector3<f64>], rest: &[Vector3<f64>], k: f64) -> (f64, f64) {
    let xz: Vec<Vector2<f64>> = mid.iter().map(|p| Vector2::new(p.x, p.z)).collect();
    let (_, r) = fit_circle(&xz).unwrap();
    let mut err: f64 = 0.0;
    for (p, x0) in mid.iter().zip(rest) {
        let s = x0.x + 0.5 * LENGTH;
        let arc = Vector3::new(-0.5 * LENGTH + (k * s).sin() / k, x0.y, -(1.0 - (k * s).cos()) / k);
        err = err.max((p - arc).norm());
    }
    (1.0 / r, err)
}

/// The Lotus flower's prescribed curvature (experiments.md §2.4, strongest layer b = 0.35) at a point
/// `(x, y)` at the start time `t` of a step.
fn lotus_curvature(x: f64, y: f64, t: f64) -> Matrix3<f64> {
    let b = 0.35;
    let alpha = 10.0 * (t / 6.0).clamp(0.0, 1.0);
    let sigma = (t / 6.0 + 1.0).min(1.8);
    let p = |u: f64| -0.2314286 + 10.89881 * u - 14.28571 * u * u + 4.427083 * u * u * u;
    let (sx, sy) = (b * p(sigma * x.abs() / 0.5), b * p(sigma * y.abs() / 0.5));
    let mut g = Matrix3::zeros();
    g[(0, 1)] = alpha * sy;
    g[(1, 0)] = -alpha * sx;
    g
}

fn pin_centre(potential: &mut IncrementalPotential, rest: &[Vector3<f64>], tol: f64) {
    let nodes: Vec<usize> = (0..rest.len())
        .filter(|&i| rest[i].x.abs() < tol && rest[i].y.abs() < tol)
        .collect();
    potential
        .parts
        .position_penalties
        .push(cosserat_assembly::boundary::PositionPenalty {
            label: "centre".into(),
            targets: nodes.iter().map(|&i| rest[i]).collect(),
            nodes,
            active: [true; 3],
            stiffness: 1e6,
        });
}

/// The Lotus flower's Tet4 row in small: a 1 m × 1 m × 1 cm slab (n × n × 1 cells) against the shell
/// (n/2 × n/2 Tri6/Tri3), dynamic with Δt = 10 ms up to `t_end`; cost per step and final shape distance.
fn lotus(n: usize, t_end: f64) {
    let dt = 0.01;
    let steps = (t_end / dt).round() as usize;
    let mut mat = ContinuumParameters::new(0.5e6, 0.3, 3000.0, 1.0);
    mat.mu_c_factor = 1.0;
    let grid = slab([1.0, 1.0, 0.01], [n, n, 1]).unwrap();
    let input = VolumeInput {
        mesh: grid.mesh.clone(),
        material: mat,
        damping: 0.0,
        angular_inertia_density: 0.0,
    };
    let options = SystemOptions {
        gravity: Vector3::zeros(),
        dynamic: true,
    };
    let mut vol = build_volume_system(&input, &options).unwrap();
    pin_centre(&mut vol.potential, &vol.rest_positions, 1e-9);
    let points = vol.point_positions.clone();
    let handle = vol.rest_curvature.clone();
    let mut settings = TimeStepSettings::fixed(dt);
    settings.newton = NewtonSettings {
        min_iterations: 1,
        ..cg_newton()
    };
    let mut stepper = TimeStepper::new(&vol.potential, settings).unwrap();
    let (mut newton, mut cg, mut asm, mut sol) = (0, 0, 0.0, 0.0);
    let start = Instant::now();
    for _ in 0..steps {
        let r = stepper
            .step(&mut vol.potential, &mut |_, t, _| {
                handle.set(|p| lotus_curvature(points[p].x, points[p].y, t))
            })
            .unwrap();
        newton += r.newton.iterations;
        cg += r.newton.cg_iterations;
        asm += r.newton.assembly_seconds;
        sol += r.newton.linear_solve_seconds;
    }
    let vol_seconds = start.elapsed().as_secs_f64();
    let vol_mid = grid.mid_surface(&vol.potential.parts.state.x);

    let tri = procedural::rectangle_grid(1.0, 1.0, n / 2, n / 2).unwrap();
    let pair = ElementPair::Tri6Tri3;
    let mut shell_material = MaterialParameters::new(0.01, 0.5e6, 0.3, 3000.0, 1.0);
    shell_material.mu_c_factor = 1.0;
    let shell_input = ShellInput {
        name: "lotus".into(),
        mesh: ShellMesh::from_tri3(tri.mesh, pair, chord_placement),
        pair,
        material: shell_material,
        rest: RestOptions::new(ModelOptions::new(ShellModel::Plate)),
        quadrature: None,
        damping: 0.0,
        angular_inertia_density: 0.0,
    };
    let mut shell = build_system(&[shell_input], &options).unwrap();
    let rest = shell.shells[0].rest_disp_positions.clone();
    let shell_points = shell.shells[0].rest_point_positions.clone();
    pin_centre(&mut shell.potential, &rest, 1e-9);
    let mut shell_stepper = TimeStepper::new(&shell.potential, TimeStepSettings::fixed(dt)).unwrap();
    let (mut shell_newton, mut shell_asm, mut shell_sol) = (0, 0.0, 0.0);
    let start = Instant::now();
    for _ in 0..steps {
        let r = shell_stepper
            .step(&mut shell.potential, &mut |p, t, _| {
                p.parts.shells[0].set_rest_fields_dyn(&mut |q| {
                    (None, Some(lotus_curvature(shell_points[q].x, shell_points[q].y, t)))
                })
            })
            .unwrap();
        shell_newton += r.newton.iterations;
        shell_asm += r.newton.assembly_seconds;
        shell_sol += r.newton.linear_solve_seconds;
    }
    let shell_seconds = start.elapsed().as_secs_f64();
    let hd = hausdorff_distance(&vol_mid, &shell.potential.parts.state.x);
    let lift = |x: &[Vector3<f64>]| x.iter().map(|p| p.z).fold(f64::NEG_INFINITY, f64::max);
    let s = steps as f64;
    println!(
        "| {n}×{n}×1 Tet4 | {} | {:.2} | {:.0} | {:.1} | {:.1} | {:.1} | {:.4} |",
        vol.potential.n_dofs(),
        newton as f64 / s,
        cg as f64 / newton.max(1) as f64,
        1e3 * vol_seconds / s,
        1e3 * asm / s,
        1e3 * sol / s,
        lift(&vol_mid)
    );
    println!(
        "| {}×{} Tri6/Tri3 shell | {} | {:.2} | – | {:.1} | {:.1} | {:.1} | {:.4} |",
        n / 2,
        n / 2,
        shell.potential.n_dofs(),
        shell_newton as f64 / s,
        1e3 * shell_seconds / s,
        1e3 * shell_asm / s,
        1e3 * shell_sol / s,
        lift(&shell.potential.parts.state.x)
    );
    println!("Hausdorff distance slab mid-surface ↔ shell nodes at t = {t_end} s: {hd:.3e} m");
}

/// Time per element of the f64 energy, the chained exact Hessian and the whole-element second-order
/// dual oracle (24 directions) of one Tet4 element in a general state.
fn kernel_cost() {
    use cosserat_geometry::rotation::{
        RotationJet, exp_map, quaternion_from_matrix, quaternion_update, rotation_matrix,
    };
    use cosserat_volume::density::strain_hessian;
    use cosserat_volume::element::{ElementDerivatives, accumulate};
    use cosserat_volume::kernel::{PointState, point_hessian, point_value};
    use cosserat_volume::oracle::{ElementContext, element_energy};
    use cosserat_volume::tet4::{deformation_gradient, point_omega, tet4_point};
    use nalgebra::SVector;
    use num_dual::Dual2SVec64;
    use std::hint::black_box;
    let x_rest = [
        Vector3::new(0.0, 0.0, 0.0),
        Vector3::new(0.1, 0.0, 0.0),
        Vector3::new(0.05, 0.0866, 0.0),
        Vector3::new(0.05, 0.0289, 0.0816),
    ];
    let point = tet4_point(&x_rest).unwrap();
    let moduli = MicropolarModuli::of(&material(0.05)).unwrap();
    let d = strain_hessian(&moduli);
    let q = |v: Vector3<f64>| quaternion_from_matrix(&exp_map(&v));
    let qp = q(Vector3::new(0.1, 0.2, -0.3));
    let qn = [0.1, 0.2, 0.3, 0.4].map(|a| q(Vector3::new(a, -a, 0.5 * a)));
    let w = [0.5, -1.0, 2.0, 0.3].map(|a| Vector3::new(a, 0.2, -a));
    let x = x_rest.map(|p| p * 1.01 + Vector3::new(0.001, 0.0, 0.0));
    let rest = Matrix3::new(0.0, 1.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.5);
    let dt = 0.01;
    let reps = 20_000;
    let time = |f: &mut dyn FnMut()| {
        let start = Instant::now();
        for _ in 0..reps {
            f();
        }
        start.elapsed().as_secs_f64() / reps as f64
    };
    let t_value = time(&mut || {
        let rp = rotation_matrix(&quaternion_update(&qp, &point_omega(&point, &w), dt));
        let nr: [Matrix3<f64>; 4] = std::array::from_fn(|k| rotation_matrix(&quaternion_update(&qn[k], &w[k], dt)));
        let f = deformation_gradient(&point, &x);
        black_box(point_value(&point, &f, &rp, std::array::from_fn(|k| &nr[k]), &rest, &d));
    });
    let t_hessian = time(&mut || {
        let jets: [RotationJet; 4] = std::array::from_fn(|k| RotationJet::of_update(&qn[k], &w[k], dt));
        let pj = RotationJet::of_update(&qp, &point_omega(&point, &w), dt);
        let state = PointState {
            f: deformation_gradient(&point, &x),
            point_jet: &pj,
            node_jets: std::array::from_fn(|k| &jets[k]),
            rest_curvature: &rest,
        };
        let local = point_hessian::<4, 21>(&point, &state, &d);
        let mut out = ElementDerivatives::<24>::zeros();
        accumulate(&point, &local, dt, point.weight, &mut out);
        black_box(out);
    });
    let ctx = ElementContext {
        point: &point,
        x_start: x,
        point_quaternion: qp,
        node_quaternions: qn,
        dt,
        rest_curvature: &rest,
        moduli: &moduli,
    };
    let u = SVector::<f64, 24>::from_fn(|i, _| if i < 12 { 0.0 } else { w[(i - 12) / 3][i % 3] });
    let oracle_reps = 200;
    let start = Instant::now();
    for _ in 0..oracle_reps {
        black_box(num_dual::hessian(
            |u: SVector<Dual2SVec64<24>, 24>| {
                let v: [Vector3<Dual2SVec64<24>>; 4] =
                    std::array::from_fn(|i| Vector3::new(u[3 * i], u[3 * i + 1], u[3 * i + 2]));
                let o: [Vector3<Dual2SVec64<24>>; 4] =
                    std::array::from_fn(|k| Vector3::new(u[12 + 3 * k], u[13 + 3 * k], u[14 + 3 * k]));
                element_energy(&ctx, &v, &o)
            },
            &u,
        ));
    }
    let t_oracle = start.elapsed().as_secs_f64() / oracle_reps as f64;
    println!("| f64 energy | chained exact Hessian | whole-element Dual2 oracle (24 dirs) | oracle / chained |");
    println!("|---|---|---|---|");
    println!(
        "| {:.2} µs | {:.2} µs | {:.1} µs | {:.0}× |",
        1e6 * t_value,
        1e6 * t_hessian,
        1e6 * t_oracle,
        t_oracle / t_hessian
    );
}

fn main() {
    if std::env::args().any(|a| a == "--kernel") {
        kernel_cost();
        return;
    }
    if let Some(pos) = std::env::args().position(|a| a == "--lotus") {
        let args: Vec<String> = std::env::args().collect();
        let n: usize = args.get(pos + 1).and_then(|v| v.parse().ok()).unwrap_or(16);
        let t_end: f64 = args.get(pos + 2).and_then(|v| v.parse().ok()).unwrap_or(1.0);
        println!(
            "| model | DOFs | Newton it./step | CG it./Newton it. | ms/step | assembly ms/step | solve ms/step | max z [m] |"
        );
        println!("|---|---|---|---|---|---|---|---|");
        lotus(n, t_end);
        return;
    }
    if std::env::args().any(|a| a == "--explore") {
        for (h, cells) in [
            (0.04, [8, 1, 1]),
            (0.04, [16, 2, 2]),
            (0.04, [32, 4, 4]),
            (0.02, [8, 1, 1]),
            (0.02, [16, 2, 2]),
            (0.02, [32, 4, 4]),
        ] {
            let (grid, out) = volume_coil(h, cells, 0.1, false);
            let rest_mid = grid.mid_surface(&grid.mesh.nodes);
            let k_th = Slab {
                material: material(0.1),
                thickness: h,
            }
            .curvature_under_rest_curvature(KAPPA);
            let (k_fit, dist) = measure(&out.mid_surface, &rest_mid, k_th);
            println!(
                "h {h} cells {cells:?}: k/κ {:.5} th {:.5} rel {:+.2e} dist {dist:.2e} it {} {:.1}s",
                k_fit / KAPPA,
                k_th / KAPPA,
                (k_fit - k_th) / k_th,
                out.iterations,
                out.seconds
            );
        }
        return;
    }
    println!("κ = π rad/m, E = 1 MPa, ν = 0.3, clamped at x = -0.5 m, 4 load levels");
    println!();
    println!(
        "| L_c [m] | h [m] | cells | DOFs | k_fit/κ | k_theory/κ | (k_fit − k_th)/k_th | max dist to arc(k_th) [m] | Newton it. | time [s] |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for lc in [0.1] {
        for h in [0.04, 0.02, 0.01] {
            for (nx, ny) in [(16, 2), (32, 4), (64, 8)] {
                let (grid, out) = volume_coil(h, [nx, ny, 1], lc, false);
                let rest_mid = grid.mid_surface(&grid.mesh.nodes);
                let k_th = Slab {
                    material: material(lc),
                    thickness: h,
                }
                .curvature_under_rest_curvature(KAPPA);
                let (k_fit, dist) = measure(&out.mid_surface, &rest_mid, k_th);
                println!(
                    "| {lc} | {h} | {nx}×{ny}×1 | {} | {:.5} | {:.5} | {:+.2e} | {:.2e} | {} | {:.2} |",
                    out.n_dofs,
                    k_fit / KAPPA,
                    k_th / KAPPA,
                    (k_fit - k_th) / k_th,
                    dist,
                    out.iterations,
                    out.seconds
                );
            }
        }
    }
    println!();
    println!("Shell comparison (Tri6/Tri3 plate, nx/2 × ny/2 cells, same nodes as the slab mid-surface):");
    println!(
        "| L_c | h | slab cells | shell k_fit/κ | Hausdorff/L | slab: it., asm s, solve s | shell: it., asm s, solve s |"
    );
    println!("|---|---|---|---|---|---|---|");
    for (lc, h) in [(0.1, 0.01), (0.1, 0.02)] {
        for (nx, ny) in [(32, 4), (64, 8)] {
            let (grid, vol) = volume_coil(h, [nx, ny, 1], lc, false);
            let shell = shell_coil(h, nx / 2, ny / 2, lc);
            let rest_mid = grid.mid_surface(&grid.mesh.nodes);
            let (k_shell, _) = measure(&shell.mid_surface, &rest_mid, KAPPA);
            let hd = hausdorff_distance(&vol.mid_surface, &shell.mid_surface) / LENGTH;
            println!(
                "| {lc} | {h} | {nx}×{ny}×1 | {:.5} | {hd:.2e} | {}, {:.3}, {:.3} | {}, {:.3}, {:.3} |",
                k_shell / KAPPA,
                vol.iterations,
                vol.assembly_seconds,
                vol.solve_seconds,
                shell.iterations,
                shell.assembly_seconds,
                shell.solve_seconds
            );
        }
    }
    println!();
    println!("Newton-CG on the same solves (LinearSolverKind::Cg: block-Jacobi PCG, reference forcing):");
    println!(
        "| h | cells | DOFs | Newton it. | CG it. | asm s | CG s | total s | direct total s | max node diff [m] |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for (h, cells) in [(0.02, [32, 4, 1]), (0.01, [32, 4, 1])] {
        let (_, cg) = volume_coil(h, cells, 0.1, true);
        let (_, direct) = volume_coil(h, cells, 0.1, false);
        let diff = cg
            .mid_surface
            .iter()
            .zip(&direct.mid_surface)
            .map(|(a, b)| (a - b).norm())
            .fold(0.0, f64::max);
        println!(
            "| {h} | {}×{}×{} | {} | {} | {} | {:.3} | {:.3} | {:.2} | {:.2} | {diff:.1e} |",
            cells[0],
            cells[1],
            cells[2],
            cg.n_dofs,
            cg.iterations,
            cg.cg_iterations,
            cg.assembly_seconds,
            cg.solve_seconds,
            cg.seconds,
            direct.seconds
        );
    }
}
