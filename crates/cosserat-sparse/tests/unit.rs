//! Tests of the public API of `cosserat-sparse`, one module per solver under `unit_tests/`.

mod unit_tests;
