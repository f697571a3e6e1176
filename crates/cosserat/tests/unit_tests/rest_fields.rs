//! Rest-field tables of one shell act as one table.

use cosserat::Simulation;
use cosserat::scene::spec::SceneSpec;
use nalgebra::Vector3;
use std::path::Path;

/// The free strip's positions after three steps, its rest state changed by the `rest_fields` tables.
fn positions_after_steps(rest_fields: &str) -> Vec<Vector3<f64>> {
    let text = super::strip_scene(rest_fields);
    let spec = SceneSpec::from_str(&text, "strip.toml", Path::new("."), &[]).unwrap();
    let mut sim = Simulation::with_memory_limit(spec, None).unwrap();
    let mut stepper = sim.time_stepper().unwrap();
    for _ in 0..3 {
        sim.step(&mut stepper).unwrap();
    }
    sim.potential().parts.state.x.clone()
}

#[test]
fn growth_and_framed_curvature_in_two_tables_act_as_one_table() {
    const GROWTH: &str = "growth = \"0.2*t*x\"";
    const CURVATURE: &str =
        "curvature = [{ row = 2, col = 1, value = \"30*t\" }]\nframe = [{ axis = \"z\", degrees = 30 }]";
    let one = positions_after_steps(&format!("[[rest_field]]\n{GROWTH}\n{CURVATURE}"));
    for two in [
        format!("[[rest_field]]\n{GROWTH}\n[[rest_field]]\n{CURVATURE}"),
        format!("[[rest_field]]\n{CURVATURE}\n[[rest_field]]\n{GROWTH}"),
    ] {
        assert_eq!(positions_after_steps(&two), one, "{two}");
    }
    // The frame matters: without it the strip ends elsewhere.
    let unframed = positions_after_steps(&format!(
        "[[rest_field]]\n{GROWTH}\ncurvature = [{{ row = 2, col = 1, value = \"30*t\" }}]"
    ));
    assert_ne!(unframed, one);
}
