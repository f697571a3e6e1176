mod common;
mod curved;
mod pattern;
mod potential;
