//! Surface loads: consistent weights, and the follower pressure's energy, force and stiffness against
//! central differences and the closed forms of a sphere.

use super::common::dense_hessian;
use cosserat_assembly::inertia::LoadTerm;
use cosserat_assembly::pressure::{FollowerPressure, area_weights, normal_weights, profiled_area_weights};
use cosserat_assembly::{DofLayout, IncrementalPotential, PotentialParts, SystemState};
use cosserat_fem::mesh::procedural;
use nalgebra::{DMatrix, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Tri3 and Tri6 meshes of the unit icosphere (the Tri6 mid-edge nodes on the sphere).
fn sphere_elements(tri6: bool) -> (Vec<Vector3<f64>>, Vec<Vec<usize>>) {
    let g = procedural::icosphere(1.0, 1).unwrap();
    if tri6 {
        let m = g.mesh.to_tri6_with(|n| n.chord().normalize());
        (m.nodes, m.elements.iter().map(|e| e.to_vec()).collect())
    } else {
        (g.mesh.nodes, g.mesh.elements.iter().map(|e| e.to_vec()).collect())
    }
}

/// A potential holding only a follower pressure on the given elements, at perturbed positions.
fn potential<const N: usize>(
    x: Vec<Vector3<f64>>,
    elements: &[Vec<usize>],
    pressure: f64,
    dt: f64,
) -> IncrementalPotential {
    let n = x.len();
    let layout = DofLayout {
        n_disp_nodes: n,
        n_rot_nodes: 0,
    };
    let parts = PotentialParts {
        layout,
        state: SystemState::at_rest(x, 0, 0),
        shells: Vec::new(),
        inertia: None,
        loads: LoadTerm {
            masses: vec![0.0; n],
            gravity: Vector3::zeros(),
            forces: vec![Vector3::zeros(); n],
            torques: Vec::new(),
        },
        position_penalties: Vec::new(),
        rotation_penalties: Vec::new(),
        omega_penalties: Vec::new(),
        position_constraints: Vec::new(),
    };
    let mut p = IncrementalPotential::new(parts);
    let els: Vec<[usize; N]> = elements.iter().map(|e| std::array::from_fn(|a| e[a])).collect();
    let mut term = FollowerPressure::new("p", els);
    term.pressure = pressure;
    p.insert(term);
    p.set_time_step(dt);
    p
}

fn gradient(p: &mut IncrementalPotential, u: &[f64]) -> Vec<f64> {
    let mut g = vec![0.0; u.len()];
    p.gradient(u, &mut g).unwrap();
    g
}

/// On a closed surface the force is the gradient of the work `−pV` and its Jacobian is symmetric:
/// gradient and Hessian match central differences of the energy and of the gradient (step 1e-6 on
/// unit-size data: truncation ~1e-12, round-off ~1e-10 relative).
fn check_closed<const N: usize>(tri6: bool) {
    let (mut x, elements) = sphere_elements(tri6);
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for xi in &mut x {
        *xi += Vector3::from_fn(|_, _| rng.random_range(-0.05..0.05));
    }
    let dt = 0.3;
    let mut p = potential::<N>(x, &elements, 2.5, dt);
    let n = p.n_dofs();
    let u: Vec<f64> = (0..n).map(|_| rng.random_range(-0.1..0.1)).collect();
    let g = gradient(&mut p, &u);
    let h = dense_hessian(&mut p, &u);
    let eps = 1e-6;
    let scale_g = g.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let scale_h = h.amax();
    for i in 0..n {
        let (mut up, mut um) = (u.clone(), u.clone());
        up[i] += eps;
        um[i] -= eps;
        let fd = (p.value(&up).unwrap() - p.value(&um).unwrap()) / (2.0 * eps);
        assert!((fd - g[i]).abs() < 1e-7 * scale_g, "gradient {i}: {fd} vs {}", g[i]);
        let (gp, gm) = (gradient(&mut p, &up), gradient(&mut p, &um));
        for j in 0..n {
            let fd = (gp[j] - gm[j]) / (2.0 * eps);
            assert!(
                (fd - h[(j, i)]).abs() < 1e-7 * scale_h,
                "Hessian ({j}, {i}): {fd} vs {}",
                h[(j, i)]
            );
        }
    }
}

#[test]
fn follower_pressure_on_a_closed_tri3_surface_is_conservative() {
    check_closed::<3>(false);
}

#[test]
fn follower_pressure_on_a_closed_tri6_surface_is_conservative() {
    check_closed::<6>(true);
}

/// On an open surface the gradient is the follower force `−Δt p ∫ N_a n` (checked against the
/// independent Tri3 formula `p/6 (x₂ − x₁) × (x₃ − x₁)` per node), and the Hessian is the symmetric
/// part of the central-difference Jacobian of that force, which itself is not symmetric.
#[test]
fn follower_pressure_on_an_open_surface_assembles_the_symmetric_part() {
    let grid = procedural::rectangle_grid(1.0, 1.0, 2, 2).unwrap();
    let mut x = grid.mesh.nodes.clone();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for xi in &mut x {
        *xi += Vector3::from_fn(|_, _| rng.random_range(-0.1..0.1));
    }
    let elements: Vec<Vec<usize>> = grid.mesh.elements.iter().map(|e| e.to_vec()).collect();
    let (dt, pressure) = (0.5, 3.0);
    let mut p = potential::<3>(x.clone(), &elements, pressure, dt);
    let n = p.n_dofs();
    let u = vec![0.0; n];
    let g = gradient(&mut p, &u);
    let mut expected = vec![0.0; n];
    for el in &elements {
        let f = (x[el[1]] - x[el[0]]).cross(&(x[el[2]] - x[el[0]])) * (pressure / 6.0);
        for &i in el {
            for c in 0..3 {
                expected[3 * i + c] -= dt * f[c];
            }
        }
    }
    for i in 0..n {
        assert!(
            (g[i] - expected[i]).abs() < 1e-14,
            "force {i}: {} vs {}",
            g[i],
            expected[i]
        );
    }
    let h = dense_hessian(&mut p, &u);
    let eps = 1e-6;
    let mut jacobian = DMatrix::zeros(n, n);
    for i in 0..n {
        let (mut up, mut um) = (u.clone(), u.clone());
        up[i] += eps;
        um[i] -= eps;
        let (gp, gm) = (gradient(&mut p, &up), gradient(&mut p, &um));
        for j in 0..n {
            jacobian[(j, i)] = (gp[j] - gm[j]) / (2.0 * eps);
        }
    }
    let sym = (&jacobian + jacobian.transpose()) * 0.5;
    assert!((&sym - &h).amax() < 1e-8 * h.amax(), "{}", (&sym - &h).amax());
    let skew = (&jacobian - jacobian.transpose()).amax();
    assert!(
        skew > 1e-2 * h.amax(),
        "the open surface's load stiffness should not be symmetric"
    );
}

/// The flat Tri6 (0,0), (2,0), (0,1) of area 1: corners, then the mid-edge nodes.
fn flat_triangle() -> [Vector3<f64>; 6] {
    [
        Vector3::new(0.0, 0.0, 0.0),
        Vector3::new(2.0, 0.0, 0.0),
        Vector3::new(0.0, 1.0, 0.0),
        Vector3::new(1.0, 0.0, 0.0),
        Vector3::new(1.0, 0.5, 0.0),
        Vector3::new(0.0, 0.5, 0.0),
    ]
}

/// Consistent weights: the areas of a sphere (icosphere level 3, Tri6 with mid-edge nodes on the sphere)
/// sum to 4π within the discretisation error, the vector areas of a closed surface sum to zero, and a
/// flat Tri6 gives its corners nothing and its mid-edge nodes a third of the area each.
#[test]
fn consistent_area_weights() {
    let g = procedural::icosphere(1.0, 3).unwrap();
    let m = g.mesh.to_tri6_with(|n| n.chord().normalize());
    let elements: Vec<Vec<usize>> = m.elements.iter().map(|e| e.to_vec()).collect();
    let area: f64 = area_weights(&elements, &|i| m.nodes[i]).iter().map(|w| w.1).sum();
    assert!((area - 4.0 * std::f64::consts::PI).abs() < 1e-3, "{area}");
    let total = normal_weights(&elements, &|i| m.nodes[i])
        .iter()
        .fold(Vector3::zeros(), |acc, w| acc + w.1);
    assert!(total.norm() < 1e-12, "{total}");
    // ∫ N_a n · x over the sphere = ∫ x·n dA = 3V ≈ 4π.
    let flux: f64 = normal_weights(&elements, &|i| m.nodes[i])
        .iter()
        .map(|(i, w)| w.dot(&m.nodes[*i]))
        .sum();
    assert!((flux - 4.0 * std::f64::consts::PI).abs() < 1e-2, "{flux}");
    let flat = vec![vec![0, 1, 2, 3, 4, 5]];
    let nodes = flat_triangle();
    let w = area_weights(&flat, &|i| nodes[i]);
    for (i, wi) in w {
        let expected = if i < 3 { 0.0 } else { 1.0 / 3.0 };
        assert!((wi - expected).abs() < 1e-15, "node {i}: {wi}");
    }
}

/// A profile `f` weighs the consistent weights: on the flat triangle (0,0), (2,0), (0,1) of area 1,
/// `Σ w_a = ∫ f dA` and `Σ w_a x_a = ∫ f x dA` (the nodes interpolate `x` exactly) hold for `f = x`
/// (∫ = 2/3 and 2/3) and `f = x²` (∫ = 2/3 and 4/5) on Tri3 and Tri6, as the degree-4 rule
/// integrates them exactly; the constant profile gives the unprofiled weights.
#[test]
fn profiled_area_weights_integrate_the_profile() {
    let nodes = flat_triangle();
    type Case<'a> = (&'a dyn Fn(&Vector3<f64>) -> f64, f64, f64);
    let cases: [Case; 2] = [(&|p| p.x, 2.0 / 3.0, 2.0 / 3.0), (&|p| p.x * p.x, 2.0 / 3.0, 4.0 / 5.0)];
    for element in [vec![0, 1, 2], vec![0, 1, 2, 3, 4, 5]] {
        let elements = [element];
        for (k, (f, total, moment)) in cases.iter().enumerate() {
            let w = profiled_area_weights(&elements, &|i| nodes[i], f);
            let sum: f64 = w.iter().map(|x| x.1).sum();
            let first: f64 = w.iter().map(|(i, x)| x * nodes[*i].x).sum();
            assert!(
                (sum - total).abs() < 1e-14,
                "{} nodes, case {k}: {sum}",
                elements[0].len()
            );
            assert!(
                (first - moment).abs() < 1e-14,
                "{} nodes, case {k}: {first}",
                elements[0].len()
            );
        }
        let plain = area_weights(&elements, &|i| nodes[i]);
        let unit = profiled_area_weights(&elements, &|i| nodes[i], &|_| 1.0);
        for (a, b) in plain.iter().zip(&unit) {
            assert_eq!(a.0, b.0);
            assert!((a.1 - b.1).abs() < 1e-15, "{a:?} vs {b:?}");
        }
    }
}
