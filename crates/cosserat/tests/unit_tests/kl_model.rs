//! Scenes with the Kirchhoff–Love model through the facade: outputs, physics against closed forms, and
//! rejection of what the model cannot express.

use cosserat::Simulation;
use cosserat::io::{RunStatus, read_pvd, read_pvd_frame};
use cosserat::scene::SceneError;
use std::path::{Path, PathBuf};

fn dir(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("cosserat_kl_model_tests")
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The last row of `probes.csv` as (column name, value) pairs.
fn last_probe_row(dir: &Path) -> Vec<(String, f64)> {
    let text = std::fs::read_to_string(dir.join("probes.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(str::to_string).collect();
    let last = lines.last().unwrap();
    header
        .into_iter()
        .zip(last.split(',').map(|v| v.parse::<f64>().unwrap()))
        .collect()
}

fn value(row: &[(String, f64)], name: &str) -> f64 {
    row.iter()
        .find(|(n, _)| n == name)
        .unwrap_or_else(|| panic!("no column {name}"))
        .1
}

fn run(text: &str, name: &str) -> (PathBuf, cosserat::io::RunSummary) {
    let d = dir(name);
    let path = d.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let spec = cosserat::scene::load_scene(&path, &[]).unwrap_or_else(|e| panic!("{e}"));
    let mut sim = Simulation::new(spec).unwrap_or_else(|e| panic!("{e}"));
    let out = d.join("out");
    let summary = sim.run(&out, &mut |_| {}, &cosserat::StopRequest::new()).unwrap();
    (out, summary)
}

const FALLING: &str = r#"
name = "kl_falling"
gravity = [0.0, 0.0, -9.81]
[time]
dt = 0.01
end = 0.05
adaptive = false
output_fps = 100.0
[solver]
tolerance = 1e-10
[mesh]
generator = "rectangle"
lx = 0.1
ly = 0.02
nx = 5
ny = 2
[material]
model = "kirchhoff_love"
law = "stvk"
thickness = 1e-3
youngs_modulus = 1e6
poisson_ratio = 0.3
density = 1000.0
[[probe]]
name = "all"
region = { all = true }
quantity = "displacement"
"#;

#[test]
fn a_free_kirchhoff_love_sheet_falls_as_backward_euler_predicts() {
    let (out, summary) = run(FALLING, "falling");
    assert_eq!(summary.status, RunStatus::Ok, "{:?}", summary.reason);
    assert_eq!(summary.n_steps, 5);
    assert_eq!(summary.displacement_element, "tri3");
    assert_eq!(summary.rotation_element, "-");
    assert_eq!(summary.strain_interpolation, "-");
    assert_eq!((summary.n_displacement_dofs, summary.n_rotation_dofs), (3 * 18, 0));
    assert_eq!(summary.n_cells, 20);
    assert_eq!(
        summary.model,
        cosserat::io::ModelRecord::KirchhoffLove { law: "stvk".into() }
    );
    assert!(summary.active_terms.iter().any(|t| t.starts_with("kirchhoff_love")));
    // Backward Euler with lumped masses: v_n = −g n Δt, z_n = −g Δt² n(n + 1)/2; a rigid translation
    // has no elastic energy. Newton stops below 1e-10 N with nodal masses ≥ 3e-5 kg: velocities exact to
    // ~1e-10 N · Δt / m ≈ 3e-8 m/s, positions to ~1e-9 m.
    let (g, dt, n) = (9.81, 0.01, 5.0);
    let row = last_probe_row(&out);
    assert!((value(&row, "t") - 0.05).abs() < 1e-12);
    let expected = -g * dt * dt * n * (n + 1.0) / 2.0;
    assert!(
        (value(&row, "all.uz") - expected).abs() < 1e-8,
        "{} vs {expected}",
        value(&row, "all.uz")
    );
    assert!(value(&row, "all.ux").abs() < 1e-10 && value(&row, "all.uy").abs() < 1e-10);
    // Frames: the Tri3 surface with displacement, velocity and unit normals (the sheet stays flat: ±z).
    let pvd = out.join("frames").join("run.pvd");
    let entries = read_pvd(&pvd).unwrap();
    assert_eq!(entries.len(), 6);
    let frame = read_pvd_frame(&pvd, 5).unwrap();
    assert_eq!((frame.points.len(), frame.triangles.len()), (18, 20));
    let normals = frame.point_array("director3").unwrap();
    for i in 0..18 {
        assert!((normals.tuple(i)[2].abs() - 1.0).abs() < 1e-9);
    }
    let v = frame.point_array("velocity").unwrap();
    assert!((v.tuple(0)[2] + g * n * dt).abs() < 1e-6);
}

/// A cantilever (ν = 0) clamped by its first two vertex columns under a small tip force, solved
/// quasi-statically: the clamp line lies midway between the columns, so the beam is L = 0.0975 m long.
const CANTILEVER: &str = r#"
name = "kl_cantilever"
[time]
mode = "quasi_static"
n_levels = 1
[solver]
tolerance = 1e-9
[mesh]
generator = "rectangle"
lx = 0.1
ly = 0.01
nx = 20
ny = 1
[material]
model = "kirchhoff_love"
law = "neo_hookean"
thickness = 1e-3
youngs_modulus = 1e9
poisson_ratio = 0.0
density = 1000.0
[[boundary]]
name = "clamp"
region = { predicate = "x <= -0.045 + 1e-9" }
position = { exact = true }
[[load]]
name = "tip"
region = { predicate = "x >= 0.05 - 1e-9" }
force = [0.0, 0.0, -2.63e-4]
[[probe]]
name = "tip"
region = { predicate = "x >= 0.05 - 1e-9" }
quantity = "displacement"
"#;

#[test]
fn a_kirchhoff_love_cantilever_scene_bends_as_euler_bernoulli_says() {
    let (out, summary) = run(CANTILEVER, "cantilever");
    assert_eq!(summary.status, RunStatus::Ok, "{:?}", summary.reason);
    // δ = F L³ / (3 E I), I = w h³ / 12: 1e-3 L here, so geometric nonlinearity is ~1e-6.
    let (f, l, e, i): (f64, f64, f64, f64) = (2.63e-4, 0.0975, 1e9, 0.01 * 1e-9 / 12.0);
    let expected = -f * l.powi(3) / (3.0 * e * i);
    let tip = value(&last_probe_row(&out), "tip.uz");
    // Measured in docs/kirchhoff-love.md: the centred clamp converges at second order, 0.9990 of the
    // beam value on 16 × 1 elements; 20 × 1 here.
    assert!(
        (tip / expected - 1.0).abs() < 2e-3,
        "tip {tip}, Euler–Bernoulli {expected}"
    );
}

#[test]
fn kirchhoff_love_scenes_with_tri6_or_rotation_conditions_are_rejected() {
    let d = dir("rejected");
    let tri6 = d.join("tri6.toml");
    std::fs::write(&tri6, FALLING.replace("ny = 2\n", "ny = 2\nelement = \"tri6\"\n")).unwrap();
    match cosserat::scene::load_scene(&tri6, &[]) {
        Err(SceneError::Invalid { field, reason, .. }) => {
            assert_eq!(field, "mesh.element");
            assert!(reason.contains("Tri6 elements are not available"), "{reason}");
        }
        other => panic!("a Tri6 Kirchhoff–Love scene was not rejected: {other:?}"),
    }
    let rotation = d.join("rotation.toml");
    let text = format!(
        "{FALLING}[[boundary]]\nregion = {{ predicate = \"x <= -0.05 + 1e-9\" }}\nrotation = {{ stiffness = 1.0 }}\n"
    );
    std::fs::write(&rotation, text).unwrap();
    let err = cosserat::scene::load_scene(&rotation, &[]).unwrap_err();
    let message = err.to_string();
    assert!(
        message.starts_with(&format!("{}:", rotation.display())) && message.contains("boundary.0.rotation"),
        "{message}"
    );
    assert!(matches!(err, SceneError::Invalid { ref field, .. } if field == "boundary.0.rotation"));
}

/// A 4 × 4 sheet falls 1 mm onto a floor box and comes to rest on it.
const ON_FLOOR: &str = r#"
name = "kl_floor"
gravity = [0.0, 0.0, -9.81]
[time]
dt = 0.005
end = 0.1
adaptive = true
output_fps = 50.0
[mesh]
generator = "rectangle"
lx = 0.1
ly = 0.1
nx = 4
ny = 4
[material]
model = "kirchhoff_love"
law = "stvk"
thickness = 1e-3
youngs_modulus = 1e6
poisson_ratio = 0.3
density = 1000.0
damping = 5.0
[contact]
stiffness = 1.0
barrier_width = 1e-4
thickness = 5e-5
[[contact.obstacle]]
name = "floor"
box = { center = [0.0, 0.0, -0.006], size = [1.0, 1.0, 0.01] }
[[probe]]
name = "all"
region = { all = true }
quantity = "position"
"#;

#[test]
fn a_kirchhoff_love_sheet_lands_on_a_floor_without_crossing_it() {
    let (out, summary) = run(ON_FLOOR, "floor");
    assert_eq!(summary.status, RunStatus::Ok, "{:?}", summary.reason);
    let contact = summary.contact.as_ref().unwrap();
    assert_eq!(contact.n_triangles, 32 + 12);
    // The floor's top is at z = −1 mm; the pair thickness keeps 0.1 mm between the surfaces.
    let min_gap = contact.min_gap.unwrap();
    assert!(min_gap > 0.0 && min_gap < 1e-4, "{min_gap}");
    let z = value(&last_probe_row(&out), "all.z");
    assert!(z > -1e-3 + 1e-4 && z < -1e-3 + 2e-4, "{z}");
}
