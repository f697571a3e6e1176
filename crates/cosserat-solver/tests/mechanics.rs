//! Mechanics of the coupled time stepper and the quasi-static solver against closed forms:
//! rest, free fall, free spin, cantilever, roll-up under an end moment, prescribed rest curvature.
//! CI runs this binary in release.
mod mechanics_tests;
