//! Scenes with the volumetric micropolar model through the facade: a slab falls as backward Euler
//! predicts, the conjugate-gradient and direct solvers reach the same curled slab, and selections act on
//! whole node columns.

use cosserat::Simulation;
use cosserat::io::{RunStatus, RunSummary, read_pvd, read_pvd_frame};
use std::path::{Path, PathBuf};

fn dir(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("cosserat_volume_model_tests")
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn probe_rows(dir: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(dir.join("probes.csv")).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(str::to_string).collect();
    let rows = lines.map(|l| l.split(',').map(|v| v.parse().unwrap()).collect()).collect();
    (header, rows)
}

fn column(header: &[String], name: &str) -> usize {
    header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name}"))
}

fn run(text: &str, name: &str, overrides: &[String]) -> (PathBuf, RunSummary) {
    let d = dir(name);
    let path = d.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let spec = cosserat::scene::load_scene(&path, overrides).unwrap_or_else(|e| panic!("{e}"));
    let mut sim = Simulation::new(spec).unwrap_or_else(|e| panic!("{e}"));
    let out = d.join("out");
    let summary = sim.run(&out, &mut |_| {}, &cosserat::StopRequest::new()).unwrap();
    (out, summary)
}

/// A 0.4 m × 0.4 m × 1 cm slab (4 × 4 × 1 cells), the centre column pinned, curled by a rest curvature
/// that grows with time; probes at an edge midpoint and a corner of the mid-surface.
const CURL: &str = r#"
name = "slab_curl"
[time]
dt = 0.01
end = 0.1
adaptive = false
output_fps = 100.0
[solver]
linear_solver = "cg"
tolerance = 1e-9
[mesh]
generator = "rectangle"
lx = 0.4
ly = 0.4
nx = 4
ny = 4
[material]
model = "micropolar_volume"
thickness = 0.01
youngs_modulus = 0.5e6
poisson_ratio = 0.3
density = 3000.0
length_scale = 0.1
[[boundary]]
name = "pin"
region = { nearest = [0.0, 0.0, 0.0] }
position = { stiffness = 1e6 }
[[rest_field]]
curvature = [{ row = 2, col = 1, value = "-30 * t * abs(x)" }]
[[probe]]
name = "centre"
point = [0.0, 0.0, 0.0]
quantity = "displacement"
[[probe]]
name = "edge"
point = [0.2, 0.0, 0.0]
quantity = "position"
[[probe]]
name = "corner"
point = [0.2, 0.2, 0.0]
quantity = "position"
"#;

#[test]
fn cg_and_direct_solvers_curl_the_slab_alike() {
    let (cg_out, cg) = run(CURL, "curl_cg", &[]);
    let (lu_out, lu) = run(CURL, "curl_direct", &["solver.linear_solver=auto".into()]);
    for s in [&cg, &lu] {
        assert_eq!(s.status, RunStatus::Ok, "{:?}", s.reason);
        assert_eq!(s.n_steps, 10);
        assert_eq!(
            (s.displacement_element.as_str(), s.rotation_element.as_str()),
            ("tet4", "tet4")
        );
        // 5 × 5 × 2 nodes, 6 tetrahedra per cell.
        assert_eq!((s.n_displacement_dofs, s.n_rotation_dofs, s.n_cells), (150, 150, 96));
        assert_eq!(
            s.model,
            cosserat::io::ModelRecord::MicropolarVolume { n_tetrahedra: 96 }
        );
    }
    assert!(cg.linear_solver.cg_iterations.unwrap() > 0);
    assert!(lu.linear_solver.cg_iterations.is_none());
    let (header, cg_rows) = probe_rows(&cg_out);
    let (_, lu_rows) = probe_rows(&lu_out);
    let z = column(&header, "edge.z");
    let (cg_last, lu_last) = (cg_rows.last().unwrap(), lu_rows.last().unwrap());
    // The rest curvature lifts the edge (Γ₂₁ < 0 turns the +x half upwards) by millimetres.
    assert!(lu_last[z] > 1e-3, "edge height {}", lu_last[z]);
    // Both solve each step to a residual of 1e-9 N: the states agree far below the motion.
    for (c, l) in cg_last.iter().zip(lu_last) {
        assert!((c - l).abs() < 1e-6 * lu_last[z], "{c} vs {l}");
    }
    // The pinned column (the mid-surface centre) stays within F/k of its place: forces ≪ 1e-3 N here.
    let centre = column(&header, "centre.uz");
    assert!(lu_last[centre].abs() < 1e-6, "{}", lu_last[centre]);
    // The frames show the mid-surface: 25 points over the grid's 32 triangles; rotations by quaternion
    // averages stay unit.
    let pvd = lu_out.join("frames").join("run.pvd");
    let frame = read_pvd_frame(&pvd, read_pvd(&pvd).unwrap().len() - 1).unwrap();
    assert_eq!((frame.points.len(), frame.triangles.len()), (25, 32));
    let d3 = frame.point_array("director3").unwrap();
    for i in 0..25 {
        let v = d3.tuple(i);
        assert!(((v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt() - 1.0).abs() < 1e-12);
    }
}

#[test]
fn a_kept_factorisation_curls_the_slab_to_the_same_states_with_fewer_factorisations() {
    let direct = ["solver.linear_solver=auto".to_string()];
    let (fresh_out, fresh) = run(CURL, "curl_fresh_factors", &direct);
    let kept = [direct[0].clone(), "solver.reuse_factorisation=0.1".into()];
    let (kept_out, kept) = run(CURL, "curl_kept_factors", &kept);
    assert_eq!((fresh.status, kept.status), (RunStatus::Ok, RunStatus::Ok));
    let its = |s: &RunSummary| (s.avg_newton_iterations * s.n_steps as f64).round() as usize;
    // Without reuse every iteration factorises; with it most iterations are chord steps.
    assert_eq!(fresh.linear_solver.factorisations, its(&fresh));
    assert!(
        2 * kept.linear_solver.factorisations < its(&kept),
        "{} factorisations in {} iterations",
        kept.linear_solver.factorisations,
        its(&kept)
    );
    // Both solve each step to a residual of 1e-9 N: the states agree far below the motion.
    let (header, fresh_rows) = probe_rows(&fresh_out);
    let (_, kept_rows) = probe_rows(&kept_out);
    let z = column(&header, "edge.z");
    for (f, k) in fresh_rows.iter().zip(&kept_rows) {
        for (a, b) in f.iter().zip(k) {
            assert!((a - b).abs() < 1e-6 * fresh_rows.last().unwrap()[z], "{a} vs {b}");
        }
    }
}

#[test]
fn a_free_slab_falls_as_backward_euler_predicts() {
    let text = CURL
        .replace(
            "name = \"slab_curl\"",
            "name = \"slab_fall\"\ngravity = [0.0, 0.0, -9.81]",
        )
        .replace("end = 0.1", "end = 0.05");
    let text = text[..text.find("[[boundary]]").unwrap()].to_string()
        + "[[probe]]\nname = \"all\"\nregion = { all = true }\nquantity = \"displacement\"\n";
    let (out, summary) = run(&text, "fall", &["solver.linear_solver=auto".into()]);
    assert_eq!(summary.status, RunStatus::Ok, "{:?}", summary.reason);
    let (header, rows) = probe_rows(&out);
    let last = rows.last().unwrap();
    // z_n = −g Δt² n (n + 1)/2 for n = 5 (no elastic energy in a rigid translation); Newton stops at 1e-9 N
    // with nodal masses ≥ 3000·4e-4/4·…  ≈ 0.1 g, so positions are exact to ~1e-9 m.
    let expected = -9.81 * 1e-4 * 15.0;
    assert!((last[column(&header, "all.uz")] - expected).abs() < 1e-8);
}
