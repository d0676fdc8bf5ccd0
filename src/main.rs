//! The `novanc` binary: the command line of SPEC §8.

fn main() {
    let code = novanc::cli::main(std::env::args().collect());
    std::process::exit(code);
}
