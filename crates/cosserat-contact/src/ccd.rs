//! Continuous collision detection with a minimum separation: additive conservative advancement
//! (Li, Kaufman, Jiang 2021, "Codimensional Incremental Potential Contact", ACCD).
//!
//! Along the linear motion `x + α Δx`, `α ∈ [0, 1]`, the distance between two primitives changes at
//! most as fast as the relative speed of their points. With the displacements made relative to their
//! mean (the distance is translation invariant), `l = |Δp̄| + maxᵢ |Δt̄ᵢ|` for a point–triangle pair and
//! `l = maxᵢ |Δāᵢ| + maxⱼ |Δb̄ⱼ|` for an edge–edge pair bound the rate: `|dg/dα| ≤ l`. Starting from the
//! gap `g₀ = d − δ`, each step advances by `h = 0.9 (g − g_min) / l`, which cannot bring the gap below
//! `g_min + 0.1 (g − g_min)` on that step; the advancement stops at `α = 1` or once the gap is within
//! `10 %` of `g₀ − g_min` above `g_min` (or after a maximum number of steps). The result is therefore
//! conservative: on `[0, α]` the gap never drops below `g_min`. There are no false negatives: nothing
//! is sampled, every bound is rigorous up to round-off (the 0.9 factor absorbs it).
//!
//! The returned `α` is not always the largest feasible fraction: it can stop short by up to the final
//! margin, and a sliding contact at a small gap takes about `l / g` steps (a cap then returns the
//! fraction reached, which is still safe).

use crate::distance::{edge_edge_distance, point_triangle_distance};
use nalgebra::Vector3;

/// Settings of the conservative advancement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CcdSettings {
    /// The gap must stay at or above this fraction of its start value (IPC and ACCD use 0.1).
    pub min_gap_fraction: f64,
    /// At most this many advancement steps per pair; the fraction reached is returned then.
    pub max_iterations: usize,
}

impl Default for CcdSettings {
    fn default() -> Self {
        Self {
            min_gap_fraction: 0.1,
            max_iterations: 10_000,
        }
    }
}

/// Which pair type a CCD query is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum PairType {
    PointTriangle,
    EdgeEdge,
}

fn gap(x: &[Vector3<f64>; 4], kind: PairType, thickness: f64) -> f64 {
    let s = match kind {
        PairType::PointTriangle => point_triangle_distance(x).1,
        PairType::EdgeEdge => edge_edge_distance(x).1,
    };
    s.sqrt() - thickness
}

/// The largest safe step fraction of a point–triangle pair `x = [p, t₀, t₁, t₂]` moving by `dx`, with
/// thickness `δ` \[m\]: the gap `d − δ` stays at or above `settings.min_gap_fraction` times its start
/// value on `[0, α]`. Returns 0 if the start gap is not positive.
pub fn point_triangle_ccd(
    x: &[Vector3<f64>; 4],
    dx: &[Vector3<f64>; 4],
    thickness: f64,
    settings: &CcdSettings,
) -> f64 {
    advance(x, dx, thickness, PairType::PointTriangle, settings)
}

/// As [`point_triangle_ccd`] for an edge–edge pair `x = [a₀, a₁, b₀, b₁]`.
pub fn edge_edge_ccd(x: &[Vector3<f64>; 4], dx: &[Vector3<f64>; 4], thickness: f64, settings: &CcdSettings) -> f64 {
    advance(x, dx, thickness, PairType::EdgeEdge, settings)
}

/// The displacements relative to their mean and the bound `l` on how fast the pair's distance can change
/// along them (per unit step fraction).
fn relative_motion(dx: &[Vector3<f64>; 4], point_triangle: bool) -> ([Vector3<f64>; 4], f64) {
    let mean = (dx[0] + dx[1] + dx[2] + dx[3]) * 0.25;
    let p: [Vector3<f64>; 4] = std::array::from_fn(|i| dx[i] - mean);
    let n: [f64; 4] = std::array::from_fn(|i| p[i].norm());
    let rate = if point_triangle {
        n[0] + n[1].max(n[2]).max(n[3])
    } else {
        n[0].max(n[1]) + n[2].max(n[3])
    };
    (p, rate)
}

/// An upper bound on how much the distance of a pair (point–triangle if `point_triangle`, else
/// edge–edge) can decrease while its points move by `dx`: `|d(1) − d(0)| ≤` this bound.
pub fn distance_change_bound(dx: &[Vector3<f64>; 4], point_triangle: bool) -> f64 {
    relative_motion(dx, point_triangle).1
}

fn advance(
    x: &[Vector3<f64>; 4],
    dx: &[Vector3<f64>; 4],
    thickness: f64,
    kind: PairType,
    settings: &CcdSettings,
) -> f64 {
    let g0 = gap(x, kind, thickness);
    if !(g0 > 0.0) {
        return 0.0;
    }
    let (p, rate) = relative_motion(dx, kind == PairType::PointTriangle);
    if !(rate > 0.0) {
        return if rate == 0.0 { 1.0 } else { 0.0 };
    }
    let g_min = settings.min_gap_fraction * g0;
    let stop = g_min + 0.1 * (g0 - g_min);
    let mut t = 0.0;
    let mut g = g0;
    for _ in 0..settings.max_iterations {
        let h = 0.9 * (g - g_min) / rate;
        if t + h >= 1.0 {
            return 1.0;
        }
        t += h;
        let xt: [Vector3<f64>; 4] = std::array::from_fn(|i| x[i] + p[i] * t);
        g = gap(&xt, kind, thickness);
        if !(g > g_min) {
            // Only round-off can bring the gap below the bound within a step; back off to the last safe
            // point conservatively.
            return (t - h).max(0.0);
        }
        if g <= stop {
            return t;
        }
    }
    t
}
