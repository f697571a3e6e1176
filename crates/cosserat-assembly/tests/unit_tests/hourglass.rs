//! The drilling hourglass of quadratic rotations on the 3-point rule (`cosserat_material::drilling_hourglass`).

use super::common::{FreePatch, dense_hessian};
use cosserat_assembly::ElementPair;
use cosserat_material::{MaterialParameters, ShellModel, StrainInterpolation};
use nalgebra::DMatrix;

/// The smallest stiffness of the nodal turns about the normal of a free flat patch at rest (the least
/// eigenvalue of the Hessian's block of those unknowns), on the rule of `degree`.
fn least_turn_stiffness(degree: usize) -> f64 {
    let patch = FreePatch {
        pair: ElementPair::Tri6Tri6,
        model: ShellModel::Plate,
        interpolation: StrainInterpolation::ReggeStabilized,
        degree: Some(degree),
        cells: 2,
        // Cells 0.05 long, 500 thicknesses: the stabilised fluctuations keep a small fraction.
        material: MaterialParameters::new(1e-4, 1e9, 0.3, 1000.0, 1e-7),
    };
    let mut p = patch.build().potential;
    let n = p.n_dofs();
    let h = dense_hessian(&mut p, &vec![0.0; n]);
    // Tri6/Tri6: as many rotation nodes as displacement nodes, after them; the normal is z.
    let turns: Vec<usize> = (n / 6..n / 3).map(|k| 3 * k + 2).collect();
    let block = DMatrix::from_fn(turns.len(), turns.len(), |i, j| h[(turns[i], turns[j])]);
    block.symmetric_eigenvalues().min()
}

/// On the 3-point rule three of each element's six nodal turn patterns vanish at the points, where the
/// stabilised drilling strain is read; the six-point rule sees them. The hourglass term holds them as
/// the six-point rule does, with the stiffness of the stabilised fluctuations, not only by the
/// curvature energy (without it, the 3-point rule's least turn stiffness here is orders of magnitude
/// below the six-point rule's).
#[test]
fn the_three_point_rule_holds_the_turns_about_the_normal_as_the_six_point_rule() {
    let (three, six) = (least_turn_stiffness(2), least_turn_stiffness(4));
    assert!(six > 0.0, "six-point rule: {six:e}");
    assert!(
        three > 0.2 * six && three < 5.0 * six,
        "3-point rule {three:e}, six-point rule {six:e}"
    );
}
