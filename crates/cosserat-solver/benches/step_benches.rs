//! Benchmarks on the real shell system of the paper's "Plate under load" (0.1 m × 0.01 m aluminium
//! strip, clamped at one end, 50 N ramped on the other, dt = 10 ms): the Hessian assembly, the
//! symbolic analysis and the numerical factorisation of its Hessian, and one full backward-Euler time
//! step (assembly, factorisations, line search, commit), for Tri3/Tri3 and Tri6/Tri3 at three sizes.
//!
//! Each case is first advanced to `t = 0.5 s` (half the load, visibly bent), so the Hessian is that of
//! a deformed state; the time-step bench restores that state before every step, so every sample
//! solves the same step. Run with `cargo bench -p cosserat-solver --bench step_benches` (add
//! `--profile perf` for the tuned profile); `cargo xtask bench-table` gives the per-step figures of
//! whole runs next to the reference's.

use std::hint::black_box;
use std::time::Duration;

use cosserat_assembly::{ElementPair, IncrementalPotential};
use cosserat_solver::{LinearSolverSettings, SparseSolver, TimeStepSettings, TimeStepper};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_main};
use nalgebra::Vector3;

#[path = "../examples/common/plate.rs"]
mod plate;

/// Time step of the scene \[s\].
const DT: f64 = 0.01;
/// Steps taken before measuring (half of the 1 s load ramp).
const WARM_STEPS: usize = 50;
/// Strip widths in elements (`nx = 10 ny`).
const SIZES: [usize; 3] = [2, 4, 8];
const PAIRS: [(&str, ElementPair); 2] = [("tri3", ElementPair::Tri3Tri3), ("tri6", ElementPair::Tri6Tri3)];

/// The plate under load, advanced to `t = 0.5 s`, with its stepper and tip nodes.
struct PlateCase {
    potential: IncrementalPotential,
    stepper: TimeStepper,
    tip: Vec<usize>,
}

impl PlateCase {
    fn new(pair: ElementPair, ny: usize) -> Self {
        let (sys, tip) = plate::clamped_plate(10 * ny, ny, pair, DT);
        let mut potential = sys.potential;
        let mut stepper = TimeStepper::new(&potential, TimeStepSettings::fixed(DT)).expect("valid settings");
        for _ in 0..WARM_STEPS {
            stepper
                .step(&mut potential, &mut |p, t, _| apply_load(p, &tip, t))
                .expect("the plate converges");
        }
        Self {
            potential,
            stepper,
            tip,
        }
    }

    /// The Hessian's upper-triangle values at the current state (zero step increment).
    fn hessian_values(&mut self) -> Vec<f64> {
        let n = self.potential.n_dofs();
        let mut grad = vec![0.0; n];
        let mut values = vec![0.0; self.potential.pattern().nnz()];
        self.potential
            .hessian(&vec![0.0; n], &mut grad, &mut values)
            .expect("finite Hessian");
        values
    }
}

/// The tip load of the scene: 50 N in +z ramped over the first second, shared by the tip nodes.
fn apply_load(potential: &mut IncrementalPotential, tip: &[usize], t: f64) {
    let f = 50.0 * t.clamp(0.0, 1.0) / tip.len() as f64;
    for &i in tip {
        potential.parts.loads.forces[i] = Vector3::new(0.0, 0.0, f);
    }
}

fn configure(group: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>, seconds: u64) {
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(seconds));
}

/// Hessian assembly (kernels and scatter, all elements, energy and gradient included).
fn assembly(c: &mut Criterion, cases: &mut [(String, usize, PlateCase)]) {
    let mut group = c.benchmark_group("plate_hessian_assembly");
    configure(&mut group, 3);
    for (name, ny, case) in cases.iter_mut() {
        let n = case.potential.n_dofs();
        group.throughput(Throughput::Elements(n as u64));
        let mut grad = vec![0.0; n];
        let mut values = vec![0.0; case.potential.pattern().nnz()];
        let u = vec![0.0; n];
        group.bench_function(BenchmarkId::new(name.as_str(), format!("ny{ny}_{n}dofs")), |b| {
            b.iter(|| case.potential.hessian(black_box(&u), &mut grad, &mut values).unwrap());
        });
    }
    group.finish();
}

/// Symbolic analysis (AMD ordering, elimination tree, supernodes) and numerical `L B Lᵀ`
/// factorisation of the plate's Hessian, with the default solver settings.
fn factorisation(c: &mut Criterion, cases: &mut [(String, usize, PlateCase)]) {
    let mut symbolic = c.benchmark_group("plate_symbolic");
    configure(&mut symbolic, 3);
    for (name, ny, case) in cases.iter() {
        let pattern = case.potential.pattern().symbolic();
        symbolic.throughput(Throughput::Elements(case.potential.n_dofs() as u64));
        let id = BenchmarkId::new(name.as_str(), format!("ny{ny}_{}dofs", case.potential.n_dofs()));
        symbolic.bench_function(id, |b| {
            b.iter(|| SparseSolver::try_new(black_box(pattern), LinearSolverSettings::default()).unwrap());
        });
    }
    symbolic.finish();
    let mut numeric = c.benchmark_group("plate_numeric");
    configure(&mut numeric, 5);
    for (name, ny, case) in cases.iter_mut() {
        let values = case.hessian_values();
        let n = case.potential.n_dofs();
        let mut solver = SparseSolver::try_new(case.potential.pattern().symbolic(), LinearSolverSettings::default())
            .expect("symbolic analysis");
        numeric.throughput(Throughput::Elements(n as u64));
        numeric.bench_function(BenchmarkId::new(name.as_str(), format!("ny{ny}_{n}dofs")), |b| {
            b.iter(|| solver.factorise(black_box(&values), None).unwrap());
        });
    }
    numeric.finish();
}

/// One full time step from the state at `t = 0.5 s`, restored before every sample.
fn time_step(c: &mut Criterion, cases: &mut [(String, usize, PlateCase)]) {
    let mut group = c.benchmark_group("plate_time_step");
    configure(&mut group, 5);
    for (name, ny, case) in cases.iter_mut() {
        let n = case.potential.n_dofs();
        let state = case.potential.parts.state.clone();
        let t0 = case.stepper.time();
        group.throughput(Throughput::Elements(n as u64));
        let PlateCase {
            potential,
            stepper,
            tip,
        } = case;
        group.bench_function(BenchmarkId::new(name.as_str(), format!("ny{ny}_{n}dofs")), |b| {
            b.iter(|| {
                potential.parts.state.clone_from(&state);
                stepper.set_time(t0);
                stepper
                    .step(potential, &mut |p, t, _| apply_load(p, tip, t))
                    .expect("the plate converges")
            });
        });
    }
    group.finish();
}

/// Builds the cases once and runs every group (written out instead of `criterion_group!`, whose
/// generated function carries no documentation).
fn benches() {
    let mut criterion = Criterion::default().configure_from_args();
    let mut cases: Vec<(String, usize, PlateCase)> = PAIRS
        .iter()
        .flat_map(|&(name, pair)| SIZES.iter().map(move |&ny| (name.to_string(), ny, PlateCase::new(pair, ny))))
        .collect();
    assembly(&mut criterion, &mut cases);
    factorisation(&mut criterion, &mut cases);
    time_step(&mut criterion, &mut cases);
}

criterion_main!(benches);
