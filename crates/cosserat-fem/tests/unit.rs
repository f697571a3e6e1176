//! Tests of the public API of `cosserat-fem`, one module per source module.

mod unit_tests;
