//! `cargo xtask experiments --quick` as a test: every experiment without contact sets up and runs a
//! few steps, and its check reads the outputs back.

use std::path::PathBuf;

#[test]
fn every_experiment_runs_a_few_steps() {
    let root = cosserat_lab::workspace_root();
    std::env::set_current_dir(&root).unwrap();
    let options = cosserat_lab::experiments::Options {
        quick: true,
        large: false,
        only: None,
        row: None,
        meshes: root.join("assets/meshes"),
        out: PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("experiments_quick"),
        render_dir: None,
        reuse: false,
    };
    let report = cosserat_lab::experiments::run_all(&options).unwrap();
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
    // The lotus scene holds the paper's three layers, each the size of the paper's one-layer run.
    assert!(
        report.markdown.contains("lotus_flower 4x4: 3 copies of the paper's 32 cells"),
        "{}",
        report.markdown
    );
    // Asked to reuse, a second pass takes the complete runs it just made instead of running them.
    let again = cosserat_lab::experiments::Options {
        only: Some("twisting_strip".into()),
        reuse: true,
        ..options
    };
    let report = cosserat_lab::experiments::run_all(&again).unwrap();
    assert!(report.failures.is_empty(), "{:?}", report.failures);
    assert!(
        report.markdown.contains("| - † | twisting_strip |"),
        "{}",
        report.markdown
    );
    assert!(report.markdown.contains("reused (`--reuse`)"), "{}", report.markdown);
}
