//! Numeric Cholesky rate on plate-under-load Hessian patterns: one factorisation of the whole matrix
//! (AMD, nested dissection, or the cheaper of the two) against the two-domain split (`DomainSplit`), and with `RELAX=1` faer's supernode relaxation
//! settings (more amalgamation raises the rate on the padded operation count but not the time).
//!
//! `cargo run --release -p cosserat-solver --example factor_rate -- <ny> [<nx / ny>]` (Tri6/Tri3 plate
//! of `10 ny × ny` elements by default; `VARIANT=two` runs only the two-domain split). The values are
//! a diagonally dominant stand-in with the Hessian's pattern: Cholesky's time does not depend on them.
use cosserat_assembly::ElementPair;
use cosserat_solver::{DomainSplit, FillOrdering, LinearSolverKind, LinearSolverSettings, SparseSolver};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::SparseColMatRef;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering, factorize_symbolic_cholesky,
};
use faer::sparse::linalg::{SupernodalThreshold, SymbolicSupernodalParams};
use faer::{Par, Side};
use std::time::Instant;

#[path = "common/plate.rs"]
mod plate;

/// faer's supernode relaxation thresholds: `(columns, fraction of explicit zeros)` pairs.
type Relaxation = &'static [(usize, f64)];

/// `Σ c_j²` over the supernodal structure, and the number of supernodes.
fn operations(symbolic: &SymbolicCholesky<usize>) -> (f64, usize) {
    let SymbolicCholeskyRaw::Supernodal(sn) = symbolic.raw() else {
        return (f64::NAN, 0);
    };
    let mut f = 0.0;
    for s in 0..sn.n_supernodes() {
        let w = sn.supernode_end()[s] - sn.supernode_begin()[s];
        let b = sn.supernode(s).pattern().len();
        f += (0..w).map(|l| ((w - l + b) as f64).powi(2)).sum::<f64>();
    }
    (f, sn.n_supernodes())
}

fn main() {
    let ny: usize = std::env::args().nth(1).map_or(16, |s| s.parse().expect("ny"));
    let aspect: usize = std::env::args().nth(2).map_or(10, |s| s.parse().expect("nx / ny"));
    let (sys, _) = plate::clamped_plate(aspect * ny, ny, ElementPair::Tri6Tri3, 0.01);
    let pattern = sys.potential.pattern().symbolic();
    let n = pattern.ncols();
    let mut values = vec![0.0; pattern.row_idx().len()];
    for j in 0..n {
        for k in pattern.col_ptr()[j]..pattern.col_ptr()[j + 1] {
            let i = pattern.row_idx()[k];
            values[k] = if i == j {
                200.0
            } else {
                -(((i * 7 + j * 13) % 17) as f64) / 17.0
            };
        }
    }
    println!("{n} unknowns");
    let variants = [
        ("whole, AMD", FillOrdering::Amd, DomainSplit::Off),
        (
            "whole, nested dissection",
            FillOrdering::NestedDissection { block: 3 },
            DomainSplit::Off,
        ),
        ("whole, automatic", FillOrdering::Auto, DomainSplit::Off),
        ("two domains, AMD", FillOrdering::Amd, DomainSplit::Always),
        ("two domains, automatic", FillOrdering::Auto, DomainSplit::Always),
    ];
    // `VARIANT=<text>` runs only the variants whose name contains it.
    let only = std::env::var("VARIANT").unwrap_or_default();
    for (name, ordering, domains) in variants.into_iter().filter(|(name, _, _)| name.contains(only.as_str())) {
        let settings = LinearSolverSettings {
            kind: LinearSolverKind::Cholesky,
            ordering,
            domains,
            ..Default::default()
        };
        let t = Instant::now();
        let mut solver = SparseSolver::try_new(pattern, settings).expect("analysis");
        let t_symbolic = t.elapsed().as_secs_f64();
        let stats = solver.symmetric_stats().expect("symmetric analysis");
        let mut best = f64::MAX;
        for _ in 0..3 {
            let t = Instant::now();
            solver.factorise(&values, None).expect("positive definite");
            best = best.min(t.elapsed().as_secs_f64());
        }
        let b: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        let mut t_solve = f64::MAX;
        for _ in 0..5 {
            let mut x = b.clone();
            let t = Instant::now();
            solver.solve_in_place(&mut x).expect("solve");
            t_solve = t_solve.min(t.elapsed().as_secs_f64());
        }
        println!(
            "{name}: symbolic {t_symbolic:.3} s, {:.3e} operations, nnz(L) {}, factorisation {best:.3} s \
             ({:.1} GFLOP/s), solve (best of 5) {t_solve:.4} s, backward error {:.1e}",
            stats.flops,
            stats.nnz_l,
            stats.flops / best / 1e9,
            solver.last_backward_error().unwrap_or(f64::NAN)
        );
    }
    if std::env::var("RELAX").is_err() {
        return;
    }
    let a = SparseColMatRef::new(pattern, &values);
    let relaxations: [(&str, Option<Relaxation>); 4] = [
        ("none", None),
        (
            "faer default",
            Some(&[(4, 1.0), (16, 0.8), (48, 0.1), (usize::MAX, 0.05)]),
        ),
        ("0.2", Some(&[(4, 1.0), (16, 0.8), (48, 0.3), (usize::MAX, 0.2)])),
        ("0.6", Some(&[(8, 1.0), (64, 0.8), (usize::MAX, 0.6)])),
    ];
    for (name, relax) in relaxations {
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
            supernodal_params: SymbolicSupernodalParams { relax },
            ..Default::default()
        };
        let symbolic =
            factorize_symbolic_cholesky(pattern, Side::Upper, SymmetricOrdering::Amd, params).expect("analysis");
        let (ops, supernodes) = operations(&symbolic);
        let mut l = vec![0.0; symbolic.len_val()];
        let mut mem = MemBuffer::new(symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()));
        let mut best = f64::MAX;
        for _ in 0..3 {
            let t = Instant::now();
            symbolic
                .factorize_numeric_llt::<f64>(
                    &mut l,
                    a,
                    Side::Upper,
                    Default::default(),
                    Par::Seq,
                    MemStack::new(&mut mem),
                    Default::default(),
                )
                .expect("positive definite");
            best = best.min(t.elapsed().as_secs_f64());
        }
        println!(
            "relaxation {name}: {supernodes} supernodes, {ops:.3e} operations, {best:.3} s ({:.1} GFLOP/s)",
            ops / best / 1e9
        );
    }
}
