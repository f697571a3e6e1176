mod common;
mod curved;
mod dynamic;
mod pattern;
mod potential;
