//! The stabilisation factors that keep a stretched sheet stable.
//!
//! When a director turns by a small angle `θ`, the tangential part of `Rᵀ F` shortens at second order,
//! so under a membrane stress `N` the membrane energy falls by about `½ N θ²`. Pointwise strains hold
//! such a turn through the transverse shear (a tilt) or the drilling strain (a turn about the normal),
//! whose energy grows as `½ K θ²` with `K` of the order of the shear modulus times the thickness, far
//! above any elastic stress. The stabilised shear and drilling strains keep only `α² K` for rotations
//! that vary inside an element ([`crate::projection`]), so a sheet loses stability once `N > α² K`:
//! spurious negative modes of the rotations, which tension alone drives (docs/model-notes.md, "A
//! stretched sheet").
//!
//! [`StrainProjection::held_in_tension`] raises an element's factors to `α² ≥ κ N / K` with the safety
//! factor [`TENSION_SAFETY`]. The stress is read from the positions at the start of the step (the
//! surface stretch, without the rotations, [`membrane_stretch`]) and at Newton's iterates, whose
//! stretch is predicted linearly along the step ([`membrane_stretch_predicted`]); an iterate that
//! stretches an element beyond what its factors hold without the safety factor
//! ([`StrainProjection::holds_tension`]) raises them (the assembly's shell term does this, with
//! hysteresis, within a step and from step to step: a step starts with the stress the last one held
//! while its own lies between a quarter of that and that). Between changes the factors are constants
//! and the element's energy keeps its exact derivatives; a sheet pulled taut within one step is held
//! as it tightens, and one whose stress varies from step to step within the band keeps its energy. The stretch is the
//! element's mean: a bent element's points stretch and shorten about a mean the bending does not move
//! (the parasitic membrane strains that the assumed membrane strains filter out). Where a sheet is not
//! stretched (bending, compression, the small loads of the locking benchmarks) nothing changes.

use crate::projection::StrainProjection;
use crate::strain_space::{DensityMatrix, StrainVector};
use nalgebra::{Matrix2, Matrix3, Vector3};

/// `κ` in `α² ≥ κ N / K`: the stress may grow between the points where it is read, and the assumed
/// membrane strains are not the point's own.
pub const TENSION_SAFETY: f64 = 2.0;

/// The tangential strain entries `Ê` 0, 1, 3, 4 ((a, γ) at 3γ + a, a, γ ∈ {0, 1}) of a point with the
/// polar rotation of its deformed tangent vectors `f_hat`: the stretch `U = √(F̂ᵀ F̂)` against the rest
/// stretch of the strain offset, without the point's own rotation.
pub fn membrane_stretch(f_hat: &[Vector3<f64>; 2], offset: &StrainVector) -> [f64; 4] {
    // A degenerate (or non-finite) surface has no stretch to read; the energy reports it.
    match polar_stretch(f_hat) {
        Some(u) => TANGENTIAL.map(|k| u[(k % 3, k / 3)] - offset[k]),
        None => [0.0; 4],
    }
}

/// The tangential strain entries of [`membrane_stretch`] for the tangent vectors `f_hat + df_hat`,
/// predicted linearly from `f_hat`: `U + dU` with `U dU + dU U = dC = F̂ᵀ dF̂ + dF̂ᵀ F̂`, the derivative
/// of `U = √(F̂ᵀ F̂)`. A step's stretch builds up linearly in its displacements, while a rotation of
/// the surface by the step (the directions of a linearised update) adds only the second-order stretch
/// that the prediction leaves out: the iterates of a thin shell bent far in one step would otherwise
/// read that artefact as tension (the reason of the mixed-integration-point iteration, too).
pub fn membrane_stretch_predicted(
    f_hat: &[Vector3<f64>; 2],
    df_hat: &[Vector3<f64>; 2],
    offset: &StrainVector,
) -> [f64; 4] {
    let Some(u) = polar_stretch(f_hat) else {
        return [0.0; 4];
    };
    let dc = |a: usize, b: usize| f_hat[a].dot(&df_hat[b]) + df_hat[a].dot(&f_hat[b]);
    // `U dU + dU U = dC` for the symmetric `dU = [[p, q], [q, r]]`; `U` is positive definite, so the
    // system is regular.
    let system = Matrix3::new(
        2.0 * u[(0, 0)],
        2.0 * u[(0, 1)],
        0.0,
        u[(0, 1)],
        u[(0, 0)] + u[(1, 1)],
        u[(0, 1)],
        0.0,
        2.0 * u[(0, 1)],
        2.0 * u[(1, 1)],
    );
    let Some(d) = system.lu().solve(&Vector3::new(dc(0, 0), dc(0, 1), dc(1, 1))) else {
        return [0.0; 4];
    };
    let predicted = u + Matrix2::new(d[0], d[1], d[1], d[2]);
    TANGENTIAL.map(|k| predicted[(k % 3, k / 3)] - offset[k])
}

/// The stretch `U = √(F̂ᵀ F̂)` of the tangent vectors `f_hat`, or `None` where the surface is
/// degenerate (or not finite).
fn polar_stretch(f_hat: &[Vector3<f64>; 2]) -> Option<Matrix2<f64>> {
    let c = Matrix2::new(
        f_hat[0].dot(&f_hat[0]),
        f_hat[0].dot(&f_hat[1]),
        f_hat[1].dot(&f_hat[0]),
        f_hat[1].dot(&f_hat[1]),
    );
    let det = c.determinant();
    if det.is_nan() || det <= 0.0 {
        return None;
    }
    // The square root of a 2 × 2 symmetric positive definite matrix in closed form.
    let s = det.sqrt();
    Some((c + Matrix2::identity() * s) / (c.trace() + 2.0 * s).sqrt())
}

/// The largest principal membrane stress \[N/m\] of the tangential strain `strain`
/// ([`membrane_stretch`]) through the density's membrane block (zero where the surface is not
/// stretched).
pub fn membrane_tension(strain: &[f64; 4], density: &DensityMatrix) -> f64 {
    let d = density.matrix();
    let [n00, n10, n01, n11] =
        TANGENTIAL.map(|r| TANGENTIAL.iter().zip(strain).map(|(&col, e)| d[(r, col)] * e).sum::<f64>());
    let n = Matrix2::new(n00, 0.5 * (n10 + n01), 0.5 * (n10 + n01), n11);
    let mean = 0.5 * n.trace();
    let radius = (0.25 * (n[(0, 0)] - n[(1, 1)]).powi(2) + n[(0, 1)].powi(2)).sqrt();
    (mean + radius).max(0.0)
}

/// The tangential entries of `Ê` among its entries 0–5.
const TANGENTIAL: [usize; 4] = [0, 1, 3, 4];

impl StrainProjection {
    /// The factors of an element under the membrane stress `tension` ([`membrane_tension`] of its mean
    /// stretch) with the density `density`: each of the shear and drilling factors
    /// raised to `√(κ N / K)` where that is larger, `K` the stiffness of the part against a turn of the
    /// directors (the shear strain's, and the skew tangential pair's), at most one.
    pub fn held_in_tension(&self, tension: f64, density: &DensityMatrix) -> Self {
        self.raised_for(TENSION_SAFETY * tension, density)
    }

    /// Whether these factors hold the membrane stress `tension` without the safety factor (`α² ≥ N / K`
    /// for the shear and drilling alike, or the factor one): a stress up to [`TENSION_SAFETY`] times
    /// that which [`Self::held_in_tension`] was given.
    pub fn holds_tension(&self, tension: f64, density: &DensityMatrix) -> bool {
        self.raised_for(tension, density) == *self
    }

    /// The factors raised to `α² ≥ N / K` for the stress `N = load` (the drilling's load doubled, see
    /// below), at most one.
    fn raised_for(&self, load: f64, density: &DensityMatrix) -> Self {
        if load <= 0.0 {
            return *self;
        }
        let d = density.matrix();
        let shear = d[(2, 2)].min(d[(5, 5)]);
        // A turn `φ` about the normal changes the entries (1, 3) by `φ (−1, 1)`; the membrane strain falls by
        // `½ φ² tr N ≤ φ² N`.
        let drilling = d[(1, 1)] - d[(1, 3)] - d[(3, 1)] + d[(3, 3)];
        let floor = |alpha: f64, stiffness: f64, load: f64| {
            if stiffness > 0.0 {
                alpha.max((load / stiffness).sqrt().min(1.0))
            } else {
                alpha
            }
        };
        Self {
            shear: floor(self.shear, shear, load),
            drilling: floor(self.drilling, drilling, 2.0 * load),
            ..*self
        }
    }
}
