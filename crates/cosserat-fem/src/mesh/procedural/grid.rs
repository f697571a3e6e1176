//! The rectangle grid of the paper's plate and strip scenes.

use super::{GeneratedMesh, Surface, at_least, positive};
use crate::error::MeshError;
use crate::mesh::TriMesh;
use nalgebra::Vector3;

/// A rectangle `lx × ly` centred at the origin in the plane `z = 0`, split into `nx × ny` quads of two
/// triangles each, with the paper's checkerboard diagonals (experiments.md §0).
///
/// Vertex `(i, j)` (`i ≤ nx` along x, `j ≤ ny` along y) has index `i·(ny+1) + j`. For quad `(i, j)`
/// with `i + j` even the diagonal runs from vertex `(i, j)` to `(i+1, j+1)`, otherwise from `(i+1, j)`
/// to `(i, j+1)`. Quads are visited with `i` outer and `j` inner, two triangles each. All triangles
/// are counter-clockwise (normal `+z`). The mesh has `(nx+1)(ny+1)` vertices and `2·nx·ny` triangles.
///
/// # Errors
/// [`MeshError::InvalidParameter`] for non-positive sizes or zero resolutions.
pub fn rectangle_grid(lx: f64, ly: f64, nx: usize, ny: usize) -> Result<GeneratedMesh, MeshError> {
    const NAME: &str = "rectangle_grid";
    positive(NAME, "lx", lx)?;
    positive(NAME, "ly", ly)?;
    at_least(NAME, "nx", nx, 1)?;
    at_least(NAME, "ny", ny, 1)?;
    let idx = |i: usize, j: usize| i * (ny + 1) + j;
    let mut nodes = Vec::with_capacity((nx + 1) * (ny + 1));
    for i in 0..=nx {
        for j in 0..=ny {
            let x = -0.5 * lx + lx * i as f64 / nx as f64;
            let y = -0.5 * ly + ly * j as f64 / ny as f64;
            nodes.push(Vector3::new(x, y, 0.0));
        }
    }
    let mut elements = Vec::with_capacity(2 * nx * ny);
    for i in 0..nx {
        for j in 0..ny {
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
        surface: Surface::Plane,
    })
}
