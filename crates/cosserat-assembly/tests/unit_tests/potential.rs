//! The assembled incremental potential: derivatives against finite differences, rest state,
//! determinism across thread counts.

use super::common::{dense_hessian, strip, strip_with};
use cosserat_assembly::boundary::{AngularVelocityPenalty, PositionPenalty, RotationPenalty};
use cosserat_assembly::{ElementPair, IncrementalPotential, Parallelism};
use cosserat_geometry::rotation::{exp_map, quaternion_from_matrix};
use cosserat_material::{ShellModel, StrainInterpolation};
use nalgebra::{DMatrix, Matrix3, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn random_vec(rng: &mut ChaCha8Rng, s: f64) -> Vector3<f64> {
    Vector3::from_fn(|_, _| rng.random_range(-s..s))
}

/// A penalty on the first and third directors of the first and last rotation nodes, one target tilted.
fn d3_penalty(n_rot: usize) -> RotationPenalty {
    RotationPenalty {
        label: "d3".into(),
        nodes: vec![0, n_rot - 1],
        targets: vec![exp_map(&Vector3::new(0.2, -0.1, 0.3)), Matrix3::identity()],
        columns: [true, false, true],
        stiffness: 10.0,
    }
}

/// Perturbs the state and adds every kind of boundary term and prescribed rest field.
fn decorate(p: &mut IncrementalPotential, rng: &mut ChaCha8Rng) {
    let parts = &mut p.parts;
    let st = &mut parts.state;
    for x in &mut st.x {
        *x += random_vec(rng, 2e-3);
    }
    for v in &mut st.v {
        *v = random_vec(rng, 0.1);
    }
    for q in st.q.iter_mut().chain(st.q_points.iter_mut()) {
        *q = quaternion_from_matrix(&exp_map(&random_vec(rng, 0.3)));
    }
    for w in &mut st.omega {
        *w = random_vec(rng, 1.0);
    }
    let n_rot = parts.layout.n_rot_nodes;
    parts.position_penalties.push(PositionPenalty {
        label: "clamp".into(),
        nodes: vec![0, 1, 2],
        targets: vec![Vector3::zeros(); 3],
        active: [true, false, true],
        stiffness: 1e3,
    });
    parts.rotation_penalties.push(d3_penalty(n_rot));
    parts.omega_penalties.push(AngularVelocityPenalty {
        label: "spin".into(),
        nodes: vec![1],
        target: Vector3::new(0.0, 0.0, 2.0),
        active: [false, true, true],
        stiffness: 5.0,
    });
    parts.loads.forces[3] = Vector3::new(0.1, -0.2, 0.3);
    parts.loads.torques[2] = Vector3::new(0.03, -0.01, 0.02);
    let g: Vec<Matrix3<f64>> = (0..p.parts.shells[0].n_points())
        .map(|_| Matrix3::from_fn(|_, _| rng.random_range(-5.0..5.0)))
        .collect();
    p.parts.shells[0].set_rest_fields_dyn(&mut |i| (Some(1.05), Some(g[i])));
}

fn check_derivatives(pair: ElementPair, model: ShellModel, seed: u64) {
    check_derivatives_with(pair, model, seed, StrainInterpolation::Paper);
}

fn check_derivatives_with(pair: ElementPair, model: ShellModel, seed: u64, interpolation: StrainInterpolation) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut p = strip_with(pair, 2, 1, model, true, interpolation).potential;
    decorate(&mut p, &mut rng);
    let n = p.n_dofs();
    let u: Vec<f64> = (0..n).map(|_| rng.random_range(-0.5..0.5)).collect();
    let mut g = vec![0.0; n];
    let e0 = p.gradient(&u, &mut g).unwrap();
    assert!((p.value(&u).unwrap() - e0).abs() <= 1e-12 * e0.abs());
    let h = dense_hessian(&mut p, &u);
    // Central differences, step 1e-6 on O(1) unknowns: truncation and round-off far below 1e-6.
    let step = 1e-6;
    let g_scale = g.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let row_max: Vec<f64> = (0..n).map(|i| h.row(i).amax()).collect();
    for i in 0..n {
        let (mut up, mut um) = (u.clone(), u.clone());
        up[i] += step;
        um[i] -= step;
        let fd = (p.value(&up).unwrap() - p.value(&um).unwrap()) / (2.0 * step);
        assert!((fd - g[i]).abs() <= 1e-6 * g_scale, "gradient {i}: {} vs {fd}", g[i]);
        let (mut gp, mut gm) = (vec![0.0; n], vec![0.0; n]);
        p.gradient(&up, &mut gp).unwrap();
        p.gradient(&um, &mut gm).unwrap();
        for j in 0..n {
            let fd = (gp[j] - gm[j]) / (2.0 * step);
            let scale = (row_max[i] * row_max[j]).sqrt();
            assert!(
                (fd - h[(j, i)]).abs() <= 1e-6 * scale,
                "hessian ({j}, {i}): {} vs {fd}",
                h[(j, i)]
            );
        }
    }
}

#[test]
fn assembled_derivatives_match_finite_differences() {
    check_derivatives(ElementPair::Tri3Tri3, ShellModel::Plate, 1);
    check_derivatives(ElementPair::Tri6Tri3, ShellModel::Plate, 2);
    check_derivatives(ElementPair::Tri6Tri6, ShellModel::Shell, 3);
    for (seed, pair) in [ElementPair::Tri3Tri3, ElementPair::Tri6Tri3, ElementPair::Tri6Tri6]
        .into_iter()
        .enumerate()
    {
        check_derivatives_with(
            pair,
            ShellModel::Plate,
            10 + seed as u64,
            StrainInterpolation::Stabilized,
        );
    }
    check_derivatives_with(
        ElementPair::Tri6Tri3,
        ShellModel::Plate,
        20,
        StrainInterpolation::Assumed,
    );
    check_derivatives_with(
        ElementPair::Tri6Tri6,
        ShellModel::Shell,
        21,
        StrainInterpolation::Assumed,
    );
    check_derivatives_with(
        ElementPair::Tri3Tri3,
        ShellModel::Plate,
        22,
        StrainInterpolation::Assumed,
    );
    check_derivatives_with(ElementPair::Tri6Tri3, ShellModel::Plate, 23, StrainInterpolation::Regge);
    check_derivatives_with(ElementPair::Tri6Tri3, ShellModel::Shell, 24, StrainInterpolation::Regge);
    check_derivatives_with(
        ElementPair::Tri6Tri3,
        ShellModel::Shell,
        25,
        StrainInterpolation::ReggeStabilized,
    );
    check_derivatives_with(
        ElementPair::Tri6Tri6,
        ShellModel::Shell,
        26,
        StrainInterpolation::ReggeStabilized,
    );
}

/// `hessian_add` adds onto whatever the buffers hold, and the gradient that comes with a Hessian is the
/// one of `gradient`.
#[test]
fn hessian_add_accumulates_and_its_gradient_is_the_gradient() {
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let mut p = strip(ElementPair::Tri6Tri3, 3, 2, ShellModel::Plate, true).potential;
    decorate(&mut p, &mut rng);
    let n = p.n_dofs();
    let nnz = p.pattern().nnz();
    let u: Vec<f64> = (0..n).map(|_| rng.random_range(-0.5..0.5)).collect();
    let (mut g, mut h) = (vec![0.0; n], vec![0.0; nnz]);
    let e = p.hessian(&u, &mut g, &mut h).unwrap();
    let g_base: Vec<f64> = (0..n).map(|_| rng.random_range(-1.0..1.0)).collect();
    let h_base: Vec<f64> = (0..nnz).map(|_| rng.random_range(-1.0..1.0)).collect();
    let (mut g_add, mut h_add) = (g_base.clone(), h_base.clone());
    assert_eq!(
        p.hessian_add(&u, &mut g_add, &mut h_add).unwrap().to_bits(),
        e.to_bits()
    );
    let close = |sum: &[f64], base: &[f64], part: &[f64]| {
        let scale = part.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
        sum.iter()
            .zip(base)
            .zip(part)
            .all(|((s, b), x)| (s - b - x).abs() <= 1e-13 * scale)
    };
    assert!(close(&g_add, &g_base, &g), "gradient not added");
    assert!(close(&h_add, &h_base, &h), "Hessian not added");
    let mut g_only = vec![0.0; n];
    let e_only = p.gradient(&u, &mut g_only).unwrap();
    assert!((e_only - e).abs() <= 1e-14 * e.abs().max(1.0));
    assert!(close(&g_only, &vec![0.0; n], &g), "gradients differ");
}

#[test]
fn a_plate_at_rest_without_loads_has_zero_energy_and_gradient() {
    for pair in [ElementPair::Tri3Tri3, ElementPair::Tri6Tri3, ElementPair::Tri6Tri6] {
        let mut p = strip(pair, 4, 2, ShellModel::Plate, true).potential;
        p.parts.loads.gravity = Vector3::zeros();
        let u = vec![0.0; p.n_dofs()];
        let mut g = vec![0.0; p.n_dofs()];
        let e = p.gradient(&u, &mut g).unwrap();
        // Scales: a unit strain costs about E h A = 1e6 · 1e-3 · 2e-3 J and the matching gradient is
        // E h L Δt ≈ 1e-3; the rest state must be zero to round-off relative to those.
        assert!(e.abs() < 1e-14 * 2.0, "{pair:?}: energy at rest {e:e}");
        let g_max = g.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        assert!(g_max < 1e-14, "{pair:?}: gradient at rest {g_max:e}");
    }
}

#[test]
fn assembly_is_bit_identical_for_one_and_two_threads() {
    for interpolation in [
        StrainInterpolation::Paper,
        StrainInterpolation::Stabilized,
        StrainInterpolation::Assumed,
        StrainInterpolation::Regge,
        StrainInterpolation::ReggeStabilized,
    ] {
        check_thread_counts(interpolation);
    }
}

fn check_thread_counts(interpolation: StrainInterpolation) {
    // 40 × 8 quads = 640 elements: more than one chunk of the ordered parallel map.
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let mut p = strip_with(ElementPair::Tri6Tri3, 40, 8, ShellModel::Plate, true, interpolation).potential;
    decorate(&mut p, &mut rng);
    let u: Vec<f64> = (0..p.n_dofs()).map(|_| rng.random_range(-0.5..0.5)).collect();
    let mut run = |threads: usize, par: Parallelism| {
        p.parallelism = par;
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            let mut g = vec![0.0; p.n_dofs()];
            let mut values = vec![0.0; p.pattern().nnz()];
            let e = p.hessian(&u, &mut g, &mut values).unwrap();
            let v = p.value(&u).unwrap();
            (
                e.to_bits(),
                v.to_bits(),
                g.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                values.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
            )
        })
    };
    let seq = run(1, Parallelism::Sequential);
    let one = run(1, Parallelism::Rayon);
    let two = run(2, Parallelism::Rayon);
    assert!(seq == one && one == two, "results differ between thread counts");
}

/// With projection on, each element Hessian is replaced by its nearest positive semi-definite matrix,
/// so the static shell's Hessian is positive semi-definite; switching it off again gives back exactly
/// the unprojected Hessian (the projected element buffers leave nothing behind).
#[test]
fn projected_element_hessians_sum_to_a_positive_semidefinite_matrix_and_leave_no_trace() {
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    let mut p = strip(ElementPair::Tri6Tri3, 6, 2, ShellModel::Plate, false).potential;
    for x in &mut p.parts.state.x {
        *x += random_vec(&mut rng, 5e-3);
    }
    for q in p.parts.state.q.iter_mut().chain(p.parts.state.q_points.iter_mut()) {
        *q = quaternion_from_matrix(&exp_map(&random_vec(&mut rng, 0.5)));
    }
    let u: Vec<f64> = (0..p.n_dofs()).map(|_| rng.random_range(-0.2..0.2)).collect();
    let min_eigenvalue = |h: &DMatrix<f64>| h.clone().symmetric_eigenvalues().min();
    let plain = dense_hessian(&mut p, &u);
    let scale = plain.amax();
    assert!(
        min_eigenvalue(&plain) < -1e-6 * scale,
        "the test needs an indefinite Hessian"
    );
    p.parts.shells[0].set_project_pd(true);
    let projected = dense_hessian(&mut p, &u);
    assert!(
        min_eigenvalue(&projected) > -1e-10 * scale,
        "{}",
        min_eigenvalue(&projected)
    );
    assert_eq!(dense_hessian(&mut p, &u), projected);
    p.parts.shells[0].set_project_pd(false);
    assert_eq!(dense_hessian(&mut p, &u), plain);
}

/// The mixed-integration-point Newton matrix on assembled shells: a prediction along a step of length
/// zero is the exact Hessian, the Hessian is affine in the step length along the linearised direction,
/// the gradient never changes, and clearing the prediction restores the exact Hessian bit for bit.
#[test]
fn predicted_strains_change_only_the_second_order_terms_of_the_hessian() {
    for (pair, interpolation) in [
        (ElementPair::Tri6Tri3, StrainInterpolation::Paper),
        (ElementPair::Tri6Tri3, StrainInterpolation::Stabilized),
        (ElementPair::Tri6Tri3, StrainInterpolation::ReggeStabilized),
        (ElementPair::Tri6Tri6, StrainInterpolation::ReggeStabilized),
    ] {
        let mut rng = ChaCha8Rng::seed_from_u64(31);
        let mut p = strip_with(pair, 3, 2, ShellModel::Shell, true, interpolation).potential;
        decorate(&mut p, &mut rng);
        let n = p.n_dofs();
        let u: Vec<f64> = (0..n).map(|_| rng.random_range(-0.5..0.5)).collect();
        let du: Vec<f64> = (0..n).map(|_| rng.random_range(-0.5..0.5)).collect();
        let hessian = |p: &mut IncrementalPotential| {
            let (mut g, mut h) = (vec![0.0; n], vec![0.0; p.pattern().nnz()]);
            p.hessian(&u, &mut g, &mut h).unwrap();
            (g, DMatrix::from_row_slice(1, h.len(), &h))
        };
        let (g_exact, exact) = hessian(&mut p);
        p.linearize_strains(&u, &du).unwrap();
        p.advance_predicted_strains(0.0);
        let (g0, zero) = hessian(&mut p);
        let scale = exact.amax();
        assert!((&zero - &exact).amax() <= 1e-13 * scale, "{interpolation:?}: zero step");
        p.advance_predicted_strains(1.0);
        let (g1, one) = hessian(&mut p);
        p.advance_predicted_strains(2.0);
        let (_, two) = hessian(&mut p);
        assert_eq!(g0, g_exact, "{interpolation:?}");
        assert_eq!(g1, g_exact, "{interpolation:?}");
        let first = &one - &exact;
        assert!(
            first.amax() > 1e-6 * scale,
            "{interpolation:?}: the prediction changes nothing"
        );
        assert!(
            (&two - &exact - &first * 2.0).amax() <= 1e-9 * first.amax(),
            "{interpolation:?}: not affine in the step length"
        );
        p.clear_predicted_strains();
        let (_, cleared) = hessian(&mut p);
        assert_eq!(cleared, exact, "{interpolation:?}");
    }
}

/// A curved strip with random start rotations and a director penalty, and unknowns in which rotation
/// node 1 turns by 2 arctan(5/2) ≈ 136° within the step, the others by a few degrees.
fn strip_turning_past_a_quarter_turn() -> (IncrementalPotential, Vec<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let mut p = strip(ElementPair::Tri6Tri3, 2, 1, ShellModel::Shell, true).potential;
    let parts = &mut p.parts;
    for q in parts.state.q.iter_mut().chain(parts.state.q_points.iter_mut()) {
        *q = quaternion_from_matrix(&exp_map(&random_vec(&mut rng, 0.3)));
    }
    let n_rot = parts.layout.n_rot_nodes;
    parts.rotation_penalties.push(d3_penalty(n_rot));
    parts.loads.forces[3] = Vector3::new(0.1, -0.2, 0.3);
    let mut u: Vec<f64> = (0..p.n_dofs()).map(|_| rng.random_range(-0.5..0.5)).collect();
    let b = 3 * p.parts.layout.rot_block(1);
    let w = Vector3::new(1.0, -2.0, 0.5).normalize() * (5.0 / p.dt());
    u[b..b + 3].copy_from_slice(w.as_slice());
    (p, u)
}

/// Rebasing re-expresses a state whose rotation updates passed a quarter turn: the same energy and
/// the same forces on the positions (the same configuration, quadrature points' rotations included),
/// zero angular velocities, and the step's start back after a restore. Committed, it leaves the
/// rotations the step would have left in one update. Nothing is rebased where a
/// term reads the angular velocities (a torque) or below a quarter turn.
#[test]
fn rebased_rotations_keep_the_configuration_and_restore_the_step_start() {
    let (mut p, u) = strip_turning_past_a_quarter_turn();
    let (layout, dt, n) = (p.parts.layout, p.dt(), p.n_dofs());
    let parameter = |u: &[f64], k: usize| dt * layout.omega(u, k).norm();
    assert!(parameter(&u, 0) < 2.0 && parameter(&u, 1) > 2.0);
    let start = (p.parts.state.q.clone(), p.parts.state.q_points.clone());
    let mut g = vec![0.0; n];
    let e = p.gradient(&u, &mut g).unwrap();
    let mut rebased = u.clone();
    assert!(p.rebase_rotations(&mut rebased));
    let mut g_rebased = vec![0.0; n];
    let e_rebased = p.gradient(&rebased, &mut g_rebased).unwrap();
    assert!((e_rebased - e).abs() <= 1e-12 * e.abs(), "{e_rebased} against {e}");
    let positions = 3 * layout.n_disp_nodes;
    assert_eq!(rebased[..positions], u[..positions]);
    assert!(rebased[positions..].iter().all(|w| *w == 0.0));
    let scale = g.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    for (a, b) in g[..positions].iter().zip(&g_rebased[..positions]) {
        assert!((a - b).abs() <= 1e-10 * scale, "position force {b} against {a}");
    }
    p.restore_step_start();
    assert_eq!((&p.parts.state.q, &p.parts.state.q_points), (&start.0, &start.1));
    assert_eq!(p.value(&u).unwrap(), e);
    // Below a quarter turn, and with a torque on the shell, the unknowns stay.
    let b = 3 * layout.rot_block(1);
    let mut small = u.clone();
    small[b..b + 3].iter_mut().for_each(|w| *w *= 0.3);
    assert!(!p.rebase_rotations(&mut small));
    p.parts.loads.torques[2] = Vector3::new(0.0, 0.0, 1e-3);
    let mut loaded = u.clone();
    assert!(!p.rebase_rotations(&mut loaded));
    assert_eq!(loaded, u);
    // The same step committed in one update and after a rebase.
    let (mut whole, u) = strip_turning_past_a_quarter_turn();
    let (mut split, mut u_split) = strip_turning_past_a_quarter_turn();
    whole.commit(&u);
    assert!(split.rebase_rotations(&mut u_split));
    split.commit(&u_split);
    let (a, b) = (&whole.parts.state, &split.parts.state);
    let close = |x: &[nalgebra::Quaternion<f64>], y: &[nalgebra::Quaternion<f64>]| {
        x.iter().zip(y).all(|(x, y)| (x.coords - y.coords).amax() < 1e-14)
    };
    assert!(close(&a.q, &b.q) && close(&a.q_points, &b.q_points));
}

/// `u` that turns the strip rigidly by `angle` about the x axis in one step: the positions' velocities
/// and, when `directors`, the nodes' angular velocities (the Cayley parameter of that angle).
fn turned(p: &IncrementalPotential, angle: f64, directors: bool) -> Vec<f64> {
    let (layout, dt) = (p.parts.layout, p.dt());
    let psi = Vector3::x() * 2.0 * (angle / 2.0).tan();
    let r = cosserat_geometry::rotation::rotation_matrix(&cosserat_geometry::rotation::quaternion_update(
        &nalgebra::Quaternion::identity(),
        &psi,
        1.0,
    ));
    let mut u = vec![0.0; p.n_dofs()];
    for (i, x) in p.parts.state.x.iter().enumerate() {
        let b = 3 * layout.disp_block(i);
        u[b..b + 3].copy_from_slice(((r * x - x) / dt).as_slice());
    }
    if directors {
        for k in 0..layout.n_rot_nodes {
            let b = 3 * layout.rot_block(k);
            u[b..b + 3].copy_from_slice((psi / dt).as_slice());
        }
    }
    u
}

#[test]
fn a_state_whose_surface_turns_away_from_its_directors_is_outside_the_domain() {
    for pair in [ElementPair::Tri3Tri3, ElementPair::Tri6Tri3, ElementPair::Tri6Tri6] {
        let mut p = strip(pair, 4, 2, ShellModel::Plate, true).potential;
        // The angle between the turned surface's normal and its unturned directors is 120°: the
        // signed area ratio is cos 120° = −0.5 at every point.
        let angle = 2.0 * std::f64::consts::PI / 3.0;
        assert!(p.check_state(&vec![0.0; p.n_dofs()]).is_ok(), "{pair:?}: rest");
        assert!(
            p.check_state(&turned(&p, angle, true)).is_ok(),
            "{pair:?}: a rigid turn"
        );
        let err = p
            .check_state(&turned(&p, angle, false))
            .expect_err("the positions turned alone");
        let text = err.to_string();
        assert!(
            text.contains("element 0 turned inside out") && text.contains("-0.500"),
            "{pair:?}: {text}"
        );
        // The energy itself is defined there: only the solvers keep their iterates out.
        assert!(p.value(&turned(&p, angle, false)).unwrap().is_finite());
    }
}
