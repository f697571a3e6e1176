//! The paper's first experiment in full (four turns, 400 steps of 10 ms; a few seconds in release): the
//! Newton iterations it needs are the check that the solver's treatment of indefinite Hessians gets
//! through the strip's saddles without halving steps, at no more iterations per step than the paper's
//! Table 1 reports for this row (4.2).

use cosserat::RunDescription;
use cosserat_lab::runner::{Runner, run_described};

#[test]
fn the_twisting_strip_runs_its_four_turns_without_halving_a_step() {
    let root = cosserat_lab::workspace_root();
    std::env::set_current_dir(&root).unwrap();
    let out = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("twisting_strip_full");
    let mut run = RunDescription::new("scenes/twisting_strip.toml", out, &["output.frames=false".into()]);
    run.threads = Some(1);
    let outcome = run_described(&Runner::InProcess, &run).unwrap();
    assert!(outcome.is_ok(), "{}", outcome.reason());
    let summary = outcome.summary.unwrap();
    assert_eq!(summary.n_steps, 400);
    assert_eq!(
        summary.n_step_reductions, 0,
        "{} wasted Newton iterations",
        summary.wasted_newton_iterations
    );
    assert!(
        summary.avg_newton_iterations <= 4.2,
        "{} Newton iterations per step (the paper's Table 1: 4.2)",
        summary.avg_newton_iterations
    );
    // The right end has turned four times, to the end time and not past it.
    let probes = outcome.probes.unwrap();
    let t_end = probes.last("t").unwrap();
    assert!((t_end - 4.0).abs() < 1e-9, "the run ended at t = {t_end}");
}
