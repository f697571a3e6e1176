mod advice;
mod contact;
mod kl_model;
mod run;
mod volume_model;
