//! A small software rasteriser that renders triangle-surface frames to PNG images.
//!
//! It exists for quick looks and report figures without ParaView: a fixed, documented camera fitted to
//! the mesh, a z-buffer, two-sided Lambert shading, an optional colour map of a point scalar and 2x2
//! supersampling by default. Input is a [`VtuFrame`] (points, triangles and point data), so frames read
//! back with [`crate::read_vtu`] or [`crate::read_pvd_frame`] render directly.
//!
//! - [`render_image`] / [`render_png`]: one frame;
//! - [`render_side_by_side`] / [`render_side_by_side_png`]: several frames in a row, with one camera and
//!   one colour range so that motion and magnitudes compare across panels.

mod camera;
pub mod colour_map;
pub mod error;
mod raster;

use std::path::Path;

use crate::{VtuFrame, write_atomic};
use camera::{Camera, unit_option};
pub use colour_map::viridis;
pub use error::RenderError;
use raster::{Shading, Target, rasterise};

/// Largest number of samples (pixels times supersampling squared) of one panel: 2^24, e.g. 2048 x 2048
/// pixels at 2x2, about 340 MB of buffers.
pub const MAX_PANEL_SAMPLES: u64 = 1 << 24;

/// Largest number of pixels of a composed image: 2^26.
pub const MAX_IMAGE_PIXELS: u64 = 1 << 26;

/// How view coordinates map to the image.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Projection {
    /// Parallel projection along the view direction.
    Orthographic,
    /// Pinhole camera on the view direction, far enough for the bounding sphere to fill the vertical
    /// field of view.
    Perspective {
        /// Vertical field of view in degrees, in `[1, 170]`.
        fov_y_degrees: f64,
    },
}

/// Which scalar of a point array colours the surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScalarMode {
    /// One component of the array.
    Component(usize),
    /// Euclidean norm of the tuple (e.g. displacement magnitude).
    Magnitude,
}

/// How the surface is coloured.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum Colouring {
    /// One colour, [`RenderOptions::surface_colour`].
    #[default]
    Uniform,
    /// The built-in colour map ([`viridis`]) of a point scalar, interpolated across triangles.
    PointScalar {
        /// Name of the point data array.
        array: String,
        /// Which scalar of the array.
        mode: ScalarMode,
        /// Values mapped to the two ends of the colour map (clamped outside); `None` takes the minimum and
        /// maximum over all rendered frames.
        range: Option<[f64; 2]>,
    },
}

/// Camera, light and image settings.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderOptions {
    /// Width of one panel in pixels. Default 800.
    pub width: u32,
    /// Height in pixels. Default 600.
    pub height: u32,
    /// Samples per pixel along each axis, in `[1, 4]`. Default 2 (2x2 supersampling).
    pub supersampling: u32,
    /// Direction from the centre of the bounding box towards the eye, world coordinates.
    /// Default `(1, -1.5, 1)`.
    pub view_direction: [f64; 3],
    /// World direction shown upwards (projected onto the image plane). Default `(0, 0, 1)`; if it is
    /// parallel to the view direction, the first of z, y, x that is not is used instead.
    pub up: [f64; 3],
    /// Projection. Default perspective with a 30 degree vertical field of view.
    pub projection: Projection,
    /// Free border on each side as a fraction of the image size, in `[0, 0.45]`. Default 0.05. The
    /// mesh's projected bounding rectangle is scaled uniformly to fill the rest and centred.
    pub margin: f64,
    /// Background colour (sRGB). Default light grey `(245, 245, 245)`.
    pub background: [u8; 3],
    /// Surface colour for [`Colouring::Uniform`] (sRGB). Default light steel blue `(176, 196, 222)`.
    pub surface_colour: [u8; 3],
    /// How the surface is coloured. Default [`Colouring::Uniform`].
    pub colouring: Colouring,
    /// Direction towards the light in view coordinates (x right, y up, z towards the viewer), so the
    /// lighting looks the same from every view direction. Default `(-0.35, 0.55, 1)`: from the upper
    /// left, behind the viewer.
    pub light_direction: [f64; 3],
    /// Intensity of unlit surfaces as a fraction of full intensity, in `[0, 1]`. Default 0.35.
    pub ambient: f64,
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            width: 800,
            height: 600,
            supersampling: 2,
            view_direction: [1.0, -1.5, 1.0],
            up: [0.0, 0.0, 1.0],
            projection: Projection::Perspective { fov_y_degrees: 30.0 },
            margin: 0.05,
            background: [245, 245, 245],
            surface_colour: [176, 196, 222],
            colouring: Colouring::Uniform,
            light_direction: [-0.35, 0.55, 1.0],
            ambient: 0.35,
        }
    }
}

/// An 8-bit RGB image.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Pixels row by row from the top left, `width * height` of them.
    pub pixels: Vec<[u8; 3]>,
}

impl Image {
    /// The pixel in column `x` and row `y` (row 0 at the top).
    ///
    /// # Panics
    /// If `(x, y)` lies outside the image.
    #[track_caller]
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 3] {
        assert!(
            x < self.width && y < self.height,
            "pixel ({x}, {y}) outside a {}x{} image",
            self.width,
            self.height
        );
        self.pixels[y as usize * self.width as usize + x as usize]
    }

    /// The image encoded as an 8-bit RGB PNG.
    ///
    /// # Errors
    /// [`RenderError::Png`] if the encoder fails.
    pub fn encode_png(&self) -> Result<Vec<u8>, RenderError> {
        let mut bytes = Vec::new();
        let mut encoder = png::Encoder::new(&mut bytes, self.width, self.height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header()?;
        writer.write_image_data(self.pixels.as_flattened())?;
        writer.finish()?;
        Ok(bytes)
    }

    /// Writes the image as a PNG file, atomically.
    ///
    /// # Errors
    /// [`RenderError::Png`] or [`RenderError::Output`] naming the path.
    pub fn write_png(&self, path: &Path) -> Result<(), RenderError> {
        let bytes = self.encode_png()?;
        write_atomic(path, &bytes)?;
        Ok(())
    }
}

/// Renders one frame.
///
/// # Errors
/// As [`render_side_by_side`].
pub fn render_image(frame: &VtuFrame, options: &RenderOptions) -> Result<Image, RenderError> {
    render_side_by_side(std::slice::from_ref(frame), options)
}

/// Renders one frame to a PNG file at `path` (written atomically).
///
/// # Errors
/// As [`render_side_by_side`], plus [`Image::write_png`].
pub fn render_png(frame: &VtuFrame, options: &RenderOptions, path: &Path) -> Result<(), RenderError> {
    render_image(frame, options)?.write_png(path)
}

/// Renders `frames` as panels of `options.width` x `options.height` pixels from left to right, with one
/// camera fitted to all frames and one colour range.
///
/// # Errors
/// - [`RenderError::NoFrames`] for an empty slice, [`RenderError::EmptyMesh`] for a frame without
///   points or triangles, [`RenderError::Frame`] for a frame that fails validation;
/// - [`RenderError::MissingArray`] or [`RenderError::ComponentOutOfRange`] for a colouring that does not
///   match a frame;
/// - [`RenderError::InvalidOption`] and [`RenderError::ImageSize`] for options out of range;
/// - [`RenderError::DegenerateView`] if the meshes project to a single point.
pub fn render_side_by_side(frames: &[VtuFrame], options: &RenderOptions) -> Result<Image, RenderError> {
    let factor = check_options(options, frames.len())?;
    if frames.is_empty() {
        return Err(RenderError::NoFrames);
    }
    for (frame_idx, frame) in frames.iter().enumerate() {
        frame.validate().map_err(|source| RenderError::Frame { frame_idx, source })?;
        if frame.points.is_empty() || frame.triangles.is_empty() {
            return Err(RenderError::EmptyMesh {
                frame_idx,
                n_points: frame.points.len(),
                n_triangles: frame.triangles.len(),
            });
        }
    }
    let scalars = colour_coordinates(frames, &options.colouring)?;

    let (panel_width, height) = (options.width as usize, options.height as usize);
    let (sample_width, sample_height) = (panel_width * factor, height * factor);
    let camera = Camera::fit(
        frames.iter().map(|frame| frame.points.as_slice()),
        options,
        sample_width as f64,
        sample_height as f64,
    )?;
    let shading = Shading {
        light: camera.view_to_world(&unit_option(options.light_direction, "light_direction")?),
        ambient: options.ambient,
        surface: options.surface_colour.map(f64::from),
    };

    let total_width = panel_width * frames.len();
    let mut pixels = vec![options.background; total_width * height];
    for (panel, frame) in frames.iter().enumerate() {
        let mut target = Target::new(sample_width, sample_height, options.background);
        let panel_scalars = scalars.as_ref().map(|s| s[panel].as_slice());
        rasterise(
            &frame.points,
            &frame.triangles,
            panel_scalars,
            &camera,
            &shading,
            &mut target,
        );
        let panel_pixels = target.resolve(factor);
        for (row, chunk) in panel_pixels.chunks_exact(panel_width).enumerate() {
            let start = row * total_width + panel * panel_width;
            pixels[start..start + panel_width].copy_from_slice(chunk);
        }
    }
    // `check_options` bounds the total width by MAX_IMAGE_PIXELS, which fits in u32.
    Ok(Image {
        width: total_width as u32,
        height: options.height,
        pixels,
    })
}

/// Renders `frames` side by side to a PNG file at `path` (written atomically).
///
/// # Errors
/// As [`render_side_by_side`], plus [`Image::write_png`].
pub fn render_side_by_side_png(frames: &[VtuFrame], options: &RenderOptions, path: &Path) -> Result<(), RenderError> {
    render_side_by_side(frames, options)?.write_png(path)
}

/// Checks the options for `n_panels` panels and returns the supersampling factor.
fn check_options(options: &RenderOptions, n_panels: usize) -> Result<usize, RenderError> {
    let size_error = |reason| RenderError::ImageSize {
        width: u64::from(options.width) * n_panels as u64,
        height: u64::from(options.height),
        supersampling: options.supersampling,
        reason,
    };
    if !(1..=4).contains(&options.supersampling) {
        return Err(RenderError::InvalidOption {
            option: "supersampling",
            reason: "must lie in [1, 4]",
        });
    }
    if options.width == 0 || options.height == 0 {
        return Err(size_error("width and height must be positive"));
    }
    let factor = u64::from(options.supersampling);
    if u64::from(options.width) * u64::from(options.height) * factor * factor > MAX_PANEL_SAMPLES {
        return Err(size_error("a panel exceeds MAX_PANEL_SAMPLES samples"));
    }
    if u64::from(options.width) * u64::from(options.height) * n_panels as u64 > MAX_IMAGE_PIXELS {
        return Err(size_error("the image exceeds MAX_IMAGE_PIXELS pixels"));
    }
    if !(0.0..=0.45).contains(&options.margin) {
        return Err(RenderError::InvalidOption {
            option: "margin",
            reason: "must lie in [0, 0.45]",
        });
    }
    if !(0.0..=1.0).contains(&options.ambient) {
        return Err(RenderError::InvalidOption {
            option: "ambient",
            reason: "must lie in [0, 1]",
        });
    }
    if let Projection::Perspective { fov_y_degrees } = options.projection
        && !(1.0..=170.0).contains(&fov_y_degrees)
    {
        return Err(RenderError::InvalidOption {
            option: "projection",
            reason: "fov_y_degrees must lie in [1, 170]",
        });
    }
    unit_option(options.view_direction, "view_direction")?;
    unit_option(options.up, "up")?;
    unit_option(options.light_direction, "light_direction")?;
    if let Colouring::PointScalar {
        range: Some([lo, hi]), ..
    } = options.colouring
        && !(lo.is_finite() && hi.is_finite() && lo <= hi)
    {
        return Err(RenderError::InvalidOption {
            option: "colouring",
            reason: "range must be finite with min <= max",
        });
    }
    Ok(options.supersampling as usize)
}

/// Colour-map coordinates in `[0, 1]` per point of every frame, `None` for uniform colouring.
fn colour_coordinates(frames: &[VtuFrame], colouring: &Colouring) -> Result<Option<Vec<Vec<f64>>>, RenderError> {
    let Colouring::PointScalar { array, mode, range } = colouring else {
        return Ok(None);
    };
    let mut values = Vec::with_capacity(frames.len());
    for (frame_idx, frame) in frames.iter().enumerate() {
        let data = frame.point_array(array).ok_or_else(|| RenderError::MissingArray {
            frame_idx,
            array: array.clone(),
        })?;
        let scalars: Vec<f64> = match *mode {
            ScalarMode::Component(component) if component < data.n_components => {
                (0..data.n_tuples()).map(|idx| data.tuple(idx)[component]).collect()
            }
            ScalarMode::Component(component) => {
                return Err(RenderError::ComponentOutOfRange {
                    frame_idx,
                    array: array.clone(),
                    component,
                    n_components: data.n_components,
                });
            }
            // `hypot` avoids the overflow of a sum of squares for huge components.
            ScalarMode::Magnitude => (0..data.n_tuples())
                .map(|idx| data.tuple(idx).iter().fold(0.0, |acc: f64, &c| acc.hypot(c)))
                .collect(),
        };
        values.push(scalars);
    }
    let [lo, hi] = range.unwrap_or_else(|| {
        let all = values.iter().flatten();
        [
            all.clone().copied().fold(f64::INFINITY, f64::min),
            all.copied().fold(f64::NEG_INFINITY, f64::max),
        ]
    });
    let span = hi - lo;
    for frame_values in &mut values {
        for v in frame_values.iter_mut() {
            let t = (*v - lo) / span;
            // A constant field (0 / 0) sits in the middle of the map; everything else is clamped.
            *v = if t.is_nan() { 0.5 } else { t.clamp(0.0, 1.0) };
        }
    }
    Ok(Some(values))
}
