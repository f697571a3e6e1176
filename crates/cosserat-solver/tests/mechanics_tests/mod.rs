mod common;
mod continuation;
mod dynamics;
mod statics;
