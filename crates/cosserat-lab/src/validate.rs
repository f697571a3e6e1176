//! `cargo xtask validate`: runs the validation scenes of `scenes/validation/` on their refinement
//! ladders, compares every load level with the published tables or closed forms, and writes
//! `docs/validation.md` with load–deflection plots in `docs/img/`.
//!
//! The error of a quantity at a load level is `|u − u_ref|` divided by the largest `|u_ref|` of that
//! quantity over the levels (the definition); a run's error is the largest over levels.

use crate::plot::{Mark, Plot, Series};
use crate::problem::{Discretisation, Errors, LevelTable, Pair, Problem, compare, registry};
use crate::runner::{RunOutcome, Runner, run_described};
use anyhow::Result;
use cosserat::RunDescription;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// How the validation runs.
#[derive(Debug, Clone)]
pub struct Options {
    /// Where runs execute.
    pub runner: Runner,
    /// Root of the run outputs.
    pub out: PathBuf,
    /// Directory of the written images (`docs/img`).
    pub images: PathBuf,
    /// Only the scene's own mesh and the coarsest ladder meshes.
    pub quick: bool,
}

/// The discretisations every problem runs: the three element pairs with the paper's strain
/// interpolation, and the default discretisation (Tri6/Tri6 with Regge membrane strains and
/// stabilised shear and drilling, on the 3-point rule).
pub const DISCRETISATIONS: [Discretisation; 4] = [
    Discretisation::paper(Pair::Tri3Tri3),
    Discretisation::paper(Pair::Tri6Tri3),
    Discretisation::paper(Pair::Tri6Tri6),
    Discretisation::DEFAULT,
];

/// Colour index of a discretisation in the plots (the reference is 0).
fn color(d: Discretisation) -> usize {
    if d == Discretisation::DEFAULT {
        4
    } else {
        d.pair.color()
    }
}

/// One run of a problem.
#[derive(Debug, Clone)]
pub struct ValidationRun {
    /// Element pair and strain interpolation.
    pub discretisation: Discretisation,
    /// Mesh label.
    pub mesh: String,
    /// Element length \[m\].
    pub h: f64,
    /// The outcome.
    pub outcome: RunOutcome,
    /// Errors against the reference (if the run finished).
    pub errors: Option<Errors>,
    /// Per-level comparison (if the run finished).
    pub levels: Option<LevelTable>,
}

/// Runs one problem on every ladder mesh of its pair for every discretisation of [`DISCRETISATIONS`]
/// (with `extra` overrides, e.g. the model).
///
/// # Errors
/// I/O failures of the output directories.
pub fn run_problem(problem: &Problem, o: &Options, extra: &[String]) -> Result<Vec<ValidationRun>> {
    let mut runs = Vec::new();
    for discretisation in DISCRETISATIONS {
        let pair = discretisation.pair;
        let ladder = (problem.ladder)(pair);
        let selected: Vec<_> = ladder
            .into_iter()
            .enumerate()
            .filter(|(i, m)| !o.quick || *i < 2 || (is_paper_pair(discretisation) && m.label == problem.default_mesh))
            .map(|(_, m)| m)
            .collect();
        for mesh in selected {
            let mut ov = discretisation.overrides();
            ov.extend(mesh.overrides.iter().cloned());
            ov.push("output.frames=false".into());
            ov.extend(extra.iter().cloned());
            let dir = o
                .out
                .join(problem.name)
                .join(format!("{}_{}", discretisation.directory(), mesh.label));
            eprintln!("{}: {} {} ...", problem.name, discretisation.label(), mesh.label);
            let outcome = run_described(&o.runner, &RunDescription::new(problem.scene, dir, &ov))?;
            let compared = outcome
                .probes
                .as_ref()
                .filter(|_| outcome.is_ok())
                .and_then(|p| compare(problem, p, false).ok());
            if !outcome.is_ok() {
                eprintln!("  failed: {}", outcome.reason());
            }
            runs.push(ValidationRun {
                discretisation,
                mesh: mesh.label,
                h: mesh.h,
                errors: compared.as_ref().map(|c| c.0.clone()),
                levels: compared.map(|c| c.1),
                outcome,
            });
        }
    }
    Ok(runs)
}

fn pct(e: f64) -> String {
    if e.is_nan() {
        "–".into()
    } else {
        format!("{:.3} %", 100.0 * e)
    }
}

/// Whether `d` is the paper's pair Tri6/Tri3 with the paper's strain interpolation.
fn is_paper_pair(d: Discretisation) -> bool {
    d == Discretisation::paper(Pair::Tri6Tri3)
}

/// The coarsest mesh of `discretisation` within `target` at every level and component, if any.
pub fn first_within(runs: &[ValidationRun], discretisation: Discretisation, target: f64) -> Option<&ValidationRun> {
    runs.iter()
        .filter(|r| r.discretisation == discretisation)
        .find(|r| r.errors.as_ref().is_some_and(|e| e.max() <= target))
}

fn run_row(problem: &Problem, r: &ValidationRun) -> String {
    let s = r.outcome.summary.as_ref();
    let errors = match &r.errors {
        Some(e) => e.per_component.iter().map(|&x| pct(x)).collect::<Vec<_>>().join(" | "),
        None => vec!["–"; problem.components.len()].join(" | "),
    };
    let status = if r.outcome.is_ok() {
        "ok".to_string()
    } else {
        format!("**failed**: {}", r.outcome.reason())
    };
    format!(
        "| {} | {} | {} | {} | {errors} | {} | {} | {:.2} s | {status} |",
        r.discretisation.label(),
        r.mesh,
        s.map_or("–".into(), |s| s.n_cells.to_string()),
        s.map_or("–".into(), |s| (s.n_displacement_dofs + s.n_rotation_dofs)
            .to_string()),
        s.map_or("–".into(), |s| format!("{:.2}", s.avg_newton_iterations)),
        s.map_or("–".into(), |s| format!("{:.2} s", s.wall_seconds)),
        r.outcome.outer_seconds,
    )
}

fn plot_problem(problem: &Problem, runs: &[ValidationRun], path: &Path) -> Result<()> {
    let mut series = Vec::new();
    let levels: Vec<f64> = runs
        .iter()
        .find_map(|r| r.levels.as_ref())
        .map(|t| t.iter().map(|x| x.0).collect())
        .unwrap_or_default();
    for (k, c) in problem.components.iter().enumerate() {
        let mut reference = vec![(0.0, 0.0)];
        reference.extend(levels.iter().map(|&l| (l, (c.reference)(l))));
        series.push(Series {
            label: format!("{} reference", c.label),
            points: reference,
            mark: Mark::Points,
            color: 0,
        });
        // Tri6/Tri3 on the scene's mesh; the others on their coarsest mesh within 1 % (else their
        // finest finished mesh).
        let shown: Vec<&ValidationRun> = DISCRETISATIONS
            .iter()
            .filter_map(|&d| {
                if is_paper_pair(d) {
                    on_scene_mesh(problem, runs, d)
                } else {
                    first_within(runs, d, 0.01)
                        .or_else(|| runs.iter().rfind(|r| r.discretisation == d && r.levels.is_some()))
                }
            })
            .collect();
        for r in shown {
            let Some(t) = &r.levels else { continue };
            let mut pts = vec![(0.0, 0.0)];
            pts.extend(t.iter().map(|(l, v)| (*l, v[k].0)));
            series.push(Series {
                label: format!("{} {} {}", c.label, r.discretisation.label(), r.mesh),
                points: pts,
                mark: Mark::Line,
                color: color(r.discretisation) + DISCRETISATIONS.len() * k,
            });
        }
    }
    Plot {
        title: problem.title.to_string(),
        x_label: "load factor λ".into(),
        y_label: "tip displacement".into(),
        log_log: false,
        series,
    }
    .write_svg(path)
}

fn level_table(problem: &Problem, r: &ValidationRun, md: &mut String) -> Result<()> {
    let Some(t) = &r.levels else { return Ok(()) };
    let mut header = "| λ |".to_string();
    let mut rule = "|---:|".to_string();
    for c in &problem.components {
        write!(header, " {0} | {0} ref. |", c.label)?;
        rule.push_str("---:|---:|");
        if let Some((label, _)) = c.second {
            write!(header, " {} {label} |", c.label)?;
            rule.push_str("---:|");
        }
        write!(header, " error {} |", c.label)?;
        rule.push_str("---:|");
    }
    writeln!(md, "{header}\n{rule}")?;
    for (lambda, values) in t {
        let mut line = format!("| {} |", load_factor(*lambda));
        for (c, (v, reference, e)) in problem.components.iter().zip(values) {
            write!(line, " {v:.5} | {reference:.5} |")?;
            if let Some((_, f)) = c.second {
                write!(line, " {} |", f(*lambda).map_or("–".into(), |x| format!("{x:.5}")))?;
            }
            write!(line, " {} |", pct(*e))?;
        }
        writeln!(md, "{line}")?;
    }
    for (k, c) in problem.components.iter().enumerate() {
        let Some((label, f)) = c.second else { continue };
        let pairs: Vec<(f64, f64)> = t.iter().filter_map(|(l, v)| Some((v[k].0, f(*l)?))).collect();
        let scale = pairs.iter().map(|p| p.1.abs()).fold(0.0, f64::max);
        if scale > 0.0 {
            let dev = pairs.iter().map(|p| (p.0 - p.1).abs()).fold(0.0, f64::max) / scale;
            writeln!(
                md,
                "\nLargest deviation of {} from the {label} column: {}.",
                c.label,
                pct(dev)
            )?;
        }
    }
    Ok(())
}

/// A tabulated load factor with the decimals it has: `0.05`, `0.025`, `1.00`.
fn load_factor(lambda: f64) -> String {
    let three = format!("{lambda:.3}");
    match three.strip_suffix('0') {
        Some(two) => two.to_string(),
        None => three,
    }
}

/// How to read the results: what the references can and cannot resolve, and what the ladders show.
const READING: &str = "How to read this:

- **The moderate mesh.** On the moderately thin strips (h/L = 1e-2) and the ring, Tri6 displacements with Tri3 rotations meet the 1 % target at every tabulated load on the scene files' meshes: 20×2 quads for the end shear (element length L/20 = 5 h), 48×4 for the roll-up (L/48 = 2.5 h; 24×2 is just over 1 % at λ ≥ 0.95, where the strip closes into a circle), 20×2 for the small load and 128 elements around the ring.
- **What the Sze 3.1 table can resolve.** Its values are Sze's own 16×1 shell-element result, rounded to 3 decimals; the converged runs differ from it by about 0.1 % of the largest −U and agree better with the inextensible elastica (the deviation from the elastica column is given under each level table). Errors below about 0.1 % in −U therefore measure the table, not the simulator. The roll-up and the small load have exact references; the ring's thin-ring formula is itself good to a few 1e-4 (extension, shear and geometric nonlinearity of this ring).
- **Tri3/Tri3 locks.** Linear displacements and rotations need about 13 elements per thickness along the strip for 1 % (1280 elements on L = 100 h), on the ring (h/R = 0.01, flat facets) even 2048 elements around stay 6 % too stiff. Use Tri6 displacements; see `docs/stability.md` for the thin limit and `docs/speed-accuracy.md` for the cost.
- **Thin strips.** The thin and very thin cantilevers are the Sze 3.1 strip at h/L = 1e-3 and 1e-4 with E = 1200/h³, so that the bending stiffness and the elastica's load path stay Sze 3.1's while the membrane and shear stiffness grow like (L/h)²; they are compared with the elastica, and their scenes run the default discretisation on 10×1 quads. `docs/stability.md` follows the same strip to h/L = 1e-5.
- **Tri6/Tri6 is not better on coarse meshes.** With quadratic rotations and the 6-point rule it is stiffer than Tri6/Tri3 (3-point rule) on the coarsest meshes and overtakes it only once refined; its asymptotic order is higher (`docs/speed-accuracy.md`).
";

/// Largest difference between the `tip` and `tip_mid` probes over all rows and components, relative
/// to the largest `tip` displacement, if both probes exist.
fn mean_vs_mid_width(p: &crate::postprocess::ProbeTable) -> Option<f64> {
    let mut diff: f64 = 0.0;
    let mut scale: f64 = 0.0;
    for comp in ["ux", "uy", "uz"] {
        let (a, b) = (
            p.column(&format!("tip.{comp}")).ok()?,
            p.column(&format!("tip_mid.{comp}")).ok()?,
        );
        for row in &p.rows {
            diff = diff.max((row[a] - row[b]).abs());
            scale = scale.max(row[a].abs());
        }
    }
    (scale > 0.0).then_some(diff / scale)
}

/// Runs every validation problem and returns the markdown of `docs/validation.md`.
///
/// # Errors
/// I/O failures.
pub fn run_all(o: &Options) -> Result<String> {
    let started = std::time::Instant::now();
    std::fs::create_dir_all(&o.images)?;
    let mut body = String::new();
    let mut summary = String::new();
    writeln!(summary, "{}", summary_header())?;
    let mut locked = String::new();
    for problem in registry() {
        let runs = run_problem(&problem, o, &[])?;
        let image = o.images.join(format!("validation_{}.svg", problem.name));
        let plotted = plot_problem(&problem, &runs, &image);
        summary_row(&problem, &runs, &mut summary)?;
        locked.push_str(&locked_note(&problem, &runs));
        problem_section(&problem, &runs, &image, plotted, &mut body)?;
    }
    body.push_str(&crate::path_validation::run_all(o)?);
    body.push_str(&crate::obstacle::run_all(&o.runner, &o.out, o.quick)?);
    let mut md = String::new();
    writeln!(md, "# Validation against published benchmarks\n")?;
    writeln!(
        md,
        "Generated by `cargo xtask validate{}` ({:.0} s, release build, one thread per run). Each run is a quasi-static scene of `scenes/validation/`: the pseudo time `t` is the load factor λ, and `probes.csv` has one row per tabulated level, so rows compare directly with the tables in [references.md](references.md). The error of a quantity at a level is |u − u_ref| divided by the largest |u_ref| of that quantity; tables give the largest over all levels. *Solve wall* is the run's time loop (`summary.json`), *total wall* the whole process including the setup of mesh and rest state. Every problem runs the three element pairs with the paper's strain interpolation and the default discretisation, `Tri6/Tri6 regge_stabilized` (quadratic rotations, Regge membrane strains, stabilised shear and drilling; docs/model-notes.md). Tri3/Tri3 ladders use one row of quads across the width (ny = 1): the width is not where a strip needs elements.\n",
        if o.quick { " --quick" } else { "" },
        started.elapsed().as_secs_f64()
    )?;
    writeln!(md, "## Summary\n\n{summary}\n{READING}{locked}")?;
    md.push_str(&body);
    Ok(md)
}

/// The run of `d` on the scene's own mesh, if it was run.
fn on_scene_mesh<'a>(problem: &Problem, runs: &'a [ValidationRun], d: Discretisation) -> Option<&'a ValidationRun> {
    runs.iter().find(|r| r.discretisation == d && r.mesh == problem.default_mesh)
}

/// The header of the summary table.
fn summary_header() -> String {
    let labels: Vec<String> = DISCRETISATIONS.iter().map(|d| d.label()).collect();
    format!(
        "| problem | scene's mesh | error: Tri6/Tri3 | {} | coarsest mesh within 1 %: {} |\n|---|---|---|---|{}",
        Discretisation::DEFAULT.label(),
        labels.join(" | "),
        "---|".repeat(labels.len())
    )
}

/// A bullet for a problem where the paper's pair misses 1 % on the scene's mesh: its error there, its
/// coarsest mesh within 1 % and the default discretisation's error on the scene's mesh (empty
/// otherwise).
fn locked_note(problem: &Problem, runs: &[ValidationRun]) -> String {
    let paper = Discretisation::paper(Pair::Tri6Tri3);
    let error = |d| on_scene_mesh(problem, runs, d).and_then(|r| r.errors.as_ref()).map(Errors::max);
    let Some(e) = error(paper).filter(|&e| e > 0.01) else {
        return String::new();
    };
    let within = first_within(runs, paper, 0.01).map_or("none of the ladder".into(), |r| r.mesh.clone());
    format!(
        "- **Where the paper's pair locks: {}.** Tri6/Tri3 is {} off on the scene's {} (within 1 %: {within}); the default discretisation {} there.\n",
        problem.title,
        pct(e),
        problem.default_mesh,
        error(Discretisation::DEFAULT).map_or("did not run".into(), pct)
    )
}

/// A problem's row of the summary table: the errors of the paper's pair and of the default
/// discretisation on the scene's mesh and, per discretisation, the coarsest mesh within 1 %.
fn summary_row(problem: &Problem, runs: &[ValidationRun], summary: &mut String) -> Result<()> {
    let error = |d: Discretisation| {
        on_scene_mesh(problem, runs, d)
            .and_then(|r| r.errors.as_ref())
            .map_or("not run or failed".into(), |e| pct(e.max()))
    };
    let within: Vec<String> = DISCRETISATIONS
        .iter()
        .map(|&d| first_within(runs, d, 0.01).map_or("none of the ladder".into(), |r| r.mesh.clone()))
        .collect();
    writeln!(
        summary,
        "| {} | {} | {} | {} | {} |",
        problem.title,
        problem.default_mesh,
        error(Discretisation::paper(Pair::Tri6Tri3)),
        error(Discretisation::DEFAULT),
        within.join(" | ")
    )?;
    Ok(())
}

/// A problem's section: its scene and reference, the plot, the table of every run and, for the
/// scene's own mesh, every load level.
fn problem_section(
    problem: &Problem,
    runs: &[ValidationRun],
    image: &Path,
    plotted: Result<()>,
    body: &mut String,
) -> Result<()> {
    writeln!(body, "\n## {}\n", problem.title)?;
    writeln!(
        body,
        "Scene `{}`. Reference: {}.\n",
        problem.scene, problem.reference_note
    )?;
    match plotted {
        Ok(()) => writeln!(
            body,
            "![{}](img/{})\n",
            problem.title,
            image.file_name().map(|f| f.to_string_lossy().into_owned()).unwrap_or_default()
        )?,
        Err(e) => writeln!(body, "(plot not written: {e})\n")?,
    }
    let labels: Vec<String> = problem.components.iter().map(|c| format!("max error {}", c.label)).collect();
    writeln!(
        body,
        "| discretisation | mesh | cells | DOFs | {} | Newton it./level | solve wall | total wall | status |\n|---|---|---|---|{}---|---|---|---|",
        labels.join(" | "),
        "---|".repeat(labels.len())
    )?;
    for r in runs {
        writeln!(body, "{}", run_row(problem, r))?;
    }
    for d in [Discretisation::paper(Pair::Tri6Tri3), Discretisation::DEFAULT] {
        let Some(r) = on_scene_mesh(problem, runs, d) else {
            continue;
        };
        writeln!(
            body,
            "\nEvery load level, {} on the scene's mesh {}:\n",
            d.label(),
            problem.default_mesh
        )?;
        level_table(problem, r, body)?;
    }
    let paper = on_scene_mesh(problem, runs, Discretisation::paper(Pair::Tri6Tri3));
    if let Some(d) = paper.and_then(|r| r.outcome.probes.as_ref()).and_then(mean_vs_mid_width) {
        writeln!(
            body,
            "\nOn Tri6/Tri3, the mean over the loaded end (`tip`) and the mid-width node (`tip_mid`) differ by at most {d:.1e} of the largest tip displacement (the strip bends without twisting).",
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::load_factor;

    #[test]
    fn load_factors_keep_their_third_decimal_only_where_they_have_one() {
        assert_eq!(load_factor(0.025), "0.025");
        assert_eq!(load_factor(0.05), "0.05");
        assert_eq!(load_factor(0.35000000000000003), "0.35");
        assert_eq!(load_factor(1.0), "1.00");
    }
}
