//! Frictional contact for the incremental potential of Cosserat shells, strongly coupled: contact forces
//! enter the same Newton solve as the shell (Incremental Potential Contact, Li et al. 2020, with a
//! contact thickness and additive CCD from Li, Kaufman, Jiang 2021).
//!
//! Model: shells contribute flat triangles over their displacement nodes, obstacles contribute triangle
//! meshes whose vertices are not unknowns. Every point–triangle and edge–edge pair between surfaces
//! `s`, `t` (including self-contact) with gap `g = d − (h_s + h_t)` below the barrier width `d̂` adds
//! `b(g) = −κ (g − d̂)² ln(g/d̂)` (edge–edge pairs times IPC's mollifier); the energy is infinite at
//! `g ≤ 0`, and CCD keeps every Newton iterate at `g > 0`. Friction is IPC's lagged, smoothed Coulomb
//! potential with the normal force, closest points and tangent basis of the start of the step.
//!
//! Entry points:
//! - [`ContactTerm`]: the `cosserat_assembly::PotentialTerm` with the step hooks
//!   ([`ContactTerm::begin_step`], [`ContactTerm::max_step_fraction`], [`ContactTerm::coverage`]);
//! - [`distance`]: point–triangle and edge–edge squared distances with closest-feature classification
//!   and exact derivatives; [`barrier`], [`mollifier`], [`friction`]: the scalar functions;
//! - [`ccd`]: additive continuous collision detection with a minimum gap;
//! - [`broad_phase`]: swept-box candidate pairs (BVH, parallel, deterministic), and
//!   [`candidate_cache`]: the same pairs kept between queries while the motion stays within a margin;
//! - [`intersection`]: exact-sign triangle–triangle intersection and [`intersecting_pairs`] of a mesh.
//!
//! Units: SI. Distances, thicknesses and `d̂` in m; `κ` in J/m² (energy per pair, no area weighting);
//! the barrier and friction energies in J, as the incremental potential in velocity unknowns; the
//! stick–slide threshold `ε_v` in m/s (slip distance `ε_v Δt`); friction coefficients dimensionless.
//!
//! Non-goals: rigid bodies with unknowns (obstacles are kinematic), curved (Tri6) contact geometry (the
//! caller splits Tri6 elements into four flat triangles), adaptive barrier stiffness, contact between
//! two obstacles.
//!
//! Feature flags: none.
//!
//! ```
//! use cosserat_contact::barrier::Barrier;
//! use cosserat_contact::distance::{PointTriangleFeature, point_triangle_distance};
//! use nalgebra::Vector3;
//!
//! // A point 2 mm above the interior of a triangle in the plane z = 0.
//! let x = [
//!     Vector3::new(0.2, 0.2, 2e-3),
//!     Vector3::new(0.0, 0.0, 0.0),
//!     Vector3::new(1.0, 0.0, 0.0),
//!     Vector3::new(0.0, 1.0, 0.0),
//! ];
//! let (feature, s) = point_triangle_distance(&x);
//! assert_eq!(feature, PointTriangleFeature::Face);
//! assert!((s.sqrt() - 2e-3).abs() < 1e-15);
//! // With thicknesses summing to 1 mm the gap is 1 mm: inside a 2 mm barrier, which repels.
//! let barrier = Barrier::try_new(1e3, 2e-3).unwrap();
//! let (b, db, _) = barrier.derivatives(s.sqrt() - 1e-3);
//! assert!(b > 0.0 && db < 0.0);
//! ```

// Comparisons written `!(x > 0.0)` deliberately reject NaN together with non-positive values.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod barrier;
pub mod broad_phase;
pub mod bvh;
pub mod candidate_cache;
pub mod ccd;
pub mod closed_form;
pub mod distance;
pub mod error;
pub mod friction;
pub mod intersection;
pub mod jet;
pub mod mesh;
pub mod mollifier;
pub mod pair;
pub mod parameters;
pub mod stats;
pub mod term;

pub use candidate_cache::CacheCounters;
pub use error::ContactError;
pub use intersection::{intersecting_pairs, triangles_intersect};
pub use jet::PairJet;
pub use mesh::{ContactMesh, ContactSurface, Obstacle};
pub use parameters::{ContactParameters, FrictionTable};
pub use stats::{ContactStats, Coverage};
pub use term::ContactTerm;
