mod common;
mod density;
mod kernel;
mod parameters;
mod projected;
