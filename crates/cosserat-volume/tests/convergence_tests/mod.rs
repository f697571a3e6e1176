mod coil;
mod common;
mod shell;
