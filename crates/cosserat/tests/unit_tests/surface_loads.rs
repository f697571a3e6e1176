//! Loads per unit area and pressure through the facade, against closed forms: a closed sphere inflated
//! by a follower pressure (membrane closed form, small and large stretch) and the Scordelis–Lo roof
//! under its weight given per unit area and as gravity; a long cylinder buckling under external
//! pressure (follower and dead) at the classical critical pressures.

use cosserat::Simulation;
use cosserat::scene::spec::SceneSpec;
use nalgebra::Vector3;
use std::path::{Path, PathBuf};

fn run(text: &str, name: &str) -> Simulation {
    let spec = SceneSpec::from_str(text, "surface_loads.toml", Path::new("."), &[]).unwrap_or_else(|e| panic!("{e}"));
    let mut sim = Simulation::new(spec).unwrap_or_else(|e| panic!("{e}"));
    let dir: PathBuf = Path::new(env!("CARGO_TARGET_TMPDIR")).join("surface_loads").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    let summary = sim
        .run(&dir, &mut |_| {}, &cosserat::StopRequest::new())
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(summary.status, cosserat::io::RunStatus::Ok, "{name}: {summary:?}");
    sim
}

const E: f64 = 1.0e6;
const NU: f64 = 0.3;
const H: f64 = 0.01;

/// The pressure that holds a thin sphere of radius 1 at the stretch `lambda` in this model: the
/// membrane strain is the Biot strain `(λ − 1) a`, so the energy per rest area is
/// `h E (λ − 1)² / (1 − ν)` and equilibrium with the work `p ⁴⁄₃π λ³` gives
/// `p = 2 h E (λ − 1) / ((1 − ν) λ²)` (the curved terms add `O(h⁴/R⁴)`).
fn sphere_pressure(lambda: f64) -> f64 {
    2.0 * H * E * (lambda - 1.0) / ((1.0 - NU) * lambda * lambda)
}

/// A unit icosphere (level 2, Tri6 displacement / Tri3 rotation, curved shell model) held only on its
/// three symmetry planes, under internal follower pressure `p` applied in `n` equal steps; returns the
/// mean radius of the displacement nodes.
fn inflate(p: f64, n: usize, name: &str) -> f64 {
    let scene = format!(
        r#"
name = "{name}"
[time]
mode = "quasi_static"
n_levels = {n}
[output]
frames = false
[mesh]
generator = "icosphere"
radius = 1.0
level = 2
element = "tri6"
rotation_element = "tri3"
[material]
model = "shell"
thickness = {H}
youngs_modulus = {E}
poisson_ratio = {NU}
density = 1.0
length_scale = 1e-5
[[boundary]]
name = "sym_x"
region = {{ predicate = "abs(x) < 1e-12" }}
position = {{ exact = true, axes = ["x"] }}
[[boundary]]
name = "sym_y"
region = {{ predicate = "abs(y) < 1e-12" }}
position = {{ exact = true, axes = ["y"] }}
[[boundary]]
name = "sym_z"
region = {{ predicate = "abs(z) < 1e-12" }}
position = {{ exact = true, axes = ["z"] }}
[[load]]
name = "inflation"
region = {{ all = true }}
pressure = {p}
scale = "t"
"#
    );
    let sim = run(&scene, name);
    let x = &sim.potential().parts.state.x;
    x.iter().map(|p| p.norm()).sum::<f64>() / x.len() as f64
}

#[test]
fn inflated_sphere_matches_the_membrane_closed_form() {
    for (lambda, n) in [(1.001, 1), (1.3, 6)] {
        let r = inflate(sphere_pressure(lambda), n, &format!("sphere_{lambda}"));
        let err = (r - lambda) / (lambda - 1.0);
        eprintln!("sphere: λ = {lambda}: mean radius {r:.6}, error in λ − 1 {:.3e}", err);
        assert!(err.abs() < 1e-2, "stretch {lambda}: radius {r}");
    }
}

/// The Scordelis–Lo roof (docs/references.md: R = 25, L = 50, 40°, h = 0.25, E = 4.32e8, ν = 0,
/// diaphragm ends) on `n × n` quads of `element`/Tri3, under 1/1000 of its weight (so the response is
/// linear, as the reference is), given as `load` (TOML). Returns the vertical displacement of the
/// midpoint of a free edge (times 1000) and the external nodal forces of the last step (loads and
/// gravity on the lumped masses).
fn roof(load: &str, gravity: &str, element: &str, n: usize, name: &str) -> (f64, Vec<Vector3<f64>>) {
    let theta = 40f64.to_radians();
    let scene = format!(
        r#"
name = "{name}"
gravity = {gravity}
[time]
mode = "quasi_static"
n_levels = 1
[output]
frames = false
[mesh]
generator = "rectangle"
lx = {lx}
ly = 50.0
nx = {n}
ny = {n}
element = "{element}"
rotation_element = "tri3"
displace = ["25*sin(x/25) - x", "0", "25*cos(x/25) - 25"]
[material]
model = "shell"
thickness = 0.25
youngs_modulus = 4.32e8
poisson_ratio = 0.0
density = 1.0
length_scale = 2.5e-4
[[boundary]]
name = "diaphragms"
region = {{ predicate = "abs(y) >= 25 - 1e-9" }}
position = {{ exact = true, axes = ["x", "z"] }}
{load}
[[probe]]
name = "edge"
point = [{xe}, 0.0, {ze}]
"#,
        lx = 50.0 * theta,
        xe = 25.0 * theta.sin(),
        ze = 25.0 * theta.cos() - 25.0,
    );
    let sim = run(&scene, name);
    let parts = &sim.potential().parts;
    let target = Vector3::new(25.0 * theta.sin(), 0.0, 25.0 * theta.cos() - 25.0);
    let (i, _) = sim.placements()[0]
        .rest_disp
        .iter()
        .enumerate()
        .min_by(|a, b| (a.1 - target).norm().total_cmp(&(b.1 - target).norm()))
        .unwrap();
    let loads = &parts.loads;
    let forces = loads
        .forces
        .iter()
        .zip(&loads.masses)
        .map(|(f, m)| f + loads.gravity * *m)
        .collect();
    ((parts.state.x[i].z - target.z) * 1e3, forces)
}

const PER_AREA: &str =
    "[[load]]\nname = \"weight\"\nregion = { all = true }\nforce = [0.0, 0.0, -0.09]\ndistribution = \"per_area\"";
/// ρ h g = 1 · 0.25 · 0.36 = 0.09 per unit area.
const GRAVITY: &str = "[0.0, 0.0, -0.36]";
const NO_GRAVITY: &str = "[0.0, 0.0, 0.0]";

/// On Tri6/Tri3 (16 × 16) the weight per unit area and the weight from density and gravity give the
/// reference deflection within the discretisation error (2.5 % at this mesh, 1.2 % at 24 × 24) and
/// agree with each other to 0.3 %: the consistent weights of a Tri6 put the load on the mid-edge nodes,
/// the lumped masses spread it equally, and the two converge together under refinement (0.52 % apart
/// at 12 × 12, 0.13 % at 24 × 24).
#[test]
fn scordelis_lo_roof_per_area_load_equals_its_weight() {
    let (per_area, _) = roof(PER_AREA, NO_GRAVITY, "tri6", 16, "roof_per_area");
    let (gravity, _) = roof("", GRAVITY, "tri6", 16, "roof_gravity");
    eprintln!("Scordelis–Lo 16 × 16: per area {per_area:.5}, gravity {gravity:.5}, reference −0.3024");
    for w in [per_area, gravity] {
        assert!((w + 0.3024).abs() < 0.03 * 0.3024, "{w}");
    }
    assert!((per_area - gravity).abs() < 0.005 * 0.3024, "{per_area} vs {gravity}");
}

/// On Tri3 elements the consistent weight of a node is a third of the area of its triangles, which is
/// exactly its share of the lumped mass: the nodal loads are equal to round-off.
#[test]
fn tri3_per_area_weights_are_the_lumped_mass_shares() {
    let (_, per_area) = roof(PER_AREA, NO_GRAVITY, "tri3", 6, "roof_tri3_per_area");
    let (_, gravity) = roof("", GRAVITY, "tri3", 6, "roof_tri3_gravity");
    let total: f64 = gravity.iter().map(|f| f.z).sum();
    // The roof's area 50 · 50 · 40π/180 · 0.09 per unit area, less the chord error of the flat facets.
    assert!(
        (total / (50.0 * 50.0 * 40f64.to_radians() * 0.09) + 1.0).abs() < 1e-2,
        "{total}"
    );
    for (a, b) in per_area.iter().zip(&gravity) {
        assert!((a - b).norm() < 1e-12 * total.abs(), "{a} vs {b}");
    }
}

/// A dead pressure on a flat plate (normal +z by the generator's node order) gives every node the
/// per-area weight times `p ẑ`: the same nodal forces as `force = [0, 0, p]` per unit area.
#[test]
fn dead_pressure_on_a_flat_plate_is_a_load_per_area_along_the_normal() {
    let plate = |load: &str, name: &str| {
        let scene = format!(
            "name = \"{name}\"\n[time]\nmode = \"quasi_static\"\nn_levels = 1\n[output]\nframes = false\n\
             [mesh]\ngenerator = \"rectangle\"\nlx = 1.0\nly = 0.5\nnx = 4\nny = 2\nelement = \"tri6\"\n\
             rotation_element = \"tri3\"\n[material]\nmodel = \"plate\"\nthickness = 0.01\nyoungs_modulus = 1e7\n\
             poisson_ratio = 0.3\ndensity = 1000.0\nlength_scale = 1e-4\n[[boundary]]\nname = \"rim\"\n\
             region = {{ predicate = \"abs(x) >= 0.5 - 1e-9\" }}\nposition = {{ exact = true }}\n\
             [[load]]\nname = \"p\"\nregion = {{ all = true }}\n{load}\n"
        );
        run(&scene, name).potential().parts.loads.forces.clone()
    };
    let dead = plate("pressure = 300.0\nfollower = false", "plate_dead");
    let per_area = plate(
        "force = [0.0, 0.0, 300.0]\ndistribution = \"per_area\"",
        "plate_per_area",
    );
    let total: f64 = dead.iter().map(|f| f.z).sum();
    assert!((total - 300.0 * 0.5).abs() < 1e-10, "{total}");
    for (a, b) in dead.iter().zip(&per_area) {
        assert!((a - b).norm() < 1e-12, "{a} vs {b}");
    }
}

/// A strip of length 1 hinged at both ends (ν = 0, so it bends as a beam) under a load per area of
/// intensity `q cos(πx)` (the profile): the Navier solution `w(0) = q / (π⁴ D)` with
/// `D = E h³ / 12`, against `5 q / (384 D)` without the profile. The load is small enough for the
/// linear solution; shear adds `O(h²)`.
#[test]
fn a_profiled_load_per_area_bends_a_hinged_strip_into_the_navier_solution() {
    let (e, h, q): (f64, f64, f64) = (1.0e6, 0.01, 1.0e-3);
    let centre = |profile: &str, name: &str| {
        let scene = format!(
            "name = \"{name}\"\n[time]\nmode = \"quasi_static\"\nn_levels = 1\n[output]\nframes = false\n\
             [mesh]\ngenerator = \"rectangle\"\nlx = 1.0\nly = 0.1\nnx = 24\nny = 2\nelement = \"tri6\"\n\
             rotation_element = \"tri3\"\n[material]\nmodel = \"plate\"\nthickness = {h}\nyoungs_modulus = {e}\n\
             poisson_ratio = 0.0\ndensity = 1000.0\nlength_scale = 1e-5\n[[boundary]]\nname = \"hinges\"\n\
             region = {{ predicate = \"abs(x) >= 0.5 - 1e-9\" }}\nposition = {{ exact = true }}\n\
             [[load]]\nname = \"q\"\nregion = {{ all = true }}\nforce = [0.0, 0.0, {q}]\n\
             distribution = \"per_area\"\n{profile}\n"
        );
        let sim = run(&scene, name);
        let x = &sim.potential().parts.state.x;
        let mid: Vec<f64> = x.iter().filter(|p| p.x.abs() < 1e-9).map(|p| p.z).collect();
        assert!(!mid.is_empty());
        mid.iter().sum::<f64>() / mid.len() as f64
    };
    let d = e * h.powi(3) / 12.0;
    let pi4 = std::f64::consts::PI.powi(4);
    let profiled = centre("profile = \"cos(pi*x)\"", "strip_profiled");
    let uniform = centre("", "strip_uniform");
    eprintln!(
        "hinged strip: profiled {profiled:.6e} (Navier {:.6e}), uniform {uniform:.6e} (closed form {:.6e})",
        q / (pi4 * d),
        5.0 * q / (384.0 * d)
    );
    assert!((profiled / (q / (pi4 * d)) - 1.0).abs() < 5e-3, "{profiled}");
    assert!((uniform / (5.0 * q / (384.0 * d)) - 1.0).abs() < 5e-3, "{uniform}");
}

/// A follower pressure on a plate clamped on one edge has free edges: the simulation warns and names
/// the load; with the whole rim held it does not.
#[test]
fn a_follower_pressure_on_free_edges_is_warned_about() {
    let scene = |clamp: &str| {
        format!(
            "name = \"fp\"\n[time]\nmode = \"quasi_static\"\nn_levels = 1\n[mesh]\ngenerator = \"rectangle\"\n\
             lx = 1.0\nly = 0.2\nnx = 4\nny = 2\nelement = \"tri6\"\nrotation_element = \"tri3\"\n[material]\n\
             model = \"plate\"\nthickness = 0.01\nyoungs_modulus = 1e7\npoisson_ratio = 0.3\ndensity = 1000.0\n\
             length_scale = 1e-4\n[[boundary]]\nname = \"clamp\"\nregion = {{ predicate = \"{clamp}\" }}\n\
             position = {{ exact = true }}\n[[load]]\nname = \"inflate\"\nregion = {{ all = true }}\npressure = 20.0\n"
        )
    };
    let advice = |clamp: &str| {
        let spec = SceneSpec::from_str(&scene(clamp), "fp.toml", Path::new("."), &[]).unwrap_or_else(|e| panic!("{e}"));
        Simulation::new(spec).unwrap_or_else(|e| panic!("{e}")).advice().to_vec()
    };
    let one_edge = advice("x <= -0.5 + 1e-9");
    assert!(
        one_edge
            .iter()
            .any(|w| w.contains("load `inflate`") && w.contains("free edges")),
        "{one_edge:?}"
    );
    let rim = advice("abs(x) >= 0.5 - 1e-9 || abs(y) >= 0.1 - 1e-9");
    assert!(!rim.iter().any(|w| w.contains("free edges")), "{rim:?}");
}

/// The critical pressure of the oval mode that the runs of `scenes/validation/cylinder_external_pressure.toml`
/// show: `pressure` is the scene's final pressure (reached at `t = 1`), and the levels' ovalisation
/// `δ = (b.uy − a.ux) / 2` is fitted to `δ = δ_Q + (p δ) / p_cr` by least squares.
fn cylinder_critical_pressure(overrides: &[&str], pressure: f64, name: &str) -> f64 {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/validation/cylinder_external_pressure.toml");
    let overrides: Vec<String> = overrides.iter().map(ToString::to_string).collect();
    let spec = cosserat::scene::load_scene(&scene, &overrides).unwrap_or_else(|e| panic!("{e}"));
    let mut sim = Simulation::new(spec).unwrap_or_else(|e| panic!("{e}"));
    let dir: PathBuf = Path::new(env!("CARGO_TARGET_TMPDIR")).join("surface_loads").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    let summary = sim
        .run(&dir, &mut |_| {}, &cosserat::StopRequest::new())
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(summary.status, cosserat::io::RunStatus::Ok, "{name}: {summary:?}");
    let text = std::fs::read_to_string(dir.join("probes.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let column = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (t, a_ux, b_uy) = (column("t"), column("a.ux"), column("b.uy"));
    let points: Vec<(f64, f64)> = lines
        .map(|l| l.split(',').map(|v| v.parse::<f64>().unwrap()).collect::<Vec<_>>())
        .filter(|row| row[t] > 0.0)
        .map(|row| {
            let delta = 0.5 * (row[b_uy] - row[a_ux]);
            (pressure * row[t] * delta, delta)
        })
        .collect();
    assert!(points.len() >= 4, "{name}: {} levels", points.len());
    let n = points.len() as f64;
    let (mx, my) = (
        points.iter().map(|p| p.0).sum::<f64>() / n,
        points.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    sxx / sxy
}

#[test]
fn a_long_cylinder_buckles_at_the_classical_critical_pressure() {
    // ν = 0: D = E h³ / 12 with E = 1e6, h = 0.01, R = 1.
    let d = 1e6 * 0.01_f64.powi(3) / 12.0;
    // Follower (hydrostatic) pressure: p_cr = 3 D / R³; the scene goes to 0.92 p_cr.
    let follower = cylinder_critical_pressure(&[], 0.23, "cylinder_follower");
    assert!(
        (follower / (3.0 * d) - 1.0).abs() < 0.01,
        "follower: p_cr = {follower}, 3 D / R³ = {}",
        3.0 * d
    );
    // A dead pressure keeps its rest direction: p_cr = 4 D / R³.
    let dead = cylinder_critical_pressure(&["load.0.follower=false", "load.0.pressure=-0.3"], 0.3, "cylinder_dead");
    assert!(
        (dead / (4.0 * d) - 1.0).abs() < 0.01,
        "dead: p_cr = {dead}, 4 D / R³ = {}",
        4.0 * d
    );
    // The coarser mesh is stiffer (the element pair's locking) and converges from above.
    let coarse = cylinder_critical_pressure(&["mesh.n_around=64"], 0.23, "cylinder_follower_64");
    assert!(coarse > follower, "64 around: {coarse}, 128 around: {follower}");
}
