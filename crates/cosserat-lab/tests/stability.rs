//! A corner of the stability matrix (`cargo xtask stability`, docs/stability.md) run in CI: a thin and
//! stiff strip with a large time step, μ_c = 0, and ten full turns of twist on a coarse strip (10×2
//! quads, one turn per element length). Each
//! must converge to the end without a non-finite value, without an inverted element, without energy
//! growth while it is held (backward Euler only dissipates), and with its twisted end where the
//! boundary condition puts it.

use cosserat_lab::ensemble::{ENSEMBLE_SIZE, perturbations, run_variant};
use cosserat_lab::runner::Runner;
use cosserat_lab::stability::{CellResult, Settings, corners, run_cell};

fn run(name: &str, settings: &Settings) -> CellResult {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("stability").join(name);
    run_cell(&Runner::InProcess, settings, &dir).expect("output directory")
}

/// Checks that hold for every cell; `max_twist_error_deg` bounds the end director's error.
fn assert_stable(name: &str, r: &CellResult, max_twist_error_deg: f64) {
    assert!(r.outcome.is_ok(), "{name}: {}", r.outcome.reason());
    assert!(!r.non_finite, "{name}: non-finite value in the outputs");
    let growth = r.energy_growth.expect("energies in the summary");
    // The summary's energies leave out the clamps' penalty energy, so energy moving between the strip
    // and the clamps shows as changes of order 1e-6 (docs/stability.md); an instability grows without
    // bound.
    assert!(
        growth <= 1e-4,
        "{name}: energy grew by a relative {growth:e} while held"
    );
    let area = r.min_area_ratio.expect("area ratio in the summary");
    assert!(area > 0.0, "{name}: inverted element (area ratio {area})");
    let twist = r.twist_error_deg.expect("director probe");
    assert!(
        twist < max_twist_error_deg,
        "{name}: end director {twist}° off its target"
    );
}

#[test]
fn thin_and_stiff_strip_with_a_large_time_step() {
    let cell = &corners()[0];
    assert_eq!(
        (cell.settings.thickness, cell.settings.youngs_modulus, cell.settings.dt),
        (1e-6, 1e11, 0.1)
    );
    // The clamp is a penalty of 1e3 × the bending stiffness: the end director follows its target to
    // within a degree.
    assert_stable("thin_stiff_large_dt", &run("thin_stiff_large_dt", &cell.settings), 1.0);
}

#[test]
fn no_couple_modulus() {
    let settings = Settings {
        mu_c_factor: 0.0,
        ..Settings::default()
    };
    assert_stable("mu_c_zero", &run("mu_c_zero", &settings), 1.0);
}

/// The settings of the matrix's ten-turn row.
fn ten_turn_row() -> Settings {
    cosserat_lab::stability::matrix()
        .into_iter()
        .find(|c| c.group.starts_with("twist") && c.settings.turns == 10.0)
        .expect("the ten-turn row of the matrix")
        .settings
}

#[test]
fn ten_full_turns_on_a_coarse_strip() {
    // The matrix's ten-turn row: 10 × 2 quads, one full turn of twist per element length, default
    // settings (no rotational inertia), dt = 0.01 s with step halving. The coarser 4 × 1 corner does
    // not get through the coiling snap (docs/stability.md).
    let s = &ten_turn_row();
    assert_eq!((s.mesh, s.dt, s.angular_inertia_density), ((10, 2), 0.01, 0.0));
    assert_stable("ten_turns", &run("ten_turns", s), 1.0);
}

#[test]
fn ten_full_turns_keep_every_element_right_side_out_in_perturbed_variants() {
    // The ten-turn row again, with the first perturbed variants of the matrix's ensemble (relative
    // changes of the clamps' stiffness and the time step, one and two threads): the coil's snaps
    // must not fold an element in any of them, as the solver keeps every element right side out.
    let settings = ten_turn_row();
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("stability")
        .join("ten_turns_variants");
    let (mut rejected, mut retracted) = (0, 0);
    for (i, p) in perturbations(ENSEMBLE_SIZE).iter().take(4).enumerate() {
        let variant = dir.join(format!("variant_{i}"));
        let r = run_variant(&settings, p, &variant).expect("output directory");
        assert!(r.outcome.is_ok(), "variant {i}: {}", r.outcome.reason());
        let area = r.min_area_ratio.expect("area ratio in the summary");
        assert!(area > 0.0, "variant {i}: inverted element (area ratio {area})");
        let summary = cosserat::io::read_summary(&variant.join("summary.json")).expect("summary");
        let convergence = summary.convergence.expect("convergence record");
        rejected += convergence.rejected_iterates;
        retracted += convergence.retracted_guesses;
    }
    // The coil's snaps are where an extrapolated guess or a full Newton step would fold an element
    // (without the check, variants 1 and 3 end inverted): the summary reports the check's work.
    assert!(rejected > 0, "no iterate turned back");
    assert!(retracted > 0, "no guess halved");
}

#[test]
fn every_cell_of_the_matrix_and_its_remedy_settings_are_valid_scenes() {
    let scene = cosserat_lab::workspace_root().join(cosserat_lab::stability::BASE_SCENE);
    for cell in cosserat_lab::stability::matrix() {
        let loaded = cosserat::scene::load_scene(&scene, &cell.settings.overrides());
        assert!(loaded.is_ok(), "{} = {}: {:?}", cell.group, cell.label, loaded.err());
    }
}

#[test]
fn the_emitted_matrix_runs_are_the_cells_and_their_variants_as_valid_scenes() {
    let out = std::path::Path::new("out/stability");
    let runs = cosserat_lab::stability::matrix_runs(out, None, 2);
    let cells = cosserat_lab::stability::matrix();
    assert_eq!(runs.len(), 3 * cells.len());
    for (c, chunk) in cells.iter().zip(runs.chunks(3)) {
        assert_eq!(chunk[0].overrides, c.settings.overrides());
        assert_eq!(chunk[0].threads, Some(1));
        assert_eq!([chunk[1].threads, chunk[2].threads], [Some(1), Some(2)]);
        for run in chunk {
            let loaded = cosserat::scene::load_scene(&run.scene, &run.overrides);
            assert!(loaded.is_ok(), "{}: {:?}", run.label, loaded.err());
        }
        // The variants differ from the cell in their clamp stiffness and time step only.
        assert_ne!(chunk[1].overrides, chunk[0].overrides);
        assert_eq!(chunk[1].overrides.len(), chunk[0].overrides.len());
    }
}
