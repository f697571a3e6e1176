//! Kirchhoff–Love thin shells with hyperelastic materials (Wen & Barbič, "Kirchhoff-Love Shells with
//! Arbitrary Hyperelastic Materials", ACM TOG 42(6), 2023), as a comparison model for the Cosserat
//! shell of this workspace.
//!
//! Unknowns are vertex velocities of a Tri3 mesh only (no rotations). A 3D hyperelastic density is
//! integrated through the thickness with a Gauss rule; at each thickness point the 3D metric is built
//! from the mid-surface fundamental forms, `g(ξ) = a − 2ξ b + ξ² b a⁻¹ b` (rest and current), and plane
//! stress is enforced in closed form. The second fundamental form uses mid-edge normals, so each face's
//! energy depends on a 6-vertex stencil. Curved rest states are stress-free.
//!
//! Entry points:
//! - [`build_kl_system`]: an `IncrementalPotential` of `cosserat-assembly` (elastic term, lumped inertia,
//!   gravity and nodal forces) that the solvers of `cosserat-solver` run unchanged;
//! - [`KirchhoffLoveTerm`]: the elastic energy as a `PotentialTerm`;
//! - [`energy`]: the stencil energy written once over the scalar ([`energy::stencil_energy`]), its fast
//!   exact Hessian ([`energy::stencil_hessian`]) and the 18-direction dual oracle;
//! - [`material`]: St. Venant–Kirchhoff and neo-Hookean densities with their plane-stress condensation;
//! - [`ForceCouple`]: end moments as follower force couples on vertex pairs.
//!
//! Non-goals: rotational boundary conditions other than clamping two rows of vertices, general
//! (numerically condensed) materials, and contact or scene files of its own: scenes reach the model
//! through `cosserat-scene` (`[material] model = "kirchhoff_love"`) and the facade's `kl_model`, which
//! adds contact as for any Tri3 shell. The model and its measured convergence are described in
//! `docs/kirchhoff-love.md`.
//!
//! Feature flags: none.
//!
//! ```
//! use cosserat_assembly::SystemOptions;
//! use cosserat_fem::mesh::procedural;
//! use cosserat_kl::{HyperelasticModel, KlMaterial, KlShell, build_kl_system};
//! use nalgebra::Vector3;
//!
//! let grid = procedural::rectangle_grid(1.0, 0.2, 10, 2).unwrap();
//! let material = KlMaterial::new(HyperelasticModel::NeoHookean, 1e6, 0.3);
//! let options = SystemOptions { gravity: Vector3::new(0.0, 0.0, -9.81), dynamic: true };
//! let mut system = build_kl_system(&grid.mesh, &KlShell::new(material, 1e-3, 1000.0), &options).unwrap();
//! // The flat rest state is stress-free (up to round-off of E × volume = 200 J).
//! assert!(system.elastic_energy().unwrap().abs() < 1e-12 * 200.0);
//! // Masses: ρ h A in total.
//! let mass: f64 = system.masses.iter().sum();
//! assert!((mass - 1000.0 * 1e-3 * 0.2).abs() < 1e-12);
//! // Energy of the step at zero velocity: only the work of gravity, which vanishes at v = 0.
//! let u = vec![0.0; system.potential.n_dofs()];
//! assert_eq!(system.potential.value(&u).unwrap(), system.elastic_energy().unwrap());
//! ```

pub mod couple;
pub mod energy;
pub mod error;
pub mod fundamental_form;
pub mod material;
mod mid_edge;
pub mod rest;
pub mod stencil;
pub mod system;
pub mod term;
pub mod thickness;

pub use couple::{ForceCouple, MomentHandle};
pub use energy::{StencilDerivatives, stencil_energy, stencil_hessian};
pub use error::KlError;
pub use material::{HyperelasticModel, KlMaterial, MaterialConstants};
pub use rest::StencilRest;
pub use stencil::{Stencil, build_stencils};
pub use system::{KlShell, KlSystem, build_kl_system};
pub use term::KirchhoffLoveTerm;
pub use thickness::{RestVolume, ThicknessRule};
