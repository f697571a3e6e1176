//! `cargo xtask experiments`: runs the paper's experiments from the scene files in `scenes/` (those with
//! contact — Bunny, Dumpling, Papyrus scroll — in the `contact` module), checks what each should show, and writes
//! the timing table beside the paper's Table 1.
//!
//! Experiments are data: a scene file plus a list of runs (override sets, e.g. the refinement ladder)
//! and a check that reads the written outputs back.

use crate::paper;
use crate::postprocess::{ProbeTable, boundary_loops, fit_circle, hausdorff, rim_shape};
use anyhow::{Context, Result};
pub use check::Check;
use check::within;
use cosserat::Simulation;
use cosserat::io::{RunStatus, RunSummary, VtuFrame, read_pvd, read_pvd_frame};
use provenance::RunInputs;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

mod check;
mod comparison;
mod contact;
mod provenance;

/// How the experiments run.
#[derive(Debug, Clone)]
pub struct Options {
    /// A short version of each run (a few steps, the coarsest meshes).
    pub quick: bool,
    /// Include the largest meshes of the ladders and the paper's armadillo mesh.
    pub large: bool,
    /// Only experiments whose name contains this.
    pub only: Option<String>,
    /// Only runs whose variant (Table 1's "Variant" column, e.g. `h = 1.5 mm` or `320x32`) contains
    /// this.
    pub row: Option<String>,
    /// Directory with the experiments' OBJ meshes (`assets/meshes` of the workspace).
    pub meshes: PathBuf,
    /// Root of the run outputs.
    pub out: PathBuf,
    /// Where to render the README pictures (`None`: no pictures).
    pub render_dir: Option<PathBuf>,
    /// Take a complete earlier run of exactly the same scene and overrides from the output folder
    /// instead of running it again (the report names the revision and machine that produced it).
    pub reuse: bool,
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
    /// What it should show, measured on the outputs: report lines (markdown) and the expected
    /// behaviours tested.
    pub check: fn(&[RunResult]) -> Check,
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
    // Long because the registry is a data table, one entry per experiment of the paper, that reads
    // best as one list.
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

fn twisting_check(r: &[RunResult]) -> Check {
    let mut c = Check::new();
    for res in r {
        let s = &res.summary;
        c.say(format!(
            "- {} steps completed ({:?}), {:.2} Newton iterations per step (at most {}).",
            s.n_steps, s.status, s.avg_newton_iterations, s.max_newton_iterations
        ));
        let end_angle = res.probes.as_ref().and_then(|p| {
            let d3 = p.last_vec("right_director", ["d3x", "d3y", "d3z"]).ok()?;
            let t = p.last("t").ok()?;
            let theta = 2.0 * std::f64::consts::PI * t;
            let target = [0.0, -theta.sin(), theta.cos()];
            let dot = (d3[0] * target[0] + d3[1] * target[1] + d3[2] * target[2]).clamp(-1.0, 1.0);
            Some((t, theta, dot.acos().to_degrees()))
        });
        c.expect(
            "the right end follows its prescribed turn of 2π rad/s (d₃ within 1° of R_x(θ) e_z; the rotation \
             condition is a penalty whose error is far below a degree)",
            end_angle.and_then(|(t, theta, angle)| {
                within(
                    angle,
                    0.0,
                    1.0,
                    format!(
                        "{angle:.3}° after a twist of {:.1}° at t = {t:.2} s",
                        theta.to_degrees()
                    ),
                )
            }),
        );
        c.expect(
            "no element turns inside out (smallest signed area ratio over all quadrature points and frames above 0)",
            s.min_area_ratio
                .and_then(|a| within(a, f64::MIN_POSITIVE, f64::INFINITY, format!("{a:.3}"))),
        );
    }
    c
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

fn plate_check(r: &[RunResult]) -> Check {
    let mut c = Check::new();
    let mut deviation: f64 = 0.0;
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
            let reference = REFERENCE_PLATE_TIP.iter().find(|x| x.0 == element && x.1 == ny);
            if let Some(x) = reference {
                deviation = deviation.max((tip - x.2).abs() / x.2);
            }
            let reference = reference.map_or("–".into(), |x| format!("{:.4}", x.2));
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
    c.extend(lines);
    c.expect(
        "every mesh's tip deflection equals the reference code's on the same discretisation within 0.05 % \
         (both solve the same equations; only the Newton tolerances differ)",
        within(
            deviation,
            0.0,
            5e-4,
            format!("largest relative difference {:.1e}", deviation),
        ),
    );
    c
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

fn coiling_check(r: &[RunResult]) -> Check {
    let mut finest = None;
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
        if res.spec.element == "tri6" {
            finest = fit.map(|(_, _, rad, _)| (res.spec.variant.clone(), (rad - target) / target, gap));
        }
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
    let mut c = Check::new();
    c.extend(lines);
    c.expect(
        "the finest Tri6 strip closes into the target circle: radius within 1 % and the free end within 5 mm \
         (1 % of the strip's length) of the clamp (Tri6 errors fall about threefold per refinement)",
        finest.and_then(|(mesh, err, gap)| {
            let gap = gap?;
            Some((
                err.abs() <= 0.01 && gap <= 5.0,
                format!("{mesh}: radius {:+.2} %, gap {gap:.2} mm", 100.0 * err),
            ))
        }),
    );
    c
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

fn lotus_check(r: &[RunResult]) -> Check {
    const PROBES: [&str; 6] = [
        "b010_edge_mid",
        "b020_edge_mid",
        "b035_edge_mid",
        "b010_corner",
        "b020_corner",
        "b035_corner",
    ];
    let mut c = Check::new();
    c.say("Paper rows are for one layer; this scene runs the three layers (b = 0.1, 0.2, 0.35) in one system, so cells and DOFs are three times the paper's.\n");
    c.say("| mesh | edge-midpoint height b = 0.1 / 0.2 / 0.35 [m] | corner height [m] |");
    c.say("|---|---|---|");
    let mut heights: Vec<Vec<f64>> = Vec::new();
    for res in r {
        let Some(p) = &res.probes else { continue };
        let z: Vec<f64> = PROBES
            .iter()
            .map(|name| p.last(&format!("{name}.z")).unwrap_or(f64::NAN))
            .collect();
        c.say(format!(
            "| {} | {:.3} / {:.3} / {:.3} | {:.3} / {:.3} / {:.3} |",
            res.spec.variant, z[0], z[1], z[2], z[3], z[4], z[5]
        ));
        heights.push(z);
    }
    c.say("");
    let converging = (heights.len() >= 3).then(|| {
        let n = heights.len();
        let worst = (0..PROBES.len())
            .map(|k| {
                let (before, last) = (
                    (heights[n - 2][k] - heights[n - 3][k]).abs(),
                    (heights[n - 1][k] - heights[n - 2][k]).abs(),
                );
                if last <= 2e-3 { 0.0 } else { last / before }
            })
            .fold(0.0, f64::max);
        (
            worst <= 0.6,
            format!("largest ratio of the last change to the one before {worst:.2}"),
        )
    });
    c.expect(
        "the heights converge under refinement: on the last mesh each changes by at most 0.6 times its change \
         on the mesh before, or by under 2 mm (second-order elements halve their error per refinement at least)",
        converging,
    );
    c
}

/// The paper's 16 × 2 strips and the strips refined once (twice with `--large`): the across-width
/// modes have only two elements across the width on the paper's mesh, so their check is convergence.
fn modes_runs(o: &Options) -> Vec<RunSpec> {
    let mut runs = vec![run(
        "top left",
        "tri6",
        "scenes/curvature_modes.toml",
        &quick_end(o, 0.05),
    )];
    if !o.quick {
        let refinements: &[usize] = if o.large { &[2, 4] } else { &[2] };
        for &n in refinements {
            let ov: Vec<String> = (0..6)
                .flat_map(|s| {
                    [
                        format!("shell.{s}.mesh.nx={}", 16 * n),
                        format!("shell.{s}.mesh.ny={}", 2 * n),
                    ]
                })
                .collect();
            runs.push(run(
                &format!("{}x{}", 16 * n, 2 * n),
                "tri6",
                "scenes/curvature_modes.toml",
                &ov,
            ));
        }
    }
    runs
}

// Strips 0–2 turn along the length (centre → tip, π per half); strips 3–5 across the width
// (edge → edge at x = 0.25 m, f · 2π · 0.125 m).
/// One strip of the curvature modes scene.
struct Mode {
    name: &'static str,
    along_length: bool,
    /// Expected angle of d₁, d₂, d₃ \[°\].
    angles: [f64; 3],
    /// Expected chord centre → tip \[m\].
    chord: Option<f64>,
    /// Whether the mode bends without stretching (in-plane bending of the wide strip stretches its
    /// edges by ±w/2R, so its centre line need not keep its length).
    isometric: bool,
}
/// The six strips of the curvature modes scene and what each should show.
fn curvature_modes() -> [Mode; 6] {
    let semicircle = 1.0 / std::f64::consts::PI;
    [
        Mode {
            name: "Γ₁₁ twist",
            along_length: true,
            angles: [0.0, 180.0, 180.0],
            chord: Some(0.5),
            isometric: true,
        },
        Mode {
            name: "Γ₂₁ bending",
            along_length: true,
            angles: [180.0, 0.0, 180.0],
            chord: Some(semicircle),
            isometric: true,
        },
        Mode {
            name: "Γ₃₁ in-plane bending",
            along_length: true,
            angles: [180.0, 180.0, 0.0],
            chord: Some(semicircle),
            isometric: false,
        },
        Mode {
            name: "Γ₁₂ width bending",
            along_length: false,
            angles: [0.0, 135.0, 135.0],
            chord: None,
            isometric: true,
        },
        Mode {
            name: "Γ₂₂ width twist",
            along_length: false,
            angles: [90.0, 0.0, 90.0],
            chord: None,
            isometric: true,
        },
        Mode {
            name: "Γ₃₂ width drilling",
            along_length: false,
            angles: [90.0, 90.0, 0.0],
            chord: None,
            isometric: true,
        },
    ]
}

/// Half the strip width of the curvature modes scene \[m\].
const MODES_HALF_WIDTH: f64 = 0.0625;

/// The curvature modes' convergence expectations from each run's per-mode angle errors (coarsest
/// mesh first).
fn expect_convergence(c: &mut Check, modes: &[Mode; 6], errors: &[(String, [f64; 6])]) {
    let turns: Vec<f64> = modes.iter().map(|m| m.angles.iter().fold(0.0, |a: f64, b| a.max(*b))).collect();
    let history = |k: usize| {
        errors
            .iter()
            .map(|(mesh, e)| format!("{mesh} {:.1}°", e[k]))
            .collect::<Vec<_>>()
            .join(" → ")
    };
    c.expect(
        "every mode converges to its prescribed turn: under each refinement every mode's angle error falls at \
         least 2.8-fold (a convergence order of 1.5 or more; the elements are of second order)",
        (errors.len() >= 2).then(|| {
            let slowest = errors
                .windows(2)
                // Errors below a tenth of a degree are converged already.
                .flat_map(|w| {
                    (0..6)
                        .filter(move |&k| w[0].1[k] > 0.1)
                        .map(move |k| w[0].1[k] / w[1].1[k].max(1e-3))
                })
                .fold(f64::INFINITY, f64::min);
            let worst = (0..6)
                .min_by(|&a, &b| {
                    let fall = |k: usize| errors[0].1[k] / errors[1].1[k].max(1e-3);
                    fall(a).total_cmp(&fall(b))
                })
                .unwrap_or(0);
            (
                slowest >= 2.8,
                format!("slowest fall {slowest:.1}-fold (strip {worst}: {})", history(worst)),
            )
        }),
    );
    c.expect(
        "on the refined mesh every mode realises its turn within 5 % of it",
        errors.get(1).map(|(mesh, e)| {
            let worst = (0..6).map(|k| e[k] / turns[k]).fold(0.0, f64::max);
            (
                worst <= 0.05,
                format!("largest error {:.1} % of the turn on {mesh}", 100.0 * worst),
            )
        }),
    );
}

fn modes_check(r: &[RunResult]) -> Check {
    let modes = curvature_modes();
    let mut c = Check::new();
    c.say("Paper row: one strip; this scene runs all six strips (0.8 m apart in y) in one system. Strips 0–2 are measured from the strip's centre to its tip (x = 0.5 m), strips 3–5 across the width from edge to edge at x = 0.25 m, so the free rigid rotation about the pinned centre line does not enter.\n");
    c.say("| mesh, strip | measured | director angles d₁ / d₂ / d₃ | expected | chord centre → tip [m] | expected |");
    c.say("|---|---|---|---|---|---|");
    // Per run: each mode's largest director angle error, and the expected turn.
    let mut errors: Vec<(String, [f64; 6])> = Vec::new();
    let mut worst_chord: Option<f64> = None;
    for res in r {
        let mut mode_errors = [0.0_f64; 6];
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
        for (k, mode) in modes.iter().enumerate() {
            let y = 0.8 * k as f64;
            let (a, b, measured) = if mode.along_length {
                (nearest([0.0, y, 0.0]), nearest([0.5, y, 0.0]), "centre → tip")
            } else {
                (
                    nearest([0.25, y - MODES_HALF_WIDTH, 0.0]),
                    nearest([0.25, y + MODES_HALF_WIDTH, 0.0]),
                    "across the width",
                )
            };
            let angles: Vec<Option<f64>> = ["director1", "director2", "director3"]
                .iter()
                .map(|d| Some(angle(director(d, a)?, director(d, b)?)))
                .collect();
            for (got, want) in angles.iter().zip(mode.angles) {
                let error = got.map_or(f64::INFINITY, |g| (g - want).abs());
                mode_errors[k] = mode_errors[k].max(error);
            }
            let text: Vec<String> = angles.iter().map(|g| g.map_or("–".into(), |g| format!("{g:.1}°"))).collect();
            let (chord, chord_expected) = match mode.chord {
                Some(want) if !mode.isometric => {
                    let got = (0..3).map(|i| (f.points[b][i] - f.points[a][i]).powi(2)).sum::<f64>().sqrt();
                    (format!("{got:.3}"), format!("({want:.3})"))
                }
                Some(want) => {
                    let got = (0..3).map(|i| (f.points[b][i] - f.points[a][i]).powi(2)).sum::<f64>().sqrt();
                    worst_chord = Some(worst_chord.unwrap_or(0.0).max((got - want).abs() / want));
                    (format!("{got:.3}"), format!("{want:.3}"))
                }
                None => ("–".into(), "–".into()),
            };
            c.say(format!(
                "| {} {k}: {} | {measured} | {} | {:.0}° / {:.0}° / {:.0}° | {chord} | {chord_expected} |",
                res.spec.variant,
                mode.name,
                text.join(" / "),
                mode.angles[0],
                mode.angles[1],
                mode.angles[2]
            ));
        }
        errors.push((res.spec.variant.clone(), mode_errors));
    }
    c.say("");
    expect_convergence(&mut c, &modes, &errors);
    c.expect(
        "the twisted and the bent strip keep their length (isometric modes): chords within 2 % of the straight \
         and the semicircular one",
        worst_chord.and_then(|w| within(w, 0.0, 0.02, format!("largest deviation {:.2} %", 100.0 * w))),
    );
    c
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

fn armadillo_check(r: &[RunResult]) -> Check {
    let mut c = Check::new();
    c.say("Head displacement of the three armadillos (A: Γ₁₃ bend, B: Γ₂₃ bend, C: Γ₃₃ twist):\n");
    let mut moved = Vec::new();
    for res in r {
        let Some(p) = &res.probes else { continue };
        for (k, label) in ["a", "b", "c"].iter().enumerate() {
            let first = p.rows.first().map(|row| {
                let c = |s: &str| p.column(&format!("head_{label}.{s}")).map(|i| row[i]).unwrap_or(f64::NAN);
                [c("x"), c("y"), c("z")]
            });
            if let (Some(a), Ok(b)) = (first, p.last_vec(&format!("head_{label}"), ["x", "y", "z"])) {
                let d = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2) + (b[2] - a[2]).powi(2)).sqrt();
                c.say(format!(
                    "- armadillo {} ({}): head moved {:.1} mm.",
                    label.to_uppercase(),
                    ["bend", "bend", "twist"][k],
                    1e3 * d
                ));
                moved.push(d);
            }
        }
    }
    c.say("");
    for res in r {
        // The paper times one armadillo; the bodies here share no unknowns, so the scene's step costs
        // the sum of independent ones.
        let n = res.summary.n_shells.max(1);
        c.say(format!(
            "{}: {:.1} ms per step for the {n} armadillos together, {:.1} ms per armadillo ({} cells each).\n",
            res.spec.variant,
            res.summary.avg_step_ms,
            res.summary.avg_step_ms / n as f64,
            res.summary.n_cells / n
        ));
    }
    c.expect(
        "the bends are realised: heads A and B move by more than half the 0.2 m height (a full half-turn bend \
         moves the head by 1.2 times the height; the body's shape realises only part of the prescribed \
         curvature)",
        (moved.len() == 3).then(|| {
            let least = moved[0].min(moved[1]);
            (least > 0.1, format!("{:.1} mm at least", 1e3 * least))
        }),
    );
    c
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

fn buckling_check(r: &[RunResult]) -> Check {
    let mut c = Check::new();
    let mut shapes = Vec::new();
    for res in r {
        let Some(f) = &res.frame else { continue };
        let Ok(shape) = rim_shape(f, 0.025) else { continue };
        c.say(format!(
            "- {}: centre {:.2} mm from the rim's best-fit plane; rim leaves that plane by up to {:.2} mm in {} waves.",
            res.spec.variant,
            1e3 * shape.centre_height,
            1e3 * shape.rim_deviation,
            shape.waves
        ));
        shapes.push((res.spec.variant.clone(), shape));
    }
    c.say("");
    let shape = |name: &str| shapes.iter().find(|(v, _)| v == name).map(|(_, s)| *s);
    // The disk floats undamped (the scene's damping is inactive, as in the paper), so after the
    // growth stops its shape keeps swinging about the equilibrium: the expectations compare the two
    // parts of the shape instead of asking either to vanish.
    c.expect(
        "inner growth makes a dome (positive Gaussian curvature): the centre stands off the rim's plane by \
         more than 5 mm (a fifth of the radius) and by more than twice the rim's own deviation from it",
        shape("inner").map(|s| {
            (
                s.centre_height > 5e-3 && s.centre_height > 2.0 * s.rim_deviation,
                format!(
                    "dome height {:.2} mm, rim deviation {:.2} mm",
                    1e3 * s.centre_height,
                    1e3 * s.rim_deviation
                ),
            )
        }),
    );
    c.expect(
        "outer growth makes a wavy rim (negative Gaussian curvature): at least two waves, the rim leaving its \
         plane by more than 1 mm and by more than twice the centre's distance from it",
        shape("outer").map(|s| {
            (
                s.waves >= 2 && s.rim_deviation > 1e-3 && s.rim_deviation > 2.0 * s.centre_height,
                format!(
                    "{} waves, rim deviation {:.2} mm, centre {:.2} mm",
                    s.waves,
                    1e3 * s.rim_deviation,
                    1e3 * s.centre_height
                ),
            )
        }),
    );
    c
}

fn moebius_runs(o: &Options) -> Vec<RunSpec> {
    vec![
        run("plate model", "tri6", "scenes/moebius_plate.toml", &quick_end(o, 0.005)),
        run("shell model", "tri6", "scenes/moebius_shell.toml", &quick_end(o, 0.005)),
    ]
}

fn moebius_check(r: &[RunResult]) -> Check {
    let mut c = Check::new();
    let mut loops = Vec::new();
    for res in r {
        let Some(f) = &res.frame else { continue };
        let zmin = f.points.iter().map(|p| p[2]).fold(f64::MAX, f64::min);
        let n = boundary_loops(&f.points, &f.triangles).ok();
        c.say(format!(
            "- {}: boundary loops {}; lowest point z = {:.2} mm.",
            res.spec.variant,
            n.map_or_else(|| "not measured (non-manifold frame)".into(), |n| n.to_string()),
            1e3 * zmin
        ));
        loops.push(n);
    }
    let distance = match r {
        [a, b] => match (&a.frame, &b.frame) {
            (Some(fa), Some(fb)) => Some(hausdorff(&fa.points, &fb.points)),
            _ => None,
        },
        _ => None,
    };
    if let Some(d) = distance {
        c.say(format!(
            "- Hausdorff distance between the plate and shell shapes: {:.3} mm.",
            1e3 * d
        ));
    }
    c.say("");
    c.expect(
        "both bands stay one-sided: one boundary loop each",
        (loops.len() == 2).then(|| {
            (
                loops.iter().all(|&n| n == Some(1)),
                format!(
                    "{} loops",
                    loops
                        .iter()
                        .map(|n| n.map_or_else(|| "?".into(), |n| n.to_string()))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            )
        }),
    );
    c.expect(
        "the plate and the shell model hang alike: their shapes within 1 mm (the curved terms are of relative \
         size h/R, a few thousandths here)",
        distance.and_then(|d| within(d, 0.0, 1e-3, format!("{:.3} mm", 1e3 * d))),
    );
    c
}

/// Renders the last frame of the experiment's runs (or only of its last run) to `<render_dir>/<name>.png`.
fn render(o: &Options, exp: &Experiment, results: &[RunResult]) -> Result<()> {
    use cosserat::io::render::{Colouring, RenderOptions, ScalarMode, render_png};
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

/// Runs one scene to completion, printing a progress line at most every [`PROGRESS_EVERY`].
pub fn execute(spec: &RunSpec, dir: &Path) -> Result<RunResult> {
    let scene = cosserat::scene::load_scene(&spec.scene, &spec.overrides)
        .with_context(|| format!("loading {}", spec.scene.display()))?;
    let mut sim = Simulation::new(scene).with_context(|| format!("setting up {}", spec.scene.display()))?;
    let started = std::time::Instant::now();
    let mut last_line = started;
    let mut progress = |info: &cosserat::StepInfo| {
        if last_line.elapsed() >= PROGRESS_EVERY && info.end > 0.0 {
            last_line = std::time::Instant::now();
            let elapsed = started.elapsed().as_secs_f64();
            let fraction = (info.t / info.end).clamp(1e-9, 1.0);
            eprintln!(
                "    t = {:.4} of {} ({:.1} %), {} steps, {:.2} s per step, about {} left",
                info.t,
                info.end,
                100.0 * fraction,
                info.step,
                elapsed / info.step.max(1) as f64,
                duration(elapsed * (1.0 - fraction) / fraction)
            );
        }
    };
    let summary = sim.run(dir, &mut progress, &cosserat::StopRequest::new())?;
    Ok(finished_run(spec, summary, dir))
}

/// How often a long run reports its progress.
pub const PROGRESS_EVERY: std::time::Duration = std::time::Duration::from_secs(30);

/// A duration in seconds as `1 h 05 min`, `12 min` or `40 s`.
pub fn duration(seconds: f64) -> String {
    let s = seconds.max(0.0).round() as u64;
    if s >= 3600 {
        format!("{} h {:02} min", s / 3600, (s % 3600) / 60)
    } else if s >= 120 {
        format!("{} min", s / 60)
    } else {
        format!("{s} s")
    }
}

/// A planned run: where it writes and what it is expected to take.
struct Planned {
    experiment: usize,
    spec: RunSpec,
    dir: PathBuf,
    /// Estimated wall time \[s\] and where the estimate comes from.
    estimate: Option<(f64, Estimate)>,
    /// The earlier complete run of the same inputs that `--reuse` takes instead of running.
    reused: Option<RunInputs>,
}

/// Where a run's time estimate comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Estimate {
    /// The wall time of an earlier run of the same row in the output folder.
    EarlierRun,
    /// The paper's total time for the row (a 32-core workstation).
    Paper,
    /// None: an earlier run is reused.
    Reused,
}

/// The runs of the chosen experiments and rows, each with its estimated time: the wall time of an
/// earlier complete run of the same row in the output folder, else the paper's total for the row.
fn plan(o: &Options, experiments: &[Experiment]) -> Vec<Planned> {
    let mut planned = Vec::new();
    for (k, exp) in experiments.iter().enumerate() {
        if o.only.as_ref().is_some_and(|f| !exp.name.contains(f.as_str())) {
            continue;
        }
        for spec in (exp.runs)(o) {
            if o.row.as_ref().is_some_and(|r| !spec.variant.contains(r.as_str())) {
                continue;
            }
            let dir = o
                .out
                .join(exp.name)
                .join(format!("{}_{}", spec.element, spec.variant.replace(' ', "_")));
            let complete = cosserat::io::read_summary(&dir.join("summary.json"))
                .ok()
                .filter(|s| s.status == RunStatus::Ok);
            let reused = complete.as_ref().filter(|_| o.reuse).and_then(|_| reusable_run(&spec, &dir));
            let earlier = complete.map(|s| (s.wall_seconds, Estimate::EarlierRun));
            let variant = spec.variant.split(" (").next().unwrap_or("");
            let paper = paper::row(exp.name, variant, &spec.element).map(|p| (p.total_s, Estimate::Paper));
            let estimate = if reused.is_some() {
                Some((0.0, Estimate::Reused))
            } else {
                earlier.or(if o.quick { None } else { paper })
            };
            planned.push(Planned {
                experiment: k,
                estimate,
                reused,
                spec,
                dir,
            });
        }
    }
    planned
}

/// The inputs of the earlier run in `dir`, if they are those of `spec`.
fn reusable_run(spec: &RunSpec, dir: &Path) -> Option<RunInputs> {
    RunInputs::read(dir).filter(|earlier| earlier.is_run_of(spec))
}

/// Prints the plan and its estimated total before anything runs.
fn announce(planned: &[Planned], experiments: &[Experiment]) {
    let known: f64 = planned.iter().filter_map(|p| p.estimate.map(|e| e.0)).sum();
    let from = |kind| planned.iter().filter(|p| p.estimate.is_some_and(|e| e.1 == kind)).count();
    let unknown = planned.iter().filter(|p| p.estimate.is_none()).count();
    eprintln!(
        "{} runs of {} experiments; estimated total {} ({} reused, {} estimated from earlier runs in the output folder, {} from the paper's Table 1{})",
        planned.len(),
        experiments.len(),
        duration(known),
        from(Estimate::Reused),
        from(Estimate::EarlierRun),
        from(Estimate::Paper),
        if unknown > 0 {
            format!(", {unknown} without an estimate")
        } else {
            String::new()
        }
    );
    for p in planned {
        eprintln!(
            "  {} {} {}: {}",
            experiments[p.experiment].name,
            p.spec.variant,
            p.spec.element,
            match p.estimate {
                Some((_, Estimate::Reused)) => "reused".into(),
                Some((t, _)) => duration(t),
                None => "–".into(),
            }
        );
    }
}

/// Runs a planned run, recording its inputs first, or reads back the earlier run it reuses.
fn run_or_reuse(p: &Planned) -> Result<RunResult> {
    if p.reused.is_some() {
        return read_run(&p.spec, &p.dir);
    }
    // A summary left by an earlier run must not pass for this one's if this one is killed before it
    // writes its own.
    let stale = p.dir.join("summary.json");
    if stale.exists() {
        std::fs::remove_file(&stale).with_context(|| format!("removing {}", stale.display()))?;
    }
    RunInputs::of(&p.spec)?.write(&p.dir)?;
    execute(&p.spec, &p.dir)
}

/// A finished run read back from its folder.
fn read_run(spec: &RunSpec, dir: &Path) -> Result<RunResult> {
    let path = dir.join("summary.json");
    let summary = cosserat::io::read_summary(&path).with_context(|| format!("reading {}", path.display()))?;
    Ok(finished_run(spec, summary, dir))
}

/// A run's result: its summary and the outputs read back from its folder.
fn finished_run(spec: &RunSpec, summary: RunSummary, dir: &Path) -> RunResult {
    RunResult {
        spec: spec.clone(),
        summary,
        probes: ProbeTable::read(&dir.join("probes.csv")).ok(),
        frame: last_frame(dir),
        dir: dir.to_path_buf(),
    }
}

/// Rows whose scene holds several copies of the paper's body (the Lotus flower's three layers, the
/// three Armadillos), recognised by a whole multiple of the paper's cell count: their time per step
/// per copy beside the paper's, which is for one.
fn per_copy_rows(all_results: &[(&str, Vec<RunResult>)]) -> String {
    let mut md = String::new();
    for (name, results) in all_results {
        for res in results {
            let variant = res.spec.variant.split(" (").next().unwrap_or("");
            let Some(p) = paper::row(name, variant, &res.spec.element) else {
                continue;
            };
            let cells = res.summary.n_cells;
            if p.cells == 0 || cells <= p.cells || !cells.is_multiple_of(p.cells) {
                continue;
            }
            let copies = cells / p.cells;
            let per_copy = res.summary.avg_step_ms / copies as f64;
            let _ = writeln!(
                md,
                "- {name} {}: {copies} copies of the paper's {} cells, {per_copy:.1} ms per step per copy against the paper's {:.0} ms ({:.1}× faster).",
                res.spec.variant,
                p.cells,
                p.step_ms,
                p.step_ms / per_copy
            );
        }
    }
    if md.is_empty() {
        return md;
    }
    format!(
        "\nThe paper ran one copy of these bodies per run; the scenes here hold several that do not interact:\n\n{md}"
    )
}

/// Table rows taken from earlier runs (`--reuse`), with the revision, time and machine of each.
fn reused_rows(planned: &[Planned], experiments: &[Experiment]) -> String {
    let mut md = String::new();
    for p in planned {
        if let Some(r) = &p.reused {
            let _ = writeln!(
                md,
                "- {} {} ({}): git {}, started {}, {}.",
                experiments[p.experiment].name, p.spec.variant, p.spec.element, r.rev, r.date_time, r.machine
            );
        }
    }
    if md.is_empty() {
        return md;
    }
    format!("\nRows marked † are earlier runs of the same scene and overrides, reused (`--reuse`):\n\n{md}")
}

fn fmt_row(res: &RunResult, name: &str, reused: bool) -> String {
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
    let mark = if reused { " †" } else { "" };
    format!("| {}{mark} | {}{status} | {ours} {paper} |", res.spec.variant, name)
}

/// The report's title, provenance line and the head of the timing table.
fn report_header(o: &Options, seconds: f64) -> Result<String> {
    let host = crate::host::Host::current();
    let mut md = String::new();
    writeln!(md, "# The paper's experiments\n")?;
    writeln!(
        md,
        "Generated by `cargo xtask experiments{}{}{}` on {} (git {}), release build, on {}. Total {:.0} s.\n",
        if o.quick { " --quick" } else { "" },
        if o.large { " --large" } else { "" },
        if o.reuse { " --reuse" } else { "" },
        host.date,
        host.rev,
        host.machine(),
        seconds
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
    Ok(md)
}

/// The experiments' report and what failed.
#[derive(Debug, Clone)]
pub struct Report {
    /// The report (markdown).
    pub markdown: String,
    /// Runs that did not complete and expected behaviours that were not met.
    pub failures: Vec<String>,
}

/// Runs the experiments and makes the report.
pub fn run_all(o: &Options) -> Result<Report> {
    let started = std::time::Instant::now();
    let experiments = registry();
    let planned = plan(o, &experiments);
    announce(&planned, &experiments);
    let mut progress = Progress {
        started,
        n_runs: planned.len(),
        total_estimate: planned.iter().filter_map(|p| p.estimate.map(|e| e.0)).sum(),
        estimated_done: 0.0,
    };
    let mut table = String::new();
    let mut checks = String::new();
    let mut failures = Vec::new();
    let mut all_results = Vec::new();
    for (k, exp) in experiments.iter().enumerate() {
        let runs: Vec<&Planned> = planned.iter().filter(|p| p.experiment == k).collect();
        if runs.is_empty() {
            continue;
        }
        let mut results = Vec::new();
        for p in runs {
            let position = planned.iter().position(|q| std::ptr::eq(q, p)).unwrap_or(0) + 1;
            progress.start(position, exp.name, p);
            results.extend(execute_and_record(p, exp.name, &mut table, &mut failures)?);
        }
        if o.render_dir.is_some() {
            render(o, exp, &results)?;
        }
        writeln!(checks, "\n### {}\n", exp.title)?;
        let check = (exp.check)(&results);
        for line in check.lines() {
            writeln!(checks, "{line}")?;
        }
        // A quick run stops early, and a single row lacks the rows its checks compare: their
        // expectations are shown but not enforced.
        if !o.quick && o.row.is_none() {
            failures.extend(check.failures().iter().map(|f| format!("{}: {f}", exp.name)));
        }
        all_results.push((exp.name, results));
    }
    let mut md = report_header(o, started.elapsed().as_secs_f64())?;
    md.push_str(&table);
    md.push_str(&reused_rows(&planned, &experiments));
    md.push_str(&per_copy_rows(&all_results));
    writeln!(md, "\n## What each experiment shows\n{checks}")?;
    md.push_str(&comparison::section(&all_results));
    if !failures.is_empty() {
        writeln!(md, "\n## Failures\n")?;
        for f in &failures {
            writeln!(md, "- {f}")?;
        }
    }
    Ok(Report { markdown: md, failures })
}

/// How far a run of the experiments has got, for the progress lines.
struct Progress {
    started: std::time::Instant,
    n_runs: usize,
    /// Seconds the planned runs with an estimate should take, and those of the runs started.
    total_estimate: f64,
    estimated_done: f64,
}

impl Progress {
    /// Announces run `position` (1-based) of the plan, with the time spent and the time left.
    fn start(&mut self, position: usize, experiment: &str, p: &Planned) {
        eprintln!(
            "[{position}/{}] {}: {} {} ({} elapsed, about {} left) ...",
            self.n_runs,
            experiment,
            p.spec.variant,
            p.spec.element,
            duration(self.started.elapsed().as_secs_f64()),
            duration(self.total_estimate - self.estimated_done)
        );
        self.estimated_done += p.estimate.map_or(0.0, |e| e.0);
    }
}

/// Runs one planned run and records it: its row of the timing table, and a failure for a run that
/// could not be set up or did not complete. The result of a run that produced one.
fn execute_and_record(
    p: &Planned,
    experiment: &str,
    table: &mut String,
    failures: &mut Vec<String>,
) -> Result<Option<RunResult>> {
    match run_or_reuse(p) {
        Ok(res) => {
            if res.summary.status != RunStatus::Ok {
                failures.push(format!(
                    "{} {}: {:?} {}",
                    experiment,
                    p.spec.variant,
                    res.summary.status,
                    res.summary.reason.clone().unwrap_or_default()
                ));
            }
            eprintln!(
                "  {:?}, {} steps, {:.2} it/step, {:.1} ms/step",
                res.summary.status, res.summary.n_steps, res.summary.avg_newton_iterations, res.summary.avg_step_ms
            );
            writeln!(table, "{}", fmt_row(&res, experiment, p.reused.is_some()))?;
            Ok(Some(res))
        }
        Err(e) => {
            failures.push(format!("{} {}: {e:#}", experiment, p.spec.variant));
            writeln!(table, "| {} | {} **failed: {e}** |", p.spec.variant, experiment)?;
            Ok(None)
        }
    }
}
