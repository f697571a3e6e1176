//! `cargo xtask study <target>`: the speed–accuracy trade. Runs a refinement ladder for each element
//! pair (and for the plate and the shell model on curved rest states), measures the error against the
//! reference (or against a Richardson extrapolation when there is none), the wall time, the Newton
//! iterations and the peak memory, and writes the table, the Pareto front of error against time and the
//! observed convergence orders into `docs/speed-accuracy.md`.
//!
//! Each ladder point runs in its own child process on one thread (see [`crate::runner`]), so the peak
//! memory is that run's alone and a crash cannot end the study. Results of each target are kept as a
//! markdown section in `out/study/<target>.md`; the document is assembled from every section present,
//! so targets can be re-run one at a time.

use crate::obstacle::{Benchmark, course};
use crate::plot::{Mark, Plot, Series};
use crate::problem::{Discretisation, Interpolation, Pair, Problem, compare, registry};
use crate::runner::{RunOutcome, Runner, run_described};
use anyhow::{Result, bail};
use cosserat::RunDescription;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Arguments of `cargo xtask study`.
#[derive(Debug, clap::Args)]
pub struct StudyArgs {
    /// Targets by name (`--list` prints them all): the validation problems (e.g.
    /// `sze_cantilever_end_shear`, `thin_cantilever_end_shear`), the shell obstacle course
    /// (`pinched_hemisphere`, `pinched_cylinder`, `scordelis_lo_roof`) or paper experiments
    /// (`plate_under_load`).
    pub targets: Vec<String>,
    /// Every target.
    #[arg(long)]
    pub all: bool,
    /// The two coarsest meshes of each ladder only (results go to out/, not docs/).
    #[arg(long)]
    pub quick: bool,
    /// List the targets.
    #[arg(long)]
    pub list: bool,
    /// Only reassemble docs/speed-accuracy.md from the saved sections of earlier runs.
    #[arg(long)]
    pub assemble: bool,
    /// Write the chosen targets' runs as a JSON list of run descriptions to this file and stop (the
    /// Python package's `cosserat.sweep.load_descriptions` reads it, e.g. to run the study on a Dask cluster).
    /// These are the ladders; the finer meshes the study adds for the paper's pairs on the obstacle course
    /// depend on the measured times, so they are not listed.
    #[arg(long, value_name = "FILE")]
    pub emit_runs: Option<PathBuf>,
}

/// The discretisations of the study: every pair with the paper's interpolation, the paper's pair with
/// the stabilised projection and with Regge membrane strains plus stabilised shear and drilling, and the
/// quadratic pair with the latter (the default, on the 3-point rule, locking-free on the obstacle course,
/// docs/validation.md), also on the six-point rule.
const STUDIED: [Discretisation; 7] = [
    Discretisation::paper(Pair::Tri3Tri3),
    Discretisation::paper(Pair::Tri6Tri3),
    Discretisation::new(Pair::Tri6Tri3, Interpolation::Stabilized),
    Discretisation::new(Pair::Tri6Tri3, Interpolation::ReggeStabilized),
    Discretisation::paper(Pair::Tri6Tri6),
    Discretisation::DEFAULT,
    Discretisation::DEFAULT.on_six_points(),
];

impl Discretisation {
    /// Plot colour; `second_model` for the plate model beside the shell's on curved problems.
    fn color(self, second_model: bool) -> usize {
        if self.quadrature_degree.is_some() {
            return 10;
        }
        match (self.interpolation, second_model) {
            (Interpolation::Paper, false) => self.pair.color(),
            (Interpolation::Paper, true) => self.pair.color() + 3,
            (Interpolation::ReggeStabilized, false) if self.pair == Pair::Tri6Tri6 => 0,
            (Interpolation::ReggeStabilized, true) if self.pair == Pair::Tri6Tri6 => 5,
            (Interpolation::ReggeStabilized, false) => 9,
            (Interpolation::ReggeStabilized, true) => 6,
            (_, false) => 7,
            (_, true) => 8,
        }
    }
}

/// A ladder of meshes: `(label, overrides, element length h)` per mesh.
pub type Ladder = Vec<(String, Vec<String>, f64)>;

/// A quantity read from a finished run of a paper experiment (no published reference).
type Quantity = fn(&RunOutcome) -> Option<f64>;

/// What a study target is compared with.
#[derive(Debug, Clone)]
pub enum Target {
    /// A validation problem with its reference solution.
    Validation(Problem),
    /// A benchmark of the shell obstacle course (thin curved shells, a published reference value).
    Course(Benchmark),
    /// A paper experiment: a scalar quantity, compared with its Richardson extrapolation.
    Experiment {
        /// Name.
        name: &'static str,
        /// Title.
        title: &'static str,
        /// Scene.
        scene: &'static str,
        /// What is measured.
        quantity_note: &'static str,
        /// The quantity.
        quantity: Quantity,
        /// Ladder per pair: (label, overrides, h).
        ladder: fn(Pair) -> Ladder,
    },
}

impl Target {
    /// The target's name.
    pub fn name(&self) -> &str {
        match self {
            Target::Validation(p) => p.name,
            Target::Course(b) => b.name,
            Target::Experiment { name, .. } => name,
        }
    }

    fn title(&self) -> &str {
        match self {
            Target::Validation(p) => p.title,
            Target::Course(b) => b.title,
            Target::Experiment { title, .. } => title,
        }
    }

    /// The smallest error the reference resolves (see [`Problem::resolution`]); 0 for a closed form.
    fn resolution(&self) -> f64 {
        match self {
            Target::Validation(p) => p.resolution.unwrap_or(0.0),
            Target::Course(_) | Target::Experiment { .. } => 0.0,
        }
    }
}

fn plate_ladder(pair: Pair) -> Ladder {
    let nys: &[usize] = match pair {
        Pair::Tri3Tri3 => &[2, 4, 8, 16, 32],
        _ => &[1, 2, 4, 8],
    };
    nys.iter()
        .map(|&ny| {
            (
                format!("{}×{ny}", 10 * ny),
                vec![format!("mesh.nx={}", 10 * ny), format!("mesh.ny={ny}")],
                0.1 / (10 * ny) as f64,
            )
        })
        .collect()
}

/// All study targets.
pub fn targets() -> Vec<Target> {
    let mut t: Vec<Target> = registry().into_iter().map(Target::Validation).collect();
    t.extend(course().into_iter().map(Target::Course));
    t.push(Target::Experiment {
        name: "plate_under_load",
        title: "Plate under load (paper experiment, dynamic)",
        scene: "scenes/plate_under_load.toml",
        quantity_note: "the tip deflection `tip.uz` at t = 2 s",
        quantity: |o| o.probes.as_ref().and_then(|p| p.last("tip.uz").ok()),
        ladder: plate_ladder,
    });
    t
}

/// The runs of a target and, for experiments, the extrapolated reference with the pair it came from.
type TargetRuns = (Vec<StudyRun>, Option<(Pair, f64)>);

/// One ladder point of a study.
#[derive(Debug, Clone)]
pub struct StudyRun {
    /// Element pair and strain interpolation.
    pub discretisation: Discretisation,
    /// Model (`plate` or `shell`).
    pub model: &'static str,
    /// Mesh label.
    pub mesh: String,
    /// Element length \[m\].
    pub h: f64,
    /// The outcome.
    pub outcome: RunOutcome,
    /// The measured quantity (first component at the last level, or the experiment's quantity).
    pub quantity: Option<f64>,
    /// Error against the reference (validation) or the extrapolated value (experiments).
    pub error: Option<f64>,
}

impl StudyRun {
    fn series_label(&self) -> String {
        format!("{} {}", self.discretisation.label(), self.model)
    }
}

/// Richardson extrapolation from three values on meshes halved in size: `(limit, order)`, if the
/// differences shrink monotonically.
pub fn richardson(q: [f64; 3]) -> Option<(f64, f64)> {
    let (d1, d2) = (q[1] - q[0], q[2] - q[1]);
    if d1 == 0.0 || d2 == 0.0 || d1.signum() != d2.signum() || d2.abs() >= d1.abs() {
        return None;
    }
    let ratio = d1 / d2;
    Some((q[2] + d2 / (ratio - 1.0), ratio.log2()))
}

/// Observed orders between successive ladder points: `log(e_i/e_{i+1}) / log(h_i/h_{i+1})`.
pub fn observed_orders(points: &[(f64, f64)]) -> Vec<f64> {
    points
        .windows(2)
        .map(|w| (w[0].1 / w[1].1).ln() / (w[0].0 / w[1].0).ln())
        .collect()
}

/// Indices of the runs on the Pareto front of (time, error): no other run is both faster and more
/// accurate.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<usize> {
    let mut idx: Vec<usize> = (0..points.len())
        .filter(|&i| points[i].0.is_finite() && points[i].1.is_finite())
        .collect();
    idx.sort_by(|&a, &b| points[a].0.total_cmp(&points[b].0));
    let mut front = Vec::new();
    let mut best = f64::INFINITY;
    for i in idx {
        if points[i].1 < best {
            best = points[i].1;
            front.push(i);
        }
    }
    front
}

/// One planned run of a study target: its description and where it sits in the ladders.
#[derive(Debug, Clone)]
pub struct PlannedRun {
    /// The run (scene, overrides, output folder; labelled `target model pair mesh`).
    pub run: RunDescription,
    /// The element pair and strain interpolation.
    pub discretisation: Discretisation,
    /// `shell` or `plate`.
    pub model: &'static str,
    /// The mesh's label in its ladder.
    pub mesh: String,
    /// The element length.
    pub h: f64,
}

/// The runs of a target's ladders (every pair, both models where the problem is curved), with their
/// outputs under `out`.
pub fn planned_runs(target: &Target, out: &Path, quick: bool) -> Vec<PlannedRun> {
    let models: &[&'static str] = match target {
        Target::Validation(p) if p.curved => &["shell", "plate"],
        // The course's shells are curved and thin; the plate model is not what they test.
        Target::Course(_) => &["shell"],
        _ => &["plate"],
    };
    let mut planned = Vec::new();
    for &model in models {
        for discretisation in STUDIED {
            let pair = discretisation.pair;
            let ladder: Ladder = match target {
                Target::Validation(p) => (p.ladder)(pair).into_iter().map(|m| (m.label, m.overrides, m.h)).collect(),
                Target::Course(b) => b.ladder.iter().map(|m| (m.label.clone(), m.overrides.clone(), m.h)).collect(),
                Target::Experiment { ladder, .. } => ladder(pair),
            };
            let n = if quick { 2.min(ladder.len()) } else { ladder.len() };
            for (label, mesh_ov, h) in ladder.into_iter().take(n) {
                planned.push(plan(target, out, model, discretisation, (label, mesh_ov, h)));
            }
        }
    }
    planned
}

/// One run of a target: `model` with `discretisation` on one mesh `(label, overrides, h)`.
fn plan(
    target: &Target,
    out: &Path,
    model: &'static str,
    discretisation: Discretisation,
    (label, mesh_ov, h): (String, Vec<String>, f64),
) -> PlannedRun {
    let scene = match target {
        Target::Validation(p) => p.scene,
        Target::Course(b) => b.scene,
        Target::Experiment { scene, .. } => scene,
    };
    let mut ov = discretisation.overrides();
    ov.extend(mesh_ov);
    ov.push("output.frames=false".into());
    ov.push(format!("material.model={model}"));
    let name = discretisation.label().replace(['/', ' '], "_");
    let dir = out.join(target.name()).join(format!("{model}_{name}_{label}"));
    let mut run = RunDescription::new(scene, dir, &ov);
    run.label = format!("{} {model} {} {label}", target.name(), discretisation.label());
    PlannedRun {
        run,
        discretisation,
        model,
        mesh: label,
        h,
    }
}

fn run_target(target: &Target, runner: &Runner, out: &Path, quick: bool) -> Result<TargetRuns> {
    let mut runs = Vec::new();
    for planned in planned_runs(target, out, quick) {
        runs.push(measure(target, runner, planned)?);
    }
    if !quick {
        extend_paper_ladders(target, runner, out, &mut runs)?;
    }
    let mut extrapolated = None;
    if let Target::Experiment { .. } = target {
        // Reference: Richardson extrapolation of the finest three meshes of the highest-order pair
        // whose differences shrink monotonically.
        let mut reference = None;
        for pair in [Pair::Tri6Tri6, Pair::Tri6Tri3] {
            let q: Vec<f64> = runs
                .iter()
                .filter(|r| r.discretisation == Discretisation::paper(pair))
                .filter_map(|r| r.quantity)
                .collect();
            if q.len() >= 3
                && let Some((limit, _)) = richardson([q[q.len() - 3], q[q.len() - 2], q[q.len() - 1]])
            {
                reference = Some((pair, limit));
                break;
            }
        }
        if let Some((_, limit)) = reference {
            for r in &mut runs {
                r.error = r.quantity.map(|q| (q - limit).abs() / limit.abs());
            }
        }
        extrapolated = reference;
    }
    Ok((runs, extrapolated))
}

/// Whether the ladder of `discretisation` goes on to a finer mesh: none of its runs is within 1 %, and
/// its last run gave a value (it finished) within [`EXTENSION_BUDGET`] times `best`.
fn ladder_goes_on(runs: &[StudyRun], discretisation: Discretisation, best: f64) -> bool {
    let own = || runs.iter().filter(|r| r.discretisation == discretisation);
    let reached = own().any(|r| r.error.is_some_and(|e| e <= 1e-2));
    let affordable = own()
        .next_back()
        .is_some_and(|r| r.error.is_some() && r.outcome.outer_seconds <= EXTENSION_BUDGET * best);
    !reached && affordable
}

/// Runs one planned run and reads its quantity and error.
fn measure(target: &Target, runner: &Runner, planned: PlannedRun) -> Result<StudyRun> {
    eprintln!("{} ...", planned.run.label);
    let outcome = run_described(runner, &planned.run)?;
    let (quantity, error) = match target {
        Target::Validation(p) => match outcome.probes.as_ref().filter(|_| outcome.is_ok()) {
            Some(probes) => match compare(p, probes, p.study_against_second) {
                Ok((e, t)) => (t.last().map(|l| l.1[0].0), Some(e.max())),
                Err(_) => (None, None),
            },
            None => (None, None),
        },
        Target::Course(b) => {
            let value = outcome
                .probes
                .as_ref()
                .filter(|_| outcome.is_ok())
                .and_then(|p| (b.read)(p).ok());
            (value, value.map(|v| (v / b.reference - 1.0).abs()))
        }
        Target::Experiment { quantity, .. } => (if outcome.is_ok() { quantity(&outcome) } else { None }, None),
    };
    if !outcome.is_ok() {
        eprintln!("  failed: {}", outcome.reason());
    }
    Ok(StudyRun {
        discretisation: planned.discretisation,
        model: planned.model,
        mesh: planned.mesh,
        h: planned.h,
        outcome,
        quantity,
        error,
    })
}

/// How many times the cheapest 1 % run of any discretisation a run with the paper's interpolation may
/// cost before its ladder stops: the atlas asks whether the alternatives are this much cheaper.
const EXTENSION_BUDGET: f64 = 4.0;

/// On a benchmark of the obstacle course, goes on refining each pair's ladder with the paper's
/// interpolation while none of its runs is within 1 %, its last run finished, and that run cost less
/// than [`EXTENSION_BUDGET`] times the cheapest 1 % run of any discretisation: a ladder that stops short
/// of 1 % while still cheap bounds the paper's cost by its finest run only.
fn extend_paper_ladders(target: &Target, runner: &Runner, out: &Path, runs: &mut Vec<StudyRun>) -> Result<()> {
    let Target::Course(b) = target else {
        return Ok(());
    };
    let Some(best) = cheapest(runs.iter(), 1e-2).map(|r| r.outcome.outer_seconds) else {
        return Ok(());
    };
    for discretisation in STUDIED.into_iter().filter(|d| d.interpolation == Interpolation::Paper) {
        for mesh in &b.extension {
            if !ladder_goes_on(runs, discretisation, best) {
                break;
            }
            let mesh = (mesh.label.clone(), mesh.overrides.clone(), mesh.h);
            let run = measure(target, runner, plan(target, out, "shell", discretisation, mesh))?;
            let after_own = runs
                .iter()
                .rposition(|r| r.discretisation == discretisation)
                .map_or(runs.len(), |i| i + 1);
            runs.insert(after_own, run);
        }
    }
    Ok(())
}

fn fmt_e(e: Option<f64>) -> String {
    e.map_or("–".into(), |e| format!("{e:.2e}"))
}

fn section(target: &Target, runs: &[StudyRun], extrapolated: Option<(Pair, f64)>, images: &Path) -> Result<String> {
    let mut md = String::new();
    writeln!(md, "\n## {}\n", target.title())?;
    intro(&mut md, target, extrapolated)?;
    let points: Vec<(f64, f64)> = runs
        .iter()
        .map(|r| (r.outcome.outer_seconds, r.error.unwrap_or(f64::NAN)))
        .collect();
    let front = pareto_front(&points);
    runs_table(&mut md, runs, &front)?;
    cheapest_table(&mut md, runs, target.resolution())?;
    let mut groups: Vec<(&str, Discretisation)> = Vec::new();
    for r in runs {
        if !groups.contains(&(r.model, r.discretisation)) {
            groups.push((r.model, r.discretisation));
        }
    }
    orders_table(&mut md, runs, &groups)?;
    plots(&mut md, target, runs, &groups, (&points, &front), images)?;
    Ok(md)
}

/// What the section's error is measured against.
fn intro(md: &mut String, target: &Target, extrapolated: Option<(Pair, f64)>) -> Result<()> {
    match target {
        Target::Validation(p) => writeln!(
            md,
            "Scene `{}`. Error: the largest over all load levels and compared quantities of |u − u_ref| / max |u_ref|, against {}.\n",
            p.scene,
            if p.study_against_second {
                "the closed form beside the published table (the table's 3 decimals cannot resolve errors below about 1e-3)"
            } else {
                p.reference_note
            }
        )?,
        Target::Course(b) => writeln!(
            md,
            "Scene `{}` (the shell obstacle course of docs/validation.md, shell model). Error: |v / v_ref − 1| of the {}, against the published {}.\n",
            b.scene, b.quantity, b.reference
        )?,
        Target::Experiment {
            scene, quantity_note, ..
        } => {
            let limit = extrapolated.map_or("no monotone ladder to extrapolate".into(), |(pair, v)| {
                format!("{v:.6e}, from the {} ladder", pair.label())
            });
            writeln!(
                md,
                "Scene `{scene}`. Quantity: {quantity_note}. No published reference: the error is relative to the Richardson extrapolation of the finest three meshes of the highest-order pair whose differences shrink monotonically ({limit}).\n"
            )?
        }
    }
    Ok(())
}

/// Every run of the ladders, with the Pareto front marked.
fn runs_table(md: &mut String, runs: &[StudyRun], front: &[usize]) -> Result<()> {
    writeln!(
        md,
        "| model | discretisation | mesh | cells | DOFs | error | solve wall | total wall | Newton it. (total) | peak memory | Pareto |\n|---|---|---|---|---|---|---|---|---|---|---|"
    )?;
    for (i, r) in runs.iter().enumerate() {
        let s = r.outcome.summary.as_ref();
        let status = if r.outcome.is_ok() {
            String::new()
        } else {
            format!(" **failed: {}**", r.outcome.reason())
        };
        writeln!(
            md,
            "| {} | {} | {} | {} | {} | {}{status} | {} | {:.3} s | {} | {} | {} |",
            r.model,
            r.discretisation.label(),
            r.mesh,
            s.map_or("–".into(), |s| s.n_cells.to_string()),
            s.map_or("–".into(), |s| (s.n_displacement_dofs + s.n_rotation_dofs)
                .to_string()),
            fmt_e(r.error),
            r.outcome.wall_seconds().map_or("–".into(), |w| format!("{w:.3} s")),
            r.outcome.outer_seconds,
            s.map_or("–".into(), |s| format!(
                "{:.2} ({:.0})",
                s.avg_newton_iterations,
                s.avg_newton_iterations * s.n_steps as f64
            )),
            r.outcome
                .peak_rss_kib
                .map_or("–".into(), |k| format!("{:.0} MiB", k as f64 / 1024.0)),
            if front.contains(&i) { "★" } else { "" }
        )?;
    }
    Ok(())
}

/// The cheapest run (total wall time) among `runs` whose error is at most `goal`.
fn cheapest<'a>(runs: impl Iterator<Item = &'a StudyRun>, goal: f64) -> Option<&'a StudyRun> {
    runs.filter(|r| r.error.is_some_and(|e| e <= goal))
        .min_by(|a, b| a.outcome.outer_seconds.total_cmp(&b.outcome.outer_seconds))
}

/// The cheapest run (total wall time) that reaches each target error the reference resolves
/// (`resolution`, see [`Problem::resolution`]).
fn cheapest_table(md: &mut String, runs: &[StudyRun], resolution: f64) -> Result<()> {
    writeln!(
        md,
        "\nCheapest run (total wall time) that reaches a target error:\n\n| target error | setting | error | total wall |\n|---|---|---|---|"
    )?;
    for goal in [1e-1, 1e-2, 1e-3, 1e-4] {
        if goal < resolution {
            writeln!(md, "| {goal:.0e} | {} | – | – |", below_resolution(resolution))?;
            continue;
        }
        match cheapest(runs.iter(), goal) {
            Some(r) => writeln!(
                md,
                "| {goal:.0e} | {} {} {} | {} | {:.3} s |",
                r.model,
                r.discretisation.label(),
                r.mesh,
                fmt_e(r.error),
                r.outcome.outer_seconds
            )?,
            None => writeln!(md, "| {goal:.0e} | none of the ladder | – | – |")?,
        }
    }
    Ok(())
}

/// How many times faster the cheapest run of any discretisation is than the cheapest run with the
/// paper's interpolation, at one target error. Saved beside a target's sections as JSON.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
enum SpeedUp {
    /// Both reached the error: the ratio of their times.
    Measured(f64),
    /// Only other interpolations reached it: at least this, see [`unreached_bound`].
    AtLeast(f64),
    /// Only other interpolations reached it, and no run of the paper's bounds the ratio.
    OnlyOther,
    /// No run reached it.
    Unreached,
}

impl SpeedUp {
    /// From the cheapest runs within the error with the paper's interpolation and with any.
    fn between(paper: Option<&StudyRun>, any: Option<&StudyRun>, runs: &[StudyRun]) -> Self {
        match (paper, any) {
            (Some(p), Some(a)) => Self::Measured(p.outcome.outer_seconds / a.outcome.outer_seconds),
            (None, Some(a)) => {
                unreached_bound(runs).map_or(Self::OnlyOther, |b| Self::AtLeast(b / a.outcome.outer_seconds))
            }
            _ => Self::Unreached,
        }
    }

    fn of(runs: &[StudyRun], goal: f64) -> Self {
        let (paper, any) = cheapest_paper_and_any(runs, goal);
        Self::between(paper, any, runs)
    }

    /// The summary table's cell.
    fn cell(self) -> String {
        match self {
            Self::Measured(x) => format!("{x:.2}"),
            Self::AtLeast(x) => format!("> {x:.1}"),
            Self::OnlyOther => "only the other".into(),
            Self::Unreached => "–".into(),
        }
    }
}

/// The cheapest run within `goal` with the paper's interpolation and with any discretisation.
fn cheapest_paper_and_any(runs: &[StudyRun], goal: f64) -> (Option<&StudyRun>, Option<&StudyRun>) {
    let paper = cheapest(
        runs.iter().filter(|r| r.discretisation.interpolation == Interpolation::Paper),
        goal,
    );
    (paper, cheapest(runs.iter(), goal))
}

/// The target's row of the summary table: the cheapest run within 1 % and within 1e-3 with the paper's
/// interpolation and with any discretisation, and the time ratio.
fn summary_row(target: &Target, runs: &[StudyRun]) -> String {
    let setting = |r: Option<&StudyRun>| {
        r.map_or("none of the ladder".into(), |r| {
            format!(
                "{} {} {} ({:.3} s)",
                r.model,
                r.discretisation.label(),
                r.mesh,
                r.outcome.outer_seconds
            )
        })
    };
    let mut row = format!("| {} ", target.title());
    for goal in [1e-2, 1e-3] {
        if goal < target.resolution() {
            let _ = write!(row, "| {} | – | – ", below_resolution(target.resolution()));
            continue;
        }
        let (paper, any) = cheapest_paper_and_any(runs, goal);
        let ratio = SpeedUp::between(paper, any, runs).cell();
        let _ = write!(row, "| {} | {} | {ratio} ", setting(paper), setting(any));
    }
    row.push('|');
    row
}

/// The speed-up a user gains at 1 % over the paper's interpolation, problem by problem: where it is at
/// least [`EXTENSION_BUDGET`] times, where it is less, and where the ladders do not decide it.
fn speed_up_paragraph(speed_ups: &[(&str, SpeedUp)]) -> String {
    let list = |keep: &dyn Fn(SpeedUp) -> bool| -> Vec<String> {
        speed_ups
            .iter()
            .filter(|(_, s)| keep(*s))
            .map(|(title, s)| format!("{title} ({})", s.cell()))
            .collect()
    };
    let fast = list(&|s| matches!(s, SpeedUp::Measured(x) | SpeedUp::AtLeast(x) if x >= EXTENSION_BUDGET));
    let slow = list(&|s| matches!(s, SpeedUp::Measured(x) if x < EXTENSION_BUDGET));
    let open = list(&|s| matches!(s, SpeedUp::AtLeast(x) if x < EXTENSION_BUDGET) || s == SpeedUp::OnlyOther);
    let join = |v: Vec<String>| if v.is_empty() { "none".to_string() } else { v.join(", ") };
    let mut text = format!(
        "\nAt 1 %, the cheapest run of any discretisation is at least {EXTENSION_BUDGET} times faster than the cheapest with the paper's interpolation on: {}. Less on: {}.",
        join(fast),
        join(slow)
    );
    if !open.is_empty() {
        text.push_str(&format!(
            " Not decided by the ladders (the paper's finest runs are too cheap to bound it): {}.",
            open.join(", ")
        ));
    }
    text.push('\n');
    text
}

/// The cell of a target error finer than the reference resolves.
fn below_resolution(resolution: f64) -> String {
    format!("below the reference's resolution ({resolution:.0e})")
}

/// A lower bound of the cost of a run with the paper's interpolation that reaches an error none of its
/// runs reached: the errors fall as the meshes refine, so such a run needs a finer mesh than every rung
/// of its pair's ladder and costs more than that ladder's most expensive run; the bound is the
/// smallest of these over the pairs.
fn unreached_bound(runs: &[StudyRun]) -> Option<f64> {
    let mut bound: Option<f64> = None;
    for pair in [Pair::Tri3Tri3, Pair::Tri6Tri3, Pair::Tri6Tri6] {
        let most = runs
            .iter()
            .filter(|r| r.discretisation == Discretisation::paper(pair))
            .map(|r| r.outcome.outer_seconds)
            .fold(None, |m: Option<f64>, t| Some(m.map_or(t, |m| m.max(t))));
        if let Some(t) = most {
            bound = Some(bound.map_or(t, |b| b.min(t)));
        }
    }
    bound
}

const SUMMARY_HEADER: &str = "## Summary\n\nThe cheapest run (total wall time) within a relative error of 1 % and of 1e-3 on each problem: with the paper's strain interpolation, with any discretisation of the study, and how many times faster the second is (1.00: a run with the paper's interpolation is the cheapest; \"> x\": no run with the paper's interpolation reached the error, and one that does would need a finer mesh than its ladder's finest, so it would cost more than the cheapest of the pairs' finest runs, x times the other; \"below the reference's resolution\": the reference is a finite element table, which resolves errors only down to the size given). On the three thin curved shells, each pair's ladder with the paper's interpolation goes on to finer meshes while none of its runs is within 1 %, its last run finished, and that run cost at most 4 times the cheapest 1 % run of any discretisation, so that a bound is not set by a ladder that stopped while still cheap.\n\n| problem | paper's, 1 % | any, 1 % | speed-up | paper's, 1e-3 | any, 1e-3 | speed-up |\n|---|---|---|---|---|---|---|";

/// Observed convergence orders per (model, discretisation).
fn orders_table(md: &mut String, runs: &[StudyRun], groups: &[(&str, Discretisation)]) -> Result<()> {
    writeln!(
        md,
        "\nObserved convergence orders (error against element length h, between successive meshes; expected in the asymptotic range: 2 for Tri3/Tri3 and Tri6/Tri3, 3 for Tri6/Tri6), and the self-convergence order of the measured quantity from its last three values (no reference needed):\n\n| model | discretisation | orders of the error | self-convergence order | expected |\n|---|---|---|---|---|"
    )?;
    for &(model, discretisation) in groups {
        let g: Vec<&StudyRun> = runs
            .iter()
            .filter(|r| r.model == model && r.discretisation == discretisation)
            .collect();
        let pts: Vec<(f64, f64)> = g.iter().filter_map(|r| Some((r.h, r.error?))).collect();
        let orders = observed_orders(&pts)
            .iter()
            .map(|p| format!("{p:.2}"))
            .collect::<Vec<_>>()
            .join(", ");
        let q: Vec<f64> = g.iter().filter_map(|r| r.quantity).collect();
        let selfp = if q.len() >= 3 {
            richardson([q[q.len() - 3], q[q.len() - 2], q[q.len() - 1]])
                .map_or("not monotone".into(), |(_, p)| format!("{p:.2}"))
        } else {
            "–".into()
        };
        writeln!(
            md,
            "| {model} | {} | {orders} | {selfp} | {:.0} |",
            discretisation.label(),
            discretisation.pair.expected_order()
        )?;
    }
    Ok(())
}

/// Error against wall time (with the Pareto front) and against element length, as SVG plots.
fn plots(
    md: &mut String,
    target: &Target,
    runs: &[StudyRun],
    groups: &[(&str, Discretisation)],
    (points, front): (&[(f64, f64)], &[usize]),
    images: &Path,
) -> Result<()> {
    let mut pareto = Vec::new();
    let mut convergence = Vec::new();
    for &(model, discretisation) in groups {
        let g: Vec<&StudyRun> = runs
            .iter()
            .filter(|r| r.model == model && r.discretisation == discretisation)
            .collect();
        let label = g.first().map(|r| r.series_label()).unwrap_or_default();
        let color = discretisation.color(model == "plate" && groups.iter().any(|x| x.0 == "shell"));
        pareto.push(Series {
            label: label.clone(),
            points: g.iter().filter_map(|r| Some((r.outcome.outer_seconds, r.error?))).collect(),
            mark: Mark::LinePoints,
            color,
        });
        convergence.push(Series {
            label,
            points: g.iter().filter_map(|r| Some((r.h, r.error?))).collect(),
            mark: Mark::LinePoints,
            color,
        });
    }
    pareto.push(Series {
        label: "Pareto front".into(),
        points: front.iter().map(|&i| points[i]).collect(),
        mark: Mark::Line,
        color: 0,
    });
    let name = target.name();
    let pareto_path = images.join(format!("study_{name}_pareto.svg"));
    let conv_path = images.join(format!("study_{name}_convergence.svg"));
    let written = Plot {
        title: format!("{}: error vs wall time", target.title()),
        x_label: "total wall time [s] (one thread, setup included)".into(),
        y_label: "relative error".into(),
        log_log: true,
        series: pareto,
    }
    .write_svg(&pareto_path)
    .and_then(|()| {
        Plot {
            title: format!("{}: error vs element length", target.title()),
            x_label: "element length h".into(),
            y_label: "relative error".into(),
            log_log: true,
            series: convergence,
        }
        .write_svg(&conv_path)
    });
    match written {
        Ok(()) => writeln!(
            md,
            "\n![error vs time](img/study_{name}_pareto.svg)\n\n![error vs h](img/study_{name}_convergence.svg)"
        )?,
        Err(e) => writeln!(md, "\n(plots not written: {e})")?,
    }
    Ok(())
}

const HEADER: &str = "# Speed–accuracy trade\n\nGenerated by `cargo xtask study --all` (release build). Discretisations: the three element pairs with the paper's strain interpolation, the paper's pair Tri6/Tri3 with two other strain interpolations (docs/model-notes.md): the stabilised projection (`material.strain_interpolation = \"stabilized\"`), labelled `Tri6/Tri3 stabilized`, and Regge membrane strains with stabilised shear and drilling (`\"regge_stabilized\"`), labelled `Tri6/Tri3 regge_stabilized`, and the quadratic pair with the latter, `Tri6/Tri6 regge_stabilized`, the default discretisation (on the 3-point rule), which meets the obstacle course's goals on thin curved shells (docs/validation.md), and the same on the pair's six-point rule (`mesh.quadrature_degree = 4`), `Tri6/Tri6 regge_stabilized 6-point`, at about 1.6 times the 3-point rule's Hessian cost per element (docs/model-notes.md). Every ladder point runs in its own child process (the hidden `cargo xtask measure-run`) on one thread with frames switched off; *solve wall* is the run's own wall time from `summary.json` (the time loop: assembly, solves, probe output; setup excluded), *total wall* the child process from start to exit (setup of mesh, rest state and sparsity included; this is what the Pareto front and the \"cheapest run\" tables use), *peak memory* the child's peak resident set size (`VmHWM` of `/proc/self/status`, read by the child just before it exits, so it includes the process's fixed ~10 MiB). Timings are indicative: the machine has 2 cores shared with other work. *Pareto* marks the runs that no other run beats in both time and error; the plots show error against time (with the front) and against element length.\n\nProblems: the validation problems of docs/validation.md: flat or gently curved and moderately thin (h/L about 1e-2), the slit annular plate under large rotations, and the Sze 3.1 strip made thin at constant bending stiffness (h/L = 1e-3 and 1e-4, the slenderness of sheet metal, paper and foil); the three thin curved shells of the shell obstacle course (pinched hemisphere, pinched cylinder, Scordelis–Lo roof); and the paper's Plate under load. The paper's discretisation locks on the thin strips, the slit plate and the thin curved shells, not on the moderately thin problems.\n\nHow to read it: pick the target error in the \"cheapest run\" table of the problem closest to yours; the discretisation it names is the one to use, the mesh tells how fine per unit length.

";

/// The page from the saved sections of `targets`: the header, the summary table with its speed-up
/// sentence, and each target's section.
fn assemble(targets: &[Target], sections: &Path) -> String {
    let read = |t: &Target, suffix: &str| std::fs::read_to_string(sections.join(format!("{}.{suffix}", t.name()))).ok();
    let mut doc = HEADER.to_string();
    doc.push_str(SUMMARY_HEADER);
    for row in targets.iter().filter_map(|t| read(t, "summary.md")) {
        doc.push('\n');
        doc.push_str(&row);
    }
    doc.push('\n');
    let speed_ups: Vec<(&str, SpeedUp)> = targets
        .iter()
        .filter_map(|t| Some((t.title(), serde_json::from_str(&read(t, "speedup.json")?).ok()?)))
        .collect();
    doc.push_str(&speed_up_paragraph(&speed_ups));
    for section in targets.iter().filter_map(|t| read(t, "md")) {
        doc.push_str(&section);
    }
    doc
}

/// Runs the study command.
///
/// # Errors
/// Unknown targets, I/O failures.
pub fn run(args: &StudyArgs) -> Result<i32> {
    let all = targets();
    if args.list {
        for t in &all {
            eprintln!("{}", t.name());
        }
        return Ok(0);
    }
    let chosen: Vec<&Target> = if args.all {
        all.iter().collect()
    } else {
        let mut v = Vec::new();
        for name in &args.targets {
            match all.iter().find(|t| t.name() == name) {
                Some(t) => v.push(t),
                None => bail!("unknown study target `{name}` (see `cargo xtask study --list`)"),
            }
        }
        v
    };
    if chosen.is_empty() && !args.assemble {
        bail!("name a study target or pass --all (see `cargo xtask study --list`)");
    }
    if let Some(path) = &args.emit_runs {
        let out = PathBuf::from(if args.quick { "out/study_quick" } else { "out/study" });
        let runs: Vec<RunDescription> = chosen
            .iter()
            .flat_map(|t| planned_runs(t, &out, args.quick))
            .map(|p| p.run)
            .collect();
        cosserat::run_description::write_runs(path, &runs)?;
        eprintln!("wrote {} run descriptions to {}", runs.len(), path.display());
        return Ok(0);
    }
    let runner = Runner::current_exe()?;
    let (out, sections, images) = if args.quick {
        (
            PathBuf::from("out/study_quick"),
            PathBuf::from("out/study_quick/sections"),
            PathBuf::from("out/img"),
        )
    } else {
        (
            PathBuf::from("out/study"),
            PathBuf::from("out/study/sections"),
            PathBuf::from("docs/img"),
        )
    };
    std::fs::create_dir_all(&sections)?;
    std::fs::create_dir_all(&images)?;
    for t in chosen {
        let (runs, extrapolated) = run_target(t, &runner, &out, args.quick)?;
        let md = section(t, &runs, extrapolated, &images)?;
        std::fs::write(sections.join(format!("{}.md", t.name())), md)?;
        std::fs::write(sections.join(format!("{}.summary.md", t.name())), summary_row(t, &runs))?;
        let speed_up = serde_json::to_string(&SpeedUp::of(&runs, 1e-2))?;
        std::fs::write(sections.join(format!("{}.speedup.json", t.name())), speed_up)?;
    }
    let doc = assemble(&all, &sections);
    let path = if args.quick {
        PathBuf::from("out/speed-accuracy_quick.md")
    } else {
        PathBuf::from("docs/speed-accuracy.md")
    };
    std::fs::write(&path, doc)?;
    eprintln!("wrote {}", path.display());
    Ok(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn richardson_recovers_a_second_order_sequence() {
        // q(h) = 3 + 0.5 h² on h = 1, 1/2, 1/4.
        let (limit, order) = richardson([3.5, 3.125, 3.03125]).unwrap();
        assert!((limit - 3.0).abs() < 1e-12 && (order - 2.0).abs() < 1e-12);
        assert!(richardson([1.0, 2.0, 1.5]).is_none());
    }

    #[test]
    fn pareto_front_keeps_only_undominated_points() {
        let pts = [(1.0, 0.1), (2.0, 0.2), (3.0, 0.01), (0.5, 0.5), (4.0, 0.01)];
        assert_eq!(pareto_front(&pts), vec![3, 0, 2]);
    }

    /// The bound is the cheapest of the paper's pairs' most expensive runs; runs of other
    /// interpolations do not count, and without any run of the paper's interpolation there is none.
    /// A run of `discretisation` that took `seconds` and reached `error`.
    fn study_run(discretisation: Discretisation, seconds: f64, error: Option<f64>) -> StudyRun {
        StudyRun {
            discretisation,
            model: "shell",
            mesh: String::new(),
            h: 1.0,
            outcome: RunOutcome {
                summary: None,
                probes: None,
                peak_rss_kib: None,
                outer_seconds: seconds,
                failure: None,
            },
            quantity: None,
            error,
        }
    }

    #[test]
    fn unreached_bound_is_the_cheapest_finest_paper_run() {
        let run = |discretisation: Discretisation, seconds: f64| study_run(discretisation, seconds, None);
        let regge = Discretisation::DEFAULT;
        let runs = [
            run(Discretisation::paper(Pair::Tri3Tri3), 0.1),
            run(Discretisation::paper(Pair::Tri3Tri3), 2.5),
            run(Discretisation::paper(Pair::Tri6Tri3), 0.4),
            run(Discretisation::paper(Pair::Tri6Tri3), 1.5),
            run(Discretisation::paper(Pair::Tri6Tri6), 4.0),
            run(regge, 0.2),
        ];
        assert_eq!(unreached_bound(&runs), Some(1.5));
        assert_eq!(unreached_bound(&[run(regge, 0.2)]), None);
    }

    #[test]
    fn a_paper_ladder_goes_on_only_while_short_of_one_percent_and_cheap() {
        let paper = Discretisation::paper(Pair::Tri6Tri3);
        let run = |seconds: f64, error: Option<f64>| study_run(paper, seconds, error);
        let best = 1.0;
        assert!(ladder_goes_on(&[run(0.1, Some(0.5)), run(3.9, Some(0.2))], paper, best));
        // Within 1 % already, too expensive to refine, or the last run failed.
        assert!(!ladder_goes_on(
            &[run(0.1, Some(0.009)), run(0.2, Some(0.2))],
            paper,
            best
        ));
        assert!(!ladder_goes_on(
            &[run(0.1, Some(0.5)), run(4.1, Some(0.2))],
            paper,
            best
        ));
        assert!(!ladder_goes_on(&[run(0.1, Some(0.5)), run(0.2, None)], paper, best));
        // Another discretisation's runs do not count.
        assert!(!ladder_goes_on(
            &[run(0.1, Some(0.5))],
            Discretisation::paper(Pair::Tri3Tri3),
            best
        ));
    }

    #[test]
    fn speed_ups_are_measured_bounded_or_open() {
        let paper = Discretisation::paper(Pair::Tri6Tri3);
        let default = Discretisation::DEFAULT;
        // Both within 1 %: the ratio of the cheapest of each.
        let both = [
            study_run(paper, 2.0, Some(0.005)),
            study_run(paper, 1.0, Some(0.02)),
            study_run(default, 0.5, Some(0.008)),
        ];
        assert_eq!(SpeedUp::of(&both, 1e-2), SpeedUp::Measured(4.0));
        // Only the default: at least the paper's finest run over the default's.
        let only = [study_run(paper, 3.0, Some(0.02)), study_run(default, 0.5, Some(0.008))];
        assert_eq!(SpeedUp::of(&only, 1e-2), SpeedUp::AtLeast(6.0));
        assert_eq!(SpeedUp::of(&only[1..], 1e-2), SpeedUp::OnlyOther);
        assert_eq!(SpeedUp::of(&only[..1], 1e-2), SpeedUp::Unreached);
        for s in [
            SpeedUp::Measured(1.04),
            SpeedUp::AtLeast(9.9),
            SpeedUp::OnlyOther,
            SpeedUp::Unreached,
        ] {
            let saved = serde_json::to_string(&s).unwrap();
            assert_eq!(serde_json::from_str::<SpeedUp>(&saved).unwrap(), s);
        }
    }

    #[test]
    fn the_speed_up_paragraph_sorts_the_problems_by_the_budget() {
        let text = speed_up_paragraph(&[
            ("A", SpeedUp::Measured(5.28)),
            ("B", SpeedUp::Measured(1.04)),
            ("C", SpeedUp::AtLeast(9.9)),
            ("D", SpeedUp::AtLeast(2.0)),
            ("E", SpeedUp::Unreached),
        ]);
        assert!(text.contains("on: A (5.28), C (> 9.9). Less on: B (1.04)."), "{text}");
        assert!(text.contains("bound it): D (> 2.0)."), "{text}");
        assert!(!text.contains("E ("), "{text}");
    }

    #[test]
    fn observed_orders_of_a_power_law() {
        let pts: Vec<(f64, f64)> = [1.0, 0.5, 0.25].iter().map(|&h| (h, 2.0 * h * h * h)).collect();
        for p in observed_orders(&pts) {
            assert!((p - 3.0).abs() < 1e-12);
        }
    }
}
