//! The exact intersection test over every frame a run wrote (`cosserat intersections DIR`): a run
//! with contact should never show two triangles that cross, in any frame, not only in the last.

use cosserat_contact::intersecting_pairs;
use cosserat_io::run::{FRAMES_DIR, PVD_FILE};
use cosserat_io::{OutputError, read_pvd, read_vtu};
use nalgebra::Vector3;
use std::path::Path;

/// A frame with intersecting triangle pairs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CrossingFrame {
    /// Index of the frame in `run.pvd`.
    pub index: usize,
    /// Its time.
    pub time: f64,
    /// Pairs of triangles that share no vertex and intersect.
    pub pairs: usize,
}

/// What the test found over a run's frames.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameIntersections {
    /// Frames tested.
    pub frames: usize,
    /// The frames with intersecting pairs, in order.
    pub crossing: Vec<CrossingFrame>,
}

impl FrameIntersections {
    /// The frame with the most intersecting pairs (the first of equals).
    pub fn worst(&self) -> Option<CrossingFrame> {
        self.crossing
            .iter()
            .copied()
            .reduce(|worst, f| if f.pairs > worst.pairs { f } else { worst })
    }
}

/// Tests every frame listed in `dir/frames/run.pvd`: all triangles of a frame against each other,
/// shells and obstacles alike (pairs that share a vertex are neighbours, not intersections).
///
/// # Errors
/// A missing or unreadable `run.pvd` or frame file.
pub fn intersections_in_frames(dir: &Path) -> Result<FrameIntersections, OutputError> {
    let pvd = dir.join(FRAMES_DIR).join(PVD_FILE);
    let entries = read_pvd(&pvd)?;
    let folder = pvd.parent().unwrap_or(dir);
    let mut crossing = Vec::new();
    for (index, entry) in entries.iter().enumerate() {
        let frame = read_vtu(&folder.join(&entry.file))?;
        let points: Vec<Vector3<f64>> = frame.points.iter().map(|p| Vector3::from(*p)).collect();
        let pairs = intersecting_pairs(&frame.triangles, &points).len();
        if pairs > 0 {
            crossing.push(CrossingFrame {
                index,
                time: entry.time,
                pairs,
            });
        }
    }
    Ok(FrameIntersections {
        frames: entries.len(),
        crossing,
    })
}
