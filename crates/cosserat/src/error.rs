//! Errors of the facade.

use thiserror::Error;

/// A failure to set up or write a simulation. Physics failures during a run (Newton not converging)
/// are not errors: they end the run with status `error` in its summary.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum SimulationError {
    /// The scene file is invalid.
    #[error(transparent)]
    Scene(#[from] cosserat_scene::SceneError),
    /// The system could not be built (mesh or material).
    #[error(transparent)]
    Build(#[from] cosserat_assembly::BuildError),
    /// A scene item cannot be set up.
    #[error("{0}")]
    Setup(String),
    /// The contact term could not be built, or the initial state violates a contact thickness.
    #[error("contact: {0}")]
    Contact(#[from] cosserat_contact::ContactError),
    /// Evaluating a term of the potential failed (e.g. an infeasible contact state).
    #[error(transparent)]
    Evaluation(#[from] cosserat_assembly::AssemblyError),
    /// The solver could not be set up.
    #[error(transparent)]
    Solver(#[from] cosserat_solver::NewtonError),
    /// Writing outputs failed.
    #[error(transparent)]
    Output(#[from] cosserat_io::OutputError),
    /// A checkpoint is missing, or does not belong to this scene or run.
    #[error("cannot resume from `{}`: {reason}", path.display())]
    Resume {
        /// The checkpoint file.
        path: std::path::PathBuf,
        /// Why.
        reason: String,
    },
    /// The scene needs more memory than the machine or `--max-memory` allows.
    #[error(transparent)]
    Memory(#[from] crate::memory::TooLarge),
}
