//! Lagrange triangle elements, quadrature rules and element meshes for Cosserat shells.
//!
//! This crate is the discretisation layer of the three-director Cosserat shell simulator (Löschner et
//! al. 2024). It knows about elements and meshes, and about geometry at quadrature points; it knows
//! nothing about energies, assembly or solvers.
//!
//! Entry points:
//! - [`element`]: the [`ShapeFunctions`] trait and the elements [`Tri3`], [`Tri6`] (the paper's
//!   displacement element, supplement section 3) and [`Tri10`], with values, gradients and second
//!   derivatives on the reference triangle.
//! - [`quadrature`]: [`QuadratureRule`], symmetric positive rules of degree 1–6 and 8, including the
//!   supplement's 3-point rule and the model's pairing per element pair.
//! - [`mesh`]: [`TriMesh`] (`Tri3Mesh`, `Tri6Mesh`, `Tri10Mesh`) with validation, [`mesh::Topology`]
//!   (edges, boundary loops, orientation), Tri3 → Tri6/Tri10 upgrades with placement hooks, the
//!   corner (rotation) mesh of a higher-order mesh, uniform refinement, normal fields (exact element
//!   normal, averaged nodal normals), the rest curvature `b, H, K` at every quadrature point
//!   ([`mesh::rest_geometry`]) and [`mesh::procedural`] generators (grid, disk/annulus, cylinder,
//!   spheres, Möbius band).
//!
//! Non-goals: energy densities and their derivatives (`cosserat-material`), global assembly and sparse
//! matrices (`cosserat-assembly`), file formats (`cosserat-scene`). Meshes are plain data with public
//! fields; the checks in `TriMesh::validate` are the contract that later layers rely on.
//!
//! Feature flags: none.
//!
//! ```
//! use cosserat_fem::mesh::{CurvatureSettings, procedural, rest_geometry};
//! use cosserat_fem::QuadratureRule;
//!
//! // A unit icosphere, upgraded to curved Tri6 elements with every node on the sphere.
//! let sphere = procedural::icosphere(1.0, 2).unwrap();
//! let tri6 = sphere.to_tri6_on_surface();
//! tri6.validate().unwrap();
//! // Rest curvature at the quadrature points of the paper's Tri6/Tri3 pairing.
//! let rule = QuadratureRule::interior_p2();
//! let geometry = rest_geometry(&tri6, &sphere.mesh, &rule, &CurvatureSettings::default()).unwrap();
//! let point = geometry.at(0, 0);
//! // Outward normal: H = -1/R, K = 1/R² (up to the discretisation error).
//! assert!((point.curvature.mean + 1.0).abs() < 0.05);
//! assert!((point.curvature.gaussian - 1.0).abs() < 0.1);
//! ```

pub mod element;
pub mod error;
pub mod mesh;
pub mod quadrature;

pub use element::{ElementKind, ShapeFunctions, Tri3, Tri6, Tri10};
pub use error::MeshError;
pub use mesh::{Tri3Mesh, Tri6Mesh, Tri10Mesh, TriMesh};
pub use quadrature::QuadratureRule;
