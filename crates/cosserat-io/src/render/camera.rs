//! The camera: a view basis from the options and a projection fitted to the meshes.
//!
//! View coordinates are `x` right, `y` up and `z` towards the viewer. The orthographic projection keeps
//! `(x, y)`; the perspective one places the eye on the view direction at the distance where the bounding
//! sphere fills the vertical field of view and divides by the distance along the view axis. In both
//! cases the projected points' bounding rectangle is scaled uniformly to the image minus the margin and
//! centred, so the fit is tight whatever the direction.

use nalgebra::Vector3;

use super::{Projection, RenderError, RenderOptions};

/// A projected point: sample coordinates (x right, y down) and a depth key that grows towards the
/// viewer and is affine in screen space (so it interpolates linearly across a triangle).
#[derive(Debug, Clone, Copy)]
pub(crate) struct ScreenPoint {
    pub x: f64,
    pub y: f64,
    pub key: f64,
}

/// A camera fitted to a set of meshes.
#[derive(Debug, Clone)]
pub(crate) struct Camera {
    centre: Vector3<f64>,
    right: Vector3<f64>,
    up: Vector3<f64>,
    back: Vector3<f64>,
    /// Distance from the centre to the eye for a perspective projection.
    eye_distance: Option<f64>,
    scale: f64,
    u_centre: f64,
    v_centre: f64,
    half_width: f64,
    half_height: f64,
}

/// A finite, non-zero vector from an option, normalised.
pub(crate) fn unit_option(v: [f64; 3], option: &'static str) -> Result<Vector3<f64>, RenderError> {
    let v = Vector3::from(v);
    let norm = v.norm();
    if v.iter().all(|c| c.is_finite()) && norm > 0.0 && norm.is_finite() {
        Ok(v / norm)
    } else {
        Err(RenderError::InvalidOption {
            option,
            reason: "must be a finite, non-zero vector",
        })
    }
}

impl Camera {
    /// Fits a camera to all `points` for an image of `width` x `height` samples.
    pub(crate) fn fit<'a>(
        point_sets: impl Iterator<Item = &'a [[f64; 3]]> + Clone,
        options: &RenderOptions,
        width: f64,
        height: f64,
    ) -> Result<Self, RenderError> {
        let back = unit_option(options.view_direction, "view_direction")?;
        let requested_up = unit_option(options.up, "up")?;
        // If the up vector is (nearly) parallel to the view direction, the first coordinate axis that is
        // not takes its place.
        let right = [requested_up, Vector3::z(), Vector3::y(), Vector3::x()]
            .iter()
            .map(|up| up.cross(&back))
            .find(|r| r.norm() > 1e-6)
            .map(|r| r.normalize())
            .unwrap_or_else(Vector3::x);
        let up = back.cross(&right);

        let (lo, hi) = bounds(point_sets.clone());
        let centre = (lo + hi) * 0.5;
        let radius = (hi - lo).norm() * 0.5;
        let eye_distance = match options.projection {
            Projection::Orthographic => None,
            Projection::Perspective { fov_y_degrees } => {
                // Every point lies within `radius` of the centre, hence strictly in front of the eye.
                Some(radius / (fov_y_degrees.to_radians() * 0.5).sin())
            }
        };
        let mut camera = Self {
            centre,
            right,
            up,
            back,
            eye_distance,
            scale: 1.0,
            u_centre: 0.0,
            v_centre: 0.0,
            half_width: width * 0.5,
            half_height: height * 0.5,
        };

        let (mut u_min, mut u_max, mut v_min, mut v_max) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for p in point_sets.flat_map(|points| points.iter()) {
            let (u, v, _) = camera.view_plane(p);
            u_min = u_min.min(u);
            u_max = u_max.max(u);
            v_min = v_min.min(v);
            v_max = v_max.max(v);
        }
        let (extent_u, extent_v) = (u_max - u_min, v_max - v_min);
        let usable = 1.0 - 2.0 * options.margin;
        let scale_u = if extent_u > 0.0 {
            width * usable / extent_u
        } else {
            f64::INFINITY
        };
        let scale_v = if extent_v > 0.0 {
            height * usable / extent_v
        } else {
            f64::INFINITY
        };
        let scale = scale_u.min(scale_v);
        if !(radius.is_finite() && radius > 0.0 && scale.is_finite() && scale > 0.0) {
            return Err(RenderError::DegenerateView { extent_u, extent_v });
        }
        camera.scale = scale;
        camera.u_centre = 0.5 * (u_min + u_max);
        camera.v_centre = 0.5 * (v_min + v_max);
        Ok(camera)
    }

    /// Projected plane coordinates `(u, v)` and the depth key of `p`.
    fn view_plane(&self, p: &[f64; 3]) -> (f64, f64, f64) {
        let q = Vector3::from(*p) - self.centre;
        let (x, y, z) = (q.dot(&self.right), q.dot(&self.up), q.dot(&self.back));
        match self.eye_distance {
            None => (x, y, z),
            Some(distance) => {
                let depth = distance - z;
                (x / depth, y / depth, 1.0 / depth)
            }
        }
    }

    /// Sample coordinates and depth key of `p`.
    pub(crate) fn project(&self, p: &[f64; 3]) -> ScreenPoint {
        let (u, v, key) = self.view_plane(p);
        ScreenPoint {
            x: self.half_width + (u - self.u_centre) * self.scale,
            y: self.half_height - (v - self.v_centre) * self.scale,
            key,
        }
    }

    /// Whether depth keys are reciprocal distances (perspective), which makes attribute interpolation
    /// weights need a perspective correction.
    pub(crate) fn is_perspective(&self) -> bool {
        self.eye_distance.is_some()
    }

    /// A direction given in view coordinates, in world coordinates.
    pub(crate) fn view_to_world(&self, v: &Vector3<f64>) -> Vector3<f64> {
        self.right * v.x + self.up * v.y + self.back * v.z
    }

    /// Direction from `p` towards the eye (not normalised).
    pub(crate) fn towards_eye(&self, p: &Vector3<f64>) -> Vector3<f64> {
        match self.eye_distance {
            None => self.back,
            Some(distance) => self.centre + self.back * distance - p,
        }
    }
}

/// Componentwise bounds of all points (the caller guarantees at least one point).
fn bounds<'a>(point_sets: impl Iterator<Item = &'a [[f64; 3]]>) -> (Vector3<f64>, Vector3<f64>) {
    let mut lo = Vector3::repeat(f64::MAX);
    let mut hi = Vector3::repeat(f64::MIN);
    for p in point_sets.flat_map(|points| points.iter()) {
        let p = Vector3::from(*p);
        lo = lo.inf(&p);
        hi = hi.sup(&p);
    }
    (lo, hi)
}
