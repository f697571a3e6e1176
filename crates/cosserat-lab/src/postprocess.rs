//! Reading run outputs back and measuring what the experiments should show (probes, circle fits,
//! boundary loops, the rim of a buckled disk). Pure geometry on written results: no physics.

use anyhow::{Context, Result, bail};
use cosserat::fem::mesh::{Topology, Tri3Mesh};
use cosserat::geometry::measure;
use cosserat::io::VtuFrame;
use nalgebra::{Vector2, Vector3};
use std::path::Path;

/// The contents of a `probes.csv`.
#[derive(Debug, Clone)]
pub struct ProbeTable {
    /// Column names (the first is `t`).
    pub columns: Vec<String>,
    /// Rows of values.
    pub rows: Vec<Vec<f64>>,
}

impl ProbeTable {
    /// Reads a probes file.
    pub fn read(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
        let mut lines = text.lines();
        let columns: Vec<String> = lines
            .next()
            .context("empty probes file")?
            .split(',')
            .map(str::to_string)
            .collect();
        let rows = lines
            .filter(|l| !l.is_empty())
            .map(|l| {
                l.split(',')
                    .map(|v| v.parse::<f64>().with_context(|| format!("bad value `{v}`")))
                    .collect::<Result<Vec<f64>>>()
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(Self { columns, rows })
    }

    /// Index of a column.
    pub fn column(&self, name: &str) -> Result<usize> {
        self.columns
            .iter()
            .position(|c| c == name)
            .with_context(|| format!("no probe column `{name}`"))
    }

    /// The last value of a column.
    pub fn last(&self, name: &str) -> Result<f64> {
        let c = self.column(name)?;
        self.rows.last().map(|r| r[c]).context("no probe rows")
    }

    /// The value of a column in the row whose `t` is closest to `t`.
    pub fn at(&self, name: &str, t: f64) -> Result<f64> {
        let c = self.column(name)?;
        let row = self
            .rows
            .iter()
            .min_by(|a, b| (a[0] - t).abs().total_cmp(&(b[0] - t).abs()))
            .context("no probe rows")?;
        Ok(row[c])
    }

    /// A 3-vector probe (`name.x`, `.y`, `.z` or `.ux`, … given the suffixes) at the last row.
    pub fn last_vec(&self, name: &str, suffixes: [&str; 3]) -> Result<[f64; 3]> {
        Ok([
            self.last(&format!("{name}.{}", suffixes[0]))?,
            self.last(&format!("{name}.{}", suffixes[1]))?,
            self.last(&format!("{name}.{}", suffixes[2]))?,
        ])
    }
}

/// Least-squares circle (Kåsa fit) through points projected on the plane of two coordinates `(a, b)`:
/// returns `(centre_a, centre_b, radius, rms residual)`.
pub fn fit_circle(points: &[[f64; 3]], a: usize, b: usize) -> Result<(f64, f64, f64, f64)> {
    let plane: Vec<Vector2<f64>> = points.iter().map(|p| Vector2::new(p[a], p[b])).collect();
    let (centre, r) = measure::fit_circle(&plane).context("a circle fit needs three points off a line")?;
    let rms = (plane.iter().map(|p| ((p - centre).norm() - r).powi(2)).sum::<f64>() / plane.len() as f64).sqrt();
    Ok((centre.x, centre.y, r, rms))
}

/// Number of boundary loops of a triangle surface (a written frame's triangles).
pub fn boundary_loops(points: &[[f64; 3]], triangles: &[[usize; 3]]) -> Result<usize> {
    let mesh = Tri3Mesh {
        nodes: vectors(points),
        elements: triangles.to_vec(),
    };
    Ok(Topology::new(&mesh).boundary_loops()?.len())
}

/// Symmetric Hausdorff distance between the point sets of two frames (brute force; small meshes).
pub fn hausdorff(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    measure::hausdorff_distance(&vectors(a), &vectors(b))
}

fn vectors(points: &[[f64; 3]]) -> Vec<Vector3<f64>> {
    points.iter().map(|p| Vector3::from(*p)).collect()
}

/// Rest positions of a frame's points (`x − displacement`).
pub fn rest_positions(frame: &VtuFrame) -> Result<Vec<[f64; 3]>> {
    let u = frame.point_array("displacement").context("frame has no displacement")?;
    Ok(frame
        .points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let d = u.tuple(i);
            [p[0] - d[0], p[1] - d[1], p[2] - d[2]]
        })
        .collect())
}

/// The shape of a buckled disk of rest radius `r`: how far its rim leaves the rim's own best-fit plane
/// (which removes the free body's rigid tilt and drift), how many waves that deviation makes along
/// the rim, and how far the disk's centre lies from that plane (a dome's height).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RimShape {
    /// Largest distance of a rim point from the rim's best-fit plane.
    pub rim_deviation: f64,
    /// Waves of the signed distance along the rim: sign changes of the deviations above a tenth of
    /// the largest, halved.
    pub waves: usize,
    /// Distance of the point nearest to the rest centre from the rim's plane.
    pub centre_height: f64,
}

/// [`RimShape`] of a frame whose rest disk has radius `r` and its centre at the origin.
pub fn rim_shape(frame: &VtuFrame, r: f64) -> Result<RimShape> {
    use nalgebra::{Matrix3, Vector3};
    let rest = rest_positions(frame)?;
    let mut rim: Vec<(f64, Vector3<f64>)> = rest
        .iter()
        .zip(&frame.points)
        .filter(|(x, _)| (x[0].hypot(x[1]) - r).abs() < 1e-3 * r)
        .map(|(x, p)| (x[1].atan2(x[0]), Vector3::from(*p)))
        .collect();
    if rim.len() < 4 {
        bail!("only {} rim points found", rim.len());
    }
    rim.sort_by(|a, b| a.0.total_cmp(&b.0));
    let centroid = rim.iter().map(|(_, p)| p).sum::<Vector3<f64>>() / rim.len() as f64;
    let scatter: Matrix3<f64> = rim.iter().map(|(_, p)| (p - centroid) * (p - centroid).transpose()).sum();
    let eigen = scatter.symmetric_eigen();
    let normal = eigen.eigenvectors.column(eigen.eigenvalues.imin()).into_owned();
    let distances: Vec<f64> = rim.iter().map(|(_, p)| (p - centroid).dot(&normal)).collect();
    let rim_deviation = distances.iter().fold(0.0_f64, |m, d| m.max(d.abs()));
    let signs: Vec<bool> = distances
        .iter()
        .filter(|d| d.abs() > 0.1 * rim_deviation)
        .map(|d| *d > 0.0)
        .collect();
    let changes = (0..signs.len()).filter(|&i| signs[i] != signs[(i + 1) % signs.len()]).count();
    let centre = (0..rest.len())
        .min_by(|&a, &b| rest[a][0].hypot(rest[a][1]).total_cmp(&rest[b][0].hypot(rest[b][1])))
        .context("empty frame")?;
    let centre_height = (Vector3::from(frame.points[centre]) - centroid).dot(&normal).abs();
    Ok(RimShape {
        rim_deviation,
        waves: changes / 2,
        centre_height,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn circle_fit_recovers_a_circle() {
        let pts: Vec<[f64; 3]> = (0..12)
            .map(|k| {
                let a = k as f64 * 0.5;
                [2.0 + 3.0 * a.cos(), 7.0, -1.0 + 3.0 * a.sin()]
            })
            .collect();
        let (ca, cb, r, rms) = fit_circle(&pts, 0, 2).unwrap();
        assert!((ca - 2.0).abs() < 1e-12 && (cb + 1.0).abs() < 1e-12 && (r - 3.0).abs() < 1e-12 && rms < 1e-12);
    }

    /// A disk of radius 1 (rim and centre points) deformed by `z(x, y)`, then tilted about x.
    fn deformed_disk(z: impl Fn(f64, f64) -> f64) -> VtuFrame {
        let mut rest = vec![[0.0, 0.0, 0.0]];
        rest.extend((0..64).map(|k| {
            let a = 2.0 * std::f64::consts::PI * k as f64 / 64.0;
            [a.cos(), a.sin(), 0.0]
        }));
        let (c, s) = (0.3_f64.cos(), 0.3_f64.sin());
        let points: Vec<[f64; 3]> = rest
            .iter()
            .map(|x| {
                let h = z(x[0], x[1]);
                [x[0] + 0.5, c * x[1] - s * h, s * x[1] + c * h]
            })
            .collect();
        let u = rest
            .iter()
            .zip(&points)
            .flat_map(|(x, p)| [p[0] - x[0], p[1] - x[1], p[2] - x[2]])
            .collect();
        let mut frame = VtuFrame::new(points, Vec::new(), 0.0);
        frame.point_data.push(cosserat::io::DataArray::new("displacement", 3, u));
        frame
    }

    #[test]
    fn rim_shape_of_a_tilted_dome_and_a_saddle() {
        let dome = rim_shape(&deformed_disk(|x, y| 0.2 * (1.0 - x * x - y * y)), 1.0).unwrap();
        assert!(dome.rim_deviation < 1e-12 && dome.waves == 0, "{dome:?}");
        assert!((dome.centre_height - 0.2).abs() < 1e-12, "{dome:?}");
        let saddle = rim_shape(&deformed_disk(|x, y| 0.1 * (x * x - y * y)), 1.0).unwrap();
        assert!(
            (saddle.rim_deviation - 0.1).abs() < 1e-12 && saddle.waves == 2,
            "{saddle:?}"
        );
        let wavy = rim_shape(&deformed_disk(|x, y| 0.05 * (3.0 * y.atan2(x)).cos()), 1.0).unwrap();
        assert_eq!(wavy.waves, 3, "{wavy:?}");
    }

    #[test]
    fn boundary_loops_of_a_strip_and_an_annulus() {
        // Two triangles forming a square: one loop.
        let square = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
        assert_eq!(boundary_loops(&square, &[[0, 1, 2], [0, 2, 3]]).unwrap(), 1);
        // A ring of 8 triangles around a square hole: two loops.
        let ring = [
            [0, 1, 5],
            [0, 5, 4],
            [1, 2, 6],
            [1, 6, 5],
            [2, 3, 7],
            [2, 7, 6],
            [3, 0, 4],
            [3, 4, 7],
        ];
        let outer = [[0.0, 0.0], [3.0, 0.0], [3.0, 3.0], [0.0, 3.0]];
        let inner = [[1.0, 1.0], [2.0, 1.0], [2.0, 2.0], [1.0, 2.0]];
        let points: Vec<[f64; 3]> = outer.iter().chain(&inner).map(|p| [p[0], p[1], 0.0]).collect();
        assert_eq!(boundary_loops(&points, &ring).unwrap(), 2);
    }
}
