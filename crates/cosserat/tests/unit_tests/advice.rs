//! Warnings about settings physics limits: the drilling rotation without stiffness, elements long
//! against the thickness (locking), and the stabilised projection on elements long against it.

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
    assert!(
        w[0].contains("drilling") && w[0].contains("length_scale > 0"),
        "{}",
        w[0]
    );
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
    assert!(
        thin[0].contains("refine") && thin[0].contains("regge_stabilized"),
        "{}",
        thin[0]
    );
    // Regge membrane strains with stabilised shear and drilling keep the thin strip free.
    let free = advice(&[
        "material.thickness=1e-4",
        "material.length_scale=1e-7",
        "material.strain_interpolation=regge_stabilized",
    ]);
    assert!(free.is_empty(), "{free:?}");
    // So does the default discretisation (the scene's `rotation_element = "tri3"` removed).
    let default = advice(&[
        "material.thickness=1e-4",
        "material.length_scale=1e-7",
        "mesh.rotation_element=",
    ]);
    assert!(default.is_empty(), "{default:?}");
}

#[test]
fn an_element_turned_inside_out_is_reported_in_the_summary() {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/validation/stability_strip.toml");
    let overrides = vec!["time.end=0".to_string(), "output.frames=false".to_string()];
    let run = |mirror: bool| {
        let spec = cosserat::scene::load_scene(&scene, &overrides).expect("the stability strip loads");
        let mut sim = Simulation::new(spec).expect("the stability strip builds");
        if mirror {
            // Mirrored positions with unchanged directors: every element is inside out.
            for x in &mut sim.potential_mut().parts.state.x {
                x.x = -x.x;
            }
        }
        let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("inverted_{mirror}"));
        sim.run(&dir, &mut |_| {}, &cosserat::StopRequest::new())
            .expect("the run writes its outputs")
    };
    assert!(run(false).warnings.is_empty());
    let inverted = run(true);
    assert!(
        inverted.warnings.iter().any(|w| w.contains("inside out")),
        "{:?}",
        inverted.warnings
    );
    assert!(inverted.min_area_ratio.unwrap() < 0.0);
}

#[test]
fn the_comparison_models_get_no_cosserat_advice() {
    // Tri3 elements twenty times longer than the thickness would lock a Cosserat Tri3 shell; the
    // Kirchhoff–Love model has no transverse shear to lock.
    let scene = |model: &str| {
        format!(
            r#"
name = "advice"
[time]
dt = 0.01
end = 0.0
[mesh]
generator = "rectangle"
lx = 0.1
ly = 0.02
nx = 5
ny = 1
[material]
{model}
thickness = 1e-3
youngs_modulus = 1e6
poisson_ratio = 0.3
density = 1000.0
"#
        )
    };
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("advice_models");
    std::fs::create_dir_all(&dir).unwrap();
    let advice_of = |name: &str, text: String| {
        let path = dir.join(format!("{name}.toml"));
        std::fs::write(&path, text).unwrap();
        let spec = cosserat::scene::load_scene(&path, &[]).unwrap_or_else(|e| panic!("{e}"));
        Simulation::new(spec).unwrap_or_else(|e| panic!("{e}")).advice().to_vec()
    };
    let kl = advice_of("kl", scene("model = \"kirchhoff_love\"\nlaw = \"stvk\""));
    assert_eq!(kl, Vec::<String>::new());
    // The same mesh as a Cosserat Tri3/Tri3 shell is flagged.
    let cosserat = advice_of(
        "cosserat",
        scene("model = \"plate\"\nlength_scale = 1e-6")
            .replace("ny = 1\n", "ny = 1\nelement = \"tri3\"\nrotation_element = \"tri3\"\n"),
    );
    assert_eq!(cosserat.len(), 1, "{cosserat:?}");
}

#[test]
fn the_stabilised_projection_on_elements_longer_than_the_thickness_is_flagged() {
    // 10 mm elements, h = 1 mm: β = 1/101 of the in-element membrane variation is kept.
    let w = advice(&["material.strain_interpolation=stabilized"]);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(w[0].contains("1.0 %") && w[0].contains("in-plane"), "{}", w[0]);
    // Elements half the thickness keep four fifths: no warning.
    let thick = advice(&[
        "material.strain_interpolation=stabilized",
        "material.thickness=0.02",
        "material.length_scale=2e-5",
    ]);
    assert!(thick.is_empty(), "{thick:?}");
}
