//! Atomic writes: full content, errors naming the path, no temporary file left behind.

use std::path::Path;

use cosserat_io::{OutputError, write_atomic};

use super::{entries, test_dir};

#[test]
fn written_file_has_the_full_content_and_no_temporary_remains() {
    let dir = test_dir("atomic_full_content");
    let path = dir.join("data.bin");
    let contents: Vec<u8> = (0..1_000_003u32).map(|i| (i * 31 % 251) as u8).collect();
    write_atomic(&path, &contents).expect("write succeeds");
    assert_eq!(std::fs::read(&path).expect("read back"), contents);
    assert_eq!(entries(&dir), vec!["data.bin".to_owned()]);
}

#[test]
fn rewriting_replaces_the_whole_file() {
    let dir = test_dir("atomic_rewrite");
    let path = dir.join("summary.json");
    write_atomic(&path, &[b'x'; 4096]).expect("first write");
    write_atomic(&path, b"short").expect("second write");
    assert_eq!(std::fs::read(&path).expect("read back"), b"short");
    assert_eq!(entries(&dir), vec!["summary.json".to_owned()]);
}

#[test]
fn missing_directory_is_an_error_naming_the_path() {
    let dir = test_dir("atomic_missing_dir");
    let path = dir.join("does_not_exist").join("frame.vtu");
    let error = write_atomic(&path, b"content").expect_err("the directory is missing");
    match &error {
        OutputError::Io {
            path: reported, source, ..
        } => {
            assert_eq!(reported, &path);
            assert_eq!(source.kind(), std::io::ErrorKind::NotFound);
        }
        other => panic!("expected an I/O error, got {other:?}"),
    }
    assert!(
        error.to_string().contains(&path.display().to_string()),
        "message: {error}"
    );
    assert!(entries(&dir).is_empty());
}

#[test]
fn path_without_file_name_is_refused() {
    let error = write_atomic(Path::new(".."), b"content").expect_err("no file name");
    assert!(matches!(error, OutputError::NotAFilePath { .. }), "{error:?}");
}
