//! Errors of the assembly layer.

use thiserror::Error;

/// A failure while evaluating the incremental potential.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum AssemblyError {
    /// A term produced a non-finite energy, gradient or Hessian entry.
    #[error("non-finite value in energy term `{term}` at {location} {index}")]
    NonFinite {
        /// The term's name.
        term: String,
        /// What `index` counts ("element", "node", ...).
        location: &'static str,
        /// Index of the element or node.
        index: usize,
    },
    /// A state outside a term's domain (e.g. two contact primitives touching or crossing). The Newton
    /// line search treats it as an invalid trial and backs off.
    #[error("infeasible state in energy term `{term}`: {reason}")]
    Infeasible {
        /// The term's name.
        term: String,
        /// What is infeasible.
        reason: String,
    },
    /// An unknown vector of the wrong length.
    #[error("unknown vector has {got} entries, expected {expected}")]
    WrongLength {
        /// Expected length.
        expected: usize,
        /// Given length.
        got: usize,
    },
}
