//! `cargo xtask bench-table`: the reference code's cases (docs/references.md) run by our
//! simulator on this machine, with the time per step beside the reference's, and the paper's largest
//! plate beside the paper's 32-core figure. Writes docs/performance.md (tables) and
//! docs/performance.json (one object per case).
//!
//! Each case runs in a child process of the `cosserat` binary, so its peak memory is its own. The
//! machine is shared and a single run can land in someone else's busy minute, so the cases run in
//! several rounds, one case after the other in each, and each case reports the run with its median
//! time per step (all columns of a row come from that one run).

use crate::host::Host;
use crate::plot::{Mark, Plot, Series};
use anyhow::{Context, Result, bail};
use cosserat::io::{RunStatus, read_summary};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

/// One benchmark case.
struct Case {
    name: &'static str,
    scene: &'static str,
    overrides: Vec<String>,
    /// The reference code on this kind of machine: ms per step and Newton iterations per step.
    reference: Option<(f64, f64)>,
    /// The paper's Table 1 (32 cores, MKL): ms per step.
    paper_ms: Option<f64>,
    note: &'static str,
    /// Threads of the child process (`RAYON_NUM_THREADS`); `None` uses all cores.
    threads: Option<usize>,
    /// The paper's Table 1 row (scene, variant) of a contact scene: its Newton iterations and ms per
    /// step stand beside ours in the contact table.
    contact_row: Option<(&'static str, &'static str)>,
}

fn plate(
    element: &'static str,
    ny: usize,
    reference: Option<(f64, f64)>,
    paper_ms: Option<f64>,
    steps: Option<usize>,
    note: &'static str,
) -> Case {
    let mut overrides = vec![
        format!("mesh.nx={}", 10 * ny),
        format!("mesh.ny={ny}"),
        format!("mesh.element={element}"),
        "output.frames=false".into(),
    ];
    if let Some(n) = steps {
        overrides.push(format!("time.end={}", n as f64 * 0.01));
    }
    let name: &'static str = Box::leak(format!("plate_under_load {element} {}x{ny}", 10 * ny).into_boxed_str());
    Case {
        name,
        scene: "scenes/plate_under_load.toml",
        overrides,
        reference,
        paper_ms,
        note,
        threads: None,
        contact_row: None,
    }
}

/// A contact scene of the paper, run in full from its scene file (frames off; meshes from the scene).
fn contact_case(name: &'static str, scene: &'static str, row: (&'static str, &'static str)) -> Case {
    let paper = crate::paper::row(row.0, row.1, "tri6");
    Case {
        name,
        scene,
        overrides: vec!["output.frames=false".into()],
        reference: None,
        paper_ms: paper.map(|p| p.step_ms),
        note: "",
        threads: None,
        contact_row: Some(row),
    }
}

/// The same case restricted to one thread, for the 1-vs-all-threads comparison.
fn single_threaded(mut case: Case) -> Case {
    case.name = Box::leak(format!("{} (1 thread)", case.name).into_boxed_str());
    case.threads = Some(1);
    case
}

/// The cases in table order: the reference code's plates, strip and cylinders, two plates on one
/// thread, the contact scenes and, with `large`, the paper's largest plate.
fn cases(large: bool) -> Vec<Case> {
    // Long because the cases are a data table, each with its reference figures, that reads best as
    // one list.
    let mut c = vec![
        plate("tri3", 1, Some((2.3, 1.50)), Some(4.0), None, ""),
        plate("tri3", 2, Some((7.4, 1.51)), Some(11.0), None, ""),
        plate("tri3", 4, Some((29.0, 1.95)), Some(28.0), None, ""),
        plate("tri3", 8, Some((122.2, 2.00)), Some(68.0), None, ""),
        plate("tri3", 16, Some((785.4, 2.00)), Some(201.0), None, ""),
        plate(
            "tri3",
            32,
            Some((4665.1, 2.00)),
            Some(694.0),
            None,
            "reference timing partly disturbed by other load, see references.md",
        ),
        plate("tri6", 1, Some((3.8, 2.39)), Some(10.0), None, ""),
        plate("tri6", 2, Some((16.0, 2.33)), Some(32.0), None, ""),
        plate("tri6", 4, Some((60.6, 2.01)), Some(47.0), None, ""),
        plate("tri6", 8, Some((361.3, 2.00)), Some(155.0), None, ""),
        plate("tri6", 16, Some((2468.7, 2.00)), Some(550.0), None, ""),
        // The reference ran only the first 10 steps of this size: (17.3 + 2.0 + 10.6 + 303.2) s / 10
        // steps from its timers, at 2.3 iterations per step.
        plate(
            "tri6",
            32,
            Some((33310.0, 2.3)),
            Some(1856.0),
            Some(10),
            "first 10 steps only, as the reference",
        ),
        Case {
            name: "twisting_strip tri6 40x4",
            scene: "scenes/twisting_strip.toml",
            overrides: vec!["output.frames=false".into()],
            reference: Some((153.9, 4.21)),
            paper_ms: Some(78.0),
            note: "",
            threads: None,
            contact_row: None,
        },
        Case {
            name: "cylinder_coiling tri3 16x4",
            scene: "scenes/cylinder_coiling.toml",
            overrides: vec!["mesh.element=tri3".into(), "output.frames=false".into()],
            reference: Some((11.7, 2.22)),
            paper_ms: Some(10.0),
            note: "",
            threads: None,
            contact_row: None,
        },
        Case {
            name: "cylinder_coiling tri6 16x4",
            scene: "scenes/cylinder_coiling.toml",
            overrides: vec!["output.frames=false".into()],
            reference: Some((27.3, 2.23)),
            paper_ms: Some(25.0),
            note: "",
            threads: None,
            contact_row: None,
        },
    ];
    c.extend([
        single_threaded(plate("tri6", 8, None, None, None, "")),
        single_threaded(plate("tri6", 16, None, None, None, "")),
        contact_case(
            "dumpling plate model",
            "scenes/dumpling_plate.toml",
            ("dumpling", "plate model"),
        ),
        contact_case(
            "dumpling shell model",
            "scenes/dumpling_shell.toml",
            ("dumpling", "shell model"),
        ),
        contact_case("papyrus_scroll", "scenes/papyrus_scroll.toml", ("papyrus_scroll", "-")),
        contact_case("bunny h = 10 mm", "scenes/bunny.toml", ("bunny", "h = 10 mm")),
    ]);
    if large {
        c.push(plate(
            "tri6",
            64,
            None,
            Some(6901.0),
            Some(5),
            "first 5 steps; the paper's figure is a 200-step average on 32 cores",
        ));
    }
    c
}

/// One row of docs/performance.json.
#[derive(Debug, Serialize)]
struct Row {
    case: String,
    dofs: usize,
    /// Threads available to the run.
    threads: usize,
    ms_per_step: f64,
    reference_ms_per_step: Option<f64>,
    ratio: Option<f64>,
    newton_iterations: f64,
    reference_newton_iterations: Option<f64>,
    paper_ms_per_step: Option<f64>,
    assembly_share: f64,
    linear_solve_share: f64,
    factor_gflops_per_s: Option<f64>,
    peak_memory_mb: Option<f64>,
    note: String,
    /// Contact scenes: the paper's Newton iterations per step and where the contact time goes.
    contact: Option<ContactRow>,
}

/// The contact columns of a row.
#[derive(Debug, Serialize)]
struct ContactRow {
    paper_newton_iterations: Option<f64>,
    /// Shares of the steps' time: all of contact, broad phases, CCD, pair energies and derivatives.
    share: f64,
    broad_phase_share: f64,
    ccd_share: f64,
    pair_share: f64,
    mean_active_pairs: f64,
    min_gap_mm: Option<f64>,
}

fn cosserat_binary() -> Result<PathBuf> {
    let status = Command::new("cargo")
        .args(["build", "--release", "-p", "cosserat", "--bin", "cosserat"])
        .status()
        .context("building the cosserat binary")?;
    if !status.success() {
        bail!("building the cosserat binary failed");
    }
    Ok(PathBuf::from("target/release/cosserat"))
}

fn run_case(bin: &Path, case: &Case, out: &Path) -> Result<Row> {
    let mut cmd = Command::new(bin);
    if let Some(n) = case.threads {
        cmd.env("RAYON_NUM_THREADS", n.to_string());
    }
    cmd.arg("run").arg(case.scene).arg("--out").arg(out).arg("--quiet");
    for o in &case.overrides {
        cmd.arg("--set").arg(o);
    }
    let status = cmd.status().with_context(|| format!("running {}", case.name))?;
    let s = read_summary(&out.join("summary.json"))?;
    if !status.success() || s.status != RunStatus::Ok {
        bail!("{}: {:?} {}", case.name, s.status, s.reason.unwrap_or_default());
    }
    Ok(Row {
        case: case.name.into(),
        dofs: s.n_displacement_dofs + s.n_rotation_dofs,
        threads: case
            .threads
            .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get())),
        ms_per_step: s.avg_step_ms,
        reference_ms_per_step: case.reference.map(|r| r.0),
        ratio: case.reference.map(|r| r.0 / s.avg_step_ms),
        newton_iterations: s.avg_newton_iterations,
        reference_newton_iterations: case.reference.map(|r| r.1),
        paper_ms_per_step: case.paper_ms,
        assembly_share: s.assembly_share,
        linear_solve_share: s.linear_solve_share,
        factor_gflops_per_s: s.linear_solver.factor.as_ref().and_then(|f| f.gflops_per_s),
        peak_memory_mb: s.peak_memory_mb,
        note: case.note.into(),
        contact: case
            .contact_row
            .zip(s.contact.as_ref())
            .map(|((scene, variant), c)| ContactRow {
                paper_newton_iterations: crate::paper::row(scene, variant, "tri6").map(|p| p.iterations),
                share: c.share_of_step,
                broad_phase_share: c.broad_phase_share,
                ccd_share: c.ccd_share,
                pair_share: c.energy_share,
                mean_active_pairs: c.mean_active_pairs,
                min_gap_mm: c.min_gap.map(|g| 1e3 * g),
            }),
    })
}

/// The contact scenes: time per step and Newton iterations beside the paper's, and where the contact
/// time goes.
fn contact_section(md: &mut String, rows: &[Row]) -> Result<()> {
    let contact: Vec<(&Row, &ContactRow)> = rows.iter().filter_map(|r| r.contact.as_ref().map(|c| (r, c))).collect();
    if contact.is_empty() {
        return Ok(());
    }
    writeln!(md, "\n## Contact scenes\n")?;
    writeln!(
        md,
        "Whole runs of the paper's contact scenes (frames off). *Contact* is the share of the steps' time spent in contact, split into broad phases (bounding-volume hierarchies and candidate pairs), continuous collision detection (the step bound of every line search) and the pair terms (barrier and friction energies with their derivatives).\n"
    )?;
    writeln!(
        md,
        "| case | DOFs | ms/step | paper ms/step | Newton it. | paper it. | contact | broad phase | CCD | pair terms | active pairs (mean) | smallest gap |"
    )?;
    writeln!(md, "|---|---|---|---|---|---|---|---|---|---|---|---|")?;
    let pct = |v: f64| format!("{:.0} %", 100.0 * v);
    for (r, c) in contact {
        writeln!(
            md,
            "| {} | {} | {:.1} | {} | {:.2} | {} | {} | {} | {} | {} | {:.0} | {} |",
            r.case,
            r.dofs,
            r.ms_per_step,
            r.paper_ms_per_step.map_or("–".into(), |x| format!("{x:.0}")),
            r.newton_iterations,
            c.paper_newton_iterations.map_or("–".into(), |x| format!("{x:.1}")),
            pct(c.share),
            pct(c.broad_phase_share),
            pct(c.ccd_share),
            pct(c.pair_share),
            c.mean_active_pairs,
            c.min_gap_mm.map_or("–".into(), |g| format!("{g:.3} mm")),
        )?;
    }
    Ok(())
}

/// Dense matrix product rate of faer on this machine (GFLOP/s, all threads), the reference for the
/// factorisation's achieved rate.
fn gemm_peak() -> f64 {
    let n = 2000;
    let a = faer::Mat::<f64>::from_fn(n, n, |i, j| ((i * 7 + j * 13) % 17) as f64 * 0.1);
    let b = faer::Mat::<f64>::from_fn(n, n, |i, j| ((i * 3 + j * 5) % 11) as f64 * 0.1);
    let mut c = faer::Mat::<f64>::zeros(n, n);
    let mut best = f64::INFINITY;
    for _ in 0..5 {
        let t = std::time::Instant::now();
        faer::linalg::matmul::matmul(
            c.as_mut(),
            faer::Accum::Replace,
            a.as_ref(),
            b.as_ref(),
            1.0,
            faer::Par::rayon(0),
        );
        best = best.min(t.elapsed().as_secs_f64());
    }
    2.0 * (n as f64).powi(3) / best / 1e9
}

/// Runs the cases in `rounds` rounds and writes the tables.
pub fn run(large: bool, rounds: usize) -> Result<()> {
    let bin = cosserat_binary()?;
    let peak = gemm_peak();
    let rows = run_rounds(&bin, &cases(large), rounds);
    let host = Host::current();
    let cores = host.cores;
    let mut md = String::new();
    writeln!(md, "## Time per step against the reference code\n")?;
    writeln!(
        md,
        "Generated by `cargo xtask bench-table{}` on {} (git {}), release build, {}; all threads; each row is the run with the median time per step of {rounds} rounds over all cases. The reference is the authors' code (Stark, Eigen SparseLU) on a machine of the same kind (docs/references.md); the paper's figures are from a 32-core workstation with MKL. Dense GEMM peak here: {peak:.0} GFLOP/s.\n",
        if large { " --large" } else { "" },
        host.date_time,
        host.rev,
        host.machine(),
    )?;
    time_per_step_section(&mut md, &rows, cores)?;
    contact_section(&mut md, &rows)?;
    scaling_section(&mut md, &rows, cores)?;
    threads_section(&mut md, &rows, cores)?;
    std::fs::write("docs/performance.json", serde_json::to_string_pretty(&rows)?)?;
    replace_generated_section(Path::new("docs/performance.md"), &md)?;
    eprintln!("wrote docs/performance.md and docs/performance.json");
    Ok(())
}

/// Every case in each of `rounds` rounds, one after the other; per case the run with the median
/// time per step (a case that failed in every round has no row).
fn run_rounds(bin: &Path, cases: &[Case], rounds: usize) -> Vec<Row> {
    let mut runs: Vec<Vec<Row>> = cases.iter().map(|_| Vec::new()).collect();
    for round in 1..=rounds {
        for (case, runs) in cases.iter().zip(&mut runs) {
            eprintln!("{} (round {round} of {rounds}) ...", case.name);
            let out = PathBuf::from("out/bench").join(case.name.replace(' ', "_"));
            match run_case(bin, case, &out) {
                Ok(row) => {
                    eprintln!(
                        "  {:.1} ms/step ({:.2} it/step, assembly {:.1} %), reference {:?}",
                        row.ms_per_step,
                        row.newton_iterations,
                        100.0 * row.assembly_share,
                        row.reference_ms_per_step
                    );
                    runs.push(row);
                }
                Err(e) => eprintln!("  failed: {e:#}"),
            }
        }
    }
    runs.into_iter().filter_map(median_run).collect()
}

/// The main table: time per step of every case without contact that ran on all cores.
fn time_per_step_section(md: &mut String, rows: &[Row], cores: usize) -> Result<()> {
    writeln!(
        md,
        "| case | DOFs | ms/step | reference ms/step | speed-up | Newton it. | reference it. | paper ms/step | assembly | solve | factorisation GFLOP/s | peak memory |"
    )?;
    writeln!(md, "|---|---|---|---|---|---|---|---|---|---|---|---|")?;
    let opt = |v: Option<f64>, p: usize| v.map_or("–".to_string(), |x| format!("{x:.p$}"));
    for r in rows.iter().filter(|r| r.threads == cores && r.contact.is_none()) {
        writeln!(
            md,
            "| {}{} | {} | {:.1} | {} | {} | {:.2} | {} | {} | {:.0} % | {:.0} % | {} | {} |",
            r.case,
            if r.note.is_empty() {
                String::new()
            } else {
                format!(" ({})", r.note)
            },
            r.dofs,
            r.ms_per_step,
            opt(r.reference_ms_per_step, 1),
            r.ratio.map_or("–".into(), |x| format!("{x:.1}×")),
            r.newton_iterations,
            opt(r.reference_newton_iterations, 2),
            opt(r.paper_ms_per_step, 0),
            100.0 * r.assembly_share,
            100.0 * r.linear_solve_share,
            opt(r.factor_gflops_per_s, 1),
            r.peak_memory_mb.map_or("–".into(), |m| format!("{m:.0} MB")),
        )?;
    }
    Ok(())
}

/// Writes `md` into the generated section of the page at `path`, keeping the hand-written rest of
/// the document (a page without the section gets it at the top).
fn replace_generated_section(path: &Path, md: &str) -> Result<()> {
    let previous = std::fs::read_to_string(path).unwrap_or_default();
    // The generated table replaces its own section; the hand-written rest of the document stays.
    const START: &str = "<!-- bench-table -->";
    const END: &str = "<!-- /bench-table -->";
    let section = format!("{START}\n{md}{END}");
    let updated = match (previous.find(START), previous.find(END)) {
        (Some(a), Some(b)) if b > a => format!("{}{}{}", &previous[..a], section, &previous[b + END.len()..]),
        _ => format!("# Performance\n\n{section}\n{previous}"),
    };
    std::fs::write(path, updated)?;
    Ok(())
}

/// The run with the median time per step (the upper one of the middle two for an even count), so that
/// every column of a row comes from one run.
fn median_run(mut runs: Vec<Row>) -> Option<Row> {
    runs.sort_by(|a, b| a.ms_per_step.total_cmp(&b.ms_per_step));
    let mid = runs.len() / 2;
    runs.into_iter().nth(mid)
}

/// The exponent `p` and factor `c` of the least-squares fit `t = c nᵖ` on log–log axes.
fn power_fit(points: &[(f64, f64)]) -> Option<(f64, f64)> {
    let logs: Vec<(f64, f64)> = points
        .iter()
        .filter(|(n, t)| *n > 0.0 && *t > 0.0)
        .map(|(n, t)| (n.ln(), t.ln()))
        .collect();
    if logs.len() < 2 {
        return None;
    }
    let k = logs.len() as f64;
    let (mx, my) = logs.iter().fold((0.0, 0.0), |(a, b), (x, y)| (a + x / k, b + y / k));
    let sxx: f64 = logs.iter().map(|(x, _)| (x - mx).powi(2)).sum();
    let sxy: f64 = logs.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let p = sxy / sxx;
    Some((p, (my - p * mx).exp()))
}

/// Smallest size included in the fits: below it, fixed per-step costs (output, scripts, setup of the
/// step) dominate and the exponent would describe them rather than the algorithms.
const FIT_MIN_DOFS: usize = 2000;

/// Time per step, assembly and linear solve against the number of unknowns for the plate series,
/// with fitted exponents, as a table and a log–log plot (docs/img/scaling.svg).
fn scaling_section(md: &mut String, rows: &[Row], cores: usize) -> Result<()> {
    let mut series = Vec::new();
    writeln!(md, "\n## Scaling with the number of unknowns\n")?;
    writeln!(
        md,
        "Least-squares fits `t = c n^p` over the Plate under load rows with at least {FIT_MIN_DOFS} unknowns ({cores} threads). A sparse direct solve of a 2D mesh problem with a minimum-degree ordering grows like n^1.5 at best; assembly is linear.\n"
    )?;
    writeln!(md, "| elements | sizes | p (step) | p (assembly) | p (linear solve) |")?;
    writeln!(md, "|---|---|---|---|---|")?;
    for (k, element) in ["tri3", "tri6"].into_iter().enumerate() {
        let plate: Vec<&Row> = rows
            .iter()
            .filter(|r| r.threads == cores && r.case.starts_with(&format!("plate_under_load {element} ")))
            .collect();
        let pick =
            |f: &dyn Fn(&Row) -> f64| -> Vec<(f64, f64)> { plate.iter().map(|r| (r.dofs as f64, f(r))).collect() };
        let step = pick(&|r| r.ms_per_step);
        let assembly = pick(&|r| r.ms_per_step * r.assembly_share);
        let solve = pick(&|r| r.ms_per_step * r.linear_solve_share);
        let fitted = |pts: &[(f64, f64)]| {
            let big: Vec<(f64, f64)> = pts.iter().copied().filter(|(n, _)| *n >= FIT_MIN_DOFS as f64).collect();
            power_fit(&big).map_or("–".to_string(), |(p, _)| format!("{p:.2}"))
        };
        let n_big = plate.iter().filter(|r| r.dofs >= FIT_MIN_DOFS).count();
        writeln!(
            md,
            "| {element} | {n_big} | {} | {} | {} |",
            fitted(&step),
            fitted(&assembly),
            fitted(&solve)
        )?;
        for (label, points, mark) in [
            ("step", step, Mark::LinePoints),
            ("assembly", assembly, Mark::Points),
            ("linear solve", solve, Mark::Points),
        ] {
            series.push(Series {
                label: format!("{element} {label}"),
                points,
                mark,
                color: 1 + 3 * k + series.len() % 3,
            });
        }
    }
    let plot = Plot {
        title: "Plate under load: time per step".into(),
        x_label: "unknowns".into(),
        y_label: "ms per step".into(),
        log_log: true,
        series,
    };
    std::fs::create_dir_all("docs/img")?;
    plot.write_svg(Path::new("docs/img/scaling.svg"))?;
    writeln!(md, "\n![time per step against unknowns](img/scaling.svg)")?;
    Ok(())
}

/// Single-threaded runs beside the same cases on all threads.
fn threads_section(md: &mut String, rows: &[Row], cores: usize) -> Result<()> {
    let single: Vec<&Row> = rows.iter().filter(|r| r.threads == 1 && cores > 1).collect();
    if single.is_empty() {
        return Ok(());
    }
    writeln!(md, "\n## One thread against {cores}\n")?;
    writeln!(
        md,
        "| case | ms/step, 1 thread | ms/step, {cores} threads | speed-up | assembly speed-up | solve speed-up |"
    )?;
    writeln!(md, "|---|---|---|---|---|---|")?;
    for one in single {
        let base = one.case.trim_end_matches(" (1 thread)");
        let Some(all) = rows.iter().find(|r| r.threads == cores && r.case == base) else {
            continue;
        };
        let part = |r: &Row, share: f64| r.ms_per_step * share;
        writeln!(
            md,
            "| {base} | {:.1} | {:.1} | {:.2}× | {:.2}× | {:.2}× |",
            one.ms_per_step,
            all.ms_per_step,
            one.ms_per_step / all.ms_per_step,
            part(one, one.assembly_share) / part(all, all.assembly_share),
            part(one, one.linear_solve_share) / part(all, all.linear_solve_share),
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(ms: f64, iterations: f64) -> Row {
        Row {
            case: "case".into(),
            dofs: 1,
            threads: 1,
            ms_per_step: ms,
            reference_ms_per_step: None,
            ratio: None,
            newton_iterations: iterations,
            reference_newton_iterations: None,
            paper_ms_per_step: None,
            assembly_share: 0.0,
            linear_solve_share: 0.0,
            factor_gflops_per_s: None,
            peak_memory_mb: None,
            note: String::new(),
            contact: None,
        }
    }

    #[test]
    fn the_median_run_is_one_whole_run() {
        // The iteration count identifies the run: it must travel with its time.
        let picked = median_run(vec![row(30.0, 3.0), row(10.0, 1.0), row(20.0, 2.0)]).unwrap();
        assert_eq!((picked.ms_per_step, picked.newton_iterations), (20.0, 2.0));
        let picked = median_run(vec![row(40.0, 4.0), row(10.0, 1.0), row(30.0, 3.0), row(20.0, 2.0)]).unwrap();
        assert_eq!((picked.ms_per_step, picked.newton_iterations), (30.0, 3.0));
        assert_eq!(median_run(vec![row(5.0, 1.0)]).unwrap().ms_per_step, 5.0);
        assert!(median_run(Vec::new()).is_none());
    }
}
