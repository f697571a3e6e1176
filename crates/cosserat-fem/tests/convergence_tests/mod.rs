//! Convergence tests, one module per study.

mod curvature;
pub mod study;
