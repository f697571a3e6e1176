//! The contact term as a potential term: derivatives against finite differences (floor contact with
//! friction, self-contact with generic and mollified edge–edge pairs, and through a full
//! `IncrementalPotential`), zero contribution when apart, determinism, Coulomb's law, CCD and candidate
//! coverage, pattern growth, obstacles and errors.

use super::broad_phase::{grid_nodes, grid_triangles};
use super::common::{random_vec, rng};
use cosserat_assembly::term::{Evaluation, NodeRotations, PotentialTerm};
use cosserat_assembly::{
    DofLayout, ElementPair, Parallelism, ShellInput, ShellMesh, SparsityPattern, SystemOptions, SystemState,
    build_system,
};
use cosserat_contact::{ContactError, ContactParameters, ContactSurface, ContactTerm, Obstacle, intersecting_pairs};
use cosserat_fem::mesh::{chord_placement, procedural};
use cosserat_material::rest::RestOptions;
use cosserat_material::{MaterialParameters, ModelOptions, ShellModel};
use nalgebra::{DMatrix, Rotation3, Vector3};
use rand::Rng;

const TH: f64 = 5e-4; // each body's thickness: δ = 1 mm for every pair
const DHAT: f64 = 1e-3;
const DT: f64 = 0.01;

struct Case {
    state: SystemState,
    layout: DofLayout,
    surfaces: Vec<ContactSurface>,
    obstacles: Vec<Obstacle>,
}

fn floor(z: f64) -> Obstacle {
    Obstacle {
        id: 1,
        positions: vec![
            Vector3::new(-1.0, -1.0, z),
            Vector3::new(1.0, -1.0, z),
            Vector3::new(1.0, 1.0, z),
            Vector3::new(-1.0, 1.0, z),
        ],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        thickness: TH,
    }
}

/// An `n × n` plate of side 0.1 m whose nodes sit at `height ± jitter` above a floor at z = 0.
fn plate_over_floor(n: usize, height: f64, jitter: f64, seed: u64) -> Case {
    let mut rng = rng(seed);
    let mut x = grid_nodes(&mut rng, n, 0.1, height, 0.0);
    for p in &mut x {
        let dz = if jitter > 0.0 {
            rng.random_range(-jitter..jitter)
        } else {
            0.0
        };
        *p += Vector3::new(rng.random_range(-1e-3..1e-3), rng.random_range(-1e-3..1e-3), dz);
    }
    let n_nodes = x.len();
    Case {
        state: SystemState::at_rest(x, 0, 0),
        layout: DofLayout {
            n_disp_nodes: n_nodes,
            n_rot_nodes: 0,
        },
        surfaces: vec![ContactSurface {
            id: 0,
            triangles: grid_triangles(n, 0),
            thickness: TH,
        }],
        obstacles: vec![floor(0.0)],
    }
}

/// Two `n × n` plates, the second rotated by `angle` about the vertical axis through the first's centre
/// and lifted by `gap + δ`.
fn two_plates(n: usize, angle: f64, gap: f64, seed: u64) -> Case {
    let mut rng = rng(seed);
    let mut x = grid_nodes(&mut rng, n, 0.1, 0.0, 2e-5);
    let centre = Vector3::new(0.05, 0.05, 0.0);
    let rot = Rotation3::from_axis_angle(&Vector3::z_axis(), angle);
    let top: Vec<Vector3<f64>> = grid_nodes(&mut rng, n, 0.1, 0.0, 2e-5)
        .into_iter()
        .map(|p| centre + rot * (p - centre) + Vector3::new(0.003, 0.002, 2.0 * TH + gap))
        .collect();
    let offset = x.len();
    x.extend(top);
    let n_nodes = x.len();
    Case {
        state: SystemState::at_rest(x, 0, 0),
        layout: DofLayout {
            n_disp_nodes: n_nodes,
            n_rot_nodes: 0,
        },
        surfaces: vec![
            ContactSurface {
                id: 0,
                triangles: grid_triangles(n, 0),
                thickness: TH,
            },
            ContactSurface {
                id: 0,
                triangles: grid_triangles(n, offset),
                thickness: TH,
            },
        ],
        obstacles: Vec::new(),
    }
}

fn parameters(mu: f64, project_pd: bool) -> ContactParameters {
    let mut p = ContactParameters::new(100.0, DHAT);
    p.stick_velocity = 0.05;
    p.friction.set(0, 1, mu).unwrap();
    p.friction.set(0, 0, mu).unwrap();
    p.project_pd = project_pd;
    p
}

fn term(case: &Case, params: ContactParameters) -> ContactTerm {
    ContactTerm::try_new(case.surfaces.clone(), case.obstacles.clone(), params, &case.state.x).unwrap()
}

fn random_u(case: &Case, tangential: f64, normal: f64, seed: u64) -> Vec<f64> {
    let mut rng = rng(seed);
    (0..case.layout.n_dofs())
        .map(|i| {
            if i % 3 == 2 {
                rng.random_range(-normal..normal)
            } else {
                rng.random_range(-tangential..tangential)
            }
        })
        .collect()
}

fn dense(pattern: &SparsityPattern, values: &[f64]) -> DMatrix<f64> {
    let n = pattern.n_dofs();
    let sym = pattern.symbolic();
    let mut h = DMatrix::zeros(n, n);
    for j in 0..n {
        for k in sym.col_ptr()[j]..sym.col_ptr()[j + 1] {
            let i = sym.row_idx()[k];
            h[(i, j)] = values[k];
            h[(j, i)] = values[k];
        }
    }
    h
}

/// Value, gradient and dense Hessian of the term alone.
fn evaluate(term: &ContactTerm, case: &Case, u: &[f64], par: Parallelism) -> (f64, Vec<f64>, DMatrix<f64>) {
    let rotations = NodeRotations::Matrices(Vec::new());
    let eval = Evaluation {
        state: &case.state,
        layout: &case.layout,
        u,
        dt: DT,
        rotations: &rotations,
        parallelism: par,
    };
    let groups = term.coupling_groups();
    let pattern = SparsityPattern::from_groups(case.layout.n_blocks(), groups.iter().map(|g| g.as_slice()));
    let mut grad = vec![0.0; u.len()];
    let mut values = vec![0.0; pattern.nnz()];
    let e = term.hessian(&eval, &mut grad, &pattern, &mut values).unwrap();
    let mut grad2 = vec![0.0; u.len()];
    assert_eq!(term.gradient(&eval, &mut grad2).unwrap(), e);
    assert_eq!(grad, grad2);
    assert!((term.value(&eval).unwrap() - e).abs() <= 1e-13 * e.abs());
    (e, grad, dense(&pattern, &values))
}

fn value(term: &ContactTerm, case: &Case, u: &[f64]) -> f64 {
    let rotations = NodeRotations::Matrices(Vec::new());
    let eval = Evaluation {
        state: &case.state,
        layout: &case.layout,
        u,
        dt: DT,
        rotations: &rotations,
        parallelism: Parallelism::Sequential,
    };
    term.value(&eval).unwrap()
}

/// Central differences of the value (gradient) and of the gradient (Hessian), both with step `h` on
/// the velocities, compared entrywise relative to the largest entry.
fn check_derivatives(name: &str, term: &ContactTerm, case: &Case, u: &[f64], h: f64, tol: f64) {
    let (_, g, hess) = evaluate(term, case, u, Parallelism::Rayon);
    let n = u.len();
    let mut fd_g = vec![0.0; n];
    let mut fd_h = DMatrix::zeros(n, n);
    for i in 0..n {
        let (mut up, mut um) = (u.to_vec(), u.to_vec());
        up[i] += h;
        um[i] -= h;
        fd_g[i] = (value(term, case, &up) - value(term, case, &um)) / (2.0 * h);
        let (gp, gm) = (
            evaluate(term, case, &up, Parallelism::Sequential).1,
            evaluate(term, case, &um, Parallelism::Sequential).1,
        );
        for j in 0..n {
            fd_h[(j, i)] = (gp[j] - gm[j]) / (2.0 * h);
        }
    }
    let gscale = g.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let gerr = g.iter().zip(&fd_g).fold(0.0f64, |m, (a, b)| m.max((a - b).abs())) / gscale;
    assert!(
        gscale > 0.0 && gerr < tol,
        "{name}: gradient error {gerr:e} (scale {gscale:e})"
    );
    let hscale = hess.amax();
    let herr = (&hess - &fd_h).amax() / hscale;
    assert!(
        hscale > 0.0 && herr < tol,
        "{name}: Hessian error {herr:e} (scale {hscale:e})"
    );
}

#[test]
fn floor_contact_with_friction_matches_finite_differences() {
    // Gaps 0.3–0.7 mm inside a 1 mm barrier; tangential displacements Δt u up to 1 mm straddle the slip
    // distance ε_v Δt = 0.5 mm, so both friction regimes occur. Step 1e-6 m/s moves nodes by 1e-8 m:
    // truncation (1e-8/3e-4)² ≈ 1e-9 and round-off far below the 1e-5 tolerance.
    let case = plate_over_floor(3, 2.0 * TH + 0.5 * DHAT, 0.2 * DHAT, 1);
    let mut t = term(&case, parameters(0.8, false));
    let u0 = vec![0.0; case.layout.n_dofs()];
    assert!(t.begin_step(&case.state, &case.layout, DT, &u0).unwrap());
    let stats = t.stats();
    assert!(stats.n_candidates >= 16 && stats.n_friction >= 16, "{stats:?}");
    assert!(
        t.pairs()
            .iter()
            .any(|p| p.mollifier.is_some_and(|m| m.is_active(cross(&t, &case, p))))
    );
    let u = random_u(&case, 0.1, 0.005, 2);
    check_derivatives("floor", &t, &case, &u, 1e-6, 1e-5);
    assert!(t.stats().n_active >= 16);
}

/// `|a × b|²` of an edge–edge pair at the start positions.
fn cross(t: &ContactTerm, case: &Case, pair: &cosserat_contact::pair::ContactPair) -> f64 {
    let positions = t.mesh().positions(|i| case.state.x[i], |o, v| case.obstacles[o].positions[v]);
    cosserat_contact::mollifier::cross_squared(&pair.vertices.map(|v| positions[v as usize]))
}

#[test]
fn self_contact_matches_finite_differences_with_generic_and_mollified_edges() {
    for (angle, name) in [
        (0.5f64, "crossing edges"),
        (0.5f64.to_radians(), "nearly parallel edges"),
    ] {
        let case = two_plates(3, angle, 0.5 * DHAT, 3);
        let mut t = term(&case, parameters(0.5, false));
        let u0 = vec![0.0; case.layout.n_dofs()];
        t.begin_step(&case.state, &case.layout, DT, &u0).unwrap();
        let n_ee = t.pairs().iter().filter(|p| p.mollifier.is_some()).count();
        assert!(n_ee > 10, "{name}: {n_ee} edge-edge pairs");
        let u = random_u(&case, 0.05, 0.005, 4);
        check_derivatives(name, &t, &case, &u, 1e-6, 1e-5);
    }
}

#[test]
fn projected_hessian_is_positive_semi_definite() {
    let case = two_plates(3, 0.3, 0.3 * DHAT, 5);
    let mut t = term(&case, parameters(0.5, true));
    t.begin_step(&case.state, &case.layout, DT, &vec![0.0; case.layout.n_dofs()])
        .unwrap();
    let u = random_u(&case, 0.05, 0.005, 6);
    let (_, _, h) = evaluate(&t, &case, &u, Parallelism::Rayon);
    let min = h.clone().symmetric_eigen().eigenvalues.min();
    assert!(min >= -1e-9 * h.amax(), "smallest eigenvalue {min:e}");
    // Without projection the barrier Hessian of this configuration is indefinite.
    let mut raw = term(&case, parameters(0.5, false));
    raw.begin_step(&case.state, &case.layout, DT, &vec![0.0; case.layout.n_dofs()])
        .unwrap();
    let (_, _, h) = evaluate(&raw, &case, &u, Parallelism::Rayon);
    assert!(h.clone().symmetric_eigen().eigenvalues.min() < -1e-6 * h.amax());
}

#[test]
fn nothing_when_far_apart() {
    let case = plate_over_floor(3, 0.1, 0.0, 7);
    let mut t = term(&case, parameters(0.8, false));
    let grew = t
        .begin_step(&case.state, &case.layout, DT, &vec![0.0; case.layout.n_dofs()])
        .unwrap();
    assert!(!grew);
    assert!(t.pairs().is_empty() && t.friction_pairs().is_empty());
    let u = random_u(&case, 0.1, 0.1, 8);
    let (e, g, h) = evaluate(&t, &case, &u, Parallelism::Rayon);
    assert_eq!(e, 0.0);
    assert!(g.iter().all(|&v| v == 0.0) && h.amax() == 0.0);
    assert_eq!(t.stats().min_gap, f64::INFINITY);
}

#[test]
fn results_are_identical_for_any_number_of_threads() {
    let case = two_plates(4, 0.4, 0.4 * DHAT, 9);
    let mut t = term(&case, parameters(0.5, true));
    t.begin_step(&case.state, &case.layout, DT, &vec![0.0; case.layout.n_dofs()])
        .unwrap();
    let u = random_u(&case, 0.05, 0.005, 10);
    let seq = evaluate(&t, &case, &u, Parallelism::Sequential);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(3).build().unwrap();
    let par = pool.install(|| evaluate(&t, &case, &u, Parallelism::Rayon));
    assert_eq!(seq.0.to_bits(), par.0.to_bits());
    assert_eq!(seq.1, par.1);
    assert_eq!(seq.2, par.2);
}

#[test]
fn sliding_friction_obeys_coulomb_and_sticks_below_the_threshold() {
    // One triangle resting above the floor, away from the floor's diagonal: only its three
    // point–triangle pairs are active, each with normal along z.
    let x = [
        Vector3::new(0.3, -0.5, 0.0),
        Vector3::new(0.5, -0.5, 0.0),
        Vector3::new(0.4, -0.3, 0.0),
    ];
    let heights = [1.3e-3, 1.5e-3, 1.7e-3];
    let x: Vec<Vector3<f64>> = x.iter().zip(heights).map(|(p, z)| p + Vector3::new(0.0, 0.0, z)).collect();
    let case = Case {
        state: SystemState::at_rest(x, 0, 0),
        layout: DofLayout {
            n_disp_nodes: 3,
            n_rot_nodes: 0,
        },
        surfaces: vec![ContactSurface {
            id: 0,
            triangles: vec![[0, 1, 2]],
            thickness: TH,
        }],
        obstacles: vec![floor(0.0)],
    };
    let mu = 0.6;
    let mut t = term(&case, parameters(mu, false));
    let zero = vec![0.0; 9];
    t.begin_step(&case.state, &case.layout, DT, &zero).unwrap();
    assert_eq!(t.friction_pairs().len(), 3);
    // The normal force at the lagged state: the z-gradient of the energy at u = 0, divided by Δt.
    let (_, g0, _) = evaluate(&t, &case, &zero, Parallelism::Sequential);
    let normal: f64 = (0..3).map(|i| -g0[3 * i + 2] / DT).sum();
    assert!(normal > 0.0);
    let eps = 0.05 * DT;
    let direction = Vector3::new(0.6, 0.8, 0.0);
    for (speed, expected) in [
        // Slip beyond ε: Coulomb, |F_t| = μ F_n.
        (3.0 * eps / DT, mu * normal),
        (10.0 * eps / DT, mu * normal),
        // Below ε: the smoothed law μ F_n f₁(y) with y = |Δt v|.
        (0.25 * eps / DT, mu * normal * (2.0 * 0.25 - 0.25 * 0.25)),
    ] {
        let u: Vec<f64> = (0..3)
            .flat_map(|_| (direction * speed).iter().copied().collect::<Vec<_>>())
            .collect();
        let (_, g, _) = evaluate(&t, &case, &u, Parallelism::Sequential);
        let force: Vector3<f64> = (0..3).map(|i| Vector3::new(g[3 * i], g[3 * i + 1], 0.0) / DT).sum();
        assert!(
            (force.norm() - expected).abs() < 1e-12 * expected,
            "{} vs {expected}",
            force.norm()
        );
        // The friction force opposes the slip (the gradient points along it).
        assert!((force.normalize() - direction).norm() < 1e-12);
    }
}

#[test]
fn step_fraction_stops_the_plate_above_the_floor() {
    let case = plate_over_floor(4, 2.0 * TH + 2.0 * DHAT, 0.3 * DHAT, 11);
    let mut t = term(&case, parameters(0.0, true));
    let n = case.layout.n_dofs();
    let zero = vec![0.0; n];
    t.begin_step(&case.state, &case.layout, DT, &zero).unwrap();
    let g0 = t.coverage(&case.state, &case.layout, &zero, DT).min_gap;
    assert!(g0 > DHAT);
    // Every node moves 1 cm down and a little sideways: far through the floor.
    let mut rng = rng(12);
    let du: Vec<f64> = (0..n)
        .map(|i| if i % 3 == 2 { -1.0 } else { rng.random_range(-0.1..0.1) })
        .collect();
    let alpha = t.max_step_fraction(&case.state, &case.layout, &zero, &du, DT);
    assert!(alpha > 0.0 && alpha < 1.0);
    for a in [alpha, 0.5 * alpha] {
        let u: Vec<f64> = du.iter().map(|d| d * a).collect();
        let c = t.coverage(&case.state, &case.layout, &u, DT);
        // Pairs closer than d̂ are checked against 10 % of their start gap; all start beyond d̂.
        assert!(c.min_gap >= 0.1 * DHAT.min(g0) - 1e-15, "gap {} at α = {a}", c.min_gap);
        // No triangle of the plate intersects the floor.
        let mut x: Vec<Vector3<f64>> = (0..case.layout.n_disp_nodes)
            .map(|i| case.state.x[i] + Vector3::new(u[3 * i], u[3 * i + 1], u[3 * i + 2]) * DT)
            .collect();
        let first = x.len();
        x.extend(floor(0.0).positions);
        let mut tris = case.surfaces[0].triangles.clone();
        tris.extend(floor(0.0).triangles.iter().map(|t| t.map(|v| v + first)));
        assert!(intersecting_pairs(&tris, &x).is_empty());
    }
    // Sliding sideways at a constant height is never limited.
    let slide: Vec<f64> = (0..n).map(|i| if i % 3 == 0 { 1.0 } else { 0.0 }).collect();
    assert_eq!(t.max_step_fraction(&case.state, &case.layout, &zero, &slide, DT), 1.0);
    // Invalid input gives no step.
    assert_eq!(t.max_step_fraction(&case.state, &case.layout, &zero, &du[1..], DT), 0.0);
    assert_eq!(t.stats().n_ccd_queries, 2);
}

#[test]
fn coverage_reports_pairs_missed_by_the_prediction_and_pattern_growth() {
    let case = plate_over_floor(3, 2.0 * TH + 4.0 * DHAT, 0.0, 13);
    let mut t = term(&case, parameters(0.0, false));
    let n = case.layout.n_dofs();
    let zero = vec![0.0; n];
    // At rest 4 mm above the contact distance: the candidate reach (d̂ + margin = 2 mm) finds nothing.
    assert!(!t.begin_step(&case.state, &case.layout, DT, &zero).unwrap());
    assert!(t.pairs().is_empty());
    // Moving 3.5 mm down brings every node into the barrier: all active pairs are uncovered.
    let down: Vec<f64> = (0..n).map(|i| if i % 3 == 2 { -0.35 } else { 0.0 }).collect();
    let c = t.coverage(&case.state, &case.layout, &down, DT);
    assert!(c.n_active >= 16 && c.n_uncovered == c.n_active, "{c:?}");
    // Predicting that motion covers them, and the coupled blocks grew.
    assert!(t.begin_step(&case.state, &case.layout, DT, &down).unwrap());
    let c = t.coverage(&case.state, &case.layout, &down, DT);
    assert!(c.n_active >= 16 && c.n_uncovered == 0, "{c:?}");
    // Node quads name displacement nodes only (the floor's vertices are left out).
    let quads = t.coupled_node_quads();
    assert_eq!(quads.len(), t.pairs().len());
    assert!(quads.iter().flatten().all(|&i| i < case.layout.n_disp_nodes));
    // Pairs with the floor's diagonal edge couple two plate nodes; an empty pattern misses them.
    let empty = SparsityPattern::from_groups(case.layout.n_blocks(), std::iter::empty());
    assert!(!t.fits_pattern(&empty));
    let groups = t.coupling_groups();
    let pattern = SparsityPattern::from_groups(case.layout.n_blocks(), groups.iter().map(|g| g.as_slice()));
    assert!(t.fits_pattern(&pattern));
    t.bind(&pattern);
    assert!(!t.begin_step(&case.state, &case.layout, DT, &down).unwrap());
}

fn shell_input(n: usize, height: f64) -> ShellInput {
    let mut grid = procedural::rectangle_grid(0.1, 0.1, n, n).unwrap();
    for p in &mut grid.mesh.nodes {
        p.z = height + 1e-4 * (p.x * 37.0).sin() * (p.y * 23.0).cos();
    }
    ShellInput {
        name: "plate".into(),
        mesh: ShellMesh::from_tri3(grid.mesh, ElementPair::Tri3Tri3, chord_placement),
        pair: ElementPair::Tri3Tri3,
        material: MaterialParameters::new(1e-3, 1e5, 0.3, 500.0, 1e-3),
        rest: RestOptions::new(ModelOptions::new(ShellModel::Plate)),
        quadrature: None,
        damping: 0.0,
        angular_inertia_density: 0.0,
    }
}

#[test]
fn through_the_incremental_potential() {
    let options = SystemOptions {
        gravity: Vector3::new(0.0, 0.0, -9.81),
        dynamic: true,
    };
    let system = build_system(&[shell_input(3, 2.0 * TH + 0.5 * DHAT)], &options).unwrap();
    let triangles: Vec<[usize; 3]> = system.shells[0].disp_elements.iter().map(|e| [e[0], e[1], e[2]]).collect();
    let mut p = system.potential;
    p.set_time_step(DT);
    let parts = &mut p.parts;
    let surfaces = vec![ContactSurface {
        id: 0,
        triangles,
        thickness: TH,
    }];
    let mut t = ContactTerm::try_new(surfaces, vec![floor(0.0)], parameters(0.7, false), &parts.state.x).unwrap();
    let mut rng = rng(14);
    for v in &mut parts.state.v {
        *v = random_vec(&mut rng, 0.05);
    }
    let n = parts.layout.n_dofs();
    let u0 = vec![0.0; n];
    assert!(t.begin_step(&parts.state, &parts.layout, DT, &u0).unwrap());
    p.insert(t);
    assert!(p.active_terms().iter().any(|s| s == "contact_barrier"));
    assert!(p.active_terms().iter().any(|s| s == "contact_friction"));
    let u: Vec<f64> = (0..n)
        .map(|i| {
            if i % 3 == 2 {
                rng.random_range(-0.005..0.005)
            } else {
                rng.random_range(-0.05..0.05)
            }
        })
        .collect();
    let mut g = vec![0.0; n];
    let mut values = vec![0.0; p.pattern().nnz()];
    p.hessian(&u, &mut g, &mut values).unwrap();
    let h = dense(p.pattern(), &values);
    let step = 1e-6;
    let (mut gerr, mut herr) = (0.0f64, 0.0f64);
    for i in 0..n {
        let (mut up, mut um) = (u.clone(), u.clone());
        up[i] += step;
        um[i] -= step;
        let fd = (p.value(&up).unwrap() - p.value(&um).unwrap()) / (2.0 * step);
        gerr = gerr.max((fd - g[i]).abs());
        let (mut gp, mut gm) = (vec![0.0; n], vec![0.0; n]);
        p.gradient(&up, &mut gp).unwrap();
        p.gradient(&um, &mut gm).unwrap();
        for j in 0..n {
            herr = herr.max(((gp[j] - gm[j]) / (2.0 * step) - h[(j, i)]).abs());
        }
    }
    let gscale = g.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(gerr < 1e-5 * gscale, "gradient error {gerr:e} of {gscale:e}");
    assert!(herr < 1e-5 * h.amax(), "Hessian error {herr:e} of {:e}", h.amax());
}

#[test]
fn begin_step_rejects_intersections_and_bad_input() {
    let case = plate_over_floor(2, 0.8 * 2.0 * TH, 0.0, 15);
    let mut t = term(&case, parameters(0.0, false));
    let zero = vec![0.0; case.layout.n_dofs()];
    let err = t.begin_step(&case.state, &case.layout, DT, &zero).unwrap_err();
    assert!(
        matches!(err, ContactError::Intersection { kind: "point-triangle", gap, .. } if gap < 0.0),
        "{err}"
    );
    let case = plate_over_floor(2, 0.1, 0.0, 15);
    let mut t = term(&case, parameters(0.0, false));
    assert!(matches!(
        t.begin_step(&case.state, &case.layout, DT, &zero[1..]),
        Err(ContactError::WrongLength { what: "unknowns", .. })
    ));
    assert!(matches!(
        t.begin_step(&case.state, &case.layout, 0.0, &zero),
        Err(ContactError::InvalidParameter { name: "dt", .. })
    ));
    let mut bad = zero.clone();
    bad[4] = f64::NAN;
    assert!(matches!(
        t.begin_step(&case.state, &case.layout, DT, &bad),
        Err(ContactError::NonFinite { vertex: 1, .. })
    ));
    let mut p = ContactParameters::new(1.0, 1e-3);
    p.sweep_factor = 0.5;
    assert!(matches!(
        ContactTerm::try_new(case.surfaces.clone(), Vec::new(), p, &case.state.x),
        Err(ContactError::InvalidParameter {
            name: "sweep_factor",
            ..
        })
    ));
    assert!(matches!(
        ContactTerm::try_new(
            case.surfaces.clone(),
            Vec::new(),
            parameters(0.0, false),
            &case.state.x[..3]
        ),
        Err(ContactError::VertexOutOfRange { .. })
    ));
}

#[test]
fn a_blocked_obstacle_does_not_hold_back_the_others() {
    let mut case = plate_over_floor(2, 2.0 * TH + 0.5 * DHAT, 0.0, 16);
    // A second floor far above the plate, moving sideways: nothing is in its way.
    let mut far = floor(1.0);
    far.id = 2;
    case.obstacles.push(far);
    let mut t = term(&case, parameters(0.0, false));
    t.set_obstacle_positions(0, floor(1e-3).positions).unwrap();
    let shifted: Vec<Vector3<f64>> = floor(1.0).positions.iter().map(|p| p + Vector3::new(0.5, 0.0, 0.0)).collect();
    t.set_obstacle_positions(1, shifted).unwrap();
    let fractions = t.obstacle_motion_fractions(&case.state);
    assert!(fractions[0] > 0.0 && fractions[0] < 0.5, "{fractions:?}");
    assert_eq!(fractions[1], 1.0, "{fractions:?}");
}

#[test]
fn kinematic_obstacles_move_and_are_checked() {
    let case = plate_over_floor(2, 2.0 * TH + 0.5 * DHAT, 0.0, 16);
    let mut t = term(&case, parameters(0.0, false));
    // Raising the floor by 1 mm would push it through the plate.
    let raised: Vec<Vector3<f64>> = floor(1e-3).positions;
    t.set_obstacle_positions(0, raised.clone()).unwrap();
    let alpha = t.obstacle_motion_fractions(&case.state)[0];
    assert!(alpha > 0.0 && alpha < 0.5, "{alpha}");
    // Lowering it is safe, and commit makes the end positions the new start.
    let lowered = floor(-1e-3).positions;
    t.set_obstacle_positions(0, lowered.clone()).unwrap();
    assert_eq!(t.obstacle_motion_fractions(&case.state), vec![1.0]);
    let mut state = case.state.clone();
    t.commit(&mut state, &case.layout, &vec![0.0; case.layout.n_dofs()], DT);
    assert_eq!(t.obstacle_positions(0), lowered.as_slice());
    assert!(matches!(
        t.set_obstacle_positions(1, raised.clone()),
        Err(ContactError::NoSuchObstacle { obstacle: 1, .. })
    ));
    assert!(matches!(
        t.set_obstacle_positions(0, raised[..2].to_vec()),
        Err(ContactError::WrongLength { .. })
    ));
}
