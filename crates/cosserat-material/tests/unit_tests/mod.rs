mod assumed;
mod common;
mod coupled_element;
mod curved_terms;
mod density;
mod kernel;
mod parameters;
mod projected;
