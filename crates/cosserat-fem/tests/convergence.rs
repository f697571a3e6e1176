//! Refinement studies of `cosserat-fem`: discrete curvature against closed forms. CI runs this binary
//! in release mode.

mod convergence_tests;
