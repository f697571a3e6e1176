mod advice;
mod contact;
mod intersections;
mod kl_model;
mod memory;
mod rest_fields;
mod run;
mod run_description;
mod script_targets;
mod surface_loads;
mod volume_model;

/// A 0.1 m × 0.01 m plate strip on 6 × 2 quads (Tri6/Tri3), dynamic with dt = 0.01 until t = 0.05, without
/// boundaries or loads: tests append their own tables.
const STRIP_HEAD: &str = r#"
name = "strip"
[time]
mode = "dynamic"
dt = 0.01
end = 0.05
adaptive = false
[mesh]
generator = "rectangle"
lx = 0.1
ly = 0.01
nx = 6
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
"#;

/// The strip of [`STRIP_HEAD`] with the tables `rest`.
fn strip_scene(rest: &str) -> String {
    format!("{STRIP_HEAD}{rest}")
}
