mod common;
mod pattern;
mod potential;
