//! Every scene under `scenes/` parses and validates, and the paper's node counts come out.

use cosserat_scene::spec::{ForceDistribution, LoadKind, ProbeReduction, SceneSpec, TimeSpec, Timing};
use nalgebra::Vector3;
use std::path::{Path, PathBuf};

/// The workspace's `scenes/` directory.
fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

/// All `.toml` files below `dir`, sorted.
fn scene_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).expect("read the scenes directory") {
        let path = entry.expect("directory entry").path();
        if path.is_dir() {
            out.extend(scene_files(&path));
        } else if path.extension().is_some_and(|e| e == "toml") {
            out.push(path);
        }
    }
    out.sort();
    out
}

fn load(name: &str) -> SceneSpec {
    load_with(name, &[])
}

fn load_with(name: &str, extra: &[&str]) -> SceneSpec {
    let path = scenes_dir().join(name);
    let overrides: Vec<String> = extra.iter().map(|s| s.to_string()).collect();
    SceneSpec::from_file(&path, &overrides).unwrap_or_else(|e| panic!("{e}"))
}

/// Displacement and rotation node counts of shell `k`.
fn node_counts(spec: &SceneSpec, k: usize) -> (usize, usize) {
    let mesh = &spec.shells[k].mesh;
    let n_rot = mesh.corners.n_nodes();
    (mesh.tri6.as_ref().map_or(n_rot, |t| t.n_nodes()), n_rot)
}

#[test]
fn every_scene_parses_and_validates() {
    let files = scene_files(&scenes_dir());
    let names: Vec<String> = files
        .iter()
        .map(|p| p.strip_prefix(scenes_dir()).unwrap().display().to_string())
        .collect();
    for expected in [
        "twisting_strip.toml",
        "plate_under_load.toml",
        "cylinder_coiling.toml",
        "lotus_flower.toml",
        "curvature_modes.toml",
        "buckling_circle_inner.toml",
        "buckling_circle_outer.toml",
        "moebius_plate.toml",
        "moebius_shell.toml",
        "armadillos.toml",
        "bunny.toml",
        "bunny_kl.toml",
        "papyrus_scroll.toml",
        "validation/sze_cantilever_end_shear.toml",
        "validation/end_moment_rollup.toml",
        "validation/cantilever_small_load.toml",
        "validation/pinched_hemisphere.toml",
        "validation/pinched_cylinder.toml",
        "validation/scordelis_lo_roof.toml",
    ] {
        assert!(
            names.iter().any(|n| n == expected),
            "missing scene {expected}; found {names:?}"
        );
    }
    for path in &files {
        let spec =
            SceneSpec::from_file(path, &[]).unwrap_or_else(|e| panic!("{} does not validate: {e}", path.display()));
        assert!(!spec.shells.is_empty());
        assert_eq!(spec.source.as_deref(), Some(path.as_path()));
        assert!(spec.warnings.is_empty(), "{}: {:?}", path.display(), spec.warnings);
    }
}

#[test]
fn twisting_strip_has_the_papers_counts_and_clamps_the_mid_edge_column() {
    let spec = load("twisting_strip.toml");
    // [S]: 2187 displacement and 615 rotation DOFs.
    assert_eq!(node_counts(&spec, 0), (729, 205));
    let x = &spec.shells[0].mesh.tri6.as_ref().unwrap().nodes;
    for b in &spec.boundaries {
        // The end column (2·ny + 1 = 9 nodes) and the mid-edge column half an element inwards (9).
        assert_eq!(b.selection.disp_nodes.len(), 18, "{}", b.name);
        assert_eq!(b.selection.rot_nodes.len(), 5, "{}", b.name);
        let mut columns: Vec<f64> = b.selection.disp_nodes.iter().map(|&i| x[i].x.abs()).collect();
        columns.sort_by(f64::total_cmp);
        columns.dedup();
        assert_eq!(columns, [0.04875, 0.05]);
        assert_eq!(b.rotation.map(|r| r.1), Some([false, false, true]));
        assert_eq!(b.timing, Timing::EndOfStep);
    }
    let (axis, center, angle) = spec.boundaries[1].motion.rotation.as_ref().unwrap();
    assert_eq!((*axis, *center), (Vector3::x(), Vector3::zeros()));
    assert!((angle.eval(0.25) - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
    // With Tri3 elements only the end column (ny + 1 = 5 nodes) is held.
    let tri3 = load_with("twisting_strip.toml", &["mesh.element=tri3"]);
    assert_eq!(node_counts(&tri3, 0), (205, 205));
    assert!(tri3.boundaries.iter().all(|b| b.selection.disp_nodes.len() == 5));
}

#[test]
fn plate_under_load_ladder_rows_come_from_overrides() {
    // (nx, ny, element) → displacement/rotation DOFs of [S] and loaded nodes.
    let rows = [
        (10, 1, "tri6", 189, 66, 3),
        (40, 4, "tri6", 2187, 615, 9),
        (80, 8, "tri6", 8211, 2187, 17),
        (10, 1, "tri3", 66, 66, 2),
        (80, 8, "tri3", 2187, 2187, 9),
    ];
    for (nx, ny, element, disp_dofs, rot_dofs, loaded) in rows {
        let spec = load_with(
            "plate_under_load.toml",
            &[
                &format!("mesh.nx={nx}"),
                &format!("mesh.ny={ny}"),
                &format!("mesh.element={element}"),
            ],
        );
        let (d, r) = node_counts(&spec, 0);
        assert_eq!((3 * d, 3 * r), (disp_dofs, rot_dofs), "{nx}x{ny} {element}");
        assert_eq!(spec.loads[0].selection.disp_nodes.len(), loaded);
        assert_eq!(spec.boundaries[0].selection.disp_nodes.len(), loaded);
    }
    let spec = load("plate_under_load.toml");
    let load = &spec.loads[0];
    let LoadKind::Force { vector, distribution } = load.kind else {
        panic!("the plate is loaded by a force")
    };
    assert_eq!(
        (vector, distribution),
        (Vector3::new(0.0, 0.0, 50.0), ForceDistribution::Equal)
    );
    assert_eq!(load.timing, Timing::StartOfStep);
    for (t, expected) in [(-0.5, 0.0), (0.0, 0.0), (0.25, 0.25), (1.0, 1.0), (1.7, 1.0)] {
        assert_eq!(load.scale.eval(t), expected);
    }
    assert_eq!(
        spec.time,
        TimeSpec::Dynamic {
            dt: 0.01,
            end: 2.0,
            adaptive: false,
            output_interval: 1.0 / 60.0
        }
    );
}

#[test]
fn lotus_layers_evaluate_the_papers_profile() {
    let spec = load("lotus_flower.toml");
    assert_eq!(spec.shells.len(), 3);
    for k in 0..3 {
        // [S] n = 16: 3267/867 DOFs per layer.
        assert_eq!(node_counts(&spec, k), (1089, 289));
        assert_eq!(spec.boundaries[k].selection.disp_nodes.len(), 1);
    }
    let p = |u: f64| -0.2314286 + 10.89881 * u - 14.28571 * u * u + 4.427083 * u * u * u;
    // The document's reference values of the profile.
    assert!((p(0.5) - 2.20).abs() < 5e-3 && (p(1.0) - 0.81).abs() < 5e-3);
    for (k, b) in [0.1, 0.2, 0.35].into_iter().enumerate() {
        let field = &spec.rest_fields[k];
        assert_eq!(field.shell, k);
        let (row, col, g12) = &field.curvature[0];
        assert_eq!((*row, *col), (0, 1));
        let (row, col, g21) = &field.curvature[1];
        assert_eq!((*row, *col), (1, 0));
        // t = 3 s: α = 10·0.5 = 5, σ = min(1.5, 1.8) = 1.5; at (x, y) = (0.2, −0.1):
        // Γ_12 = 5·b·p(1.5·0.1/0.5), Γ_21 = −5·b·p(1.5·0.2/0.5).
        let x = Vector3::new(0.2, -0.1, 0.0);
        let expected_12 = 5.0 * b * p(0.3);
        let expected_21 = -5.0 * b * p(0.6);
        assert!((g12.eval(&x, 3.0) - expected_12).abs() < 1e-12, "{}", g12.eval(&x, 3.0));
        assert!((g21.eval(&x, 3.0) - expected_21).abs() < 1e-12);
        // t = 6 s: α = 10, σ = min(2, 1.8) = 1.8.
        assert!((g21.eval(&x, 6.0) + 10.0 * b * p(1.8 * 0.4)).abs() < 1e-12);
    }
}

#[test]
fn curvature_modes_prescribe_one_antisymmetric_entry_per_strip() {
    let spec = load("curvature_modes.toml");
    let entries = [
        (0, 0, 1.0),
        (1, 0, 1.0),
        (2, 0, 1.0),
        (0, 1, 3.0),
        (1, 1, 2.0),
        (2, 1, 2.0),
    ];
    for (k, (row, col, f)) in entries.into_iter().enumerate() {
        assert_eq!(node_counts(&spec, k), (165, 51));
        assert_eq!(
            spec.boundaries[k].selection.disp_nodes.len(),
            5,
            "centre line of strip {k}"
        );
        let field = &spec.rest_fields[k];
        assert_eq!(field.curvature.len(), 1);
        let (r, c, value) = &field.curvature[0];
        assert_eq!((*r, *c), (row, col));
        let y = 0.8 * k as f64;
        let full = f * 2.0 * std::f64::consts::PI;
        assert!((value.eval(&Vector3::new(0.3, y, 0.0), 2.5) - full).abs() < 1e-12);
        assert!((value.eval(&Vector3::new(-0.3, y, 0.0), 4.0) + full).abs() < 1e-12);
        // sgn(0) = −1, and half strength at t = 1.25 s.
        assert!((value.eval(&Vector3::new(0.0, y, 0.0), 1.25) + 0.5 * full).abs() < 1e-12);
    }
    // The strips do not overlap in their rest positions.
    for k in 1..6 {
        let min_y = spec.shells[k]
            .mesh
            .corners
            .nodes
            .iter()
            .map(|p| p.y)
            .fold(f64::INFINITY, f64::min);
        let max_y_prev = spec.shells[k - 1]
            .mesh
            .corners
            .nodes
            .iter()
            .map(|p| p.y)
            .fold(f64::NEG_INFINITY, f64::max);
        assert!(min_y - max_y_prev > 0.6);
    }
}

#[test]
fn buckling_circle_is_a_flat_disk_with_curved_boundary_and_tilted_initial_positions() {
    for name in ["buckling_circle_inner.toml", "buckling_circle_outer.toml"] {
        let spec = load(name);
        let shell = &spec.shells[0];
        // [S]: 783/213 DOFs.
        assert_eq!(node_counts(&spec, 0), (261, 71));
        let tri6 = shell.mesh.tri6.as_ref().unwrap();
        assert!(tri6.nodes.iter().all(|p| p.z == 0.0));
        let r = 0.025;
        assert!(tri6.nodes.iter().all(|p| p.norm() <= r * (1.0 + 1e-12)));
        // 20 boundary edges: 20 corners and 20 mid-edge nodes exactly on the circle.
        let on_circle = tri6.nodes.iter().filter(|p| (p.norm() - r).abs() < 1e-15).count();
        assert_eq!(on_circle, 40);
        let initial = shell.initial_positions.as_ref().unwrap();
        let (s, c) = 1.5_f64.to_radians().sin_cos();
        for (x, q) in tri6.nodes.iter().zip(initial) {
            let expected = Vector3::new(x.x, c * x.y - s * x.z, s * x.y + c * x.z + 0.01);
            assert!((q - expected).norm() < 1e-15);
        }
        assert!(spec.boundaries.is_empty());
        let growth = spec.rest_fields[0].growth.as_ref().unwrap();
        let centre = Vector3::zeros();
        let rim = Vector3::new(0.0, r, 0.0);
        let (at_centre, at_rim) = (growth.eval(&centre, 5.0), growth.eval(&rim, 5.0));
        if name.contains("inner") {
            assert!((at_centre - 0.15).abs() < 1e-15 && at_rim == 0.0);
        } else {
            assert!(at_centre == 0.0 && (at_rim - 0.15).abs() < 1e-15);
        }
        // Half strength at t = 3 s, nothing before 1 s.
        assert!((growth.eval(&centre, 3.0) + growth.eval(&rim, 3.0) - 0.075).abs() < 1e-15);
        assert_eq!(growth.eval(&centre, 0.5) + growth.eval(&rim, 0.5), 0.0);
    }
}

#[test]
fn moebius_band_has_the_welded_meshs_counts_and_a_clamped_cross_section() {
    for (name, model) in [("moebius_plate.toml", "Plate"), ("moebius_shell.toml", "Shell")] {
        let spec = load(name);
        // [S]: 600/180 DOFs.
        assert_eq!(node_counts(&spec, 0), (200, 60));
        assert_eq!(format!("{:?}", spec.shells[0].rest.model.model), model);
        let b = &spec.boundaries[0];
        assert_eq!((b.selection.disp_nodes.len(), b.selection.rot_nodes.len()), (5, 3));
        assert_eq!(spec.gravity, Vector3::new(0.0, 0.0, -9.81));
        let tri6 = spec.shells[0].mesh.tri6.as_ref().unwrap();
        for &i in &b.selection.disp_nodes {
            let p = tri6.nodes[i];
            assert!(
                p.x.abs() < 1e-15 && p.z.abs() < 1e-15 && (-0.0225..=-0.0075).contains(&p.y),
                "{p:?}"
            );
        }
    }
}

#[test]
fn armadillos_read_the_papers_mesh() {
    let spec = load("armadillos.toml");
    for k in 0..3 {
        // [S]: 15,482 cells, 92,898 displacement and 23,229 rotation DOFs per armadillo.
        assert_eq!(spec.shells[k].mesh.tri6.as_ref().unwrap().elements.len(), 15_482);
        assert_eq!(node_counts(&spec, k), (30_966, 7_743));
    }
}

#[test]
fn armadillos_validate_with_the_fixture_mesh_and_hold_their_feet() {
    let fixture = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/octahedron.obj");
    let overrides: Vec<String> = (0..3).map(|k| format!("shell.{k}.mesh.path={}", fixture.display())).collect();
    let spec = SceneSpec::from_file(scenes_dir().join("armadillos.toml"), &overrides).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(spec.shells.len(), 3);
    for (k, x) in [-0.25, 0.0, 0.25].into_iter().enumerate() {
        let nodes = &spec.shells[k].mesh.tri6.as_ref().unwrap().nodes;
        let (lo, hi) = nodes.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p.z), hi.max(p.z))
        });
        assert!(
            (lo + 0.1).abs() < 1e-15 && (hi - 0.1).abs() < 1e-15,
            "height 0.2 centred: {lo} {hi}"
        );
        let feet = &spec.boundaries[k].selection.disp_nodes;
        assert_eq!(feet.len(), 1, "the octahedron's lowest vertex");
        assert!((nodes[feet[0]] - Vector3::new(x, 0.0, -0.1)).norm() < 1e-15);
        let (row, col, value) = &spec.rest_fields[k].curvature[0];
        assert_eq!((*row, *col), (k, 2));
        assert!((value.eval(&Vector3::zeros(), 1.0) + std::f64::consts::PI / 0.4).abs() < 1e-12);
    }
}

#[test]
fn validation_scenes_load_every_tabulated_level() {
    let tabulated: Vec<f64> = (1..=20).map(|k| k as f64 / 20.0).collect();
    // The end edge of a Tri6 rectangle mesh with ny rows of quads carries 2 ny + 1 nodes.
    for (name, end_nodes) in [
        ("validation/sze_cantilever_end_shear.toml", 5),
        ("validation/end_moment_rollup.toml", 9),
    ] {
        let spec = load(name);
        assert_eq!(
            spec.time,
            TimeSpec::QuasiStatic {
                levels: tabulated.clone(),
                adaptive: true,
            },
            "{name}"
        );
        let load = &spec.loads[0];
        assert_eq!(load.scale.eval(0.35), 0.35);
        let distribution = match load.kind {
            LoadKind::Force { distribution, .. } | LoadKind::Torque { distribution, .. } => distribution,
            LoadKind::Pressure { .. } => panic!("{name} is not loaded by a pressure"),
        };
        assert_eq!(distribution, ForceDistribution::TotalOverLength);
        assert_eq!(spec.probes[0].reduction, ProbeReduction::Mean);
        assert_eq!(spec.probes[0].selection.disp_nodes.len(), end_nodes, "{name}");
    }
    let rollup = load("validation/end_moment_rollup.toml");
    match rollup.loads[0].kind {
        LoadKind::Torque { vector, .. } => {
            assert!((vector.y + 50.0 * std::f64::consts::PI / 3.0).abs() < 1e-12 && vector.x == 0.0 && vector.z == 0.0);
        }
        LoadKind::Force { .. } | LoadKind::Pressure { .. } => panic!("the roll-up is loaded by a torque"),
    }
    // The end edge of the 48 × 4 mesh carries ny + 1 = 5 rotation (corner) nodes.
    assert_eq!(rollup.loads[0].selection.rot_nodes.len(), 5);
    let small = load("validation/cantilever_small_load.toml");
    assert_eq!(
        small.time,
        TimeSpec::QuasiStatic {
            levels: vec![0.5, 1.0],
            adaptive: true
        }
    );
}
