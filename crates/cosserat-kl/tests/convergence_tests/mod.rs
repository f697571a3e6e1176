mod cantilever;
mod common;
mod curved_rest;
mod roll_up;
mod sze;
