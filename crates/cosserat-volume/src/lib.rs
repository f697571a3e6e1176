//! A volumetric micropolar (Cosserat) continuum on linear tetrahedra, the comparison model of the
//! shell paper's Lotus "Tet4" row (Löschner, Fernández-Fernández, Jeske, Bender: "Micropolar Elasticity
//! in Physically-Based Animation", 2023). That row was solved with block-Jacobi preconditioned
//! conjugate gradients: `cosserat_solver::LinearSolverKind::Cg` with the reference's forcing sequence
//! (`cosserat_solver::CgForcing::Reference`) in the standard `NewtonSolver`, `TimeStepper` and
//! `solve_quasi_static`.
//!
//! Unknowns per node are the end-of-step velocity and spatial angular velocity, advanced exactly like
//! the shell's (`x = xⁿ + Δt v`, `R = cay(Δt ω) Rⁿ`). Strains are the non-symmetric stretch
//! `E = Rᵀ F − I` and the wryness `Γ_j = axl(Rᵀ ∂_j R)` minus a prescribed rest curvature; the energy
//! density is `W_mp(E) + W_curv(Γ)` in the shell supplement's notation ([`density`]).
//!
//! Entry points:
//! - [`mesh::slab`] / [`TetMesh`]: Tet4 meshes (a box of hexahedra split into six tetrahedra each);
//! - [`build_volume_system`]: a [`VolumeInput`] → [`VolumeSystem`], an
//!   [`IncrementalPotential`](cosserat_assembly::IncrementalPotential) with the [`Tet4Volume`] term in
//!   `parts.extra`, inertia and loads, plus the [`RestCurvature`] handle for scripts;
//! - [`kernel`] (fast exact point Hessian) and [`oracle`] (the same energy for dual-number checks);
//! - [`measure`]: circle fits and Hausdorff distances for shape comparisons.
//!
//! Non-goals: higher-order tetrahedra, contact, scene files of its own (scenes reach the model through
//! `cosserat-scene`'s `model = "micropolar_volume"` and the facade's `volume_model`, which extrudes a
//! flat grid into a slab), and solvers of its own: the built potential is an ordinary
//! `IncrementalPotential` for `cosserat-solver`.
//!
//! Feature flags: none.
//!
//! A slab at rest has zero energy and zero gradient; under gravity, one time step with the Lotus row's
//! solver (Newton with block-Jacobi CG steps) lets it fall freely, `v = g Δt`:
//! ```
//! use cosserat_assembly::SystemOptions;
//! use cosserat_volume::{ContinuumParameters, VolumeInput, build_volume_system, mesh};
//! use nalgebra::Vector3;
//!
//! let grid = mesh::slab([0.2, 0.05, 0.01], [4, 1, 1]).unwrap();
//! assert_eq!(grid.mesh.n_elements(), 24);
//! let input = VolumeInput {
//!     mesh: grid.mesh,
//!     material: ContinuumParameters::new(1e6, 0.3, 1000.0, 0.05),
//!     damping: 0.0,
//!     angular_inertia_density: 0.0,
//! };
//! let options = SystemOptions { gravity: Vector3::zeros(), dynamic: true };
//! let mut system = build_volume_system(&input, &options).unwrap();
//! let n = system.potential.n_dofs();
//! let mut grad = vec![0.0; n];
//! let energy = system.potential.gradient(&vec![0.0; n], &mut grad).unwrap();
//! assert!(energy.abs() < 1e-12 && grad.iter().all(|g| g.abs() < 1e-12));
//! // A Poisson ratio of 0.5 is rejected before any computation.
//! let mut bad = input.clone();
//! bad.material.poisson_ratio = 0.5;
//! assert!(build_volume_system(&bad, &options).is_err());
//!
//! use cosserat_solver::{LinearSolverKind, TimeStepSettings, TimeStepper};
//! system.potential.parts.loads.gravity = Vector3::new(0.0, 0.0, -9.81);
//! let mut settings = TimeStepSettings::fixed(0.01);
//! settings.newton.linear_solver.kind = LinearSolverKind::Cg;
//! let mut stepper = TimeStepper::new(&system.potential, settings).unwrap();
//! let report = stepper.step(&mut system.potential, &mut |_, _, _| {}).unwrap();
//! assert_eq!(report.newton.factorisations.cg, report.newton.iterations);
//! // Newton stops below a force residual of 1e-7 N; the smallest nodal mass is about 1e-3 kg, so the
//! // velocities are exact to 1e-7 N / (m / Δt) ≈ 1e-6 m/s.
//! let state = &system.potential.parts.state;
//! assert!(state.v.iter().all(|v| (v - Vector3::new(0.0, 0.0, -0.0981)).norm() < 1e-5));
//! ```

pub mod builder;
pub mod density;
pub mod element;
pub mod error;
pub mod grid;
pub mod kernel;
pub mod material;
pub use cosserat_geometry::measure;
pub mod mesh;
pub mod oracle;
pub mod term;
pub mod tet4;

pub use builder::{VolumeInput, VolumeSystem, build_volume_system};
pub use cosserat_material::ContinuumParameters;
pub use error::{BuildError, MaterialError, MeshError};
pub use material::{MicropolarModuli, Slab};
pub use mesh::{SlabGrid, TetMesh};
pub use term::{RestCurvature, Tet4Volume, VolumeTerm};
