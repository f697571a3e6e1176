//! Newton-CG on a toy problem (convergence, fixed unknowns, settings) and on the volumetric system,
//! against the direct Newton solver and time stepper of `cosserat-solver`.

use super::common::{material, small_system};
use cosserat_assembly::boundary::PositionConstraint;
use cosserat_solver::potential_problem::PotentialProblem;
use cosserat_solver::{NewtonProblem, NewtonSettings, NewtonSolver, ProblemError, TimeStepSettings, TimeStepper};
use cosserat_volume::error::CgNewtonSetting;
use cosserat_volume::{
    CgNewtonError, CgNewtonSettings, CgNewtonSolver, CgTimeStepSettings, CgTimeStepper, ForcingTerm,
};
use faer::sparse::{SymbolicSparseColMat, SymbolicSparseColMatRef};

/// `Π(x) = Σ_i (x_i − i)⁴/4 + ½ Σ_i (x_{i+1} − x_i − 1)²` on 6 unknowns: a strictly convex chain of
/// unit-length springs whose minimiser is `x_i = i` (every term vanishes there).
struct Chain {
    pattern: SymbolicSparseColMat<usize>,
    fixed: Option<Vec<bool>>,
}

impl Chain {
    fn new(fixed: Option<Vec<bool>>) -> Self {
        let n = 6;
        let mut col_ptr = vec![0];
        let mut rows = Vec::new();
        for c in 0..n {
            if c > 0 {
                rows.push(c - 1);
            }
            rows.push(c);
            col_ptr.push(rows.len());
        }
        Self {
            pattern: SymbolicSparseColMat::new_checked(n, n, col_ptr, None, rows),
            fixed,
        }
    }
}

impl NewtonProblem for Chain {
    fn n_dofs(&self) -> usize {
        6
    }
    fn hessian_pattern(&self) -> SymbolicSparseColMatRef<'_, usize> {
        self.pattern.as_ref()
    }
    fn value(&mut self, x: &[f64]) -> Result<f64, ProblemError> {
        let mut e = 0.0;
        for i in 0..6 {
            e += (x[i] - i as f64).powi(4) / 4.0;
            if i + 1 < 6 {
                e += 0.5 * (x[i + 1] - x[i] - 1.0).powi(2);
            }
        }
        Ok(e)
    }
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> Result<f64, ProblemError> {
        for i in 0..6 {
            g[i] = (x[i] - i as f64).powi(3);
            if i + 1 < 6 {
                g[i] -= x[i + 1] - x[i] - 1.0;
            }
            if i > 0 {
                g[i] += x[i] - x[i - 1] - 1.0;
            }
        }
        self.value(x)
    }
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> Result<f64, ProblemError> {
        // Column c holds (c − 1, c) then (c, c).
        let mut idx = 0;
        for c in 0..6 {
            if c > 0 {
                h[idx] = -1.0;
                idx += 1;
            }
            let springs = if c == 0 || c == 5 { 1.0 } else { 2.0 };
            h[idx] = 3.0 * (x[c] - c as f64).powi(2) + springs;
            idx += 1;
        }
        self.gradient(x, g)
    }
    fn fixed_dofs(&self) -> Option<&[bool]> {
        self.fixed.as_deref()
    }
}

#[test]
fn newton_cg_minimises_a_convex_chain() {
    let mut problem = Chain::new(None);
    let mut solver = CgNewtonSolver::for_problem(&problem, CgNewtonSettings::default()).unwrap();
    let mut x = [3.0, -2.0, 0.5, 7.0, 1.0, 0.0];
    let report = solver.solve(&mut problem, &mut x).unwrap();
    assert!(report.residual() < 1e-7);
    assert_eq!(report.residuals.len(), report.iterations + 1);
    assert_eq!(report.cg_iterations.len(), report.iterations);
    // The error shrinks like the quartic allows (factor 2/3 per exact Newton step near a degenerate
    // minimum): the gradient tolerance 1e-7 bounds |x_i − i|³ by about 1e-7.
    for (i, xi) in x.iter().enumerate() {
        assert!((xi - i as f64).abs() < 1e-2, "x[{i}] = {xi}");
    }
}

#[test]
fn fixed_unknowns_keep_their_values_and_do_not_count() {
    let mut fixed = vec![false; 6];
    fixed[0] = true;
    let mut problem = Chain::new(Some(fixed));
    let mut solver = CgNewtonSolver::for_problem(&problem, CgNewtonSettings::default()).unwrap();
    let mut x = [10.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    solver.solve(&mut problem, &mut x).unwrap();
    assert_eq!(x[0], 10.0);
    let mut g = [0.0; 6];
    problem.gradient(&x, &mut g).unwrap();
    assert!(g[1..].iter().all(|g| g.abs() < 1e-7));
    assert!(g[0].abs() > 1.0);
}

#[test]
fn invalid_settings_are_named() {
    let problem = Chain::new(None);
    let bad = CgNewtonSettings {
        forcing: ForcingTerm::Fixed(1.5),
        ..Default::default()
    };
    assert!(matches!(
        CgNewtonSolver::for_problem(&problem, bad),
        Err(CgNewtonError::InvalidSetting {
            name: CgNewtonSetting::Forcing,
            ..
        })
    ));
    let bad = CgNewtonSettings {
        residual_tolerance: -1.0,
        ..Default::default()
    };
    assert!(matches!(
        CgNewtonSolver::for_problem(&problem, bad),
        Err(CgNewtonError::InvalidSetting {
            name: CgNewtonSetting::ResidualTolerance,
            ..
        })
    ));
    // The reference forcing sequence: 0.1 far from the solution, ‖g‖^{3/2} near it.
    assert_eq!(ForcingTerm::Reference.tolerance(100.0), 0.1);
    assert!((ForcingTerm::Reference.tolerance(1e-4) - 1e-6).abs() < 1e-18);
}

/// Clamps the slab's end x = −0.05 exactly (all three axes of every node there).
fn clamp(sys: &mut cosserat_volume::VolumeSystem) {
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

#[test]
fn newton_cg_steps_agree_with_direct_newton_steps() {
    // A clamped slab sagging under gravity for 5 steps of 10 ms, with Newton-CG and with the direct
    // Newton time stepper; both converge to the same residual tolerance, so the states agree to about
    // that tolerance over the stiffness.
    let mut cg_sys = small_system([4, 2, 1], material(), true, 0.0);
    let mut lu_sys = small_system([4, 2, 1], material(), true, 0.0);
    clamp(&mut cg_sys);
    clamp(&mut lu_sys);
    let mut cg = CgTimeStepper::new(&mut cg_sys.potential, CgTimeStepSettings::fixed(0.01)).unwrap();
    let mut lu = TimeStepper::new(&lu_sys.potential, TimeStepSettings::fixed(0.01)).unwrap();
    let mut total_cg = 0;
    for _ in 0..5 {
        let a = cg.step(&mut cg_sys.potential, &mut |_, _, _| {}).unwrap();
        lu.step(&mut lu_sys.potential, &mut |_, _, _| {}).unwrap();
        assert!(a.newton.residual() < 1e-7);
        total_cg += a.newton.total_cg_iterations();
    }
    assert!(total_cg > 0);
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
fn one_newton_cg_solve_matches_the_direct_solution() {
    let mut sys = small_system([3, 2, 1], material(), true, 0.0);
    clamp(&mut sys);
    let fixed = sys.potential.fixed_dofs().map(|(m, _)| m);
    let n = sys.potential.n_dofs();
    let mut u_cg = vec![0.0; n];
    let mut u_lu = vec![0.0; n];
    let settings = CgNewtonSettings {
        residual_scale: 0.01,
        residual_tolerance: 1e-9,
        ..Default::default()
    };
    let mut problem = PotentialProblem::new(&mut sys.potential, fixed.clone());
    let mut cg = CgNewtonSolver::for_problem(&problem, settings).unwrap();
    cg.solve(&mut problem, &mut u_cg).unwrap();
    let mut lu = NewtonSolver::for_problem(
        &problem,
        NewtonSettings {
            residual_scale: 0.01,
            residual_tolerance: 1e-9,
            ..Default::default()
        },
    )
    .unwrap();
    lu.solve(&mut problem, &mut u_lu).unwrap();
    let scale = u_lu.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let diff = u_cg.iter().zip(&u_lu).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(diff < 1e-6 * scale, "difference {diff} of {scale}");
}
