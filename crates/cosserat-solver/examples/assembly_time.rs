//! Times Hessian and gradient evaluations of the Tri6 plate-under-load potential (`-- <ny> <repetitions>`;
//! medians, since this machine is shared).
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
    let mut th = Vec::new();
    let mut tg = Vec::new();
    for _ in 0..reps {
        g.fill(0.0);
        h.fill(0.0);
        let t = Instant::now();
        pot.hessian(&u, &mut g, &mut h).unwrap();
        th.push(t.elapsed().as_secs_f64());
        g.fill(0.0);
        let t = Instant::now();
        pot.gradient(&u, &mut g).unwrap();
        tg.push(t.elapsed().as_secs_f64());
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
