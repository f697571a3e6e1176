//! The built system under `cosserat-solver`'s Newton method with block-Jacobi conjugate gradients
//! (`LinearSolverKind::Cg`, the Lotus Tet4 row's solver) and with a direct factorisation: time steps,
//! single solves and quasi-static load levels reach the same states to the solvers' tolerance.

use super::common::{material, small_system};
use cosserat_assembly::boundary::PositionConstraint;
use cosserat_solver::potential_problem::PotentialProblem;
use cosserat_solver::{
    LinearSolverKind, LinearSolverSettings, NewtonSettings, NewtonSolver, QuasiStaticSettings, TimeStepSettings,
    TimeStepper, solve_quasi_static,
};
use cosserat_volume::VolumeSystem;
use nalgebra::Matrix3;

fn cg() -> LinearSolverSettings {
    LinearSolverSettings {
        kind: LinearSolverKind::Cg,
        ..Default::default()
    }
}

/// Clamps the slab's end x = −0.05 exactly (all three axes of every node there).
fn clamp(sys: &mut VolumeSystem) {
    let nodes: Vec<usize> = (0..sys.rest_positions.len())
        .filter(|&i| sys.rest_positions[i].x < -0.05 + 1e-9)
        .collect();
    let targets = nodes.iter().map(|&i| sys.rest_positions[i]).collect();
    sys.potential.parts.position_constraints.push(PositionConstraint {
        label: "clamp".into(),
        nodes,
        targets,
        active: [true; 3],
    });
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

#[test]
fn cg_time_steps_agree_with_direct_time_steps() {
    // A clamped slab sagging under gravity for 5 steps of 10 ms, with CG steps and with the direct
    // factorisation; both converge to the same residual tolerance, so the states agree to about that
    // tolerance over the stiffness.
    let mut cg_sys = small_system([4, 2, 1], material(), true, 0.0);
    let mut lu_sys = small_system([4, 2, 1], material(), true, 0.0);
    clamp(&mut cg_sys);
    clamp(&mut lu_sys);
    let mut lu_settings = TimeStepSettings::fixed(0.01);
    lu_settings.newton.tolerance = cosserat_solver::Tolerance::Absolute(1e-7);
    let mut cg_settings = lu_settings;
    cg_settings.newton.linear_solver = cg();
    let mut cg_stepper = TimeStepper::new(&cg_sys.potential, cg_settings).unwrap();
    let mut lu_stepper = TimeStepper::new(&lu_sys.potential, lu_settings).unwrap();
    let mut total_cg = 0;
    for _ in 0..5 {
        let a = cg_stepper.step(&mut cg_sys.potential, &mut |_, _, _| {}).unwrap();
        let b = lu_stepper.step(&mut lu_sys.potential, &mut |_, _, _| {}).unwrap();
        assert!(a.newton.residual() < 1e-7 && b.newton.residual() < 1e-7);
        assert_eq!(a.newton.factorisations.cg, a.newton.iterations);
        assert_eq!(b.newton.factorisations.cg, 0);
        total_cg += a.newton.cg_iterations;
    }
    assert!(total_cg > 0);
    assert_eq!(cg_stepper.solver().linear_solver().symbolic_analysis_count(), 0);
    let (xa, xb) = (&cg_sys.potential.parts.state.x, &lu_sys.potential.parts.state.x);
    let sag = xb.iter().map(|x| x.z.abs()).fold(0.0, f64::max);
    assert!(sag > 1e-5, "the slab must move: {sag}");
    let diff = xa.iter().zip(xb).map(|(a, b)| (a - b).norm()).fold(0.0, f64::max);
    assert!(diff < 1e-6 * sag, "max difference {diff} for a sag of {sag}");
    let qa = &cg_sys.potential.parts.state.q;
    let qb = &lu_sys.potential.parts.state.q;
    assert!(qa.iter().zip(qb).all(|(a, b)| (a - b).norm() < 1e-6));
}

#[test]
fn one_cg_newton_solve_matches_the_direct_solution() {
    let mut sys = small_system([3, 2, 1], material(), true, 0.0);
    clamp(&mut sys);
    let fixed = sys.potential.fixed_dofs().map(|(m, _)| m);
    let n = sys.potential.n_dofs();
    let direct = NewtonSettings {
        residual_scale: 0.01,
        tolerance: cosserat_solver::Tolerance::Absolute(1e-9),
        ..Default::default()
    };
    let iterative = NewtonSettings {
        linear_solver: cg(),
        ..direct
    };
    let mut problem = PotentialProblem::new(&mut sys.potential, fixed);
    let mut u_cg = vec![0.0; n];
    let report = NewtonSolver::for_problem(&problem, iterative)
        .unwrap()
        .solve(&mut problem, &mut u_cg)
        .unwrap();
    assert!(report.cg_iterations > 0 && report.factorisations.cg == report.iterations);
    let mut u_lu = vec![0.0; n];
    NewtonSolver::for_problem(&problem, direct)
        .unwrap()
        .solve(&mut problem, &mut u_lu)
        .unwrap();
    let scale = max_abs(&u_lu);
    let diff = u_cg.iter().zip(&u_lu).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(diff < 1e-6 * scale, "difference {diff} of {scale}");
}

#[test]
fn quasi_static_cg_levels_agree_with_direct_levels() {
    // The slab curled by a ramped rest curvature without inertia (a badly conditioned system for CG):
    // the equilibria of both solvers agree to the residual tolerance over the stiffness.
    let run = |linear_solver: LinearSolverSettings| {
        let mut sys = small_system([6, 1, 1], material(), false, 0.0);
        clamp(&mut sys);
        sys.potential.parts.loads.gravity = nalgebra::Vector3::zeros();
        let handle = sys.rest_curvature.clone();
        let settings = QuasiStaticSettings {
            newton: NewtonSettings {
                linear_solver,
                tolerance: cosserat_solver::Tolerance::Absolute(1e-9),
                ..Default::default()
            },
            ..Default::default()
        };
        let reports = solve_quasi_static(
            &mut sys.potential,
            &[0.5, 1.0],
            &settings,
            &mut |_, lambda| {
                let mut g = Matrix3::zeros();
                g[(1, 0)] = 5.0 * lambda;
                handle.set_uniform(g);
            },
            &mut |_, _| {},
        )
        .unwrap();
        let cg_iterations: usize = reports.iter().map(|r| r.newton.cg_iterations).sum();
        (sys.potential.parts.state.x.clone(), sys.rest_positions, cg_iterations)
    };
    let (x_cg, rest, cg_iterations) = run(cg());
    let (x_lu, _, direct_cg) = run(LinearSolverSettings::default());
    assert!(cg_iterations > 0 && direct_cg == 0);
    let deflection = x_lu.iter().zip(&rest).map(|(x, r)| (x - r).norm()).fold(0.0, f64::max);
    assert!(deflection > 1e-4, "the slab must curl: {deflection}");
    let diff = x_cg.iter().zip(&x_lu).map(|(a, b)| (a - b).norm()).fold(0.0, f64::max);
    assert!(
        diff < 1e-6 * deflection,
        "max difference {diff} for a deflection of {deflection}"
    );
}
