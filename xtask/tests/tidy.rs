//! `cargo xtask tidy` as a test: the repository passes its own checks.

use std::path::PathBuf;

#[test]
fn the_repository_is_tidy() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).parent().unwrap().to_path_buf();
    if let Err(e) = xtask::tidy::run(&root) {
        panic!("{e:#}");
    }
}

#[test]
fn a_reference_beside_the_clone_is_found() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("tidy_fixture");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("scenes")).unwrap();
    let needle = ["..", "/shared", "/models/bunny.obj"].concat();
    std::fs::write(dir.join("scenes/a.toml"), format!("[mesh]\npath = \"{needle}\"\n")).unwrap();
    std::fs::create_dir_all(dir.join("target")).unwrap();
    std::fs::write(dir.join("target/ignored.txt"), &needle).unwrap();
    let found = xtask::tidy::references_outside_the_clone(&dir).unwrap();
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(found[0].starts_with("scenes/a.toml:2: path = "), "{found:?}");
}

#[test]
fn a_stale_scene_reference_is_found() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).parent().unwrap().to_path_buf();
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("tidy_stale_docs");
    let _ = std::fs::remove_dir_all(&dir);
    let schema = "crates/cosserat-scene/src/schema";
    std::fs::create_dir_all(dir.join(schema)).unwrap();
    std::fs::create_dir_all(dir.join("docs")).unwrap();
    for file in ["mod.rs", "contact.rs", "value.rs"] {
        std::fs::copy(root.join(schema).join(file), dir.join(schema).join(file)).unwrap();
    }
    xtask::scene_reference::write(&dir).unwrap();
    assert!(xtask::tidy::stale_docs(&dir).unwrap().is_empty());
    // A field documented differently than the page says.
    let path = dir.join(schema).join("mod.rs");
    let text = std::fs::read_to_string(&path).unwrap();
    let changed = text.replacen("/// The scene's name", "/// The name of the scene", 1);
    assert_ne!(text, changed);
    std::fs::write(&path, changed).unwrap();
    let found = xtask::tidy::stale_docs(&dir).unwrap();
    assert_eq!(found.len(), 1, "{found:?}");
}
