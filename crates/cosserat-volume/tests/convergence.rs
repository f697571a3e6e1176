//! Refinement studies of the volumetric slab: curling under a prescribed rest curvature against the
//! closed form (mesh and thickness), and against the Cosserat shell.
mod convergence_tests;
