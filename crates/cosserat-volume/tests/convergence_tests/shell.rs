//! The volumetric slab against the Cosserat shell (Tri6/Tri3 plate model, same material and rest
//! curvature): the shell curls exactly to `κ`, the thin slab nearly so, and their shapes converge.

use super::common::{KAPPA, LENGTH, fitted_curvature, shell_coil, volume_coil};
use cosserat_volume::measure::hausdorff_distance;

#[test]
fn the_thin_slab_matches_the_shell_shape() {
    // h = 1 cm, L_c = 0.1 m (closed form k/κ = 0.9988). The shell on nx/2 × ny/2 Tri6 cells has its
    // nodes at the slab's mid-surface grid. Measured (docs/micropolar-volume.md): Hausdorff distance of
    // the slab's mid-surface nodes to the shell's nodes 9.3e-2 L at 16 × 2 × 1, 2.9e-2 L at 32 × 4 × 1,
    // 1.1e-2 L at 64 × 8 × 1. The coarsest shell (8 × 1 Tri6) curls to 1.0135 κ, the next to 1.0033 κ.
    let (h, lc) = (0.01, 0.1);
    let mut distances = Vec::new();
    for (nx, ny) in [(16, 2), (32, 4)] {
        let (mid, _) = volume_coil(h, [nx, ny, 1], lc);
        let shell = shell_coil(h, nx / 2, ny / 2, lc);
        let k_shell = fitted_curvature(&shell);
        assert!((k_shell - KAPPA).abs() < 0.02 * KAPPA, "shell curvature {k_shell}");
        distances.push(hausdorff_distance(&mid, &shell) / LENGTH);
    }
    assert!(distances[1] < 0.6 * distances[0], "{distances:?}");
    assert!(distances[1] < 0.035, "{distances:?}");
}
