//! Goals of the locking issue that the stabilised strain projection reaches, pinned on their named
//! meshes (docs/validation.md has the whole ladders, every interpolation): the pinched hemisphere within
//! 2 % on 8 bands, and the thin Sze 3.1 cantilever (h/L = 1e-3 and 1e-4) within 1 % of the elastica on
//! 20 × 2 quads; the thin cantilever with Regge membrane strains; the goals that Regge membrane strains
//! with stabilised shear and drilling reach (pinched cylinder within 5 % on 32 × 16 and 2 % on 64 × 32,
//! Scordelis–Lo roof within 1 % on 16 × 16, the thin cantilever within 1 % at h/L = 1e-3 and 1e-4); every
//! goal of the course with quadratic rotations and `"regge_stabilized"` on the 3-point rule (the
//! default) and on six points, and the default's thin cantilever down to h/L = 1e-5; and in-plane
//! bending of a strip one element wide. Each run takes a few seconds to a minute in release.

use cosserat::RunDescription;
use cosserat_lab::locking::Row;
use cosserat_lab::obstacle::course;
use cosserat_lab::problem::{Discretisation, Interpolation, Pair};
use cosserat_lab::runner::{Runner, run_described};

fn out(name: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("obstacle").join(name)
}

#[test]
fn stabilized_pinched_hemisphere_is_within_two_percent_on_eight_bands() {
    let root = cosserat_lab::workspace_root();
    std::env::set_current_dir(&root).unwrap();
    let b = course().into_iter().find(|b| b.name == "pinched_hemisphere").unwrap();
    let mesh = b.ladder[1].clone();
    assert!(mesh.label.contains("8 bands"), "{}", mesh.label);
    let mut ov = mesh.overrides;
    ov.push(Interpolation::Stabilized.scene_override());
    ov.push("output.frames=false".into());
    let outcome = run_described(
        &Runner::InProcess,
        &RunDescription::new(b.scene, out("hemisphere"), &ov),
    )
    .unwrap();
    assert!(outcome.is_ok(), "{}", outcome.reason());
    let v = (b.read)(outcome.probes.as_ref().unwrap()).unwrap();
    let error = v / b.reference - 1.0;
    assert!(error.abs() <= 0.02, "radial displacement {v} ({:+.2} %)", 100.0 * error);
}

#[test]
fn stabilized_thin_cantilever_is_within_one_percent_of_the_elastica() {
    let root = cosserat_lab::workspace_root();
    std::env::set_current_dir(&root).unwrap();
    let row = Row::new(Pair::Tri6Tri3, Interpolation::Stabilized, 20, 2);
    let ov = cosserat_lab::locking::overrides(&row, 1e-3);
    let run = RunDescription::new(cosserat_lab::locking::SCENE, out("sze"), &ov);
    let outcome = run_described(&Runner::InProcess, &run).unwrap();
    let ratio = cosserat_lab::locking::deflection_ratio(&outcome).unwrap_or_else(|| panic!("{}", outcome.reason()));
    assert!((ratio - 1.0).abs() <= 0.01, "tip deflection / elastica = {ratio}");
}

/// One run of the locking study's Sze 3.1 cantilever (`row`, `h_over_l`, extra overrides) in `dir`:
/// its tip deflection over the elastica's and its Newton iterations per level.
fn sze_run(row: &Row, h_over_l: f64, extra: &[String], dir: &str) -> (f64, f64) {
    let mut ov = cosserat_lab::locking::overrides(row, h_over_l);
    ov.extend_from_slice(extra);
    let outcome = run_described(
        &Runner::InProcess,
        &RunDescription::new(cosserat_lab::locking::SCENE, out(dir), &ov),
    )
    .unwrap();
    let ratio = cosserat_lab::locking::deflection_ratio(&outcome).unwrap_or_else(|| panic!("{}", outcome.reason()));
    (ratio, outcome.summary.as_ref().unwrap().avg_newton_iterations)
}

#[test]
fn regge_thin_cantilevers_are_within_one_percent_of_the_elastica() {
    let root = cosserat_lab::workspace_root();
    std::env::set_current_dir(&root).unwrap();
    // The default discretisation down to the thin-limit table's h/L = 1e-5, where the relative
    // residual test reaches the round-off floor.
    for (pair, interpolation, thicknesses) in [
        (Pair::Tri6Tri3, Interpolation::Regge, &[1e-3, 1e-4][..]),
        (Pair::Tri6Tri3, Interpolation::ReggeStabilized, &[1e-3, 1e-4][..]),
        (Pair::Tri6Tri6, Interpolation::ReggeStabilized, &[1e-3, 1e-4, 1e-5][..]),
    ] {
        for &h_over_l in thicknesses {
            let row = Row::new(pair, interpolation, 20, 2);
            let dir = format!(
                "sze_{}_{h_over_l:e}",
                Discretisation::new(pair, interpolation).directory()
            );
            let (ratio, _) = sze_run(&row, h_over_l, &[], &dir);
            assert!(
                (ratio - 1.0).abs() <= 0.01,
                "{} h/L = {h_over_l:e}: tip deflection / elastica = {ratio}",
                row.label()
            );
        }
    }
}

/// The mixed-integration-point Newton method (`solver.mixed_integration_points`) reaches the same
/// deflections of thin end-loaded cantilevers with at least 12 % fewer Newton iterations where many
/// are needed (the paper's interpolation at h/L = 1e-3, Regge strains at 1e-4): its Newton matrices
/// leave out the stresses of each step's second-order stretching error.
#[test]
fn mixed_integration_points_cut_the_newton_iterations_of_thin_cantilevers() {
    let root = cosserat_lab::workspace_root();
    std::env::set_current_dir(&root).unwrap();
    for (interpolation, h_over_l) in [(Interpolation::Paper, 1e-3), (Interpolation::ReggeStabilized, 1e-4)] {
        let row = Row::new(Pair::Tri6Tri3, interpolation, 20, 2);
        let run = |mixed: bool| {
            let dir = format!("mip_{}_{h_over_l:e}_{mixed}", interpolation.as_str());
            sze_run(
                &row,
                h_over_l,
                &[format!("solver.mixed_integration_points={mixed}")],
                &dir,
            )
        };
        let (ratio, iterations) = run(false);
        let (mixed_ratio, mixed_iterations) = run(true);
        let label = format!("{} h/L = {h_over_l:e}", interpolation.as_str());
        assert!(
            (mixed_ratio / ratio - 1.0).abs() < 1e-5,
            "{label}: deflections {mixed_ratio} and {ratio}"
        );
        assert!(
            mixed_iterations <= 0.88 * iterations,
            "{label}: {mixed_iterations} Newton iterations per level against {iterations}"
        );
    }
}

/// The error of one obstacle-course benchmark on the ladder rung labelled `mesh`, with a
/// discretisation.
fn course_error(name: &str, mesh: &str, discretisation: Discretisation) -> f64 {
    let b = course().into_iter().find(|b| b.name == name).unwrap();
    let mut ov = b.ladder.iter().find(|m| m.label == mesh).unwrap().overrides.clone();
    ov.extend(discretisation.overrides());
    ov.push("output.frames=false".into());
    let dir = out(&format!("{name}_{mesh}_{}", discretisation.directory()));
    let outcome = run_described(&Runner::InProcess, &RunDescription::new(b.scene, dir, &ov)).unwrap();
    assert!(outcome.is_ok(), "{name} {mesh}: {}", outcome.reason());
    (b.read)(outcome.probes.as_ref().unwrap()).unwrap() / b.reference - 1.0
}

/// Asserts that a discretisation meets each goal `(benchmark, mesh, relative error)` of the course.
fn assert_course_goals(discretisation: Discretisation, goals: &[(&str, &str, f64)]) {
    for &(name, mesh, within) in goals {
        let error = course_error(name, mesh, discretisation);
        assert!(
            error.abs() <= within,
            "{} {name} {mesh}: {:+.2} % (goal {} %)",
            discretisation.label(),
            100.0 * error,
            100.0 * within
        );
    }
}

#[test]
fn regge_stabilized_meets_the_cylinder_and_roof_goals() {
    let root = cosserat_lab::workspace_root();
    std::env::set_current_dir(&root).unwrap();
    assert_course_goals(
        Discretisation::new(Pair::Tri6Tri3, Interpolation::ReggeStabilized),
        &[
            ("pinched_cylinder", "32×16", 0.05),
            ("pinched_cylinder", "64×32", 0.02),
            ("scordelis_lo_roof", "16×16", 0.01),
        ],
    );
}

/// Quadratic rotations with Regge membrane strains and stabilised shear and drilling meet every goal
/// of the obstacle course on its named meshes, on the 3-point rule (the default) and on six points:
/// the pinched hemisphere within 2 % on 8 bands and 1 % on 16, the pinched cylinder within 5 % on
/// 32 × 16 and 2 % on 64 × 32, the Scordelis–Lo roof within 2 % on 8 × 8 and 1 % on 16 × 16.
#[test]
fn quadratic_rotations_with_regge_stabilized_meet_every_course_goal() {
    let root = cosserat_lab::workspace_root();
    std::env::set_current_dir(&root).unwrap();
    let default = Discretisation::DEFAULT;
    for discretisation in [default, default.on_six_points()] {
        assert_course_goals(
            discretisation,
            &[
                ("pinched_hemisphere", "32×10 (8 bands)", 0.02),
                ("pinched_hemisphere", "64×20 (16 bands)", 0.01),
                ("pinched_cylinder", "32×16", 0.05),
                ("pinched_cylinder", "64×32", 0.02),
                ("scordelis_lo_roof", "8×8", 0.02),
                ("scordelis_lo_roof", "16×16", 0.01),
            ],
        );
    }
}

/// In-plane bending of a strip one element wide: the linear variation of the membrane strain across an
/// element carries the whole load, so an interpolation that keeps it must give the beam's deflection
/// on the coarsest mesh. Timoshenko's cantilever (ν = 0, shear factor 5/6):
/// `δ = F L³ / (3 E I) + F L / (κ G A)` with `I = h b³ / 12`, `A = b h`, `G = E / 2`. The stabilised
/// projection scales that variation by `α` and is far too flexible here (docs/model-notes.md), so it
/// is not among the interpolations checked.
#[test]
fn in_plane_bending_of_a_strip_one_element_wide_matches_the_beam() {
    let root = cosserat_lab::workspace_root();
    std::env::set_current_dir(&root).unwrap();
    let scene = "scenes/validation/cantilever_small_load.toml";
    let (l, b, h, e, f): (f64, f64, f64, f64, f64) = (1.0, 0.1, 0.01, 1e9, 1.0);
    let expected = f * l.powi(3) / (3.0 * e * h * b.powi(3) / 12.0) + f * l / (5.0 / 6.0 * 0.5 * e * b * h);
    for discretisation in [
        Discretisation::paper(Pair::Tri6Tri3),
        Discretisation::new(Pair::Tri6Tri3, Interpolation::Regge),
        Discretisation::new(Pair::Tri6Tri3, Interpolation::ReggeStabilized),
        Discretisation::DEFAULT,
    ] {
        let mut ov = vec![
            "mesh.nx=10".into(),
            "mesh.ny=1".into(),
            format!("load.0.force=[0.0, {f}, 0.0]"),
            "output.frames=false".into(),
        ];
        ov.extend(discretisation.overrides());
        let run = RunDescription::new(scene, out(&format!("in_plane_{}", discretisation.directory())), &ov);
        let outcome = run_described(&Runner::InProcess, &run).unwrap();
        assert!(outcome.is_ok(), "{}", outcome.reason());
        let uy = outcome.probes.as_ref().unwrap().last("tip.uy").unwrap();
        let error = uy / expected - 1.0;
        assert!(
            error.abs() <= 0.005,
            "{}: tip deflection {uy:e} against {expected:e} ({:+.2} %)",
            discretisation.label(),
            100.0 * error
        );
    }
}
