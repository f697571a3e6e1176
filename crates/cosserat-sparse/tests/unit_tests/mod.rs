//! Test modules mirroring `src/`; the test matrices are `cosserat_sparse::testing`.

mod cg;
mod linear;
mod two_domain;
