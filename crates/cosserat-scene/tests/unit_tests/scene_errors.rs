//! Bad input is rejected with a message that names the file, the line, the field and the reason.

use cosserat_scene::error::SceneError;
use cosserat_scene::spec::SceneSpec;
use std::path::{Path, PathBuf};

const MESH: &str = r#"generator = "rectangle"
lx = 0.1
ly = 0.01
nx = 10
ny = 2
element = "tri6""#;

/// A valid scene; `{mesh}` is replaced by the body of the `[mesh]` table (6 lines).
const BASE: &str = r#"name = "base"

[time]
dt = 0.01
end = 1.0

[mesh]
{mesh}

[material]
model = "plate"
thickness = 1e-3
youngs_modulus = 1e6
poisson_ratio = 0.3
density = 1000.0
length_scale = 1e-6

[[boundary]]
name = "clamp"
region = { predicate = "x <= -0.05 + 1e-9" }
position = { stiffness = 1e6 }
rotation = { stiffness = 1e4, directors = [3] }

[[load]]
region = { predicate = "x >= 0.05 - 1e-9" }
force = [0.0, 0.0, 1.0]
scale = "ramp(t, 0, 1)"

[[probe]]
name = "tip"
point = [0.05, 0.0, 0.0]
"#;

fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data")
}

fn scene(replace: &[(&str, &str)]) -> String {
    let mut text = BASE.replace("{mesh}", MESH);
    for (from, to) in replace {
        assert!(text.contains(from), "the base scene has no `{from}`");
        text = text.replacen(from, to, 1);
    }
    text
}

fn load(text: &str, overrides: &[&str]) -> Result<SceneSpec, SceneError> {
    let overrides: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    SceneSpec::from_str(text, "scene.toml", &data_dir(), &overrides)
}

fn message(replace: &[(&str, &str)], overrides: &[&str]) -> String {
    match load(&scene(replace), overrides) {
        Ok(_) => panic!("the scene was accepted: {replace:?} {overrides:?}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn the_base_scene_is_valid() {
    let spec = load(&scene(&[]), &[]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(spec.name, "base");
    assert_eq!(spec.boundaries[0].selection.disp_nodes.len(), 5);
}

#[test]
fn unknown_keys_list_the_expected_names() {
    let top = message(&[("name = \"base\"\n", "name = \"base\"\ngravty = [0, 0, -9.81]")], &[]);
    assert_eq!(
        top,
        "scene.toml:2: gravty: unknown field `gravty`, expected one of `name`, `description`, `time`, `solver`, \
         `gravity`, `functions`, `mesh`, `material`, `shell`, `boundary`, `load`, `rest_field`, `probe`, `output`, \
         `contact`"
    );
    let nested = message(
        &[("position = { stiffness = 1e6 }", "position = { stifness = 1e6 }")],
        &[],
    );
    assert_eq!(
        nested,
        "scene.toml:26: boundary.0.position.stifness: unknown field `stifness`, expected one of `stiffness`, \
         `exact`, `axes`"
    );
    let in_mesh = message(&[("ny = 2\n", "ny = 2\nradius = 1.0\n")], &[]);
    assert_eq!(
        in_mesh,
        "scene.toml:13: mesh.radius: not a parameter of the `rectangle` generator (its parameters: lx, ly, nx, ny)"
    );
}

#[test]
fn wrong_types_and_missing_keys_name_the_field() {
    assert_eq!(
        message(&[("nx = 10", "nx = \"ten\"")], &[]),
        "scene.toml:11: mesh.nx: invalid type: string \"ten\", expected usize"
    );
    assert_eq!(
        message(&[("model = \"plate\"", "model = \"plat\"")], &[]),
        "scene.toml:16: material.model: unknown variant `plat`, expected one of `plate`, `shell`, \
         `kirchhoff_love`, `micropolar_volume`"
    );
    assert_eq!(
        message(&[("thickness = 1e-3\n", "")], &[]),
        "scene.toml:15: material: missing field `thickness`"
    );
    assert_eq!(
        message(&[("scale = \"ramp(t, 0, 1)\"", "scale = [1, 2]")], &[]),
        "scene.toml:32: load.0.scale: invalid type: sequence, expected a number or an expression string"
    );
    assert_eq!(
        message(&[("dt = 0.01", "dt = = 0.01")], &[]),
        "scene.toml:4: invalid TOML: extra `=`, expected nothing"
    );
}

#[test]
fn time_values_are_checked() {
    assert_eq!(
        message(&[("dt = 0.01", "dt = 0.0")], &[]),
        "scene.toml:4: time.dt: must be positive (got 0)"
    );
    assert_eq!(
        message(&[("dt = 0.01", "dt = -0.01")], &[]),
        "scene.toml:4: time.dt: must be positive (got -0.01)"
    );
    assert_eq!(
        message(&[("end = 1.0", "end = -1.0")], &[]),
        "scene.toml:5: time.end: must be finite and non-negative (got -1)"
    );
    // Arc-length paths: no time step, a first increment within the path, and either tolerance.
    assert_eq!(
        message(&[], &["time.mode=arc_length"]),
        "scene.toml:4: time.dt: not used in `arc_length` mode"
    );
    assert_eq!(
        message(
            &[("dt = 0.01\n", "")],
            &["time.mode=arc_length", "time.initial_increment=2"]
        ),
        "override `time.initial_increment=2`: time.initial_increment: must lie in (0, end = 1] (got 2)"
    );
    assert_eq!(
        message(&[], &["solver.tolerance=1e-7", "solver.relative_tolerance=1e-6"]),
        "override `solver.relative_tolerance=1e-6`: solver.relative_tolerance: give an absolute `tolerance` or a \
         `relative_tolerance`, not both"
    );
    assert_eq!(
        message(&[], &["solver.reuse_factorisation=1"]),
        "override `solver.reuse_factorisation=1`: solver.reuse_factorisation: must lie in [0, 1): the residual \
         reduction per iteration below which the factorisation is kept, 0 for none (got 1)"
    );
    assert_eq!(
        message(
            &[("dt = 0.01\n", "")],
            &["time.mode=arc_length", "solver.reuse_factorisation=0.1"]
        ),
        "override `solver.reuse_factorisation=0.1`: solver.reuse_factorisation: not used in `arc_length` mode \
         (the corrector factorises the tangent every iteration)"
    );
    assert_eq!(
        message(
            &[("dt = 0.01\nend = 1.0\n", "n_levels = 4\n")],
            &["time.mode=quasi_static", "solver.initial_guess=least_energy"]
        ),
        "override `solver.initial_guess=least_energy`: solver.initial_guess: in `quasi_static` mode a level \
         starts from the last increments extrapolated (`\"extrapolated\"`, the default) or from the last \
         equilibrium (`\"zero\"`)"
    );
}

#[test]
fn poisson_ratios_at_either_bound_are_rejected_for_that_bound() {
    assert_eq!(
        message(&[("poisson_ratio = 0.3", "poisson_ratio = 0.5")], &[]),
        "scene.toml:19: material.poisson_ratio: must be below 0.5; 0.5 would make the Lamé parameter \
         λ = Eν/((1 + ν)(1 − 2ν)) infinite (got 0.5)"
    );
    assert_eq!(
        message(&[("poisson_ratio = 0.3", "poisson_ratio = -1.0")], &[]),
        "scene.toml:19: material.poisson_ratio: must be above −1; −1 would make the shear modulus \
         μ = E/(2(1 + ν)) infinite (got -1)"
    );
}

#[test]
fn material_values_whose_products_overflow_or_underflow_are_rejected() {
    // Each value alone is finite and positive; the stiffness or mass made of it is not.
    let cases = [
        (
            "thickness = 1e-3",
            "thickness = 1e303",
            "material.thickness",
            "the membrane stiffness E·h overflows",
        ),
        (
            "thickness = 1e-3",
            "thickness = 1e-200",
            "material.thickness",
            "the plate bending stiffness E·h³/(12(1 − ν²)) underflows to zero",
        ),
        (
            "length_scale = 1e-6",
            "length_scale = 1e200",
            "material.length_scale",
            "the curvature stiffness h·μ·L_c²·(b₁ + b₂) overflows",
        ),
        (
            "density = 1000.0",
            "density = 1e-322",
            "material.density",
            "the mass per area ρ·h underflows to zero",
        ),
    ];
    for (from, to, field, reason) in cases {
        let text = scene(&[(from, to)]);
        let err = SceneSpec::from_str(&text, "scene.toml", &data_dir(), &[]).unwrap_err();
        assert_eq!(err.field(), Some(field), "{to}: {err}");
        assert!(err.to_string().contains(reason), "{to}: {err}");
    }
}

#[test]
fn a_growth_beyond_what_the_energy_can_hold_is_rejected() {
    const END: &str = "point = [0.05, 0.0, 0.0]\n";
    let growth = |s: &str| format!("{END}\n[[rest_field]]\ngrowth = \"{s}\"\n");
    // Finite everywhere, but e^(2s) with s = 1000 is not: the run stopped at once with a non-finite energy.
    let text = message(&[(END, &growth("1000"))], &[]);
    assert!(
        text.starts_with(
            "scene.toml:39: rest_field.0.growth: `1000` is 1000 at t = 0, (x, y, z) = (-0.05, -0.005, 0): the rest \
             metric"
        ),
        "{text}"
    );
    let text = message(&[(END, &growth("-400*t"))], &[]);
    assert!(text.contains("rest_field.0.growth: `-400*t` is -18"), "{text}");
    // A constant growth is named as it reads, not in its 309 digits.
    let constant = format!("{END}\n[[rest_field]]\ngrowth = 1e308\n");
    let text = message(&[(END, &constant)], &[]);
    assert!(text.contains("rest_field.0.growth: `1e308` is 1e308 at"), "{text}");
    // A large but computable growth is allowed.
    let text = scene(&[(END, &growth("5*x"))]);
    load(&text, &[]).unwrap_or_else(|e| panic!("{e}"));
}

#[test]
fn huge_and_tiny_numbers_are_shown_with_an_exponent() {
    // Rust's `Display` of 1e300 has 301 digits; messages show the exponent instead.
    assert_eq!(
        message(&[("end = 1.0", "end = -1e300")], &[]),
        "scene.toml:5: time.end: must be finite and non-negative (got -1e300)"
    );
    assert_eq!(
        message(&[], &["probe.0.point=[1e300, 0, 1e-300]"]),
        "override `probe.0.point=[1e300, 0, 1e-300]`: probe.0.point: the point (1e300, 0, 1e-300) lies outside the \
         bounding box of shell `shell` ([-0.05, 0.05] × [-0.005, 0.005] × [0, 0], grown by 1 % of its diagonal)"
    );
    let text = message(&[("dt = 0.01\nend = 1.0", "dt = 1e300\nend = 1e300")], &[]);
    assert!(
        text.ends_with("(up to 2e300 s); frames are written at most once per step, so an interval of time.dt = 1e300 s already writes every step"),
        "{text}"
    );
}

#[test]
fn expressions_are_checked_where_they_are_written() {
    assert_eq!(
        message(&[("scale = \"ramp(t, 0, 1)\"", "scale = \"ramp(t, 0, 1\"")], &[]),
        "scene.toml:32: load.0.scale: `ramp(t, 0, 1`: column 13: expected `,` or `)`, found the end of the expression"
    );
    assert_eq!(
        message(&[("scale = \"ramp(t, 0, 1)\"", "scale = \"ramp(s, 0, 1)\"")], &[]),
        "scene.toml:32: load.0.scale: `ramp(s, 0, 1)`: column 6: unknown variable `s` (allowed here: t)"
    );
    assert_eq!(
        message(&[("\"x <= -0.05 + 1e-9\"", "\"x <= -0.05 + t\"")], &[]),
        "scene.toml:25: boundary.0.region.predicate: `x <= -0.05 + t`: column 14: unknown variable `t` \
         (allowed here: x, y, z)"
    );
    // Finite where it is written, but NaN within the run: t is sampled at 200 steps up to
    // end + dt = 1.01, and the first sample past 1 is 1.01·199/200 = 1.00495.
    assert_eq!(
        message(&[("scale = \"ramp(t, 0, 1)\"", "scale = \"sqrt(1 - t)\"")], &[]),
        "scene.toml:32: load.0.scale: `sqrt(1 - t)` evaluates to NaN at t = 1.00495"
    );
}

#[test]
fn a_load_profile_is_a_finite_function_of_the_rest_position_on_a_force_or_torque() {
    let with = |profile: &str| {
        [(
            "scale = \"ramp(t, 0, 1)\"",
            format!("scale = \"ramp(t, 0, 1)\"\nprofile = {profile}"),
        )]
    };
    let accept = |profile: &str| {
        let r = with(profile);
        let spec = load(&scene(&[(r[0].0, &r[0].1)]), &[]).unwrap_or_else(|e| panic!("{profile}: {e}"));
        let p = spec.loads[0].profile.as_ref().expect("a profile");
        p.eval(&nalgebra::Vector3::new(0.05, 0.0, 0.0), 0.0)
    };
    assert_eq!(accept("\"1 + 20*x\""), 2.0);
    assert_eq!(accept("0.5"), 0.5);
    let refuse = |profile: &str| {
        let r = with(profile);
        message(&[(r[0].0, &r[0].1)], &[])
    };
    assert_eq!(
        refuse("\"x*t\""),
        "scene.toml:33: load.0.profile: is a function of the rest position `x, y, z` only; put the time \
         dependence in `scale`"
    );
    assert!(refuse("\"sqrt(x)\"").starts_with("scene.toml:33: load.0.profile: `sqrt(x)` evaluates to NaN"));
    let pressure = message(
        &[
            ("force = [0.0, 0.0, 1.0]", "pressure = 1.0"),
            ("scale = \"ramp(t, 0, 1)\"", "profile = \"x\""),
        ],
        &[],
    );
    assert!(pressure.contains("load.0.profile: a pressure is uniform"), "{pressure}");
}

#[test]
fn a_region_that_selects_nothing_is_an_error() {
    assert_eq!(
        message(&[("\"x <= -0.05 + 1e-9\"", "\"x <= -1\"")], &[]),
        "scene.toml:25: boundary.0.region: the region (predicate `x <= -1`) selects no displacement node of shell \
         `shell`"
    );
    // Rotation nodes are resolved by their own positions: with linear rotations they are the corners,
    // and a box around a mid-edge column holds displacement nodes but no corner, so a rotation
    // condition on it has nothing to act on.
    let err = message(
        &[(
            "{ predicate = \"x <= -0.05 + 1e-9\" }",
            "{ box = { center = [-0.045, 0.0, 0.0], size = [0.001, 0.02, 0.01] } }",
        )],
        &["mesh.rotation_element=tri3"],
    );
    assert_eq!(
        err,
        "scene.toml:25: boundary.0.region: the region (box centre (-0.045, 0, 0) size (0.001, 0.02, 0.01)) selects \
         no rotation node of shell `shell`"
    );
}

#[test]
fn a_probe_point_outside_the_mesh_is_an_error() {
    assert_eq!(
        message(&[("point = [0.05, 0.0, 0.0]", "point = [0.5, 0.0, 0.0]")], &[]),
        "scene.toml:36: probe.0.point: the point (0.5, 0, 0) lies outside the bounding box of shell `shell` \
         ([-0.05, 0.05] × [-0.005, 0.005] × [0, 0], grown by 1 % of its diagonal)"
    );
}

#[test]
fn mesh_files_are_checked() {
    let path = |name: &str| data_dir().join(name).display().to_string();
    let with_path = |file: &str| message(&[(MESH, &format!("path = \"{file}\""))], &[]);
    let missing = with_path("missing.obj");
    assert!(
        missing.starts_with(&format!(
            "scene.toml:8: mesh.path: cannot read `{}`: ",
            path("missing.obj")
        )),
        "{missing}"
    );
    assert_eq!(
        with_path("quad_face.obj"),
        format!(
            "scene.toml:8: mesh.path: `{}` line 8: face 1 has 4 vertices; only triangles are supported",
            path("quad_face.obj")
        )
    );
    assert!(
        with_path("degenerate_triangle.obj").starts_with(&format!(
            "scene.toml:8: mesh.path: `{}` line 7: face 1 is degenerate (area 0e0)",
            path("degenerate_triangle.obj")
        )),
        "{}",
        with_path("degenerate_triangle.obj")
    );
    assert_eq!(
        with_path("nonmanifold_edge.obj"),
        format!(
            "scene.toml:8: mesh.path: `{}` line 9: the edge between vertices 0 and 1 is shared by 3 faces (at most two \
             are allowed)",
            path("nonmanifold_edge.obj")
        )
    );
    assert_eq!(
        with_path("unreferenced_vertex.obj"),
        format!(
            "scene.toml:8: mesh.path: `{}` line 5: vertex 3 is not used by any face",
            path("unreferenced_vertex.obj")
        )
    );
}

#[test]
fn overrides_are_named_in_errors() {
    assert_eq!(
        message(&[], &["time.dtt=0.1"]),
        "override `time.dtt=0.1`: time.dtt: unknown field `dtt`, expected one of `mode`, `dt`, `end`, `output_fps`, \
         `output_interval`, `adaptive`, `levels`, `n_levels`, `initial_increment`, `max_steps`"
    );
    assert_eq!(
        message(&[], &["boundary.3.position.stiffness=1"]),
        "override `boundary.3.position.stiffness=1`: `boundary` has 1 entry, so index 3 does not exist"
    );
    assert_eq!(
        message(&[], &["mesh.nx=ten"]),
        "override `mesh.nx=ten`: mesh.nx: invalid type: string \"ten\", expected usize"
    );
    assert_eq!(
        message(&[], &["time.dt=-1"]),
        "override `time.dt=-1`: time.dt: must be positive (got -1)"
    );
    assert_eq!(message(&[], &["time.dt"]), "override `time.dt`: expected `key=value`");
    assert_eq!(
        message(&[], &["time..dt=1"]),
        "override `time..dt=1`: the key has an empty segment (two dots in a row, or a leading or trailing dot)"
    );
    assert_eq!(
        message(&[], &["time.dt.x=1"]),
        "override `time.dt.x=1`: `time.dt` is a float, not a table"
    );
}

#[test]
fn multi_shell_scenes_need_the_shell_named() {
    let text = scene(&[
        ("[mesh]\n", "[[shell]]\nname = \"a\"\n[shell.mesh]\n"),
        ("[material]\n", "[shell.material]\n"),
    ]);
    let second = text[text.find("[[shell]]").unwrap()..text.find("[[boundary]]").unwrap()].replace("\"a\"", "\"b\"");
    let text = text.replace("[[boundary]]", &format!("{second}[[boundary]]"));
    let err = load(&text, &[]).unwrap_err().to_string();
    assert!(
        err.ends_with("boundary.0.shell: the scene has 2 shells; name one of: a, b"),
        "{err}"
    );
    let err = load(
        &text.replace("name = \"clamp\"", "name = \"clamp\"\nshell = \"c\""),
        &[],
    )
    .unwrap_err()
    .to_string();
    assert!(
        err.ends_with("boundary.0.shell: no shell is named `c` (shells: a, b)"),
        "{err}"
    );
}

#[test]
fn error_variants_carry_location_and_field() {
    let err = load(&scene(&[("dt = 0.01", "dt = -0.01")]), &[]).unwrap_err();
    assert!(matches!(err, SceneError::Invalid { .. }));
    assert_eq!(err.field(), Some("time.dt"));
    assert_eq!(err.location().map(|l| l.to_string()), Some("scene.toml:4".to_string()));
    let err = load(&scene(&[]), &["time.dt=-1"]).unwrap_err();
    assert_eq!(
        err.location().map(|l| l.to_string()),
        Some("override `time.dt=-1`".to_string())
    );
    let err = SceneSpec::from_file(data_dir().join("no_such_scene.toml"), &[]).unwrap_err();
    assert!(matches!(err, SceneError::ReadScene { .. }));
}

#[test]
fn top_level_problems_have_no_field_prefix() {
    let err = load("name = \"x\"\n[time]\ndt = 0.1\nend = 1.0\n", &[]).unwrap_err();
    assert_eq!(
        err.to_string(),
        "scene.toml: the scene has no shell: add `[mesh]` and `[material]`, or `[[shell]]` tables"
    );
    let err = load("[time]\ndt = 0.1\nend = 1.0\n", &[]).unwrap_err();
    assert_eq!(err.to_string(), "scene.toml:1: missing field `name`");
}

#[test]
fn errors_inside_arrays_of_inline_tables_point_at_their_line() {
    // `[[rest_field]]` replaces `[[probe]]` on line 34, so the second entry is on line 37.
    let rest_field = "[[rest_field]]\ncurvature = [\n    { row = 2, col = 1, value = \"ramp(t, 0, 1)\" },\n    \
                      { row = 1, col = 2, value = \"ramp(t, 0, 1) * w\" },\n]\n\n[[probe]]";
    let err = message(&[("[[probe]]", rest_field)], &[]);
    assert_eq!(
        err,
        "scene.toml:37: rest_field.0.curvature.1.value: `ramp(t, 0, 1) * w`: column 17: unknown variable `w` \
         (allowed here: x, y, z, t)"
    );
    let err = message(&[("[[probe]]", &rest_field.replace("row = 1", "row = 4"))], &[]);
    assert_eq!(
        err,
        "scene.toml:37: rest_field.0.curvature.1.row: rows and columns are numbered 1 to 3, as in the paper's Γ_ij \
         (got 4)"
    );
}

#[test]
fn sizes_that_exhaust_memory_are_refused_against_the_field_that_sets_them() {
    assert_eq!(
        message(&[], &["mesh.nx=100000000"]),
        "override `mesh.nx=100000000`: mesh.nx: the generator would make 400000000 triangles, more than the \
         limit of 10000000 (the largest mesh the simulator builds)"
    );
    let sphere = [(MESH, "generator = \"icosphere\"\nradius = 1.0\nlevel = 12\n\n\n")];
    assert_eq!(
        message(&sphere, &[]),
        "scene.toml:10: mesh.level: the generator would make 335544320 triangles, more than the limit of \
         10000000 (the largest mesh the simulator builds)"
    );
    // 20·4⁴⁰ triangles: more than a count can hold, so the message gives the bound.
    let sphere = [(MESH, "generator = \"icosphere\"\nradius = 1.0\nlevel = 40\n\n\n")];
    assert_eq!(
        message(&sphere, &[]),
        format!(
            "scene.toml:10: mesh.level: the generator would make at least {} triangles, more than the limit of \
             10000000 (the largest mesh the simulator builds)",
            usize::MAX
        )
    );
    assert_eq!(
        message(&[], &["mesh.refine=8", "mesh.nx=100"]),
        "override `mesh.refine=8`: mesh.refine: the mesh would have 26214400 elements, more than the limit of \
         10000000 (the largest mesh the simulator builds)"
    );
    let quasi_static = [(
        "dt = 0.01\nend = 1.0",
        "mode = \"quasi_static\"\nn_levels = 1000000000000",
    )];
    assert_eq!(
        message(&quasi_static, &[]),
        "scene.toml:5: time.n_levels: must be at most 100000 (got 1000000000000)"
    );
    assert!(message(&[], &["time.dt=1e-12"]).starts_with("override `time.dt=1e-12`: time.dt: end / dt = 1.000e12"));
}

#[test]
fn an_output_interval_that_cannot_advance_is_refused() {
    let err = message(&[], &["time.output_fps=1e300"]);
    assert!(
        err.starts_with("override `time.output_fps=1e300`: time.output_fps: an output interval of 1e-300 s is below"),
        "{err}"
    );
    // Shorter than a step is fine: a frame every step.
    load(&scene(&[]), &["time.output_fps=1e6"]).unwrap();
}

#[test]
fn quadrature_rules_with_zero_energy_modes_are_refused() {
    assert_eq!(
        message(&[], &["mesh.quadrature_degree=1"]),
        "override `mesh.quadrature_degree=1`: mesh.quadrature_degree: a rule of degree 1 leaves zero-energy modes \
         in Tri6 elements (they deform without resistance); use at least degree 2 or leave the key out for the \
         default"
    );
    assert!(message(&[], &["mesh.quadrature_degree=0"]).contains("a rule of degree 0 leaves zero-energy modes"));
    load(&scene(&[]), &["mesh.quadrature_degree=2"]).unwrap();
    load(&scene(&[]), &["mesh.quadrature_degree=1", "mesh.element=tri3"]).unwrap();
}

#[test]
fn scene_names_are_safe_folder_names() {
    for bad in ["../../x", "/tmp/x", ".hidden", "a b", ""] {
        let err = message(&[("name = \"base\"", &format!("name = \"{bad}\""))], &[]);
        assert!(
            err.starts_with(&format!("scene.toml:1: name: `{bad}` is not a usable name")),
            "{err}"
        );
    }
    load(&scene(&[("name = \"base\"", "name = \"plate_tri6.v2-a\"")]), &[]).unwrap();
}

#[test]
fn generator_errors_name_the_generator_and_field() {
    let disk = [(
        MESH,
        "generator = \"disk\"\nradius = 1.0\nn_radial = 0\nn_angular = 8\n\n",
    )];
    assert_eq!(
        message(&disk, &[]),
        "scene.toml:10: mesh.n_radial: disk: parameter `n_radial` = 0 is invalid: must be at least 1"
    );
    let hole = |degrees: &str| {
        let body = format!(
            "generator = \"hemisphere\"\nradius = 10.0\nn_lon = 16\nn_lat = 8\npolar_hole_degrees = {degrees}\n"
        );
        message(&[(MESH, &body)], &[])
    };
    assert_eq!(
        hole("95.0"),
        "scene.toml:12: mesh.polar_hole_degrees: must lie in [0, 90): the polar angle of the hole's rim in degrees \
         (got 95)"
    );
    let err = hole("89.0");
    assert!(
        err.starts_with("scene.toml:12: mesh.polar_hole_degrees: hemisphere: parameter `polar_hole_degrees` = 89")
            && err.contains("leaves no face"),
        "{err}"
    );
}

#[test]
fn checkpoints_are_refused_where_a_run_cannot_resume() {
    let every = |n: &str| format!("output.checkpoint_every={n}");
    let spec = load(&scene(&[]), &[&every("5")]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(spec.output.checkpoint_every, Some(5));
    assert_eq!(load(&scene(&[]), &[]).unwrap().output.checkpoint_every, None);
    let zero = message(&[], &[&every("0")]);
    assert!(
        zero.contains("output.checkpoint_every") && zero.contains("at least 1"),
        "{zero}"
    );
    let usd = message(&[], &[&every("5"), "output.formats=[\"vtu\", \"usd\"]"]);
    assert!(usd.contains("output.checkpoint_every") && usd.contains("USD"), "{usd}");
    let arc = message(
        &[(
            "dt = 0.01\nend = 1.0",
            "mode = \"arc_length\"\ninitial_increment = 0.1\nend = 1.0",
        )],
        &[&every("5")],
    );
    assert!(
        arc.contains("output.checkpoint_every") && arc.contains("arc-length"),
        "{arc}"
    );
}

#[test]
fn a_frame_format_named_twice_is_refused() {
    let twice = |formats: &str| format!("{}\n[output]\nformats = {formats}\n", scene(&[]));
    let err = load(&twice("[\"vtu\", \"obj\", \"vtu\"]"), &[]).unwrap_err();
    assert_eq!(err.field(), Some("output.formats"));
    assert_eq!(
        err.to_string(),
        "scene.toml:39: output.formats: lists `vtu` twice (entries 1 and 3); name each format once"
    );
    let spec = load(&twice("[\"vtu\", \"obj\"]"), &[]).unwrap_or_else(|e| panic!("{e}"));
    assert!(spec.output.formats.vtu && spec.output.formats.obj);
}

#[test]
fn a_mesh_file_of_an_unknown_format_is_refused_by_its_extension() {
    let with_path = |file: &str| load(&scene(&[(MESH, &format!("path = \"{file}\""))]), &[]).unwrap_err();
    assert_eq!(
        with_path("plate.stl").to_string(),
        "scene.toml:8: mesh.path: the extension `.stl` is not a mesh format the simulator reads; use `.obj` \
         (Wavefront OBJ), `.msh` (Gmsh MSH 4.1) or `.ply` (PLY), in any case"
    );
    assert!(with_path("plate.txt").to_string().contains("the extension `.txt` is not"));
    let bare = with_path("plate").to_string();
    assert!(
        bare.contains("plate` has no extension to tell its format; use `.obj`"),
        "{bare}"
    );
    // Known extensions in any case are read in their format (these files do not exist).
    assert!(matches!(with_path("missing.OBJ"), SceneError::Obj { .. }));
    assert!(matches!(with_path("missing.Msh"), SceneError::MeshFile { .. }));
}

#[test]
fn a_section_written_as_the_other_kind_of_table_is_named_with_its_kind() {
    assert_eq!(
        message(&[("[time]", "[[time]]")], &[]),
        "scene.toml:3: time: is a table (`[time]`), not an array of tables (`[[time]]`)"
    );
    assert_eq!(
        message(&[("[[boundary]]", "[boundary]")], &[]),
        "scene.toml:23: boundary: is an array of tables (one `[[boundary]]` per entry), not a table (`[boundary]`)"
    );
    assert_eq!(
        message(
            &[("position = { stiffness = 1e6 }", "position = [{ stiffness = 1e6 }]")],
            &[]
        ),
        "scene.toml:26: boundary.0.position: is a table (`[boundary.position]`), not an array of tables \
         (`[[boundary.position]]`)"
    );
    // A list of numbers written as tables is not a table either: serde's message stays.
    assert_eq!(
        message(&[("name = \"base\"\n", "name = \"base\"\n[[gravity]]\n")], &[]),
        "scene.toml:2: gravity.0: invalid type: map, expected f64"
    );
}

#[test]
fn loads_too_large_to_square_are_refused_naming_the_field() {
    // Gravity of 1e308 passed as finite and stopped the run in its first step with a non-finite energy.
    assert_eq!(
        message(&[], &["gravity=[0, 0, -1e308]"]),
        "override `gravity=[0, 0, -1e308]`: gravity: -1e308 exceeds 1e150 in magnitude, the largest load the \
         solver takes: it squares loads, and their squares overflow from about 1.3e154"
    );
    let force = message(&[("force = [0.0, 0.0, 1.0]", "force = [0.0, 2e150, 1.0]")], &[]);
    assert!(
        force.starts_with("scene.toml:31: load.0.force: 2e150 exceeds 1e150"),
        "{force}"
    );
    let torque = message(&[("force = [0.0, 0.0, 1.0]", "torque = [1e200, 0.0, 0.0]")], &[]);
    assert!(
        torque.starts_with("scene.toml:31: load.0.torque: 1e200 exceeds 1e150"),
        "{torque}"
    );
    let pressure = message(&[("force = [0.0, 0.0, 1.0]", "pressure = -1e160")], &[]);
    assert!(
        pressure.starts_with("scene.toml:31: load.0.pressure: -1e160 exceeds 1e150"),
        "{pressure}"
    );
    load(&scene(&[]), &["gravity=[0, 0, -1e150]", "load.0.force=[0, 0, 1e150]"]).unwrap_or_else(|e| panic!("{e}"));
}

#[test]
fn rest_fields_of_one_shell_that_cannot_act_as_one_are_refused() {
    const END: &str = "point = [0.05, 0.0, 0.0]\n";
    let tables = |first: &str, second: &str| format!("{END}\n[[rest_field]]\n{first}\n\n[[rest_field]]\n{second}\n");
    let curvature = "curvature = [{ row = 1, col = 1, value = \"1\" }]";
    let cases = [
        (
            "growth = \"0.1\"",
            "growth = \"0.2\"",
            "rest_field.1.growth",
            "one growth field",
        ),
        (
            curvature,
            &format!("{curvature}\ntiming = \"end_of_step\""),
            "rest_field.1.timing",
            "one timing",
        ),
        (
            curvature,
            &format!("{curvature}\nframe = [{{ axis = \"z\", degrees = 3 }}]"),
            "rest_field.1.frame",
            "one frame",
        ),
    ];
    for (first, second, field, reason) in cases {
        let err = load(&scene(&[(END, &tables(first, second))]), &[]).unwrap_err();
        assert_eq!(err.field(), Some(field), "{second}: {err}");
        assert!(err.to_string().contains(reason), "{second}: {err}");
        assert!(
            err.to_string().contains("`rest_field.0` acts on the same shell"),
            "{err}"
        );
    }
    // Growth beside curvature in a frame, and curvature entries split over two tables, act as one.
    let framed = format!("{curvature}\nframe = [{{ axis = \"z\", degrees = 3 }}]");
    for (first, second) in [
        ("growth = \"0.1\"", framed.as_str()),
        (curvature, "curvature = [{ row = 2, col = 2, value = \"1\" }]"),
    ] {
        load(&scene(&[(END, &tables(first, second))]), &[]).unwrap_or_else(|e| panic!("{second}: {e}"));
    }
}
