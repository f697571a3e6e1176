//! Time stepping: rest, free fall, free spin.

use super::common::{FailsOnce, strip_system};
use cosserat_assembly::ElementPair;
use cosserat_material::MaterialParameters;
use cosserat_solver::{InitialGuess, TimeStepSettings, TimeStepper, Tolerance};
use nalgebra::Vector3;

fn steel_like() -> MaterialParameters {
    MaterialParameters::new(1e-3, 1e9, 0.3, 1000.0, 1e-4)
}

#[test]
fn a_plate_at_rest_without_loads_stays_at_rest() {
    let mut sys = strip_system(
        ElementPair::Tri6Tri3,
        (0.1, 0.02),
        (10, 2),
        steel_like(),
        Vector3::zeros(),
        true,
        0.01,
    );
    let x0 = sys.potential.parts.state.x.clone();
    let mut stepper = TimeStepper::new(&sys.potential, TimeStepSettings::fixed(0.01)).unwrap();
    for _ in 0..100 {
        let report = stepper.step(&mut sys.potential, &mut |_, _, _| {}).unwrap();
        // The time stepper always takes one Newton step (min_iterations = 1); at rest it is a zero step.
        assert_eq!(
            report.newton.iterations, 1,
            "the rest state must converge in the first step"
        );
        // Round-off of the internal forces: E h L ≈ 1e4 N times a few ε.
        assert!(
            report.newton.residual() < 1e-9,
            "residual {:e}",
            report.newton.residual()
        );
    }
    let drift = sys
        .potential
        .parts
        .state
        .x
        .iter()
        .zip(&x0)
        .map(|(a, b)| (a - b).norm())
        .fold(0.0, f64::max);
    assert!(drift < 1e-15, "drift {drift:e} m after 100 steps");
    assert!((stepper.time() - 1.0).abs() < 1e-12);
}

#[test]
fn free_fall_follows_backward_euler_exactly() {
    let g = Vector3::new(0.0, 0.0, -9.81);
    for pair in [ElementPair::Tri3Tri3, ElementPair::Tri6Tri3] {
        // A soft material keeps M + Δt² K well conditioned, so the linear solves are exact to ~1e-12.
        let soft = MaterialParameters::new(1e-3, 1e6, 0.3, 1000.0, 1e-4);
        let mut sys = strip_system(pair, (0.1, 0.02), (6, 2), soft, g, true, 0.02);
        let damping = 0.7;
        sys.potential.parts.inertia.as_mut().unwrap().damping.fill(damping);
        let x0 = sys.potential.parts.state.x.clone();
        let mut settings = TimeStepSettings::fixed(0.02);
        settings.initial_guess = InitialGuess::Zero;
        let mut stepper = TimeStepper::new(&sys.potential, settings).unwrap();
        // Closed form of backward Euler with mass-proportional damping for a rigid translation:
        // v⁺ = (v + Δt g)/(1 + d Δt), x⁺ = x + Δt v⁺.
        let (dt, mut v, mut dx) = (0.02, Vector3::zeros(), Vector3::zeros());
        for _ in 0..50 {
            stepper.step(&mut sys.potential, &mut |_, _, _| {}).unwrap();
            v = (v + g * dt) / (1.0 + damping * dt);
            dx += v * dt;
        }
        let st = &sys.potential.parts.state;
        for (i, x) in st.x.iter().enumerate() {
            assert!(
                (x - x0[i] - dx).norm() < 1e-9 * dx.norm(),
                "{pair:?}: node {i} off the closed form by {:e} (of {:e})",
                (x - x0[i] - dx).norm(),
                dx.norm()
            );
            assert!((st.v[i] - v).norm() < 1e-9 * v.norm());
        }
    }
}

#[test]
fn the_extrapolated_guess_is_exact_in_free_fall() {
    // Undamped backward Euler free fall is uniformly accelerated (`vⁿ⁺¹ = vⁿ + Δt g`), which the linear
    // extrapolation of the last two steps' velocities predicts exactly: from the third step on Newton
    // starts at the solution, while the previous velocities miss it by the step's `m g`.
    let g = Vector3::new(0.0, 0.0, -9.81);
    let first_residuals = |guess: InitialGuess| -> Vec<f64> {
        let soft = MaterialParameters::new(1e-3, 1e6, 0.3, 1000.0, 1e-4);
        let mut sys = strip_system(ElementPair::Tri6Tri3, (0.1, 0.02), (6, 2), soft, g, true, 0.02);
        let mut settings = TimeStepSettings::fixed(0.02);
        settings.initial_guess = guess;
        let mut stepper = TimeStepper::new(&sys.potential, settings).unwrap();
        (0..6)
            .map(|_| stepper.step(&mut sys.potential, &mut |_, _, _| {}).unwrap().newton.residuals[0])
            .collect()
    };
    let previous = first_residuals(InitialGuess::PreviousVelocity);
    let extrapolated = first_residuals(InitialGuess::Extrapolated);
    let least_energy = first_residuals(InitialGuess::LeastEnergy);
    // The first step has no history, so all start from the previous (zero) velocities.
    assert_eq!(previous[0], extrapolated[0]);
    assert_eq!(least_energy[0], extrapolated[0]);
    for step in 2..6 {
        // The least-energy start finds the extrapolation nearest the solution and takes it.
        for (name, residuals) in [("extrapolation", &extrapolated), ("least-energy start", &least_energy)] {
            assert!(
                residuals[step] < 1e-6 * previous[step],
                "step {step}: first residual {:e} from the {name} against {:e} from the previous velocities",
                residuals[step],
                previous[step]
            );
        }
    }
}

/// Angular velocity of a rigid rotor advanced by backward Euler (velocity form) with a rigid
/// constraint: the step angles `a_n` obey `tan a₁ = Ω Δt` and `tan a_{n+1} = sin a_n / (2 − cos a_n)`
/// (angular-momentum balance at the end of each step; derivation in docs/time-integration.md), and the
/// discrete angular momentum is `I sin(a_n)/Δt`.
fn rigid_rotor_step_angles(omega0: f64, dt: f64, n: usize) -> Vec<f64> {
    let mut a = vec![(omega0 * dt).atan()];
    while a.len() < n {
        let b = *a.last().unwrap();
        a.push((b.sin() / (2.0 - b.cos())).atan());
    }
    a
}

#[test]
fn a_free_spinning_plate_keeps_its_shape_and_loses_momentum_like_backward_euler() {
    let (omega0, dt, n) = (2.0 * std::f64::consts::PI, 0.01, 60);
    let mut sys = strip_system(
        ElementPair::Tri6Tri3,
        (0.1, 0.1),
        (4, 4),
        steel_like(),
        Vector3::zeros(),
        true,
        dt,
    );
    let spin = Vector3::new(0.0, 0.0, omega0);
    {
        let st = &mut sys.potential.parts.state;
        for (x, v) in st.x.iter().zip(st.v.iter_mut()) {
            *v = spin.cross(x);
        }
        st.omega.fill(spin);
    }
    let masses = sys.potential.parts.inertia.as_ref().unwrap().masses.clone();
    let x0 = sys.potential.parts.state.x.clone();
    let inertia: f64 = masses.iter().zip(&x0).map(|(m, x)| m * (x.x * x.x + x.y * x.y)).sum();
    // An absolute tolerance far below the nodes' momentum change per step (about 5e-3 N). The default
    // relative tolerance is not tight enough here: its scale includes the step's first residual, which
    // for a stiff spinning plate is the elastic force of the stretch that the straight-line guess
    // `x + Δt v` gives a turning body (tens of N), so it accepts residuals of a few percent of the
    // nodes' momentum change.
    let mut settings = TimeStepSettings::fixed(dt);
    settings.newton.tolerance = Tolerance::Absolute(1e-8);
    let mut stepper = TimeStepper::new(&sys.potential, settings).unwrap();
    let angles = rigid_rotor_step_angles(omega0, dt, n);
    for step in 0..n {
        stepper.step(&mut sys.potential, &mut |_, _, _| {}).unwrap();
        let st = &sys.potential.parts.state;
        let l: f64 = masses
            .iter()
            .zip(st.x.iter().zip(&st.v))
            .map(|(m, (x, v))| m * x.cross(v).z)
            .sum();
        let expected = inertia * angles[step].sin() / dt;
        assert!(
            (l - expected).abs() < 2e-4 * expected,
            "step {step}: L = {l}, rigid backward Euler {expected}"
        );
    }
    // Shape: all pairwise distances to the centre node are kept.
    let st = &sys.potential.parts.state;
    let centre = (0..x0.len()).min_by(|&a, &b| x0[a].norm().total_cmp(&x0[b].norm())).unwrap();
    for i in 0..x0.len() {
        let d0 = (x0[i] - x0[centre]).norm();
        let d = (st.x[i] - st.x[centre]).norm();
        assert!(
            (d - d0).abs() <= 1e-6 * 0.1,
            "node {i}: distance changed by {:e}",
            d - d0
        );
        assert!(st.x[i].z.abs() < 1e-9, "the plate left its plane");
    }
    // The directors turned with the plate: the rotation nodes' d1 matches the turned body axis.
    let turned: f64 = angles.iter().sum();
    let d1 = cosserat_geometry::rotation::rotation_matrix(&st.q[0]).column(0).into_owned();
    assert!(
        (d1 - Vector3::new(turned.cos(), turned.sin(), 0.0)).norm() < 1e-3,
        "directors lag the body: {d1:?}"
    );
}

/// A test term that refuses time steps above a threshold (as a non-finite energy would).
struct FailsAbove(f64);

impl cosserat_assembly::PotentialTerm for FailsAbove {
    fn name(&self) -> String {
        "fails_above".into()
    }

    fn value(&self, eval: &cosserat_assembly::term::Evaluation<'_>) -> Result<f64, cosserat_assembly::AssemblyError> {
        if eval.dt > self.0 {
            Err(cosserat_assembly::AssemblyError::NonFinite {
                term: self.name(),
                location: "term",
                index: 0,
            })
        } else {
            Ok(0.0)
        }
    }

    fn gradient(
        &self,
        eval: &cosserat_assembly::term::Evaluation<'_>,
        _: &mut [f64],
    ) -> Result<f64, cosserat_assembly::AssemblyError> {
        self.value(eval)
    }

    fn hessian(
        &self,
        eval: &cosserat_assembly::term::Evaluation<'_>,
        _: &mut [f64],
        _: &cosserat_assembly::SparsityPattern,
        _: &mut [f64],
    ) -> Result<f64, cosserat_assembly::AssemblyError> {
        self.value(eval)
    }
}

#[test]
fn a_failed_step_is_retried_with_half_the_time_step_and_then_stops_with_a_diagnostic() {
    let g = Vector3::new(0.0, 0.0, -9.81);
    let mut sys = strip_system(ElementPair::Tri3Tri3, (0.1, 0.02), (4, 1), steel_like(), g, true, 0.04);
    sys.potential.insert(FailsAbove(0.011));
    let mut stepper = TimeStepper::new(&sys.potential, TimeStepSettings::fixed(0.04)).unwrap();
    let report = stepper.step(&mut sys.potential, &mut |_, _, _| {}).unwrap();
    // 0.04 → 0.02 → 0.01: two reductions, and the step advanced by the reduced Δt only.
    assert_eq!(report.reductions, 2);
    assert!((report.dt - 0.01).abs() < 1e-15 && (stepper.time() - 0.01).abs() < 1e-15);

    // A term that always fails: the run stops with every attempt listed and the state untouched.
    let mut sys = strip_system(ElementPair::Tri3Tri3, (0.1, 0.02), (4, 1), steel_like(), g, true, 0.04);
    sys.potential.insert(FailsAbove(0.0));
    let before = sys.potential.parts.state.clone();
    let mut settings = TimeStepSettings::fixed(0.04);
    settings.max_reductions = 3;
    let mut stepper = TimeStepper::new(&sys.potential, settings).unwrap();
    let err = stepper.step(&mut sys.potential, &mut |_, _, _| {}).unwrap_err();
    assert_eq!(err.attempts().len(), 4);
    assert_eq!(
        err.attempts().iter().map(|a| a.dt).collect::<Vec<_>>(),
        [0.04, 0.02, 0.01, 0.005]
    );
    assert!(
        err.to_string().contains("fails_above") || err.to_string().contains("non-finite"),
        "{err}"
    );
    assert_eq!(sys.potential.parts.state, before);
    assert_eq!(stepper.time(), 0.0);
}

/// A step's report counts every solve of the step: the iterations, factorisations and times of a
/// failed attempt belong to the step that retried it.
#[test]
fn a_step_reports_the_cost_of_its_failed_attempts() {
    let g = Vector3::new(0.0, 0.0, -9.81);
    let mut sys = strip_system(ElementPair::Tri6Tri3, (0.1, 0.02), (8, 1), steel_like(), g, true, 0.2);
    // The first attempt fails in its second iteration, after one full Newton iteration.
    sys.potential.insert(FailsOnce::at_hessian(2));
    let mut stepper = TimeStepper::new(&sys.potential, TimeStepSettings::fixed(0.2)).unwrap();
    let report = stepper.step(&mut sys.potential, &mut |_, _, _| {}).unwrap();
    assert_eq!(report.reductions, 1, "the first attempt must fail");
    assert_eq!(report.wasted_iterations, 1);
    assert_eq!(report.iterations(), report.newton.iterations);
    assert_eq!(
        report.cost.iterations,
        report.newton.iterations + report.wasted_iterations
    );
    let (all, accepted) = (&report.cost, &report.newton);
    assert_eq!(
        all.factorisations.factorised(),
        accepted.factorisations.factorised() + 1,
        "the failed attempt's factorisation"
    );
    assert!(all.assembly_seconds > accepted.assembly_seconds);
    assert!(all.linear_solve_seconds > accepted.linear_solve_seconds);
}

#[test]
fn rotation_updates_running_to_a_half_turn_are_reflected_across_it() {
    use cosserat_solver::NewtonProblem;
    use cosserat_solver::potential_problem::PotentialProblem;
    let dt = 0.01;
    let mut sys = strip_system(
        ElementPair::Tri6Tri3,
        (0.1, 0.01),
        (2, 1),
        steel_like(),
        Vector3::zeros(),
        true,
        dt,
    );
    let layout = sys.potential.parts.layout;
    let problem = PotentialProblem::new(&mut sys.potential, None);
    let n = layout.n_blocks() * 3;
    let block = |k: usize| 3 * layout.rot_block(k);
    let disp = 3 * layout.disp_block(0);
    // Cayley parameters |Δt ω| of 2000 (moving out), 500 (below the threshold of 1000), and 2000
    // coming in from 3000; a velocity of 2000/Δt m/s is no rotation.
    let mut from = vec![0.0; n];
    let mut x = vec![0.0; n];
    x[block(0)] = 2000.0 / dt;
    x[block(1) + 1] = 500.0 / dt;
    from[block(2) + 2] = 3000.0 / dt;
    x[block(2) + 2] = 2000.0 / dt;
    x[disp] = 2000.0 / dt;
    let before = x.clone();
    problem.cross_singularities(&from, &mut x);
    assert_eq!(x[block(0)], -before[block(0)], "reflected across the half turn");
    for i in (0..n).filter(|&i| i != block(0)) {
        assert_eq!(x[i], before[i], "unknown {i} moved");
    }
}
