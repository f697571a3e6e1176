//! The locking study of `cargo xtask stability`: the thin-limit behaviour of each element pair.
//!
//! The Sze 3.1 cantilever (`scenes/validation/sze_cantilever_end_shear.toml`, L = 10, b = 1) is run at
//! h/L = 1e-1 … 1e-5 with Young's modulus scaled as E = 1200/h³, so that the bending stiffness
//! EI = E b h³/12 = 100 and the whole load path stay those of the benchmark while the membrane and
//! shear stiffness grow like (L/h)². The tip deflection at the full load (α = P L²/EI = 4) is divided by
//! the inextensible elastica's 6.6996: a pair that locks gives a ratio falling towards 0 as h/L → 0
//! on a fixed mesh. The scene's absolute residual tolerance is removed: across ten decades of E the
//! default relative test (a millionth of the load scale, never below the residual's round-off floor)
//! judges every cell alike, where a fixed tolerance lies below the floor of the thinnest ones.

use crate::plot::{Mark, Plot, Series};
use crate::problem::{Interpolation, Pair};
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

/// One row of the study: element pair, strain interpolation and mesh.
#[derive(Debug, Clone, Copy)]
pub struct Row {
    /// The element pair.
    pub pair: Pair,
    /// The strain interpolation.
    pub interpolation: Interpolation,
    /// Quads along the strip.
    pub nx: usize,
    /// Quads across the strip.
    pub ny: usize,
}

impl Row {
    /// A row.
    pub const fn new(pair: Pair, interpolation: Interpolation, nx: usize, ny: usize) -> Self {
        Self {
            pair,
            interpolation,
            nx,
            ny,
        }
    }

    /// `Tri6/Tri3` for the paper's interpolation, `Tri6/Tri3 regge` for another.
    pub fn label(&self) -> String {
        if self.interpolation == Interpolation::Paper {
            self.pair.label().to_string()
        } else {
            format!("{} {}", self.pair.label(), self.interpolation.as_str())
        }
    }
}

/// The rows of the study: the three pairs on coarse and fine meshes with the paper's interpolation, the
/// locking-free interpolations on the coarse Tri6/Tri3 mesh, and quadratic rotations with
/// `regge_stabilized` (the obstacle course's choice) on the same mesh.
pub const ROWS: [Row; 12] = [
    Row::new(Pair::Tri3Tri3, Interpolation::Paper, 20, 2),
    Row::new(Pair::Tri3Tri3, Interpolation::Paper, 320, 1),
    Row::new(Pair::Tri3Tri3, Interpolation::Paper, 1280, 1),
    Row::new(Pair::Tri6Tri3, Interpolation::Paper, 10, 1),
    Row::new(Pair::Tri6Tri3, Interpolation::Paper, 20, 2),
    Row::new(Pair::Tri6Tri3, Interpolation::Paper, 80, 8),
    Row::new(Pair::Tri6Tri3, Interpolation::Regge, 20, 2),
    Row::new(Pair::Tri6Tri3, Interpolation::Stabilized, 20, 2),
    Row::new(Pair::Tri6Tri3, Interpolation::ReggeStabilized, 20, 2),
    Row::new(Pair::Tri6Tri6, Interpolation::Paper, 20, 2),
    Row::new(Pair::Tri6Tri6, Interpolation::Paper, 80, 8),
    Row::new(Pair::Tri6Tri6, Interpolation::ReggeStabilized, 20, 2),
];

/// The accuracy the advice asks of a mesh: within 1 % of the elastica.
const WITHIN: f64 = 0.01;

/// Overrides of one run: thickness `h_over_l · 10`, `E = 1200/h³`, the relative tolerance and the
/// mesh.
pub fn overrides(row: &Row, h_over_l: f64) -> Vec<String> {
    let h = 10.0 * h_over_l;
    let e = 1200.0 / h.powi(3);
    let mut ov = row.pair.overrides();
    ov.extend([
        format!("material.thickness={h:e}"),
        format!("material.youngs_modulus={e:e}"),
        format!("material.length_scale={:e}", 1e-3 * h),
        row.interpolation.scene_override(),
        "solver.tolerance=".into(),
        format!("mesh.nx={}", row.nx),
        format!("mesh.ny={}", row.ny),
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

/// The outcome of one run of the study: the deflection ratio and Newton's effort, or why the run did
/// not finish.
#[derive(Debug, Clone)]
pub enum Cell {
    /// Tip deflection over the elastica's, and the Newton iterations per requested load level (those
    /// of intermediate levels and failed solves included).
    Ratio(f64, f64),
    /// The run did not reach the full load.
    Failed(String),
}

impl Cell {
    fn within(&self) -> bool {
        matches!(self, Cell::Ratio(r, _) if (r - 1.0).abs() <= WITHIN)
    }
}

/// Runs the study; returns its markdown section, the table with its plot and the advice drawn from it.
///
/// # Errors
/// I/O failures.
pub fn run_all(runner: &Runner, out: &Path, images: &Path) -> Result<String> {
    let mut results = Vec::new();
    for row in &ROWS {
        let mut cells = Vec::new();
        for &r in &H_OVER_L {
            eprintln!("locking: {} {}×{} h/L = {r:.0e} ...", row.label(), row.nx, row.ny);
            let name = format!("{}_{}x{}_{r:.0e}", row.label(), row.nx, row.ny);
            let dir = out.join(name.replace(['/', ' '], "_"));
            let outcome = run_described(runner, &RunDescription::new(SCENE, dir, &overrides(row, r)))?;
            let iterations = outcome.summary.as_ref().map(|s| s.avg_newton_iterations);
            cells.push(match (deflection_ratio(&outcome), iterations) {
                (Some(ratio), Some(iterations)) => Cell::Ratio(ratio, iterations),
                _ => Cell::Failed(outcome.reason()),
            });
        }
        results.push((*row, cells));
    }
    let mut md = table(&results)?;
    md.push_str(&plot(&results, images)?);
    md.push_str(&advice(&results)?);
    Ok(md)
}

fn table(results: &[(Row, Vec<Cell>)]) -> Result<String> {
    let mut md = String::new();
    writeln!(md, "\n## Locking in the thin limit\n")?;
    writeln!(
        md,
        "Scene `{SCENE}` (Sze 3.1) at h/L from 1e-1 to 1e-5 with E = 1200/h³, so that EI = 100 and the load path stay the benchmark's while the membrane and shear stiffness grow like (L/h)². Entries: tip deflection W at the full load divided by the inextensible elastica's (6.6996), and in brackets the Newton iterations per load level (the default solver settings); 1 is right, a ratio falling with h/L is locking. Rows name the element pair and, where it is not the paper's, the strain interpolation (`material.strain_interpolation`, docs/model-notes.md). Residual tolerance: the default relative test (a millionth of the load scale, never below the residual's round-off floor; `solver.tolerance=` removes the scene's absolute 1e-7).\n"
    )?;
    let header: Vec<String> = H_OVER_L.iter().map(|r| format!("h/L = {r:.0e}")).collect();
    writeln!(
        md,
        "| pair | mesh | {} |\n|---|---|{}",
        header.join(" | "),
        "---|".repeat(H_OVER_L.len())
    )?;
    for (row, cells) in results {
        let cells: Vec<String> = cells
            .iter()
            .map(|c| match c {
                Cell::Ratio(r, iterations) => format!("{r:.4} ({iterations:.1})"),
                Cell::Failed(reason) => format!("failed: {reason}"),
            })
            .collect();
        writeln!(
            md,
            "| {} | {}×{} | {} |",
            row.label(),
            row.nx,
            row.ny,
            cells.join(" | ")
        )?;
    }
    Ok(md)
}

fn plot(results: &[(Row, Vec<Cell>)], images: &Path) -> Result<String> {
    let series = results
        .iter()
        .enumerate()
        .map(|(k, (row, cells))| Series {
            label: format!("{} {}×{}", row.label(), row.nx, row.ny),
            points: H_OVER_L
                .iter()
                .zip(cells)
                .filter_map(|(&r, c)| match c {
                    Cell::Ratio(ratio, _) => Some((r, *ratio)),
                    Cell::Failed(_) => None,
                })
                .collect(),
            mark: Mark::LinePoints,
            color: row.pair.color() + 3 * (k % 2),
        })
        .collect();
    let path = images.join("stability_locking.svg");
    let plot = Plot {
        title: "Tip deflection / elastica vs h/L (Sze 3.1, EI fixed)".into(),
        x_label: "h/L".into(),
        y_label: "W / W_elastica".into(),
        log_log: true,
        series,
    };
    Ok(match plot.write_svg(&path) {
        Ok(()) => "\n![locking](img/stability_locking.svg)\n\n".to_string(),
        Err(e) => format!("\n(plot not written: {e})\n\n"),
    })
}

/// What the table says, row by row, and which row to choose: generated from the results so that it
/// cannot contradict them.
fn advice(results: &[(Row, Vec<Cell>)]) -> Result<String> {
    let mut md = String::new();
    writeln!(md, "What the table shows (within 1 % = |W / W_elastica − 1| ≤ 0.01):\n")?;
    for (row, cells) in results {
        writeln!(
            md,
            "- **{} on {}×{}**: {}.",
            row.label(),
            row.nx,
            row.ny,
            row_finding(cells)
        )?;
    }
    let thinnest = |row: &Row, cells: &[Cell]| thinnest_within(cells).map(|r| (r, row.nx * row.ny));
    // The best rows reach the thinnest shell within 1 %, and among equals have the fewest quads; rows
    // that tie are all named.
    let reached: Vec<(&Row, (f64, usize))> = results
        .iter()
        .filter_map(|(row, cells)| thinnest(row, cells).map(|t| (row, t)))
        .collect();
    let best = reached
        .iter()
        .map(|(_, t)| *t)
        .min_by(|(ra, na), (rb, nb)| ra.total_cmp(rb).then(na.cmp(nb)));
    if let Some((r, quads)) = best {
        let rows: Vec<&Row> = reached.iter().filter(|(_, t)| *t == (r, quads)).map(|(row, _)| *row).collect();
        let names: Vec<String> = rows.iter().map(|row| format!("**{}**", row.label())).collect();
        writeln!(
            md,
            "\nThe thinnest strip within 1 % on the fewest quads: {} on {}×{} (to h/L = {r:.0e}). A pair or interpolation that locks needs elements of a few thicknesses where the shell bends; refine as h/L decreases and check a thin shell's result on a second, finer mesh (docs/model-notes.md compares the interpolations on curved shells, where they differ).",
            names.join(" and "),
            rows[0].nx,
            rows[0].ny
        )?;
    }
    Ok(md)
}

/// The thinnest h/L at which every thicker strip of the row is within 1 % as well.
fn thinnest_within(cells: &[Cell]) -> Option<f64> {
    H_OVER_L
        .iter()
        .zip(cells)
        .take_while(|(_, c)| c.within())
        .last()
        .map(|(&r, _)| r)
}

fn row_finding(cells: &[Cell]) -> String {
    let mut parts = Vec::new();
    match thinnest_within(cells) {
        Some(r) => parts.push(format!("within 1 % down to h/L = {r:.0e}")),
        None => parts.push(format!("not within 1 % even at h/L = {:.0e}", H_OVER_L[0])),
    }
    let beyond = H_OVER_L.iter().zip(cells).skip_while(|(_, c)| c.within());
    for (r, c) in beyond {
        parts.push(match c {
            // Below a ratio of 0.005 the percentage would round to 100: the strip does not bend.
            Cell::Ratio(ratio, _) if *ratio < 0.005 => format!("locked at {r:.0e} (W / W_elastica = {ratio:.1e})"),
            Cell::Ratio(ratio, _) if *ratio < 1.0 => {
                format!("{:.0} % too stiff at {r:.0e}", 100.0 * (1.0 - ratio))
            }
            Cell::Ratio(ratio, _) => format!("{:.1} % too flexible at {r:.0e}", 100.0 * (ratio - 1.0)),
            Cell::Failed(_) => format!("no solution at {r:.0e} (the load path stops)"),
        });
    }
    parts.join("; ")
}
