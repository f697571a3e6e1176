//! Warnings about settings physics limits: the drilling rotation without stiffness, and elements long
//! against the thickness (locking).

use cosserat::Simulation;
use std::path::Path;

fn advice(overrides: &[&str]) -> Vec<String> {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/validation/stability_strip.toml");
    let overrides: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    let spec = cosserat::scene::load_scene(&scene, &overrides).expect("the stability strip loads");
    let sim = Simulation::new(spec).expect("the stability strip builds");
    sim.advice().to_vec()
}

#[test]
fn a_well_posed_scene_gets_no_warning() {
    // Tri6/Tri3, 10 mm elements on a 1 mm thick strip, L_c = 1e-3 h.
    assert_eq!(advice(&[]), Vec::<String>::new());
}

#[test]
fn no_couple_modulus_and_no_length_scale_is_flagged_with_its_remedy() {
    let w = advice(&["material.mu_c_factor=0", "material.length_scale=0"]);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(w[0].contains("drilling") && w[0].contains("length_scale > 0"), "{}", w[0]);
    // Either one alone gives the drilling rotation a stiffness.
    assert!(advice(&["material.mu_c_factor=0"]).is_empty());
    assert!(advice(&["material.length_scale=0"]).is_empty());
}

#[test]
fn linear_displacements_on_elements_longer_than_the_thickness_are_flagged() {
    let w = advice(&["mesh.element=tri3"]);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(w[0].contains("lock") && w[0].contains("tri6"), "{}", w[0]);
    // Quadratic displacements lock only far thinner: 10 mm elements at h = 0.1 mm is ℓ/h = 100.
    assert!(advice(&[]).is_empty());
    let thin = advice(&["material.thickness=1e-4", "material.length_scale=1e-7"]);
    assert_eq!(thin.len(), 1, "{thin:?}");
    assert!(thin[0].contains("refine"), "{}", thin[0]);
}
