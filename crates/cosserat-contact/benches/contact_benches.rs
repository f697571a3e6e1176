//! Benchmarks of the contact layer: per-pair kernels (distance jets, pair energy with derivatives),
//! per-step costs of the term (candidate search with lagged friction, Hessian assembly, CCD) for two
//! stacked plates in self-contact at three sizes, and the cost of one contact step against the number
//! of triangles for an icosphere shell (self-contact on) landing on a floor, 320 to 20 480 triangles.

// `criterion_group!` generates undocumented items.
#![allow(missing_docs)]

use cosserat_assembly::term::{Evaluation, NodeRotations, PotentialTerm};
use cosserat_assembly::{DofLayout, Parallelism, SparsityPattern, SystemState};
use cosserat_contact::barrier::Barrier;
use cosserat_contact::distance::{EdgeEdgeFeature, PointTriangleFeature, edge_edge_jet, point_triangle_jet};
use cosserat_contact::mesh::Obstacle;
use cosserat_contact::{ContactParameters, ContactSurface, ContactTerm};
use cosserat_fem::mesh::procedural::icosphere;
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use nalgebra::{Rotation3, Vector3};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::hint::black_box;
use std::time::Duration;

const TH: f64 = 5e-4;
const DHAT: f64 = 1e-3;
const DT: f64 = 0.01;

fn grid(n: usize, offset: usize) -> Vec<[usize; 3]> {
    let idx = |i: usize, j: usize| offset + i * (n + 1) + j;
    (0..n)
        .flat_map(|i| {
            (0..n).flat_map(move |j| {
                [
                    [idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)],
                    [idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)],
                ]
            })
        })
        .collect()
}

/// Two `n × n` plates of side 0.1 m, the upper one turned by 0.3 rad, 0.5 mm into each other's
/// barrier (gap 0.5 mm at δ = 1 mm), with random velocities.
struct Scene {
    state: SystemState,
    layout: DofLayout,
    term: ContactTerm,
    u: Vec<f64>,
}

fn scene(n: usize) -> Scene {
    let mut rng = ChaCha8Rng::seed_from_u64(n as u64);
    let h = 0.1 / n as f64;
    let rot = Rotation3::from_axis_angle(&Vector3::z_axis(), 0.3);
    let centre = Vector3::new(0.05, 0.05, 0.0);
    let mut x = Vec::new();
    for level in 0..2 {
        for i in 0..=n {
            for j in 0..=n {
                let p = Vector3::new(i as f64 * h, j as f64 * h, rng.random_range(-1e-5..1e-5));
                x.push(if level == 0 {
                    p
                } else {
                    centre + rot * (p - centre) + Vector3::new(0.0, 0.0, 2.0 * TH + 0.5 * DHAT)
                });
            }
        }
    }
    let half = x.len() / 2;
    let surfaces = vec![
        ContactSurface {
            id: 0,
            triangles: grid(n, 0),
            thickness: TH,
        },
        ContactSurface {
            id: 0,
            triangles: grid(n, half),
            thickness: TH,
        },
    ];
    let mut params = ContactParameters::new(100.0, DHAT);
    params.friction.set(0, 0, 0.5).unwrap();
    params.stick_velocity = 0.05;
    let term = ContactTerm::try_new(surfaces, Vec::new(), params, &x).unwrap();
    let layout = DofLayout {
        n_disp_nodes: x.len(),
        n_rot_nodes: 0,
    };
    let u = (0..layout.n_dofs())
        .map(|i| {
            if i % 3 == 2 {
                rng.random_range(-0.005..0.005)
            } else {
                rng.random_range(-0.05..0.05)
            }
        })
        .collect();
    Scene {
        state: SystemState::at_rest(x, 0, 0),
        layout,
        term,
        u,
    }
}

fn kernels(c: &mut Criterion) {
    let mut g = c.benchmark_group("pair_kernel");
    let x = [
        Vector3::new(0.2, 0.3, 0.01),
        Vector3::new(0.0, 0.0, 0.0),
        Vector3::new(1.0, 0.1, 0.0),
        Vector3::new(0.1, 1.0, 0.02),
    ];
    g.bench_function("point_plane_jet", |b| {
        b.iter(|| point_triangle_jet(black_box(&x), PointTriangleFeature::Face))
    });
    g.bench_function("point_line_jet", |b| {
        b.iter(|| point_triangle_jet(black_box(&x), PointTriangleFeature::Edge(0)))
    });
    g.bench_function("line_line_jet", |b| {
        b.iter(|| edge_edge_jet(black_box(&x), EdgeEdgeFeature::Interior))
    });
    let s = scene(4);
    let mut s = s;
    let zero = vec![0.0; s.layout.n_dofs()];
    s.term.begin_step(&s.state, &s.layout, DT, &zero).unwrap();
    let barrier = Barrier::try_new(100.0, DHAT).unwrap();
    let positions = s.term.mesh().positions(|i| s.state.x[i], |_, _| Vector3::zeros());
    let pair = *s
        .term
        .pairs()
        .iter()
        .find(|p| p.gap(&p.vertices.map(|v| positions[v as usize])) < DHAT)
        .unwrap();
    let px = pair.vertices.map(|v| positions[v as usize]);
    g.bench_function("pair_energy", |b| b.iter(|| pair.energy(black_box(&px), &barrier)));
    g.bench_function("pair_energy_jet", |b| {
        b.iter(|| pair.energy_jet(black_box(&px), &barrier))
    });
    g.finish();
}

fn step(c: &mut Criterion) {
    let mut g = c.benchmark_group("contact_step");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    for n in [8, 16, 32] {
        let mut s = scene(n);
        let n_tris = 4 * n * n;
        g.throughput(Throughput::Elements(n_tris as u64));
        let zero = vec![0.0; s.layout.n_dofs()];
        g.bench_with_input(BenchmarkId::new("begin_step", n_tris), &n, |b, _| {
            b.iter(|| s.term.begin_step(&s.state, &s.layout, DT, black_box(&s.u)).unwrap())
        });
        s.term.begin_step(&s.state, &s.layout, DT, &zero).unwrap();
        let groups = s.term.coupling_groups();
        let pattern = SparsityPattern::from_groups(s.layout.n_blocks(), groups.iter().map(|g| g.as_slice()));
        let rotations = NodeRotations::Matrices(Vec::new());
        let eval = Evaluation {
            state: &s.state,
            layout: &s.layout,
            u: &s.u,
            dt: DT,
            rotations: &rotations,
            parallelism: Parallelism::Rayon,
        };
        let mut grad = vec![0.0; s.layout.n_dofs()];
        let mut values = vec![0.0; pattern.nnz()];
        // Value and Hessian report throughput per candidate pair.
        g.throughput(Throughput::Elements(s.term.pairs().len() as u64));
        g.bench_with_input(BenchmarkId::new("value", n_tris), &n, |b, _| {
            b.iter(|| s.term.value(&eval).unwrap())
        });
        g.bench_with_input(BenchmarkId::new("hessian", n_tris), &n, |b, _| {
            b.iter(|| s.term.hessian(&eval, &mut grad, &pattern, &mut values).unwrap())
        });
        g.throughput(Throughput::Elements(n_tris as u64));
        let du: Vec<f64> = s.u.iter().map(|v| -v).collect();
        g.bench_with_input(BenchmarkId::new("max_step_fraction", n_tris), &n, |b, _| {
            b.iter(|| s.term.max_step_fraction(&s.state, &s.layout, &s.u, black_box(&du), DT))
        });
    }
    g.finish();
}

/// Contact thickness of the icosphere scene \[m\] (the Bunny's).
const SPHERE_TH: f64 = 5e-5;
/// Barrier width of the icosphere scene \[m\] (the Bunny's).
const SPHERE_DHAT: f64 = 1e-4;

/// An icosphere shell of radius 0.1 m (subdivision `level`, self-contact on, the Bunny's thickness and
/// barrier width) whose lowest vertex is half the barrier width into the barrier of a 1 m floor square,
/// falling at 2 mm/s with seeded random velocity perturbations of up to 0.5 mm/s (the end of the step
/// stays feasible). The contact patch keeps its physical size while the mesh is refined, and the reach
/// stays below a tenth of the edge length (as in the experiments), so the cost per triangle shows how
/// the broad phase and CCD scale rather than how crowded the neighbourhoods get.
fn sphere_on_floor(level: usize) -> Scene {
    let mut rng = ChaCha8Rng::seed_from_u64(level as u64);
    let sphere = icosphere(0.1, level).unwrap();
    let x = sphere.mesh.nodes.clone();
    let bottom = x.iter().map(|p| p.z).fold(f64::INFINITY, f64::min);
    let floor_z = bottom - 2.0 * SPHERE_TH - 0.5 * SPHERE_DHAT;
    let floor = Obstacle {
        id: 1,
        positions: vec![
            Vector3::new(-0.5, -0.5, floor_z),
            Vector3::new(0.5, -0.5, floor_z),
            Vector3::new(0.5, 0.5, floor_z),
            Vector3::new(-0.5, 0.5, floor_z),
        ],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        thickness: SPHERE_TH,
    };
    let surfaces = vec![ContactSurface {
        id: 0,
        triangles: sphere.mesh.elements.clone(),
        thickness: SPHERE_TH,
    }];
    let mut params = ContactParameters::new(100.0, SPHERE_DHAT);
    params.friction.set(0, 1, 0.5).unwrap();
    params.friction.set(0, 0, 0.5).unwrap();
    params.stick_velocity = 0.05;
    let term = ContactTerm::try_new(surfaces, vec![floor], params, &x).unwrap();
    let layout = DofLayout {
        n_disp_nodes: x.len(),
        n_rot_nodes: 0,
    };
    let u = (0..layout.n_dofs())
        .map(|i| rng.random_range(-0.0005..0.0005) - if i % 3 == 2 { 0.002 } else { 0.0 })
        .collect();
    Scene {
        state: SystemState::at_rest(x, 0, 0),
        layout,
        term,
        u,
    }
}

/// One contact step as the time stepper runs it with two Newton iterations: `begin_step`, two
/// Hessian evaluations (with gradients) each followed by the CCD step limit, two line-search values,
/// and the coverage check of the converged state. Returns the step's CCD fraction.
fn contact_step(s: &mut Scene, pattern: &mut SparsityPattern, values: &mut Vec<f64>, grad: &mut [f64]) -> f64 {
    s.term.begin_step(&s.state, &s.layout, DT, &s.u).unwrap();
    if !s.term.fits_pattern(pattern) {
        let groups = s.term.coupling_groups();
        *pattern = SparsityPattern::from_groups(s.layout.n_blocks(), groups.iter().map(|g| g.as_slice()));
        values.resize(pattern.nnz(), 0.0);
    }
    let rotations = NodeRotations::Matrices(Vec::new());
    let eval = Evaluation {
        state: &s.state,
        layout: &s.layout,
        u: &s.u,
        dt: DT,
        rotations: &rotations,
        parallelism: Parallelism::Rayon,
    };
    let du: Vec<f64> = s.u.iter().map(|v| 0.1 * v).collect();
    let mut alpha = 1.0_f64;
    for _ in 0..2 {
        grad.fill(0.0);
        values.fill(0.0);
        s.term.hessian(&eval, grad, pattern, values).unwrap();
        alpha = alpha.min(s.term.max_step_fraction(&s.state, &s.layout, &s.u, &du, DT));
        black_box(s.term.value(&eval).unwrap());
    }
    black_box(s.term.coverage(&s.state, &s.layout, &s.u, DT));
    alpha
}

fn refinement(c: &mut Criterion) {
    let mut g = c.benchmark_group("sphere_on_floor");
    g.sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    for level in 2..=5 {
        let mut s = sphere_on_floor(level);
        let n_tris = s.term.mesh().triangles().len() - 2;
        g.throughput(Throughput::Elements(n_tris as u64));
        let zero = vec![0.0; s.layout.n_dofs()];
        s.term.begin_step(&s.state, &s.layout, DT, &zero).unwrap();
        let groups = s.term.coupling_groups();
        let mut pattern = SparsityPattern::from_groups(s.layout.n_blocks(), groups.iter().map(|g| g.as_slice()));
        let mut values = vec![0.0; pattern.nnz()];
        let mut grad = vec![0.0; s.layout.n_dofs()];
        g.bench_with_input(BenchmarkId::new("step", n_tris), &level, |b, _| {
            b.iter(|| contact_step(&mut s, &mut pattern, &mut values, &mut grad))
        });
        g.bench_with_input(BenchmarkId::new("begin_step", n_tris), &level, |b, _| {
            b.iter(|| s.term.begin_step(&s.state, &s.layout, DT, black_box(&s.u)).unwrap())
        });
        let du: Vec<f64> = s.u.iter().map(|v| 0.1 * v).collect();
        g.bench_with_input(BenchmarkId::new("max_step_fraction", n_tris), &level, |b, _| {
            b.iter(|| s.term.max_step_fraction(&s.state, &s.layout, &s.u, black_box(&du), DT))
        });
        g.bench_with_input(BenchmarkId::new("coverage", n_tris), &level, |b, _| {
            b.iter(|| s.term.coverage(&s.state, &s.layout, black_box(&s.u), DT))
        });
    }
    g.finish();
}

criterion_group!(benches, kernels, step, refinement);
criterion_main!(benches);
