//! The `cosserat` command-line runner.

fn main() {
    std::process::exit(cosserat::cli::main_with_args(std::env::args_os()));
}
