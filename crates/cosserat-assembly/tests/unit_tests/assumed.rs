//! Assumed strains at tying points on assembled shells: curved shells rest at zero energy and keep
//! exactly the rigid null space, and on flat straight-sided elements (where every strain field of the
//! element pair is linear) the linear stiffness is the paper's, so the paper's patch tests carry over.

use super::common::dense_hessian;
use cosserat_assembly::{ElementPair, ShellInput, ShellMesh, System, SystemOptions, build_system};
use cosserat_fem::mesh::procedural::GeneratedMesh;
use cosserat_fem::mesh::{chord_placement, procedural};
use cosserat_material::rest::RestOptions;
use cosserat_material::{MaterialParameters, ModelOptions, ShellModel, StrainInterpolation};
use nalgebra::{DMatrix, Vector3};

fn build(generated: &GeneratedMesh, pair: ElementPair, on_surface: bool, interpolation: StrainInterpolation) -> System {
    let mesh = if on_surface {
        ShellMesh::from_tri3(generated.mesh.clone(), pair, |n| generated.place(n))
    } else {
        ShellMesh::from_tri3(generated.mesh.clone(), pair, chord_placement)
    };
    let mut rest = RestOptions::new(ModelOptions::new(ShellModel::Shell));
    rest.interpolation = interpolation;
    let input = ShellInput {
        name: "shell".into(),
        mesh,
        pair,
        material: MaterialParameters::new(1e-2, 1e6, 0.3, 1000.0, 1e-2),
        rest,
        quadrature: None,
        damping: 0.0,
        angular_inertia_density: 0.0,
    };
    let options = SystemOptions {
        gravity: Vector3::zeros(),
        dynamic: false,
    };
    build_system(&[input], &options).unwrap()
}

/// The Hessian at rest, dense.
fn rest_hessian(system: &mut System) -> DMatrix<f64> {
    let n = system.potential.n_dofs();
    dense_hessian(&mut system.potential, &vec![0.0; n])
}

#[test]
fn curved_shells_rest_at_zero_energy_with_assumed_strains() {
    let sphere = procedural::icosphere(1.0, 1).unwrap();
    let cylinder = procedural::cylinder(0.5, 2.0, 12, 4).unwrap();
    for (label, generated) in [("sphere", &sphere), ("cylinder", &cylinder)] {
        for (pair, interpolation, on_surface) in [
            (ElementPair::Tri6Tri3, StrainInterpolation::Assumed, false),
            (ElementPair::Tri6Tri3, StrainInterpolation::Assumed, true),
            (ElementPair::Tri6Tri3, StrainInterpolation::Regge, false),
            (ElementPair::Tri6Tri3, StrainInterpolation::Regge, true),
            (ElementPair::Tri6Tri3, StrainInterpolation::ReggeStabilized, false),
            (ElementPair::Tri6Tri3, StrainInterpolation::ReggeStabilized, true),
            (ElementPair::Tri6Tri6, StrainInterpolation::ReggeStabilized, true),
        ] {
            let mut sys = build(generated, pair, on_surface, interpolation);
            let u = vec![0.0; sys.potential.n_dofs()];
            let mut g = vec![0.0; u.len()];
            let e = sys.potential.gradient(&u, &mut g).unwrap();
            // Scales: a unit strain costs E h A ≈ 1e6 · 1e-2 · 12 J, and its gradient is about
            // E h L ≈ 1e4 per unit velocity; the rest state is zero to round-off relative to those.
            let g_max = g.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            assert!(
                e.abs() < 1e-15,
                "{label} {pair:?} {interpolation:?} on_surface={on_surface}: energy at rest {e:e}"
            );
            assert!(
                g_max < 1e-14 * 1e4,
                "{label} {pair:?} {interpolation:?} on_surface={on_surface}: gradient at rest {g_max:e}"
            );
        }
    }
}

/// A free curved patch (a quarter of a cylinder, curved Tri6 elements) has exactly the six rigid
/// modes.
#[test]
fn a_free_curved_patch_has_only_the_rigid_modes() {
    let generated = procedural::cylinder(0.5, 0.4, 8, 2).unwrap();
    for (pair, interpolation) in [
        (ElementPair::Tri6Tri3, StrainInterpolation::Paper),
        (ElementPair::Tri6Tri3, StrainInterpolation::Assumed),
        (ElementPair::Tri6Tri3, StrainInterpolation::Regge),
        (ElementPair::Tri6Tri3, StrainInterpolation::ReggeStabilized),
        (ElementPair::Tri6Tri6, StrainInterpolation::ReggeStabilized),
    ] {
        let h = rest_hessian(&mut build(&generated, pair, true, interpolation));
        let eigenvalues = h.symmetric_eigenvalues();
        let largest = eigenvalues.iter().fold(0.0f64, |a, e| a.max(e.abs()));
        let zeros = eigenvalues.iter().filter(|e| e.abs() < 1e-9 * largest).count();
        assert_eq!(zeros, 6, "{pair:?} {interpolation:?}");
    }
}

/// On a distorted flat mesh of straight-sided elements the linear stiffness equals the paper's: every
/// linearised strain field of the pair is linear in the element and the tying interpolation
/// reproduces linear fields, so constant membrane strain and constant curvature states (and all
/// others) are represented as by the paper's element.
#[test]
fn flat_straight_elements_keep_the_papers_linear_stiffness() {
    let mut generated = procedural::rectangle_grid(1.0, 0.6, 4, 3).unwrap();
    for (i, x) in generated.mesh.nodes.iter_mut().enumerate() {
        let interior = x.x > 1e-9 && x.x < 1.0 - 1e-9 && x.y > 1e-9 && x.y < 0.6 - 1e-9;
        if interior {
            x.x += 0.06 * ((i * 7 % 5) as f64 - 2.0) / 2.0;
            x.y += 0.05 * ((i * 3 % 4) as f64 - 1.5) / 1.5;
        }
    }
    // Tri6 rotations make the linearised shear and drilling quadratic: that pair is not covered.
    for pair in [ElementPair::Tri3Tri3, ElementPair::Tri6Tri3] {
        let paper = rest_hessian(&mut build(&generated, pair, false, StrainInterpolation::Paper));
        for interpolation in [StrainInterpolation::Assumed, StrainInterpolation::Regge] {
            let assumed = rest_hessian(&mut build(&generated, pair, false, interpolation));
            let diff = (&assumed - &paper).amax();
            assert!(
                diff <= 1e-10 * paper.amax(),
                "{pair:?} {interpolation:?}: {diff:e} of {:e}",
                paper.amax()
            );
        }
    }
}
