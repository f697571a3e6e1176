//! Reading run outputs back and measuring what the experiments should show (probes, circle fits,
//! boundary loops, the rim of a buckled disk). Pure geometry on written results: no physics.

use anyhow::{Context, Result, bail};
use cosserat::io::VtuFrame;
use std::collections::HashMap;
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
    if points.len() < 3 {
        bail!("a circle fit needs at least 3 points");
    }
    // Solve [x y 1] [D E F]ᵀ = −(x² + y²) in the least-squares sense.
    let mut ata = nalgebra::Matrix3::<f64>::zeros();
    let mut atb = nalgebra::Vector3::<f64>::zeros();
    for p in points {
        let row = nalgebra::Vector3::new(p[a], p[b], 1.0);
        ata += row * row.transpose();
        atb += row * -(p[a] * p[a] + p[b] * p[b]);
    }
    let sol = ata.lu().solve(&atb).context("degenerate circle fit")?;
    let (ca, cb) = (-0.5 * sol[0], -0.5 * sol[1]);
    let r = (ca * ca + cb * cb - sol[2]).sqrt();
    let rms =
        (points.iter().map(|p| ((p[a] - ca).hypot(p[b] - cb) - r).powi(2)).sum::<f64>() / points.len() as f64).sqrt();
    Ok((ca, cb, r, rms))
}

/// Number of boundary loops of a triangle surface (edges used by exactly one triangle, chained).
pub fn boundary_loops(triangles: &[[usize; 3]]) -> usize {
    let mut count: HashMap<(usize, usize), usize> = HashMap::new();
    for t in triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            *count.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    let boundary: Vec<(usize, usize)> = count.into_iter().filter(|&(_, n)| n == 1).map(|(e, _)| e).collect();
    let mut adjacency: HashMap<usize, Vec<usize>> = HashMap::new();
    for &(a, b) in &boundary {
        adjacency.entry(a).or_default().push(b);
        adjacency.entry(b).or_default().push(a);
    }
    // Connected components of the boundary graph.
    let mut seen: HashMap<usize, bool> = HashMap::new();
    let mut loops = 0;
    for &start in adjacency.keys() {
        if seen.contains_key(&start) {
            continue;
        }
        loops += 1;
        let mut stack = vec![start];
        while let Some(v) = stack.pop() {
            if seen.insert(v, true).is_some() {
                continue;
            }
            stack.extend(adjacency[&v].iter().filter(|w| !seen.contains_key(w)));
        }
    }
    loops
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

/// Symmetric Hausdorff distance between the point sets of two frames (brute force; small meshes).
pub fn hausdorff(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    let one_way = |p: &[[f64; 3]], q: &[[f64; 3]]| {
        p.iter()
            .map(|x| {
                q.iter()
                    .map(|y| ((x[0] - y[0]).powi(2) + (x[1] - y[1]).powi(2) + (x[2] - y[2]).powi(2)).sqrt())
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0, f64::max)
    };
    one_way(a, b).max(one_way(b, a))
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
        assert_eq!(boundary_loops(&[[0, 1, 2], [0, 2, 3]]), 1);
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
        assert_eq!(boundary_loops(&ring), 2);
    }
}
