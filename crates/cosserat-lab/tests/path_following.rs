//! Arc-length continuation through limit points against reference paths, on each scene's own mesh:
//! every problem of `cargo xtask validate` with a required accuracy lies within it (the hinged roof of
//! Sze 3.8 within 2 % of the published path, the shallow arch within 2 % of its closed form), and the
//! shallow arch's limit load is that of the closed form. A few seconds each in release.

use cosserat::RunDescription;
use cosserat_lab::path_validation::{PathProblem, compare_path, problems, read_path};
use cosserat_lab::runner::{Runner, run_described};

/// The path of a validation problem on its scene's mesh, and the problem.
fn path_of(name: &str) -> (Vec<(f64, f64)>, PathProblem) {
    let root = cosserat_lab::workspace_root();
    std::env::set_current_dir(&root).unwrap();
    let p = problems().into_iter().find(|p| p.name == name).unwrap();
    let out = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("path_following")
        .join(name);
    let outcome = run_described(
        &Runner::InProcess,
        &RunDescription::new(p.scene, out, &["output.frames=false".to_string()]),
    )
    .unwrap();
    assert!(outcome.is_ok(), "{name}: {}", outcome.reason());
    (read_path(&outcome).unwrap(), p)
}

#[test]
fn the_hinged_roof_and_the_shallow_arch_follow_their_reference_paths() {
    for name in ["hinged_roof", "shallow_arch"] {
        let (path, p) = path_of(name);
        let (reference, required) = (&p.reference, p.required.expect("a required accuracy"));
        let c = compare_path(reference, &path, p.monotone);
        eprintln!(
            "{name}: {} equilibria, largest distance {:.3} %, largest load error {:?}",
            path.len(),
            100.0 * c.max_distance,
            c.max_load_error
        );
        assert!(c.max_distance <= required, "{name}: distance {}", c.max_distance);
        // The path passes every reference deflection (it does not end early).
        let w_end = path.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max);
        let w_ref = reference.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max);
        assert!(w_end >= w_ref, "{name}: ends at deflection {w_end} before {w_ref}");
    }
}

/// The first limit load of the shallow arch is the closed form's `8 EI k⁴ r` (λ = 0.74986 for the
/// scene's load), within the order `(ke)²` that shallow-arch theory neglects, at the crown
/// deflection `2r`.
#[test]
fn the_shallow_arch_snaps_at_the_closed_form_limit_load() {
    let (path, p) = path_of("shallow_arch");
    let first_peak = |p: &[(f64, f64)]| p[p.windows(2).position(|s| s[1].0 < s[0].0).expect("a limit point")];
    let (l_ref, w_ref) = first_peak(&p.reference);
    let (l, w) = first_peak(&path);
    eprintln!("shallow arch: limit load {l:.5} at {w:.5} (closed form {l_ref:.5} at {w_ref:.5})");
    assert!((l / l_ref - 1.0).abs() < 3e-3, "limit load {l} vs {l_ref}");
    assert!((w / w_ref - 1.0).abs() < 0.02, "deflection at the limit {w} vs {w_ref}");
}
