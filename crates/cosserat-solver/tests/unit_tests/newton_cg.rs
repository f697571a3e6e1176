//! Newton's method with conjugate-gradient steps (`LinearSolverKind::Cg`) on the toy problems: the
//! forcing sequences and their tolerances.

use cosserat_solver::{
    CgForcing, CgSettings, LinearSolverKind, LinearSolverSettings, NewtonError, NewtonProblem, NewtonSettings,
    NewtonSolver, SettingName,
};
use nalgebra::DVector;

use super::fixtures::{block_grid, random_vector, rng};
use super::toy::{Quadratic, Rosenbrock, SpringChain};

fn cg_settings(relative_tolerance: f64, max_iterations: Option<usize>) -> LinearSolverSettings {
    LinearSolverSettings {
        kind: LinearSolverKind::Cg,
        cg: CgSettings {
            relative_tolerance,
            max_iterations,
        },
        ..Default::default()
    }
}

fn newton_cg(forcing: CgForcing) -> NewtonSettings {
    NewtonSettings {
        linear_solver: cg_settings(1e-8, None),
        cg_forcing: forcing,
        tolerance: cosserat_solver::Tolerance::Absolute(1e-7),
        ..Default::default()
    }
}

#[test]
fn newton_with_cg_minimises_a_quadratic() {
    let mut r = rng(29);
    let a = block_grid(6, 5, 1e-1, &mut r);
    let b = random_vector(a.n(), &mut r);
    let dense = a.to_dense();
    let lambda_min = dense.clone().symmetric_eigen().eigenvalues.min();
    let reference = dense.cholesky().unwrap().solve(&DVector::from_column_slice(&b));
    let mut problem = Quadratic { a, b };
    let mut x = vec![0.0; problem.n_dofs()];
    let mut solver = NewtonSolver::for_problem(&problem, newton_cg(CgForcing::Reference)).unwrap();
    let report = solver.solve(&mut problem, &mut x).unwrap();
    // Inexact steps: convergence, not one iteration.
    assert!(report.residual() < 1e-7);
    assert_eq!(report.residuals.len(), report.iterations + 1);
    assert_eq!(report.factorisations.cg, report.iterations);
    assert_eq!(
        report.factorisations.llt + report.factorisations.lblt + report.factorisations.lu,
        0
    );
    assert!(report.cg_iterations >= report.iterations);
    assert_eq!(report.cg_negative_curvature_stops + report.cg_iteration_cap_stops, 0);
    // ‖x − x*‖₂ ≤ ‖∇Π‖₂ / λ_min ≤ √n · residual / λ_min.
    let n = x.len() as f64;
    let err = (DVector::from_column_slice(&x) - &reference).norm();
    assert!(err <= n.sqrt() * report.residual() / lambda_min, "{err:e}");
    assert_eq!(solver.linear_solver().symbolic_analysis_count(), 0);
}

/// A stretched 3D spring chain between walls, with its straight equilibrium in closed form (equal
/// tension `T` in all springs: `d_i = l_i + T/k_i`, `Σ d_i = |B − A|`), and a perturbed start.
fn stretched_chain() -> (SpringChain, Vec<f64>, Vec<f64>) {
    let stiffness = vec![12.0, 30.0, 20.0, 45.0, 25.0, 18.0];
    let rest_length = vec![0.4, 0.3, 0.5, 0.45, 0.35, 0.5];
    let chain = SpringChain::new(stiffness.clone(), rest_length.clone());
    let n_nodes = chain.n_nodes;
    let end: [f64; 3] = [2.5, -1.5, 2.0];
    let span = end.iter().map(|v| v * v).sum::<f64>().sqrt();
    let tension = (span - rest_length.iter().sum::<f64>()) / stiffness.iter().map(|k| 1.0 / k).sum::<f64>();
    assert!(tension > 0.0);
    let mut exact = vec![0.0; 3 * n_nodes];
    let mut s = 0.0;
    for node in 0..n_nodes {
        for d in 0..3 {
            exact[3 * node + d] = end[d] * s / span;
        }
        if node + 1 < n_nodes {
            s += rest_length[node] + tension / stiffness[node];
        }
    }
    let mut start = exact.clone();
    let mut r = rng(30);
    for node in 1..n_nodes - 1 {
        let p = random_vector(3, &mut r);
        for d in 0..3 {
            start[3 * node + d] += 0.3 * p[d];
        }
    }
    (chain, start, exact)
}

#[test]
fn newton_with_cg_reaches_the_spring_chain_equilibrium_with_fixed_walls() {
    let (mut chain, start, exact) = stretched_chain();
    let mut x = start.clone();
    // The softest mode is transverse with stiffness about T/d ≥ 1 N/m: a force residual of 1e-10 N
    // bounds the position error by about 1e-10 m.
    let settings = NewtonSettings {
        tolerance: cosserat_solver::Tolerance::Absolute(1e-10),
        ..newton_cg(CgForcing::Reference)
    };
    let mut solver = NewtonSolver::for_problem(&chain, settings).unwrap();
    let report = solver.solve(&mut chain, &mut x).unwrap();
    assert!(report.residual() < 1e-10);
    let n = x.len();
    for i in (0..3).chain(n - 3..n) {
        assert_eq!(x[i], start[i], "wall unknown {i} moved");
    }
    let err = x.iter().zip(&exact).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(err < 1e-8, "max position error {err:e}");
    // The inexact steps still converge superlinearly: the reference forcing makes the relative CG
    // residual ~ ‖g‖^{3/2}, so the last residual ratio is far below the linear rate of a fixed forcing.
    let m = report.residuals.len();
    let (a, b, c) = (
        report.residuals[m - 3],
        report.residuals[m - 2],
        report.residuals[m - 1],
    );
    let order = (c / b).ln() / (b / a).ln();
    assert!(order > 1.3, "observed order {order} from {:?}", report.residuals);
}

#[test]
fn a_fixed_forcing_converges_linearly_and_sets_the_cg_tolerance() {
    let (mut chain, start, exact) = stretched_chain();
    let mut x = start;
    let settings = NewtonSettings {
        tolerance: cosserat_solver::Tolerance::Absolute(1e-10),
        ..newton_cg(CgForcing::Fixed(0.25))
    };
    let mut solver = NewtonSolver::for_problem(&chain, settings).unwrap();
    let report = solver.solve(&mut chain, &mut x).unwrap();
    let err = x.iter().zip(&exact).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(err < 1e-8, "max position error {err:e}");
    assert_eq!(
        solver.linear_solver().last_cg_report().unwrap().relative_tolerance,
        0.25
    );
    // Near the solution the Newton map is linear, and each inexact step removes at least the fraction
    // 1 − η of the error in the energy norm (CG is optimal there): the gradient shrinks, but no faster
    // than a fixed fraction per step on average, so more iterations than with the reference forcing.
    let mut reference = newton_cg(CgForcing::Reference);
    reference.tolerance = cosserat_solver::Tolerance::Absolute(1e-10);
    let (mut chain2, start2, _) = stretched_chain();
    let mut x2 = start2;
    let report_ref = NewtonSolver::for_problem(&chain2, reference)
        .unwrap()
        .solve(&mut chain2, &mut x2)
        .unwrap();
    assert!(
        report.iterations > report_ref.iterations,
        "fixed {} vs reference {}",
        report.iterations,
        report_ref.iterations
    );
}

#[test]
fn newton_with_cg_converges_on_the_chained_rosenbrock_function() {
    // The Hessian is indefinite on the way (the direct solver needs L B Lᵀ there); truncated CG still
    // yields descent directions.
    let n = 30;
    let mut problem = Rosenbrock::new(n);
    let mut x: Vec<f64> = (0..n).map(|i| if i % 2 == 0 { -1.2 } else { 1.0 }).collect();
    let mut solver = NewtonSolver::for_problem(&problem, newton_cg(CgForcing::Reference)).unwrap();
    let report = solver.solve(&mut problem, &mut x).unwrap();
    assert!(report.residual() < 1e-7);
    let err = x.iter().map(|v| (v - 1.0).abs()).fold(0.0, f64::max);
    assert!(err < 1e-6, "max |x_i − 1| = {err:e}");
    assert_eq!(report.factorisations.cg, report.iterations);
    // CG meets negative curvature on the way (measured: 3 of 63 solves) and the truncated directions
    // descend without being flipped.
    assert!(report.cg_negative_curvature_stops > 0, "{report:?}");
    assert_eq!(report.direction_flips, 0);
}

#[test]
fn chord_steps_are_not_taken_with_cg() {
    let (mut chain, start, _) = stretched_chain();
    let mut x = start;
    let settings = NewtonSettings {
        reuse_max_ratio: Some(0.9),
        ..newton_cg(CgForcing::Reference)
    };
    let report = NewtonSolver::for_problem(&chain, settings)
        .unwrap()
        .solve(&mut chain, &mut x)
        .unwrap();
    assert_eq!(report.chord_iterations, 0);
    assert_eq!(report.factorisations.cg, report.iterations);
}

#[test]
fn invalid_cg_settings_are_named() {
    let problem = Rosenbrock::new(4);
    let cases = [
        (newton_cg(CgForcing::Fixed(1.5)), SettingName::CgForcing),
        (newton_cg(CgForcing::Fixed(0.0)), SettingName::CgForcing),
        (
            NewtonSettings {
                linear_solver: cg_settings(0.0, None),
                ..Default::default()
            },
            SettingName::CgRelativeTolerance,
        ),
        (
            NewtonSettings {
                linear_solver: cg_settings(1e-8, Some(0)),
                ..Default::default()
            },
            SettingName::CgMaxIterations,
        ),
    ];
    for (settings, expected) in cases {
        match NewtonSolver::for_problem(&problem, settings) {
            Err(NewtonError::InvalidSetting { name, .. }) => assert_eq!(name, expected),
            other => panic!("expected InvalidSetting {expected:?}, got {other:?}"),
        }
    }
}

#[test]
fn an_exactly_stationary_start_converges_with_a_zero_step() {
    // With `min_iterations = 1` (the time stepper's setting) Newton must take a step even at a start that
    // satisfies the tolerance; at an exactly stationary point (a scene at rest, Rosenbrock at (1, 1))
    // that step is zero for a direct solve and for CG alike, and is accepted rather than rejected as a
    // non-descent direction.
    for linear_solver in [LinearSolverSettings::default(), cg_settings(1e-8, None)] {
        let mut problem = Rosenbrock::new(2);
        let mut x = [1.0, 1.0];
        let settings = NewtonSettings {
            min_iterations: 1,
            linear_solver,
            ..Default::default()
        };
        let report = NewtonSolver::for_problem(&problem, settings)
            .unwrap()
            .solve(&mut problem, &mut x)
            .unwrap();
        assert_eq!((report.iterations, report.residuals.clone()), (1, vec![0.0, 0.0]));
        assert_eq!(x, [1.0, 1.0]);
        assert_eq!(report.energy, 0.0);
    }
}
