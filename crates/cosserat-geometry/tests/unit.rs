//! Tests of the public API of `cosserat-geometry`, one module per source module.
//!
//! Reference values come from closed forms: analytic parametrisations of exact surfaces (plane, sphere,
//! cylinder, saddle, torus) for the surface module, and exact rotation identities (axis–angle
//! quaternions, the Cayley angle `2 arctan(|v|/2)`, the exponential map) for the rotation module.

mod unit_tests;
