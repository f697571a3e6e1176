//! Unit tests of the public API of `cosserat-volume`, one module per source module.
mod unit_tests;
