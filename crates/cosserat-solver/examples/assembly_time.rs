//! Times Hessian and gradient evaluations of the Tri6 plate-under-load potential (`-- <ny> <repetitions>`;
//! medians, since this machine is shared).
//!
//! With `FACTORISE=1` a two-domain Cholesky factorisation and solve of the rest state's Hessian runs
//! between the repetitions, as in a Newton iteration: the assembly after it must be as fast as
//! without it (see `linear/vector_state.rs`). `SEQ=1` prints every Hessian time in order.
use cosserat_assembly::ElementPair;
use std::time::Instant;

#[path = "common/plate.rs"]
mod plate;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let ny: usize = args.get(1).map_or(4, |s| s.parse().unwrap());
    let reps: usize = args.get(2).map_or(10, |s| s.parse().unwrap());
    let (mut sys, _) = plate::clamped_plate(10 * ny, ny, ElementPair::Tri6Tri3, 0.01);
    let pot = &mut sys.potential;
    let n = pot.n_dofs();
    let u: Vec<f64> = (0..n).map(|i| 1e-3 * ((i as f64) * 0.7).sin()).collect();
    let mut g = vec![0.0; n];
    let mut h = vec![0.0; pot.pattern().nnz()];
    let mut linear = std::env::var_os("FACTORISE").map(|_| {
        let settings = cosserat_solver::LinearSolverSettings {
            kind: cosserat_solver::LinearSolverKind::Cholesky,
            domains: cosserat_solver::DomainSplit::Always,
            ..Default::default()
        };
        let solver = cosserat_solver::SparseSolver::try_new(pot.pattern().symbolic(), settings).unwrap();
        // The Hessian at rest is positive definite (the one at `u` need not be).
        let (mut g0, mut h0) = (vec![0.0; n], vec![0.0; pot.pattern().nnz()]);
        pot.hessian(&vec![0.0; n], &mut g0, &mut h0).unwrap();
        (solver, h0, g0)
    });
    let mut th = Vec::new();
    let mut tg = Vec::new();
    for _ in 0..reps {
        g.fill(0.0);
        h.fill(0.0);
        let t = Instant::now();
        pot.hessian(&u, &mut g, &mut h).unwrap();
        th.push(t.elapsed().as_secs_f64());
        if let Some((solver, h0, g0)) = linear.as_mut() {
            solver.factorise(h0, None).unwrap();
            let mut x = g0.clone();
            solver.solve_in_place(&mut x).unwrap();
        }
        g.fill(0.0);
        let t = Instant::now();
        pot.gradient(&u, &mut g).unwrap();
        tg.push(t.elapsed().as_secs_f64());
    }
    if std::env::var_os("SEQ").is_some() {
        let ms: Vec<u32> = th.iter().map(|t| (t * 1e3).round() as u32).collect();
        println!("hessian ms in order: {ms:?}");
    }
    th.sort_by(f64::total_cmp);
    tg.sort_by(f64::total_cmp);
    println!(
        "dofs {n}: hessian median {:.1} ms (min {:.1}), gradient median {:.1} ms (min {:.1})",
        1e3 * th[reps / 2],
        1e3 * th[0],
        1e3 * tg[reps / 2],
        1e3 * tg[0]
    );
}
