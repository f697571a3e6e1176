//! The volume term inside the incremental potential: derivatives of the assembled system, determinism
//! across threads, the rest-curvature handle, non-finite input and the point-rotation update.

use super::common::{amax, dense, material, perturb_state, random_unknowns, small_system};
use cosserat_assembly::{AssemblyError, Parallelism};
use cosserat_geometry::rotation::quaternion_update;
use cosserat_volume::MicropolarModuli;
use cosserat_volume::density::curvature_density;
use nalgebra::{Matrix3, Vector3};

#[test]
fn assembled_gradient_and_hessian_match_central_differences() {
    let mut sys = small_system([2, 1, 1], material(), true, 0.0);
    perturb_state(&mut sys, 1);
    sys.rest_curvature
        .set(|p| Matrix3::from_fn(|r, c| 0.5 * (p as f64 + 1.0) * ((r + 2 * c) as f64 - 3.0)));
    let p = &mut sys.potential;
    let n = p.n_dofs();
    let u = random_unknowns(n, 2);
    let mut g = vec![0.0; n];
    let mut values = vec![0.0; p.pattern().nnz()];
    let e = p.hessian(&u, &mut g, &mut values).unwrap();
    let h = dense(p.pattern(), &values);
    let mut g2 = vec![0.0; n];
    // The three paths sum the same element energies in different association orders.
    assert!((p.gradient(&u, &mut g2).unwrap() - e).abs() < 1e-14 * e.abs());
    assert_eq!(g, g2);
    assert!((p.value(&u).unwrap() - e).abs() < 1e-14 * e.abs());
    // Central differences with steps of 1e-6 (velocities ~0.5 m/s, angular velocities ~0.5 rad/s):
    // truncation and round-off both below 1e-6 of the largest entry.
    let step = 1e-6;
    let (mut gp, mut gm) = (vec![0.0; n], vec![0.0; n]);
    let mut max_g_err: f64 = 0.0;
    let mut max_h_err: f64 = 0.0;
    for i in 0..n {
        let mut up = u.clone();
        let mut um = u.clone();
        up[i] += step;
        um[i] -= step;
        let fd = (p.gradient(&up, &mut gp).unwrap() - p.gradient(&um, &mut gm).unwrap()) / (2.0 * step);
        max_g_err = max_g_err.max((fd - g[i]).abs());
        for j in 0..n {
            max_h_err = max_h_err.max(((gp[j] - gm[j]) / (2.0 * step) - h[(j, i)]).abs());
        }
    }
    assert!(max_g_err < 1e-6 * amax(&g), "gradient error {max_g_err}");
    assert!(max_h_err < 1e-6 * h.amax(), "hessian error {max_h_err}");
}

#[test]
fn results_are_bit_identical_for_one_and_many_threads() {
    // 6 × 4 × 2 cells = 288 elements: more than one chunk of the ordered parallel map.
    let mut sys = small_system([6, 4, 2], material(), true, 0.0);
    perturb_state(&mut sys, 3);
    let p = &mut sys.potential;
    let n = p.n_dofs();
    let u = random_unknowns(n, 4);
    let mut run = |par: Parallelism| {
        p.parallelism = par;
        let mut g = vec![0.0; n];
        let mut h = vec![0.0; p.pattern().nnz()];
        let e = p.hessian(&u, &mut g, &mut h).unwrap();
        (e, g, h, p.value(&u).unwrap())
    };
    let seq = run(Parallelism::Sequential);
    let par = rayon::ThreadPoolBuilder::new()
        .num_threads(3)
        .build()
        .unwrap()
        .install(|| run(Parallelism::Rayon));
    assert_eq!(seq, par);
}

#[test]
fn rest_curvature_at_rest_costs_its_curvature_energy() {
    let m = material();
    let mut sys = small_system([2, 2, 1], m, false, 0.0);
    let gamma = Matrix3::new(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0);
    sys.rest_curvature.set_uniform(gamma);
    assert_eq!(sys.rest_curvature.get(3), gamma);
    let n = sys.potential.n_dofs();
    // At rest E = 0 and Γ = 0, so the energy is the volume times W_curv(−Γ_rest) (gravity does no work
    // at zero velocity).
    let e = sys.potential.value(&vec![0.0; n]).unwrap();
    let expected = sys.volume() * curvature_density(&(-gamma), &MicropolarModuli::of(&m).unwrap());
    assert!((e - expected).abs() < 1e-12 * expected, "{e} vs {expected}");
    sys.rest_curvature.clear();
    assert_eq!(sys.potential.value(&vec![0.0; n]).unwrap(), 0.0);
}

#[test]
fn a_non_finite_position_is_reported_with_its_element() {
    let mut sys = small_system([1, 1, 1], material(), false, 0.0);
    sys.potential.parts.state.x[7].x = f64::NAN;
    let n = sys.potential.n_dofs();
    match sys.potential.value(&vec![0.0; n]) {
        Err(AssemblyError::NonFinite { term, location, index }) => {
            assert_eq!(term, "micropolar_tet4");
            assert_eq!(location, "element");
            assert!(index < 6);
        }
        other => panic!("expected a non-finite error, got {other:?}"),
    }
    let mut g = vec![0.0; n];
    assert!(matches!(
        sys.potential.gradient(&vec![0.0; n], &mut g),
        Err(AssemblyError::NonFinite { .. })
    ));
}

#[test]
fn commit_advances_point_rotations_with_the_mean_angular_velocity() {
    let mut sys = small_system([1, 1, 1], material(), true, 0.0);
    let n = sys.potential.n_dofs();
    let n_nodes = sys.rest_positions.len();
    let mut u = vec![0.0; n];
    let w = Vector3::new(0.3, -0.2, 1.0);
    for k in 0..n_nodes {
        u[3 * (n_nodes + k)..3 * (n_nodes + k) + 3].copy_from_slice(w.as_slice());
    }
    sys.potential.commit(&u);
    let st = &sys.potential.parts.state;
    let expected = quaternion_update(&nalgebra::Quaternion::identity(), &w, 0.01);
    assert!(st.q_points.iter().all(|q| (q - expected).norm() < 1e-15));
    assert!(st.q.iter().all(|q| (q - expected).norm() < 1e-15));
    assert_eq!(
        sys.potential.active_terms(),
        [
            "inertia",
            "external_loads",
            "micropolar_stretch",
            "micropolar_curvature"
        ]
    );
}

/// Rebasing the rotations of a step past a quarter turn keeps the volume's configuration: the same
/// energy and the same forces on the positions, the points' rotations moved with the nodes'.
#[test]
fn rebased_rotations_keep_the_energy_of_the_solid() {
    let mut sys = small_system([1, 1, 1], material(), true, 0.0);
    perturb_state(&mut sys, 4);
    let p = &mut sys.potential;
    let n = p.n_dofs();
    let mut u = random_unknowns(n, 5);
    let layout = p.parts.layout;
    let b = 3 * layout.rot_block(0);
    let w = Vector3::new(0.3, 1.0, -0.4).normalize() * (4.0 / p.dt());
    u[b..b + 3].copy_from_slice(w.as_slice());
    let (mut g, mut g_rebased) = (vec![0.0; n], vec![0.0; n]);
    let e = p.gradient(&u, &mut g).unwrap();
    let mut rebased = u.clone();
    assert!(p.rebase_rotations(&mut rebased));
    let e_rebased = p.gradient(&rebased, &mut g_rebased).unwrap();
    assert!((e_rebased - e).abs() <= 1e-12 * e.abs(), "{e_rebased} against {e}");
    let positions = 3 * layout.n_disp_nodes;
    for (a, b) in g[..positions].iter().zip(&g_rebased[..positions]) {
        assert!((a - b).abs() <= 1e-10 * amax(&g), "position force {b} against {a}");
    }
}

#[test]
fn a_state_with_a_mirrored_solid_is_outside_the_domain() {
    let mut sys = small_system([2, 1, 1], material(), true, 0.0);
    let p = &mut sys.potential;
    let (layout, dt) = (p.parts.layout, p.dt());
    let mut u = vec![0.0; p.n_dofs()];
    assert!(p.check_state(&u).is_ok(), "rest");
    // Velocities that mirror every position across the plane x = 0 in one step: det F = −1.
    for (i, x) in p.parts.state.x.iter().enumerate() {
        u[3 * layout.disp_block(i)] = -2.0 * x.x / dt;
    }
    let text = p.check_state(&u).expect_err("a mirrored solid").to_string();
    assert!(
        text.contains("micropolar_tet4") && text.contains("element 0 turned inside out") && text.contains("-1.000"),
        "{text}"
    );
    // The energy itself is defined there: only the solvers keep their iterates out.
    assert!(p.value(&u).unwrap().is_finite());
}
