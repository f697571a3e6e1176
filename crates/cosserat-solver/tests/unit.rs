//! Tests of the public API of `cosserat-solver`, one module per source module under `unit_tests/`.

mod unit_tests;
