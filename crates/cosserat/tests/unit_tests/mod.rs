mod advice;
mod contact;
mod kl_model;
mod memory;
mod run;
mod script_targets;
mod surface_loads;
mod volume_model;
