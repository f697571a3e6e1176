//! Assembly benchmarks: energy, gradient and Hessian of the whole incremental potential per element,
//! for each element pair and model, on a bent state of a plate (so every term is active).

// `criterion_group!` generates undocumented items.
#![allow(missing_docs)]

use cosserat_assembly::{ElementPair, ShellInput, ShellMesh, System, SystemOptions, build_system};
use cosserat_fem::QuadratureRule;
use cosserat_fem::mesh::procedural;
use cosserat_geometry::rotation::{exp_map, quaternion_from_matrix};
use cosserat_material::rest::RestOptions;
use cosserat_material::{MaterialParameters, ModelOptions, ShellModel, StrainInterpolation};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use nalgebra::Vector3;
use std::cell::RefCell;
use std::hint::black_box;
use std::time::Duration;

fn system(
    pair: ElementPair,
    model: ShellModel,
    interpolation: StrainInterpolation,
    quadrature: Option<QuadratureRule>,
    nx: usize,
    ny: usize,
) -> System {
    // A quarter cylinder for the shell model (every point curved), a flat strip for the plate.
    let generated = match model {
        ShellModel::Plate => procedural::rectangle_grid(0.1, 0.1 * ny as f64 / nx as f64, nx, ny).unwrap(),
        ShellModel::Shell => procedural::cylinder(0.05, 0.1, nx, ny).unwrap(),
    };
    let mut rest = RestOptions::new(ModelOptions::new(model));
    rest.interpolation = interpolation;
    let input = ShellInput {
        name: "bench".into(),
        mesh: ShellMesh::from_tri3(generated.mesh.clone(), pair, |n| generated.place(n)),
        pair,
        material: MaterialParameters::new(2e-3, 70e9, 0.35, 2700.0, 2e-6),
        rest,
        quadrature,
        damping: 0.0,
        angular_inertia_density: 0.0,
    };
    let mut sys = build_system(
        &[input],
        &SystemOptions {
            gravity: Vector3::zeros(),
            dynamic: true,
        },
    )
    .unwrap();
    let st = &mut sys.potential.parts.state;
    for (k, q) in st.q.iter_mut().enumerate() {
        *q = quaternion_from_matrix(&exp_map(&Vector3::new(0.1 * (k as f64).sin(), 0.2, 0.05)));
    }
    sys
}

/// Quads along and across the bench's meshes (two triangles each).
const NX: usize = 40;
const NY: usize = 8;

/// A system with a state to evaluate at and the buffers its derivatives are written to.
struct Fixture {
    sys: System,
    u: Vec<f64>,
    g: Vec<f64>,
    values: Vec<f64>,
}

impl Fixture {
    fn new(sys: System) -> Self {
        let u: Vec<f64> = (0..sys.potential.n_dofs()).map(|i| 0.01 * ((i as f64) * 0.37).sin()).collect();
        Self {
            g: vec![0.0; u.len()],
            values: vec![0.0; sys.potential.pattern().nnz()],
            u,
            sys,
        }
    }
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("assembly_per_element");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(2));
    // The paper's discretisation for every pair, the stabilised strain projection and the assumed
    // strains (MITC6-style and Regge) for the paper's pair, and Regge with stabilised shear for quadratic
    // rotations, on its default 3-point rule and on the pair's six-point rule (their cost relative to
    // the paper's is reported in docs/model-notes.md).
    let paper = StrainInterpolation::Paper;
    let six_points = QuadratureRule::for_degree(4);
    for (pair, interpolation, quadrature, label) in [
        (ElementPair::Tri3Tri3, paper, None, "tri3_tri3"),
        (ElementPair::Tri6Tri3, paper, None, "tri6_tri3"),
        (ElementPair::Tri6Tri6, paper, None, "tri6_tri6"),
        (
            ElementPair::Tri6Tri3,
            StrainInterpolation::Stabilized,
            None,
            "tri6_tri3_stabilized",
        ),
        (
            ElementPair::Tri6Tri3,
            StrainInterpolation::Assumed,
            None,
            "tri6_tri3_assumed",
        ),
        (
            ElementPair::Tri6Tri3,
            StrainInterpolation::Regge,
            None,
            "tri6_tri3_regge",
        ),
        (
            ElementPair::Tri6Tri3,
            StrainInterpolation::ReggeStabilized,
            None,
            "tri6_tri3_regge_stabilized",
        ),
        (
            ElementPair::Tri6Tri6,
            StrainInterpolation::ReggeStabilized,
            None,
            "tri6_tri6_regge_stabilized",
        ),
        (
            ElementPair::Tri6Tri6,
            StrainInterpolation::ReggeStabilized,
            six_points,
            "tri6_tri6_regge_stabilized_six_points",
        ),
    ] {
        for (model, m) in [(ShellModel::Plate, "plate"), (ShellModel::Shell, "shell")] {
            // Built on first use, so that a filtered run (a profiler's) builds only what it measures.
            let fixture = RefCell::new(None::<Fixture>);
            let with_fixture = |f: &mut dyn FnMut(&mut Fixture)| {
                let mut slot = fixture.borrow_mut();
                f(slot.get_or_insert_with(|| Fixture::new(system(pair, model, interpolation, quadrature, NX, NY))));
            };
            // The throughput is known without the system: two Tri3 triangles per quad either way.
            group.throughput(Throughput::Elements((2 * NX * NY) as u64));
            let id = format!("{label}_{m}");
            group.bench_function(BenchmarkId::new("energy", &id), |b| {
                with_fixture(&mut |x| b.iter(|| black_box(x.sys.potential.value(&x.u).unwrap())));
            });
            group.bench_function(BenchmarkId::new("gradient", &id), |b| {
                with_fixture(&mut |x| b.iter(|| black_box(x.sys.potential.gradient(&x.u, &mut x.g).unwrap())));
            });
            group.bench_function(BenchmarkId::new("hessian", &id), |b| {
                with_fixture(&mut |x| {
                    b.iter(|| black_box(x.sys.potential.hessian(&x.u, &mut x.g, &mut x.values).unwrap()))
                });
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
