//! `cargo xtask experiments`: runs the paper's experiments from the scene files in `scenes/` (those with
//! contact — Bunny, Dumpling, Papyrus scroll — in the `contact` module), checks what each should show, and writes
//! the timing table beside the paper's Table 1.
//!
//! Experiments are data: a scene file plus a list of runs (override sets, e.g. the refinement ladder)
//! and a check that reads the written outputs back.

use crate::paper;
use crate::postprocess::{ProbeTable, boundary_loops, fit_circle, hausdorff, rim_waves};
use anyhow::{Context, Result};
use cosserat::Simulation;
use cosserat::scene::output::{RunStatus, RunSummary, VtuFrame, read_pvd, read_pvd_frame};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

mod comparison;
mod contact;

/// How the experiments run.
#[derive(Debug, Clone)]
pub struct Options {
    /// A short version of each run (a few steps, the coarsest meshes).
    pub quick: bool,
    /// Include the largest meshes of the ladders and the paper's armadillo mesh.
    pub large: bool,
    /// Only experiments whose name contains this.
    pub only: Option<String>,
    /// Directory with the experiments' OBJ meshes (`assets/meshes` of the workspace).
    pub meshes: PathBuf,
    /// Root of the run outputs.
    pub out: PathBuf,
    /// Where to render the README pictures (`None`: no pictures).
    pub render_dir: Option<PathBuf>,
}

impl Options {
    /// The absolute path of a mesh in [`Options::meshes`], for a `--set …path=` override (scene paths
    /// are resolved against the scene file's folder). A missing file is left to the run, whose error
    /// names it.
    fn mesh(&self, name: &str) -> PathBuf {
        let path = self.meshes.join(name);
        std::path::absolute(&path).unwrap_or(path)
    }
}

/// One run of an experiment.
#[derive(Debug, Clone)]
pub struct RunSpec {
    /// Variant label (Table 1's "Variant" column).
    pub variant: String,
    /// Displacement element.
    pub element: String,
    /// Scene file.
    pub scene: PathBuf,
    /// `--set` overrides.
    pub overrides: Vec<String>,
}

/// A finished run with its outputs read back.
#[derive(Debug, Clone)]
pub struct RunResult {
    /// The run.
    pub spec: RunSpec,
    /// Its summary.
    pub summary: RunSummary,
    /// Its probes.
    pub probes: Option<ProbeTable>,
    /// Its last frame.
    pub frame: Option<VtuFrame>,
    /// Its output directory.
    pub dir: PathBuf,
}

/// An experiment: its runs and its check.
pub struct Experiment {
    /// Name (Table 1's scene).
    pub name: &'static str,
    /// Title for the report.
    pub title: &'static str,
    /// The runs.
    pub runs: fn(&Options) -> Vec<RunSpec>,
    /// What it should show, measured on the outputs: report lines (markdown).
    pub check: fn(&[RunResult]) -> Vec<String>,
    /// Render every run's last frame for the README (`false`: only the last run, the finest mesh).
    pub render_each: bool,
}

fn run(variant: &str, element: &str, scene: &str, overrides: &[String]) -> RunSpec {
    RunSpec {
        variant: variant.into(),
        element: element.into(),
        scene: PathBuf::from(scene),
        overrides: overrides.to_vec(),
    }
}

fn quick_end(o: &Options, end: f64) -> Vec<String> {
    if o.quick {
        vec![format!("time.end={end}")]
    } else {
        Vec::new()
    }
}

fn ladder(o: &Options, full: &[usize], large: &[usize], quick: &[usize]) -> Vec<usize> {
    if o.quick {
        quick.to_vec()
    } else if o.large {
        full.iter().chain(large).copied().collect()
    } else {
        full.to_vec()
    }
}

/// All experiments.
pub fn registry() -> Vec<Experiment> {
    vec![
        Experiment {
            name: "twisting_strip",
            title: "Twisting strip",
            runs: twisting_runs,
            check: twisting_check,
            render_each: false,
        },
        Experiment {
            name: "plate_under_load",
            title: "Plate under load",
            runs: plate_runs,
            check: plate_check,
            render_each: false,
        },
        Experiment {
            name: "cylinder_coiling",
            title: "Cylinder coiling",
            runs: coiling_runs,
            check: coiling_check,
            render_each: false,
        },
        Experiment {
            name: "lotus_flower",
            title: "Lotus flower",
            runs: lotus_runs,
            check: lotus_check,
            render_each: false,
        },
        Experiment {
            name: "curvature_modes",
            title: "Curvature modes",
            runs: modes_runs,
            check: modes_check,
            render_each: false,
        },
        Experiment {
            name: "armadillos",
            title: "Armadillos",
            runs: armadillo_runs,
            check: armadillo_check,
            render_each: false,
        },
        Experiment {
            name: "buckling_circle",
            title: "Buckling circle",
            runs: buckling_runs,
            check: buckling_check,
            render_each: true,
        },
        Experiment {
            name: "moebius",
            title: "Möbius strip",
            runs: moebius_runs,
            check: moebius_check,
            render_each: true,
        },
        Experiment {
            name: "bunny",
            title: "Bunny",
            runs: contact::bunny_runs,
            check: contact::bunny_check,
            render_each: true,
        },
        Experiment {
            name: "bunny_kl",
            title: "Bunny, Kirchhoff–Love comparison model",
            runs: comparison::bunny_kl_runs,
            check: comparison::bunny_kl_check,
            render_each: true,
        },
        Experiment {
            name: "lotus_flower_tet4",
            title: "Lotus flower, volumetric Tet4 comparison model",
            runs: comparison::lotus_tet4_runs,
            check: comparison::lotus_tet4_check,
            render_each: false,
        },
        Experiment {
            name: "dumpling",
            title: "Dumpling",
            runs: contact::dumpling_runs,
            check: contact::dumpling_check,
            render_each: true,
        },
        Experiment {
            name: "papyrus_scroll",
            title: "Papyrus scroll",
            runs: contact::scroll_runs,
            check: contact::scroll_check,
            render_each: false,
        },
    ]
}

fn twisting_runs(o: &Options) -> Vec<RunSpec> {
    vec![run("-", "tri6", "scenes/twisting_strip.toml", &quick_end(o, 0.05))]
}

fn twisting_check(r: &[RunResult]) -> Vec<String> {
    let mut lines = Vec::new();
    for res in r {
        let s = &res.summary;
        lines.push(format!(
            "- {} steps completed ({:?}), {:.2} Newton iterations per step (at most {}).",
            s.n_steps,
            s.status,
            s.avg_newton_iterations,
            s.extra.get("max_newton_iterations").map_or("?".into(), |v| v.to_string())
        ));
        if let Some(p) = &res.probes
            && let (Ok(d3), Ok(t)) = (p.last_vec("right_director", ["d3x", "d3y", "d3z"]), p.last("t"))
        {
            let theta = 2.0 * std::f64::consts::PI * t;
            let target = [0.0, -theta.sin(), theta.cos()];
            let dot = (d3[0] * target[0] + d3[1] * target[1] + d3[2] * target[2]).clamp(-1.0, 1.0);
            lines.push(format!(
                "- Right end at t = {t:.2} s: twist {:.1}°; angle between its d₃ and the target R_x(θ) e_z: {:.3}°.",
                theta.to_degrees(),
                dot.acos().to_degrees()
            ));
        }
        if let Some(a) = s.extra.get("min_area_ratio").and_then(|v| v.as_f64()) {
            lines.push(format!(
                "- Smallest signed area ratio over all quadrature points and frames: {a:.3} ({}).",
                if a > 0.0 {
                    "no inverted element"
                } else {
                    "INVERTED ELEMENT"
                }
            ));
        }
    }
    lines
}

/// Tip deflections (mm) of the reference code on this kind of machine (docs/references.md).
const REFERENCE_PLATE_TIP: &[(&str, usize, f64)] = &[
    ("tri3", 1, 2.3691),
    ("tri3", 2, 7.2877),
    ("tri3", 4, 16.6727),
    ("tri3", 8, 25.6076),
    ("tri3", 16, 29.8340),
    ("tri3", 32, 31.1462),
    ("tri6", 1, 30.9501),
    ("tri6", 2, 31.4029),
    ("tri6", 4, 31.5405),
    ("tri6", 8, 31.5966),
    ("tri6", 16, 31.6096),
];

fn plate_runs(o: &Options) -> Vec<RunSpec> {
    let mut runs = Vec::new();
    for element in ["tri3", "tri6"] {
        for ny in ladder(o, &[1, 2, 4, 8, 16], &[32, 64], &[1, 2]) {
            let mut ov = vec![
                format!("mesh.nx={}", 10 * ny),
                format!("mesh.ny={ny}"),
                format!("mesh.element={element}"),
            ];
            ov.extend(quick_end(o, 0.05));
            runs.push(run(
                &format!("{}x{ny}", 10 * ny),
                element,
                "scenes/plate_under_load.toml",
                &ov,
            ));
        }
    }
    runs
}

fn plate_check(r: &[RunResult]) -> Vec<String> {
    let mut lines = vec![
        "| element | mesh | tip u_z at t = end [mm] | reference code [mm] | change from previous mesh [mm] |"
            .to_string(),
        "|---|---|---|---|---|".to_string(),
    ];
    for element in ["tri3", "tri6"] {
        let mut prev: Option<f64> = None;
        let mut tips = Vec::new();
        for res in r.iter().filter(|x| x.spec.element == element) {
            let Some(tip) = res.probes.as_ref().and_then(|p| p.last("tip.uz").ok()).map(|v| 1e3 * v) else {
                continue;
            };
            let ny: usize = res.spec.variant.split('x').nth(1).and_then(|s| s.parse().ok()).unwrap_or(0);
            let reference = REFERENCE_PLATE_TIP
                .iter()
                .find(|x| x.0 == element && x.1 == ny)
                .map_or("–".into(), |x| format!("{:.4}", x.2));
            let change = prev.map_or("–".into(), |p| format!("{:+.4}", tip - p));
            lines.push(format!(
                "| {element} | {} | {tip:.4} | {reference} | {change} |",
                res.spec.variant
            ));
            prev = Some(tip);
            tips.push(tip);
        }
        if tips.len() >= 3 {
            let n = tips.len();
            let (d1, d2) = (tips[n - 2] - tips[n - 3], tips[n - 1] - tips[n - 2]);
            if d1 != 0.0 && d2 != 0.0 && d1.signum() == d2.signum() {
                let order = (d1 / d2).abs().log2();
                let extrapolated = tips[n - 1] + d2 / ((d1 / d2).abs() - 1.0);
                lines.push(format!("\n{element}: observed convergence order of the tip deflection over the last three meshes: {order:.2}; Richardson-extrapolated value {extrapolated:.4} mm.\n"));
            }
        }
    }
    lines
}

fn coiling_runs(o: &Options) -> Vec<RunSpec> {
    let mut runs = Vec::new();
    for element in ["tri3", "tri6"] {
        for ny in ladder(o, &[1, 2, 4, 8], &[16, 32, 64], &[1]) {
            let mut ov = vec![
                format!("mesh.nx={}", 4 * ny),
                format!("mesh.ny={ny}"),
                format!("mesh.element={element}"),
            ];
            ov.extend(quick_end(o, 0.05));
            runs.push(run(
                &format!("{}x{ny}", 4 * ny),
                element,
                "scenes/cylinder_coiling.toml",
                &ov,
            ));
        }
    }
    runs
}

fn coiling_check(r: &[RunResult]) -> Vec<String> {
    let target = 1.0 / (4.0 * std::f64::consts::PI);
    let mut lines = vec![
        format!(
            "Target: a full circle of radius 1/(4π) = {:.3} mm; the free end meets the clamped end.\n",
            1e3 * target
        ),
        "| element | mesh | gap free end – clamp [mm] | fitted radius [mm] | radius error | rms off-circle [mm] |"
            .to_string(),
        "|---|---|---|---|---|---|".to_string(),
    ];
    for res in r {
        let gap = res.probes.as_ref().and_then(|p| {
            let a = p.last_vec("free_end", ["x", "y", "z"]).ok()?;
            let b = p.last_vec("clamped_end", ["x", "y", "z"]).ok()?;
            Some(1e3 * ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt())
        });
        let fit = res.frame.as_ref().and_then(|f| fit_circle(&f.points, 0, 2).ok());
        let (radius, err, rms) = fit.map_or(("–".into(), "–".into(), "–".into()), |(_, _, rad, rms)| {
            (
                format!("{:.3}", 1e3 * rad),
                format!("{:+.2} %", 100.0 * (rad - target) / target),
                format!("{:.3}", 1e3 * rms),
            )
        });
        lines.push(format!(
            "| {} | {} | {} | {radius} | {err} | {rms} |",
            res.spec.element,
            res.spec.variant,
            gap.map_or("–".into(), |g| format!("{g:.2}"))
        ));
    }
    lines
}

fn lotus_runs(o: &Options) -> Vec<RunSpec> {
    ladder(o, &[4, 8, 16], &[32, 64], &[4])
        .into_iter()
        .map(|n| {
            let mut ov: Vec<String> = (0..3)
                .flat_map(|s| [format!("shell.{s}.mesh.nx={n}"), format!("shell.{s}.mesh.ny={n}")])
                .collect();
            ov.extend(quick_end(o, 0.05));
            run(&format!("{n}x{n}"), "tri6", "scenes/lotus_flower.toml", &ov)
        })
        .collect()
}

fn lotus_check(r: &[RunResult]) -> Vec<String> {
    let mut lines = vec![
        "Paper rows are for one layer; this scene runs the three layers (b = 0.1, 0.2, 0.35) in one system, so cells and DOFs are three times the paper's.\n".to_string(),
        "| mesh | edge-midpoint height b = 0.1 / 0.2 / 0.35 [m] | corner height [m] |".to_string(),
        "|---|---|---|".to_string(),
    ];
    for res in r {
        let Some(p) = &res.probes else { continue };
        let z = |name: &str| p.last(&format!("{name}.z")).map_or("–".into(), |v| format!("{v:.3}"));
        lines.push(format!(
            "| {} | {} / {} / {} | {} / {} / {} |",
            res.spec.variant,
            z("b010_edge_mid"),
            z("b020_edge_mid"),
            z("b035_edge_mid"),
            z("b010_corner"),
            z("b020_corner"),
            z("b035_corner")
        ));
    }
    lines
}

fn modes_runs(o: &Options) -> Vec<RunSpec> {
    vec![run(
        "top left",
        "tri6",
        "scenes/curvature_modes.toml",
        &quick_end(o, 0.05),
    )]
}

fn modes_check(r: &[RunResult]) -> Vec<String> {
    let names = [
        "Γ₁₁ twist",
        "Γ₂₁ bending",
        "Γ₃₁ in-plane bending",
        "Γ₁₂ width bending",
        "Γ₂₂ width twist",
        "Γ₃₂ width drilling",
    ];
    let mut lines = vec![
        "Paper row: one strip; this scene runs all six strips (0.8 m apart in y) in one system. Angles and chords are measured between the strip's centre and its tip (x = 0.5 m), so the free rigid rotation about the pinned centre line does not enter.\n".to_string(),
        "| strip | rotation centre → tip: d₁ / d₂ / d₃ | chord centre → tip [m] | expected |".to_string(),
        "|---|---|---|---|".to_string(),
    ];
    let expected = [
        "d₁ 0°, d₂ d₃ 180°; chord 0.5",
        "d₁ d₃ 180°, d₂ 0°; chord 1/π = 0.318",
        "d₁ d₂ 180°, d₃ 0°; chord 0.318",
        "across the width (135°)",
        "across the width (90°)",
        "across the width (90°)",
    ];
    for res in r {
        let Some(f) = &res.frame else { continue };
        let Ok(rest) = crate::postprocess::rest_positions(f) else {
            continue;
        };
        let nearest = |target: [f64; 3]| {
            (0..rest.len())
                .min_by(|&a, &b| {
                    let d = |i: usize| (0..3).map(|c| (rest[i][c] - target[c]).powi(2)).sum::<f64>();
                    d(a).total_cmp(&d(b))
                })
                .unwrap_or(0)
        };
        let director =
            |name: &str, i: usize| f.point_array(name).map(|a| [a.tuple(i)[0], a.tuple(i)[1], a.tuple(i)[2]]);
        let angle =
            |a: [f64; 3], b: [f64; 3]| (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]).clamp(-1.0, 1.0).acos().to_degrees();
        for (k, name) in names.iter().enumerate() {
            let y = 0.8 * k as f64;
            let (c, t) = (nearest([0.0, y, 0.0]), nearest([0.5, y, 0.0]));
            let angles: Vec<String> = ["director1", "director2", "director3"]
                .iter()
                .map(|d| match (director(d, c), director(d, t)) {
                    (Some(a), Some(b)) => format!("{:.1}°", angle(a, b)),
                    _ => "–".into(),
                })
                .collect();
            let chord = (0..3).map(|i| (f.points[t][i] - f.points[c][i]).powi(2)).sum::<f64>().sqrt();
            lines.push(format!(
                "| {k}: {name} | {} | {chord:.3} | {} |",
                angles.join(" / "),
                expected[k]
            ));
        }
    }
    lines
}

fn armadillo_runs(o: &Options) -> Vec<RunSpec> {
    let mesh = if o.large {
        "armadillo_lvl2_verts7743.obj"
    } else {
        "armadillo_lvl5_verts969.obj"
    };
    let path = o.mesh(mesh);
    let mut ov: Vec<String> = (0..3).map(|s| format!("shell.{s}.mesh.path={}", path.display())).collect();
    ov.extend(quick_end(o, 0.025));
    vec![run(
        if o.large { "left" } else { "left (lvl5 mesh)" },
        "tri6",
        "scenes/armadillos.toml",
        &ov,
    )]
}

fn armadillo_check(r: &[RunResult]) -> Vec<String> {
    let mut lines =
        vec!["Head displacement of the three armadillos (A: Γ₁₃ bend, B: Γ₂₃ bend, C: Γ₃₃ twist):\n".to_string()];
    for res in r {
        let Some(p) = &res.probes else { continue };
        for (k, label) in ["a", "b", "c"].iter().enumerate() {
            let first = p.rows.first().map(|row| {
                let c = |s: &str| p.column(&format!("head_{label}.{s}")).map(|i| row[i]).unwrap_or(f64::NAN);
                [c("x"), c("y"), c("z")]
            });
            if let (Some(a), Ok(b)) = (first, p.last_vec(&format!("head_{label}"), ["x", "y", "z"])) {
                let d = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2) + (b[2] - a[2]).powi(2)).sqrt();
                lines.push(format!(
                    "- armadillo {} ({}): head moved {:.1} mm.",
                    label.to_uppercase(),
                    ["bend", "bend", "twist"][k],
                    1e3 * d
                ));
            }
        }
    }
    lines
}

fn buckling_runs(o: &Options) -> Vec<RunSpec> {
    vec![
        run(
            "inner",
            "tri6",
            "scenes/buckling_circle_inner.toml",
            &quick_end(o, 0.05),
        ),
        run(
            "outer",
            "tri6",
            "scenes/buckling_circle_outer.toml",
            &quick_end(o, 0.05),
        ),
    ]
}

fn buckling_check(r: &[RunResult]) -> Vec<String> {
    let mut lines = Vec::new();
    for res in r {
        let Some(f) = &res.frame else { continue };
        let (zmin, zmax) = f
            .points
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p[2]), b.max(p[2])));
        let waves = rim_waves(f, 0.025).map_or("–".into(), |w| w.to_string());
        lines.push(format!(
            "- {}: out-of-plane extent {:.2} mm; waves along the rim: {waves}.",
            res.spec.variant,
            1e3 * (zmax - zmin)
        ));
    }
    lines.push("\nExpected: inner growth gives a dome (positive Gaussian curvature, no rim waves); outer growth a wavy rim (negative Gaussian curvature).".into());
    lines
}

fn moebius_runs(o: &Options) -> Vec<RunSpec> {
    vec![
        run("plate model", "tri6", "scenes/moebius_plate.toml", &quick_end(o, 0.005)),
        run("shell model", "tri6", "scenes/moebius_shell.toml", &quick_end(o, 0.005)),
    ]
}

fn moebius_check(r: &[RunResult]) -> Vec<String> {
    let mut lines = Vec::new();
    for res in r {
        let Some(f) = &res.frame else { continue };
        let zmin = f.points.iter().map(|p| p[2]).fold(f64::MAX, f64::min);
        lines.push(format!(
            "- {}: boundary loops {} (a Möbius band has one); lowest point z = {:.2} mm.",
            res.spec.variant,
            boundary_loops(&f.triangles),
            1e3 * zmin
        ));
    }
    if let [a, b] = r
        && let (Some(fa), Some(fb)) = (&a.frame, &b.frame)
    {
        lines.push(format!(
            "- Hausdorff distance between the plate and shell shapes: {:.3} mm.",
            1e3 * hausdorff(&fa.points, &fb.points)
        ));
    }
    lines
}

/// Renders the last frame of the experiment's runs (or only of its last run) to `<render_dir>/<name>.png`.
fn render(o: &Options, exp: &Experiment, results: &[RunResult]) -> Result<()> {
    use cosserat::scene::render::{Colouring, RenderOptions, ScalarMode, render_png};
    let Some(dir) = &o.render_dir else { return Ok(()) };
    std::fs::create_dir_all(dir)?;
    let picked: Vec<&RunResult> = if exp.render_each {
        results.iter().collect()
    } else {
        results.last().into_iter().collect()
    };
    for res in picked {
        let Some(frame) = &res.frame else { continue };
        // Obstacles (floors, boxes) would fill the picture: show the shells.
        let frame = &contact::without_obstacles(frame);
        let options = RenderOptions {
            colouring: Colouring::PointScalar {
                array: "displacement".into(),
                mode: ScalarMode::Magnitude,
                range: None,
            },
            ..RenderOptions::default()
        };
        let file = if exp.render_each {
            format!("{}_{}.png", exp.name, res.spec.variant.replace(' ', "_"))
        } else {
            format!("{}.png", exp.name)
        };
        render_png(frame, &options, &dir.join(file))?;
    }
    Ok(())
}

fn last_frame(dir: &Path) -> Option<VtuFrame> {
    let pvd = dir.join("frames").join("run.pvd");
    let entries = read_pvd(&pvd).ok()?;
    read_pvd_frame(&pvd, entries.len().checked_sub(1)?).ok()
}

/// Runs one scene to completion, quietly.
pub fn execute(spec: &RunSpec, dir: &Path) -> Result<RunResult> {
    let scene = cosserat::scene::load_scene(&spec.scene, &spec.overrides)
        .with_context(|| format!("loading {}", spec.scene.display()))?;
    let mut sim = Simulation::new(scene).with_context(|| format!("setting up {}", spec.scene.display()))?;
    let summary = sim.run(dir, &mut |_| {}, &cosserat::StopRequest::new())?;
    let probes = ProbeTable::read(&dir.join("probes.csv")).ok();
    Ok(RunResult {
        spec: spec.clone(),
        summary,
        probes,
        frame: last_frame(dir),
        dir: dir.to_path_buf(),
    })
}

fn machine() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .map(|l| l.split(':').nth(1).unwrap_or("").trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    format!("{cpu}, {cores} cores")
}

fn fmt_row(res: &RunResult, name: &str) -> String {
    let s = &res.summary;
    let ours = format!(
        "{} | {} | {} | {} | {:.0} ms | {:.2} | {:.2} s | {:.1} ms | {:.0} % | {:.0} %",
        res.spec.element,
        s.n_cells,
        s.n_displacement_dofs,
        s.n_rotation_dofs,
        1e3 * s.dt,
        s.avg_newton_iterations,
        s.wall_seconds,
        s.avg_step_ms,
        100.0 * s.assembly_share,
        100.0 * s.linear_solve_share
    );
    let variant = res.spec.variant.split(" (").next().unwrap_or("");
    let paper = paper::row(name, variant, &res.spec.element).map_or("| – | – | – | – | –".into(), |p| {
        format!(
            "| {:.1} | {:.2} s | {:.0} ms | {:.1} % | {:.1} %",
            p.iterations, p.total_s, p.step_ms, p.assembly_pct, p.lu_pct
        )
    });
    let status = if s.status == RunStatus::Ok {
        String::new()
    } else {
        format!(" **{:?}: {}**", s.status, s.reason.clone().unwrap_or_default())
    };
    format!("| {} | {}{status} | {ours} {paper} |", res.spec.variant, name)
}

/// Runs the experiments and writes the report; returns its markdown.
pub fn run_all(o: &Options) -> Result<String> {
    let started = std::time::Instant::now();
    let mut table = String::new();
    let mut checks = String::new();
    let mut failures = Vec::new();
    let mut all_results = Vec::new();
    for exp in registry() {
        if o.only.as_ref().is_some_and(|f| !exp.name.contains(f.as_str())) {
            continue;
        }
        let mut results = Vec::new();
        for spec in (exp.runs)(o) {
            let dir = o
                .out
                .join(exp.name)
                .join(format!("{}_{}", spec.element, spec.variant.replace(' ', "_")));
            eprintln!("{}: {} {} ...", exp.name, spec.variant, spec.element);
            match execute(&spec, &dir) {
                Ok(res) => {
                    if res.summary.status != RunStatus::Ok {
                        failures.push(format!(
                            "{} {}: {:?} {}",
                            exp.name,
                            spec.variant,
                            res.summary.status,
                            res.summary.reason.clone().unwrap_or_default()
                        ));
                    }
                    eprintln!(
                        "  {:?}, {} steps, {:.2} it/step, {:.1} ms/step",
                        res.summary.status,
                        res.summary.n_steps,
                        res.summary.avg_newton_iterations,
                        res.summary.avg_step_ms
                    );
                    writeln!(table, "{}", fmt_row(&res, exp.name))?;
                    results.push(res);
                }
                Err(e) => {
                    failures.push(format!("{} {}: {e:#}", exp.name, spec.variant));
                    writeln!(table, "| {} | {} **failed: {e}** |", spec.variant, exp.name)?;
                }
            }
        }
        if o.render_dir.is_some() {
            render(o, &exp, &results)?;
        }
        writeln!(checks, "\n### {}\n", exp.title)?;
        for line in (exp.check)(&results) {
            writeln!(checks, "{line}")?;
        }
        all_results.push((exp.name, results));
    }
    let date = std::process::Command::new("date")
        .arg("-u")
        .arg("+%Y-%m-%d")
        .output()
        .ok()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_default();
    let rev = std::process::Command::new("git")
        .args(["rev-parse", "--short", "HEAD"])
        .output()
        .ok()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_default();
    let mut md = String::new();
    writeln!(md, "# The paper's experiments\n")?;
    writeln!(
        md,
        "Generated by `cargo xtask experiments{}{}` on {date} (git {rev}), release build, on {}. Total {:.0} s.\n",
        if o.quick { " --quick" } else { "" },
        if o.large { " --large" } else { "" },
        machine(),
        started.elapsed().as_secs_f64()
    )?;
    writeln!(
        md,
        "Our columns first, then the paper's Table 1 (32-core workstation with MKL). \"solve\" is our share of time in linear solves (factorisation and solve); the paper's is its LU share. Total times cover the whole run including output.\n"
    )?;
    writeln!(
        md,
        "| variant | scene | el. | cells | disp. DOFs | rot. DOFs | dt | Newton it. | total | avg step | assembly | solve | paper it. | paper total | paper step | paper assembly | paper LU |"
    )?;
    writeln!(
        md,
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
    )?;
    md.push_str(&table);
    writeln!(md, "\n## What each experiment shows\n{checks}")?;
    md.push_str(&comparison::section(&all_results));
    if !failures.is_empty() {
        writeln!(md, "\n## Failures\n")?;
        for f in &failures {
            writeln!(md, "- {f}")?;
        }
    }
    Ok(md)
}
