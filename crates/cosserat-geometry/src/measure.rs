//! Shape measures for comparing configurations: a least-squares circle through points of a plane
//! curve, and the Hausdorff distance between point sets.

use nalgebra::{Matrix3, Vector2, Vector3};

/// The circle `(centre, radius)` that best fits `points` in the algebraic (Kåsa) sense: it minimises
/// `Σ (|p − c|² − r²)²`, a linear least-squares problem. Exact for points on a circle; `None` for fewer
/// than three points or collinear ones.
pub fn fit_circle(points: &[Vector2<f64>]) -> Option<(Vector2<f64>, f64)> {
    if points.len() < 3 {
        return None;
    }
    // Shift to the centroid for conditioning, then solve for (a, b, c) in x² + y² = a x + b y + c.
    let mean = points.iter().sum::<Vector2<f64>>() / points.len() as f64;
    let mut ata = Matrix3::<f64>::zeros();
    let mut atb = Vector3::<f64>::zeros();
    for p in points {
        let d = p - mean;
        let row = Vector3::new(d.x, d.y, 1.0);
        ata += row * row.transpose();
        atb += row * d.norm_squared();
    }
    let sol = ata.cholesky()?.solve(&atb);
    let centre = Vector2::new(0.5 * sol.x, 0.5 * sol.y);
    let r2 = sol.z + centre.norm_squared();
    (r2 > 0.0 && r2.is_finite()).then(|| (centre + mean, r2.sqrt()))
}

/// The symmetric Hausdorff distance `max(sup_a inf_b |a − b|, sup_b inf_a |a − b|)` between two
/// non-empty point sets (brute force, `O(|a| |b|)`); infinite if either set is empty.
pub fn hausdorff_distance(a: &[Vector3<f64>], b: &[Vector3<f64>]) -> f64 {
    if a.is_empty() || b.is_empty() {
        return f64::INFINITY;
    }
    let directed = |from: &[Vector3<f64>], to: &[Vector3<f64>]| {
        from.iter()
            .map(|p| to.iter().map(|q| (p - q).norm_squared()).fold(f64::INFINITY, f64::min))
            .fold(0.0, f64::max)
            .sqrt()
    };
    directed(a, b).max(directed(b, a))
}
