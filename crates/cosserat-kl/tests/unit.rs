//! Tests of the public API of `cosserat-kl`, one module per source module.
mod unit_tests;
