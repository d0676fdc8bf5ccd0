//! The `novanc` binary: the command line of docs/cli.md.

fn main() {
    let code = novanc::cli::main_os(std::env::args_os());
    std::process::exit(code);
}
