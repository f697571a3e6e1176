//! The `.pvd` collection: all frames in order with their exact times, kept up to date after each frame.

use cosserat_io::pvd::to_pvd_string;
use cosserat_io::{OutputError, PvdEntry, RunWriter, VtuFrame, read_pvd, read_pvd_frame};

use super::test_dir;

fn triangle_frame(time: f64, lift: f64) -> VtuFrame {
    VtuFrame::new(
        vec![[0.0, 0.0, 0.0], [1.0, 0.0, lift], [0.0, 1.0, 0.0]],
        vec![[0, 1, 2]],
        time,
    )
}

/// `(timestep, file)` of every DataSet, parsed with a plain XML parser.
fn listed(pvd: &std::path::Path) -> Vec<(f64, String)> {
    let text = std::fs::read_to_string(pvd).expect("read the collection");
    let document = roxmltree::Document::parse(&text).expect("well-formed XML");
    assert_eq!(document.root_element().attribute("type"), Some("Collection"));
    document
        .descendants()
        .filter(|n| n.has_tag_name("DataSet"))
        .map(|n| {
            let time = n.attribute("timestep").expect("timestep").parse().expect("a number");
            (time, n.attribute("file").expect("file").to_owned())
        })
        .collect()
}

#[test]
fn collection_lists_all_frames_in_order_with_their_times() {
    let dir = test_dir("pvd_lists_frames");
    // Strictly increasing times, including ones whose shortest decimal form is long or tiny.
    let times = [0.0, 1e-7, 0.1, 0.1 + 0.2, 12.5];
    let mut writer = RunWriter::create(&dir, &[] as &[&str]).expect("create");
    for (idx, &t) in times.iter().enumerate() {
        writer.write_frame(&triangle_frame(t, idx as f64)).expect("write frame");
        let listed = listed(&writer.pvd_path());
        assert_eq!(listed.len(), idx + 1, "the collection lists the frames written so far");
        for (k, (time, file)) in listed.iter().enumerate() {
            assert_eq!(time.to_bits(), times[k].to_bits(), "time of frame {k}");
            assert_eq!(file, &format!("frame_{k:05}.vtu"));
            assert!(writer.frames_dir().join(file).is_file(), "{file} exists");
        }
    }
    let entries = read_pvd(&writer.pvd_path()).expect("read_pvd");
    assert_eq!(entries, writer.frames());
}

#[test]
fn a_chosen_frame_is_read_through_the_collection() {
    let dir = test_dir("pvd_chosen_frame");
    let mut writer = RunWriter::create(&dir, &[] as &[&str]).expect("create");
    for k in 0..3 {
        writer
            .write_frame(&triangle_frame(k as f64, 0.5 * k as f64))
            .expect("write frame");
    }
    let frame = read_pvd_frame(&writer.pvd_path(), 2).expect("frame 2");
    assert_eq!(frame, triangle_frame(2.0, 1.0));
    let error = read_pvd_frame(&writer.pvd_path(), 3).expect_err("only three frames");
    assert!(
        matches!(
            error,
            OutputError::FrameIndexOutOfRange {
                frame_idx: 3,
                n_frames: 3,
                ..
            }
        ),
        "{error:?}"
    );
}

#[test]
fn non_finite_times_and_empty_names_are_refused() {
    let nan = [PvdEntry {
        time: f64::NAN,
        file: "frame_00000.vtu".to_owned(),
    }];
    assert!(matches!(to_pvd_string(&nan), Err(OutputError::NonFiniteValue { .. })));
    let unnamed = [PvdEntry {
        time: 0.0,
        file: String::new(),
    }];
    assert!(matches!(to_pvd_string(&unnamed), Err(OutputError::InvalidName { .. })));
}
