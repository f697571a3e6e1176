//! `cosserat intersections DIR`: the exact test over every written frame.

use cosserat::intersections::intersections_in_frames;
use cosserat::io::{PvdEntry, VtuFrame, write_pvd, write_vtu};
use std::path::PathBuf;

/// Two triangles: the second lies `lift` above the first's plane, tilted so that it pierces the first
/// when `lift` is small.
fn pair(lift: f64, time: f64) -> VtuFrame {
    let points = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.2, 0.2, lift - 0.5],
        [0.3, 0.2, lift + 0.5],
        [0.2, 0.3, lift + 0.5],
    ];
    VtuFrame::new(points, vec![[0, 1, 2], [3, 4, 5]], time)
}

/// A run folder with the frames given.
fn run_with(name: &str, frames: &[VtuFrame]) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("intersections").join(name);
    let folder = dir.join("frames");
    std::fs::create_dir_all(&folder).unwrap();
    let mut entries = Vec::new();
    for (k, f) in frames.iter().enumerate() {
        let file = format!("frame_{k:05}.vtu");
        write_vtu(&folder.join(&file), f).unwrap();
        entries.push(PvdEntry { time: f.time, file });
    }
    write_pvd(&folder.join("run.pvd"), &entries).unwrap();
    dir
}

#[test]
fn every_frame_is_tested_and_the_crossing_ones_are_named() {
    // Apart (the tilted triangle's lowest corner 0.5 above the plane), crossing, apart again.
    let dir = run_with("crossing", &[pair(1.0, 0.0), pair(0.0, 0.1), pair(1.0, 0.2)]);
    let found = intersections_in_frames(&dir).unwrap();
    assert_eq!(found.frames, 3);
    assert_eq!(found.crossing.len(), 1, "{found:?}");
    let worst = found.worst().unwrap();
    assert_eq!((worst.index, worst.time, worst.pairs), (1, 0.1, 1));
    let exit = cosserat::cli::main_with_args(["cosserat", "intersections", dir.to_str().unwrap()]);
    assert_eq!(exit, 1);
}

#[test]
fn a_run_without_crossings_passes() {
    let dir = run_with("apart", &[pair(1.0, 0.0), pair(0.6, 0.1)]);
    let found = intersections_in_frames(&dir).unwrap();
    assert_eq!((found.frames, found.crossing.len()), (2, 0));
    let exit = cosserat::cli::main_with_args(["cosserat", "intersections", dir.to_str().unwrap()]);
    assert_eq!(exit, 0);
}

#[test]
fn a_folder_without_frames_is_an_error_naming_the_file() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("intersections").join("empty");
    std::fs::create_dir_all(&dir).unwrap();
    let error = intersections_in_frames(&dir).unwrap_err().to_string();
    assert!(error.contains("run.pvd"), "{error}");
}
