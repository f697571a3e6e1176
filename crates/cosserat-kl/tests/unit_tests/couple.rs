//! Force couples: the work of a moment, a pure couple of the applied magnitude, derivatives, errors.

use super::common::{fd_gradient, fd_jacobian, relative_error, rng};
use cosserat_assembly::term::{Evaluation, NodeRotations, PotentialTerm};
use cosserat_assembly::{DofLayout, Parallelism, SparsityPattern, SystemState};
use cosserat_kl::couple::pair_potential;
use cosserat_kl::{ForceCouple, KlError};
use nalgebra::{DMatrix, DVector, Rotation3, SVector, Vector3};
use rand::Rng;

#[test]
fn the_potential_is_minus_the_moment_times_the_turned_angle() {
    let axis = Vector3::new(0.0, -1.0, 0.0);
    let d0 = Vector3::new(1.0, 0.3, 0.0);
    for theta in [-3.0, -1.0, 0.2, 1.5, 3.1] {
        // Turn the segment by θ about the axis, and add a component along the axis (ignored).
        let d = Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(axis), theta) * d0 + axis * 0.7;
        let xa = Vector3::new(0.5, -2.0, 1.0);
        let xb = xa + d * 1.3;
        let x = SVector::<f64, 6>::from([xa.x, xa.y, xa.z, xb.x, xb.y, xb.z]);
        let v = pair_potential(&x, &d0, &axis, 2.0);
        assert!((v + 2.0 * theta).abs() < 1e-13, "θ = {theta}: {v}");
    }
}

fn setup() -> (ForceCouple, SparsityPattern, SystemState, DofLayout) {
    let x = vec![
        Vector3::new(0.0, 0.0, 0.0),
        Vector3::new(1.0, 0.0, 0.2),
        Vector3::new(0.0, 1.0, 0.0),
        Vector3::new(1.0, 1.0, -0.1),
    ];
    let mut c = ForceCouple::try_new("end", vec![[0, 1], [2, 3]], &[0.5, 1.5], Vector3::new(0.0, 2.0, 0.0), 4).unwrap();
    assert_eq!(c.shares(), &[0.25, 0.75]);
    assert_eq!(c.axis(), &Vector3::y());
    let groups = c.coupling_groups();
    let pattern = SparsityPattern::from_groups(4, groups.iter().map(|g| g.as_slice()));
    c.bind(&pattern);
    (
        c,
        pattern,
        SystemState::at_rest(x, 0, 0),
        DofLayout {
            n_disp_nodes: 4,
            n_rot_nodes: 0,
        },
    )
}

#[test]
fn the_gradient_is_a_pure_couple_of_the_applied_moment() {
    let (c, _, state, layout) = setup();
    let handle = c.handle();
    handle.set(3.0);
    assert_eq!(c.handle().get(), 3.0);
    let mut r = rng(41);
    let u: Vec<f64> = (0..12).map(|_| r.random_range(-0.3..0.3)).collect();
    let dt = 0.5;
    let rot = NodeRotations::Matrices(Vec::new());
    let e = Evaluation {
        state: &state,
        layout: &layout,
        u: &u,
        dt,
        rotations: &rot,
        parallelism: Parallelism::Sequential,
    };
    let mut g = vec![0.0; 12];
    c.gradient(&e, &mut g).unwrap();
    // Forces f = −∂Π/∂x = −(∂Π/∂v)/Δt: zero net force, moment about the axis = the applied moment.
    let x: Vec<Vector3<f64>> = (0..4).map(|i| state.x[i] + layout.velocity(&u, i) * dt).collect();
    let f: Vec<Vector3<f64>> = (0..4).map(|i| -layout.velocity(&g, i) / dt).collect();
    let net: Vector3<f64> = f.iter().sum();
    let moment: f64 = (0..4).map(|i| x[i].cross(&f[i]).y).sum();
    assert!(net.norm() < 1e-13, "net force {net}");
    assert!((moment - 3.0).abs() < 1e-13, "moment {moment}");
}

#[test]
fn derivatives_match_finite_differences() {
    let (c, pattern, state, layout) = setup();
    c.handle().set(-1.7);
    let mut r = rng(42);
    let u: Vec<f64> = (0..12).map(|_| r.random_range(-0.3..0.3)).collect();
    let dt = 0.5;
    let rot = NodeRotations::Matrices(Vec::new());
    let eval = |v: &DVector<f64>| -> (f64, Vec<f64>) {
        let e = Evaluation {
            state: &state,
            layout: &layout,
            u: v.as_slice(),
            dt,
            rotations: &rot,
            parallelism: Parallelism::Sequential,
        };
        let mut g = vec![0.0; 12];
        let value = c.gradient(&e, &mut g).unwrap();
        assert_eq!(value, c.value(&e).unwrap());
        (value, g)
    };
    let ud = DVector::from_vec(u.clone());
    let g_fd = fd_gradient(|v| eval(v).0, &ud, 1e-6);
    assert!(relative_error(&eval(&ud).1, g_fd.as_slice()) < 1e-7);
    let e = Evaluation {
        state: &state,
        layout: &layout,
        u: &u,
        dt,
        rotations: &rot,
        parallelism: Parallelism::Sequential,
    };
    let mut g = vec![0.0; 12];
    let mut h = vec![0.0; pattern.nnz()];
    c.hessian(&e, &mut g, &pattern, &mut h).unwrap();
    let h_fd = fd_jacobian(|v| DVector::from_vec(eval(v).1), &ud, 1e-6);
    let mut dense = DMatrix::<f64>::zeros(12, 12);
    for i in 0..12 {
        for j in i..12 {
            if let Some(k) = pattern.entry(i, j) {
                dense[(i, j)] = h[k];
                dense[(j, i)] = h[k];
            }
        }
    }
    assert!(relative_error(dense.as_slice(), h_fd.as_slice()) < 1e-7);
}

#[test]
fn invalid_pairs_axes_and_weights_are_rejected() {
    let y = Vector3::y();
    assert!(matches!(
        ForceCouple::try_new("c", vec![[0, 1], [2, 2]], &[1.0, 1.0], y, 4),
        Err(KlError::InvalidPair {
            pair_idx: 1,
            a: 2,
            b: 2,
            ..
        })
    ));
    assert!(matches!(
        ForceCouple::try_new("c", vec![[0, 9]], &[1.0], y, 4),
        Err(KlError::InvalidPair {
            pair_idx: 0,
            b: 9,
            n_vertices: 4,
            ..
        })
    ));
    assert!(matches!(
        ForceCouple::try_new("c", vec![[0, 1]], &[1.0], Vector3::zeros(), 4),
        Err(KlError::InvalidParameter { name: "axis", .. })
    ));
    assert!(matches!(
        ForceCouple::try_new("c", vec![[0, 1]], &[1.0, 2.0], y, 4),
        Err(KlError::InvalidParameter {
            name: "weights.len",
            ..
        })
    ));
    assert!(matches!(
        ForceCouple::try_new("c", vec![[0, 1]], &[-1.0], y, 4),
        Err(KlError::InvalidParameter { name: "weights", .. })
    ));
    assert!(matches!(
        ForceCouple::try_new("c", vec![[0, 1]], &[0.0], y, 4),
        Err(KlError::InvalidParameter {
            name: "weights.sum",
            ..
        })
    ));
}
