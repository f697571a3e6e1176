//! Tests of the simulator facade and the command-line runner: the output contract, failures and
//! interruptions.
mod unit_tests;
