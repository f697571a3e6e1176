//! Refinement studies and validation of the Kirchhoff–Love model against beam theory and the Sze et al.
//! (2004) cantilever: tip load (Euler–Bernoulli), end-moment roll-up, large-deflection end shear, and a
//! curved rest state straightened by an end moment. CI runs this binary in release.
mod convergence_tests;
