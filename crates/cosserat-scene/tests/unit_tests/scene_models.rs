//! The comparison models in scene files: `model = "kirchhoff_love"` (Tri3, no rotations, a hyperelastic
//! law) and `model = "micropolar_volume"` (a flat grid extruded into a Tet4 slab), the `cg` solver name,
//! and the rejection of what a model cannot express, with file, line and field in the message.

use cosserat_scene::spec::{HyperelasticLaw, KlRestVolume, KlSettings, ModelKind, SceneSpec};
use cosserat_solver::{DomainSplit, LinearSolverKind};
use cosserat_volume::grid::PlanarGrid;
use nalgebra::Vector3;
use std::path::Path;

/// A valid Kirchhoff–Love scene: a 10 × 2 strip clamped by two columns of vertices.
const KL: &str = r#"name = "kl"

[time]
dt = 0.01
end = 0.1

[mesh]
generator = "rectangle"
lx = 0.1
ly = 0.02
nx = 10
ny = 2

[material]
model = "kirchhoff_love"
law = "neo_hookean"
thickness = 1e-3
youngs_modulus = 1e6
poisson_ratio = 0.3
density = 1000.0

[[boundary]]
name = "clamp"
region = { predicate = "x <= -0.04 + 1e-9" }
position = { exact = true }

[[probe]]
name = "tip"
point = [0.05, 0.0, 0.0]
"#;

/// A valid micropolar volume scene: a 4 × 4 grid extruded to a 1 cm slab, pinned at its centre.
const VOLUME: &str = r#"name = "slab"

[time]
dt = 0.01
end = 0.05

[solver]
linear_solver = "cg"

[mesh]
generator = "rectangle"
lx = 1.0
ly = 1.0
nx = 4
ny = 4
element = "tri3"

[material]
model = "micropolar_volume"
thickness = 0.01
youngs_modulus = 0.5e6
poisson_ratio = 0.3
density = 3000.0
length_scale = 1.0

[[boundary]]
name = "pin"
region = { nearest = [0.0, 0.0, 0.0] }
position = { stiffness = 1e6 }

[[rest_field]]
curvature = [{ row = 2, col = 1, value = "-t * abs(x)" }]
"#;

fn load(text: &str, replace: &[(&str, &str)]) -> Result<SceneSpec, String> {
    let mut text = text.to_string();
    for (from, to) in replace {
        assert!(text.contains(from), "the scene has no `{from}`");
        text = text.replacen(from, to, 1);
    }
    SceneSpec::from_str(&text, "scene.toml", Path::new("."), &[]).map_err(|e| e.to_string())
}

fn message(text: &str, replace: &[(&str, &str)]) -> String {
    match load(text, replace) {
        Ok(_) => panic!("the scene was accepted: {replace:?}"),
        Err(e) => e,
    }
}

#[test]
fn a_kirchhoff_love_scene_is_a_tri3_shell_with_its_law() {
    let spec = load(KL, &[]).unwrap_or_else(|e| panic!("{e}"));
    let shell = &spec.shells[0];
    assert_eq!(
        shell.model,
        ModelKind::KirchhoffLove(KlSettings {
            law: HyperelasticLaw::NeoHookean,
            rest_volume: KlRestVolume::Exact,
        })
    );
    // Tri3 by default for this model: 11 × 3 vertices, no Tri6 nodes.
    assert_eq!(shell.pair, cosserat_assembly::ElementPair::Tri3Tri3);
    assert_eq!(shell.mesh.corners.n_nodes(), 33);
    // Two clamped columns of 3 vertices (x = −0.05 and −0.04).
    assert_eq!(spec.boundaries[0].selection.disp_nodes.len(), 6);
    let stvk = load(
        KL,
        &[("law = \"neo_hookean\"", "law = \"stvk\"\nrest_volume = \"mid_surface\"")],
    )
    .unwrap();
    assert_eq!(
        stvk.shells[0].model,
        ModelKind::KirchhoffLove(KlSettings {
            law: HyperelasticLaw::StVenantKirchhoff,
            rest_volume: KlRestVolume::MidSurface,
        })
    );
}

#[test]
fn a_kirchhoff_love_scene_rejects_tri6_and_rotations() {
    assert_eq!(
        message(KL, &[("ny = 2\n", "ny = 2\nelement = \"tri6\"\n")]),
        "scene.toml:13: mesh.element: the Kirchhoff–Love (`kirchhoff_love`) model is built on the Tri3 mesh \
         (`element = \"tri3\"`, the default for it); Tri6 elements are not available"
    );
    assert_eq!(
        message(
            KL,
            &[(
                "position = { exact = true }",
                "position = { exact = true }\nrotation = { stiffness = 1e4 }"
            )]
        ),
        "scene.toml:26: boundary.0.rotation: the Kirchhoff–Love model has no rotation unknowns: clamp an edge by \
         fixing the positions of two rows of vertices"
    );
    assert!(
        message(
            KL,
            &[(
                "position = { exact = true }",
                "position = { exact = true }\nangular_velocity = { stiffness = 1.0 }"
            )]
        )
        .starts_with("scene.toml:26: boundary.0.angular_velocity: the Kirchhoff–Love model has no rotation unknowns")
    );
    let torque = "[[load]]\nregion = { predicate = \"x >= 0.05 - 1e-9\" }\ntorque = [0.0, 1.0, 0.0]\n\n[[probe]]";
    assert_eq!(
        message(KL, &[("[[probe]]", torque)]),
        "scene.toml:29: load.0.torque: the Kirchhoff–Love model has no rotation unknowns to carry a torque"
    );
    // The key that prescribes the field is named, not the table's header.
    let field = "[[rest_field]]\ncurvature = [{ row = 2, col = 1, value = 1.0 }]\n\n[[probe]]";
    assert_eq!(
        message(KL, &[("[[probe]]", field)]),
        "scene.toml:28: rest_field.0.curvature: the Kirchhoff–Love model takes its rest state from the rest mesh; \
         a prescribed rest curvature is not available"
    );
    let growth = "[[rest_field]]\ntiming = \"end_of_step\"\ngrowth = \"0.1 * t\"\n\n[[probe]]";
    assert_eq!(
        message(KL, &[("[[probe]]", growth)]),
        "scene.toml:29: rest_field.0.growth: the Kirchhoff–Love model takes its rest state from the rest mesh; a \
         prescribed rest-metric growth is not available"
    );
    assert_eq!(
        message(
            KL,
            &[(
                "point = [0.05, 0.0, 0.0]",
                "point = [0.05, 0.0, 0.0]\nquantity = \"director\""
            )]
        ),
        "scene.toml:30: probe.0.quantity: the Kirchhoff–Love model has no directors (no rotation unknowns)"
    );
}

#[test]
fn material_keys_belong_to_their_models() {
    assert_eq!(
        message(KL, &[("law = \"neo_hookean\"\n", "")]),
        "scene.toml:14: material.law: required by the Kirchhoff–Love model: \"stvk\" or \"neo_hookean\""
    );
    assert_eq!(
        message(KL, &[("density = 1000.0", "density = 1000.0\nlength_scale = 1e-3")]),
        "scene.toml:21: material.length_scale: does not apply to the Kirchhoff–Love (`kirchhoff_love`) model"
    );
    assert_eq!(
        message(VOLUME, &[("length_scale = 1.0", "length_scale = 1.0\nlaw = \"stvk\"")]),
        "scene.toml:25: material.law: only the Kirchhoff–Love model (`model = \"kirchhoff_love\"`) takes a \
         hyperelastic law"
    );
    assert_eq!(
        message(VOLUME, &[("length_scale = 1.0\n", "")]),
        "scene.toml:18: material.length_scale: required by the Cosserat models"
    );
    assert_eq!(
        message(VOLUME, &[("length_scale = 1.0", "length_scale = 1.0\nlayers = 0")]),
        "scene.toml:25: material.layers: must be at least 1"
    );
}

#[test]
fn reusing_the_factorisation_is_off_by_default_and_zero_turns_it_off() {
    assert_eq!(load(VOLUME, &[]).unwrap().solver.reuse_factorisation, None);
    for (value, expected) in [("0.1", Some(0.1)), ("0", None), ("0.0", None)] {
        let spec = load(
            VOLUME,
            &[(
                "linear_solver = \"cg\"",
                &format!("linear_solver = \"cg\"\nreuse_factorisation = {value}"),
            )],
        )
        .unwrap();
        assert_eq!(spec.solver.reuse_factorisation, expected, "{value}");
    }
}

#[test]
fn the_domain_split_is_named_in_the_solver_section() {
    assert_eq!(load(VOLUME, &[]).unwrap().solver.domain_split, DomainSplit::Auto);
    for (name, split) in [
        ("off", DomainSplit::Off),
        ("always", DomainSplit::Always),
        ("auto", DomainSplit::Auto),
    ] {
        let spec = load(
            VOLUME,
            &[(
                "linear_solver = \"cg\"",
                &format!("linear_solver = \"cg\"\ndomain_split = \"{name}\""),
            )],
        )
        .unwrap();
        assert_eq!(spec.solver.domain_split, split, "{name}");
    }
    let bad = message(
        VOLUME,
        &[(
            "linear_solver = \"cg\"",
            "linear_solver = \"cg\"\ndomain_split = \"two\"",
        )],
    );
    assert!(
        bad.starts_with(
            "scene.toml:9: solver.domain_split: unknown variant `two`, expected one of `auto`, `off`, `always`"
        ),
        "{bad}"
    );
}

#[test]
fn a_volume_scene_needs_a_flat_grid_and_has_no_growth() {
    let spec = load(VOLUME, &[]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(spec.shells[0].model, ModelKind::MicropolarVolume { layers: 1 });
    assert_eq!(spec.solver.linear_solver, LinearSolverKind::Cg);
    let two = load(VOLUME, &[("length_scale = 1.0", "length_scale = 1.0\nlayers = 2")]).unwrap();
    assert_eq!(two.shells[0].model, ModelKind::MicropolarVolume { layers: 2 });
    let disk = message(
        VOLUME,
        &[(
            "generator = \"rectangle\"\nlx = 1.0\nly = 1.0\nnx = 4\nny = 4",
            "generator = \"disk\"\nradius = 0.5\nn_radial = 2\nn_angular = 8",
        )],
    );
    assert!(
        disk.starts_with("scene.toml:10: mesh: the micropolar volume model extrudes a flat rectangular grid"),
        "{disk}"
    );
    assert_eq!(
        message(
            VOLUME,
            &[("value = \"-t * abs(x)\" }]", "value = \"-t * abs(x)\" }]\ngrowth = 0.1")]
        ),
        "scene.toml:33: rest_field.0.growth: the micropolar volume model has no rest-metric growth (only rest \
         curvature)"
    );
}

#[test]
fn planar_grids_are_recognised_with_their_vertex_positions() {
    let mut points = Vec::new();
    // A 3 × 2 cell grid listed column-major, shifted and at height 0.7.
    for j in 0..3 {
        for i in 0..4 {
            points.push(Vector3::new(1.0 + 0.5 * i as f64, -2.0 + 0.25 * j as f64, 0.7));
        }
    }
    let grid = PlanarGrid::detect(&points).unwrap();
    assert_eq!(grid.cells(), [3, 2]);
    assert_eq!(grid.size(), [1.5, 0.5]);
    assert_eq!(grid.center(), Vector3::new(1.75, -1.75, 0.7));
    assert_eq!(grid.vertex_ij[5], (1, 1));
    let mut bent = points.clone();
    bent[3].z += 0.1;
    assert!(PlanarGrid::detect(&bent).unwrap_err().contains("one plane"));
    let mut missing = points.clone();
    missing.pop();
    assert!(PlanarGrid::detect(&missing).unwrap_err().contains("full grid"));
    let mut uneven = points;
    for p in uneven.iter_mut().filter(|p| p.x > 2.2) {
        p.x += 0.1;
    }
    assert!(PlanarGrid::detect(&uneven).unwrap_err().contains("not uniform"));
}
