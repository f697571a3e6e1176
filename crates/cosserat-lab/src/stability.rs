//! `cargo xtask stability`: the solver at the extremes. Sweeps one setting at a time around a small
//! twisting strip (`scenes/validation/stability_strip.toml`) — thickness, Young's modulus, Poisson
//! ratio, μ_c, L_c, time step, twist, sliver elements, element pair — plus a few combined corners, and
//! records for every cell whether it converged, the Newton iterations, the step reductions, the energy
//! drift over the hold phase and any non-finite value. Cells that fail are run again with the remedy a
//! user would apply. The locking study ([`crate::locking`]) is part of the same document,
//! `docs/stability.md`.

use crate::ensemble::{ENSEMBLE_SIZE, EnsembleResult, perturbations, run_ensemble};
use crate::locking;
use crate::runner::{RunOutcome, Runner, run_described};
use anyhow::Result;
use cosserat::RunDescription;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Arguments of `cargo xtask stability`.
#[derive(Debug, clap::Args)]
pub struct StabilityArgs {
    /// Only the cells whose group contains this (writes out/stability_partial.md instead).
    #[arg(long)]
    pub only: Option<String>,
    /// Reuse the locking study of the previous run (out/stability/locking.md) instead of running it.
    #[arg(long)]
    pub reuse_locking: bool,
    /// Perturbed variants per cell (docs/stability.md says how many were run).
    #[arg(long, default_value_t = ENSEMBLE_SIZE)]
    pub variants: usize,
    /// Write the matrix's runs (every cell and its perturbed variants) as a JSON list of run
    /// descriptions to this file and stop (the Python package's `cosserat.sweep.load_descriptions`
    /// reads it, e.g. to run the matrix on a Dask cluster).
    #[arg(long, value_name = "FILE")]
    pub emit_runs: Option<PathBuf>,
}

/// The base scene of the matrix.
pub const BASE_SCENE: &str = "scenes/validation/stability_strip.toml";

/// The settings of one cell (the base scene's values by default).
#[derive(Debug, Clone, PartialEq)]
pub struct Settings {
    /// Thickness \[m\] (strip length 0.1 m).
    pub thickness: f64,
    /// Young's modulus \[Pa\].
    pub youngs_modulus: f64,
    /// Poisson ratio.
    pub poisson_ratio: f64,
    /// `μ_c/μ`.
    pub mu_c_factor: f64,
    /// Internal length \[m\]; `None` keeps `L_c = 1e-3·h`.
    pub length_scale: Option<f64>,
    /// Time step \[s\].
    pub dt: f64,
    /// Full turns of the right end (at one turn per second).
    pub turns: f64,
    /// Quads along and across the strip.
    pub mesh: (usize, usize),
    /// Displacement and rotation element names.
    pub pair: (&'static str, &'static str),
    /// Strain interpolation (`material.strain_interpolation`; the matrix runs the paper's).
    pub interpolation: &'static str,
    /// Residual tolerance \[N, N·m\]; `None` keeps the scene's default (1e-7).
    pub tolerance: Option<f64>,
    /// Angular inertia density `ρ_θ` \[kg/m\] (the paper's scenes and the default use 0).
    pub angular_inertia_density: f64,
    /// Duration of the hold after the twist \[s\].
    pub hold: f64,
    /// Factor on the clamps' rotation penalty (1: 1e3 × E h³/12); the ensemble perturbs it.
    pub clamp_factor: f64,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            thickness: 1e-3,
            youngs_modulus: 1e9,
            poisson_ratio: 0.3,
            mu_c_factor: 1.0,
            length_scale: None,
            dt: 0.01,
            turns: 1.0,
            mesh: (10, 2),
            pair: ("tri6", "tri3"),
            interpolation: "paper",
            tolerance: None,
            angular_inertia_density: 0.0,
            hold: 0.5,
            clamp_factor: 1.0,
        }
    }
}

impl Settings {
    /// Scene overrides of these settings.
    pub fn overrides(&self) -> Vec<String> {
        let h = self.thickness;
        let lc = self.length_scale.unwrap_or(1e-3 * h);
        // Clamp penalty: 1e3 × the plate bending stiffness, so that E and h sweeps change the
        // material, not the clamp's relative stiffness.
        let k = self.clamp_factor * 1e3 * self.youngs_modulus * h.powi(3) / 12.0;
        let mut ov = vec![
            format!("material.thickness={h:e}"),
            format!("material.youngs_modulus={:e}", self.youngs_modulus),
            format!("material.poisson_ratio={}", self.poisson_ratio),
            format!("material.mu_c_factor={}", self.mu_c_factor),
            format!("material.length_scale={lc:e}"),
            format!("time.dt={:e}", self.dt),
            format!("time.end={}", self.turns + self.hold),
            format!("time.output_interval={}", self.dt.max(0.05)),
            format!("boundary.0.rotation.stiffness={k:e}"),
            format!("boundary.1.rotation.stiffness={k:e}"),
            format!("boundary.1.motion.rotate.angle=2*pi*min(t, {})", self.turns),
            format!("mesh.nx={}", self.mesh.0),
            format!("mesh.ny={}", self.mesh.1),
            format!("mesh.element={}", self.pair.0),
            format!("mesh.rotation_element={}", self.pair.1),
            format!("material.strain_interpolation={}", self.interpolation),
            "output.frames=false".to_string(),
        ];
        if self.angular_inertia_density > 0.0 {
            ov.push(format!(
                "material.angular_inertia_density={:e}",
                self.angular_inertia_density
            ));
        }
        if let Some(tol) = self.tolerance {
            ov.push(format!("solver.tolerance={tol:e}"));
        }
        ov
    }
}

/// One cell of the matrix.
#[derive(Debug, Clone)]
pub struct Cell {
    /// The swept setting (e.g. `h/L`), or `corner` for combined settings.
    pub group: &'static str,
    /// The value, e.g. `1e-5`.
    pub label: String,
    /// The settings.
    pub settings: Settings,
}

fn cell(group: &'static str, label: impl Into<String>, settings: Settings) -> Cell {
    Cell {
        group,
        label: label.into(),
        settings,
    }
}

/// The cells of the matrix: one-at-a-time sweeps, then combined corners.
pub fn matrix() -> Vec<Cell> {
    let base = Settings::default;
    let mut cells = Vec::new();
    for h_over_l in [1e-1, 1e-2, 1e-3, 1e-4, 1e-5] {
        let s = Settings {
            thickness: 0.1 * h_over_l,
            ..base()
        };
        cells.push(cell("h/L", format!("{h_over_l:.0e}"), s));
    }
    for e in [1e3, 1e5, 1e7, 1e9, 1e11] {
        cells.push(cell(
            "E [Pa]",
            format!("{e:.0e}"),
            Settings {
                youngs_modulus: e,
                ..base()
            },
        ));
    }
    for nu in [0.0, 0.3, 0.45, 0.49, 0.499] {
        cells.push(cell(
            "ν",
            format!("{nu}"),
            Settings {
                poisson_ratio: nu,
                ..base()
            },
        ));
    }
    for f in [0.0, 0.01, 1.0, 10.0] {
        cells.push(cell(
            "μ_c/μ",
            format!("{f}"),
            Settings {
                mu_c_factor: f,
                ..base()
            },
        ));
    }
    for (label, lc) in [
        ("0", 0.0),
        ("1e-3·h", 1e-6),
        ("1e-2·h", 1e-5),
        ("0.1·h", 1e-4),
        ("h", 1e-3),
    ] {
        cells.push(cell(
            "L_c",
            label,
            Settings {
                length_scale: Some(lc),
                ..base()
            },
        ));
    }
    for dt in [1e-4, 1e-3, 1e-2, 1e-1] {
        cells.push(cell("dt [s]", format!("{dt:.0e}"), Settings { dt, ..base() }));
    }
    for turns in [1.0, 4.0, 10.0] {
        cells.push(cell("twist [turns]", format!("{turns}"), Settings { turns, ..base() }));
    }
    cells.push(cell(
        "sliver (aspect 100)",
        "4×40 quads",
        Settings {
            mesh: (4, 40),
            ..base()
        },
    ));
    cells.extend(element_pairs());
    cells.extend(corners());
    cells
}

/// The three element pairs with the paper's strains, and the default discretisation.
fn element_pairs() -> Vec<Cell> {
    [
        ("Tri3/Tri3", ("tri3", "tri3"), "paper"),
        ("Tri6/Tri3", ("tri6", "tri3"), "paper"),
        ("Tri6/Tri6", ("tri6", "tri6"), "paper"),
        (
            "Tri6/Tri6 regge_stabilized (the default)",
            ("tri6", "tri6"),
            "regge_stabilized",
        ),
    ]
    .into_iter()
    .map(|(label, pair, interpolation)| {
        let settings = Settings {
            pair,
            interpolation,
            ..Settings::default()
        };
        cell("element pair", label, settings)
    })
    .collect()
}

/// The angular inertia density `ρ h²/12` of the base strip \[kg/m\] (ρ = 1000 kg/m³, h = 1 mm): the
/// rotational inertia of the cross-section, which regularises the rotations as dt shrinks.
pub const ROTATIONAL_INERTIA: f64 = 1000.0 * 1e-6 / 12.0;

/// The combined corners (also the cells the tests run).
pub fn corners() -> Vec<Cell> {
    let base = Settings::default;
    let corner = |label: &str, settings: Settings| cell("corner", label, settings);
    vec![
        corner(
            "thin and stiff, large dt: h/L = 1e-5, E = 1e11, dt = 0.1",
            Settings {
                thickness: 1e-6,
                youngs_modulus: 1e11,
                dt: 0.1,
                ..base()
            },
        ),
        corner(
            "μ_c = 0 and L_c = 0",
            Settings {
                mu_c_factor: 0.0,
                length_scale: Some(0.0),
                ..base()
            },
        ),
        corner(
            "ten turns on a coarse strip (4×1)",
            Settings {
                turns: 10.0,
                mesh: (4, 1),
                ..base()
            },
        ),
        corner(
            "ten turns on a coarse strip (4×1), ρ_θ = ρh²/12",
            Settings {
                turns: 10.0,
                mesh: (4, 1),
                angular_inertia_density: ROTATIONAL_INERTIA,
                ..base()
            },
        ),
        corner(
            "ten turns on a coarse strip (4×1), dt = 0.1",
            Settings {
                turns: 10.0,
                mesh: (4, 1),
                dt: 0.1,
                ..base()
            },
        ),
        corner(
            "nearly incompressible and thin: ν = 0.499, h/L = 1e-4",
            Settings {
                poisson_ratio: 0.499,
                thickness: 1e-5,
                ..base()
            },
        ),
        corner(
            "slivers, thin, four turns: 4×40, h/L = 1e-4",
            Settings {
                mesh: (4, 40),
                thickness: 1e-5,
                turns: 4.0,
                ..base()
            },
        ),
        corner(
            "soft and large dt, four turns: E = 1e3, dt = 0.1",
            Settings {
                youngs_modulus: 1e3,
                dt: 0.1,
                turns: 4.0,
                ..base()
            },
        ),
    ]
}

/// What a cell showed.
#[derive(Debug, Clone)]
pub struct CellResult {
    /// The run.
    pub outcome: RunOutcome,
    /// Average and largest Newton iterations per step.
    pub newton: Option<(f64, u64)>,
    /// Step reductions (dt halvings).
    pub reductions: Option<usize>,
    /// Largest relative increase of kinetic + elastic energy over the hold phase (negative: it only
    /// decreased), relative to its value at the start of the hold.
    pub energy_growth: Option<f64>,
    /// A non-finite value in the probes or the energies.
    pub non_finite: bool,
    /// Angle between the right end's director d₃ and its target at the end \[degrees\].
    pub twist_error_deg: Option<f64>,
    /// Smallest signed area ratio of any quadrature point (≤ 0: an inverted element).
    pub min_area_ratio: Option<f64>,
}

impl CellResult {
    /// Converged to the end, with finite values.
    pub fn is_ok(&self) -> bool {
        self.outcome.is_ok() && !self.non_finite && !self.inverted()
    }

    /// Whether some element turned inside out (a deformed-to-rest area ratio ≤ 0) during the run: the
    /// result is not to be trusted even if every step converged.
    pub fn inverted(&self) -> bool {
        self.min_area_ratio.is_some_and(|a| a <= 0.0)
    }
}

/// Reads what a cell showed from its outputs.
pub fn assess(settings: &Settings, outcome: RunOutcome) -> CellResult {
    let summary = outcome.summary.as_ref();
    let newton = summary.map(|s| (s.avg_newton_iterations, s.max_newton_iterations as u64));
    let reductions = summary.map(|s| s.n_step_reductions);
    let min_area_ratio = summary.and_then(|s| s.min_area_ratio);
    let mut non_finite = outcome
        .probes
        .as_ref()
        .is_some_and(|p| p.rows.iter().any(|r| r.iter().any(|v| !v.is_finite())));
    let energy_growth = summary.and_then(|s| {
        let e = &s.energy;
        let (t, kin, el) = (&e.t, &e.kinetic, &e.elastic);
        let total: Vec<(f64, f64)> = t.iter().zip(kin.iter().zip(el.iter())).map(|(t, (k, e))| (*t, k + e)).collect();
        let hold_start = settings.turns - 1e-9;
        let (_, e0) = *total.iter().find(|(t, _)| *t >= hold_start)?;
        let growth = total
            .iter()
            .filter(|(t, _)| *t >= hold_start)
            .map(|(_, e)| (e - e0) / e0.abs().max(f64::MIN_POSITIVE))
            .fold(f64::NEG_INFINITY, f64::max);
        Some(growth)
    });
    if energy_growth.is_some_and(|g| !g.is_finite()) {
        non_finite = true;
    }
    let twist_error_deg = outcome.probes.as_ref().and_then(|p| {
        let d = p.last_vec("right_director", ["d3x", "d3y", "d3z"]).ok()?;
        let theta = 2.0 * std::f64::consts::PI * settings.turns;
        let target = [0.0, -theta.sin(), theta.cos()];
        let dot = (d[0] * target[0] + d[1] * target[1] + d[2] * target[2]).clamp(-1.0, 1.0);
        Some(dot.acos().to_degrees())
    });
    CellResult {
        outcome,
        newton,
        reductions,
        energy_growth,
        non_finite,
        twist_error_deg,
        min_area_ratio,
    }
}

/// The run of a cell's settings into `dir`, on one thread.
pub fn cell_run(settings: &Settings, dir: &Path) -> RunDescription {
    // An absolute path lets tests run from any working directory.
    RunDescription::new(crate::workspace_root().join(BASE_SCENE), dir, &settings.overrides())
}

/// Runs one cell of the matrix.
///
/// # Errors
/// I/O failures of the output directory.
pub fn run_cell(runner: &Runner, settings: &Settings, dir: &Path) -> Result<CellResult> {
    let outcome = run_described(runner, &cell_run(settings, dir))?;
    Ok(assess(settings, outcome))
}

/// Every run of the matrix (as [`run_all`] runs them, in the same folders): each cell, then its
/// perturbed variants on their thread counts.
pub fn matrix_runs(out: &Path, only: Option<&str>, variants: usize) -> Vec<RunDescription> {
    let perturbed = perturbations(variants);
    let mut runs = Vec::new();
    for (i, c) in matrix().into_iter().enumerate() {
        if only.is_some_and(|f| !c.group.contains(f)) {
            continue;
        }
        let mut base = cell_run(&c.settings, &out.join(format!("cell_{i:02}")));
        base.label = format!("{} = {}", c.group, c.label);
        runs.push(base);
        for (k, p) in perturbed.iter().enumerate() {
            let dir = out.join(format!("cell_{i:02}_ensemble")).join(format!("variant_{k:02}"));
            let mut run = cell_run(&p.apply(&c.settings), &dir);
            run.label = format!("{} = {}, variant {k}", c.group, c.label);
            run.threads = Some(p.threads);
            runs.push(run);
        }
    }
    runs
}

/// The remedy for a failed cell, as changed settings and a sentence, if one is known.
pub fn remedy(settings: &Settings, result: &CellResult) -> Option<(Settings, String)> {
    let reason = result.outcome.reason();
    if settings.mu_c_factor == 0.0 && settings.length_scale == Some(0.0) {
        return Some((
            Settings {
                length_scale: Some(1e-3 * settings.thickness),
                ..settings.clone()
            },
            "the drilling rotation has no stiffness when μ_c = 0 and L_c = 0; give L_c > 0 (here 1e-3·h) or μ_c > 0"
                .into(),
        ));
    }
    // A dynamic step that could not be completed even after halving dt to its floor: the coiling snap
    // of a strip twisted with more than a turn per element length or with large steps of the driven
    // rotation, which the mesh cannot follow without folding an element. Rotational inertia changes
    // the snaps' dynamics, not what the mesh can follow, so it is not offered as a remedy.
    if reason.contains("failed after") {
        let mut fixed = settings.clone();
        let mut why = Vec::new();
        let turns_per_element = settings.turns / settings.mesh.0 as f64;
        if settings.mesh.1 < 2 {
            let nx = settings.mesh.0.max(settings.turns.ceil() as usize);
            fixed.mesh = (nx, 2);
            why.push(format!(
                "a strip one element wide with {turns_per_element:.1} turns per element along it does not get through the coiling snap: use two elements across and at most one turn per element along ({nx} × 2 quads)"
            ));
        } else if turns_per_element >= 1.0 {
            let nx = (4.0 * settings.turns).ceil() as usize;
            fixed.mesh.0 = nx;
            why.push(format!(
                "{turns_per_element:.1} turns per element along the strip: refine along it to a quarter turn per element ({nx} quads)"
            ));
        }
        if settings.dt > 0.01 {
            fixed.dt = 0.01;
            why.push(format!(
                "steps of {:.0}° of end rotation are too large once the strip coils: dt = 0.01 s (3.6° per step)",
                360.0 * settings.dt
            ));
        }
        if why.is_empty() {
            return None;
        }
        return Some((fixed, why.join("; ")));
    }
    if reason.contains("no convergence") {
        // The absolute residual tolerance can lie below the round-off floor of stiff, fine problems
        // (about 1e-16 E h per node times the element count along the strip).
        let tol = 1e-11 * settings.youngs_modulus * settings.thickness;
        if tol > settings.tolerance.unwrap_or(1e-7) {
            return Some((
                Settings {
                    tolerance: Some(tol),
                    ..settings.clone()
                },
                format!(
                    "the residual stalls at its round-off floor; scale the tolerance with the membrane stiffness, solver.tolerance = 1e-11·E·h = {tol:.1e}"
                ),
            ));
        }
    }
    None
}

fn fmt_opt<T>(v: Option<T>, f: impl Fn(T) -> String) -> String {
    v.map_or("–".into(), f)
}

fn row(c: &Cell, r: &CellResult, e: &EnsembleResult) -> String {
    let status = if r.is_ok() {
        "ok".to_string()
    } else if r.non_finite {
        "**non-finite**".to_string()
    } else if r.outcome.is_ok() && r.inverted() {
        "**inverted elements**".to_string()
    } else {
        format!("**failed**: {}", r.outcome.reason())
    };
    format!(
        "| {} | {} | {status} | {}{} | {} | {} | {} | {} | {} | {} | {} | {} |",
        c.group,
        c.label,
        e.rate(),
        if e.inverted > 0 {
            format!(" ({} inverted)", e.inverted)
        } else {
            String::new()
        },
        e.max_newton,
        fmt_opt(r.outcome.summary.as_ref(), |s| s.n_steps.to_string()),
        fmt_opt(r.newton, |(a, m)| format!("{a:.2} / {m}")),
        fmt_opt(r.reductions, |n| n.to_string()),
        fmt_opt(r.energy_growth, |g| format!("{g:+.1e}")),
        fmt_opt(r.twist_error_deg, |d| format!("{d:.2}°")),
        fmt_opt(r.min_area_ratio, |a| format!("{a:.3}")),
        fmt_opt(r.outcome.wall_seconds(), |w| format!("{w:.2} s")),
    )
}

/// One cell's unperturbed run and its ensemble.
struct CellRecord {
    cell: Cell,
    base: CellResult,
    ensemble: EnsembleResult,
}

/// The remedy line for a failed cell (runs the remedy), or `None` for a cell that passed.
fn remedy_line(runner: &Runner, c: &Cell, r: &CellResult, dir: &Path) -> Result<Option<String>> {
    if r.is_ok() {
        return Ok(None);
    }
    let line = match remedy(&c.settings, r) {
        Some((fixed, why)) => {
            let r2 = run_cell(runner, &fixed, dir)?;
            format!(
                "- **{} = {}**: {why}. With the remedy: {}.",
                c.group,
                c.label,
                if r2.is_ok() {
                    format!(
                        "converged, {:.2} Newton iterations per step, {} step reductions",
                        r2.newton.map_or(0.0, |n| n.0),
                        r2.reductions.unwrap_or(0)
                    )
                } else {
                    format!("still failing ({})", r2.outcome.reason())
                }
            )
        }
        None if r.outcome.is_ok() && r.inverted() => format!(
            "- **{} = {}**: every step converged, but elements turned inside out (smallest area ratio {:.3}); the run warns about it. A run with inverted elements must not be trusted: refine across the strip (at least two elements) or reduce the twist per element.",
            c.group,
            c.label,
            r.min_area_ratio.unwrap_or(f64::NAN)
        ),
        None => format!(
            "- **{} = {}**: no remedy known: {}",
            c.group,
            c.label,
            r.outcome.reason()
        ),
    };
    Ok(Some(line))
}

/// Runs every selected cell unperturbed (with `runner`) and as an ensemble of `variants` perturbed
/// runs (in this process, one or two threads each).
fn run_matrix(runner: &Runner, out: &Path, only: Option<&str>, variants: usize) -> Result<Vec<CellRecord>> {
    let perturbed = perturbations(variants);
    let mut records = Vec::new();
    for (i, c) in matrix().into_iter().enumerate() {
        if only.is_some_and(|f| !c.group.contains(f)) {
            continue;
        }
        eprintln!("stability: {} = {} ...", c.group, c.label);
        let base = run_cell(runner, &c.settings, &out.join(format!("cell_{i:02}")))?;
        let ensemble = run_ensemble(&c.settings, &perturbed, &out.join(format!("cell_{i:02}_ensemble")))?;
        eprintln!(
            "  {} (ensemble {})",
            if base.is_ok() { "ok" } else { "failed" },
            ensemble.rate()
        );
        records.push(CellRecord {
            cell: c,
            base,
            ensemble,
        });
    }
    Ok(records)
}

/// Runs the matrix with its ensembles and the locking study; returns the markdown of
/// `docs/stability.md`.
///
/// # Errors
/// I/O failures.
pub fn run_all(
    runner: &Runner,
    out: &Path,
    images: &Path,
    only: Option<&str>,
    reuse_locking: bool,
    variants: usize,
) -> Result<String> {
    let started = std::time::Instant::now();
    let records = run_matrix(runner, out, only, variants)?;
    let mut table = String::new();
    let mut remedies = String::new();
    for (i, rec) in records.iter().enumerate() {
        writeln!(table, "{}", row(&rec.cell, &rec.base, &rec.ensemble))?;
        let dir = out.join(format!("cell_{i:02}_remedy"));
        if let Some(line) = remedy_line(runner, &rec.cell, &rec.base, &dir)? {
            writeln!(remedies, "{line}")?;
        }
    }
    let saved = out.join("locking.md");
    let locking = if reuse_locking && saved.exists() {
        std::fs::read_to_string(&saved)?
    } else if only.is_none_or(|f| "locking".contains(f)) {
        let md = locking::run_all(runner, &out.join("locking"), images)?;
        std::fs::write(&saved, &md)?;
        md
    } else {
        String::new()
    };
    let mut md = String::new();
    writeln!(md, "# Stability at the extremes\n")?;
    writeln!(
        md,
        "Generated by `cargo xtask stability{}{}` ({:.0} s, release build; the unperturbed run of each cell on one thread in its own process, so that a crash is recorded rather than fatal, the perturbed variants in the study's process{}).\n",
        if reuse_locking { " --reuse-locking" } else { "" },
        if variants == ENSEMBLE_SIZE {
            String::new()
        } else {
            format!(" --variants {variants}")
        },
        started.elapsed().as_secs_f64(),
        if reuse_locking {
            "; the locking study is the previous run's, about 20 minutes of its own"
        } else {
            ""
        }
    )?;
    writeln!(
        md,
        "## The matrix\n\nBase scene `{BASE_SCENE}`: a 100 mm × 10 mm strip, h = 1 mm, E = 1 GPa, ν = 0.3, ρ = 1000 kg/m³, L_c = 1e-3·h, μ_c = μ, 10 × 2 Tri6/Tri3 quads, both ends clamped, the right end turned about the centre line at one turn per second, then held for 0.5 s without damping; dt = 10 ms with step halving on failure (adaptive), default solver settings (no `solver.tolerance`: residuals relative to the load scale). Each row changes one setting (the corners several). The clamps' rotation penalty stays at 1e3 × E h³/12.\n\n{}\n\nColumns: *ensemble* is the number of perturbed variants that completed with finite values, of {variants} (variants with an inverted element are counted as completed and named in brackets); *ens. max* the largest Newton iterations of a step over the variants. The other columns are the unperturbed run's: *Newton* is the average / largest number of iterations per step; *reductions* the number of dt halvings; *energy growth* the largest relative increase of kinetic + elastic energy during the hold phase over its value at the start of the hold (the clamps' penalty energy is not included; backward Euler only dissipates, so a positive value above round-off would signal an instability); *twist error* the angle between the right end's director d₃ and its prescribed direction at the end; *min area ratio* the smallest ratio of deformed to rest area over all quadrature points and output times (≤ 0 means an inverted element). Non-finite values are looked for in the probes and the energies.\n",
        ensemble_text(variants)
    )?;
    writeln!(
        md,
        "| setting | value | status | ensemble | ens. max | steps | Newton avg / max | reductions | energy growth | twist error | min area ratio | wall |\n|---|---|---|---|---|---|---|---|---|---|---|---|"
    )?;
    md.push_str(&table);
    md.push('\n');
    if !remedies.is_empty() {
        writeln!(md, "### Failed cells and their remedies\n\n{remedies}")?;
    }
    md.push_str(&findings(&records, variants));
    md.push_str(ADVICE);
    md.push_str(&locking);
    Ok(md)
}

/// How the ensemble is drawn.
fn ensemble_text(variants: usize) -> String {
    let full = if variants == ENSEMBLE_SIZE {
        String::new()
    } else {
        format!(" (this page was generated with {variants} of the {ENSEMBLE_SIZE} variants the study runs by default)")
    };
    format!(
        "Every cell is also run as an ensemble of {variants} perturbed variants{full}: the clamps' rotation penalty and the time step each changed by a relative amount of magnitude between 1e-7 and 1e-3 (log-uniform, either sign, from a fixed seed), on one and two threads alternately (which changes the order of the parallel sums). A cell that completes only for some roundings is not robust; `cargo test --release -p cosserat-lab --test stability_ensemble` runs the same {ENSEMBLE_SIZE} variants of every cell in CI, on shortened settings that keep each cell's hard feature."
    )
}

/// The findings, generated from the records so that they cannot contradict the table.
fn findings(records: &[CellRecord], variants: usize) -> String {
    let mut s = String::from("\n## What the matrix shows\n\n");
    let m = records.len();
    let robust = records.iter().filter(|r| r.ensemble.all_completed()).count();
    let base_ok = records.iter().filter(|r| r.base.is_ok()).count();
    let _ = write!(
        s,
        "- **Ensemble.** {robust} of {m} cells complete all {variants} perturbed variants."
    );
    if let Some(worst) = records.iter().min_by_key(|r| r.ensemble.completed)
        && !worst.ensemble.all_completed()
    {
        let failing: Vec<String> = records
            .iter()
            .filter(|r| !r.ensemble.all_completed())
            .map(|r| format!("{} = {} ({})", r.cell.group, r.cell.label, r.ensemble.rate()))
            .collect();
        let f = &worst.ensemble.failures[0];
        let p = &f.perturbation;
        let _ = write!(
            s,
            " The worst cell is {} = {} with {}; cells with failed variants: {}. A failed variant of the worst cell (variant {}: clamp ×(1{:+.1e}), dt ×(1{:+.1e}), {} thread(s)): {}.",
            worst.cell.group,
            worst.cell.label,
            worst.ensemble.rate(),
            failing.join(", "),
            f.index,
            p.clamp,
            p.dt,
            p.threads,
            f.reason
        );
    }
    let inverted: Vec<String> = records
        .iter()
        .filter(|r| r.ensemble.inverted > 0 || r.base.inverted())
        .map(|r| format!("{} = {}", r.cell.group, r.cell.label))
        .collect();
    if inverted.is_empty() {
        let _ = writeln!(s, " No run went on through an inverted element.");
    } else {
        let _ = writeln!(
            s,
            " Runs that completed through inverted elements (not to be trusted): {}.",
            inverted.join(", ")
        );
    }
    let _ = writeln!(
        s,
        "- **Unperturbed runs.** {base_ok} of {m} cells converge to the end with finite values and no inverted element."
    );
    if let Some(hardest) = records.iter().max_by_key(|r| r.ensemble.max_newton) {
        let _ = writeln!(
            s,
            "- **Hardest steps.** The most Newton iterations in one step, over all runs, were {} ({} = {}); the unperturbed runs average {:.2} to {:.2} iterations per step.",
            hardest.ensemble.max_newton.max(hardest.base.newton.map_or(0, |n| n.1)),
            hardest.cell.group,
            hardest.cell.label,
            records
                .iter()
                .filter_map(|r| r.base.newton.map(|n| n.0))
                .fold(f64::INFINITY, f64::min),
            records.iter().filter_map(|r| r.base.newton.map(|n| n.0)).fold(0.0, f64::max),
        );
    }
    let growth = records
        .iter()
        .filter_map(|r| r.base.energy_growth.map(|g| (g, r)))
        .max_by(|a, b| a.0.total_cmp(&b.0));
    if let Some((g, r)) = growth {
        let _ = writeln!(
            s,
            "- **Energy.** Without damping and with the ends held, kinetic plus elastic energy grew by at most a relative {g:.1e} over the hold phase ({} = {}); small changes are exchanges with the clamps' penalty energy, which the summary's energies leave out.",
            r.cell.group, r.cell.label
        );
    }
    s
}

/// Advice that holds independently of the measured numbers.
const ADVICE: &str = "
## What to do at the extremes

- **μ_c = 0 together with L_c = 0** leaves the drilling rotation (about the normal) without any stiffness of its own: it is held only through the clamps, and the interior drilling rotation is not determined by the energy. Give any L_c > 0 (1e-3·h changes the bending stiffness by a relative 1.2e-5) or μ_c > 0. The simulator warns about this combination when it builds the scene (on stderr and in `summary.json` under `warnings`), as it does about elements much longer than the thickness (locking, below).
- **Coiling.** A twisted strip buckles into a coil after a few turns, and the coil snaps as the twist grows. Use at least two elements across a strip that coils, at most about one turn of twist per element along it, and steps of the driven rotation of a few degrees (dt = 0.01 s at one turn per second). Giving the rotations inertia (`material.angular_inertia_density = ρh²/12`) changes the dynamics of the snaps. The solver keeps every element right side out (docs/time-integration.md, \"Inverted elements\"): a mesh too coarse for the coil stops at the step that would fold an element, with the steps before kept and the reason in `summary.json`, instead of going on with a result not to be trusted.
- **Indefinite Hessians.** Where the Hessian of a time step is not positive definite, Newton's method shifts it to positive definiteness by default (`solver.indefinite_hessian = \"shift\"`), a trust-region step that gets through the snaps of this matrix (quasi-static runs, the thin-limit table among them, take Newton's own steps by default, docs/time-integration.md). A shifted descent cannot settle on a solution that is a saddle of the step's energy, and a finer strip driven through its twist (the paper's Twisting strip, 40 × 4 quads, whose massless rotations pass such saddles) then has its steps halved again and again, and with the default tolerance stops at the first coil: there `\"factorise\"` (the reference code's treatment, Newton's own steps throughout) or `\"adaptive\"` (Newton's own steps while they pass in full, the shift after) converge where the shift does not. The matrix runs the default.
- **Tolerances.** Without `solver.tolerance` the residual is judged relative to the step's load scale (external loads, reactions, or the first residual; a quasi-static level takes them at the last equilibrium, not at its predicted start), with a floor from the assembled stiffness and machine precision; a step that stagnates at that floor is accepted with a warning in `summary.json`. Set `solver.tolerance` only to require an absolute residual in force units.

";

/// Runs the stability command.
///
/// # Errors
/// I/O failures.
pub fn run(args: &StabilityArgs) -> Result<i32> {
    if let Some(path) = &args.emit_runs {
        let runs = matrix_runs(Path::new("out/stability"), args.only.as_deref(), args.variants);
        cosserat::run_description::write_runs(path, &runs)?;
        eprintln!("wrote {} run descriptions to {}", runs.len(), path.display());
        return Ok(0);
    }
    let runner = Runner::current_exe()?;
    let partial = args.only.is_some();
    let images = PathBuf::from(if partial { "out/img" } else { "docs/img" });
    std::fs::create_dir_all(&images)?;
    let md = run_all(
        &runner,
        Path::new("out/stability"),
        &images,
        args.only.as_deref(),
        args.reuse_locking,
        args.variants,
    )?;
    let path = PathBuf::from(if partial {
        "out/stability_partial.md"
    } else {
        "docs/stability.md"
    });
    std::fs::write(&path, md)?;
    eprintln!("wrote {}", path.display());
    Ok(0)
}
