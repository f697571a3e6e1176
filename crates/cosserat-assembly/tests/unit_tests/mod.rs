mod common;
mod curved;
mod dynamic;
mod finite;
mod pattern;
mod potential;
mod pressure;
mod quadrature_rank;
