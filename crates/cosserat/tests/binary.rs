//! The `cosserat` binary as a user runs it: real signals, exit codes, paths relative to the working
//! directory, and re-runs into a folder that holds an earlier run.

use cosserat::io::{RunStatus, read_pvd, read_summary, read_vtu};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const BINARY: &str = env!("CARGO_BIN_EXE_cosserat");

/// A cantilever strip; `[time]` is appended by each test.
const STRIP: &str = r#"
name = "strip"
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
force = [0.0, 0.0, -0.001]
[[probe]]
name = "tip"
region = { predicate = "x >= 0.05 - 1e-9" }
quantity = "displacement"
"#;

/// Many load levels: long enough to be interrupted in the middle.
const QUASI_STATIC: &str = "[time]\nmode = \"quasi_static\"\nn_levels = 20000\n";
/// Many time steps: likewise.
const DYNAMIC: &str = "[time]\nmode = \"dynamic\"\ndt = 0.001\nend = 100.0\nadaptive = false\noutput_fps = 1000.0\n";

fn folder(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cosserat_binary_tests").join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn start(cwd: &Path, args: &[&str]) -> Child {
    Command::new(BINARY)
        .current_dir(cwd)
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start the binary")
}

/// Waits until `probes.csv` in `out` has at least `rows` data rows (the run is under way).
fn wait_for_rows(out: &Path, rows: usize, child: &mut Child) {
    let deadline = Instant::now() + Duration::from_secs(120);
    loop {
        let n = std::fs::read_to_string(out.join("probes.csv")).map_or(0, |s| s.lines().count().saturating_sub(1));
        if n >= rows {
            return;
        }
        if let Some(status) = child.try_wait().unwrap() {
            panic!("the run ended before it could be interrupted: {status}");
        }
        assert!(Instant::now() < deadline, "the run did not start within two minutes");
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn signal(child: &Child, name: &str) {
    let status = Command::new("kill")
        .args([&format!("-{name}"), &child.id().to_string()])
        .status()
        .expect("run kill");
    assert!(status.success());
}

/// Checks the outputs of an interrupted run: the summary says so, and every frame in the collection
/// is complete and matches a probe row.
fn check_interrupted(out: &Path, reason: &str) {
    let summary = read_summary(&out.join("summary.json")).unwrap();
    assert_eq!(summary.status, RunStatus::Interrupted);
    assert_eq!(summary.reason.as_deref(), Some(reason));
    assert!(summary.n_steps >= 3, "{} steps", summary.n_steps);
    let frames = read_pvd(&out.join("frames").join("run.pvd")).unwrap();
    for f in &frames {
        read_vtu(&out.join("frames").join(&f.file)).unwrap();
    }
    let probes = std::fs::read_to_string(out.join("probes.csv")).unwrap();
    assert_eq!(probes.lines().count() - 1, frames.len(), "one probe row per frame");
    let last = frames.last().unwrap().time;
    assert_eq!(summary.stopped_at, Some(last), "the run stopped at its last output");
}

#[test]
fn ctrl_c_stops_a_quasi_static_run_after_the_current_level() {
    let d = folder("sigint_quasi_static");
    std::fs::write(d.join("scene.toml"), format!("{STRIP}{QUASI_STATIC}")).unwrap();
    let mut child = start(&d, &["run", "scene.toml", "--out", "out", "--quiet", "--threads", "1"]);
    wait_for_rows(&d.join("out"), 3, &mut child);
    signal(&child, "INT");
    let output = child.wait_with_output().unwrap();
    assert_eq!(
        output.status.code(),
        Some(130),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    check_interrupted(&d.join("out"), "interrupted by SIGINT (Ctrl-C)");
}

#[test]
fn sigterm_stops_a_dynamic_run_and_writes_its_summary() {
    let d = folder("sigterm_dynamic");
    std::fs::write(d.join("scene.toml"), format!("{STRIP}{DYNAMIC}")).unwrap();
    let mut child = start(&d, &["run", "scene.toml", "--out", "out", "--quiet", "--threads", "1"]);
    wait_for_rows(&d.join("out"), 3, &mut child);
    signal(&child, "TERM");
    let output = child.wait_with_output().unwrap();
    assert_eq!(
        output.status.code(),
        Some(143),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    check_interrupted(&d.join("out"), "interrupted by SIGTERM");
}

#[test]
fn paths_are_relative_to_the_working_directory() {
    let d = folder("relative_paths");
    let scenes = d.join("my scenes");
    std::fs::create_dir_all(&scenes).unwrap();
    let quick = "[time]\nmode = \"quasi_static\"\nn_levels = 2\n";
    std::fs::write(scenes.join("base.toml"), format!("{STRIP}{quick}")).unwrap();
    // From the scene's own folder, without --out: the outputs go to out/<name> there.
    let output = start(&scenes, &["run", "base.toml", "--quiet"]).wait_with_output().unwrap();
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(scenes.join("out/strip/summary.json").exists());
    // From its parent, with a relative scene path and output folder.
    let output = start(&d, &["run", "my scenes/base.toml", "--out", "elsewhere", "--quiet"])
        .wait_with_output()
        .unwrap();
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert_eq!(
        read_summary(&d.join("elsewhere/summary.json")).unwrap().status,
        RunStatus::Ok
    );
}

#[test]
fn a_scene_that_does_not_parse_leaves_the_earlier_run_alone() {
    let d = folder("rerun_unparsable");
    let quick = "[time]\nmode = \"quasi_static\"\nn_levels = 3\n";
    std::fs::write(d.join("scene.toml"), format!("{STRIP}{quick}")).unwrap();
    let output = start(&d, &["run", "scene.toml", "--out", "out", "--quiet"])
        .wait_with_output()
        .unwrap();
    assert_eq!(
        output.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let files = ["summary.json", "probes.csv", "frames/run.pvd", "frames/frame_00003.vtu"];
    let before: Vec<Vec<u8>> = files.iter().map(|f| std::fs::read(d.join("out").join(f)).unwrap()).collect();
    std::fs::write(d.join("broken.toml"), "name = \"strip\"\n[mesh\n").unwrap();
    let output = start(&d, &["run", "broken.toml", "--out", "out"]).wait_with_output().unwrap();
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("broken.toml") && stderr.contains("left as they were"),
        "{stderr}"
    );
    for (file, bytes) in files.iter().zip(before) {
        assert_eq!(
            std::fs::read(d.join("out").join(file)).unwrap(),
            bytes,
            "{file} changed"
        );
    }
}

#[test]
fn a_scene_too_large_for_the_memory_is_refused_before_it_is_built() {
    let d = folder("max_memory");
    let quick = "[time]\nmode = \"quasi_static\"\nn_levels = 1\n";
    std::fs::write(d.join("scene.toml"), format!("{STRIP}{quick}")).unwrap();
    // 200 × 200 quads: far beyond 64 MiB, refused before the mesh is built.
    let output = start(
        &d,
        &[
            "run",
            "scene.toml",
            "--out",
            "out",
            "--max-memory",
            "64M",
            "--set",
            "mesh.nx=200",
            "--set",
            "mesh.ny=200",
        ],
    )
    .wait_with_output()
    .unwrap();
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.contains("mesh.nx: the generator would make 80000 triangles, more than the limit of")
            && stderr.contains("allowed by --max-memory"),
        "{stderr}"
    );
    let summary = read_summary(&d.join("out/summary.json")).unwrap();
    assert_eq!(summary.status, RunStatus::Error);
    // The 10 × 2 strip fits the mesh budget of 17 MiB, but not the estimate of its 414 unknowns.
    let output = start(&d, &["run", "scene.toml", "--out", "out", "--max-memory", "17M"])
        .wait_with_output()
        .unwrap();
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("unknowns and needs at least"), "{stderr}");
}

#[test]
fn a_run_that_fails_at_a_known_step_keeps_the_steps_before() {
    let d = folder("known_failure");
    // From t = 0.05 on the load jumps beyond what eight Newton iterations can follow, and no step
    // reduction is allowed: the steps to t = 0.05 converge, the next one fails.
    let dynamic = "[time]\nmode = \"dynamic\"\ndt = 0.01\nend = 0.1\nadaptive = false\noutput_fps = 50.0\n\
                   [solver]\nmax_newton_iterations = 8\nmax_step_reductions = 0\n";
    let scene = STRIP.replace(
        "force = [0.0, 0.0, -0.001]",
        "force = [0.0, 0.0, -0.001]\nscale = \"1 + 1e10*(t > 0.045)\"",
    );
    std::fs::write(d.join("scene.toml"), format!("{scene}{dynamic}")).unwrap();
    let output = start(&d, &["run", "scene.toml", "--out", "out", "--quiet"])
        .wait_with_output()
        .unwrap();
    assert_eq!(
        output.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let summary = read_summary(&d.join("out/summary.json")).unwrap();
    assert_eq!(summary.status, RunStatus::Error);
    assert_eq!(summary.n_steps, 5);
    assert!((summary.stopped_at.unwrap() - 0.05).abs() < 1e-12);
    let failed = summary.failed_step.unwrap();
    assert_eq!(failed.attempts.len(), 1);
    assert_eq!(
        failed.attempts[0].residuals.len(),
        9,
        "the initial residual and eight iterations"
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("run failed at t = 0.05"), "{stderr}");
    let frames = read_pvd(&d.join("out/frames/run.pvd")).unwrap();
    assert_eq!(frames.iter().map(|f| f.time).collect::<Vec<_>>(), [0.0, 0.02, 0.04]);
    // The same at a millionth of the time scale: the time is written with an exponent.
    let tiny = dynamic
        .replace("dt = 0.01\nend = 0.1", "dt = 1e-8\nend = 1e-7")
        .replace("50.0", "5e7");
    let scene = scene.replace("1e10*(t > 0.045)", "1e25*(t > 4.5e-8)");
    std::fs::write(d.join("scene.toml"), format!("{scene}{tiny}")).unwrap();
    let output = start(&d, &["run", "scene.toml", "--out", "out_tiny", "--quiet"])
        .wait_with_output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.starts_with("run failed at t = 5e-8: "), "{stderr}");
    // The solver's reason writes the step's time and size with an exponent too.
    assert!(stderr.contains("time step from t = 5e-8 failed"), "{stderr}");
    assert!(stderr.contains("dt = 1e-8: "), "{stderr}");
    assert!(!stderr.contains("0.0000"), "{stderr}");
    for f in &frames {
        read_vtu(&d.join("out/frames").join(&f.file)).unwrap();
    }
}

#[test]
fn a_finished_run_names_its_discretisation() {
    let d = folder("discretisation");
    std::fs::write(d.join("scene.toml"), format!("{STRIP}{DYNAMIC}")).unwrap();
    let run = |extra: &[&str]| {
        let mut args = vec![
            "run",
            "scene.toml",
            "--out",
            "out",
            "--threads",
            "1",
            "--set",
            "time.end=0.003",
        ];
        args.extend_from_slice(extra);
        let output = start(&d, &args).wait_with_output().unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr).into_owned();
        assert!(output.status.success(), "{stderr}");
        stderr
    };
    let paper = run(&[]);
    assert!(
        paper.contains("strip (tri6/tri3 elements, paper strains, 3 points): 3 steps"),
        "{paper}"
    );
    let default = run(&["--set", "mesh.rotation_element="]);
    assert!(
        default.contains("strip (tri6/tri6 elements, regge_stabilized strains, 3 points): 3 steps"),
        "{default}"
    );
}

#[test]
fn an_output_folder_that_is_a_file_is_named_with_its_cause_once() {
    let d = folder("out_is_a_file");
    let quick = "[time]\nmode = \"quasi_static\"\nn_levels = 1\n";
    std::fs::write(d.join("scene.toml"), format!("{STRIP}{quick}")).unwrap();
    std::fs::write(d.join("taken"), "").unwrap();
    let output = start(&d, &["run", "scene.toml", "--out", "taken", "--quiet"])
        .wait_with_output()
        .unwrap();
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("cannot create the directory `taken`"), "{stderr}");
    assert_eq!(
        stderr.matches("os error").count(),
        1,
        "the cause is printed once: {stderr}"
    );
}

#[test]
fn a_scene_that_cannot_be_set_up_names_its_file() {
    let d = folder("setup_failure");
    // Valid, but the strip's own triangles start closer than a contact thickness of 1 m.
    let contact = "[time]\nmode = \"quasi_static\"\nn_levels = 1\n\
                   [contact]\nstiffness = 1.0\nbarrier_width = 1e-3\nthickness = 1.0\n";
    std::fs::write(d.join("scene.toml"), format!("{STRIP}{contact}")).unwrap();
    let output = start(&d, &["run", "scene.toml", "--out", "out", "--quiet"])
        .wait_with_output()
        .unwrap();
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        stderr.starts_with("error: scene.toml: contact: the initial state has a pair of contact primitives"),
        "{stderr}"
    );
    let summary = read_summary(&d.join("out/summary.json")).unwrap();
    assert!(
        summary.reason.as_deref().is_some_and(|r| r.starts_with("scene.toml: contact:")),
        "{:?}",
        summary.reason
    );
}

#[test]
fn resuming_a_run_without_a_checkpoint_says_how_to_write_one() {
    let d = folder("resume_without_checkpoint");
    let quick = "[time]\nmode = \"quasi_static\"\nn_levels = 1\n";
    std::fs::write(d.join("scene.toml"), format!("{STRIP}{quick}")).unwrap();
    let run = start(&d, &["run", "scene.toml", "--out", "out", "--quiet"])
        .wait_with_output()
        .unwrap();
    assert_eq!(run.status.code(), Some(0), "{}", String::from_utf8_lossy(&run.stderr));
    for (dir, reason) in [
        ("out", "a run writes one only with `output.checkpoint_every`"),
        ("missing", "no such output directory"),
    ] {
        let output = start(&d, &["resume", dir, "--quiet"]).wait_with_output().unwrap();
        assert_eq!(output.status.code(), Some(1));
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(stderr.contains("cannot resume from"), "{stderr}");
        assert!(stderr.contains(reason), "{stderr}");
    }
}

#[test]
fn a_second_run_into_a_folder_in_use_is_refused_and_changes_nothing() {
    let d = folder("folder_in_use");
    let checkpoints = "[output]\ncheckpoint_every = 2\n";
    std::fs::write(d.join("scene.toml"), format!("{STRIP}{DYNAMIC}{checkpoints}")).unwrap();
    let args = ["run", "scene.toml", "--out", "out", "--quiet", "--threads", "1"];
    let mut first = start(&d, &args);
    // Past the first checkpoint, which the resume reads before it finds the folder in use.
    wait_for_rows(&d.join("out"), 6, &mut first);
    let refused: Vec<_> = [&args[..], &["resume", "out", "--quiet"]]
        .into_iter()
        .map(|second| start(&d, second).wait_with_output().unwrap())
        .collect();
    signal(&first, "INT");
    let output = first.wait_with_output().unwrap();
    assert_eq!(output.status.code(), Some(130));
    for output in refused {
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{stderr}");
        assert!(stderr.contains("`out` is in use by another run"), "{stderr}");
    }
    // The first run's rows and frames are its own, without a gap: the second run removed nothing.
    check_interrupted(&d.join("out"), "interrupted by SIGINT (Ctrl-C)");
    let probes = std::fs::read_to_string(d.join("out").join("probes.csv")).unwrap();
    let times: Vec<f64> = probes
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .collect();
    assert!(times.windows(2).all(|w| w[1] > w[0]) && times[0] == 0.0, "{probes}");
}
