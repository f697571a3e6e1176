//! The Möbius band: one half twist, welded into a non-orientable surface with one boundary loop.

use super::{GeneratedMesh, Surface, at_least, positive};
use crate::error::MeshError;
use crate::mesh::TriMesh;
use nalgebra::{Matrix2, Matrix3x2, Vector2, Vector3};
use std::f64::consts::PI;

/// The point `X(u, v)` of the Möbius band of centre-line radius `radius`.
fn point(radius: f64, u: f64, v: f64) -> Vector3<f64> {
    let s = radius + v * (0.5 * u).cos();
    Vector3::new(s * u.cos(), s * u.sin(), v * (0.5 * u).sin())
}

/// `[∂X/∂u ∂X/∂v]`.
fn tangent(radius: f64, u: f64, v: f64) -> Matrix3x2<f64> {
    let (c2, s2) = ((0.5 * u).cos(), (0.5 * u).sin());
    let s = radius + v * c2;
    let s_u = -0.5 * v * s2;
    Matrix3x2::new(
        s_u * u.cos() - s * u.sin(),
        c2 * u.cos(),
        s_u * u.sin() + s * u.cos(),
        c2 * u.sin(),
        0.5 * v * c2,
        s2,
    )
}

/// The band parameters `(u, v)` of the closest point to `p` (for `p` near the band), by Gauss–Newton
/// from the estimate of the circle through the centre line. `u` is in `(−π, π]` up to the final
/// Newton corrections.
fn parameters(radius: f64, p: &Vector3<f64>) -> Vector2<f64> {
    let u0 = p.y.atan2(p.x);
    let r = p.xy().norm();
    let mut uv = Vector2::new(u0, (r - radius) * (0.5 * u0).cos() + p.z * (0.5 * u0).sin());
    for _ in 0..50 {
        let t = tangent(radius, uv.x, uv.y);
        let residual = p - point(radius, uv.x, uv.y);
        let normal: Matrix2<f64> = t.transpose() * t;
        let Some(step) = normal.lu().solve(&(t.transpose() * residual)) else {
            break;
        };
        uv += step;
        if step.norm() <= 1e-15 * (1.0 + uv.norm()) {
            break;
        }
    }
    uv
}

/// The closest point of the band to `p` (for `p` near the band); `p` itself if the iteration fails.
pub(super) fn project(radius: f64, p: &Vector3<f64>) -> Vector3<f64> {
    let uv = parameters(radius, p);
    let q = point(radius, uv.x, uv.y);
    if q.iter().all(|c| c.is_finite()) { q } else { *p }
}

/// The band point at the weighted mean of the parameters of points `x` on the band.
///
/// Parameters are unwrapped relative to the first point using the band's identification
/// `(u + 2π, v) ≡ (u, −v)`, so edges across the seam interpolate the short way.
pub(super) fn interpolate(radius: f64, x: &[Vector3<f64>], weights: &[f64]) -> Vector3<f64> {
    let first = parameters(radius, &x[0]);
    let mut mean = Vector2::zeros();
    for (p, &w) in x.iter().zip(weights) {
        let uv = parameters(radius, p);
        let unwrapped = [-1.0_f64, 0.0, 1.0]
            .map(|k| Vector2::new(uv.x + 2.0 * PI * k, if k == 0.0 { uv.y } else { -uv.y }))
            .into_iter()
            .min_by(|a, b| (a.x - first.x).abs().total_cmp(&(b.x - first.x).abs()))
            .unwrap_or(uv);
        mean += unwrapped * w;
    }
    let q = point(radius, mean.x, mean.y);
    if q.iter().all(|c| c.is_finite()) {
        q
    } else {
        x.iter().zip(weights).fold(Vector3::zeros(), |acc, (p, &w)| acc + p * w)
    }
}

/// A Möbius band of centre-line radius `radius` and width `width` (`|v| ≤ width/2`), with one half
/// twist: `X(u, v) = ((R + v cos(u/2)) cos u, (R + v cos(u/2)) sin u, v sin(u/2))`.
///
/// `n_along` columns of vertices at `u = 2πi/n_along` and `n_across + 1` vertices across each;
/// vertex `(i, j)` has index `i·(n_across+1) + j`. The last column of quads is welded to column 0
/// with `j ↦ n_across − j` (since `X(2π, v) = X(0, −v)`), so the mesh is non-orientable with exactly
/// one boundary loop of `2·n_along` edges. Quads use alternating diagonals.
///
/// # Errors
/// [`MeshError::InvalidParameter`] for non-positive sizes, `width ≥ 2·radius` (self-intersection),
/// `n_along < 3` or `n_across < 1`.
pub fn mobius_strip(radius: f64, width: f64, n_along: usize, n_across: usize) -> Result<GeneratedMesh, MeshError> {
    const NAME: &str = "mobius_strip";
    positive(NAME, "radius", radius)?;
    positive(NAME, "width", width)?;
    if width >= 2.0 * radius {
        return Err(MeshError::InvalidParameter {
            generator: NAME,
            parameter: "width",
            value: width,
            reason: "must be less than twice the radius",
        });
    }
    at_least(NAME, "n_along", n_along, 3)?;
    at_least(NAME, "n_across", n_across, 1)?;
    let m = n_across + 1;
    let mut nodes = Vec::with_capacity(n_along * m);
    for i in 0..n_along {
        let u = 2.0 * PI * i as f64 / n_along as f64;
        for j in 0..m {
            let v = width * (j as f64 / n_across as f64 - 0.5);
            nodes.push(point(radius, u, v));
        }
    }
    // Column n_along is column 0 read backwards.
    let idx = |i: usize, j: usize| {
        if i == n_along { n_across - j } else { i * m + j }
    };
    let mut elements = Vec::with_capacity(2 * n_along * n_across);
    for i in 0..n_along {
        for j in 0..n_across {
            let (v00, v10, v11, v01) = (idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1));
            if (i + j) % 2 == 0 {
                elements.push([v00, v10, v11]);
                elements.push([v00, v11, v01]);
            } else {
                elements.push([v00, v10, v01]);
                elements.push([v10, v11, v01]);
            }
        }
    }
    Ok(GeneratedMesh {
        mesh: TriMesh { nodes, elements },
        surface: Surface::Mobius { radius },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tangent_matches_finite_differences() {
        let (r, u, v) = (1.3, 0.7, -0.2);
        let t = tangent(r, u, v);
        let h = 1e-6;
        let du = (point(r, u + h, v) - point(r, u - h, v)) / (2.0 * h);
        let dv = (point(r, u, v + h) - point(r, u, v - h)) / (2.0 * h);
        assert!((t.column(0) - du).norm() < 1e-8);
        assert!((t.column(1) - dv).norm() < 1e-8);
    }

    #[test]
    fn interpolation_across_the_seam_takes_the_short_way() {
        // Points just before and just after u = 0 (= 2π); the second is reached from the first through
        // the seam, where v changes sign.
        let r = 1.0;
        let a = point(r, 2.0 * PI - 0.1, 0.2);
        let b = point(r, 0.1, -0.2);
        let mid = interpolate(r, &[a, b], &[0.5, 0.5]);
        assert!((mid - point(r, 0.0, -0.2)).norm() < 1e-12, "{mid:?}");
    }

    #[test]
    fn projection_recovers_a_point_pushed_off_along_the_normal() {
        let (r, u, v) = (1.0, 2.1, 0.15);
        let t = tangent(r, u, v);
        let n = t.column(0).cross(&t.column(1)).normalize();
        let on = point(r, u, v);
        let q = project(r, &(on + n * 0.01));
        assert!((q - on).norm() < 1e-12, "{}", (q - on).norm());
    }
}
