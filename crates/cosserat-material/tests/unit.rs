//! Unit tests of the public API of `cosserat-material`.
mod unit_tests;
