mod assumed;
mod common;
mod curved_terms;
mod density;
mod kernel;
mod parameters;
mod projected;
