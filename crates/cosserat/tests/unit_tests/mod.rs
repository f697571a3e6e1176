mod advice;
mod contact;
mod kl_model;
mod memory;
mod run;
mod volume_model;
