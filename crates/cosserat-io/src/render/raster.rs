//! Z-buffered triangle rasterisation with two-sided Lambert shading.
//!
//! Triangles are sampled at sample centres with edge functions; a sample is covered when its three
//! barycentric coordinates are non-negative. The depth key is affine in screen space for both projections
//! (view depth for orthographic, reciprocal distance for perspective), so it interpolates linearly, and
//! attribute weights get the usual perspective correction. Normals are smooth (area-weighted vertex
//! normals) where they agree with the face and flat otherwise, and they are turned towards the viewer
//! before shading, so both sides of a shell are lit alike.

use nalgebra::Vector3;

use super::camera::{Camera, ScreenPoint};
use super::colour_map::viridis_channels;

/// Light and base colour of a panel.
pub(crate) struct Shading {
    /// Unit direction towards the light, world coordinates.
    pub light: Vector3<f64>,
    /// Ambient fraction of the intensity in `[0, 1]`.
    pub ambient: f64,
    /// Colour of the surface without a scalar field, channels in `[0, 255]`.
    pub surface: [f64; 3],
}

/// A supersampled colour and depth buffer.
pub(crate) struct Target {
    width: usize,
    height: usize,
    colour: Vec<[f64; 3]>,
    depth: Vec<f64>,
}

impl Target {
    /// A buffer of `width` x `height` samples cleared to `background`.
    pub(crate) fn new(width: usize, height: usize, background: [u8; 3]) -> Self {
        let n = width * height;
        Self {
            width,
            height,
            colour: vec![background.map(f64::from); n],
            depth: vec![f64::NEG_INFINITY; n],
        }
    }

    /// Box-filters `factor` x `factor` blocks into pixels, row-major from the top left.
    pub(crate) fn resolve(&self, factor: usize) -> Vec<[u8; 3]> {
        let (width, height) = (self.width / factor, self.height / factor);
        let weight = 1.0 / (factor * factor) as f64;
        let mut pixels = Vec::with_capacity(width * height);
        for py in 0..height {
            for px in 0..width {
                let mut sum = [0.0; 3];
                for sy in py * factor..(py + 1) * factor {
                    for sample in &self.colour[sy * self.width + px * factor..sy * self.width + (px + 1) * factor] {
                        for c in 0..3 {
                            sum[c] += sample[c];
                        }
                    }
                }
                pixels.push(sum.map(|s| (s * weight).round().clamp(0.0, 255.0) as u8));
            }
        }
        pixels
    }
}

/// Twice the signed area of the screen triangle `(a, b, p)`.
fn edge(a: &ScreenPoint, b: &ScreenPoint, px: f64, py: f64) -> f64 {
    (b.x - a.x) * (py - a.y) - (b.y - a.y) * (px - a.x)
}

/// Area-weighted unit vertex normals (zero where the adjacent faces cancel or are degenerate).
fn vertex_normals(points: &[[f64; 3]], triangles: &[[usize; 3]]) -> Vec<Vector3<f64>> {
    let mut normals = vec![Vector3::zeros(); points.len()];
    for tri in triangles {
        let [a, b, c] = tri.map(|idx| Vector3::from(points[idx]));
        let n = (b - a).cross(&(c - a));
        for &idx in tri {
            normals[idx] += n;
        }
    }
    for n in &mut normals {
        let norm = n.norm();
        *n = if norm > 0.0 && norm.is_finite() {
            *n / norm
        } else {
            Vector3::zeros()
        };
    }
    normals
}

/// The first and last sample columns and rows of a `width × height` buffer within the bounding box
/// of a screen triangle (inclusive); `None` if it lies left of or above the buffer.
fn sample_box(s: &[ScreenPoint; 3], width: usize, height: usize) -> Option<((usize, usize), (usize, usize))> {
    let x_min = s.iter().map(|p| p.x).fold(f64::INFINITY, f64::min);
    let x_max = s.iter().map(|p| p.x).fold(f64::NEG_INFINITY, f64::max);
    let y_min = s.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
    let y_max = s.iter().map(|p| p.y).fold(f64::NEG_INFINITY, f64::max);
    // Sample (i, j) sits at (i + 0.5, j + 0.5); clamp the covered range to the buffer.
    let first = |lo: f64| (lo - 0.5).ceil().max(0.0) as usize;
    let last = |hi: f64, n: usize| ((hi - 0.5).floor().min(n as f64 - 1.0)).max(-1.0);
    let (i0, j0) = (first(x_min), first(y_min));
    let (i1, j1) = (last(x_max, width), last(y_max, height));
    if i1 < 0.0 || j1 < 0.0 {
        return None;
    }
    Some(((i0, i1 as usize), (j0, j1 as usize)))
}

/// Draws the triangles of one mesh. `scalars`, if given, holds one colour-map coordinate per point.
pub(crate) fn rasterise(
    points: &[[f64; 3]],
    triangles: &[[usize; 3]],
    scalars: Option<&[f64]>,
    camera: &Camera,
    shading: &Shading,
    target: &mut Target,
) {
    let screen: Vec<ScreenPoint> = points.iter().map(|p| camera.project(p)).collect();
    let normals = vertex_normals(points, triangles);
    for tri in triangles {
        let [a, b, c] = tri.map(|idx| Vector3::from(points[idx]));
        let face = (b - a).cross(&(c - a));
        let face_norm = face.norm();
        if !(face_norm > 0.0 && face_norm.is_finite()) {
            continue;
        }
        let face = face / face_norm;
        let centroid = (a + b + c) / 3.0;
        let towards_viewer = if face.dot(&camera.towards_eye(&centroid)) < 0.0 {
            -1.0
        } else {
            1.0
        };
        let s = tri.map(|idx| screen[idx]);
        let area = edge(&s[0], &s[1], s[2].x, s[2].y);
        if area.abs() < 1e-12 {
            continue;
        }
        let Some(((i0, i1), (j0, j1))) = sample_box(&s, target.width, target.height) else {
            continue;
        };
        for j in j0..=j1 {
            let py = j as f64 + 0.5;
            for i in i0..=i1 {
                let px = i as f64 + 0.5;
                let w = [
                    edge(&s[1], &s[2], px, py) / area,
                    edge(&s[2], &s[0], px, py) / area,
                    edge(&s[0], &s[1], px, py) / area,
                ];
                if w.iter().any(|&wk| wk < 0.0) {
                    continue;
                }
                let key = w[0] * s[0].key + w[1] * s[1].key + w[2] * s[2].key;
                let idx = j * target.width + i;
                if key <= target.depth[idx] {
                    continue;
                }
                target.depth[idx] = key;
                let weights = if camera.is_perspective() {
                    let corrected = [w[0] * s[0].key, w[1] * s[1].key, w[2] * s[2].key];
                    let sum: f64 = corrected.iter().sum();
                    corrected.map(|c| c / sum)
                } else {
                    w
                };
                let smooth: Vector3<f64> = (0..3).map(|k| normals[tri[k]] * weights[k]).sum();
                let normal = if smooth.dot(&face) > 1e-3 * smooth.norm() && smooth.norm() > 1e-12 {
                    smooth.normalize()
                } else {
                    face
                } * towards_viewer;
                let lambert = normal.dot(&shading.light).max(0.0);
                let intensity = shading.ambient + (1.0 - shading.ambient) * lambert;
                let base = match scalars {
                    Some(t) => viridis_channels((0..3).map(|k| t[tri[k]] * weights[k]).sum()),
                    None => shading.surface,
                };
                target.colour[idx] = base.map(|c| c * intensity);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resolve_averages_blocks() {
        let mut target = Target::new(4, 2, [0, 0, 0]);
        target.colour[0] = [255.0, 0.0, 0.0];
        target.colour[1] = [255.0, 0.0, 0.0];
        target.colour[4] = [255.0, 255.0, 0.0];
        target.colour[5] = [255.0, 255.0, 0.0];
        let pixels = target.resolve(2);
        assert_eq!(pixels, vec![[255, 128, 0], [0, 0, 0]]);
    }

    #[test]
    fn vertex_normals_of_a_flat_fan_are_the_plane_normal() {
        let points = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
        let triangles = [[0, 1, 2], [0, 2, 3]];
        for n in vertex_normals(&points, &triangles) {
            assert!((n - Vector3::z()).norm() < 1e-15);
        }
    }
}
