//! Flat tensor-product grids recognised in a triangle mesh's vertices: the mid-surface that the
//! micropolar volume model extrudes into a slab of tetrahedra.
//!
//! The scene describes a volumetric slab by its mid-surface (a rectangle mesh) and a thickness, so that
//! regions, probes and rest fields are written exactly as for a shell. [`PlanarGrid::detect`] checks
//! that the vertices form a full `nx + 1` by `ny + 1` grid in a plane `z = const` and gives each vertex
//! its grid position `(i, j)`; the simulator maps a vertex to the column of slab nodes above it.

/// A flat grid: sorted distinct coordinates along x and y, the plane's height, and each vertex's
/// grid position.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanarGrid {
    /// Distinct x coordinates, increasing \[m\].
    pub xs: Vec<f64>,
    /// Distinct y coordinates, increasing \[m\].
    pub ys: Vec<f64>,
    /// The height of the plane \[m\].
    pub z: f64,
    /// `(i, j)` of every vertex: its x is `xs[i]`, its y is `ys[j]`.
    pub vertex_ij: Vec<(usize, usize)>,
}

/// Distinct values of `v` (sorted), merging values closer than `tol`.
fn distinct(mut v: Vec<f64>, tol: f64) -> Vec<f64> {
    v.sort_by(f64::total_cmp);
    let mut out: Vec<f64> = Vec::new();
    for x in v {
        if out.last().is_none_or(|&last| x - last > tol) {
            out.push(x);
        }
    }
    out
}

impl PlanarGrid {
    /// Recognises the grid of `points`.
    ///
    /// # Errors
    /// A message saying why the points are not a full, flat, uniform grid in a plane `z = const`
    /// (vertices off the plane, a missing or repeated grid point, or unequal spacing).
    pub fn detect(points: &[nalgebra::Vector3<f64>]) -> Result<Self, String> {
        if points.len() < 4 || points.iter().any(|p| !p.iter().all(|c| c.is_finite())) {
            return Err("the mesh needs at least 4 finite vertices".into());
        }
        let extent = points
            .iter()
            .fold(0.0f64, |m, p| m.max(p.x.abs()).max(p.y.abs()).max(p.z.abs()));
        let tol = 1e-9 * extent.max(1e-12);
        let z = points[0].z;
        if let Some(p) = points.iter().find(|p| (p.z - z).abs() > tol) {
            return Err(format!(
                "its vertices do not lie in one plane z = const (z = {z} and z = {} occur)",
                p.z
            ));
        }
        let xs = distinct(points.iter().map(|p| p.x).collect(), tol);
        let ys = distinct(points.iter().map(|p| p.y).collect(), tol);
        if xs.len() < 2 || ys.len() < 2 {
            return Err("the vertices span no area in the xy plane".into());
        }
        if xs.len() * ys.len() != points.len() {
            return Err(format!(
                "{} vertices do not form a full grid of {} × {} distinct x and y values",
                points.len(),
                xs.len(),
                ys.len()
            ));
        }
        for (axis, values) in [("x", &xs), ("y", &ys)] {
            let step = (values[values.len() - 1] - values[0]) / (values.len() - 1) as f64;
            if values.windows(2).any(|w| ((w[1] - w[0]) - step).abs() > 1e-6 * step) {
                return Err(format!("the grid spacing along {axis} is not uniform"));
            }
        }
        let index = |values: &[f64], v: f64| values.partition_point(|&x| x < v - tol);
        let mut seen = vec![false; points.len()];
        let mut vertex_ij = Vec::with_capacity(points.len());
        for p in points {
            let ij = (index(&xs, p.x), index(&ys, p.y));
            let slot = ij.0 * ys.len() + ij.1;
            if std::mem::replace(&mut seen[slot], true) {
                return Err(format!(
                    "two vertices share the grid point ({}, {})",
                    xs[ij.0], ys[ij.1]
                ));
            }
            vertex_ij.push(ij);
        }
        Ok(Self { xs, ys, z, vertex_ij })
    }

    /// Cells along x and y.
    pub fn cells(&self) -> [usize; 2] {
        [self.xs.len() - 1, self.ys.len() - 1]
    }

    /// Edge lengths along x and y \[m\].
    pub fn size(&self) -> [f64; 2] {
        [
            self.xs[self.xs.len() - 1] - self.xs[0],
            self.ys[self.ys.len() - 1] - self.ys[0],
        ]
    }

    /// The centre of the grid \[m\].
    pub fn center(&self) -> nalgebra::Vector3<f64> {
        nalgebra::Vector3::new(
            0.5 * (self.xs[0] + self.xs[self.xs.len() - 1]),
            0.5 * (self.ys[0] + self.ys[self.ys.len() - 1]),
            self.z,
        )
    }
}
