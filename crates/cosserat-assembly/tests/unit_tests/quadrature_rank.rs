//! Which quadrature rules leave spurious zero-energy modes: the null space of a free patch's Hessian
//! at rest, counted for every element pair and rule degree.

use super::common::{FreePatch, dense_hessian};
use cosserat_assembly::ElementPair;
use cosserat_fem::QuadratureRule;
use cosserat_material::{MaterialParameters, ShellModel, StrainInterpolation};

/// The number of zero eigenvalues (relative to the largest) of a free 2 × 2 patch's Hessian at rest.
fn zero_modes(pair: ElementPair, model: ShellModel, degree: usize) -> usize {
    zero_modes_with(pair, model, degree, StrainInterpolation::Paper)
}

fn zero_modes_with(pair: ElementPair, model: ShellModel, degree: usize, interpolation: StrainInterpolation) -> usize {
    let patch = FreePatch {
        pair,
        model,
        interpolation,
        degree: Some(degree),
        cells: 2,
        material: MaterialParameters::new(1e-2, 1e6, 0.3, 1000.0, 1e-2),
    };
    let mut p = patch.build().potential;
    let zero = vec![0.0; p.n_dofs()];
    let h = dense_hessian(&mut p, &zero);
    let eigenvalues = h.symmetric_eigenvalues();
    let largest = eigenvalues.iter().fold(0.0f64, |a, e| a.max(e.abs()));
    eigenvalues.iter().filter(|e| e.abs() < 1e-9 * largest).count()
}

#[test]
fn rules_from_the_minimum_degree_leave_only_the_rigid_modes() {
    for pair in [ElementPair::Tri3Tri3, ElementPair::Tri6Tri3, ElementPair::Tri6Tri6] {
        for model in [ShellModel::Plate, ShellModel::Shell] {
            let min = pair.min_quadrature_degree();
            for degree in min..=6 {
                assert_eq!(zero_modes(pair, model, degree), 6, "{pair:?} {model:?} degree {degree}");
            }
            if min > 1 {
                let spurious = zero_modes(pair, model, min - 1);
                assert!(
                    spurious > 6,
                    "{pair:?} {model:?} degree {}: {spurious} zero modes",
                    min - 1
                );
            }
        }
    }
}

/// The stabilised strain projection adds no zero-energy mode: a free patch keeps exactly the six rigid
/// modes with the pair's default rule, even where the projection keeps only a small fraction of the
/// fluctuations (elements 10 thicknesses long here: √β ≈ 0.1).
#[test]
fn the_stabilized_projection_leaves_only_the_rigid_modes() {
    for pair in [ElementPair::Tri3Tri3, ElementPair::Tri6Tri3, ElementPair::Tri6Tri6] {
        for model in [ShellModel::Plate, ShellModel::Shell] {
            let degree = QuadratureRule::for_element_pair(pair.displacement(), pair.rotation()).degree();
            let n = zero_modes_with(pair, model, degree, StrainInterpolation::Stabilized);
            assert_eq!(n, 6, "{pair:?} {model:?}");
        }
    }
}

/// The assumed strains (MITC6-style, Regge, Regge with stabilised shear and drilling) add no zero-energy mode: a free patch keeps exactly the six rigid modes with
/// the pair's default rule.
#[test]
fn the_assumed_strains_leave_only_the_rigid_modes() {
    for pair in [ElementPair::Tri3Tri3, ElementPair::Tri6Tri3, ElementPair::Tri6Tri6] {
        for model in [ShellModel::Plate, ShellModel::Shell] {
            let degree = QuadratureRule::for_element_pair(pair.displacement(), pair.rotation()).degree();
            for interpolation in [
                StrainInterpolation::Assumed,
                StrainInterpolation::Regge,
                StrainInterpolation::ReggeStabilized,
            ] {
                let n = zero_modes_with(pair, model, degree, interpolation);
                assert_eq!(n, 6, "{pair:?} {model:?} {interpolation:?}");
            }
        }
    }
}

/// Quadratic rotations with `"regge_stabilized"` on the 3-point rule (the faster choice of
/// docs/model-notes.md, whose interior tying points are the rule's points) keep exactly the six rigid
/// modes too.
#[test]
fn regge_stabilized_quadratic_rotations_on_three_points_leave_only_the_rigid_modes() {
    for model in [ShellModel::Plate, ShellModel::Shell] {
        let n = zero_modes_with(ElementPair::Tri6Tri6, model, 2, StrainInterpolation::ReggeStabilized);
        assert_eq!(n, 6, "{model:?}");
    }
}
