//! Test modules mirroring `src/`, plus shared fixtures (sparse matrices and toy problems).

mod cg;
mod continuation;
mod convergence;
mod error;
mod fixtures;
mod linear;
mod newton;
mod toy;
mod two_domain;
