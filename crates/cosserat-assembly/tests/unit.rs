//! Unit tests of the public API of `cosserat-assembly`.
mod unit_tests;
