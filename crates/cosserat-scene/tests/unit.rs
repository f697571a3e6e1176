//! Tests of the public API of `cosserat-scene`, one module per source module under `unit_tests/`.

mod unit_tests;
