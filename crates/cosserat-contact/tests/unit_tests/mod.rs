mod barrier;
mod broad_phase;
mod ccd;
mod common;
mod distance;
mod intersection;
mod term;
