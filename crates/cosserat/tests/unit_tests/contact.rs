//! Contact through the facade, against physics: a plate at rest on a floor carries its weight, Coulomb
//! friction on an incline (stick below the friction angle, the Coulomb acceleration above it), and no
//! intersection nor penetration below the contact thickness at any step for a plate thrown at a thin
//! plate and a strip rolled onto itself.

use cosserat::Simulation;
use cosserat::scene::spec::SceneSpec;
use nalgebra::Vector3;
use std::path::Path;

const G: f64 = 9.81;
/// Contact thickness of every body \[m\]: pairs keep δ = 1 mm apart.
const TH: f64 = 5e-4;

fn load(text: &str) -> Simulation {
    let spec = SceneSpec::from_str(text, "contact_test.toml", Path::new("."), &[]).unwrap_or_else(|e| panic!("{e}"));
    Simulation::new(spec).unwrap_or_else(|e| panic!("{e}"))
}

/// Total mass of the shells \[kg\] from the lumped masses (ρ h A exactly).
fn mass(sim: &Simulation) -> f64 {
    sim.system().potential.parts.inertia.as_ref().unwrap().masses.iter().sum()
}

/// Mean velocity of the shells' displacement nodes, mass-weighted \[m/s\].
fn mean_velocity(sim: &Simulation) -> Vector3<f64> {
    let parts = &sim.system().potential.parts;
    let masses = &parts.inertia.as_ref().unwrap().masses;
    let m: f64 = masses.iter().sum();
    parts.state.v.iter().zip(masses).map(|(v, mi)| v * *mi).sum::<Vector3<f64>>() / m
}

/// A 0.1 m square plate (Tri3, 4 × 4 quads, E = 10 MPa, h = 1 mm, ρ = 1000 kg/m³) whose rest pose is
/// rotated by `degrees` about y and moved by `translate`, with contact: κ, d̂ = 1 mm, thickness 0.5 mm,
/// friction `mu` with the floor, ε_v = 1 mm/s, and a floor obstacle given by `floor` (TOML).
fn plate_scene(degrees: f64, translate: Vector3<f64>, floor: &str, mu: f64, end: f64) -> String {
    format!(
        r#"
name = "plate_on_floor"
gravity = [0.0, 0.0, -9.81]
[time]
dt = 0.01
end = {end}
adaptive = true
output_fps = 100.0
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
transform = {{ rotate = [{{ axis = "y", degrees = {degrees} }}], translate = [{}, {}, {}] }}
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
thickness = {TH}
stick_velocity = 1e-3
[[contact.obstacle]]
name = "floor"
{floor}
[[contact.friction]]
between = ["shell", "floor"]
mu = {mu}
"#,
        translate.x, translate.y, translate.z
    )
}

#[test]
fn a_plate_dropped_on_the_floor_comes_to_rest_carrying_its_weight() {
    // The floor's top face (z = 0) is split along the diagonal x = y; the plate lies 0.25 m off it,
    // inside one triangle, 2 mm above the contact distance.
    let floor = r#"box = { center = [0.0, 0.0, -0.05], size = [1.0, 1.0, 0.1] }"#;
    let drop = 2.0 * TH + 2e-3;
    let mut sim = load(&plate_scene(0.0, Vector3::new(0.25, -0.25, drop), floor, 0.0, 1.0));
    let mut stepper = sim.time_stepper().unwrap();
    for _ in 0..100 {
        sim.step(&mut stepper).unwrap();
    }
    let v = mean_velocity(&sim);
    assert!(v.norm() < 1e-5, "not at rest: mean velocity {v:?}");
    let weight = mass(&sim) * G;
    let expected = 1000.0 * 1e-3 * 0.1 * 0.1 * G;
    assert!(
        (weight - expected).abs() < 1e-12 * expected,
        "lumped mass {weight} vs ρhA g {expected}"
    );
    let forces = sim.contact_forces().unwrap().unwrap();
    let total: Vector3<f64> = forces.iter().sum();
    assert!(
        (total.z - weight).abs() < 0.01 * weight,
        "contact force {total:?} N against the weight {weight} N"
    );
    assert!(total.xy().norm() < 0.01 * weight, "lateral contact force {total:?}");
    let gap = sim.contact_monitor().unwrap().min_gap();
    assert!(
        gap > 0.0 && gap < 1e-3,
        "the plate rests inside the barrier: smallest gap {gap}"
    );
}

/// A plate on a floor inclined by `degrees` about y, sliding or sticking with friction `mu`: the
/// velocity along the slope after each of `n` steps of 10 ms.
fn incline(degrees: f64, mu: f64, n: usize) -> Vec<f64> {
    let theta = degrees.to_radians();
    let rot = nalgebra::Rotation3::from_axis_angle(&Vector3::y_axis(), theta);
    let normal = rot * Vector3::z();
    let downhill = rot * Vector3::x();
    assert!(downhill.z < 0.0);
    // Floor: a 2 m square rotated like the plate; its diagonal runs along local y = x, the plate sits
    // at local (−0.3, −0.5), away from it for the whole slide.
    let floor = format!(
        r#"mesh = {{ generator = "rectangle", lx = 2.0, ly = 2.0, nx = 1, ny = 1, transform = {{ rotate = [{{ axis = "y", degrees = {degrees} }}] }} }}"#
    );
    let at = rot * Vector3::new(-0.3, -0.5, 0.0) + normal * (2.0 * TH + 2e-4);
    let mut sim = load(&plate_scene(degrees, at, &floor, mu, 10.0));
    let mut stepper = sim.time_stepper().unwrap();
    (0..n)
        .map(|_| {
            sim.step(&mut stepper).unwrap();
            mean_velocity(&sim).dot(&downhill)
        })
        .collect()
}

#[test]
fn a_plate_on_an_incline_below_the_friction_angle_sticks() {
    // tan 20° = 0.36 < μ = 0.5: static friction holds the plate. The smoothed friction lets it creep
    // below the stick–slide velocity ε_v = 1 mm/s: in steady creep μ N f₁(y) = m g sin θ with
    // N = m g cos θ and f₁(y) = 2y/ε − y²/ε², ε = ε_v Δt, so the slip per step is
    // y = ε (1 − √(1 − tan θ/μ)) and the creep velocity ε_v (1 − √(1 − tan θ/μ)).
    let (degrees, mu, eps_v) = (20.0_f64, 0.5, 1e-3);
    let v = incline(degrees, mu, 40);
    let fastest = v.iter().skip(5).fold(0.0_f64, |a, b| a.max(b.abs()));
    assert!(fastest < eps_v, "sliding at {fastest} m/s");
    let creep = eps_v * (1.0 - (1.0 - degrees.to_radians().tan() / mu).sqrt());
    assert!(
        (v[39] - creep).abs() < 0.01 * creep,
        "creep {} m/s against the smoothed-friction prediction {creep} m/s",
        v[39]
    );
}

#[test]
fn a_plate_on_an_incline_above_the_friction_angle_slides_with_the_coulomb_acceleration() {
    // tan 30° = 0.58 > μ = 0.3: a = g (sin θ − μ cos θ).
    let (degrees, mu) = (30.0_f64, 0.3);
    let theta = degrees.to_radians();
    let expected = G * (theta.sin() - mu * theta.cos());
    let v = incline(degrees, mu, 40);
    // After the plate has settled into the barrier (the first steps), fit the acceleration over the
    // last 20 steps.
    let (a, b) = (&v[19], &v[39]);
    let measured = (b - a) / (20.0 * 0.01);
    assert!(
        (measured - expected).abs() < 0.01 * expected,
        "acceleration {measured} m/s² against g (sin θ − μ cos θ) = {expected} m/s²"
    );
    assert!(v[39] > 20.0 * 0.01 * expected, "the plate slides");
}

/// Steps `n` times; after every step no pair of contact triangles intersects (exact test over the whole
/// contact mesh) and no pair is closer than its thicknesses (the smallest gap over all pairs in reach).
/// `observe` sees the simulation after every step.
fn step_without_intersections(sim: &mut Simulation, n: usize, observe: &mut dyn FnMut(&Simulation)) {
    let mut stepper = sim.time_stepper().unwrap();
    for k in 0..n {
        sim.step(&mut stepper).unwrap_or_else(|e| panic!("step {k}: {e}"));
        observe(sim);
        let crossing = sim.contact_intersections().unwrap();
        assert!(crossing.is_empty(), "step {k}: intersecting triangles {crossing:?}");
        let gap = sim.contact_coverage().unwrap().min_gap;
        assert!(gap > 0.0, "step {k}: smallest gap {gap} m");
        // The run statistics see every pair within the barrier (d̂ = 1 mm).
        let recorded = sim.contact_monitor().unwrap().min_gap();
        assert!(recorded > 0.0, "step {k}: recorded smallest gap {recorded} m");
        assert!(
            gap >= 1e-3 || recorded <= gap,
            "step {k}: recorded {recorded} m, present {gap} m"
        );
    }
}

#[test]
fn a_plate_thrown_at_a_thin_plate_never_passes_through_it() {
    // A 4 cm plate, turned 30° about z so its edges cross the target's, starts 2 cm above a 0.1 mm
    // thin plate pinned at its corners and flies down at 5 m/s: it reaches the target within the first
    // 5 ms step, so only CCD keeps it from passing through.
    let text = format!(
        r#"
name = "throw"
[time]
dt = 0.005
end = 1.0
adaptive = true
[[shell]]
name = "target"
[shell.mesh]
generator = "rectangle"
lx = 0.1
ly = 0.1
nx = 6
ny = 6
element = "tri3"
rotation_element = "tri3"
[shell.material]
model = "plate"
thickness = 1e-4
youngs_modulus = 1e6
poisson_ratio = 0.3
density = 1000.0
length_scale = 1e-4
[[shell]]
name = "projectile"
[shell.mesh]
generator = "rectangle"
lx = 0.04
ly = 0.04
nx = 2
ny = 2
element = "tri3"
rotation_element = "tri3"
transform = {{ rotate = [{{ axis = "z", degrees = 30.0 }}], translate = [0.005, -0.003, 0.02] }}
[shell.material]
model = "plate"
thickness = 1e-3
youngs_modulus = 1e7
poisson_ratio = 0.3
density = 1000.0
length_scale = 1e-3
[[boundary]]
shell = "target"
region = {{ predicate = "abs(x) > 0.049 && abs(y) > 0.049" }}
position = {{ stiffness = 1e3 }}
[contact]
stiffness = 1.0
barrier_width = 1e-3
thickness = {TH}
"#
    );
    let mut sim = load(&text);
    let projectile = sim.system().shells[1].disp_nodes.clone();
    for i in projectile.clone() {
        sim.system_mut().potential.parts.state.v[i] = Vector3::new(0.0, 0.0, -5.0);
    }
    let mut lowest = f64::INFINITY;
    step_without_intersections(&mut sim, 30, &mut |sim| {
        let x = &sim.system().potential.parts.state.x;
        lowest = projectile.clone().map(|i| x[i].z).fold(lowest, f64::min);
    });
    assert!(
        sim.contact_monitor().unwrap().max_active_pairs() > 0,
        "the plates never met"
    );
    // The projectile pushed the target down through its rest plane, then bounced off it.
    assert!(lowest < -0.01, "the projectile got no lower than z = {lowest} m");
    let v = sim.system().potential.parts.state.v[projectile.start];
    assert!(v.z > 0.0, "the projectile did not bounce back: v = {v:?}");
}

#[test]
fn a_strip_rolled_onto_itself_never_intersects() {
    // A 0.12 m strip (Tri6, contact through the 4-split flat triangles) clamped at x = −0.06 rolls up
    // under a rest curvature rising from 80 rad/m at the clamp to 300 rad/m at the free end (ramped in
    // over 0.5 s): 22.8 rad ≈ 3.6 turns of rest curvature, the free end innermost, layers 1 mm apart.
    let text = format!(
        r#"
name = "roll"
[time]
dt = 0.01
end = 10.0
adaptive = true
[mesh]
generator = "rectangle"
lx = 0.12
ly = 0.01
nx = 12
ny = 1
element = "tri6"
rotation_element = "tri3"
[material]
model = "plate"
thickness = 5e-4
youngs_modulus = 1e6
poisson_ratio = 0.3
density = 1000.0
length_scale = 1e-3
[[boundary]]
region = {{ predicate = "x <= -0.06 + 1e-9" }}
position = {{ stiffness = 1e4 }}
rotation = {{ stiffness = 10.0, directors = [3] }}
[[rest_field]]
curvature = [{{ row = 2, col = 1, value = "-(80 + 220*(x + 0.06)/0.12)*ramp(t, 0, 0.5)" }}]
[contact]
stiffness = 1.0
barrier_width = 1e-3
thickness = {TH}
project_pd = false
"#
    );
    let mut sim = load(&text);
    step_without_intersections(&mut sim, 70, &mut |_| {});
    assert!(
        sim.contact_monitor().unwrap().max_active_pairs() > 100,
        "the strip barely touched itself"
    );
}

/// A 0.1 m Tri3 plate at height `z` without gravity, with `contact` appended (TOML).
fn plain_plate(z: f64, end: f64, contact: &str) -> String {
    format!(
        r#"
name = "plain"
[time]
dt = 0.01
end = {end}
adaptive = false
output_fps = 100.0
[mesh]
generator = "rectangle"
lx = 0.1
ly = 0.1
nx = 2
ny = 2
element = "tri3"
rotation_element = "tri3"
transform = {{ translate = [0.0, 0.0, {z}] }}
[material]
model = "plate"
thickness = 1e-3
youngs_modulus = 1e7
poisson_ratio = 0.3
density = 1000.0
length_scale = 1e-3
{contact}
"#
    )
}

fn run_dir(name: &str) -> std::path::PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cosserat_contact_tests").join(name);
    let _ = std::fs::remove_dir_all(&d);
    d
}

#[test]
fn a_scene_without_contact_builds_and_reports_no_contact() {
    let mut sim = load(&plain_plate(0.0, 0.02, ""));
    assert!(sim.contact_term_mut().is_none());
    assert!(sim.system().potential.parts.extra.is_empty());
    assert!(sim.contact_forces().unwrap().is_none());
    let summary = sim
        .run(&run_dir("no_contact"), &mut |_| {}, &cosserat::StopRequest::new())
        .unwrap();
    assert!(!summary.extra.contains_key("contact"));
    assert!(!summary.active_terms.iter().any(|t| t.starts_with("contact")));
}

#[test]
fn bodies_that_start_within_their_thicknesses_are_rejected() {
    // The plate 0.8 mm above a floor whose top is at z = 0: closer than the 1 mm thickness sum.
    let floor = format!(
        "[contact]\nstiffness = 1.0\nbarrier_width = 1e-3\nthickness = {TH}\n[[contact.obstacle]]\nname = \"floor\"\nbox = {{ center = [0.0, 0.0, -0.05], size = [1.0, 1.0, 0.1] }}"
    );
    let spec = SceneSpec::from_str(&plain_plate(8e-4, 0.02, &floor), "t.toml", Path::new("."), &[]).unwrap();
    match Simulation::new(spec) {
        Err(cosserat::SimulationError::Setup(reason)) => {
            assert!(reason.contains("closer than their thicknesses"), "{reason}")
        }
        Err(e) => panic!("unexpected error {e}"),
        Ok(_) => panic!("an initially penetrating plate was accepted"),
    }
    // 1.2 mm above it is fine.
    let spec = SceneSpec::from_str(&plain_plate(1.2e-3, 0.02, &floor), "t.toml", Path::new("."), &[]).unwrap();
    assert!(Simulation::new(spec).is_ok());
}

#[test]
fn a_kinematic_obstacle_follows_its_script_and_is_written_to_the_frames() {
    // A box sliding past the plate at 1 m/s (never near it) and turning about z.
    let contact = format!(
        r#"[contact]
stiffness = 1.0
barrier_width = 1e-3
thickness = {TH}
[[contact.obstacle]]
name = "slider"
box = {{ center = [0.0, 0.5, 0.0], size = [0.1, 0.1, 0.1] }}
motion = {{ translate = ["t", 0.0, 0.0], rotate = {{ axis = "z", center = [0.0, 0.5, 0.0], angle = "2*t" }} }}"#
    );
    let mut sim = load(&plain_plate(0.0, 0.1, &contact));
    let dir = run_dir("kinematic");
    let summary = sim.run(&dir, &mut |_| {}, &cosserat::StopRequest::new()).unwrap();
    assert_eq!(summary.extra["max_obstacle_lag"].as_f64(), Some(0.0));
    let frame = cosserat::scene::output::read_vtu(&dir.join("frames").join("frame_00010.vtu")).unwrap();
    assert!((frame.time - 0.1).abs() < 1e-12);
    let marker = frame.point_array("obstacle").unwrap();
    let plate_points = (0..frame.points.len()).filter(|&i| marker.tuple(i)[0] == 0.0).count();
    assert_eq!(plate_points, 9);
    assert_eq!(frame.triangles.len(), 8 + 12);
    // The box at t = 0.1 s: rest corners turned by 0.2 rad about (0, 0.5) and moved 0.1 m along x.
    let (c, s) = (0.2_f64.cos(), 0.2_f64.sin());
    let boxed: Vec<[f64; 3]> = (0..frame.points.len())
        .filter(|&i| marker.tuple(i)[0] == 1.0)
        .map(|i| frame.points[i])
        .collect();
    assert_eq!(boxed.len(), 8);
    for k in 0..8 {
        let sign = |bit: usize| if k & (1 << bit) != 0 { 0.05 } else { -0.05 };
        let (x, y) = (sign(0), sign(1));
        let expected = [c * x - s * y + 0.1, s * x + c * y + 0.5, sign(2)];
        let p = boxed[k];
        assert!(
            (0..3).all(|a| (p[a] - expected[a]).abs() < 1e-12),
            "{p:?} vs {expected:?}"
        );
    }
}
