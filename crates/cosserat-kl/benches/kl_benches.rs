//! Cost per stencil of the Kirchhoff–Love energy: the f64 energy, the gradient, the chained exact Hessian
//! and the 18-direction dual oracle, side by side (both materials), plus a whole-term Hessian assembly.

// `criterion_group!` generates undocumented items.
#![allow(missing_docs)]

use cosserat_assembly::SystemOptions;
use cosserat_fem::mesh::procedural;
use cosserat_kl::energy::{stencil_gradient, stencil_hessian_oracle};
use cosserat_kl::{
    HyperelasticModel, KlMaterial, KlShell, StencilRest, ThicknessRule, build_kl_system, build_stencils,
    stencil_energy, stencil_hessian,
};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use nalgebra::{SVector, Vector3};
use std::hint::black_box;
use std::time::Duration;

/// 64 interior stencils of a bent sphere patch: rest data and a perturbed current state each.
fn stencils() -> Vec<(SVector<f64, 18>, StencilRest)> {
    let mesh = procedural::icosphere(1.0, 3).unwrap().mesh;
    let all = build_stencils(&mesh).unwrap();
    all.iter()
        .take(64)
        .enumerate()
        .map(|(f, s)| {
            let rest = SVector::<f64, 18>::from_fn(|i, _| mesh.nodes[s.vertices()[i / 3].unwrap()][i % 3]);
            let r = StencilRest::try_new(f, &rest, s.present(), 0.01, &ThicknessRule::default()).unwrap();
            let x = rest + SVector::<f64, 18>::from_fn(|i, _| 0.01 * ((i * 7 + f) as f64).sin());
            (x, r)
        })
        .collect()
}

fn bench_stencil(c: &mut Criterion) {
    let data = stencils();
    let mut group = c.benchmark_group("kl_stencil");
    group
        .sample_size(20)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    group.throughput(Throughput::Elements(data.len() as u64));
    for model in [HyperelasticModel::StVenantKirchhoff, HyperelasticModel::NeoHookean] {
        let m = KlMaterial::new(model, 1e6, 0.3).constants().unwrap();
        group.bench_function(BenchmarkId::new("energy_f64", model.name()), |b| {
            b.iter(|| data.iter().map(|(x, r)| stencil_energy(black_box(x), r, &m)).sum::<f64>())
        });
        group.bench_function(BenchmarkId::new("gradient", model.name()), |b| {
            b.iter(|| {
                data.iter()
                    .map(|(x, r)| stencil_gradient(black_box(x), r, &m).1[0])
                    .sum::<f64>()
            })
        });
        group.bench_function(BenchmarkId::new("hessian_chained", model.name()), |b| {
            b.iter(|| {
                data.iter()
                    .map(|(x, r)| stencil_hessian(black_box(x), r, &m).hessian[(0, 0)])
                    .sum::<f64>()
            })
        });
        group.bench_function(BenchmarkId::new("hessian_oracle_dual18", model.name()), |b| {
            b.iter(|| {
                data.iter()
                    .map(|(x, r)| stencil_hessian_oracle(black_box(x), r, &m).hessian[(0, 0)])
                    .sum::<f64>()
            })
        });
    }
    group.finish();
}

fn bench_assembly(c: &mut Criterion) {
    let mesh = procedural::rectangle_grid(1.0, 1.0, 32, 32).unwrap().mesh;
    let shell = KlShell::new(KlMaterial::new(HyperelasticModel::NeoHookean, 1e6, 0.3), 0.01, 1000.0);
    let options = SystemOptions {
        gravity: Vector3::zeros(),
        dynamic: true,
    };
    let mut sys = build_kl_system(&mesh, &shell, &options).unwrap();
    let n = sys.potential.n_dofs();
    let u: Vec<f64> = (0..n).map(|i| 0.1 * (i as f64 * 0.37).sin()).collect();
    let mut g = vec![0.0; n];
    let mut h = vec![0.0; sys.potential.pattern().nnz()];
    let mut group = c.benchmark_group("kl_assembly");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(5));
    group.throughput(Throughput::Elements(mesh.n_elements() as u64));
    group.bench_function(BenchmarkId::new("hessian", mesh.n_elements()), |b| {
        b.iter(|| sys.potential.hessian(black_box(&u), &mut g, &mut h).unwrap())
    });
    group.finish();
}

criterion_group!(benches, bench_stencil, bench_assembly);
criterion_main!(benches);
