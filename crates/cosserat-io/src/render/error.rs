//! The error type of the renderer.

use thiserror::Error;

use crate::OutputError;

/// A frame or option set that cannot be rendered, or an image that cannot be written.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum RenderError {
    /// No frame was given.
    #[error("no frame to render")]
    NoFrames,
    /// A frame without points or without triangles.
    #[error("frame {frame_idx} is empty ({n_points} points, {n_triangles} triangles): nothing to render")]
    EmptyMesh {
        /// Index of the frame among those rendered.
        frame_idx: usize,
        /// Its number of points.
        n_points: usize,
        /// Its number of triangles.
        n_triangles: usize,
    },
    /// A frame that fails [`crate::VtuFrame::validate`].
    #[error("frame {frame_idx} is invalid: {source}")]
    Frame {
        /// Index of the frame among those rendered.
        frame_idx: usize,
        /// The validation failure.
        #[source]
        source: OutputError,
    },
    /// The point data array chosen for colouring is missing from a frame.
    #[error("frame {frame_idx} has no point data array `{array}` to colour by")]
    MissingArray {
        /// Index of the frame among those rendered.
        frame_idx: usize,
        /// Name of the array.
        array: String,
    },
    /// The component chosen for colouring does not exist.
    #[error("array `{array}` of frame {frame_idx} has {n_components} components, component {component} requested")]
    ComponentOutOfRange {
        /// Index of the frame among those rendered.
        frame_idx: usize,
        /// Name of the array.
        array: String,
        /// The requested component.
        component: usize,
        /// Components of the array.
        n_components: usize,
    },
    /// An option outside its documented range.
    #[error("render option `{option}` is invalid: {reason}")]
    InvalidOption {
        /// Name of the field of [`super::RenderOptions`].
        option: &'static str,
        /// What is required.
        reason: &'static str,
    },
    /// An image that is empty or too large to render.
    #[error("image of {width}x{height} pixels with {supersampling}x{supersampling} supersampling: {reason}")]
    ImageSize {
        /// Requested total width in pixels.
        width: u64,
        /// Requested height in pixels.
        height: u64,
        /// Supersampling factor per axis.
        supersampling: u32,
        /// What is wrong.
        reason: &'static str,
    },
    /// The mesh projects to a single point (all points coincide or lie on the viewing ray), or its extent
    /// overflows: no camera can frame it.
    #[error("the mesh cannot be framed: its projected extent is {extent_u} x {extent_v}")]
    DegenerateView {
        /// Width of the projected mesh in view units.
        extent_u: f64,
        /// Height of the projected mesh in view units.
        extent_v: f64,
    },
    /// PNG encoding failed.
    #[error("PNG encoding failed: {0}")]
    Png(#[from] png::EncodingError),
    /// Reading a frame or writing the image file failed.
    #[error(transparent)]
    Output(#[from] OutputError),
}
