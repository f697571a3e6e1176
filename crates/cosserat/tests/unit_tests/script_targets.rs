//! Script targets set by a program between steps (`Scripts::set_motion`, `Scripts::set_load_scale`).

use cosserat::Simulation;
use cosserat::scene::spec::SceneSpec;
use cosserat::scripts::{RigidMotion, ScriptTargetError};
use nalgebra::{Matrix3, Vector3};
use std::path::Path;

/// A clamped strip turned at its right end by `angle` about x, with a tip load scaled by `scale`.
fn strip(angle: &str, scale: &str) -> Simulation {
    let text = super::strip_scene(&format!(
        r#"
[[boundary]]
name = "left"
region = {{ predicate = "x <= -0.05 + 1e-9" }}
position = {{ stiffness = 1e6 }}
rotation = {{ stiffness = 1e2, directors = [3] }}
[[boundary]]
name = "right"
region = {{ predicate = "x >= 0.05 - 1e-9" }}
position = {{ stiffness = 1e6 }}
rotation = {{ stiffness = 1e2, directors = [3] }}
motion = {{ rotate = {{ axis = "x", center = [0.0, 0.0, 0.0], angle = "{angle}" }} }}
[[load]]
name = "push"
region = {{ predicate = "abs(x) <= 0.01" }}
force = [0.0, 0.0, 1e-3]
scale = "{scale}"
"#
    ));
    let spec = SceneSpec::from_str(&text, "strip.toml", Path::new("."), &[]).unwrap();
    Simulation::with_memory_limit(spec, None).unwrap()
}

fn steps(sim: &mut Simulation, n: usize, mut before: impl FnMut(&mut Simulation, f64)) -> Vec<Vector3<f64>> {
    let mut stepper = sim.time_stepper().unwrap();
    for _ in 0..n {
        let t = stepper.time();
        before(sim, t);
        sim.step(&mut stepper).unwrap();
    }
    sim.potential().parts.state.x.clone()
}

#[test]
fn a_set_motion_and_scale_replace_the_scripted_ones_exactly() {
    let mut scripted = strip("3*t", "2*t");
    let mut driven = strip("0", "0");
    let expected = steps(&mut scripted, 3, |_, _| {});
    let got = steps(&mut driven, 3, |sim, t| {
        // Boundary targets apply at the end of the step (the default), loads at its start.
        let motion = RigidMotion::about_axis(Vector3::x(), 3.0 * (t + 0.01), Vector3::zeros()).unwrap();
        sim.scripts_mut().set_motion("right", Some(motion)).unwrap();
        sim.scripts_mut().set_load_scale("push", Some(2.0 * t)).unwrap();
    });
    assert_eq!(got, expected);
    // Back to the scene's (zero) motion and scale: the result differs.
    let mut reset = strip("0", "0");
    let other = steps(&mut reset, 3, |sim, _| {
        sim.scripts_mut().set_motion("right", None).unwrap();
        sim.scripts_mut().set_load_scale("push", None).unwrap();
    });
    assert_ne!(other, expected);
}

#[test]
fn unknown_names_and_non_rotations_are_rejected() {
    let mut sim = strip("0", "1");
    let scripts = sim.scripts_mut();
    assert_eq!(scripts.boundary_names().collect::<Vec<_>>(), ["left", "right"]);
    match scripts.set_motion("middle", None) {
        Err(ScriptTargetError::UnknownBoundary { known, .. }) => assert_eq!(known, "left, right"),
        other => panic!("expected an unknown boundary, got {other:?}"),
    }
    assert!(matches!(
        scripts.set_load_scale("left", Some(1.0)),
        Err(ScriptTargetError::UnknownLoad { .. })
    ));
    assert!(matches!(
        scripts.set_load_scale("push", Some(f64::INFINITY)),
        Err(ScriptTargetError::InvalidValue(_))
    ));
    let stretched = RigidMotion {
        rotation: Matrix3::identity() * 2.0,
        center: Vector3::zeros(),
        translation: Vector3::zeros(),
    };
    assert!(matches!(
        scripts.set_motion("right", Some(stretched)),
        Err(ScriptTargetError::InvalidValue(_))
    ));
    let mirror = RigidMotion {
        rotation: Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, -1.0)),
        ..stretched
    };
    assert!(scripts.set_motion("right", Some(mirror)).is_err());
    assert!(RigidMotion::about_axis(Vector3::zeros(), 1.0, Vector3::zeros()).is_err());
}
