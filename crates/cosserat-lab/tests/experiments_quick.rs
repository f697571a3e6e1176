//! `cargo xtask experiments --quick` as a test: every experiment without contact sets up and runs a
//! few steps, and its check reads the outputs back.

use std::path::PathBuf;

#[test]
fn every_experiment_runs_a_few_steps() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).parent().unwrap().to_path_buf();
    std::env::set_current_dir(&root).unwrap();
    let options = xtask::experiments::Options {
        quick: true,
        large: false,
        only: None,
        meshes: root.join("assets/meshes"),
        out: PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("experiments_quick"),
        render_dir: None,
    };
    let report = xtask::experiments::run_all(&options).unwrap();
    assert!(report.failures.is_empty(), "{:?}", report.failures);
    for name in [
        "twisting_strip",
        "plate_under_load",
        "cylinder_coiling",
        "lotus_flower",
        "curvature_modes",
        "buckling_circle",
        "moebius",
    ] {
        assert!(
            report.markdown.contains(&format!("| {name} |")),
            "{name} missing from the report"
        );
    }
}
