//! `--set key=value` overrides: parsing, and their effect on a loaded scene.

use cosserat_scene::overrides::Override;
use cosserat_scene::spec::{PositionEnforcement, SceneSpec};
use nalgebra::Vector3;
use std::path::Path;

const SCENE: &str = r#"name = "strip"
[time]
dt = 0.01
end = 1.0
[mesh]
generator = "rectangle"
lx = 0.1
ly = 0.01
nx = 10
ny = 2
element = "tri3"
[material]
model = "plate"
thickness = 1e-3
youngs_modulus = 1e6
poisson_ratio = 0.3
density = 1000.0
length_scale = 1e-6
[[boundary]]
region = { predicate = "x <= -0.05 + 1e-9" }
position = { stiffness = 1e6 }
"#;

fn load(overrides: &[&str]) -> SceneSpec {
    let overrides: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    SceneSpec::from_str(SCENE, "strip.toml", Path::new("."), &overrides).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn parse_splits_key_path_and_value() {
    let o = Override::parse(" boundary.0.position.stiffness = 2.5e6 ").unwrap();
    assert_eq!(o.path, ["boundary", "0", "position", "stiffness"]);
    assert_eq!(o.value, "2.5e6");
    assert_eq!(o.key(), "boundary.0.position.stiffness");
    // Only the first `=` separates; the value may contain more.
    let o = Override::parse("mesh.path=a=b.obj").unwrap();
    assert_eq!((o.key().as_str(), o.value.as_str()), ("mesh.path", "a=b.obj"));
}

#[test]
fn values_are_toml_values_or_plain_strings() {
    let spec = load(&[
        "mesh.nx=20",
        "mesh.element=tri6",
        "gravity=[0, 0, -9.81]",
        "name=\"renamed\"",
    ]);
    assert_eq!(spec.name, "renamed");
    assert_eq!(spec.gravity, Vector3::new(0.0, 0.0, -9.81));
    // 20 × 2 Tri6: 41 × 5 nodes.
    assert_eq!(spec.shells[0].mesh.tri6.as_ref().map(|t| t.n_nodes()), Some(205));
    let spec = load(&["name=plain_word"]);
    assert_eq!(spec.name, "plain_word");
}

#[test]
fn array_entries_and_missing_tables_are_reached() {
    let spec = load(&[
        "boundary.0.position.stiffness=5",
        "output.frames=false",
        "solver.tolerance=1e-9",
    ]);
    assert_eq!(
        spec.boundaries[0].position.map(|p| p.0),
        Some(PositionEnforcement::Penalty(5.0))
    );
    assert!(!spec.output.frames);
    assert_eq!(spec.solver.tolerance, cosserat_solver::Tolerance::Absolute(1e-9));
    // A whole inline table replaces the region.
    let spec = load(&["boundary.0.region={ all = true }"]);
    assert_eq!(spec.boundaries[0].selection.disp_nodes.len(), 33);
}

#[test]
fn later_overrides_win() {
    let spec = load(&["time.dt=0.1", "time.dt=0.2"]);
    assert!(matches!(spec.time, cosserat_scene::spec::TimeSpec::Dynamic { dt, .. } if dt == 0.2));
}

#[test]
fn an_empty_value_removes_the_key_and_its_default_applies() {
    let absolute = load(&["solver.tolerance=1e-9"]);
    assert_eq!(absolute.solver.tolerance, cosserat_solver::Tolerance::Absolute(1e-9));
    let spec = load(&["solver.tolerance=1e-9", "solver.tolerance="]);
    assert_eq!(spec.solver.tolerance, load(&[]).solver.tolerance);
    assert!(matches!(spec.solver.tolerance, cosserat_solver::Tolerance::Relative(_)));
    // A key or a table that is not there is left alone.
    let spec = load(&["solver.missing=", "absent.table.key=", "boundary.0.absent.key="]);
    assert_eq!(spec.solver.tolerance, load(&[]).solver.tolerance);
    // An array entry is not removed, and a path through a number is refused.
    let refused = |ov: &str| {
        let overrides = vec![ov.to_string()];
        SceneSpec::from_str(SCENE, "strip.toml", Path::new("."), &overrides)
            .err()
            .unwrap_or_else(|| panic!("`{ov}` was accepted"))
            .to_string()
    };
    assert!(
        refused("boundary.0=").contains("cannot be removed"),
        "{}",
        refused("boundary.0=")
    );
    assert!(
        refused("mesh.nx.size=").contains("not a table"),
        "{}",
        refused("mesh.nx.size=")
    );
}

#[test]
fn quadratic_displacements_default_to_the_locking_free_pair_and_tri3_rotations_select_the_papers() {
    use cosserat_assembly::ElementPair::{Tri3Tri3, Tri6Tri3, Tri6Tri6};
    use cosserat_material::StrainInterpolation::{Paper, ReggeStabilized};
    let discretisation = |overrides: &[&str]| {
        let spec = load(overrides);
        (spec.shells[0].pair, spec.shells[0].rest.interpolation)
    };
    assert_eq!(discretisation(&[]), (Tri3Tri3, Paper));
    assert_eq!(discretisation(&["mesh.element="]), (Tri6Tri6, ReggeStabilized));
    // One key gives the paper's discretisation.
    assert_eq!(
        discretisation(&["mesh.element=", "mesh.rotation_element=tri3"]),
        (Tri6Tri3, Paper)
    );
    // Either part can still be chosen on its own.
    assert_eq!(
        discretisation(&["mesh.element=", "material.strain_interpolation=paper"]),
        (Tri6Tri6, Paper)
    );
    assert_eq!(
        discretisation(&[
            "mesh.element=tri6",
            "mesh.rotation_element=tri3",
            "material.strain_interpolation=regge_stabilized"
        ]),
        (Tri6Tri3, ReggeStabilized)
    );
}

#[test]
fn the_default_discretisation_takes_the_three_point_rule_unless_the_scene_names_one() {
    let points = |overrides: &[&str]| load(overrides).shells[0].quadrature_rule().n_points();
    assert_eq!(points(&["mesh.element="]), 3);
    assert_eq!(
        points(&["mesh.element=", "material.strain_interpolation=regge_stabilized"]),
        3
    );
    assert_eq!(points(&["mesh.element=", "mesh.quadrature_degree=4"]), 6);
    // Every other discretisation keeps its pair's rule: six points on Tri6/Tri6, three on the others.
    assert_eq!(points(&["mesh.element=", "material.strain_interpolation=paper"]), 6);
    assert_eq!(points(&["mesh.element=", "mesh.rotation_element=tri3"]), 3);
    assert_eq!(points(&[]), 3);
}

#[test]
fn quasi_static_runs_default_to_newtons_own_steps_and_dynamic_runs_to_the_shift() {
    use cosserat_solver::IndefiniteHessian::{Factorise, Shift};
    let treatment = |overrides: &[&str]| load(overrides).solver.indefinite_hessian;
    assert_eq!(treatment(&[]), Shift);
    let quasi_static = [
        "time.mode=quasi_static",
        "time.dt=",
        "time.end=",
        "time.levels=[0.5, 1.0]",
    ];
    assert_eq!(treatment(&quasi_static), Factorise);
    let chosen = [&quasi_static[..], &["solver.indefinite_hessian=shift"]].concat();
    assert_eq!(treatment(&chosen), Shift);
}
