//! Runs of small scenes through the facade and the CLI.

use cosserat::Simulation;
use cosserat::cli::{RunArgs, run_scene};
use cosserat::scene::output::{RunStatus, read_pvd, read_summary, read_vtu};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

const STRIP: &str = r#"
name = "strip"
[time]
mode = "dynamic"
dt = 0.01
end = 0.1
adaptive = false
output_fps = 50.0
[mesh]
generator = "rectangle"
lx = 0.1
ly = 0.01
nx = 10
ny = 2
element = "tri6"
rotation_element = "tri3"
[material]
model = "plate"
thickness = 1e-3
youngs_modulus = 1e6
poisson_ratio = 0.3
density = 1000.0
length_scale = 1e-4
[[boundary]]
name = "clamp"
region = { predicate = "x <= -0.05 + 1e-9" }
position = { stiffness = 1e6 }
rotation = { stiffness = 1e2, directors = [3] }
[[load]]
name = "tip"
region = { predicate = "x >= 0.05 - 1e-9" }
force = [0.0, 0.0, -0.01]
scale = "ramp(t, 0, 0.05)"
[[probe]]
name = "tip"
region = { predicate = "x >= 0.05 - 1e-9" }
quantity = "displacement"
"#;

fn dir(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cosserat_run_tests").join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn write_scene(dir: &Path, text: &str) -> PathBuf {
    let p = dir.join("scene.toml");
    std::fs::write(&p, text).unwrap();
    p
}

fn files(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

fn args(scene: PathBuf, out: PathBuf, overrides: &[&str]) -> RunArgs {
    RunArgs {
        scene,
        out: Some(out),
        overrides: overrides.iter().map(|s| s.to_string()).collect(),
        threads: Some(1),
        quiet: true,
    }
}

#[test]
fn a_run_writes_the_output_contract() {
    let d = dir("contract");
    let scene = write_scene(&d, STRIP);
    let out = d.join("out");
    assert_eq!(run_scene(&args(scene, out.clone(), &[])).unwrap(), 0);
    assert_eq!(files(&out), ["frames", "probes.csv", "summary.json"]);
    let summary = read_summary(&out.join("summary.json")).unwrap();
    assert_eq!(summary.status, RunStatus::Ok);
    assert_eq!(summary.n_steps, 10);
    assert_eq!(
        (summary.displacement_element.as_str(), summary.rotation_element.as_str()),
        ("tri6", "tri3")
    );
    assert_eq!(summary.n_cells, 40);
    assert_eq!(summary.n_displacement_dofs, 3 * 21 * 5);
    assert_eq!(summary.n_rotation_dofs, 3 * 11 * 3);
    assert!(
        summary.active_terms.iter().any(|t| t == "membrane") && summary.active_terms.iter().any(|t| t == "inertia")
    );
    // The linear algebra is reported: one factorisation of the whole (small) matrix, its operation
    // count and the rate over the factorisations' own time.
    let number = |key: &str| summary.extra.get(key).and_then(serde_json::Value::as_f64);
    assert_eq!(number("factor_domains"), Some(1.0));
    assert!(number("factor_flops").is_some_and(|f| f > 0.0));
    assert!(number("factorisation_seconds").is_some_and(|t| t > 0.0 && t < summary.wall_seconds));
    assert!(number("factor_gflops_per_s").is_some_and(|r| r > 0.0 && r.is_finite()));
    let probes = std::fs::read_to_string(out.join("probes.csv")).unwrap();
    let mut lines = probes.lines();
    assert_eq!(lines.next().unwrap(), "t,tip.ux,tip.uy,tip.uz");
    // Frames every 1/50 s plus the initial one: t = 0, 0.02, …, 0.1.
    assert_eq!(lines.count(), 6);
    let frames = read_pvd(&out.join("frames").join("run.pvd")).unwrap();
    assert_eq!(frames.len(), 6);
    for f in &frames {
        let frame = read_vtu(&out.join("frames").join(&f.file)).unwrap();
        assert!(frame.point_array("director3").is_some() && frame.point_array("angular_velocity").is_some());
        // Tri6 subdivided through the mid-edge nodes: 4 triangles per element.
        assert_eq!(frame.triangles.len(), 4 * 40);
    }
}

#[test]
fn invalid_input_leaves_only_a_summary_with_the_reason() {
    let d = dir("invalid");
    let scene = write_scene(
        &d,
        &STRIP.replace("poisson_ratio = 0.3", "poisson_ratio = 0.3\nyoungs_modulu = 1.0"),
    );
    let out = d.join("out");
    assert_eq!(run_scene(&args(scene, out.clone(), &[])).unwrap(), 1);
    assert_eq!(files(&out), ["summary.json"]);
    let summary = read_summary(&out.join("summary.json")).unwrap();
    assert_eq!(summary.status, RunStatus::Error);
    let reason = summary.reason.unwrap();
    assert!(
        reason.contains("scene.toml") && reason.contains("youngs_modulu"),
        "{reason}"
    );
}

#[test]
fn a_newton_failure_stops_the_run_and_leaves_only_the_diagnostic() {
    let d = dir("newton_failure");
    let scene = write_scene(&d, STRIP);
    let out = d.join("out");
    // An unreachable tolerance with one iteration and no step reduction allowed.
    let overrides = [
        "solver.tolerance=1e-300",
        "solver.max_newton_iterations=1",
        "solver.max_step_reductions=0",
    ];
    assert_eq!(run_scene(&args(scene, out.clone(), &overrides)).unwrap(), 1);
    assert_eq!(files(&out), ["summary.json"]);
    let summary = read_summary(&out.join("summary.json")).unwrap();
    assert_eq!(summary.status, RunStatus::Error);
    assert_eq!(summary.stopped_at, Some(0.0));
    assert!(summary.reason.unwrap().contains("failed"));
}

#[test]
fn an_interrupted_run_keeps_complete_frames_and_says_where_it_stopped() {
    let d = dir("interrupted");
    let scene = write_scene(&d, STRIP);
    let out = d.join("out");
    let spec = cosserat::scene::load_scene(&scene, &[]).unwrap();
    let mut sim = Simulation::new(spec).unwrap();
    let stop = AtomicBool::new(false);
    let summary = sim
        .run(
            &out,
            &mut |info| {
                if info.step == 4 {
                    stop.store(true, Ordering::Relaxed)
                }
            },
            &stop,
        )
        .unwrap();
    assert_eq!(summary.status, RunStatus::Interrupted);
    assert!((summary.stopped_at.unwrap() - 0.04).abs() < 1e-12);
    assert_eq!(summary.n_steps, 4);
    let frames = read_pvd(&out.join("frames").join("run.pvd")).unwrap();
    assert_eq!(frames.len(), 3); // t = 0, 0.02, 0.04
    for f in &frames {
        read_vtu(&out.join("frames").join(&f.file)).unwrap();
    }
    assert_eq!(
        read_summary(&out.join("summary.json")).unwrap().status,
        RunStatus::Interrupted
    );
}
