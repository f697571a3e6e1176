//! Load paths through limit points in `cargo xtask validate`: the hinged cylindrical roofs (Sze 3.8,
//! h = 12.7 and 6.35) and the shallow sinusoidal arch (closed form) traced by arc-length continuation
//! on a mesh ladder and compared with the reference paths along the path, with plots of the load
//! factor against the centre deflection.
//!
//! Two measures compare a computed path with a reference one. The *distance* of a reference point
//! `(W, λ)` to the computed path (a polyline through its equilibria, in path order) is measured with
//! deflections divided by the reference path's largest deflection and load factors by its largest
//! load factor; it is small wherever the two paths lie on each other, whether they are steep or flat
//! there. The *load at the reference deflection* is the computed load factor where the computed path
//! crosses the reference deflection (the crossing nearest in load), divided by the reference path's
//! largest load factor; it is meaningful where the deflection grows along the path and is not given
//! for paths that snap back.

use crate::plot::{Mark, Plot, Series};
use crate::reference::{SZE_HINGED_ROOF, SZE_HINGED_ROOF_THIN, shallow_arch_load};
use crate::runner::{RunOutcome, run_described};
use crate::validate::Options;
use anyhow::Result;
use cosserat::RunDescription;
use std::fmt::Write as _;
use std::path::Path;

/// A validation problem whose reference is a load path.
pub struct PathProblem {
    /// Short name (output folder, image name).
    pub name: &'static str,
    /// Section title.
    pub title: &'static str,
    /// Scene file.
    pub scene: &'static str,
    /// The reference path: `(λ, W)` in path order.
    pub reference: Vec<(f64, f64)>,
    /// The reference's name in the plot.
    pub reference_label: &'static str,
    /// Where the reference comes from.
    pub reference_note: &'static str,
    /// The ladder's meshes, quads `(nx, ny)` (the scene's own first).
    pub meshes: &'static [(usize, usize)],
    /// Whether the deflection grows along the whole path (then loads are compared at deflections).
    pub monotone: bool,
    /// The largest distance any reference point may have from the path on the scene's mesh.
    pub required: Option<f64>,
}

/// The problems.
pub fn problems() -> Vec<PathProblem> {
    vec![
        PathProblem {
            name: "hinged_roof",
            title: "Hinged cylindrical roof, h = 12.7: snap-through (Sze 3.8)",
            scene: "scenes/validation/hinged_roof.toml",
            reference: SZE_HINGED_ROOF.to_vec(),
            reference_label: "Sze et al. 2004",
            reference_note: "Sze, Liu and Lo (2004), problem 3.8, isotropic, h = 12.7: −W_C at the centre along the path (docs/references.md)",
            meshes: &[(16, 16), (24, 24), (32, 32)],
            monotone: true,
            required: Some(0.02),
        },
        PathProblem {
            name: "hinged_roof_thin",
            title: "Hinged cylindrical roof, h = 6.35: snap-through and snap-back (Sze 3.8)",
            scene: "scenes/validation/hinged_roof_thin.toml",
            reference: SZE_HINGED_ROOF_THIN.to_vec(),
            reference_label: "Sze et al. 2004",
            reference_note: "Sze, Liu and Lo (2004), problem 3.8, isotropic, h = 6.35, normalised by the thicker roof's P_max = 3000 (docs/references.md)",
            meshes: &[(16, 16), (24, 24), (32, 32)],
            monotone: false,
            required: None,
        },
        PathProblem {
            name: "shallow_arch",
            title: "Shallow sinusoidal arch under a sinusoidal load: snap-through (closed form)",
            scene: "scenes/validation/shallow_arch.toml",
            reference: shallow_arch_reference(),
            reference_label: "shallow-arch closed form",
            reference_note: "the closed form of shallow-arch theory for the rise e = 4r, every quarter of r in crown deflection (docs/references.md)",
            meshes: &[(32, 2), (16, 2), (64, 2)],
            monotone: true,
            required: Some(0.02),
        },
    ]
}

/// The closed-form path of the shallow arch scene: `(λ, W)` at crown deflections `W` every quarter
/// of the radius of gyration `r`, up to `8.25 r` (past the second crossing of the limit load). The
/// scene's values: span 1 (`k = π`), `h = 0.01`, `E = 1e6`, the load `0.25 λ` per area, rise `4r`.
fn shallow_arch_reference() -> Vec<(f64, f64)> {
    let (h, young, load) = (0.01_f64, 1.0e6, 0.25);
    let r = h / 12f64.sqrt();
    let unit = young * h.powi(3) / 12.0 * std::f64::consts::PI.powi(4) * r / load;
    (0..=33)
        .map(|i| 0.25 * f64::from(i))
        .map(|w| (unit * shallow_arch_load(4.0, w), w * r))
        .collect()
}

/// A computed path against the reference one.
#[derive(Debug, Clone)]
pub struct PathComparison {
    /// Per reference point: `(W, λ, distance, load at that deflection)`.
    pub points: Vec<(f64, f64, f64, Option<f64>)>,
    /// The largest distance.
    pub max_distance: f64,
    /// The largest difference of load at the reference deflections (relative), where compared.
    pub max_load_error: Option<f64>,
}

/// Compares `path` (`(λ, W)` in path order) with `reference` (see the module documentation).
pub fn compare_path(reference: &[(f64, f64)], path: &[(f64, f64)], monotone: bool) -> PathComparison {
    let w_max = reference.iter().map(|p| p.1.abs()).fold(0.0, f64::max);
    let l_max = reference.iter().map(|p| p.0.abs()).fold(0.0, f64::max);
    let scaled: Vec<(f64, f64)> = path.iter().map(|&(l, w)| (w / w_max, l / l_max)).collect();
    let mut points = Vec::new();
    for &(l, w) in reference {
        let p = (w / w_max, l / l_max);
        let distance = scaled
            .windows(2)
            .map(|s| segment_distance(p, s[0], s[1]))
            .fold(f64::INFINITY, f64::min);
        let load = monotone.then(|| load_at_deflection(path, w, l)).flatten();
        points.push((w, l, distance, load));
    }
    let max_distance = points.iter().map(|p| p.2).fold(0.0, f64::max);
    let max_load_error = monotone.then(|| {
        points
            .iter()
            .map(|p| p.3.map_or(f64::INFINITY, |x| (x - p.1).abs() / l_max))
            .fold(0.0, f64::max)
    });
    PathComparison {
        points,
        max_distance,
        max_load_error,
    }
}

/// Distance of `p` to the segment `a b`.
fn segment_distance(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len2 = dx * dx + dy * dy;
    let t = if len2 == 0.0 {
        0.0
    } else {
        (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / len2).clamp(0.0, 1.0)
    };
    ((p.0 - a.0 - t * dx).powi(2) + (p.1 - a.1 - t * dy).powi(2)).sqrt()
}

/// The load factor where `path` crosses the deflection `w`, the crossing nearest to `near` in load.
fn load_at_deflection(path: &[(f64, f64)], w: f64, near: f64) -> Option<f64> {
    path.windows(2)
        .filter(|s| (s[0].1 - w) * (s[1].1 - w) <= 0.0 && s[0].1 != s[1].1)
        .map(|s| s[0].0 + (s[1].0 - s[0].0) * (w - s[0].1) / (s[1].1 - s[0].1))
        .min_by(|a, b| (a - near).abs().total_cmp(&(b - near).abs()))
}

/// One run of a path problem.
struct PathRun {
    mesh: (usize, usize),
    outcome: RunOutcome,
    path: Vec<(f64, f64)>,
    comparison: Option<PathComparison>,
}

/// The computed path `(λ, −centre.uz)` of a run, including the start.
pub fn read_path(outcome: &RunOutcome) -> Option<Vec<(f64, f64)>> {
    let p = outcome.probes.as_ref()?;
    let (l, w) = (p.column("path.load_factor").ok()?, p.column("centre.uz").ok()?);
    Some(p.rows.iter().map(|r| (r[l], -r[w])).collect())
}

fn run_problem(problem: &PathProblem, o: &Options) -> Result<Vec<PathRun>> {
    let meshes = if o.quick { &problem.meshes[..1] } else { problem.meshes };
    let mut runs = Vec::new();
    for &(nx, ny) in meshes {
        let overrides = [
            format!("mesh.nx={nx}"),
            format!("mesh.ny={ny}"),
            "output.frames=false".into(),
        ];
        let dir = o.out.join(problem.name).join(format!("{nx}x{ny}"));
        eprintln!("{}: {nx}×{ny} ...", problem.name);
        let outcome = run_described(&o.runner, &RunDescription::new(problem.scene, dir, &overrides))?;
        if !outcome.is_ok() {
            eprintln!("  failed: {}", outcome.reason());
        }
        let path = read_path(&outcome).unwrap_or_default();
        let comparison =
            (outcome.is_ok() && path.len() > 1).then(|| compare_path(&problem.reference, &path, problem.monotone));
        runs.push(PathRun {
            mesh: (nx, ny),
            outcome,
            path,
            comparison,
        });
    }
    Ok(runs)
}

fn plot(problem: &PathProblem, runs: &[PathRun], path: &Path) -> Result<()> {
    let mut series = vec![Series {
        label: problem.reference_label.into(),
        points: problem.reference.iter().map(|&(l, w)| (w, l)).collect(),
        mark: Mark::Points,
        color: 0,
    }];
    for (k, r) in runs.iter().enumerate().filter(|(_, r)| r.path.len() > 1) {
        series.push(Series {
            label: format!("Tri6/Tri3 {}×{}", r.mesh.0, r.mesh.1),
            points: r.path.iter().map(|&(l, w)| (w, l)).collect(),
            mark: Mark::Line,
            color: 1 + k,
        });
    }
    Plot {
        title: problem.title.into(),
        x_label: "centre deflection".into(),
        y_label: "load factor P/P_max".into(),
        log_log: false,
        series,
    }
    .write_svg(path)
}

/// `x` with four significant digits.
fn significant(x: f64) -> String {
    let digits = if x == 0.0 {
        3
    } else {
        (3 - x.abs().log10().floor() as i64).max(0) as usize
    };
    format!("{x:.digits$}")
}

fn pct(x: f64) -> String {
    format!("{:.2} %", 100.0 * x)
}

/// Runs the path problems and returns their section of `docs/validation.md`.
///
/// # Errors
/// I/O failures.
pub fn run_all(o: &Options) -> Result<String> {
    let mut md = String::from(
        "\n## Load paths through limit points (arc-length continuation)\n\nScenes with `time.mode = \"arc_length\"`: every equilibrium along the path is a row of `probes.csv`, with the load factor in `path.load_factor`. Two measures compare a computed path with the reference one (published points or a closed form): the *distance* of each reference point from the computed path, with deflections divided by the reference path's largest deflection and load factors by its largest load factor (small wherever the paths lie on each other, steep or flat); and, where the deflection grows along the whole path, the computed *load at the reference deflection*, its difference divided by the largest reference load factor. Largest over the reference points.\n",
    );
    for problem in problems() {
        let runs = run_problem(&problem, o)?;
        let image = o.images.join(format!("validation_{}.svg", problem.name));
        writeln!(
            md,
            "\n### {}\n\nScene `{}`. Reference: {}.\n",
            problem.title, problem.scene, problem.reference_note
        )?;
        match plot(&problem, &runs, &image) {
            Ok(()) => writeln!(
                md,
                "![{}](img/{})\n",
                problem.title,
                image.file_name().map(|f| f.to_string_lossy().into_owned()).unwrap_or_default()
            )?,
            Err(e) => writeln!(md, "(plot not written: {e})\n")?,
        }
        writeln!(
            md,
            "| mesh | DOFs | steps | corrector it./step | largest distance | largest load error at the reference deflections | solve wall | status |\n|---|---|---|---|---|---|---|---|"
        )?;
        for r in &runs {
            writeln!(md, "{}", run_row(r))?;
        }
        writeln!(md, "\n{}", findings(&problem, &runs))?;
        if let Some(r) = runs.iter().rev().find(|r| r.comparison.is_some()) {
            point_table(&problem, r, &mut md)?;
        }
    }
    Ok(md)
}

fn run_row(r: &PathRun) -> String {
    let s = r.outcome.summary.as_ref();
    let c = r.comparison.as_ref();
    format!(
        "| {}×{} | {} | {} | {} | {} | {} | {} | {} |",
        r.mesh.0,
        r.mesh.1,
        s.map_or("–".into(), |s| (s.n_displacement_dofs + s.n_rotation_dofs)
            .to_string()),
        s.map_or("–".into(), |s| s.n_steps.to_string()),
        s.map_or("–".into(), |s| format!("{:.2}", s.avg_newton_iterations)),
        c.map_or("–".into(), |c| pct(c.max_distance)),
        c.and_then(|c| c.max_load_error).map_or("–".into(), pct),
        s.map_or("–".into(), |s| format!("{:.1} s", s.wall_seconds)),
        if r.outcome.is_ok() {
            "ok".to_string()
        } else {
            format!("**failed**: {}", r.outcome.reason())
        }
    )
}

/// The paragraph under a problem's table, from its runs.
fn findings(problem: &PathProblem, runs: &[PathRun]) -> String {
    let Some(own) = runs.first().filter(|r| r.comparison.is_some()) else {
        return "The run on the scene's mesh did not finish; see the table.".into();
    };
    let c = own.comparison.as_ref().expect("filtered");
    let (l, w) = extremes(&own.path);
    let ref_max = problem.reference.iter().map(|p| p.0).fold(f64::NEG_INFINITY, f64::max);
    let first_limit = problem
        .reference
        .windows(2)
        .find(|s| s[1].0 < s[0].0)
        .map_or(ref_max, |s| s[0].0);
    let mut text = format!(
        "On the scene's mesh ({}×{}) every reference point lies within {} of the computed path. The computed first limit load is λ = {:.4} against the reference's {first_limit:.4} ({:+.2} %); the smallest load after it is λ = {:.4}, and the centre deflection reaches {}.",
        own.mesh.0,
        own.mesh.1,
        pct(c.max_distance),
        l.0,
        100.0 * (l.0 / first_limit - 1.0),
        l.1,
        significant(w)
    );
    if let Some(required) = problem.required {
        let verdict = if c.max_distance <= required {
            "within"
        } else {
            "**outside**"
        };
        write!(text, " That is {verdict} the required {}.", pct(required)).ok();
    }
    text
}

/// The first limit load along a path and the smallest load after it, and the largest deflection.
fn extremes(path: &[(f64, f64)]) -> ((f64, f64), f64) {
    let peak = path.windows(2).position(|s| s[1].0 < s[0].0).unwrap_or(path.len() - 1);
    let first = path[peak].0;
    let valley = path[peak..]
        .windows(2)
        .position(|s| s[1].0 > s[0].0)
        .map_or(first, |k| path[peak + k].0);
    let w_max = path.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max);
    ((first, valley), w_max)
}

fn point_table(problem: &PathProblem, r: &PathRun, md: &mut String) -> Result<()> {
    let c = r.comparison.as_ref().expect("compared runs only");
    writeln!(
        md,
        "\nEvery reference point against the {}×{} path:\n\n| deflection W | λ reference | λ computed at W | distance |\n|---:|---:|---:|---:|",
        r.mesh.0, r.mesh.1
    )?;
    for &(w, l, d, load) in &c.points {
        let computed = if problem.monotone {
            load.map_or("–".into(), |x| format!("{x:.4}"))
        } else {
            "–".into()
        };
        writeln!(md, "| {} | {l:.4} | {computed} | {} |", significant(w), pct(d))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_path_through_the_published_points_has_no_distance_and_a_shifted_one_has_its_shift() {
        let reference = [(0.5, 1.0), (1.0, 2.0), (0.5, 3.0)];
        let exact = compare_path(&reference, &[(0.0, 0.0), (0.5, 1.0), (1.0, 2.0), (0.5, 3.0)], true);
        assert!(exact.max_distance < 1e-15);
        assert_eq!(exact.max_load_error, Some(0.0));
        // Loads 0.1 higher everywhere: the load error is 0.1 of the largest load 1, and the distance
        // at most that.
        let shifted = compare_path(&reference, &[(0.1, 0.0), (0.6, 1.0), (1.1, 2.0), (0.6, 3.0)], true);
        assert!((shifted.max_load_error.unwrap() - 0.1).abs() < 1e-12);
        assert!(shifted.max_distance <= 0.1 + 1e-12 && shifted.max_distance > 0.0);
        // A path that ends before the last point is far from it.
        let short = compare_path(&reference, &[(0.0, 0.0), (0.5, 1.0), (1.0, 2.0)], true);
        assert!(short.max_distance > 0.3);
        assert_eq!(short.max_load_error, Some(f64::INFINITY));
    }
}
