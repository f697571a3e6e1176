//! The `[contact]` section: shells, obstacles (boxes, generated and OBJ meshes, scripted motion),
//! friction between named bodies, the rest-shape `displace` step, the contact scenes of `scenes/`, and
//! errors that name the file, the line and the field.

use cosserat_scene::spec::{ContactBody, ObstacleSpec, SceneSpec};
use nalgebra::Vector3;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

const BASE: &str = r#"name = "contact"
[time]
dt = 0.01
end = 1.0
[[shell]]
name = "sheet"
[shell.mesh]
generator = "rectangle"
lx = 0.1
ly = 0.1
nx = 2
ny = 2
element = "tri6"
[shell.material]
model = "plate"
thickness = 1e-3
youngs_modulus = 1e6
poisson_ratio = 0.3
density = 1000.0
length_scale = 1e-3
[[shell]]
name = "cloth"
[shell.mesh]
generator = "rectangle"
lx = 0.1
ly = 0.1
nx = 2
ny = 2
element = "tri3"
rotation_element = "tri3"
transform = { translate = [0.0, 0.0, 0.05] }
[shell.material]
model = "plate"
thickness = 1e-3
youngs_modulus = 1e6
poisson_ratio = 0.3
density = 1000.0
length_scale = 1e-3
[contact]
stiffness = 10.0
barrier_width = 1e-3
thickness = 5e-4
[[contact.obstacle]]
name = "floor"
box = { center = [0.0, 0.0, -0.5], size = [2.0, 3.0, 1.0] }
thickness = 0.0
[[contact.obstacle]]
name = "plane"
mesh = { generator = "rectangle", lx = 1.0, ly = 1.0, nx = 1, ny = 1, transform = { rotate = [{ axis = "x", degrees = 90.0 }], translate = [0.0, 0.5, 0.0] } }
motion = { translate = [0.0, "0.1*t", 0.0], rotate = { axis = "z", center = [0.0, 0.5, 0.0], angle = "t" } }
[[contact.friction]]
between = ["sheet", "floor"]
mu = 0.5
[[contact.friction]]
between = ["cloth", "cloth"]
mu = 1.0
"#;

fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data")
}

fn load(text: &str, overrides: &[&str]) -> Result<SceneSpec, String> {
    let overrides: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    SceneSpec::from_str(text, "scene.toml", &data_dir(), &overrides).map_err(|e| e.to_string())
}

fn message(text: &str, overrides: &[&str]) -> String {
    match load(text, overrides) {
        Ok(_) => panic!("accepted: {overrides:?}"),
        Err(e) => e,
    }
}

fn replaced(from: &str, to: &str) -> String {
    assert!(BASE.contains(from), "the base scene has no `{from}`");
    BASE.replacen(from, to, 1)
}

/// Signed volume enclosed by a triangle mesh (divergence theorem); positive for outward normals.
fn enclosed_volume(x: &[Vector3<f64>], triangles: &[[usize; 3]]) -> f64 {
    triangles.iter().map(|t| x[t[0]].dot(&x[t[1]].cross(&x[t[2]])) / 6.0).sum()
}

/// How often each undirected edge occurs.
fn edge_counts(triangles: &[[usize; 3]]) -> BTreeMap<(usize, usize), usize> {
    let mut count = BTreeMap::new();
    for t in triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            *count.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    count
}

#[test]
fn a_scene_without_contact_has_none() {
    let text = BASE.split("[contact]").next().unwrap();
    assert!(load(text, &[]).unwrap().contact.is_none());
}

#[test]
fn the_contact_section_becomes_a_contact_spec() {
    let spec = load(BASE, &[]).unwrap_or_else(|e| panic!("{e}"));
    let c = spec.contact.as_ref().unwrap();
    assert_eq!((c.stiffness, c.barrier_width), (10.0, 1e-3));
    // Defaults.
    assert_eq!((c.stick_velocity, c.project_pd, c.min_gap_fraction), (0.1, true, 0.1));
    // Without surface tables every shell takes part with the default thickness.
    assert_eq!(c.surfaces.len(), 2);
    assert!(c.surfaces.iter().enumerate().all(|(k, s)| s.shell == k && s.thickness == 5e-4));
    assert_eq!(c.obstacles.len(), 2);
    assert_eq!(c.obstacles[0].name, "floor");
    assert_eq!(c.obstacles[0].thickness, 0.0);
    assert!(c.obstacles[0].motion.is_none());
    assert_eq!(c.obstacles[1].thickness, 5e-4);
    assert_eq!(c.friction.len(), 2);
    assert_eq!(c.friction[0].bodies, [ContactBody::Shell(0), ContactBody::Obstacle(0)]);
    assert_eq!(c.friction[0].coefficient, 0.5);
    assert_eq!(c.friction[1].bodies, [ContactBody::Shell(1), ContactBody::Shell(1)]);
    // Overrides reach the section like any other.
    let spec = load(BASE, &["contact.stick_velocity=0.01", "contact.project_pd=false"]).unwrap();
    let c = spec.contact.unwrap();
    assert_eq!((c.stick_velocity, c.project_pd), (0.01, false));
}

#[test]
fn surface_tables_select_shells_and_thicknesses() {
    let text = replaced(
        "[[contact.obstacle]]\nname = \"floor\"",
        "[[contact.surface]]\nshell = \"cloth\"\nthickness = 2e-4\n[[contact.obstacle]]\nname = \"floor\"",
    );
    let text = text.replace("between = [\"sheet\", \"floor\"]", "between = [\"cloth\", \"floor\"]");
    let c = load(&text, &[]).unwrap_or_else(|e| panic!("{e}")).contact.unwrap();
    assert_eq!(c.surfaces.len(), 1);
    assert_eq!((c.surfaces[0].shell, c.surfaces[0].thickness), (1, 2e-4));
}

#[test]
fn a_box_obstacle_is_a_closed_outward_box_of_twelve_triangles() {
    let c = load(BASE, &[]).unwrap().contact.unwrap();
    let floor = &c.obstacles[0];
    assert_eq!((floor.positions.len(), floor.triangles.len()), (8, 12));
    // Closed: every edge shared by exactly two triangles; 18 edges (Euler: V − E + F = 2).
    let edges = edge_counts(&floor.triangles);
    assert_eq!(edges.len(), 18);
    assert!(edges.values().all(|&n| n == 2));
    // Outward normals: the enclosed volume is +2 · 3 · 1 m³, about any origin.
    assert!((enclosed_volume(&floor.positions, &floor.triangles) - 6.0).abs() < 1e-12);
    let shifted: Vec<Vector3<f64>> = floor.positions.iter().map(|p| p + Vector3::new(5.0, -7.0, 3.0)).collect();
    assert!((enclosed_volume(&shifted, &floor.triangles) - 6.0).abs() < 1e-9);
    // The top face is at z = 0 and every vertex is a corner of the box.
    let top = floor.positions.iter().map(|p| p.z).fold(f64::MIN, f64::max);
    assert_eq!(top, 0.0);
    for p in &floor.positions {
        assert!((p.x.abs() - 1.0).abs() < 1e-15 && (p.y.abs() - 1.5).abs() < 1e-15);
    }
    // Each face's two triangles have the face's outward normal.
    for t in &floor.triangles {
        let x = t.map(|v| floor.positions[v]);
        let n = (x[1] - x[0]).cross(&(x[2] - x[0]));
        let centre = (x[0] + x[1] + x[2]) / 3.0 - Vector3::new(0.0, 0.0, -0.5);
        assert!(n.dot(&centre) > 0.0, "inward triangle {t:?}");
    }
    let (p, t) = ObstacleSpec::box_mesh(Vector3::zeros(), Vector3::new(1.0, 2.0, 3.0));
    assert!((enclosed_volume(&p, &t) - 6.0).abs() < 1e-12);
}

#[test]
fn a_mesh_obstacle_uses_the_shell_mesh_steps_and_moves_along_its_script() {
    let c = load(BASE, &[]).unwrap().contact.unwrap();
    let plane = &c.obstacles[1];
    // A 1 × 1 rectangle of 2 triangles turned upright (normal along −y) and moved to y = 0.5.
    assert_eq!((plane.positions.len(), plane.triangles.len()), (4, 2));
    assert!(plane.positions.iter().all(|p| (p.y - 0.5).abs() < 1e-15));
    let z: Vec<f64> = plane.positions.iter().map(|p| p.z).collect();
    assert!(z.iter().all(|z| (z.abs() - 0.5).abs() < 1e-15), "{z:?}");
    // At t = 0 the motion is the identity; at t = π/2 a quarter turn about the vertical axis through
    // (0, 0.5, 0), then a shift of 0.1·t along y.
    let p0 = plane.positions_at(0.0);
    assert!(p0.iter().zip(&plane.positions).all(|(a, b)| (a - b).norm() < 1e-15));
    let t = std::f64::consts::FRAC_PI_2;
    for (moved, rest) in plane.positions_at(t).iter().zip(&plane.positions) {
        let r = rest - Vector3::new(0.0, 0.5, 0.0);
        let expected = Vector3::new(-r.y, r.x, r.z) + Vector3::new(0.0, 0.5 + 0.1 * t, 0.0);
        assert!((moved - expected).norm() < 1e-14, "{moved:?} vs {expected:?}");
    }
}

#[test]
fn an_obj_obstacle_is_read_and_transformed() {
    let text = replaced(
        "box = { center = [0.0, 0.0, -0.5], size = [2.0, 3.0, 1.0] }",
        "mesh = { path = \"octahedron.obj\", transform = { center = true, height = 0.03, translate = [0.0, 0.0, -0.1] } }",
    );
    let c = load(&text, &[]).unwrap_or_else(|e| panic!("{e}")).contact.unwrap();
    let o = &c.obstacles[0];
    assert_eq!((o.positions.len(), o.triangles.len()), (6, 8));
    let (lo, hi) = o
        .positions
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.z), b.max(p.z)));
    assert!((lo + 0.115).abs() < 1e-15 && (hi + 0.085).abs() < 1e-15, "{lo} {hi}");
}

#[test]
fn displace_moves_every_node_including_mid_edge_nodes() {
    let text = replaced(
        "nx = 2\nny = 2\nelement = \"tri6\"",
        "nx = 2\nny = 2\nelement = \"tri6\"\ndisplace = [0.0, 0.0, \"0.01*cos(2*pi*x/0.1)\"]",
    );
    let spec = load(&text, &[]).unwrap_or_else(|e| panic!("{e}"));
    let mesh = &spec.shells[0].mesh;
    let tri6 = mesh.tri6.as_ref().unwrap();
    // Rectangle nodes are flat: after the step z = 0.01 cos(2π x/0.1) at every node.
    for p in tri6.nodes.iter().chain(&mesh.corners.nodes) {
        assert!((p.z - 0.01 * (2.0 * std::f64::consts::PI * p.x / 0.1).cos()).abs() < 1e-15);
    }
    // Mid-edge nodes (x = ±0.025) are at z = 0, corners at x = ±0.05 at −0.01, x = 0 at +0.01.
    assert!(tri6.nodes.iter().any(|p| (p.x - 0.025).abs() < 1e-15 && p.z.abs() < 1e-15));
    // The corner mesh and the Tri6 mesh stay consistent.
    for (v, &node) in mesh.corner_nodes.iter().enumerate() {
        assert_eq!(mesh.corners.nodes[v], tri6.nodes[node]);
    }
    assert_eq!(
        message(&text.replace("cos(2*pi*x/0.1)\"", "cos(2*pi*x/0.1)*t\""), &[]),
        "scene.toml:14: shell.0.mesh.displace.2: a rest-shape displacement depends on the position only, not on `t`"
    );
}

#[test]
fn contact_errors_name_the_field() {
    assert_eq!(
        message(&replaced("stiffness = 10.0", "stiffness = -1.0"), &[]),
        "scene.toml:40: contact.stiffness: must be positive (got -1)"
    );
    assert_eq!(
        message(BASE, &["contact.min_gap_fraction=1.5"]),
        "override `contact.min_gap_fraction=1.5`: contact.min_gap_fraction: must lie in (0, 1) (got 1.5)"
    );
    assert_eq!(
        message(&replaced("barrier_width = 1e-3", "barier_width = 1e-3"), &[]),
        "scene.toml:41: contact.barier_width: unknown field `barier_width`, expected one of `stiffness`, \
         `barrier_width`, `thickness`, `stick_velocity`, `project_pd`, `min_gap_fraction`, `surface`, \
         `obstacle`, `friction`"
    );
    assert_eq!(
        message(&replaced("thickness = 5e-4\n", ""), &[]),
        "scene.toml:39: contact.thickness: no contact thickness: give `thickness` here or a default \
         `contact.thickness`"
    );
    assert_eq!(
        message(
            &replaced("between = [\"sheet\", \"floor\"]", "between = [\"sheet\", \"flor\"]"),
            &[]
        ),
        "scene.toml:52: contact.friction.0.between.1: no shell or obstacle is named `flor` (names: sheet, \
         cloth, floor, plane)"
    );
    assert_eq!(
        message(&replaced("mu = 0.5", "mu = -0.5"), &[]),
        "scene.toml:53: contact.friction.0.mu: must be finite and non-negative (got -0.5)"
    );
    assert_eq!(
        message(
            &replaced("between = [\"cloth\", \"cloth\"]", "between = [\"floor\", \"sheet\"]"),
            &[]
        ),
        "scene.toml:55: contact.friction.1.between: friction between `floor` and `sheet` is set twice"
    );
    assert_eq!(
        message(&replaced("name = \"plane\"", "name = \"cloth\""), &[]),
        "scene.toml:48: contact.obstacle.1.name: `cloth` is already the name of a shell"
    );
    assert_eq!(
        message(&replaced("name = \"plane\"", "name = \"floor\""), &[]),
        "scene.toml:48: contact.obstacle.1.name: the name `floor` is used twice"
    );
    assert_eq!(
        message(
            &replaced(
                "thickness = 0.0\n",
                "thickness = 0.0\nmesh = { path = \"octahedron.obj\" }\n"
            ),
            &[]
        ),
        "scene.toml:47: contact.obstacle.0.mesh: give `box` or `mesh`, not both"
    );
    assert_eq!(
        message(
            &replaced("box = { center = [0.0, 0.0, -0.5], size = [2.0, 3.0, 1.0] }\n", ""),
            &[]
        ),
        "scene.toml:43: contact.obstacle.0: needs a `box = { center, size }` or a `mesh = { … }`"
    );
    assert_eq!(
        message(&replaced("size = [2.0, 3.0, 1.0]", "size = [2.0, 0.0, 1.0]"), &[]),
        "scene.toml:45: contact.obstacle.0.box.size: every edge length must be positive (got [2.0, 0.0, 1.0])"
    );
    assert_eq!(
        message(&replaced("nx = 1, ny = 1,", "nx = 1, ny = 1, element = \"tri6\","), &[]),
        "scene.toml:49: contact.obstacle.1.mesh.element: does not apply to an obstacle (a flat triangle mesh \
         that is not simulated)"
    );
    assert_eq!(
        message(&replaced("angle = \"t\"", "angle = \"ln(t - 0.5)\""), &[]),
        "scene.toml:50: contact.obstacle.1.motion.rotate.angle: `ln(t - 0.5)` evaluates to NaN at t = 0"
    );
    let twice = replaced(
        "[[contact.obstacle]]\nname = \"floor\"",
        "[[contact.surface]]\nshell = \"sheet\"\n[[contact.surface]]\nshell = 0\n[[contact.obstacle]]\nname = \"floor\"",
    );
    assert_eq!(
        message(&twice, &[]),
        "scene.toml:46: contact.surface.1.shell: shell `sheet` is listed twice"
    );
    let not_a_surface = replaced(
        "[[contact.obstacle]]\nname = \"floor\"",
        "[[contact.surface]]\nshell = \"sheet\"\n[[contact.obstacle]]\nname = \"floor\"",
    );
    assert_eq!(
        message(&not_a_surface, &[]),
        "scene.toml:57: contact.friction.1.between.0: shell `cloth` does not take part in contact (see \
         `contact.surface`)"
    );
}

/// A scene of the workspace's `scenes/` directory.
fn scene(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes").join(name)
}

#[test]
fn the_dumpling_scenes_have_the_papers_counts() {
    for (name, shell) in [("dumpling_plate.toml", false), ("dumpling_shell.toml", true)] {
        let spec = SceneSpec::from_file(scene(name), &[]).unwrap_or_else(|e| panic!("{e}"));
        let mesh = &spec.shells[0].mesh;
        let tri6 = mesh.tri6.as_ref().unwrap();
        // [S]: 1536 cells, 9411 displacement and 2403 rotation DOFs.
        assert_eq!(tri6.elements.len(), 1536);
        assert_eq!((tri6.nodes.len(), mesh.corners.nodes.len()), (3137, 801));
        assert!(tri6.nodes.iter().all(|p| (p.norm() - 1.0).abs() < 1e-14 && p.z >= -1e-15));
        assert_eq!(
            spec.shells[0].rest.model.model == cosserat_material::ShellModel::Shell,
            shell
        );
        // The equator (64 corner segments: 128 Tri6 nodes) is held, the pole's frame turns.
        assert_eq!(spec.boundaries[0].selection.disp_nodes.len(), 128);
        let pole = &spec.boundaries[1];
        assert_eq!(pole.selection.rot_nodes.len(), 1);
        assert_eq!(pole.rotation.map(|r| r.1), Some([true; 3]));
        let (_, _, angle) = pole.motion.rotation.as_ref().unwrap();
        assert!((angle.eval(2.0) - std::f64::consts::PI).abs() < 1e-15);
        assert!((angle.eval(5.0) - 2.0 * std::f64::consts::PI).abs() < 1e-15);
        let c = spec.contact.as_ref().unwrap();
        assert_eq!((c.surfaces[0].thickness, c.obstacles.len()), (5e-3, 0));
        assert_eq!(c.friction[0].bodies, [ContactBody::Shell(0); 2]);
        assert_eq!(c.friction[0].coefficient, 1.0);
    }
}

#[test]
fn the_papyrus_scroll_scene_has_the_wavy_sheet_boxes_and_floor() {
    let spec = SceneSpec::from_file(scene("papyrus_scroll.toml"), &[]).unwrap_or_else(|e| panic!("{e}"));
    let mesh = &spec.shells[0].mesh;
    let tri6 = mesh.tri6.as_ref().unwrap();
    // [S]: 400 cells, 2583 displacement and 693 rotation DOFs.
    assert_eq!(
        (tri6.elements.len(), tri6.nodes.len(), mesh.corners.nodes.len()),
        (400, 861, 231)
    );
    // The wave: the lowest node at −5.86 mm (experiments.md §2.11).
    let lowest = tri6.nodes.iter().map(|p| p.z).fold(f64::MAX, f64::min);
    assert!((lowest + 5.86e-3).abs() < 1e-5, "lowest node at {lowest}");
    assert_eq!(spec.boundaries.len(), 2);
    for (b, y) in spec.boundaries.iter().zip([0.125, -0.125]) {
        let node = tri6.nodes[b.selection.disp_nodes[0]];
        assert_eq!(b.selection.disp_nodes.len(), 1);
        assert!(node.x.abs() < 1e-15 && (node.y - y).abs() < 1e-15);
    }
    let c = spec.contact.as_ref().unwrap();
    assert_eq!(c.obstacles.len(), 4);
    let floor_top = c.obstacles[0].positions.iter().map(|p| p.z).fold(f64::MIN, f64::max);
    assert!((floor_top + 0.0065).abs() < 1e-15);
    // Every box descends from z = 0.5 to 0.016 between 6 and 8 s, then slides to its x target.
    for (o, (x0, x1)) in c.obstacles[1..]
        .iter()
        .zip([(0.003688, -0.15362), (0.0, 0.12337), (-0.003688, -0.2163)])
    {
        assert!(o.motion.is_some());
        let centre = |t: f64| {
            let p = o.positions_at(t);
            let (lo, hi) = p
                .iter()
                .fold((Vector3::repeat(f64::MAX), Vector3::repeat(f64::MIN)), |(a, b), x| {
                    (a.inf(x), b.sup(x))
                });
            ((lo + hi) * 0.5, hi.z - lo.z)
        };
        let (c0, height) = centre(0.0);
        assert!((height - 0.03).abs() < 1e-12);
        assert!((c0 - Vector3::new(x0, c0.y, 0.5)).norm() < 1e-12);
        let (c1, _) = centre(8.5);
        assert!((c1 - Vector3::new(x0, c0.y, 0.016)).norm() < 1e-12);
        let (c2, _) = centre(12.0);
        assert!((c2 - Vector3::new(x1, c0.y, 0.016)).norm() < 1e-12);
    }
    assert_eq!(c.friction.len(), 1);
    assert_eq!(c.friction[0].bodies, [ContactBody::Shell(0), ContactBody::Obstacle(0)]);
    assert_eq!(c.friction[0].coefficient, 1.0);
    assert_eq!(spec.rest_fields[0].curvature.len(), 2);
}

#[test]
fn the_bunny_scene_reads_its_mesh_and_takes_thickness_overrides() {
    let spec = SceneSpec::from_file(
        scene("bunny.toml"),
        &[
            "material.thickness=0.0015".into(),
            "material.length_scale=0.00075".into(),
        ],
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(spec.shells[0].material.thickness, 0.0015);
    let x = &spec.shells[0].mesh.tri6.as_ref().unwrap().nodes;
    let (lo, hi) = x.iter().fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.z), b.max(p.z)));
    assert!((lo + 0.1).abs() < 1e-12 && (hi - 0.1).abs() < 1e-12);
    // [S]: 6612 cells, 39678 displacement and 9924 rotation DOFs.
    assert_eq!((x.len(), spec.shells[0].mesh.corners.n_nodes()), (13226, 3308));
    let c = spec.contact.as_ref().unwrap();
    let floor = &c.obstacles[0];
    let top = floor.positions.iter().map(|p| p.z).fold(f64::MIN, f64::max);
    // The floor's top lies one contact distance (2 × 0.05 mm) plus 0.1 mm below the lowest point.
    assert!((top - (lo - 2e-4)).abs() < 1e-12, "floor top {top}");
    assert_eq!(c.friction[0].bodies, [ContactBody::Shell(0); 2]);
}
