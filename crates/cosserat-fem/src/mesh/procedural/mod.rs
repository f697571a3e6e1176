//! Procedural Tri3 meshes of simple surfaces, with the exact surface attached so that upgrades and
//! refinements can place their new nodes on it.
//!
//! Every generator returns a [`GeneratedMesh`]: the Tri3 mesh plus a [`Surface`] description.
//! [`GeneratedMesh::to_tri6_on_surface`] and [`GeneratedMesh::to_tri10_on_surface`] give curved
//! elements whose nodes lie on the exact surface; [`GeneratedMesh::refine_on_surface`] refines while
//! keeping all vertices on it. Parameters are checked and bad values give
//! [`MeshError::InvalidParameter`], never a panic or NaN.
//!
//! Generators: [`rectangle_grid`] (the paper's checkerboard grid), [`disk`] and [`annulus`] (optional
//! radial slit), [`cylinder`], [`icosphere`], [`uv_sphere`], [`uv_hemisphere`] (optional polar hole via
//! [`GeneratedMesh::with_polar_hole`]) and [`mobius_strip`].

mod cylinder;
mod disk;
mod grid;
mod mobius;
mod sphere;

pub use cylinder::cylinder;
pub use disk::{AnnulusSettings, annulus, disk};
pub use grid::rectangle_grid;
pub use mobius::mobius_strip;
pub use sphere::{icosphere, uv_hemisphere, uv_sphere};

use super::tri_mesh::{Tri3Mesh, Tri6Mesh, Tri10Mesh, TriMesh};
use super::upgrade::NewNode;
use crate::error::MeshError;
use nalgebra::Vector3;
use std::f64::consts::PI;

/// The exact surface a generated mesh approximates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Surface {
    /// The plane `z = 0` with a polygonal outline (straight edges are exact).
    Plane,
    /// The plane `z = 0` with circular boundaries of radius `inner_radius` (if positive) and
    /// `outer_radius` about the origin. New nodes on boundary edges are placed on the circles.
    Annulus {
        /// Inner radius (0 for a disk).
        inner_radius: f64,
        /// Outer radius.
        outer_radius: f64,
    },
    /// The cylinder of radius `radius` about the z axis.
    Cylinder {
        /// Radius.
        radius: f64,
    },
    /// The sphere of radius `radius` about the origin.
    Sphere {
        /// Radius.
        radius: f64,
    },
    /// The Möbius band `X(u, v) = ((R + v cos(u/2)) cos u, (R + v cos(u/2)) sin u, v sin(u/2))`.
    Mobius {
        /// Centre-line radius `R`.
        radius: f64,
    },
}

impl Surface {
    /// The point of the surface closest to `p` (for points near the surface).
    ///
    /// Planes and the annulus project along z, the cylinder radially from its axis, the sphere
    /// radially from its centre; the Möbius band by a few Gauss–Newton iterations on `(u, v)`. A point
    /// on an axis (or the centre) where the projection is undefined is returned unchanged.
    pub fn project(&self, p: &Vector3<f64>) -> Vector3<f64> {
        match *self {
            Self::Plane | Self::Annulus { .. } => Vector3::new(p.x, p.y, 0.0),
            Self::Cylinder { radius } => {
                let r = p.xy().norm();
                if r > 0.0 {
                    Vector3::new(p.x * radius / r, p.y * radius / r, p.z)
                } else {
                    *p
                }
            }
            Self::Sphere { radius } => {
                let r = p.norm();
                if r > 0.0 { p * (radius / r) } else { *p }
            }
            Self::Mobius { radius } => mobius::project(radius, p),
        }
    }
}

/// A generated Tri3 mesh and the exact surface it approximates.
#[derive(Debug, Clone, PartialEq)]
pub struct GeneratedMesh {
    /// The Tri3 mesh; all its vertices lie on `surface`.
    pub mesh: Tri3Mesh,
    /// The exact surface.
    pub surface: Surface,
}

impl GeneratedMesh {
    /// The exact-surface position of a node created by an upgrade or refinement of `self.mesh`.
    ///
    /// New nodes are placed by interpolating the surface's own coordinates, so that Tri10 edge nodes
    /// at ⅓ and ⅔ are equally spaced along the surface (projecting the chord points instead spaces them
    /// unevenly and makes the cubic interpolant's curvature several times less accurate):
    /// - sphere: edge nodes on the great-circle arc at angle fraction `t` (slerp), interior nodes
    ///   projected radially from the flat position;
    /// - cylinder: angle about the axis and height interpolated linearly (a helix);
    /// - Möbius band: the band parameters `(u, v)` interpolated linearly across the seam;
    /// - annulus: a node on an edge whose two vertices lie on the same boundary circle is placed on that
    ///   circle at the interpolated angle; every other node stays at its chord position;
    /// - plane: the chord position.
    ///
    /// At `t = ½` the sphere and cylinder placements coincide with projecting the chord midpoint.
    ///
    /// # Panics
    /// If the node refers to a vertex index out of range of `self.mesh`.
    pub fn place(&self, node: NewNode) -> Vector3<f64> {
        let (vertices, weights): (Vec<usize>, Vec<f64>) = match node {
            NewNode::Edge { vertices, t, .. } => (vertices.to_vec(), vec![1.0 - t, t]),
            NewNode::Interior {
                vertices, barycentric, ..
            } => (vertices.to_vec(), barycentric.to_vec()),
        };
        let x: Vec<Vector3<f64>> = vertices.iter().map(|&v| self.mesh.nodes[v]).collect();
        match (self.surface, node) {
            (Surface::Plane, _) => node.chord(),
            (
                Surface::Annulus {
                    inner_radius,
                    outer_radius,
                },
                NewNode::Edge { .. },
            ) => {
                for r in [inner_radius, outer_radius] {
                    let on = |p: &Vector3<f64>| r > 0.0 && (p.xy().norm() - r).abs() <= 1e-9 * r;
                    if on(&x[0]) && on(&x[1]) {
                        let theta = interpolate_angles(&[x[0].y.atan2(x[0].x), x[1].y.atan2(x[1].x)], &weights);
                        return Vector3::new(r * theta.cos(), r * theta.sin(), 0.0);
                    }
                }
                node.chord()
            }
            (Surface::Annulus { .. }, NewNode::Interior { .. }) => node.chord(),
            (Surface::Sphere { radius }, NewNode::Edge { t, .. }) => slerp(&x[0], &x[1], t) * radius,
            (Surface::Sphere { .. }, NewNode::Interior { .. }) => self.surface.project(&node.chord()),
            (Surface::Cylinder { radius }, _) => {
                let angles: Vec<f64> = x.iter().map(|p| p.y.atan2(p.x)).collect();
                let theta = interpolate_angles(&angles, &weights);
                let z = x.iter().zip(&weights).map(|(p, w)| p.z * w).sum();
                Vector3::new(radius * theta.cos(), radius * theta.sin(), z)
            }
            (Surface::Mobius { radius }, _) => mobius::interpolate(radius, &x, &weights),
        }
    }

    /// The Tri6 upgrade with every new node on the exact surface (curved elements).
    pub fn to_tri6_on_surface(&self) -> Tri6Mesh {
        self.mesh.to_tri6_with(|node| self.place(node))
    }

    /// The Tri10 upgrade with every new node on the exact surface (curved elements).
    pub fn to_tri10_on_surface(&self) -> Tri10Mesh {
        self.mesh.to_tri10_with(|node| self.place(node))
    }

    /// One uniform refinement with the new vertices on the exact surface.
    pub fn refine_on_surface(&self) -> GeneratedMesh {
        GeneratedMesh {
            mesh: self.mesh.refine_uniform_with(|node| self.place(node)),
            surface: self.surface,
        }
    }

    /// Keeps the faces for which `keep(face index, corner positions)` holds, and drops the vertices
    /// no longer used (vertex order is preserved).
    ///
    /// # Errors
    /// [`MeshError::EmptyMesh`] if no face is kept.
    pub fn retain_faces(self, mut keep: impl FnMut(usize, &[Vector3<f64>; 3]) -> bool) -> Result<Self, MeshError> {
        let elements: Vec<[usize; 3]> = (0..self.mesh.n_elements())
            .filter(|&f| keep(f, &self.mesh.element_nodes(f)))
            .map(|f| self.mesh.elements[f])
            .collect();
        if elements.is_empty() {
            return Err(MeshError::EmptyMesh {
                operation: "retain_faces",
            });
        }
        let (mesh, _) = TriMesh {
            nodes: self.mesh.nodes,
            elements,
        }
        .without_unreferenced_nodes();
        Ok(Self {
            mesh,
            surface: self.surface,
        })
    }

    /// Removes the polar cap: keeps the faces whose centroid has a polar angle (from the +z axis, seen
    /// from the origin) of at least `polar_angle` radians. On a UV sphere whose latitude ring lies at
    /// `polar_angle`, the hole's rim is exactly that ring.
    ///
    /// # Errors
    /// [`MeshError::InvalidParameter`] unless `0 ≤ polar_angle < π`; [`MeshError::EmptyMesh`] if
    /// every face is removed.
    pub fn with_polar_hole(self, polar_angle: f64) -> Result<Self, MeshError> {
        if !(0.0..PI).contains(&polar_angle) {
            return Err(MeshError::InvalidParameter {
                generator: "with_polar_hole",
                parameter: "polar_angle",
                value: polar_angle,
                reason: "must lie in [0, π)",
            });
        }
        self.retain_faces(|_, x| {
            let c = (x[0] + x[1] + x[2]) / 3.0;
            c.xy().norm().atan2(c.z) >= polar_angle
        })
    }
}

/// The weighted mean of angles, each unwrapped to within π of the first.
fn interpolate_angles(angles: &[f64], weights: &[f64]) -> f64 {
    let first = angles[0];
    angles
        .iter()
        .zip(weights)
        .map(|(&a, &w)| {
            let mut d = a - first;
            if d > PI {
                d -= 2.0 * PI;
            } else if d < -PI {
                d += 2.0 * PI;
            }
            w * (first + d)
        })
        .sum()
}

/// The point at fraction `t` of the great-circle arc from `a/|a|` to `b/|b|` (a unit vector); the
/// normalised chord point if the two are (nearly) parallel or antipodal.
fn slerp(a: &Vector3<f64>, b: &Vector3<f64>, t: f64) -> Vector3<f64> {
    let (ua, ub) = (a.normalize(), b.normalize());
    let omega = ua.cross(&ub).norm().atan2(ua.dot(&ub));
    let s = omega.sin();
    if s < 1e-12 {
        return (ua * (1.0 - t) + ub * t).normalize();
    }
    ua * (((1.0 - t) * omega).sin() / s) + ub * ((t * omega).sin() / s)
}

/// Checks a positive finite length.
fn positive(generator: &'static str, parameter: &'static str, value: f64) -> Result<f64, MeshError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(MeshError::InvalidParameter {
            generator,
            parameter,
            value,
            reason: "must be positive and finite",
        })
    }
}

/// Checks a resolution of at least `min`.
fn at_least(generator: &'static str, parameter: &'static str, value: usize, min: usize) -> Result<usize, MeshError> {
    if value >= min {
        Ok(value)
    } else {
        Err(MeshError::InvalidParameter {
            generator,
            parameter,
            value: value as f64,
            reason: match min {
                1 => "must be at least 1",
                2 => "must be at least 2",
                3 => "must be at least 3",
                _ => "is too small",
            },
        })
    }
}

/// Reverses the faces whose normal has a positive component along `inward(centroid)`, so that every
/// normal points away from that direction.
fn orient_faces(mesh: &mut Tri3Mesh, inward: impl Fn(&Vector3<f64>) -> Vector3<f64>) {
    for f in 0..mesh.n_elements() {
        let x = mesh.element_nodes(f);
        let n = (x[1] - x[0]).cross(&(x[2] - x[0]));
        let c = (x[0] + x[1] + x[2]) / 3.0;
        if n.dot(&inward(&c)) > 0.0 {
            mesh.elements[f].swap(1, 2);
        }
    }
}
