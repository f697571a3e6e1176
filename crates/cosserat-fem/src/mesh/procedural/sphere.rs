//! Spheres and hemispheres about the origin: icospheres and latitude–longitude (UV) spheres.

use super::{GeneratedMesh, Surface, at_least, orient_faces, positive};
use crate::error::MeshError;
use crate::mesh::TriMesh;
use nalgebra::Vector3;
use std::f64::consts::PI;

/// The icosahedron subdivided `level` times, every vertex on the sphere of radius `radius` about the
/// origin (new vertices are projected radially after each subdivision). Normals point outwards.
///
/// Level `l` has `10·4^l + 2` vertices and `20·4^l` triangles; the 12 original vertices keep indices
/// 0–11 and have five neighbours, all others six.
///
/// # Errors
/// [`MeshError::InvalidParameter`] for a non-positive radius or `level > 8` (over a million faces).
pub fn icosphere(radius: f64, level: usize) -> Result<GeneratedMesh, MeshError> {
    positive("icosphere", "radius", radius)?;
    if level > 8 {
        return Err(MeshError::InvalidParameter {
            generator: "icosphere",
            parameter: "level",
            value: level as f64,
            reason: "must be at most 8",
        });
    }
    let phi = 0.5 * (1.0 + 5.0_f64.sqrt());
    #[rustfmt::skip]
    let raw = [
        [-1.0, phi, 0.0], [1.0, phi, 0.0], [-1.0, -phi, 0.0], [1.0, -phi, 0.0],
        [0.0, -1.0, phi], [0.0, 1.0, phi], [0.0, -1.0, -phi], [0.0, 1.0, -phi],
        [phi, 0.0, -1.0], [phi, 0.0, 1.0], [-phi, 0.0, -1.0], [-phi, 0.0, 1.0],
    ];
    let nodes = raw.iter().map(|p| Vector3::from(*p).normalize() * radius).collect();
    #[rustfmt::skip]
    let elements = vec![
        [0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11],
        [1, 5, 9], [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8],
        [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9],
        [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1],
    ];
    let mut mesh = TriMesh { nodes, elements };
    orient_faces(&mut mesh, |c| -c);
    let mut generated = GeneratedMesh {
        mesh,
        surface: Surface::Sphere { radius },
    };
    for _ in 0..level {
        generated = generated.refine_on_surface();
    }
    Ok(generated)
}

/// A latitude–longitude sphere of radius `radius` about the origin: poles on the z axis, `n_lat − 1`
/// rings of `n_lon` vertices at polar angles `πk/n_lat`, pole fans and quads split into two triangles.
/// Normals point outwards. Vertex 0 is the north pole `(0, 0, R)`, the last vertex the south pole.
///
/// # Errors
/// [`MeshError::InvalidParameter`] for a non-positive radius, `n_lon < 3` or `n_lat < 2`.
pub fn uv_sphere(radius: f64, n_lon: usize, n_lat: usize) -> Result<GeneratedMesh, MeshError> {
    const NAME: &str = "uv_sphere";
    positive(NAME, "radius", radius)?;
    at_least(NAME, "n_lon", n_lon, 3)?;
    at_least(NAME, "n_lat", n_lat, 2)?;
    let rings: Vec<f64> = (1..n_lat).map(|k| PI * k as f64 / n_lat as f64).collect();
    let mut mesh = latitude_rings(radius, n_lon, &rings);
    let south = mesh.n_nodes();
    mesh.nodes.push(Vector3::new(0.0, 0.0, -radius));
    let last = 1 + (rings.len() - 1) * n_lon;
    for j in 0..n_lon {
        mesh.elements.push([south, last + j, last + (j + 1) % n_lon]);
    }
    orient_faces(&mut mesh, |c| -c);
    Ok(GeneratedMesh {
        mesh,
        surface: Surface::Sphere { radius },
    })
}

/// The upper half `z ≥ 0` of a latitude–longitude sphere: the north pole (vertex 0) and `n_lat` rings
/// of `n_lon` vertices at polar angles `(π/2)·k/n_lat`, the last ring exactly on the equator `z = 0`.
/// Normals point outwards; one boundary loop (the equator).
///
/// `uv_hemisphere(1.0, 8, 2)` is the Dumpling's base mesh (17 vertices, 24 triangles).
///
/// # Errors
/// [`MeshError::InvalidParameter`] for a non-positive radius, `n_lon < 3` or `n_lat < 1`.
pub fn uv_hemisphere(radius: f64, n_lon: usize, n_lat: usize) -> Result<GeneratedMesh, MeshError> {
    const NAME: &str = "uv_hemisphere";
    positive(NAME, "radius", radius)?;
    at_least(NAME, "n_lon", n_lon, 3)?;
    at_least(NAME, "n_lat", n_lat, 1)?;
    let rings: Vec<f64> = (1..=n_lat).map(|k| 0.5 * PI * k as f64 / n_lat as f64).collect();
    let mut mesh = latitude_rings(radius, n_lon, &rings);
    // The last ring is the equator: make its z exactly 0.
    let equator = 1 + (n_lat - 1) * n_lon;
    for p in &mut mesh.nodes[equator..] {
        p.z = 0.0;
    }
    orient_faces(&mut mesh, |c| -c);
    Ok(GeneratedMesh {
        mesh,
        surface: Surface::Sphere { radius },
    })
}

/// The north pole, rings of `n_lon` vertices at the given polar angles, the pole fan and the quads
/// between consecutive rings (not yet oriented).
fn latitude_rings(radius: f64, n_lon: usize, polar_angles: &[f64]) -> TriMesh<3> {
    let mut nodes = vec![Vector3::new(0.0, 0.0, radius)];
    for &theta in polar_angles {
        for j in 0..n_lon {
            let phi = 2.0 * PI * j as f64 / n_lon as f64;
            nodes.push(radius * Vector3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos()));
        }
    }
    let ring = |k: usize, j: usize| 1 + k * n_lon + j % n_lon;
    let mut elements = Vec::new();
    for j in 0..n_lon {
        elements.push([0, ring(0, j), ring(0, j + 1)]);
    }
    for k in 0..polar_angles.len() - 1 {
        for j in 0..n_lon {
            let (a, b, c, d) = (ring(k, j), ring(k, j + 1), ring(k + 1, j + 1), ring(k + 1, j));
            elements.push([a, b, c]);
            elements.push([a, c, d]);
        }
    }
    TriMesh { nodes, elements }
}
