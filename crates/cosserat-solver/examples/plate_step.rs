//! Times steps of the plate-under-load setup (scratch profiling tool).
use cosserat_assembly::ElementPair;
use cosserat_solver::{TimeStepSettings, TimeStepper};
use nalgebra::Vector3;
use std::time::Instant;

#[path = "common/plate.rs"]
mod plate;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let ny: usize = args.get(1).map_or(4, |s| s.parse().unwrap());
    let steps: usize = args.get(2).map_or(20, |s| s.parse().unwrap());
    let pair = if args.get(3).is_some_and(|s| s == "tri3") {
        ElementPair::Tri3Tri3
    } else {
        ElementPair::Tri6Tri3
    };
    let nx = 10 * ny;
    let t_build = Instant::now();
    let (mut sys, tip) = plate::clamped_plate(nx, ny, pair, 0.01);
    println!(
        "build {:.3} s, dofs {}, nnz {}",
        t_build.elapsed().as_secs_f64(),
        sys.potential.n_dofs(),
        sys.potential.pattern().nnz()
    );
    let mut settings = TimeStepSettings::fixed(0.01);
    if std::env::var("ND").is_ok() {
        settings.newton.linear_solver.ordering = cosserat_solver::FillOrdering::NestedDissection { block: 3 };
    }
    if let Ok(r) = std::env::var("REUSE") {
        settings.newton.reuse_max_ratio = Some(r.parse().unwrap());
    }
    if std::env::var("WHOLE").is_ok() {
        settings.newton.linear_solver.domains = cosserat_solver::DomainSplit::Off;
    }
    if std::env::var("PAR").is_ok() {
        settings.newton.linear_solver.parallelism = faer::Par::rayon(0);
    }
    let t_sym = Instant::now();
    let mut stepper = TimeStepper::new(&sys.potential, settings).unwrap();
    println!("symbolic {:.3} s", t_sym.elapsed().as_secs_f64());
    let (mut asm, mut sol, mut its) = (0.0, 0.0, 0);
    let t0 = Instant::now();
    for _ in 0..steps {
        let r = stepper
            .step(&mut sys.potential, &mut |p, t, _| {
                let f = 50.0 * (t / 1.0).clamp(0.0, 1.0) / tip.len() as f64;
                for &i in &tip {
                    p.parts.loads.forces[i] = Vector3::new(0.0, 0.0, f);
                }
            })
            .unwrap();
        asm += r.newton.assembly_seconds;
        sol += r.newton.linear_solve_seconds;
        its += r.newton.iterations;
    }
    let total = t0.elapsed().as_secs_f64();
    println!(
        "{} steps: {:.1} ms/step, {:.2} it/step, assembly {:.1}%, solve {:.1}%, tip uz {:.4} mm, stats {:?}",
        steps,
        1e3 * total / steps as f64,
        its as f64 / steps as f64,
        100.0 * asm / total,
        100.0 * sol / total,
        1e3 * tip.iter().map(|&i| sys.potential.parts.state.x[i].z).sum::<f64>() / tip.len() as f64,
        stepper.solver().linear_solver().symmetric_stats()
    );
}
