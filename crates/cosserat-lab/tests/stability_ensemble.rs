//! Every cell of the stability matrix (`cargo xtask stability`, docs/stability.md) as an ensemble of
//! 20 perturbed variants: the clamps' rotation penalty and the time step changed by relative amounts
//! between 1e-7 and 1e-3, on one and two threads alternately. Every variant must complete with finite
//! values and without an inverted element: a cell that completes only for some roundings passes by
//! luck, not by margin. The one exception is named by `stopped_folding`.
//!
//! The study runs the cells at full size; CI runs them shortened (see [`ci_settings`]) so that the
//! ensemble fits the test budget. Each shortening keeps the cell's swept setting and its hard
//! feature: the full turn of the end (a huge rotation through the half turn), the coiling snaps of the
//! multi-turn cells, the thin limit, the slivers and the extreme time steps.

use cosserat_lab::ensemble::{ENSEMBLE_SIZE, VariantFailure, perturbations, run_ensemble};
use cosserat_lab::stability::{Cell, Settings, matrix};
use std::path::PathBuf;

/// The part of the matrix a test runs (the parts are balanced so that the test harness's threads
/// share the work).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Part {
    /// One setting at a time: thickness, material and internal length.
    MaterialSweeps,
    /// One setting at a time: time step, twist, slivers and element pairs.
    ResolutionSweeps,
    /// The corners that need no coiling snap or finish in a few dozen steps.
    QuickCorners,
    /// The ten-turn corners on the coarse 4 × 1 strip without rotational inertia.
    CoarseTenTurns,
    /// The ten-turn corner with rotational inertia.
    RotationalInertia,
    /// Slivers, thin, four turns.
    ThinSlivers,
}

fn part(cell: &Cell) -> Part {
    let s = &cell.settings;
    match cell.group {
        "h/L" | "E [Pa]" | "ν" | "μ_c/μ" | "L_c" => Part::MaterialSweeps,
        "corner" if s.angular_inertia_density > 0.0 => Part::RotationalInertia,
        "corner" if s.turns >= 10.0 => Part::CoarseTenTurns,
        "corner" if s.mesh.1 >= 40 => Part::ThinSlivers,
        "corner" => Part::QuickCorners,
        _ => Part::ResolutionSweeps,
    }
}

/// Turns of the end that the shortened multi-turn cells keep: past the first coiling snap, near 3.8
/// turns, where the unrobust runs of the full matrix stalled (docs/stability.md).
const TURNS_THROUGH_THE_FIRST_SNAP: f64 = 4.5;

/// A cell's settings, shortened for CI. What each change keeps:
/// - a hold of 0.1 s (0.05 s after several turns) instead of 0.5 s: the twist, not the free
///   vibration after it, is what fails; the hold still checks that the held state stays finite;
/// - runs of at most about a hundred steps (dt = 0.1 s) stay whole: the coarse ten-turn cell at
///   dt = 0.1 s runs all its ten turns, whose snaps turn massless rotations through half turns within
///   a step;
/// - one-turn cells on 10 × 2 quads run on 5 × 2: the end still turns a full turn (through the half
///   turn, where the rotation update has to be reflected), with the cell's material, thickness and
///   element pair; the thin cells' elements get longer against the thickness, which makes the thin
///   limit stiffer, not easier;
/// - small time steps run 100 steps of the twist and 50 of the hold: their difficulty, the inertia
///   term of order 1/dt² against a massless rotation field, is the same in every step;
/// - the sliver row keeps aspect 100 on 2 × 20 quads;
/// - ten-turn cells stop after [`TURNS_THROUGH_THE_FIRST_SNAP`] turns, on their own mesh and time step;
/// - the thin four-turn sliver corner keeps its four turns, its thickness and one turn of twist per
///   element along the strip on 4 × 10 quads (aspect 25 instead of 100; the 4 × 40 mesh costs ten
///   times more and its aspect ratio alone is the sliver row's feature).
fn ci_settings(cell: &Cell) -> Settings {
    let s = &cell.settings;
    let mut ci = s.clone();
    let steps = (s.turns + s.hold) / s.dt;
    if steps <= 110.0 {
        return ci;
    }
    ci.hold = if s.turns > 1.0 { 0.05 } else { 0.1 };
    if s.turns > TURNS_THROUGH_THE_FIRST_SNAP {
        ci.turns = TURNS_THROUGH_THE_FIRST_SNAP;
    }
    if s.turns == 1.0 && s.mesh == (10, 2) {
        ci.mesh = (5, 2);
    }
    if s.dt < 0.01 {
        ci.turns = 100.0 * s.dt;
        ci.hold = 50.0 * s.dt;
    }
    if s.mesh == (4, 40) {
        ci.mesh = if s.turns > 1.0 { (4, 10) } else { (2, 20) };
    }
    ci
}

/// Whether a variant of `which` that stopped did so as the coarse ten-turn corners may: past the
/// first coiling snap, at the step that would turn an element inside out. Those corners twist a strip
/// one element wide by 2.5 turns per element, beyond what the mesh can follow through every later snap
/// without folding an element (docs/stability.md, "Coiling"); the solver keeps every element right
/// side out, so such a run stops there with its steps before kept, where it used to go on through
/// inverted elements.
fn stopped_folding(which: Part, f: &VariantFailure) -> bool {
    which == Part::CoarseTenTurns
        && f.stopped_at.is_some_and(|t| t >= TURNS_THROUGH_THE_FIRST_SNAP)
        && f.reason.contains("turned inside out")
}

fn run_part(which: Part) {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("stability_ensemble");
    let variants = perturbations(ENSEMBLE_SIZE);
    let mut failures = Vec::new();
    let mut n = 0;
    for (i, cell) in matrix().iter().enumerate().filter(|(_, c)| part(c) == which) {
        n += 1;
        let settings = ci_settings(cell);
        let e = run_ensemble(&settings, &variants, &dir.join(format!("cell_{i:02}"))).expect("output directory");
        eprintln!("{} = {}: {} completed", cell.group, cell.label, e.rate());
        if e.inverted > 0 {
            failures.push(format!(
                "{} = {}: {} variants completed through inverted elements",
                cell.group, cell.label, e.inverted
            ));
        }
        for f in &e.failures {
            let line = format!(
                "{} = {}, variant {} ({:?}): {}",
                cell.group, cell.label, f.index, f.perturbation, f.reason
            );
            if stopped_folding(which, f) {
                eprintln!("stopped where an element would fold: {line}");
            } else {
                failures.push(line);
            }
        }
    }
    assert!(n > 0, "{which:?} holds no cell");
    assert!(
        failures.is_empty(),
        "variants that did not complete:\n{}",
        failures.join("\n")
    );
}

#[test]
fn material_and_thickness_sweeps_complete_in_every_variant() {
    run_part(Part::MaterialSweeps);
}

#[test]
fn time_step_twist_sliver_and_element_pair_sweeps_complete_in_every_variant() {
    run_part(Part::ResolutionSweeps);
}

#[test]
fn quick_corners_complete_in_every_variant() {
    run_part(Part::QuickCorners);
}

#[test]
fn coarse_ten_turn_corners_get_through_the_first_snap_in_every_variant() {
    run_part(Part::CoarseTenTurns);
}

#[test]
fn ten_turns_with_rotational_inertia_get_through_the_snap_in_every_variant() {
    run_part(Part::RotationalInertia);
}

#[test]
fn thin_four_turn_slivers_get_through_the_snap_in_every_variant() {
    run_part(Part::ThinSlivers);
}

#[test]
fn shortened_cells_keep_their_swept_setting() {
    for cell in matrix() {
        let (s, ci) = (&cell.settings, ci_settings(&cell));
        let name = format!("{} = {}", cell.group, cell.label);
        assert_eq!(
            (s.thickness, s.youngs_modulus, s.poisson_ratio, s.mu_c_factor),
            (ci.thickness, ci.youngs_modulus, ci.poisson_ratio, ci.mu_c_factor),
            "{name}"
        );
        assert_eq!(
            (s.length_scale, s.dt, s.pair),
            (ci.length_scale, ci.dt, ci.pair),
            "{name}"
        );
        assert_eq!(s.angular_inertia_density, ci.angular_inertia_density, "{name}");
        // The huge rotation: a full turn at least (the small-step cells excepted, whose difficulty
        // is the step), and past the first coiling snap where the cell twists more than four turns.
        if s.dt >= 0.01 {
            assert!(ci.turns >= s.turns.min(TURNS_THROUGH_THE_FIRST_SNAP), "{name}");
        }
        if s.mesh == (4, 40) && s.turns == 1.0 {
            let aspect = |m: (usize, usize)| (0.1 / m.0 as f64) / (0.01 / m.1 as f64);
            assert_eq!(aspect(ci.mesh), aspect(s.mesh), "{name}: sliver aspect kept");
        }
    }
}

#[test]
fn the_perturbations_span_the_relative_range_and_both_thread_counts() {
    let p = perturbations(ENSEMBLE_SIZE);
    for x in p.iter().flat_map(|p| [p.clamp, p.dt]) {
        assert!((1e-7..=1e-3).contains(&x.abs()), "relative change {x:e} out of range");
    }
    assert!(p.iter().any(|p| p.clamp > 0.0) && p.iter().any(|p| p.clamp < 0.0));
    assert!(p.iter().any(|p| p.dt.abs() < 1e-6) && p.iter().any(|p| p.dt.abs() > 1e-4));
    assert_eq!(p.iter().filter(|p| p.threads == 2).count(), ENSEMBLE_SIZE / 2);
    assert_eq!(p, perturbations(ENSEMBLE_SIZE), "the same variants on every call");
}
