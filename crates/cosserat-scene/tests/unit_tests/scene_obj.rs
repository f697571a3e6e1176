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
fn a_triangle_too_large_for_its_area_is_not_called_collinear() {
    let text = "v 1e300 0 0\nv 0 1e300 0\nv -1e300 -1e300 0\nf 1 2 3\n";
    let err = parse_obj(text, Path::new("huge.obj")).unwrap_err();
    assert!(
        matches!(err, ObjError::DegenerateFace { line: 4, face: 0, .. }),
        "{err:?}"
    );
    let message = err.to_string();
    assert!(
        message.contains("overflows") && !message.contains("collinear"),
        "{message}"
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
fn a_doubled_triangle_is_rejected_with_both_lines() {
    // The second face repeats the first (reversed): each edge has two faces, yet there is no surface.
    let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\nf 3 2 1\n";
    let err = parse_obj(text, Path::new("doubled.obj")).unwrap_err();
    assert!(
        matches!(
            err,
            ObjError::DuplicateFace {
                line: 5,
                face: 1,
                first_line: 4,
                first: 0,
                ..
            }
        ),
        "{err:?}"
    );
    assert!(
        err.to_string()
            .starts_with("`doubled.obj` line 5: face 1 has the same three vertices as face 0 (line 4)"),
        "{err}"
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

#[test]
fn a_vertex_weight_other_than_one_is_refused_with_its_line() {
    let path = Path::new("weighted.obj");
    let triangle = |second: &str| format!("v 0 0 0\n{second}\nv 0 1 0\nf 1 2 3\n");
    let err = parse_obj(&triangle("v 1 0 0 0.5"), path).unwrap_err();
    assert_eq!(
        err.to_string(),
        "`weighted.obj` line 2: the vertex has the weight w = 0.5; only w = 1 is supported (a rational vertex \
         cannot be a node of a triangle mesh)"
    );
    // With a colour after the weight.
    let err = parse_obj(&triangle("v 1 0 0 2 0.1 0.2 0.3"), path).unwrap_err();
    assert!(
        matches!(err, ObjError::Parse { line: 2, ref reason, .. } if reason.contains("w = 2")),
        "{err}"
    );
    let err = parse_obj(&triangle("v 1 0 0 1 0"), path).unwrap_err();
    assert!(err.to_string().contains("line 2: a vertex is `v x y z`"), "{err}");
    // A weight of 1 (to round-off) and a colour alone are read as the plain position.
    for second in [
        "v 1 0 0 1",
        "v 1 0 0 1.0000000000001",
        "v 1 0 0 0.5 0.5 0.5",
        "v 1 0 0 1 0.5 0.5 0.5",
    ] {
        let obj = parse_obj(&triangle(second), path).unwrap_or_else(|e| panic!("{second}: {e}"));
        assert_eq!(obj.mesh.nodes[1], Vector3::x(), "{second}");
    }
}

/// Two unit squares side by side, written as two pieces: the shared edge's vertices appear twice.
const SPLIT: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 1 0 0\nv 1 1 0\nv 2 0 0\nv 2 1 0\n\
                     f 1 2 3\nf 1 3 4\nf 5 7 8\nf 5 8 6\n";

#[test]
fn coincident_vertices_are_reported_and_can_be_welded() {
    let path = Path::new("split.obj");
    let obj = parse_obj(SPLIT, path).unwrap();
    let warnings = obj.warnings(path);
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(
        warnings[0].starts_with("`split.obj`: 2 vertices lie exactly on earlier ones (first: line 5 on line 2)"),
        "{}",
        warnings[0]
    );
    let (welded, merged) = obj.welded(1e-9, path).unwrap();
    assert_eq!(merged, 2);
    assert_eq!(welded.mesh.n_nodes(), 6);
    assert_eq!(welded.mesh.elements, [[0, 1, 2], [0, 2, 3], [1, 4, 5], [1, 5, 2]]);
    assert_eq!(welded.vertex_lines, [1, 2, 3, 4, 7, 8]);
    assert!(welded.warnings(path).is_empty());
    // A tolerance that merges the corners of a face is an error on that face's line.
    let err = obj.welded(1.5, path).unwrap_err();
    assert!(matches!(err, ObjError::DegenerateFace { line: 9, .. }), "{err:?}");
}

#[test]
fn bowtie_vertices_are_reported() {
    let path = Path::new("bowtie.obj");
    let bowtie = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv -1 0 0\nv 0 -1 0\nf 1 2 3\nf 1 4 5\n";
    let warnings = parse_obj(bowtie, path).unwrap().warnings(path);
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(
        warnings[0].contains("1 vertices join faces that share no edge there (first: line 1)"),
        "{}",
        warnings[0]
    );
    // A fan around a vertex is no bowtie.
    assert!(
        parse_obj(SPLIT, path)
            .unwrap()
            .welded(1e-9, path)
            .unwrap()
            .0
            .warnings(path)
            .is_empty()
    );
}

#[test]
fn a_scene_welds_when_asked_and_warns_when_not() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("obj_weld");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("split.obj"), SPLIT).unwrap();
    let scene = |weld: &str| {
        format!(
            "name = \"w\"\n[time]\ndt = 0.01\nend = 0.1\n[mesh]\npath = \"split.obj\"\n{weld}\n[material]\nmodel = \"plate\"\n\
             thickness = 1e-3\nyoungs_modulus = 1e6\npoisson_ratio = 0.3\ndensity = 1000.0\nlength_scale = 1e-4\n"
        )
    };
    let spec = cosserat_scene::spec::SceneSpec::from_str(&scene(""), "w.toml", &dir, &[]).unwrap();
    assert_eq!(spec.warnings.len(), 1);
    assert_eq!(spec.shells[0].mesh.corners.n_nodes(), 8);
    let spec = cosserat_scene::spec::SceneSpec::from_str(&scene("weld = 1e-6"), "w.toml", &dir, &[]).unwrap();
    assert!(spec.warnings.is_empty(), "{:?}", spec.warnings);
    assert_eq!(spec.shells[0].mesh.corners.n_nodes(), 6);
    let err = cosserat_scene::spec::SceneSpec::from_str(&scene("weld = -1.0"), "w.toml", &dir, &[]).unwrap_err();
    assert_eq!(err.to_string(), "w.toml:7: mesh.weld: must be positive (got -1)");
    // A distance longer than the faces collapses them: the weld is at fault, not the file.
    let err = cosserat_scene::spec::SceneSpec::from_str(&scene("weld = 10.0"), "w.toml", &dir, &[]).unwrap_err();
    assert_eq!(err.field(), Some("mesh.weld"), "{err}");
    assert!(
        err.to_string()
            .starts_with("w.toml:7: mesh.weld: merging the vertices closer than 1e1 m breaks the mesh: `"),
        "{err}"
    );
}
