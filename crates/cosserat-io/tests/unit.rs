//! Tests of the public API of `cosserat-io`, one module per source module under `unit_tests/`.

mod unit_tests;
