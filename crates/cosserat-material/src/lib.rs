//! Cosserat plate and curved-shell energy densities, strain measures and element kernels.
//!
//! The three-director Cosserat shell of Löschner et al. (CGF 2024) in the formulation of the supplement
//! (eqs. 1–7) and model.md: unknowns are nodal velocities and spatial angular velocities at the end of a
//! time step; strains are the membrane strain `E = Rᵀ F − a` and the curvature tensor `Γ`; the energy is
//! a weighted sum of quadratic forms of the strains.
//!
//! Entry points:
//! - [`MaterialParameters`] → [`Moduli`] (validated), [`ModelOptions`], [`TermSet::select`] (the active
//!   terms of a point, from the model, the material and the rest state);
//! - [`density`]: the energy density written once, generic over the scalar (`f64` or dual numbers);
//! - [`strain_space`]: the rest-frame strain vector and the density's constant Hessian `D` (num-dual);
//! - [`kernel`]: the fast exact energy, gradient and Hessian of a quadrature point w.r.t. its compact
//!   locals; [`element`]: the constant map from locals to element unknowns;
//! - [`projection`], [`projected`]: the stabilised strain projection against locking and its part of
//!   the element kernel; [`assumed`], [`assumed_kernel`]: assumed covariant strains at tying points
//!   (MITC6-style) and theirs; [`coupled`]: the element kernel both share;
//! - [`tension`]: the stabilisation factors raised where a sheet is stretched;
//! - [`oracle`]: the same energy composed directly, for tests (finite differences, dual oracles);
//! - [`volume`]: the optional nonlinear membrane volume term.
//!
//! Non-goals: meshes and quadrature (`cosserat-fem`), global assembly, inertia and boundary conditions
//! (`cosserat-assembly`).
//!
//! Feature flags: none.
//!
//! ```
//! use cosserat_material::{MaterialParameters, ModelOptions, ShellModel, TermSet};
//! let material = MaterialParameters::new(2e-3, 70e9, 0.35, 2700.0, 2e-6);
//! let moduli = material.moduli().unwrap();
//! let terms = TermSet::select(&ModelOptions::new(ShellModel::Plate), &moduli, false).unwrap();
//! assert_eq!(terms.names(), ["membrane", "bending", "curvature"]);
//! // ν = 0.5 is rejected before any computation.
//! assert!(MaterialParameters::new(2e-3, 70e9, 0.5, 2700.0, 2e-6).moduli().is_err());
//! ```

pub mod assumed;
pub mod assumed_kernel;
pub mod coupled;
pub mod density;
pub mod drilling_hourglass;
pub mod element;
pub mod error;
pub mod kernel;
pub mod model;
pub mod oracle;
pub mod parameters;
pub mod projected;
pub mod projection;
pub mod rest;
pub mod strain_space;
pub mod tension;
pub mod volume;

pub use error::{MaterialError, RestStateError};
pub use model::{AxlVariant, CurvedTerms, EnergyTerm, MembraneVolume, ModelOptions, ShellModel, TermSet};
pub use parameters::{ContinuumParameters, MaterialParameters, Moduli, poisson_ratio_problem};
pub use projection::{StabilizationConstants, StrainInterpolation, StrainProjection};
