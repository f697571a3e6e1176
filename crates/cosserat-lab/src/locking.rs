//! The locking study of `cargo xtask stability`: the thin-limit behaviour of each element pair.
//!
//! The Sze 3.1 cantilever (`scenes/validation/sze_cantilever_end_shear.toml`, L = 10, b = 1) is run at
//! h/L = 1e-1 … 1e-5 with Young's modulus scaled as E = 1200/h³, so that the bending stiffness
//! EI = E b h³/12 = 100 and the whole load path stay those of the benchmark while the membrane and
//! shear stiffness grow like (L/h)². The tip deflection at the full load (α = P L²/EI = 4) is divided by
//! the inextensible elastica's 6.6996: a pair that locks gives a ratio falling towards 0 as h/L → 0
//! on a fixed mesh. The residual tolerance scales with the membrane stiffness E h (1e-13·E·h, at
//! least 1e-7), because an absolute tolerance below the round-off floor cannot be met.

use crate::plot::{Mark, Plot, Series};
use crate::problem::Pair;
use crate::reference::elastica_tip;
use crate::runner::{Runner, run_described};
use anyhow::Result;
use cosserat::RunDescription;
use std::fmt::Write as _;
use std::path::Path;

/// The scene of the study.
pub const SCENE: &str = "scenes/validation/sze_cantilever_end_shear.toml";

/// Thickness ratios h/L of the study.
pub const H_OVER_L: [f64; 5] = [1e-1, 1e-2, 1e-3, 1e-4, 1e-5];

/// The meshes of the study: `(pair, nx, ny)`.
pub const MESHES: [(Pair, usize, usize); 8] = [
    (Pair::Tri3Tri3, 20, 2),
    (Pair::Tri3Tri3, 320, 1),
    (Pair::Tri3Tri3, 1280, 1),
    (Pair::Tri6Tri3, 10, 1),
    (Pair::Tri6Tri3, 20, 2),
    (Pair::Tri6Tri3, 80, 8),
    (Pair::Tri6Tri6, 20, 2),
    (Pair::Tri6Tri6, 80, 8),
];

/// Overrides of one run: thickness `h_over_l · 10`, `E = 1200/h³`, the tolerance and the mesh.
pub fn overrides(pair: Pair, nx: usize, ny: usize, h_over_l: f64) -> Vec<String> {
    let h = 10.0 * h_over_l;
    let e = 1200.0 / h.powi(3);
    let tol = (1e-13 * e * h).max(1e-7);
    let mut ov = pair.overrides();
    ov.extend([
        format!("material.thickness={h:e}"),
        format!("material.youngs_modulus={e:e}"),
        format!("material.length_scale={:e}", 1e-3 * h),
        format!("solver.tolerance={tol:e}"),
        format!("mesh.nx={nx}"),
        format!("mesh.ny={ny}"),
        "output.frames=false".into(),
    ]);
    ov
}

/// Tip deflection ratio `W / W_elastica` at the full load, from a finished run's probes.
pub fn deflection_ratio(outcome: &crate::runner::RunOutcome) -> Option<f64> {
    if !outcome.is_ok() {
        return None;
    }
    let w = outcome.probes.as_ref()?.last("tip.uz").ok()?;
    Some(w / (10.0 * elastica_tip(4.0).0))
}

/// Runs the study; returns its markdown section.
///
/// # Errors
/// I/O failures.
pub fn run_all(runner: &Runner, out: &Path, images: &Path) -> Result<String> {
    let mut md = String::new();
    writeln!(md, "\n## Locking in the thin limit\n")?;
    writeln!(
        md,
        "Scene `{SCENE}` (Sze 3.1) at h/L from 1e-1 to 1e-5 with E = 1200/h³, so that EI = 100 and the load path stay the benchmark's while the membrane and shear stiffness grow like (L/h)². Entries: tip deflection W at the full load divided by the inextensible elastica's (6.6996); 1 is right, a ratio falling with h/L is locking. Residual tolerance 1e-13·E·h (at least 1e-7).\n"
    )?;
    let header: Vec<String> = H_OVER_L.iter().map(|r| format!("h/L = {r:.0e}")).collect();
    writeln!(
        md,
        "| pair | mesh | {} |\n|---|---|{}",
        header.join(" | "),
        "---|".repeat(H_OVER_L.len())
    )?;
    let mut series = Vec::new();
    for (k, &(pair, nx, ny)) in MESHES.iter().enumerate() {
        let mut cells = Vec::new();
        let mut points = Vec::new();
        for &r in &H_OVER_L {
            eprintln!("locking: {} {nx}×{ny} h/L = {r:.0e} ...", pair.label());
            let dir = out.join(format!("{}_{nx}x{ny}_{r:.0e}", pair.label().replace('/', "_")));
            let outcome = run_described(runner, &RunDescription::new(SCENE, dir, &overrides(pair, nx, ny, r)))?;
            match deflection_ratio(&outcome) {
                Some(ratio) => {
                    cells.push(format!("{ratio:.4}"));
                    points.push((r, ratio));
                }
                None => cells.push(format!("failed: {}", outcome.reason())),
            }
        }
        writeln!(md, "| {} | {nx}×{ny} | {} |", pair.label(), cells.join(" | "))?;
        series.push(Series {
            label: format!("{} {nx}×{ny}", pair.label()),
            points,
            mark: Mark::LinePoints,
            color: pair.color() + 3 * (k % 2),
        });
    }
    let path = images.join("stability_locking.svg");
    let plot = Plot {
        title: "Tip deflection / elastica vs h/L (Sze 3.1, EI fixed)".into(),
        x_label: "h/L".into(),
        y_label: "W / W_elastica".into(),
        log_log: true,
        series,
    };
    match plot.write_svg(&path) {
        Ok(()) => writeln!(md, "\n![locking](img/stability_locking.svg)\n")?,
        Err(e) => writeln!(md, "\n(plot not written: {e})\n")?,
    }
    Ok(md)
}
