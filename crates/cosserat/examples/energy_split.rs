//! Runs a scene and prints the elastic energy of its final state split by strain part: which part
//! of the strain carries the energy (and, on a locking mesh, which part locks).
//!
//! `cargo run --release -p cosserat --example energy_split -- <scene.toml> <output dir> [key=value ...]`

use cosserat::{Simulation, StopRequest};
use std::path::Path;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    if args.len() < 3 {
        anyhow::bail!("usage: energy_split <scene.toml> <output dir> [key=value ...]");
    }
    let spec = cosserat_scene::load_scene(Path::new(&args[1]), &args[3..])?;
    let mut sim = Simulation::new(spec)?;
    let summary = sim.run(Path::new(&args[2]), &mut |_| {}, &StopRequest::new())?;
    let parts = &sim.potential().parts;
    for shell in &parts.shells {
        let e = shell.energy_parts(&parts.state);
        let t = e.total;
        let coupling = t - e.membrane - e.drilling - e.shear - e.bending;
        println!(
            "status {:?}; energy {t:.6e}: membrane {:.4}, drilling {:.4}, shear {:.4}, bending {:.4}, coupling {:.4}",
            summary.status,
            e.membrane / t,
            e.drilling / t,
            e.shear / t,
            e.bending / t,
            coupling / t
        );
    }
    Ok(())
}
