mod common;
mod curved;
mod dynamic;
mod finite;
mod pattern;
mod potential;
mod quadrature_rank;
