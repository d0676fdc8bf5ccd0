//! The `novanc` binary: the command line of docs/cli.md.

fn main() {
    let code = novanc::cli::main(std::env::args().collect());
    std::process::exit(code);
}
