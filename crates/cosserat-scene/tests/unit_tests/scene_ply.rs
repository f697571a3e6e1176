//! PLY input: ASCII and binary give the same mesh, integer vertex properties become groups, and bad
//! files are reported with their line or face.

use cosserat_scene::error::MeshFileError;
use cosserat_scene::gmsh::Location;
use cosserat_scene::ply::parse_ply;
use nalgebra::Vector3;
use std::path::Path;

const VERTICES: [([f32; 3], u8); 4] = [
    ([0.0, 0.0, 0.0], 1),
    ([1.0, 0.0, 0.0], 0),
    ([1.0, 1.0, 0.0], 0),
    ([0.0, 1.0, 0.5], 1),
];
const FACES: [[i32; 3]; 2] = [[0, 1, 2], [0, 2, 3]];

fn header(format: &str) -> String {
    format!(
        "ply\nformat {format} 1.0\ncomment a square\nelement vertex 4\nproperty float x\nproperty float y\n\
         property float z\nproperty uchar red\nproperty uchar clamp\nelement face 2\n\
         property list uchar int vertex_indices\nend_header\n"
    )
}

fn ascii() -> String {
    let mut s = header("ascii");
    for (p, c) in VERTICES {
        s += &format!("{} {} {} 255 {c}\n", p[0], p[1], p[2]);
    }
    for f in FACES {
        s += &format!("3 {} {} {}\n", f[0], f[1], f[2]);
    }
    s
}

fn binary(big: bool) -> Vec<u8> {
    let mut b = header(if big {
        "binary_big_endian"
    } else {
        "binary_little_endian"
    })
    .into_bytes();
    for (p, c) in VERTICES {
        for x in p {
            b.extend(if big { x.to_be_bytes() } else { x.to_le_bytes() });
        }
        b.extend([255, c]);
    }
    for f in FACES {
        b.push(3);
        for i in f {
            b.extend(if big { i.to_be_bytes() } else { i.to_le_bytes() });
        }
    }
    b
}

#[test]
fn ascii_and_binary_ply_give_the_same_mesh_and_groups() {
    let a = parse_ply(ascii().as_bytes(), Path::new("square.ply")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(a.mesh.elements, FACES.map(|f| f.map(|i| i as usize)));
    assert_eq!(a.mesh.nodes[3], Vector3::new(0.0, 1.0, 0.5));
    assert_eq!(a.groups.len(), 1, "colour channels are not groups");
    assert_eq!(
        (a.groups[0].name.as_str(), a.groups[0].vertices.as_slice()),
        ("clamp", &[0, 3][..])
    );
    for big in [false, true] {
        let b = parse_ply(&binary(big), Path::new("square.ply")).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(a, b);
    }
}

fn parse_error(bytes: &[u8]) -> (Location, String) {
    match parse_ply(bytes, Path::new("bad.ply")).unwrap_err() {
        MeshFileError::Parse { at, reason, .. } => (at, reason),
        other => panic!("{other}"),
    }
}

#[test]
fn bad_ply_files_name_the_line_or_face() {
    let text = ascii();
    // A quad on the second face line (line 18).
    let (at, reason) = parse_error(text.replace("3 0 2 3", "4 0 2 3 1").as_bytes());
    assert_eq!(at, Location::Element(1));
    assert!(reason.contains("4 vertices"), "{reason}");
    let (at, reason) = parse_error(text.replace("3 0 2 3", "3 0 2 9").as_bytes());
    assert_eq!(at, Location::Line(18));
    assert!(reason.contains("vertex 9"), "{reason}");
    // The second face repeating the first, reversed: a doubled triangle.
    let (at, reason) = parse_error(text.replace("3 0 2 3", "3 2 1 0").as_bytes());
    assert_eq!(at, Location::Line(18));
    assert!(reason.contains("same three corners as the one at line 17"), "{reason}");
    let (at, reason) = parse_error(text.replace("1 1 0 255", "1 x 0 255").as_bytes());
    assert_eq!((at, reason.as_str()), (Location::Line(15), "`x` is not a number"));
    let b = binary(false);
    let (at, _) = parse_error(&b[..b.len() - 3]);
    assert!(matches!(at, Location::Byte(_)), "{at:?}");
}
