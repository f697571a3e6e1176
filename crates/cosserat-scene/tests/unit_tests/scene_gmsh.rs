//! Gmsh MSH 4.1 input, ASCII and binary, written here from the format's specification: 6-node
//! triangles keep their own mid-edge nodes, physical groups become named regions, OBJ groups too, and
//! bad files are reported with their line, byte or element.

use cosserat_scene::error::MeshFileError;
use cosserat_scene::gmsh::{Location, parse_gmsh};
use cosserat_scene::spec::SceneSpec;
use nalgebra::Vector3;
use std::path::{Path, PathBuf};

/// A unit square of two 6-node triangles whose mid-edge nodes are lifted by 0.05 (curved elements),
/// its edge x = 0 a 3-node line in the physical curve "clamp", the triangles in the surface "shell".
/// Node tags are 10, 20, … so that tags and indices differ.
struct Patch {
    nodes: Vec<(u64, [f64; 3])>,
    line: (u64, [u64; 3]),
    triangles: Vec<(u64, [u64; 6])>,
}

fn patch() -> Patch {
    let lift = 0.05;
    let coords = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.5, 0.0, lift],
        [1.0, 0.5, lift],
        [0.5, 0.5, lift],
        [0.5, 1.0, lift],
        [0.0, 0.5, lift],
    ];
    let t = |k: u64| 10 * k;
    Patch {
        nodes: coords.iter().enumerate().map(|(i, p)| (t(i as u64 + 1), *p)).collect(),
        line: (1, [t(4), t(1), t(9)]),
        triangles: vec![
            (2, [t(1), t(2), t(3), t(5), t(6), t(7)]),
            (3, [t(1), t(3), t(4), t(7), t(8), t(9)]),
        ],
    }
}

const NAMES: &str = "$PhysicalNames\n2\n1 1 \"clamp\"\n2 2 \"shell\"\n$EndPhysicalNames\n";

fn ascii(p: &Patch) -> String {
    let mut s = String::from("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n");
    s += NAMES;
    s += "$Entities\n0 1 1 0\n1 0 0 0 0 1 0.05 1 1 2 4 -1\n1 0 0 0 1 1 0.05 1 2 0\n$EndEntities\n";
    s += &format!(
        "$Nodes\n1 {n} 10 {m}\n2 1 0 {n}\n",
        n = p.nodes.len(),
        m = 10 * p.nodes.len()
    );
    for (t, _) in &p.nodes {
        s += &format!("{t}\n");
    }
    for (_, x) in &p.nodes {
        s += &format!("{} {} {}\n", x[0], x[1], x[2]);
    }
    s += "$EndNodes\n$Elements\n2 3 1 3\n1 1 8 1\n";
    s += &format!("{} {} {} {}\n", p.line.0, p.line.1[0], p.line.1[1], p.line.1[2]);
    s += &format!("2 1 9 {}\n", p.triangles.len());
    for (t, n) in &p.triangles {
        s += &format!("{t} {}\n", n.map(|k| k.to_string()).join(" "));
    }
    s += "$EndElements\n";
    s
}

fn binary(p: &Patch) -> Vec<u8> {
    let mut b: Vec<u8> = b"$MeshFormat\n4.1 1 8\n".to_vec();
    b.extend(1i32.to_le_bytes());
    b.extend(b"\n$EndMeshFormat\n");
    b.extend(NAMES.as_bytes());
    let int = |b: &mut Vec<u8>, v: i32| b.extend(v.to_le_bytes());
    let size = |b: &mut Vec<u8>, v: u64| b.extend(v.to_le_bytes());
    let float = |b: &mut Vec<u8>, v: f64| b.extend(v.to_le_bytes());
    b.extend(b"$Entities\n");
    for n in [0, 1, 1, 0] {
        size(&mut b, n);
    }
    // The curve: tag, box, one physical tag, two bounding points.
    int(&mut b, 1);
    for v in [0.0, 0.0, 0.0, 0.0, 1.0, 0.05] {
        float(&mut b, v);
    }
    size(&mut b, 1);
    int(&mut b, 1);
    size(&mut b, 2);
    int(&mut b, 4);
    int(&mut b, -1);
    // The surface: tag, box, one physical tag, no bounding curves.
    int(&mut b, 1);
    for v in [0.0, 0.0, 0.0, 1.0, 1.0, 0.05] {
        float(&mut b, v);
    }
    size(&mut b, 1);
    int(&mut b, 2);
    size(&mut b, 0);
    b.extend(b"\n$EndEntities\n$Nodes\n");
    for v in [1, p.nodes.len() as u64, 10, 10 * p.nodes.len() as u64] {
        size(&mut b, v);
    }
    int(&mut b, 2);
    int(&mut b, 1);
    int(&mut b, 0);
    size(&mut b, p.nodes.len() as u64);
    for (t, _) in &p.nodes {
        size(&mut b, *t);
    }
    for (_, x) in &p.nodes {
        x.iter().for_each(|&c| float(&mut b, c));
    }
    b.extend(b"\n$EndNodes\n$Elements\n");
    for v in [2, 3, 1, 3] {
        size(&mut b, v);
    }
    for v in [1, 1, 8] {
        int(&mut b, v);
    }
    size(&mut b, 1);
    size(&mut b, p.line.0);
    p.line.1.iter().for_each(|&n| size(&mut b, n));
    for v in [2, 1, 9] {
        int(&mut b, v);
    }
    size(&mut b, p.triangles.len() as u64);
    for (t, n) in &p.triangles {
        size(&mut b, *t);
        n.iter().for_each(|&k| size(&mut b, k));
    }
    b.extend(b"\n$EndElements\n");
    b
}

#[test]
fn ascii_and_binary_files_give_the_same_mesh_and_groups() {
    let p = patch();
    let a = parse_gmsh(ascii(&p).as_bytes(), Path::new("patch.msh")).unwrap_or_else(|e| panic!("{e}"));
    let b = parse_gmsh(&binary(&p), Path::new("patch.msh")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(a, b);
    // Corner vertices in node order: tags 10, 20, 30, 40.
    assert_eq!(a.mesh.nodes[3], Vector3::new(0.0, 1.0, 0.0));
    assert_eq!(a.mesh.elements, [[0, 1, 2], [0, 2, 3]]);
    assert_eq!(a.element_tags, [2, 3]);
    let mid = a.mid_edge.as_ref().unwrap();
    assert_eq!(mid.len(), 5);
    assert_eq!(mid[&[0, 3]], Vector3::new(0.0, 0.5, 0.05));
    let names: Vec<(&str, usize, &[usize])> = a
        .groups
        .iter()
        .map(|g| (g.name.as_str(), g.dim, g.vertices.as_slice()))
        .collect();
    assert_eq!(names, [("clamp", 1, &[0, 3][..]), ("shell", 2, &[0, 1, 2, 3][..])]);
}

fn scene_dir(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("scene_gmsh").join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn scene(mesh_path: &str, region: &str) -> String {
    format!(
        "name = \"patch\"\n[time]\nmode = \"quasi_static\"\nn_levels = 1\n[mesh]\npath = \"{mesh_path}\"\n\
         element = \"tri6\"\nrotation_element = \"tri3\"\n[material]\nmodel = \"shell\"\nthickness = 0.01\n\
         youngs_modulus = 1e6\npoisson_ratio = 0.3\ndensity = 1000.0\nlength_scale = 1e-3\n\
         [[boundary]]\nname = \"clamp\"\nregion = {region}\nposition = {{ exact = true }}\n"
    )
}

/// Through a scene: the Tri6 nodes are the file's (the lifted mid-edge nodes, not chord midpoints),
/// and `group = "clamp"` selects the clamped edge's two corners and its mid-edge node.
#[test]
fn a_six_node_gmsh_mesh_keeps_its_nodes_and_its_groups_select_regions() {
    let dir = scene_dir("groups");
    std::fs::write(dir.join("patch.msh"), binary(&patch())).unwrap();
    let text = scene("patch.msh", "{ group = \"clamp\" }");
    let spec = SceneSpec::from_str(&text, "patch.toml", &dir, &[]).unwrap_or_else(|e| panic!("{e}"));
    let tri6 = spec.shells[0].mesh.tri6.as_ref().unwrap();
    let lifted = tri6.nodes.iter().filter(|x| x.z == 0.05).count();
    assert_eq!(lifted, 5, "every mid-edge node is the file's");
    let clamp: Vec<Vector3<f64>> = spec.boundaries[0].selection.disp_nodes.iter().map(|&i| tri6.nodes[i]).collect();
    assert_eq!(clamp.len(), 3);
    assert!(clamp.iter().all(|x| x.x == 0.0));
    let err = SceneSpec::from_str(&scene("patch.msh", "{ group = \"clmap\" }"), "patch.toml", &dir, &[]).unwrap_err();
    let msg = err.to_string();
    assert!(
        msg.contains("no group `clmap`") && msg.contains("clamp, shell"),
        "{msg}"
    );
}

#[test]
fn obj_groups_select_regions() {
    let dir = scene_dir("obj_groups");
    let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\ng left\nf 1 2 3\nf 1 3 4\ng right\nf 2 5 3\n";
    std::fs::write(dir.join("two.obj"), obj).unwrap();
    let text = scene("two.obj", "{ group = \"right\" }").replace("element = \"tri6\"", "element = \"tri3\"");
    let spec = SceneSpec::from_str(&text, "two.toml", &dir, &[]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(spec.boundaries[0].selection.disp_nodes, [1, 2, 4]);
}

fn parse_error(bytes: &[u8]) -> (Location, String) {
    match parse_gmsh(bytes, Path::new("bad.msh")).unwrap_err() {
        MeshFileError::Parse { at, reason, .. } => (at, reason),
        other => panic!("{other}"),
    }
}

#[test]
fn bad_files_name_the_line_byte_or_element() {
    let p = patch();
    let text = ascii(&p);
    let (at, reason) = parse_error(text.replace("4.1 0 8", "2.2 0 8").as_bytes());
    assert_eq!(at, Location::Line(2));
    assert!(reason.contains("version 2.2") && reason.contains("4.1"), "{reason}");
    // A quadrangle block (type 3).
    let quads = text.replace("2 1 9 2\n2 10", "2 1 3 2\n2 10");
    let (at, reason) = parse_error(quads.as_bytes());
    assert_eq!(at, Location::Element(2));
    assert!(reason.contains("type 3"), "{reason}");
    // A coordinate that is not a number, on the line of node 30's coordinates.
    let lines: Vec<&str> = text.lines().collect();
    let line = lines.iter().position(|l| *l == "1 1 0").unwrap() + 1;
    let (at, reason) = parse_error(text.replace("\n1 1 0\n", "\n1 one 0\n").as_bytes());
    assert_eq!((at, reason.as_str()), (Location::Line(line), "`one` is not a number"));
    // An element that names a missing node.
    let (at, reason) = parse_error(text.replace("3 10 30 40", "3 10 30 41").as_bytes());
    assert_eq!(at, Location::Element(3));
    assert!(reason.contains("node 41"), "{reason}");
    // Binary data cut short.
    let b = binary(&p);
    let (at, _) = parse_error(&b[..b.len() - 40]);
    assert!(matches!(at, Location::Byte(_)), "{at:?}");
}

/// A mesh that Gmsh itself wrote (Gmsh 4.15.2, the `gmsh` Python wheel), ASCII and binary: the
/// lateral surface of a quarter cylinder of radius 1 and length 1 about z (OpenCASCADE
/// `addCylinder(0, 0, 0, 0, 0, 1, 1, angle = π/2)` with the other faces removed), mesh size 0.4,
/// `setOrder(2)`, the straight edge at y = 0 as the physical curve "clamp" and the surface as
/// "shell". Gmsh puts the second-order nodes on the cylinder, so every node of the Tri6 mesh has radius
/// 1, where chord midpoints would lie inside by up to `1 − cos(h/2R)`.
#[test]
fn a_mesh_written_by_gmsh_keeps_its_curved_nodes_and_groups() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let read = |name: &str| cosserat_scene::gmsh::read_gmsh(&data.join(name)).unwrap_or_else(|e| panic!("{e}"));
    let (ascii, binary) = (read("gmsh_panel_tri6.msh"), read("gmsh_panel_tri6_binary.msh"));
    // Gmsh writes 16 significant digits in ASCII, so the two agree to the last digit or two.
    assert_eq!(
        (&ascii.mesh.elements, &ascii.groups),
        (&binary.mesh.elements, &binary.groups)
    );
    let close = |a: &Vector3<f64>, b: &Vector3<f64>| (a - b).amax() < 1e-15;
    assert!(ascii.mesh.nodes.iter().zip(&binary.mesh.nodes).all(|(a, b)| close(a, b)));
    let (ma, mb) = (ascii.mid_edge.as_ref().unwrap(), binary.mid_edge.as_ref().unwrap());
    assert!(ma.iter().all(|(k, a)| close(a, &mb[k])));
    assert_eq!(ascii.mesh.n_elements(), 32);
    let radius = |x: &Vector3<f64>| x.x.hypot(x.y);
    let mid = ascii.mid_edge.as_ref().unwrap();
    for x in ascii.mesh.nodes.iter().chain(mid.values()) {
        assert!((radius(x) - 1.0).abs() < 1e-12, "{x}");
    }
    let clamp = ascii.groups.iter().find(|g| g.name == "clamp").unwrap();
    assert_eq!((clamp.dim, clamp.vertices.len()), (1, 4));
    assert!(clamp.vertices.iter().all(|&v| ascii.mesh.nodes[v].y.abs() < 1e-12));
    // Through a scene, the clamp selects its 4 corners and the 3 mid-edge nodes between them.
    let text = scene(
        &data.join("gmsh_panel_tri6.msh").display().to_string(),
        "{ group = \"clamp\" }",
    );
    let spec = SceneSpec::from_str(&text, "panel.toml", &data, &[]).unwrap_or_else(|e| panic!("{e}"));
    let tri6 = spec.shells[0].mesh.tri6.as_ref().unwrap();
    assert!(tri6.nodes.iter().all(|x| (radius(x) - 1.0).abs() < 1e-12));
    assert_eq!(spec.boundaries[0].selection.disp_nodes.len(), 7);
}
