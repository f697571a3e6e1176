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

/// Under load control (quasi-static levels, no continuation) the shallow arch snaps through at its limit
/// load to the far stable branch, with either treatment of indefinite Hessians: Newton's own steps (the
/// quasi-static default) and the shift. Below the limit load the crown deflection lies on the near
/// branch of the closed form, above it on the far one (`W > 6r`, where the load rises again), each
/// within the 2 % of the continuation's test.
#[test]
fn under_load_control_the_shallow_arch_snaps_to_the_far_branch_of_the_closed_form() {
    let root = cosserat_lab::workspace_root();
    std::env::set_current_dir(&root).unwrap();
    let r = 0.01 / 12f64.sqrt();
    // The scene's load factor in units of `EI k⁴ r` (see `path_validation`).
    let unit = 1.0e6 * 1e-6 / 12.0 * std::f64::consts::PI.powi(4) * r / 0.25;
    let levels = [0.5, 0.7, 0.84, 1.0];
    for treatment in ["factorise", "shift"] {
        let overrides: Vec<String> = [
            "output.frames=false",
            "time.mode=quasi_static",
            "time.initial_increment=",
            "time.end=",
            "time.levels=[0.5, 0.7, 0.84, 1.0]",
        ]
        .iter()
        .map(|s| s.to_string())
        .chain([format!("solver.indefinite_hessian={treatment}")])
        .collect();
        let out = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
            .join("path_following")
            .join(format!("arch_load_control_{treatment}"));
        let outcome = run_described(
            &Runner::InProcess,
            &RunDescription::new("scenes/validation/shallow_arch.toml", out, &overrides),
        )
        .unwrap();
        assert!(outcome.is_ok(), "{treatment}: {}", outcome.reason());
        let probes = outcome.probes.as_ref().unwrap();
        let w = probes.column("centre.uz").unwrap();
        let deflections: Vec<f64> = probes.rows.iter().skip(1).map(|row| -row[w] / r).collect();
        assert_eq!(deflections.len(), levels.len(), "{treatment}: one row per level");
        for (&lambda, &found) in levels.iter().zip(&deflections) {
            // The closed form's branch: before the limit load (λ = 0.74986) the near one, W < 2r.
            let branch = if lambda < 0.74986 { (0.0, 2.0) } else { (6.0, 10.0) };
            let expected = deflection_on_branch(lambda / unit, branch);
            eprintln!("{treatment}: λ = {lambda}: W = {found:.4} r (closed form {expected:.4} r)");
            assert!(
                (found / expected - 1.0).abs() < 0.02,
                "{treatment}: λ = {lambda}: W = {found} r, closed form {expected} r"
            );
        }
    }
}

/// The crown deflection (in `r`) where the closed-form load (in `EI k⁴ r`) is `load`, on the branch
/// `(lo, hi)` along which it is monotone (bisection).
fn deflection_on_branch(load: f64, (mut lo, mut hi): (f64, f64)) -> f64 {
    let f = |w: f64| cosserat_lab::reference::shallow_arch_load(4.0, w) - load;
    assert!(f(lo) * f(hi) < 0.0, "load {load} not on the branch ({lo}, {hi})");
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if f(lo) * f(mid) <= 0.0 { hi = mid } else { lo = mid }
    }
    0.5 * (lo + hi)
}
