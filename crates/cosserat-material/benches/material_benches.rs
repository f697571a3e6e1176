//! Kernel benchmarks: energy, gradient and exact Hessian of one quadrature point, against the
//! whole-point second-order dual oracle (see docs/performance.md).

// `criterion_group!` generates undocumented items.
#![allow(missing_docs)]

use cosserat_geometry::rotation::{RotationJet, exp_map, quaternion_from_matrix, rotation_matrix};
use cosserat_material::element::{ElementDerivatives, accumulate_upper, f_hat, point_omega};
use cosserat_material::kernel::{PointInput, PointShape, point_gradient, point_hessian, point_value};
use cosserat_material::oracle::{PointContext, local_energy};
use cosserat_material::strain_space::{DensityMatrix, local_geometry, strain_hessian, strain_offset};
use cosserat_material::volume::{volume_density, volume_hessian};
use cosserat_material::{AxlVariant, MaterialParameters, ModelOptions, ShellModel, TermSet};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use nalgebra::{Matrix3, Quaternion, SMatrix, SVector, Vector3};
use num_dual::Dual2SVec64;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::hint::black_box;
use std::time::Duration;

struct Input<const NU: usize, const NR: usize> {
    shape: PointShape<NU, NR>,
    q_point: Quaternion<f64>,
    q_nodes: [Quaternion<f64>; NR],
    x: [Vector3<f64>; NU],
    omega: [Vector3<f64>; NR],
}

fn inputs<const NU: usize, const NR: usize>(n: usize) -> Vec<Input<NU, NR>> {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut v = |s: f64| Vector3::from_fn(|_, _| rng.random_range(-s..s));
    (0..n)
        .map(|_| {
            let frame = exp_map(&v(2.0));
            let mut m = SVector::<f64, NR>::from_fn(|i, _| 1.0 + 0.1 * i as f64);
            m /= m.sum();
            Input {
                shape: PointShape {
                    disp_grad: SMatrix::from_fn(|i, j| ((i + 2 * j) as f64 * 0.37).sin() * 40.0),
                    rot_values: m,
                    rot_grad: SMatrix::from_fn(|i, j| ((3 * i + j) as f64 * 0.71).cos() * 40.0),
                    frame,
                    weight: 1e-4,
                },
                q_point: quaternion_from_matrix(&exp_map(&v(1.0))),
                q_nodes: std::array::from_fn(|_| quaternion_from_matrix(&exp_map(&v(1.0)))),
                x: std::array::from_fn(|_| v(0.05)),
                omega: std::array::from_fn(|_| v(2.0)),
            }
        })
        .collect()
}

fn bench_point(c: &mut Criterion) {
    let material = MaterialParameters::new(2e-3, 70e9, 0.35, 2700.0, 2e-6);
    let moduli = material.moduli().unwrap();
    let terms = TermSet::select(&ModelOptions::new(ShellModel::Plate), &moduli, false).unwrap();
    let d = DensityMatrix::new(strain_hessian(
        &terms,
        &local_geometry(&Matrix3::identity(), &Matrix3::zeros()),
        &moduli,
    ));
    let dt = 0.01;
    let data = inputs::<6, 3>(64);
    let offset = strain_offset(&Matrix3::identity(), None, None);
    let mut group = c.benchmark_group("quadrature_point_tri6_tri3_plate");
    group
        .sample_size(30)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    group.throughput(Throughput::Elements(data.len() as u64));
    group.bench_function(BenchmarkId::new("energy", "f64"), |b| {
        b.iter(|| {
            let mut s = 0.0;
            for p in &data {
                let r = rotation_matrix(&cosserat_geometry::rotation::quaternion_update(
                    &p.q_point,
                    &point_omega(&p.shape, &p.omega),
                    dt,
                ));
                let rn: [Matrix3<f64>; 3] = std::array::from_fn(|k| {
                    rotation_matrix(&cosserat_geometry::rotation::quaternion_update(
                        &p.q_nodes[k],
                        &p.omega[k],
                        dt,
                    ))
                });
                s += point_value(
                    &p.shape,
                    &f_hat(&p.shape, &p.x),
                    &r,
                    [&rn[0], &rn[1], &rn[2]],
                    &offset,
                    &d,
                    AxlVariant::SkewPart,
                );
            }
            black_box(s)
        })
    });
    group.bench_function(BenchmarkId::new("rotation_jet", "dual2x3"), |b| {
        b.iter(|| {
            for p in &data {
                black_box(RotationJet::of_update(black_box(&p.q_point), &p.omega[0], dt));
            }
        })
    });
    let jets = |p: &Input<6, 3>| {
        (
            RotationJet::of_update(&p.q_point, &point_omega(&p.shape, &p.omega), dt),
            std::array::from_fn::<RotationJet, 3, _>(|k| RotationJet::of_update(&p.q_nodes[k], &p.omega[k], dt)),
        )
    };
    let prepared: Vec<_> = data.iter().map(jets).collect();
    group.bench_function(BenchmarkId::new("gradient", "chained"), |b| {
        b.iter(|| {
            for (p, (pj, nj)) in data.iter().zip(&prepared) {
                let input = PointInput {
                    f_hat: f_hat(&p.shape, &p.x),
                    point_jet: pj,
                    node_jets: [&nj[0], &nj[1], &nj[2]],
                    offset: &offset,
                };
                black_box(point_gradient::<6, 3, 15>(&p.shape, &input, &d, AxlVariant::SkewPart));
            }
        })
    });
    group.bench_function(BenchmarkId::new("hessian", "chained"), |b| {
        b.iter(|| {
            for (p, (pj, nj)) in data.iter().zip(&prepared) {
                let input = PointInput {
                    f_hat: f_hat(&p.shape, &p.x),
                    point_jet: pj,
                    node_jets: [&nj[0], &nj[1], &nj[2]],
                    offset: &offset,
                };
                black_box(point_hessian::<6, 3, 15>(&p.shape, &input, &d, AxlVariant::SkewPart));
            }
        })
    });
    group.bench_function(
        BenchmarkId::new("hessian", "chained_with_point_jet_and_element_map"),
        |b| {
            // As the assembly does it: three points into one element, whose lower triangle is filled
            // once.
            let mut out = ElementDerivatives::<27>::zeros();
            b.iter(|| {
                for (points, jets) in data.chunks(3).zip(prepared.chunks(3)) {
                    out.value = 0.0;
                    out.gradient.fill(0.0);
                    out.hessian.as_mut_slice().fill(0.0);
                    for (p, (_, nj)) in points.iter().zip(jets) {
                        let pj = RotationJet::of_update(&p.q_point, &point_omega(&p.shape, &p.omega), dt);
                        let input = PointInput {
                            f_hat: f_hat(&p.shape, &p.x),
                            point_jet: &pj,
                            node_jets: [&nj[0], &nj[1], &nj[2]],
                            offset: &offset,
                        };
                        let local = point_hessian::<6, 3, 15>(&p.shape, &input, &d, AxlVariant::SkewPart);
                        accumulate_upper(&p.shape, &local, dt, p.shape.weight, &mut out);
                    }
                    out.fill_lower_from_upper();
                    black_box(&out);
                }
            })
        },
    );
    group.finish();

    let mut oracle = c.benchmark_group("quadrature_point_tri6_tri3_plate_oracle");
    oracle
        .sample_size(10)
        .warm_up_time(Duration::from_millis(200))
        .measurement_time(Duration::from_secs(2));
    let few = &data[..4];
    oracle.throughput(Throughput::Elements(few.len() as u64));
    let geom = local_geometry(&Matrix3::identity(), &Matrix3::zeros());
    oracle.bench_function(BenchmarkId::new("hessian", "whole_point_dual2x15"), |b| {
        b.iter(|| {
            for p in few {
                let ctx = PointContext {
                    shape: &p.shape,
                    point_quaternion: p.q_point,
                    node_quaternions: p.q_nodes,
                    dt,
                    offset: &offset,
                    geometry: &geom,
                    terms: &terms,
                    moduli: &moduli,
                    axl: AxlVariant::SkewPart,
                };
                let f = f_hat(&p.shape, &p.x);
                let x = SVector::<f64, 15>::from_fn(|i, _| {
                    if i < 6 {
                        f[i / 3][i % 3]
                    } else {
                        p.omega[(i - 6) / 3][(i - 6) % 3]
                    }
                });
                black_box(num_dual::hessian(
                    |x: SVector<Dual2SVec64<15>, 15>| {
                        let fh = [Vector3::new(x[0], x[1], x[2]), Vector3::new(x[3], x[4], x[5])];
                        let om: [Vector3<Dual2SVec64<15>>; 3] =
                            std::array::from_fn(|k| Vector3::new(x[6 + 3 * k], x[7 + 3 * k], x[8 + 3 * k]));
                        local_energy(&ctx, &fh, &om)
                    },
                    &x,
                ));
            }
        })
    });
    oracle.finish();
}

/// The nonlinear volume term per quadrature point: the closed form against its num-dual oracle.
fn bench_volume(c: &mut Criterion) {
    let moduli = MaterialParameters::new(2e-3, 70e9, 0.35, 2700.0, 2e-6).moduli().unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let mut v = || Vector3::from_fn(|_, _| rng.random_range(-0.2..0.2));
    let points: Vec<[Vector3<f64>; 2]> = (0..64).map(|_| [Vector3::x() + v(), Vector3::y() + v()]).collect();
    let mut group = c.benchmark_group("volume_term_point");
    group.throughput(Throughput::Elements(points.len() as u64));
    group.bench_function(BenchmarkId::new("hessian", "closed_form"), |b| {
        b.iter(|| {
            for f in &points {
                black_box(volume_hessian(black_box(f), &moduli));
            }
        })
    });
    group.bench_function(BenchmarkId::new("hessian", "dual2x6"), |b| {
        b.iter(|| {
            for f in &points {
                let x = SVector::<f64, 6>::from_fn(|i, _| f[i / 3][i % 3]);
                black_box(num_dual::hessian(
                    |x: SVector<Dual2SVec64<6>, 6>| {
                        volume_density(
                            &[Vector3::new(x[0], x[1], x[2]), Vector3::new(x[3], x[4], x[5])],
                            &moduli,
                        )
                    },
                    &x,
                ));
            }
        })
    });
    group.finish();
}

criterion_group!(benches, bench_point, bench_volume);
criterion_main!(benches);
