//! Unit tests of the public API of `cosserat-contact`.
mod unit_tests;
