//! Checkpoint and restart: a run stopped after a checkpoint and resumed from it writes the same bytes
//! (every probe row, every frame) as a run that was never stopped, for a dynamic, a frictional contact
//! and a quasi-static scene; resuming refuses a changed scene and a missing or damaged checkpoint with
//! an error naming the file and the reason.

use cosserat::checkpoint::{Checkpoint, state_path};
use cosserat::cli::{ResumeArgs, RunArgs, resume_run, run_scene};
use cosserat::io::{RunStatus, RunSummary, read_summary};
use cosserat::scene::load_scene;
use cosserat::{Simulation, StopReason, StopRequest};
use std::path::{Path, PathBuf};

/// A clamped strip (Tri6 displacements, Tri3 rotations) bent by a tip load; `{time}` is the time
/// section's body and `{scale}` the tip load's scale.
fn strip(time: &str, force: f64, scale: &str) -> String {
    format!(
        r#"
name = "strip"
[time]
{time}
[output]
checkpoint_every = 3
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
region = {{ predicate = "x <= -0.05 + 1e-9" }}
position = {{ stiffness = 1e6 }}
rotation = {{ stiffness = 1e2, directors = [3] }}
[[load]]
name = "tip"
region = {{ predicate = "x >= 0.05 - 1e-9" }}
force = [0.0, 0.0, {force}]
scale = "{scale}"
[[probe]]
name = "tip"
region = {{ predicate = "x >= 0.05 - 1e-9" }}
quantity = "displacement"
[[probe]]
name = "tip_v"
region = {{ predicate = "x >= 0.05 - 1e-9" }}
quantity = "velocity"
"#
    )
}

/// A dynamic run of 12 steps with an adaptive time step and a frame every other step.
fn dynamic_strip() -> String {
    let time = "mode = \"dynamic\"\ndt = 0.01\nend = 0.12\nadaptive = true\noutput_fps = 50.0";
    strip(time, -0.01, "ramp(t, 0, 0.05)")
}

/// Six load levels of a bending strip (tip deflection about 40 % of its length).
fn quasi_static_strip() -> String {
    strip("mode = \"quasi_static\"\nn_levels = 6", -1e-4, "t")
}

/// The same strip under ten times the load, with a checkpoint after every level and plain Newton
/// (`solver.mixed_integration_points = false`): some levels need more Newton iterations than the
/// increment control wants, so the levels after them are reached through intermediate ones (with the
/// default's relaxed steps every level converges within them).
fn quasi_static_strip_with_intermediate_levels() -> String {
    strip("mode = \"quasi_static\"\nn_levels = 6", -1e-3, "t").replace(
        "[output]\ncheckpoint_every = 3",
        "[solver]\nmixed_integration_points = false\n[output]\ncheckpoint_every = 1",
    )
}

/// The strip ten times thinner (h/L = 1e-3, E scaled so that its bending stiffness stays) with quadratic
/// rotations and `regge_stabilized`, and a checkpoint after every level: its levels start from quadratic
/// predictions of the last two increments, which a resumed run must continue.
fn thin_quasi_static_strip() -> String {
    strip("mode = \"quasi_static\"\nn_levels = 6", -1e-3, "t")
        .replace("checkpoint_every = 3", "checkpoint_every = 1")
        .replace("rotation_element = \"tri3\"", "rotation_element = \"tri6\"")
        .replace(
            "thickness = 1e-3",
            "thickness = 1e-4\nstrain_interpolation = \"regge_stabilized\"",
        )
        .replace("youngs_modulus = 1e6", "youngs_modulus = 1e9")
        .replace("length_scale = 1e-4", "length_scale = 1e-7")
}

/// The strip with the default discretisation (quadratic rotations, `regge_stabilized`), cells of 100
/// thicknesses, pulled along its axis to about 1 % by an end load applied at once: it vibrates in
/// tension, so its stabilisation keeps, from step to step, stresses other than the step start's, which
/// the checkpoint must hold.
fn stretched_strip() -> String {
    let time = "mode = \"dynamic\"\ndt = 0.002\nend = 0.024\noutput_fps = 250.0";
    strip(time, 1000.0, "1")
        .replace(
            "force = [0.0, 0.0, 1000]",
            "force = [1000.0, 0.0, 0.0]\ndistribution = \"per_length\"",
        )
        .replace("rotation_element = \"tri3\"\n", "")
        .replace("thickness = 1e-3", "thickness = 1e-4")
        .replace("youngs_modulus = 1e6", "youngs_modulus = 1e9")
        .replace("length_scale = 1e-4", "length_scale = 1e-7")
}

/// A plate dropped onto a floor inclined by 20° with friction μ = 0.5: it lands within the first
/// steps and then sticks and slides with friction active (Tri3, 4 × 4 quads).
fn contact_plate() -> String {
    let (degrees, th) = (20.0_f64, 5e-4);
    let theta = degrees.to_radians();
    let lift = 2.0 * th + 1e-3;
    let (x, z) = (
        -0.3 * theta.cos() + lift * theta.sin(),
        0.3 * theta.sin() + lift * theta.cos(),
    );
    format!(
        r#"
name = "plate_on_incline"
gravity = [0.0, 0.0, -9.81]
[time]
dt = 0.01
end = 0.12
adaptive = true
output_fps = 100.0
[output]
checkpoint_every = 4
[solver]
tolerance = 1e-9
[mesh]
generator = "rectangle"
lx = 0.1
ly = 0.1
nx = 4
ny = 4
element = "tri3"
rotation_element = "tri3"
transform = {{ rotate = [{{ axis = "y", degrees = {degrees} }}], translate = [{x}, -0.5, {z}] }}
[material]
model = "plate"
thickness = 1e-3
youngs_modulus = 1e7
poisson_ratio = 0.3
density = 1000.0
length_scale = 1e-3
[contact]
stiffness = 1.0
barrier_width = 1e-3
thickness = {th}
stick_velocity = 1e-3
[[contact.obstacle]]
name = "floor"
mesh = {{ generator = "rectangle", lx = 2.0, ly = 2.0, nx = 1, ny = 1, transform = {{ rotate = [{{ axis = "y", degrees = {degrees} }}] }} }}
[[contact.friction]]
between = ["shell", "floor"]
mu = 0.5
[[probe]]
name = "centre"
point = [{x}, -0.5, {z}]
quantity = "position"
"#
    )
}

fn dir(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("cosserat_checkpoint_tests")
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn write_scene(dir: &Path, text: &str) -> PathBuf {
    let p = dir.join("scene.toml");
    std::fs::write(&p, text).unwrap();
    p
}

fn simulation(scene: &Path) -> Simulation {
    let spec = load_scene(scene, &[]).unwrap_or_else(|e| panic!("{e}"));
    Simulation::new(spec).unwrap_or_else(|e| panic!("{e}"))
}

/// Runs `scene` into `out`, stopping after `stop_after` steps (with `reason`) if given.
fn run(scene: &Path, out: &Path, stop_after: Option<(usize, StopReason)>) -> RunSummary {
    let stop = StopRequest::new();
    let mut sim = simulation(scene);
    sim.run(
        out,
        &mut |info| {
            if let Some((k, reason)) = stop_after
                && info.step == k
            {
                match reason {
                    // As the SIGINT handler does: the signal number into the flag.
                    StopReason::Interrupt => stop.flag().store(2, std::sync::atomic::Ordering::SeqCst),
                    _ => stop.request(reason),
                }
            }
        },
        &stop,
    )
    .unwrap()
}

/// Resumes the run in `out` from its checkpoint through the library.
fn resume(scene: &Path, out: &Path) -> RunSummary {
    let checkpoint = Checkpoint::read(out).unwrap_or_else(|e| panic!("{e}"));
    let mut sim = simulation(scene);
    sim.resume_from(out, checkpoint).unwrap_or_else(|e| panic!("{e}"));
    sim.run(out, &mut |_| {}, &StopRequest::new()).unwrap()
}

/// The run's output files that must match byte for byte: `probes.csv` and everything in `frames/`.
fn outputs(out: &Path) -> Vec<(String, Vec<u8>)> {
    let mut files = vec![("probes.csv".to_string(), std::fs::read(out.join("probes.csv")).unwrap())];
    let mut frames: Vec<_> = std::fs::read_dir(out.join("frames"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    frames.sort();
    for f in frames {
        let name = format!("frames/{}", f.file_name().unwrap().to_string_lossy());
        files.push((name, std::fs::read(&f).unwrap()));
    }
    files
}

fn assert_same_outputs(expected: &Path, resumed: &Path) {
    let (a, b) = (outputs(expected), outputs(resumed));
    let names = |v: &[(String, Vec<u8>)]| v.iter().map(|(n, _)| n.clone()).collect::<Vec<_>>();
    assert_eq!(names(&a), names(&b), "the resumed run wrote other files");
    for ((name, x), (_, y)) in a.iter().zip(&b) {
        assert!(x == y, "{name} differs between the uninterrupted and the resumed run");
    }
}

/// The summary's counts that a resumed run must reproduce (times differ).
fn counts(s: &RunSummary) -> (RunStatus, usize, usize, usize, usize, usize) {
    (
        s.status,
        s.n_steps,
        s.n_frames,
        s.max_newton_iterations,
        s.wasted_newton_iterations,
        s.n_step_reductions,
    )
}

/// Runs `text` uninterrupted and stopped after `stop_after` steps then resumed; the outputs must be
/// identical. Returns the step the resumed run started from.
fn check_bit_identity(name: &str, text: &str, stop_after: usize) -> (RunSummary, RunSummary) {
    let d = dir(name);
    let scene = write_scene(&d, text);
    let (whole, parts) = (d.join("whole"), d.join("parts"));
    let expected = run(&scene, &whole, None);
    assert_eq!(expected.status, RunStatus::Ok, "{:?}", expected.reason);
    let stopped = run(&scene, &parts, Some((stop_after, StopReason::Requested)));
    assert_eq!(stopped.status, RunStatus::Interrupted);
    assert_eq!(stopped.n_steps, stop_after);
    let resumed = resume(&scene, &parts);
    assert_same_outputs(&whole, &parts);
    assert_eq!(counts(&resumed), counts(&expected));
    assert_eq!(resumed.energy, expected.energy);
    (expected, resumed)
}

#[test]
fn a_resumed_dynamic_run_is_bit_identical() {
    // Checkpoints after steps 3, 6, 9: stopped after step 7, the run goes back to step 6 and writes
    // step 7's row again.
    let (_, resumed) = check_bit_identity("dynamic", &dynamic_strip(), 7);
    assert_eq!(resumed.resumed_from, Some(6));
    assert_eq!(resumed.n_steps, 12);
}

#[test]
fn a_resumed_run_of_a_sheet_in_tension_is_bit_identical() {
    let (expected, resumed) = check_bit_identity("stretched", &stretched_strip(), 7);
    assert_eq!(resumed.resumed_from, Some(6));
    assert_eq!(expected.n_steps, 12);
}

#[test]
fn a_resumed_run_from_the_least_energy_start_is_bit_identical() {
    // The stretched strip started from the least incremental potential, with a checkpoint after every
    // step. Its steps from the eighth on start from the extrapolation and converge in one iteration, so
    // the next start is taken without comparing: a run resumed after step 8 must know that its last
    // step was smooth to start step 9 as the uninterrupted run does.
    let text = stretched_strip()
        .replace("checkpoint_every = 3", "checkpoint_every = 1")
        .replace("[mesh]", "[solver]\ninitial_guess = \"least_energy\"\n[mesh]");
    let (expected, resumed) = check_bit_identity("least_energy", &text, 8);
    assert_eq!(resumed.resumed_from, Some(8));
    assert_eq!(expected.n_steps, 12);
}

#[test]
fn a_resumed_contact_run_with_friction_is_bit_identical() {
    let (expected, resumed) = check_bit_identity("contact", &contact_plate(), 10);
    assert_eq!(resumed.resumed_from, Some(8));
    let (a, b) = (expected.contact.unwrap(), resumed.contact.unwrap());
    assert!(a.max_active_pairs > 0, "the plate never reached the floor");
    assert_eq!(
        (
            a.max_active_pairs,
            a.mean_active_pairs.to_bits(),
            a.min_gap.map(f64::to_bits)
        ),
        (
            b.max_active_pairs,
            b.mean_active_pairs.to_bits(),
            b.min_gap.map(f64::to_bits)
        )
    );
    // The contact term's counters continue across the resume (the restored run asks the broad phase
    // once more, to rebuild the pattern, so its query count is not compared).
    assert!(a.n_ccd_queries > 0 && a.n_evaluations > 0);
    assert_eq!(
        (
            a.n_evaluations,
            a.n_ccd_queries,
            a.n_step_cuts,
            a.mean_step_fraction.map(f64::to_bits),
        ),
        (
            b.n_evaluations,
            b.n_ccd_queries,
            b.n_step_cuts,
            b.mean_step_fraction.map(f64::to_bits),
        )
    );
}

#[test]
fn a_resumed_quasi_static_run_is_bit_identical() {
    let (_, resumed) = check_bit_identity("quasi_static", &quasi_static_strip(), 4);
    assert_eq!(resumed.resumed_from, Some(3));
    assert_eq!(resumed.n_steps, 6);
}

#[test]
fn a_resumed_quasi_static_run_with_intermediate_levels_is_bit_identical() {
    let (expected, resumed) = check_bit_identity(
        "quasi_static_intermediate",
        &quasi_static_strip_with_intermediate_levels(),
        2,
    );
    assert!(expected.n_intermediate_levels > 0, "no intermediate level was solved");
    assert_eq!(resumed.n_intermediate_levels, expected.n_intermediate_levels);
    // The first level is one of the slow ones: the run resumes with a shortened increment.
    assert_eq!(resumed.resumed_from, Some(2));
}

#[test]
fn a_resumed_thin_quasi_static_run_continues_its_quadratic_predictions() {
    // The checkpoint keeps the predictor's increments: the resumed levels start from the same
    // quadratic predictions, bit for bit.
    let (expected, resumed) = check_bit_identity("quasi_static_thin", &thin_quasi_static_strip(), 4);
    assert_eq!(resumed.resumed_from, Some(4));
    assert_eq!(resumed.n_steps, expected.n_steps);
}

#[test]
fn an_interrupted_run_resumes_from_its_last_checkpoint_with_the_command() {
    let d = dir("interrupted");
    let scene = write_scene(&d, &dynamic_strip());
    let (whole, parts) = (d.join("whole"), d.join("parts"));
    run(&scene, &whole, None);
    let stopped = run(&scene, &parts, Some((5, StopReason::Interrupt)));
    assert_eq!(stopped.status, RunStatus::Interrupted);
    assert_eq!(stopped.reason.as_deref(), Some("interrupted by SIGINT (Ctrl-C)"));
    let code = resume_run(&ResumeArgs {
        dir: parts.clone(),
        threads: Some(1),
        quiet: true,
        max_memory: None,
    })
    .unwrap();
    assert_eq!(code, 0);
    assert_same_outputs(&whole, &parts);
    let summary = read_summary(&parts.join("summary.json")).unwrap();
    assert_eq!(summary.status, RunStatus::Ok);
    assert_eq!(summary.resumed_from, Some(3));
    assert_eq!(summary.n_steps, 12);
    assert_eq!(
        std::fs::read_to_string(parts.join("checkpoint").join("scene.toml")).unwrap(),
        dynamic_strip()
    );
}

/// A quiet one-thread command-line run of `scene` into `out`.
fn run_args(scene: &Path, out: &Path) -> RunArgs {
    RunArgs {
        scene: scene.to_path_buf(),
        out: Some(out.to_path_buf()),
        overrides: Vec::new(),
        threads: Some(1),
        quiet: true,
        max_memory: None,
    }
}

fn resume_args(dir: &Path) -> ResumeArgs {
    ResumeArgs {
        dir: dir.to_path_buf(),
        threads: Some(1),
        quiet: true,
        max_memory: None,
    }
}

/// A finished command-line run of the dynamic strip in `d/out`, with its checkpoint.
fn finished_run(d: &Path) -> (PathBuf, PathBuf) {
    let scene = write_scene(d, &dynamic_strip());
    let out = d.join("out");
    assert_eq!(run_scene(&run_args(&scene, &out)).unwrap(), 0);
    assert!(state_path(&out).is_file());
    (scene, out)
}

#[test]
fn resuming_with_a_changed_scene_is_refused() {
    let d = dir("changed_scene");
    let (scene, out) = finished_run(&d);
    let summary_before = std::fs::read(out.join("summary.json")).unwrap();
    std::fs::write(
        &scene,
        dynamic_strip().replace("force = [0.0, 0.0, -0.01]", "force = [0.0, 0.0, -0.02]"),
    )
    .unwrap();
    let error = format!("{:#}", resume_run(&resume_args(&out)).unwrap_err());
    assert!(error.contains("state.bin"), "{error}");
    assert!(error.contains("the scene differs"), "{error}");
    assert!(error.contains("checkpoint/scene.toml"), "{error}");
    assert_eq!(std::fs::read(out.join("summary.json")).unwrap(), summary_before);
}

#[test]
fn a_missing_or_damaged_checkpoint_is_refused_with_the_reason() {
    let d = dir("damaged");
    let (_, out) = finished_run(&d);
    let path = state_path(&out);
    let bytes = std::fs::read(&path).unwrap();
    let error_for = |contents: Option<&[u8]>| {
        match contents {
            Some(c) => std::fs::write(&path, c).unwrap(),
            None => std::fs::remove_file(&path).unwrap(),
        }
        format!("{:#}", resume_run(&resume_args(&out)).unwrap_err())
    };
    let mut flipped = bytes.clone();
    let middle = flipped.len() / 2;
    flipped[middle] ^= 0x10;
    let cases: [(Option<&[u8]>, &str); 4] = [
        (Some(&flipped), "checksum"),
        (Some(&bytes[..bytes.len() - 100]), "checksum"),
        (Some(b"name = \"strip\"\n"), "not a checkpoint"),
        (None, "a run writes one only with `output.checkpoint_every`"),
    ];
    for (contents, reason) in cases {
        let error = error_for(contents);
        assert!(error.contains(&path.display().to_string()), "{error}");
        assert!(error.contains(reason), "{error}");
    }
}

/// The dynamic strip stopped after step 8 in `d/out`: its last checkpoint (step 6) counts four probe
/// rows and frames, the run wrote a fifth of each after it.
fn stopped_after_its_checkpoint(d: &Path, text: &str) -> PathBuf {
    let scene = write_scene(d, text);
    let out = d.join("out");
    let stopped = run(&scene, &out, Some((8, StopReason::Interrupt)));
    assert_eq!(stopped.status, RunStatus::Interrupted);
    let rows = std::fs::read_to_string(out.join("probes.csv")).unwrap().lines().count() - 1;
    assert_eq!((Checkpoint::read(&out).unwrap().probe_rows, rows), (4, 5));
    out
}

#[test]
fn a_refused_resume_leaves_the_run_as_it_was() {
    let d = dir("refused_untouched");
    let out = stopped_after_its_checkpoint(&d, &dynamic_strip());
    std::fs::remove_file(out.join("frames").join("frame_00001.vtu")).unwrap();
    let before = outputs(&out);
    let error = format!("{:#}", resume_run(&resume_args(&out)).unwrap_err());
    assert!(error.contains("frame_00001.vtu"), "{error}");
    assert!(before == outputs(&out), "the refused resume changed the outputs");
}

#[test]
fn resuming_refuses_a_missing_obj_or_ply_frame() {
    let d = dir("missing_mesh_frame");
    let text = dynamic_strip().replace("[output]\n", "[output]\nformats = [\"vtu\", \"obj\", \"ply\"]\n");
    let out = stopped_after_its_checkpoint(&d, &text);
    for file in ["frame_00002.obj", "frame_00003.ply"] {
        let path = out.join("frames").join(file);
        let bytes = std::fs::read(&path).unwrap();
        std::fs::remove_file(&path).unwrap();
        let error = format!("{:#}", resume_run(&resume_args(&out)).unwrap_err());
        assert!(error.contains(&path.display().to_string()), "{error}");
        assert!(error.contains("the checkpoint counts it"), "{error}");
        std::fs::write(&path, bytes).unwrap();
    }
}

#[test]
fn resuming_removes_the_temporary_files_of_a_killed_run() {
    let d = dir("killed_temporaries");
    let out = stopped_after_its_checkpoint(&d, &dynamic_strip());
    // What a run killed while writing leaves: hidden temporaries of its atomic writes.
    let left = [
        out.join(".probes.csv.tmp4242-1"),
        out.join("frames").join(".run.pvd.tmp4242-2"),
        out.join("frames").join(".frame_00005.vtu.tmp4242-3"),
        out.join("checkpoint").join(".state.bin.tmp4242-4"),
    ];
    let keep = out.join("checkpoint").join("notes.txt");
    for path in left.iter().chain([&keep]) {
        std::fs::write(path, "partial").unwrap();
    }
    assert_eq!(resume_run(&resume_args(&out)).unwrap(), 0);
    for path in &left {
        assert!(!path.exists(), "{} stayed", path.display());
    }
    assert!(keep.exists(), "a file of the user went");
    // A new run into the folder clears its checkpoint's temporaries too.
    std::fs::write(&left[3], "partial").unwrap();
    assert_eq!(run_scene(&run_args(&d.join("scene.toml"), &out)).unwrap(), 0);
    assert!(!left[3].exists());
}

#[test]
fn a_resumed_run_under_way_leaves_no_summary_of_the_earlier_run() {
    // A resumed run that is killed must not leave the earlier run's summary, which says where that
    // run stopped, next to the rows and frames written after it.
    let d = dir("resumed_summary");
    let out = stopped_after_its_checkpoint(&d, &dynamic_strip());
    assert!(out.join("summary.json").is_file());
    let mut sim = simulation(&d.join("scene.toml"));
    sim.resume_from(&out, Checkpoint::read(&out).unwrap()).unwrap();
    let mut seen = Vec::new();
    let summary = sim
        .run(
            &out,
            &mut |_| seen.push(out.join("summary.json").exists()),
            &StopRequest::new(),
        )
        .unwrap();
    assert_eq!(summary.status, RunStatus::Ok);
    assert!(!seen.is_empty() && seen.iter().all(|&exists| !exists), "{seen:?}");
    assert!(out.join("summary.json").is_file());
}

#[test]
fn resuming_refuses_a_vtu_frame_that_is_cut_short_or_overwritten() {
    let d = dir("damaged_frame");
    let out = stopped_after_its_checkpoint(&d, &dynamic_strip());
    let path = out.join("frames").join("frame_00002.vtu");
    let bytes = std::fs::read(&path).unwrap();
    for damaged in [&bytes[..bytes.len() / 2], b"not a frame"] {
        std::fs::write(&path, damaged).unwrap();
        let before = outputs(&out);
        let error = format!("{:#}", resume_run(&resume_args(&out)).unwrap_err());
        assert!(error.contains(&path.display().to_string()), "{error}");
        assert!(error.contains("the frame is damaged"), "{error}");
        assert!(before == outputs(&out), "the refused resume changed the outputs");
    }
    std::fs::write(&path, bytes).unwrap();
    assert_eq!(resume_run(&resume_args(&out)).unwrap(), 0);
}

#[test]
fn a_resume_that_cannot_take_over_the_frames_keeps_the_earlier_summary() {
    let d = dir("takeover_fails");
    let out = stopped_after_its_checkpoint(&d, &dynamic_strip());
    let summary = std::fs::read(out.join("summary.json")).unwrap();
    // A frame after the checkpoint that cannot be removed, as in a frames folder without write access.
    let stuck = out.join("frames").join("frame_00004.vtu");
    std::fs::remove_file(&stuck).unwrap();
    std::fs::create_dir(&stuck).unwrap();
    let error = format!("{:#}", resume_run(&resume_args(&out)).unwrap_err());
    assert!(error.contains("frame_00004.vtu"), "{error}");
    assert_eq!(std::fs::read(out.join("summary.json")).unwrap(), summary);
}
