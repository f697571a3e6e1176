//! Disks and annuli in the plane `z = 0`, optionally cut open along a radius.

use super::{GeneratedMesh, Surface, at_least, positive};
use crate::error::MeshError;
use crate::mesh::TriMesh;
use nalgebra::Vector3;
use std::f64::consts::PI;

/// Parameters of [`annulus`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AnnulusSettings {
    /// Inner radius; 0 gives a disk with a centre vertex.
    pub inner_radius: f64,
    /// Outer radius, larger than the inner one.
    pub outer_radius: f64,
    /// Number of rings of elements between the radii (at least 1).
    pub n_radial: usize,
    /// Number of vertices per ring (at least 3).
    pub n_angular: usize,
    /// Cut the mesh open along the positive x axis: the vertices at angle 0 are duplicated, so the
    /// elements on the two sides of the cut share no edge.
    pub slit: bool,
}

impl AnnulusSettings {
    /// The corner vertices on the two sides of the slit, from the inner boundary outwards (ascending
    /// indices): first the
    /// side at angle 0, whose elements begin the sweep, then its duplicates at angle 2π, whose elements
    /// end it (a disk's centre vertex lies on both). `None` without a slit. The indices are those of
    /// [`annulus`]'s mesh.
    pub fn slit_sides(&self) -> Option<(Vec<usize>, Vec<usize>)> {
        if !self.slit {
            return None;
        }
        let per_ring = self.n_angular + 1;
        let (centre, rings) = if self.inner_radius == 0.0 {
            (vec![0], self.n_radial)
        } else {
            (Vec::new(), self.n_radial + 1)
        };
        let side = |j: usize| {
            let offset = centre.len();
            centre
                .iter()
                .copied()
                .chain((0..rings).map(|ring| offset + ring * per_ring + j))
                .collect()
        };
        Some((side(0), side(self.n_angular)))
    }
}

/// A disk of radius `radius` about the origin in `z = 0`; see [`annulus`].
///
/// # Errors
/// As [`annulus`].
pub fn disk(radius: f64, n_radial: usize, n_angular: usize) -> Result<GeneratedMesh, MeshError> {
    annulus(&AnnulusSettings {
        inner_radius: 0.0,
        outer_radius: radius,
        n_radial,
        n_angular,
        slit: false,
    })
}

/// An annulus (or a disk, for inner radius 0) about the origin in `z = 0`, with normal `+z`.
///
/// Rings of `n_angular` vertices sit at equally spaced radii (and angles `2πk/n_angular`); a disk has
/// one more vertex at the centre, joined to the first ring by a fan. The quads between rings are split
/// with alternating diagonals. With a slit each ring has `n_angular + 1` vertices, the last one a
/// duplicate of the first. Boundary loops: one for a disk or a slit annulus, two for an annulus.
///
/// # Errors
/// [`MeshError::InvalidParameter`] unless `0 ≤ inner < outer` (finite), `n_radial ≥ 1` and
/// `n_angular ≥ 3`.
pub fn annulus(settings: &AnnulusSettings) -> Result<GeneratedMesh, MeshError> {
    const NAME: &str = "annulus";
    let &AnnulusSettings {
        inner_radius,
        outer_radius,
        n_radial,
        n_angular,
        slit,
    } = settings;
    positive(NAME, "outer_radius", outer_radius)?;
    if !(inner_radius >= 0.0 && inner_radius < outer_radius) {
        return Err(MeshError::InvalidParameter {
            generator: NAME,
            parameter: "inner_radius",
            value: inner_radius,
            reason: "must satisfy 0 ≤ inner_radius < outer_radius",
        });
    }
    at_least(NAME, "n_radial", n_radial, 1)?;
    at_least(NAME, "n_angular", n_angular, 3)?;
    let is_disk = inner_radius == 0.0;
    let per_ring = if slit { n_angular + 1 } else { n_angular };
    let rings: Vec<usize> = if is_disk {
        (1..=n_radial).collect()
    } else {
        (0..=n_radial).collect()
    };
    let mut nodes = Vec::new();
    if is_disk {
        nodes.push(Vector3::zeros());
    }
    let offset = nodes.len();
    for &k in &rings {
        let r = inner_radius + (outer_radius - inner_radius) * k as f64 / n_radial as f64;
        for j in 0..per_ring {
            let theta = 2.0 * PI * j as f64 / n_angular as f64;
            nodes.push(if j == n_angular {
                // The slit duplicate of the vertex at angle 0, bit-identical to it.
                Vector3::new(r, 0.0, 0.0)
            } else {
                Vector3::new(r * theta.cos(), r * theta.sin(), 0.0)
            });
        }
    }
    let ring_vertex = |ring: usize, j: usize| offset + ring * per_ring + j;
    let next = |j: usize| if slit { j + 1 } else { (j + 1) % n_angular };
    let mut elements = Vec::new();
    if is_disk {
        for j in 0..n_angular {
            elements.push([0, ring_vertex(0, j), ring_vertex(0, next(j))]);
        }
    }
    for ring in 0..rings.len() - 1 {
        for j in 0..n_angular {
            let (a, b) = (ring_vertex(ring, j), ring_vertex(ring, next(j)));
            let (c, d) = (ring_vertex(ring + 1, next(j)), ring_vertex(ring + 1, j));
            // Counter-clockwise seen from +z: a → d (outwards) → c → b (back inwards).
            if (ring + j) % 2 == 0 {
                elements.push([a, d, c]);
                elements.push([a, c, b]);
            } else {
                elements.push([a, d, b]);
                elements.push([d, c, b]);
            }
        }
    }
    Ok(GeneratedMesh {
        mesh: TriMesh { nodes, elements },
        surface: Surface::Annulus {
            inner_radius,
            outer_radius,
        },
    })
}
