//! Differential geometry at a point and rotations, generic over the scalar type; and how the project
//! writes numbers as text ([`Num`]).
//!
//! This is the bottom layer of the Cosserat shell simulator. Everything here is written once for any
//! scalar `T: Real`, so the same code runs on `f64`, on first-order dual numbers (gradients) and on
//! second-order dual numbers (Hessians) from `num-dual`.
//!
//! Entry points:
//! - [`surface`]: the first fundamental form, the pseudo-inverse `G⁺` of the tangent, the tangent
//!   projector `a = G G⁺`, the second fundamental form `II`, the shape operator `S` (supplement eq. 8),
//!   the second fundamental tensor `b` (eqs. 10–11), the alternating tensor `c` (eq. 13) and the mean and
//!   Gaussian curvatures `H` and `K` (eq. 12).
//! - [`rotation`]: unit quaternions (scalar first), rotation matrices, `axl`/`skew`, the exponential and
//!   Cayley maps, and the time update `Φ(q, ω, Δt)` of a quaternion by a spatial angular velocity.
//! - [`Real`]: the scalar bound used throughout the workspace.
//!
//! Non-goals: meshes, elements and anything that knows about more than one point (see `cosserat-fem`).
//!
//! Feature flags: none.
//!
//! ```
//! use cosserat_geometry::surface::{SurfaceMetric, second_fundamental_tensor, mean_curvature, gaussian_curvature};
//! use nalgebra::{Matrix3x2, Vector3};
//! // A sphere of radius 2 parametrised around its north pole: x(u, v) = (u, v, sqrt(4 - u² - v²)).
//! let tangent: Matrix3x2<f64> = Matrix3x2::new(1.0, 0.0, 0.0, 1.0, 0.0, 0.0);
//! // Outward normal n = x / 2, so ∂n/∂u = (1/2, 0, 0) and ∂n/∂v = (0, 1/2, 0) at the pole.
//! let normal_gradient = Matrix3x2::new(0.5, 0.0, 0.0, 0.5, 0.0, 0.0);
//! let metric = SurfaceMetric::try_new(&tangent).unwrap();
//! let b = second_fundamental_tensor(&metric, &normal_gradient);
//! assert!((mean_curvature(&b) + 0.5).abs() < 1e-15); // H = -1/R with the outward normal
//! assert!((gaussian_curvature(&b) - 0.25).abs() < 1e-15); // K = 1/R²
//! ```

pub mod error;
pub mod measure;
pub mod number;
pub mod real;
pub mod rotation;
pub mod surface;

pub use error::GeometryError;
pub use number::Num;
pub use real::Real;
