//! VTU frames: bit-exact round trip, well-formed XML with the right counts, independent decoding of the
//! binary arrays, refusal of non-finite values and inconsistent data, and reading hand-written files.

use std::path::Path;

use base64::Engine as _;
use base64::engine::general_purpose::STANDARD;
use cosserat_io::vtu::{to_vtu_string, write_vtu};
use cosserat_io::vtu_read::parse_vtu;
use cosserat_io::{DataArray, OutputError, VtuFrame, read_vtu};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::{entries, test_dir};

/// Values that stress a text or binary round trip.
const AWKWARD: [f64; 8] = [
    -0.0,
    5e-324,
    f64::MIN_POSITIVE,
    0.1,
    1.0 / 3.0,
    1e300,
    -f64::MAX,
    f64::EPSILON,
];

/// A random grid-like frame with `n` x `n` points, point vectors and scalars, and cell scalars.
fn sample_frame(n: usize, seed: u64) -> VtuFrame {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut points = Vec::new();
    for j in 0..n {
        for i in 0..n {
            points.push([
                i as f64 + rng.random::<f64>() * 0.1,
                j as f64,
                rng.random::<f64>() - 0.5,
            ]);
        }
    }
    let mut triangles = Vec::new();
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let k = j * n + i;
            triangles.push([k, k + 1, k + n + 1]);
            triangles.push([k, k + n + 1, k + n]);
        }
    }
    let n_points = points.len();
    let mut displacement: Vec<f64> = (0..3 * n_points).map(|_| rng.random::<f64>() * 2.0 - 1.0).collect();
    displacement[..AWKWARD.len()].copy_from_slice(&AWKWARD);
    let mut frame = VtuFrame::new(points, triangles, 0.125 + 1e-17);
    frame.point_data.push(DataArray::new("displacement", 3, displacement));
    frame.point_data.push(DataArray::scalars(
        "angle",
        (0..n_points).map(|_| rng.random::<f64>()).collect(),
    ));
    let n_cells = frame.triangles.len();
    frame.cell_data.push(DataArray::scalars(
        "strain energy",
        (0..n_cells).map(|_| rng.random::<f64>()).collect(),
    ));
    frame
}

fn assert_bit_identical(a: &[f64], b: &[f64], what: &str) {
    assert_eq!(a.len(), b.len(), "{what}: lengths differ");
    for (idx, (x, y)) in a.iter().zip(b).enumerate() {
        assert_eq!(x.to_bits(), y.to_bits(), "{what}[{idx}]: {x:e} != {y:e}");
    }
}

fn assert_frames_bit_identical(a: &VtuFrame, b: &VtuFrame) {
    assert_eq!(a.time.to_bits(), b.time.to_bits(), "time");
    assert_bit_identical(a.points.as_flattened(), b.points.as_flattened(), "points");
    assert_eq!(a.triangles, b.triangles);
    for (arrays_a, arrays_b) in [(&a.point_data, &b.point_data), (&a.cell_data, &b.cell_data)] {
        assert_eq!(arrays_a.len(), arrays_b.len());
        for (x, y) in arrays_a.iter().zip(arrays_b) {
            assert_eq!(x.name, y.name);
            assert_eq!(x.n_components, y.n_components);
            assert_bit_identical(&x.values, &y.values, &x.name);
        }
    }
}

#[test]
fn write_then_read_is_bit_exact() {
    let dir = test_dir("vtu_round_trip");
    let path = dir.join("frame.vtu");
    let frame = sample_frame(6, 1);
    write_vtu(&path, &frame).expect("write");
    let read = read_vtu(&path).expect("read");
    assert_frames_bit_identical(&frame, &read);
}

#[test]
fn awkward_names_and_an_empty_frame_round_trip() {
    let dir = test_dir("vtu_names_empty");
    let mut frame = sample_frame(2, 2);
    frame.point_data[0].name = "a<b & \"c\" 'd'".to_owned();
    let path = dir.join("named.vtu");
    write_vtu(&path, &frame).expect("write");
    assert_frames_bit_identical(&frame, &read_vtu(&path).expect("read"));

    let empty = VtuFrame::new(Vec::new(), Vec::new(), 0.0);
    let path = dir.join("empty.vtu");
    write_vtu(&path, &empty).expect("write");
    assert_frames_bit_identical(&empty, &read_vtu(&path).expect("read"));
}

#[test]
fn xml_is_well_formed_and_declares_the_counts() {
    let frame = sample_frame(4, 3);
    let xml = to_vtu_string(&frame).expect("encode");
    let document = roxmltree::Document::parse(&xml).expect("well-formed XML");
    let root = document.root_element();
    assert_eq!(root.tag_name().name(), "VTKFile");
    assert_eq!(root.attribute("type"), Some("UnstructuredGrid"));
    assert_eq!(root.attribute("byte_order"), Some("LittleEndian"));
    assert_eq!(root.attribute("header_type"), Some("UInt64"));
    let piece = document.descendants().find(|n| n.has_tag_name("Piece")).expect("a Piece");
    assert_eq!(piece.attribute("NumberOfPoints"), Some("16"));
    assert_eq!(piece.attribute("NumberOfCells"), Some("18"));
    let names: Vec<&str> = document
        .descendants()
        .filter(|n| n.has_tag_name("DataArray"))
        .filter_map(|n| n.attribute("Name"))
        .collect();
    assert_eq!(
        names,
        [
            "TimeValue",
            "displacement",
            "angle",
            "strain energy",
            "Points",
            "connectivity",
            "offsets",
            "types"
        ]
    );
}

/// Decodes one inline binary array by hand: base64, a little-endian UInt64 byte count, then the data.
fn decode_array_bytes(xml: &str, name: &str) -> Vec<u8> {
    let document = roxmltree::Document::parse(xml).expect("well-formed XML");
    let node = document
        .descendants()
        .find(|n| n.has_tag_name("DataArray") && n.attribute("Name") == Some(name))
        .expect("the array exists");
    assert_eq!(node.attribute("format"), Some("binary"));
    let bytes = STANDARD.decode(node.text().expect("inline data").trim()).expect("valid base64");
    let declared = u64::from_le_bytes(bytes[..8].try_into().expect("8 header bytes"));
    assert_eq!(declared as usize, bytes.len() - 8, "{name}: header byte count");
    bytes[8..].to_vec()
}

#[test]
fn binary_arrays_decode_independently_of_the_reader() {
    let frame = sample_frame(3, 4);
    let xml = to_vtu_string(&frame).expect("encode");

    let points = decode_array_bytes(&xml, "Points");
    let coordinates: Vec<f64> = points
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")))
        .collect();
    assert_bit_identical(&coordinates, frame.points.as_flattened(), "Points");

    let connectivity = decode_array_bytes(&xml, "connectivity");
    let indices: Vec<i64> = connectivity
        .chunks_exact(8)
        .map(|c| i64::from_le_bytes(c.try_into().expect("8 bytes")))
        .collect();
    let expected: Vec<i64> = frame.triangles.iter().flatten().map(|&i| i as i64).collect();
    assert_eq!(indices, expected);

    let offsets = decode_array_bytes(&xml, "offsets");
    let offsets: Vec<i64> = offsets
        .chunks_exact(8)
        .map(|c| i64::from_le_bytes(c.try_into().expect("8 bytes")))
        .collect();
    assert_eq!(
        offsets,
        (1..=frame.triangles.len() as i64).map(|c| 3 * c).collect::<Vec<_>>()
    );

    assert_eq!(decode_array_bytes(&xml, "types"), vec![5u8; frame.triangles.len()]);

    let time = decode_array_bytes(&xml, "TimeValue");
    assert_eq!(
        f64::from_le_bytes(time.try_into().expect("one f64")).to_bits(),
        frame.time.to_bits()
    );
}

#[test]
fn non_finite_values_are_refused_in_every_array_and_nothing_is_written() {
    let dir = test_dir("vtu_non_finite");
    let path = dir.join("frame.vtu");
    let base = sample_frame(3, 5);
    type Poison = fn(&mut VtuFrame);
    let cases: [(&str, usize, usize, Poison); 5] = [
        ("Points", 4, 2, |f| f.points[4][2] = f64::NAN),
        ("displacement", 7, 1, |f| {
            f.point_data[0].values[7 * 3 + 1] = f64::INFINITY
        }),
        ("angle", 8, 0, |f| f.point_data[1].values[8] = f64::NEG_INFINITY),
        ("strain energy", 3, 0, |f| f.cell_data[0].values[3] = f64::NAN),
        ("TimeValue", 0, 0, |f| f.time = f64::NAN),
    ];
    for (array, tuple, component, poison) in cases {
        let mut frame = base.clone();
        poison(&mut frame);
        match write_vtu(&path, &frame) {
            Err(OutputError::NonFiniteValue {
                array: a,
                tuple: t,
                component: c,
                ..
            }) => {
                assert_eq!((a.as_str(), t, c), (array, tuple, component));
            }
            other => panic!("{array}: expected a non-finite error, got {other:?}"),
        }
        assert!(entries(&dir).is_empty(), "{array}: a file was created");
    }
}

#[test]
fn inconsistent_frames_are_refused() {
    let base = sample_frame(3, 6);

    let mut frame = base.clone();
    frame.triangles[2] = [0, 1, 9];
    assert!(matches!(
        to_vtu_string(&frame),
        Err(OutputError::PointIndexOutOfRange {
            triangle: 2,
            point: 9,
            n_points: 9
        })
    ));

    let mut frame = base.clone();
    frame.point_data[1].values.pop();
    assert!(matches!(
        to_vtu_string(&frame),
        Err(OutputError::ArrayLength {
            expected: 9,
            found: 8,
            ..
        })
    ));

    let mut frame = base.clone();
    frame.point_data[1].name = "displacement".to_owned();
    assert!(matches!(to_vtu_string(&frame), Err(OutputError::DuplicateName { .. })));

    let mut frame = base.clone();
    frame.cell_data[0].name = String::new();
    assert!(matches!(to_vtu_string(&frame), Err(OutputError::InvalidName { .. })));

    let mut frame = base;
    frame.point_data.push(DataArray::new("nothing", 0, Vec::new()));
    assert!(matches!(to_vtu_string(&frame), Err(OutputError::ZeroComponents { .. })));
}

/// A VTU file in the style of other tools: ASCII arrays, 32-bit integers, UInt32 headers, Float32 data.
const HAND_WRITTEN: &str = r#"<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">
  <UnstructuredGrid>
    <FieldData>
      <DataArray type="Float64" Name="TimeValue" NumberOfTuples="1" format="ascii">2.5</DataArray>
    </FieldData>
    <Piece NumberOfPoints="4" NumberOfCells="2">
      <PointData>
        <DataArray type="Float32" Name="u" NumberOfComponents="2" format="ascii">
          0.5 -1 0 0 1 2 3 4
        </DataArray>
      </PointData>
      <Points>
        <DataArray type="Float64" NumberOfComponents="3" format="ascii">
          0 0 0  1 0 0  1 1 0  0 1 0
        </DataArray>
      </Points>
      <Cells>
        <DataArray type="Int32" Name="connectivity" format="ascii">0 1 2 0 2 3</DataArray>
        <DataArray type="Int32" Name="offsets" format="ascii">3 6</DataArray>
        <DataArray type="UInt8" Name="types" format="ascii">5 5</DataArray>
      </Cells>
    </Piece>
  </UnstructuredGrid>
</VTKFile>
"#;

#[test]
fn hand_written_ascii_file_is_read() {
    let frame = parse_vtu(HAND_WRITTEN, Path::new("hand.vtu")).expect("parse");
    assert_eq!(frame.time, 2.5);
    assert_eq!(
        frame.points,
        vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]]
    );
    assert_eq!(frame.triangles, vec![[0, 1, 2], [0, 2, 3]]);
    assert_eq!(
        frame.point_data,
        vec![DataArray::new("u", 2, vec![0.5, -1.0, 0.0, 0.0, 1.0, 2.0, 3.0, 4.0])]
    );
    assert!(frame.cell_data.is_empty());
}

#[test]
fn broken_files_give_errors_naming_the_file() {
    let path = Path::new("broken.vtu");
    let error = parse_vtu("<VTKFile><oops></VTKFile>", path).expect_err("malformed");
    assert!(matches!(error, OutputError::Xml { .. }), "{error:?}");
    assert!(error.to_string().contains("broken.vtu"));

    let nan = HAND_WRITTEN.replace("0.5 -1 0 0", "0.5 nan 0 0");
    let error = parse_vtu(&nan, path).expect_err("NaN in the file");
    match error {
        OutputError::InvalidFrame { source, .. } => {
            assert!(
                matches!(
                    *source,
                    OutputError::NonFiniteValue {
                        tuple: 0,
                        component: 1,
                        ..
                    }
                ),
                "{source:?}"
            )
        }
        other => panic!("expected an invalid frame, got {other:?}"),
    }

    let quad = HAND_WRITTEN.replace(">5 5<", ">5 9<");
    assert!(matches!(parse_vtu(&quad, path), Err(OutputError::Format { .. })));

    let dangling = HAND_WRITTEN.replace("0 1 2 0 2 3", "0 1 2 0 2 4");
    assert!(matches!(parse_vtu(&dangling, path), Err(OutputError::Format { .. })));

    let xml = to_vtu_string(&sample_frame(2, 7)).expect("encode");
    let start = xml.find("Name=\"Points\"").expect("points array");
    let data = start + xml[start..].find('>').expect("end of tag") + 1;
    let mut corrupted = xml.clone();
    corrupted.replace_range(data..data + 4, "!!!!");
    assert!(matches!(parse_vtu(&corrupted, path), Err(OutputError::Base64 { array, .. }) if array == "Points"));

    let missing = read_vtu(Path::new("/nonexistent/dir/frame.vtu")).expect_err("no such file");
    assert!(matches!(missing, OutputError::Io { .. }));
}
