//! OBJ input: the file's vertex order, attributes ignored, and every defect reported with its line.

use cosserat_scene::error::ObjError;
use cosserat_scene::obj::{parse_obj, read_obj};
use nalgebra::Vector3;
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data").join(name)
}

#[test]
fn attributes_groups_and_relative_indices_are_read() {
    let obj = read_obj(&data("square_with_attributes.obj")).unwrap();
    assert_eq!(
        obj.mesh.nodes,
        [
            Vector3::zeros(),
            Vector3::x(),
            Vector3::new(1.0, 1.0, 0.0),
            Vector3::y()
        ]
    );
    assert_eq!(obj.mesh.elements, [[0, 1, 2], [0, 2, 3]]);
    assert_eq!(obj.vertex_lines, [5, 6, 7, 8]);
    assert_eq!(obj.face_lines, [16, 17]);
}

#[test]
fn the_closed_fixture_is_valid() {
    let obj = read_obj(&data("octahedron.obj")).unwrap();
    assert_eq!((obj.mesh.n_nodes(), obj.mesh.n_elements()), (6, 8));
}

#[test]
fn a_quad_face_is_rejected_with_its_line() {
    let err = read_obj(&data("quad_face.obj")).unwrap_err();
    assert!(
        matches!(
            err,
            ObjError::NonTriangle {
                line: 8,
                face: 1,
                n_vertices: 4,
                ..
            }
        ),
        "{err:?}"
    );
    assert!(
        err.to_string()
            .ends_with("quad_face.obj` line 8: face 1 has 4 vertices; only triangles are supported"),
        "{err}"
    );
}

#[test]
fn a_degenerate_triangle_is_rejected_with_its_line() {
    let err = read_obj(&data("degenerate_triangle.obj")).unwrap_err();
    assert!(
        matches!(err, ObjError::DegenerateFace { line: 7, face: 1, .. }),
        "{err:?}"
    );
}

#[test]
fn a_non_manifold_edge_is_rejected_with_the_line_of_the_third_face() {
    let err = read_obj(&data("nonmanifold_edge.obj")).unwrap_err();
    assert!(
        matches!(
            err,
            ObjError::NonManifoldEdge {
                line: 9,
                a: 0,
                b: 1,
                n_faces: 3,
                ..
            }
        ),
        "{err:?}"
    );
}

#[test]
fn an_unreferenced_vertex_is_rejected_with_its_line() {
    let err = read_obj(&data("unreferenced_vertex.obj")).unwrap_err();
    assert!(
        matches!(err, ObjError::UnreferencedVertex { line: 5, vertex: 3, .. }),
        "{err:?}"
    );
}

#[test]
fn a_missing_file_names_the_path() {
    let err = read_obj(&data("no_such_mesh.obj")).unwrap_err();
    assert!(matches!(err, ObjError::Read { ref path, .. } if path.ends_with("no_such_mesh.obj")));
}

#[test]
fn malformed_statements_are_rejected_with_their_line() {
    let path = Path::new("inline.obj");
    let cases = [
        ("v 0 0\nf 1 1 1\n", 1, "3 coordinates"),
        ("v 0 0 x\n", 1, "not a finite coordinate"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", 4, "vertex 4 does not exist"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", 4, "start at 1"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 1 2\n", 4, "before the first vertex"),
        ("v 0 0 0\nv 1 0 0\nl 1 2\n", 3, "not supported"),
    ];
    for (text, line, needle) in cases {
        match parse_obj(text, path) {
            Err(ObjError::Parse { line: l, reason, .. }) => {
                assert_eq!(l, line, "{text:?}");
                assert!(reason.contains(needle), "{text:?}: {reason}");
            }
            other => panic!("{text:?}: expected a parse error, got {other:?}"),
        }
    }
    assert!(matches!(parse_obj("v 0 0 0\n", path), Err(ObjError::Empty { .. })));
}
