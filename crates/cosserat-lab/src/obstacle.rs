//! The shell obstacle course of `cargo xtask validate`: the pinched hemisphere, the pinched cylinder
//! and the Scordelis–Lo roof (linear benchmarks, docs/references.md), run with the paper's
//! discretisation and the locking-free alternatives on refinement ladders, with the error against the
//! reference over unknowns and wall time.

use crate::postprocess::ProbeTable;
use crate::problem::{Discretisation, Interpolation, Mesh, Pair};
use crate::runner::{RunOutcome, Runner, run_described};
use anyhow::Result;
use cosserat::RunDescription;
use std::fmt::Write as _;
use std::path::Path;

/// One benchmark of the course.
#[derive(Debug, Clone)]
pub struct Benchmark {
    /// The scene's name.
    pub name: &'static str,
    /// Title.
    pub title: &'static str,
    /// Scene file.
    pub scene: &'static str,
    /// The published value.
    pub reference: f64,
    /// What is compared.
    pub quantity: &'static str,
    /// Reads the compared value (in the benchmark's load scale) from the probes.
    pub read: fn(&ProbeTable) -> Result<f64>,
    /// Meshes, coarse to fine.
    pub ladder: Vec<Mesh>,
    /// Finer meshes beyond the ladder, for the atlas (`cargo xtask study`): it runs them with the paper's
    /// interpolation while none of that pair's runs is within 1 % and its finest is still cheap.
    pub extension: Vec<Mesh>,
}

/// The discretisations compared: the paper's pair with every strain interpolation, and quadratic
/// rotations with Regge membrane strains and stabilised shear and drilling on the 3-point rule (the
/// default) and on six points.
pub const DISCRETISATIONS: [Discretisation; 6] = [
    Discretisation::paper(Pair::Tri6Tri3),
    Discretisation::new(Pair::Tri6Tri3, Interpolation::Stabilized),
    Discretisation::new(Pair::Tri6Tri3, Interpolation::Regge),
    Discretisation::new(Pair::Tri6Tri3, Interpolation::ReggeStabilized),
    Discretisation::DEFAULT,
    Discretisation::DEFAULT.on_six_points(),
];

fn hemisphere_meshes(meshes: &[(usize, usize)]) -> Vec<Mesh> {
    // The shell spans 72° of meridian of a sphere of radius 10 in `4 n_lat / 5` bands.
    let meridian = 10.0 * 72f64.to_radians();
    meshes
        .iter()
        .map(|&(lon, lat)| {
            let bands = lat * 4 / 5;
            Mesh {
                label: format!("{lon}×{lat} ({bands} bands)"),
                overrides: vec![format!("mesh.n_lon={lon}"), format!("mesh.n_lat={lat}")],
                h: meridian / bands as f64,
            }
        })
        .collect()
}

fn cylinder_meshes(meshes: &[(usize, usize)]) -> Vec<Mesh> {
    // Radius 300: the element's side around the circumference (the longer one; 600 along).
    let circumference = 2.0 * std::f64::consts::PI * 300.0;
    meshes
        .iter()
        .map(|&(a, l)| Mesh {
            label: format!("{a}×{l}"),
            overrides: vec![format!("mesh.n_around={a}"), format!("mesh.n_along={l}")],
            h: circumference / a as f64,
        })
        .collect()
}

fn roof_meshes(ns: &[usize]) -> Vec<Mesh> {
    // The panel is 50 along the axis (the longer side) by 34.9 of arc.
    ns.iter()
        .map(|&n| Mesh {
            label: format!("{n}×{n}"),
            overrides: vec![format!("mesh.nx={n}"), format!("mesh.ny={n}")],
            h: 50.0 / n as f64,
        })
        .collect()
}

/// The three benchmarks.
pub fn course() -> Vec<Benchmark> {
    vec![
        Benchmark {
            name: "pinched_hemisphere",
            title: "Pinched hemisphere, 18° hole",
            scene: "scenes/validation/pinched_hemisphere.toml",
            reference: 0.094,
            quantity: "radial displacement under an outward load (× 1000 for loads of 2)",
            read: |p| Ok(1000.0 * p.last("out.ux")?),
            ladder: hemisphere_meshes(&[(16, 5), (32, 10), (64, 20), (128, 40)]),
            extension: hemisphere_meshes(&[(256, 80)]),
        },
        Benchmark {
            name: "pinched_cylinder",
            title: "Pinched cylinder with diaphragms",
            scene: "scenes/validation/pinched_cylinder.toml",
            reference: 1.8248e-5,
            quantity: "radial displacement under a load",
            read: |p| Ok(-p.last("a.ux")?),
            ladder: cylinder_meshes(&[(16, 8), (32, 16), (64, 32)]),
            extension: cylinder_meshes(&[(128, 64), (256, 128)]),
        },
        Benchmark {
            name: "scordelis_lo_roof",
            title: "Scordelis–Lo roof",
            scene: "scenes/validation/scordelis_lo_roof.toml",
            reference: 0.3024,
            quantity: "vertical displacement at the midpoint of a free edge (× 1000 for the full weight)",
            read: |p| Ok(-1000.0 * p.last("edge.uz")?),
            ladder: roof_meshes(&[4, 8, 16, 32]),
            extension: roof_meshes(&[64]),
        },
    ]
}

/// One run of the course.
#[derive(Debug, Clone)]
pub struct CourseRun {
    /// One of [`DISCRETISATIONS`].
    pub discretisation: Discretisation,
    /// Mesh label.
    pub mesh: String,
    /// The outcome.
    pub outcome: RunOutcome,
    /// The compared value, if the run finished.
    pub value: Option<f64>,
}

/// Runs a benchmark's ladder with every discretisation (`quick`: the two coarsest meshes).
///
/// # Errors
/// I/O failures of the output directories.
pub fn run_benchmark(b: &Benchmark, runner: &Runner, out: &Path, quick: bool) -> Result<Vec<CourseRun>> {
    let mut runs = Vec::new();
    for discretisation in DISCRETISATIONS {
        for (i, mesh) in b.ladder.iter().enumerate() {
            if quick && i >= 2 {
                continue;
            }
            let mut ov = mesh.overrides.clone();
            ov.extend(discretisation.overrides());
            ov.push("output.frames=false".into());
            let dir = out.join(b.name).join(format!("{}_{i}", discretisation.directory()));
            eprintln!("{}: {} {} ...", b.name, discretisation.label(), mesh.label);
            let outcome = run_described(runner, &RunDescription::new(b.scene, dir, &ov))?;
            let value = outcome
                .probes
                .as_ref()
                .filter(|_| outcome.is_ok())
                .and_then(|p| (b.read)(p).ok());
            runs.push(CourseRun {
                discretisation,
                mesh: mesh.label.clone(),
                outcome,
                value,
            });
        }
    }
    Ok(runs)
}

/// The markdown section of one benchmark: error against unknowns and wall time, every
/// discretisation.
///
/// # Errors
/// Formatting only.
pub fn section(b: &Benchmark, runs: &[CourseRun]) -> Result<String> {
    let mut md = String::new();
    writeln!(md, "\n### {}\n", b.title)?;
    writeln!(
        md,
        "Scene `{}`. Compared: {}; reference {}.\n",
        b.scene, b.quantity, b.reference
    )?;
    writeln!(
        md,
        "| discretisation | mesh | unknowns | value | error | solve wall | total wall | status |\n|---|---|---|---|---|---|---|---|"
    )?;
    for r in runs {
        let s = r.outcome.summary.as_ref();
        let status = if r.outcome.is_ok() {
            "ok".to_string()
        } else {
            format!("**failed**: {}", r.outcome.reason())
        };
        writeln!(
            md,
            "| {} | {} | {} | {} | {} | {} | {:.2} s | {status} |",
            r.discretisation.label(),
            r.mesh,
            s.map_or("–".into(), |s| (s.n_displacement_dofs + s.n_rotation_dofs)
                .to_string()),
            r.value.map_or("–".into(), |v| format!("{v:.5e}")),
            r.value
                .map_or("–".into(), |v| format!("{:+.2} %", 100.0 * (v / b.reference - 1.0))),
            s.map_or("–".into(), |s| format!("{:.2} s", s.wall_seconds)),
            r.outcome.outer_seconds,
        )?;
    }
    for discretisation in DISCRETISATIONS {
        let within = |tol: f64| {
            runs.iter()
                .filter(|r| r.discretisation == discretisation)
                .find(|r| r.value.is_some_and(|v| (v / b.reference - 1.0).abs() <= tol))
                .map_or("none of the ladder".to_string(), |r| r.mesh.clone())
        };
        writeln!(
            md,
            "\n{}: coarsest mesh within 2 %: {}; within 1 %: {}.",
            discretisation.label(),
            within(0.02),
            within(0.01)
        )?;
    }
    Ok(md)
}

/// Runs the course; returns its markdown section.
///
/// # Errors
/// I/O failures.
pub fn run_all(runner: &Runner, out: &Path, quick: bool) -> Result<String> {
    let mut md = String::new();
    writeln!(md, "\n## The shell obstacle course (linear)\n")?;
    writeln!(
        md,
        "The paper's pair Tri6/Tri3 with the paper's strain interpolation (`mesh.rotation_element = \"tri3\"` selects both) and the alternatives of docs/model-notes.md: the stabilised projection (`\"stabilized\"`), Regge membrane strains (`\"regge\"`), and Regge membrane strains with stabilised shear and drilling (`\"regge_stabilized\"`); and quadratic rotations (Tri6/Tri6, `mesh.rotation_element = \"tri6\"`) with `\"regge_stabilized\"`, whose shear and drilling stabilisation is set for quadratic rotations: the default discretisation, on the 3-point rule, and the same on the six-point rule (`mesh.quadrature_degree = 4`, labelled `6-point`). Tri6/Tri6 has six unknowns per node, the unknowns of a four-node shell mesh with the same nodes. Error = value / reference − 1: negative is too stiff (locking), positive too flexible. *Solve wall* is the run's time loop, *total wall* the whole process including the rest-state set-up."
    )?;
    for b in course() {
        let runs = run_benchmark(&b, runner, out, quick)?;
        md.push_str(&section(&b, &runs)?);
    }
    Ok(md)
}
