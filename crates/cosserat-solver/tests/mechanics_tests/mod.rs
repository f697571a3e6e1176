mod common;
mod dynamics;
mod statics;
