//! The run directory: layout, removal of stale outputs, frame time order, failure reports.

use std::fs;

use cosserat_io::run::{FRAMES_DIR, PROBES_FILE, PVD_FILE, SUMMARY_FILE, frame_file_name};
use cosserat_io::{
    FrameFormats, OutputError, RunStatus, RunSummary, RunWriter, VtuFrame, read_summary, read_vtu,
    write_failure_summary,
};

use super::{entries, test_dir};

fn frame(time: f64) -> VtuFrame {
    VtuFrame::new(
        vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, time]],
        vec![[0, 1, 2]],
        time,
    )
}

fn ok_summary() -> RunSummary {
    let mut summary = RunSummary::failed("demo", RunStatus::Ok, "unused");
    summary.reason = None;
    summary.n_steps = 2;
    summary
}

#[test]
fn a_run_writes_the_contract_layout() {
    let dir = test_dir("run_layout");
    let mut writer = RunWriter::create(dir.join("out"), &["tip.uz"]).expect("create");
    for (k, t) in [0.0, 0.5, 1.0].into_iter().enumerate() {
        let path = writer.write_frame(&frame(t)).expect("frame");
        assert_eq!(path, dir.join("out").join(FRAMES_DIR).join(frame_file_name(k)));
        writer.write_probes(t, &[t * 2.0]).expect("probes");
    }
    assert_eq!(writer.n_frames(), 3);
    let summary_path = writer.finish(&ok_summary()).expect("finish");

    let out = dir.join("out");
    assert_eq!(entries(&out), [FRAMES_DIR, PROBES_FILE, SUMMARY_FILE]);
    assert_eq!(
        entries(&out.join(FRAMES_DIR)),
        ["frame_00000.vtu", "frame_00001.vtu", "frame_00002.vtu", PVD_FILE]
    );
    assert_eq!(read_summary(&summary_path).expect("summary").status, RunStatus::Ok);
    assert_eq!(
        read_vtu(&out.join(FRAMES_DIR).join("frame_00001.vtu")).expect("frame"),
        frame(0.5)
    );
    let probes = fs::read_to_string(out.join(PROBES_FILE)).expect("probes");
    assert_eq!(probes, "t,tip.uz\n0,0\n0.5,1\n1,2\n");
}

#[test]
fn starting_a_run_removes_only_stale_run_outputs() {
    let dir = test_dir("run_stale");
    let frames = dir.join(FRAMES_DIR);
    fs::create_dir_all(&frames).expect("frames dir");
    for stale in [
        "frame_00007.vtu",
        "frame_123456.vtu",
        PVD_FILE,
        ".frame_00008.vtu.tmp42-1",
    ] {
        fs::write(frames.join(stale), "stale").expect("stale frame file");
    }
    for stale in [SUMMARY_FILE, PROBES_FILE, ".summary.json.tmp42-3"] {
        fs::write(dir.join(stale), "stale").expect("stale file");
    }
    fs::write(dir.join("notes.txt"), "keep").expect("user file");
    fs::write(frames.join("camera.pvsm"), "keep").expect("user file");
    fs::write(frames.join("frame_1.vtu"), "keep").expect("not a name this writer makes");

    let writer = RunWriter::create(&dir, &["a.x"]).expect("create");
    assert_eq!(entries(&dir), [FRAMES_DIR, "notes.txt", PROBES_FILE]);
    assert_eq!(entries(&frames), ["camera.pvsm", "frame_1.vtu"]);
    assert_eq!(fs::read_to_string(writer.probes_path()).expect("probes"), "t,a.x\n");
}

#[test]
fn invalid_probe_columns_leave_an_earlier_run_intact() {
    let dir = test_dir("run_bad_columns");
    let mut writer = RunWriter::create(&dir, &["tip.ux"]).expect("create");
    writer.write_frame(&frame(0.0)).expect("frame");
    writer.finish(&ok_summary()).expect("finish");
    let before = (entries(&dir), entries(&dir.join(FRAMES_DIR)));

    let error = RunWriter::create(&dir, &["tip ux"]).expect_err("malformed column");
    assert!(matches!(error, OutputError::InvalidName { .. }), "{error:?}");
    assert_eq!((entries(&dir), entries(&dir.join(FRAMES_DIR))), before);
}

#[test]
fn frame_times_must_increase_and_bad_frames_are_not_listed() {
    let dir = test_dir("run_times");
    let mut writer = RunWriter::create(&dir, &[] as &[&str]).expect("create");
    writer.write_frame(&frame(1.0)).expect("first frame");
    let error = writer.write_frame(&frame(1.0)).expect_err("same time");
    assert!(
        matches!(error, OutputError::FrameTimeNotIncreasing { frame_idx: 1, .. }),
        "{error:?}"
    );
    assert!(matches!(
        writer.write_frame(&frame(0.5)),
        Err(OutputError::FrameTimeNotIncreasing { .. })
    ));

    let mut bad = frame(2.0);
    bad.points[1][0] = f64::NAN;
    assert!(matches!(
        writer.write_frame(&bad),
        Err(OutputError::NonFiniteValue { .. })
    ));
    assert_eq!(writer.n_frames(), 1);
    assert_eq!(entries(&writer.frames_dir()), ["frame_00000.vtu", PVD_FILE]);
    writer.write_frame(&frame(2.0)).expect("a valid frame after refusals");
    assert_eq!(writer.frames().last().map(|e| e.file.as_str()), Some("frame_00001.vtu"));
}

#[test]
fn a_failed_run_keeps_its_frames_and_probes() {
    let dir = test_dir("run_fail");
    let mut writer = RunWriter::create(&dir, &["tip.ux"]).expect("create");
    for (k, t) in [0.0, 0.1, 0.2].into_iter().enumerate() {
        writer.write_frame(&frame(t)).expect("frame");
        writer.write_probes(t, &[k as f64]).expect("probes");
    }
    let summary = RunSummary::failed("demo", RunStatus::Error, "Newton did not converge at t = 0.25");
    let path = writer.finish(&summary).expect("finish");
    assert_eq!(entries(&dir), [FRAMES_DIR, PROBES_FILE, SUMMARY_FILE]);
    assert_eq!(
        entries(&dir.join(FRAMES_DIR)),
        ["frame_00000.vtu", "frame_00001.vtu", "frame_00002.vtu", PVD_FILE]
    );
    let listed = cosserat_io::read_pvd(&dir.join(FRAMES_DIR).join(PVD_FILE)).expect("pvd");
    assert_eq!(listed.len(), 3);
    let probes = std::fs::read_to_string(dir.join(PROBES_FILE)).expect("probes");
    assert_eq!(probes.lines().count(), 4, "header and three rows: {probes}");
    let read = read_summary(&path).expect("summary");
    assert_eq!(read.status, RunStatus::Error);
    assert_eq!(read.reason.as_deref(), Some("Newton did not converge at t = 0.25"));
}

#[test]
fn failure_summary_helper_touches_nothing_else_and_refuses_ok() {
    let dir = test_dir("run_failure_helper");
    let mut writer = RunWriter::create(&dir, &["tip.ux"]).expect("create");
    writer.write_frame(&frame(0.0)).expect("frame");
    drop(writer);

    let error = write_failure_summary(&dir, &ok_summary()).expect_err("status ok");
    assert!(matches!(error, OutputError::NotAFailure), "{error:?}");
    assert_eq!(entries(&dir), [FRAMES_DIR, PROBES_FILE], "nothing written on refusal");

    let summary = RunSummary::failed("demo", RunStatus::Interrupted, "stopped by the user");
    write_failure_summary(&dir, &summary).expect("failure summary");
    assert_eq!(entries(&dir), [FRAMES_DIR, PROBES_FILE, SUMMARY_FILE]);

    let fresh = dir.join("never_started");
    write_failure_summary(
        &fresh,
        &RunSummary::failed("x", RunStatus::Error, "scene did not validate"),
    )
    .expect("creates the directory");
    assert_eq!(entries(&fresh), [SUMMARY_FILE]);
}

#[test]
fn a_frame_that_fails_halfway_leaves_none_of_its_files() {
    let dir = test_dir("run_frame_fails_halfway");
    let mut writer = RunWriter::create(&dir, &["tip.ux"]).expect("create");
    writer
        .set_formats(FrameFormats {
            obj: true,
            ply: true,
            ..FrameFormats::default()
        })
        .expect("formats");
    writer.write_frame(&frame(0.0)).expect("first frame");
    let frames = writer.frames_dir();
    // A directory where the VTU file goes: its OBJ and PLY siblings are written before the VTU fails,
    // as when a disk fills up between them.
    fs::create_dir(frames.join("frame_00001.vtu")).expect("blocking directory");
    writer.write_frame(&frame(0.5)).expect_err("the VTU file cannot be written");
    let first = ["frame_00000.obj", "frame_00000.ply", "frame_00000.vtu"];
    assert_eq!(entries(&frames), [&first[..], &["frame_00001.vtu", PVD_FILE]].concat());
    fs::remove_dir(frames.join("frame_00001.vtu")).expect("unblock");
    // The collection cannot be rewritten: the frame it would list goes with it.
    fs::remove_file(frames.join(PVD_FILE)).expect("remove the collection");
    fs::create_dir(frames.join(PVD_FILE)).expect("blocking directory");
    writer.write_frame(&frame(0.5)).expect_err("the collection cannot be written");
    assert_eq!(entries(&frames), [&first[..], &[PVD_FILE]].concat());
    assert_eq!(writer.n_frames(), 1);
}
