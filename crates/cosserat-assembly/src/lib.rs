//! The incremental potential of a Cosserat shell system: energy terms, sparsity pattern and
//! deterministic parallel assembly.
//!
//! Entry points:
//! - [`IncrementalPotential`] built from [`PotentialParts`]: shells ([`shell::ShellTerm`]), inertia and
//!   loads ([`inertia`]) from a model's [`NodalMasses`], boundary conditions ([`boundary`]); further
//!   [`PotentialTerm`]s (another model's elastic energy, contact) are inserted by their owners, who keep
//!   a typed [`TermHandle`] to them;
//! - [`build_system`]: the Cosserat shells of a scene as such a potential, with their [`ShellLayout`]s;
//! - [`SparsityPattern`]: the upper-triangular 3×3-block CSC pattern, built once per topology;
//! - [`parallel::ordered_map`]: element kernels in parallel, scattered in element order, so results are
//!   bit-identical for any number of threads.
//! - [`element_assembly`]: the element loop of the elastic terms (this crate's shell, the comparison
//!   models' elements): a term says what one element computes ([`element_assembly::ElementKernel`]) and
//!   [`element_assembly::ElementAssembly`] runs, checks and scatters it.
//!
//! Non-goals: solving (`cosserat-solver`), scenes and file formats (`cosserat-scene`).
//!
//! Feature flags: none.
//!
//! ```
//! use cosserat_assembly::SparsityPattern;
//! // Two elements sharing blocks 1 and 2.
//! let p = SparsityPattern::from_groups(4, [&[0, 1, 2][..], &[1, 2, 3][..]]);
//! assert_eq!(p.n_dofs(), 12);
//! assert!(p.entry(0, 3 * 2).is_some()); // block (0, 2) coupled
//! assert!(p.entry(0, 3 * 3).is_none()); // block (0, 3) not coupled
//! ```

pub mod boundary;
pub mod dofs;
pub mod element_assembly;
pub mod error;
pub mod finite;
pub mod inertia;
pub mod parallel;
pub mod pattern;
pub mod potential;
pub mod pressure;
pub mod scatter;
pub mod shell;
pub mod state;
mod strain_prediction;
pub mod system;
pub mod term;

pub use dofs::DofLayout;
pub use error::AssemblyError;
pub use parallel::Parallelism;
pub use pattern::SparsityPattern;
pub use potential::{IncrementalPotential, NodalMasses, PSEUDO_TIME_STEP, PotentialParts, ShellEnergy, TermHandle};
pub use state::SystemState;
pub use system::{BuildError, ElementPair, ShellInput, ShellLayout, ShellMesh, System, SystemOptions, build_system};
pub use term::PotentialTerm;
