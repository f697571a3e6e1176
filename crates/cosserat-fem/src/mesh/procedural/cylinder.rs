//! Open cylinders about the z axis.

use super::{GeneratedMesh, Surface, at_least, positive};
use crate::error::MeshError;
use crate::mesh::TriMesh;
use nalgebra::Vector3;
use std::f64::consts::PI;

/// An open cylinder of radius `radius` about the z axis, `−length/2 ≤ z ≤ length/2`, with `n_around`
/// vertices per ring and `n_along` rings of quads, split with alternating diagonals. Normals point
/// outwards. Vertex `(i, j)` (`i` around, `j ≤ n_along` along) has index `j·n_around + i`. Two
/// boundary loops (the end circles).
///
/// # Errors
/// [`MeshError::InvalidParameter`] for non-positive sizes, `n_around < 3` or `n_along < 1`.
pub fn cylinder(radius: f64, length: f64, n_around: usize, n_along: usize) -> Result<GeneratedMesh, MeshError> {
    const NAME: &str = "cylinder";
    positive(NAME, "radius", radius)?;
    positive(NAME, "length", length)?;
    at_least(NAME, "n_around", n_around, 3)?;
    at_least(NAME, "n_along", n_along, 1)?;
    let idx = |i: usize, j: usize| j * n_around + i % n_around;
    let mut nodes = Vec::with_capacity(n_around * (n_along + 1));
    for j in 0..=n_along {
        let z = -0.5 * length + length * j as f64 / n_along as f64;
        for i in 0..n_around {
            let theta = 2.0 * PI * i as f64 / n_around as f64;
            nodes.push(Vector3::new(radius * theta.cos(), radius * theta.sin(), z));
        }
    }
    let mut elements = Vec::with_capacity(2 * n_around * n_along);
    for j in 0..n_along {
        for i in 0..n_around {
            // (e_θ, e_z) is a right-handed tangent pair for the outward normal e_r.
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
        surface: Surface::Cylinder { radius },
    })
}
