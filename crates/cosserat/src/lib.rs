//! Cosserat shell simulator: the [`Simulation`] facade and the command-line runner.
//!
//! Three-director Cosserat shells after Löschner et al., "Curved Three-Director Cosserat Shells with
//! Strong Coupling" (CGF 2024): displacements and microrotations solved together in one Newton solve
//! per time step.
//!
//! Entry points:
//! - [`Simulation::new`] from a validated [`SceneSpec`](cosserat_scene::spec::SceneSpec) (read one with
//!   `cosserat_scene`), then [`Simulation::run`] writes `summary.json`, `probes.csv` and VTU frames;
//! - [`cli::run`]: the `cosserat` binary (`cosserat run <scene.toml> [--out DIR] [--set key=value]`,
//!   `cosserat render <out dir>`);
//! - the layers below are re-exported: [`geometry`], [`fem`], [`material`], [`assembly`], [`solver`],
//!   [`scene`], [`contact`];
//! - [`model`]: the mechanical model of a scene behind one trait: the Cosserat shells
//!   ([`cosserat_model`]) or a comparison model ([`kl_model`]: `[material] model = "kirchhoff_love"` on
//!   `cosserat-kl`; [`volume_model`]: `"micropolar_volume"` on `cosserat-volume`), each placed in the
//!   system for scripts and probes ([`placement`]);
//! - [`contact_run`]: the contact of a scene with a `[contact]` section (built only then): its term,
//!   obstacles, statistics and queries;
//!
//! Non-goals: no physics lives here; this crate composes the layers.
//!
//! Feature flags: none.
//!
//! ```no_run
//! use cosserat::{Simulation, StopRequest};
//! let spec = cosserat::scene::load_scene(std::path::Path::new("scenes/twisting_strip.toml"), &[]).unwrap();
//! let mut sim = Simulation::new(spec).unwrap();
//! let summary = sim.run(std::path::Path::new("out/twisting_strip"), &mut |_| {}, &StopRequest::new()).unwrap();
//! println!("{} steps, {:.1} Newton iterations per step", summary.n_steps, summary.avg_newton_iterations);
//! ```

pub mod advice;
pub mod checkpoint;
pub mod cli;
pub mod contact_run;
mod convergence;
pub mod cosserat_model;
pub mod error;
pub mod frames;
pub mod intersections;
pub mod kl_model;
pub mod memory;
pub mod model;
mod outcome;
pub mod placement;
pub mod probes;
pub mod record;
pub mod run_description;
pub mod scripts;
pub mod simulation;
pub mod stop;
pub mod volume_model;

pub use cosserat_assembly as assembly;
pub use cosserat_contact as contact;
pub use cosserat_fem as fem;
pub use cosserat_geometry as geometry;
pub use cosserat_io as io;
pub use cosserat_material as material;
pub use cosserat_scene as scene;
pub use cosserat_solver as solver;
pub use error::SimulationError;
pub use run_description::RunDescription;
pub use simulation::{Simulation, StepInfo};
pub use stop::{StopReason, StopRequest};
