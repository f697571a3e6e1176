//! The assembled Kirchhoff–Love term: derivatives in velocity units, scatter into the pattern,
//! determinism across threads, and errors.

use super::common::{fd_gradient, fd_jacobian, relative_error, rng};
use cosserat_assembly::term::{Evaluation, NodeRotations, PotentialTerm};
use cosserat_assembly::{AssemblyError, DofLayout, Parallelism, SparsityPattern, SystemState};
use cosserat_fem::mesh::procedural;
use cosserat_fem::{MeshError, Tri3Mesh};
use cosserat_kl::{HyperelasticModel, KirchhoffLoveTerm, KlError, KlMaterial, ThicknessRule, stencil_energy};
use nalgebra::{DMatrix, DVector, Vector3};
use rand::Rng;

fn layout(mesh: &Tri3Mesh) -> DofLayout {
    DofLayout {
        n_disp_nodes: mesh.n_nodes(),
        n_rot_nodes: 0,
    }
}

/// A bound term with its pattern.
fn bound(mesh: &Tri3Mesh, model: HyperelasticModel) -> (KirchhoffLoveTerm, SparsityPattern) {
    let material = KlMaterial::new(model, 1e4, 0.3);
    let mut term = KirchhoffLoveTerm::try_new(mesh, &material, 0.01, ThicknessRule::default(), layout(mesh)).unwrap();
    let groups = term.coupling_groups();
    let pattern = SparsityPattern::from_groups(mesh.n_nodes(), groups.iter().map(|g| g.as_slice()));
    term.bind(&pattern);
    (term, pattern)
}

fn eval<'a>(
    state: &'a SystemState,
    layout: &'a DofLayout,
    u: &'a [f64],
    dt: f64,
    rotations: &'a NodeRotations,
    parallelism: Parallelism,
) -> Evaluation<'a> {
    Evaluation {
        state,
        layout,
        u,
        dt,
        rotations,
        parallelism,
    }
}

/// A gently curved start-of-step state of a small grid, with random velocities.
fn state_and_velocities(mesh: &Tri3Mesh, seed: u64) -> (SystemState, Vec<f64>) {
    let mut r = rng(seed);
    let x = mesh
        .nodes
        .iter()
        .map(|p| p + Vector3::new(0.0, 0.0, 0.1 * p.x * p.x - 0.05 * p.y))
        .collect();
    let u = (0..3 * mesh.n_nodes()).map(|_| r.random_range(-0.2..0.2)).collect();
    (SystemState::at_rest(x, 0, 0), u)
}

#[test]
fn assembled_gradient_and_hessian_are_the_derivatives_of_the_value_in_velocity_units() {
    let mesh = procedural::rectangle_grid(1.0, 0.6, 4, 3).unwrap().mesh;
    let dt = 0.1;
    for model in [HyperelasticModel::StVenantKirchhoff, HyperelasticModel::NeoHookean] {
        let (term, pattern) = bound(&mesh, model);
        let (state, u) = state_and_velocities(&mesh, 31);
        let l = layout(&mesh);
        let rot = NodeRotations::Matrices(Vec::new());
        let value = |v: &DVector<f64>| {
            term.value(&eval(&state, &l, v.as_slice(), dt, &rot, Parallelism::Sequential))
                .unwrap()
        };
        let gradient = |v: &DVector<f64>| {
            let mut g = vec![0.0; v.len()];
            term.gradient(
                &eval(&state, &l, v.as_slice(), dt, &rot, Parallelism::Sequential),
                &mut g,
            )
            .unwrap();
            DVector::from_vec(g)
        };
        let ud = DVector::from_vec(u.clone());
        let mut g = vec![0.0; u.len()];
        let mut h = vec![0.0; pattern.nnz()];
        let e = term
            .hessian(
                &eval(&state, &l, &u, dt, &rot, Parallelism::Sequential),
                &mut g,
                &pattern,
                &mut h,
            )
            .unwrap();
        assert!((e - value(&ud)).abs() < 1e-12 * e);
        assert!(relative_error(&g, gradient(&ud).as_slice()) < 1e-13);
        // Central differences with steps of 1e-6 (velocities of order 0.1): see the stencil battery.
        let g_fd = fd_gradient(value, &ud, 1e-6);
        assert!(relative_error(&g, g_fd.as_slice()) < 1e-6, "{model:?}: gradient");
        let h_fd = fd_jacobian(gradient, &ud, 1e-6);
        let n = u.len();
        let mut dense = DMatrix::<f64>::zeros(n, n);
        for i in 0..n {
            for j in i..n {
                match pattern.entry(i, j) {
                    Some(k) => {
                        dense[(i, j)] = h[k];
                        dense[(j, i)] = h[k];
                    }
                    None => assert!(
                        h_fd[(i, j)].abs() < 1e-9 * h_fd.amax(),
                        "({i}, {j}) coupled but not in the pattern"
                    ),
                }
            }
        }
        let err = relative_error(dense.as_slice(), h_fd.as_slice());
        assert!(err < 1e-6, "{model:?}: Hessian error {err:e}");
    }
}

#[test]
fn results_are_bit_identical_for_sequential_and_parallel_evaluation() {
    // More faces than one chunk (256), so the chunked pipeline is exercised.
    let mesh = procedural::rectangle_grid(1.0, 1.0, 12, 12).unwrap().mesh;
    let (term, pattern) = bound(&mesh, HyperelasticModel::NeoHookean);
    assert!(term.n_faces() > 256);
    let (state, u) = state_and_velocities(&mesh, 32);
    let l = layout(&mesh);
    let rot = NodeRotations::Matrices(Vec::new());
    let run = |par| {
        let mut g = vec![0.0; u.len()];
        let mut h = vec![0.0; pattern.nnz()];
        let e = term
            .hessian(&eval(&state, &l, &u, 0.05, &rot, par), &mut g, &pattern, &mut h)
            .unwrap();
        let v = term.value(&eval(&state, &l, &u, 0.05, &rot, par)).unwrap();
        (e, v, g, h)
    };
    let (a, b) = (run(Parallelism::Sequential), run(Parallelism::Rayon));
    assert_eq!(a.0.to_bits(), b.0.to_bits());
    assert_eq!(a.1.to_bits(), b.1.to_bits());
    assert!(a.2.iter().zip(&b.2).all(|(x, y)| x.to_bits() == y.to_bits()));
    assert!(a.3.iter().zip(&b.3).all(|(x, y)| x.to_bits() == y.to_bits()));
}

#[test]
fn a_collapsed_face_is_reported_by_index() {
    let mesh = procedural::rectangle_grid(1.0, 1.0, 3, 3).unwrap().mesh;
    let (term, pattern) = bound(&mesh, HyperelasticModel::StVenantKirchhoff);
    let l = layout(&mesh);
    let rot = NodeRotations::Matrices(Vec::new());
    let state = SystemState::at_rest(mesh.nodes.clone(), 0, 0);
    // Move corner 1 of face 7 onto corner 0 over a step of 1 s.
    let [a, b, _] = mesh.elements[7];
    let mut u = vec![0.0; 3 * mesh.n_nodes()];
    let d = mesh.nodes[a] - mesh.nodes[b];
    u[3 * b..3 * b + 3].copy_from_slice(d.as_slice());
    let e = eval(&state, &l, &u, 1.0, &rot, Parallelism::Sequential);
    // The first face whose stencil energy, evaluated on its own, is not finite.
    let x: Vec<Vector3<f64>> = (0..mesh.n_nodes()).map(|i| state.x[i] + l.velocity(&u, i)).collect();
    let first = (0..term.n_faces())
        .position(|f| {
            let s = &term.stencils()[f];
            let xs = nalgebra::SVector::<f64, 18>::from_fn(|i, _| s.vertices()[i / 3].map_or(0.0, |v| x[v][i % 3]));
            !stencil_energy(&xs, &term.rest()[f], term.material()).is_finite()
        })
        .unwrap();
    assert!(term.stencils()[first].face.contains(&a) || term.stencils()[first].face.contains(&b));
    for result in [
        term.value(&e),
        term.gradient(&e, &mut vec![0.0; u.len()]),
        term.hessian(&e, &mut vec![0.0; u.len()], &pattern, &mut vec![0.0; pattern.nnz()]),
    ] {
        match result {
            Err(AssemblyError::NonFinite {
                location: "face",
                index,
                term: name,
            }) => {
                assert_eq!(index, first);
                assert_eq!(name, "kirchhoff_love_stvk");
            }
            other => panic!("{other:?}"),
        }
    }
}

#[test]
fn coupling_groups_hold_the_present_stencil_vertices() {
    let mesh = procedural::rectangle_grid(1.0, 1.0, 2, 2).unwrap().mesh;
    let (term, _) = bound(&mesh, HyperelasticModel::NeoHookean);
    assert_eq!(term.name(), "kirchhoff_love_neo_hookean");
    for (g, s) in term.coupling_groups().iter().zip(term.stencils()) {
        assert_eq!(g.len(), 3 + s.opposite.iter().flatten().count());
    }
    let x: Vec<Vector3<f64>> = mesh.nodes.iter().map(|p| p * 1.1).collect();
    // A uniform stretch by 1.1 stores energy; the rest state none.
    assert!(term.energy_at(&x).unwrap() > 0.0);
    assert!(term.energy_at(&mesh.nodes).unwrap().abs() < 1e-20);
}

#[test]
fn construction_errors_name_their_cause() {
    let mesh = procedural::rectangle_grid(1.0, 1.0, 2, 2).unwrap().mesh;
    let good = KlMaterial::new(HyperelasticModel::NeoHookean, 1.0, 0.3);
    let rule = ThicknessRule::default();
    let small = DofLayout {
        n_disp_nodes: 3,
        n_rot_nodes: 0,
    };
    assert!(matches!(
        KirchhoffLoveTerm::try_new(&mesh, &good, 0.01, rule, small),
        Err(KlError::InvalidParameter {
            name: "layout.n_disp_nodes",
            ..
        })
    ));
    let bad = KlMaterial::new(HyperelasticModel::NeoHookean, 1.0, 0.5);
    assert!(matches!(
        KirchhoffLoveTerm::try_new(&mesh, &bad, 0.01, rule, layout(&mesh)),
        Err(KlError::InvalidParameter {
            name: "poisson_ratio",
            ..
        })
    ));
    let mut degenerate = mesh.clone();
    degenerate.nodes[4] = degenerate.nodes[0];
    assert!(matches!(
        KirchhoffLoveTerm::try_new(&degenerate, &good, 0.01, rule, layout(&mesh)),
        Err(KlError::Mesh(MeshError::DegenerateElement { .. }))
    ));
}
