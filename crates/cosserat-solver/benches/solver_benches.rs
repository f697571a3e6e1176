//! Benchmarks of the sparse linear solvers: symbolic analysis and numerical factorisation of a
//! 3×3-block, Laplacian-like SPD matrix on a 2D grid (the block pattern of a shell mesh with three
//! unknowns per node) at about 10k, 40k and 160k unknowns, for Cholesky, LDLᵀ (`L B Lᵀ`) and LU.
//!
//! Run with `cargo bench -p cosserat-solver --bench solver_benches` (add `--profile perf` for the
//! tuned profile). Inputs are generated from a fixed seed; nothing is read from disk.

use std::hint::black_box;
use std::time::Duration;

use cosserat_solver::{DomainSplit, FillOrdering, LinearSolverKind, LinearSolverSettings, SparseSolver};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_main};
use faer::sparse::SymbolicSparseColMat;
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::SeedableRng;

/// The upper triangle of a block matrix on an `m × m` node grid: every grid edge `e = (p, q)` adds
/// `s_e [[K, −K], [−K, K]]` with a fixed SPD 3×3 `K` and a seeded scale `s_e ∈ [0.5, 1.5]`, and every
/// node adds `0.01 I` (a lumped mass), which makes the matrix positive definite.
struct GridMatrix {
    pattern: SymbolicSparseColMat<usize>,
    values: Vec<f64>,
}

const K: [[f64; 3]; 3] = [[2.0, 0.5, 0.2], [0.5, 2.0, 0.3], [0.2, 0.3, 2.0]];

fn grid_matrix(m: usize, seed: u64) -> GridMatrix {
    let n_nodes = m * m;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    // Scales of the edges to the node below (p − m) and to the left (p − 1), NaN where absent.
    let mut scale_down = vec![f64::NAN; n_nodes];
    let mut scale_left = vec![f64::NAN; n_nodes];
    let mut diag_scale = vec![0.0; n_nodes];
    for p in 0..n_nodes {
        let (i, j) = (p / m, p % m);
        if i > 0 {
            let s = rng.random_range(0.5..1.5);
            scale_down[p] = s;
            diag_scale[p] += s;
            diag_scale[p - m] += s;
        }
        if j > 0 {
            let s = rng.random_range(0.5..1.5);
            scale_left[p] = s;
            diag_scale[p] += s;
            diag_scale[p - 1] += s;
        }
    }
    let n = 3 * n_nodes;
    let mut col_ptr = Vec::with_capacity(n + 1);
    let mut row_idx = Vec::new();
    let mut values = Vec::new();
    col_ptr.push(0);
    for p in 0..n_nodes {
        for a in 0..3 {
            // Neighbours with smaller index first (rows sorted), then the node's own block.
            for (q, s) in [(p.wrapping_sub(m), scale_down[p]), (p.wrapping_sub(1), scale_left[p])] {
                if s.is_nan() {
                    continue;
                }
                for b in 0..3 {
                    row_idx.push(3 * q + b);
                    values.push(-s * K[b][a]);
                }
            }
            for b in 0..=a {
                row_idx.push(3 * p + b);
                values.push(diag_scale[p] * K[b][a] + if a == b { 0.01 } else { 0.0 });
            }
            col_ptr.push(row_idx.len());
        }
    }
    let pattern = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
    GridMatrix { pattern, values }
}

/// Grid sides giving about 10k, 40k and 160k unknowns (3 per node).
const SIDES: [usize; 3] = [58, 116, 231];

const KINDS: [(&str, LinearSolverKind); 3] = [
    ("cholesky", LinearSolverKind::Cholesky),
    ("ldlt", LinearSolverKind::Ldlt),
    ("lu", LinearSolverKind::Lu),
];

/// One factorisation of the whole matrix (the two-domain split is benchmarked as its own variant).
fn settings(kind: LinearSolverKind) -> LinearSolverSettings {
    LinearSolverSettings {
        kind,
        domains: DomainSplit::Off,
        ..Default::default()
    }
}

fn symbolic(c: &mut Criterion) {
    let mut group = c.benchmark_group("symbolic");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    for m in SIDES {
        let a = grid_matrix(m, 1);
        let n = a.pattern.ncols();
        group.throughput(Throughput::Elements(n as u64));
        for (name, kind) in KINDS {
            group.bench_with_input(BenchmarkId::new(name, n), &a, |bench, a| {
                bench.iter(|| SparseSolver::try_new(black_box(a.pattern.as_ref()), settings(kind)).unwrap());
            });
        }
    }
    group.finish();
}

fn numeric(c: &mut Criterion) {
    let mut group = c.benchmark_group("numeric");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(5));
    for m in SIDES {
        let a = grid_matrix(m, 2);
        let n = a.pattern.ncols();
        group.throughput(Throughput::Elements(n as u64));
        for (name, kind) in KINDS {
            let mut solver = SparseSolver::try_new(a.pattern.as_ref(), settings(kind)).unwrap();
            group.bench_with_input(BenchmarkId::new(name, n), &a.values, |bench, values| {
                bench.iter(|| solver.factorise(black_box(values), None).unwrap());
            });
        }
    }
    group.finish();
}

/// Factorisation and one solve, the cost of one Newton iteration's linear algebra: the direct solvers
/// (Cholesky also with nested dissection, and split into two domains factorised at once) against block-Jacobi conjugate gradients to a relative
/// residual of 1e-8. The grid operator's condition number grows like the square of its side, so CG's
/// iteration count grows with the size while the factorisations' fill does.
fn factorise_and_solve(c: &mut Criterion) {
    let mut group = c.benchmark_group("factorise_and_solve");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(5));
    let variants = [
        ("cholesky_amd", settings(LinearSolverKind::Cholesky)),
        (
            "cholesky_two_domains",
            LinearSolverSettings {
                domains: DomainSplit::Always,
                ..settings(LinearSolverKind::Cholesky)
            },
        ),
        (
            "cholesky_nested_dissection",
            LinearSolverSettings {
                ordering: FillOrdering::NestedDissection { block: 3 },
                ..settings(LinearSolverKind::Cholesky)
            },
        ),
        ("ldlt", settings(LinearSolverKind::Ldlt)),
        ("lu", settings(LinearSolverKind::Lu)),
        ("cg_block_jacobi", settings(LinearSolverKind::Cg)),
    ];
    for m in SIDES {
        let a = grid_matrix(m, 3);
        let n = a.pattern.ncols();
        group.throughput(Throughput::Elements(n as u64));
        for (name, s) in variants {
            let mut solver = SparseSolver::try_new(a.pattern.as_ref(), s).unwrap();
            group.bench_with_input(BenchmarkId::new(name, n), &a.values, |bench, values| {
                bench.iter(|| {
                    solver.factorise(black_box(values), None).unwrap();
                    let mut x = vec![1.0; n];
                    solver.solve_in_place(&mut x).unwrap();
                    black_box(x)
                });
            });
        }
    }
    group.finish();
}

/// Runs every group of this harness (written out instead of `criterion_group!`, whose generated
/// function carries no documentation).
fn benches() {
    let mut criterion = Criterion::default().configure_from_args();
    symbolic(&mut criterion);
    numeric(&mut criterion);
    factorise_and_solve(&mut criterion);
}

criterion_main!(benches);
