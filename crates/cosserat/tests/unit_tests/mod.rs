mod advice;
mod contact;
mod run;
