//! The command line (SPEC §8, a stable interface): one module per subcommand, each with a
//! `main(argv) -> exit code` and its own `--help`.

pub mod args;
pub mod edit;
pub mod run;
pub mod script;
pub mod translate;

use std::io::Write;

const USAGE: &str = "\
novanc: CNC operator console

usage:
  novanc [--state DIR] [--rows N] [--cols N]   interactive console (terminal)
  novanc --window                              the console in an egui window (feature \"window\")
  novanc translate PROG [--tools TAPE] [--magazine TCODES]
  novanc run PROG [--tools ..] [--magazine ..] [--record OUT.mcap] [--realtime] [--feed-override PCT]
  novanc edit FILE -c 'CMDLINE' [-c ..] [--write]
  novanc script FILE [--record OUT.mcap]

Each subcommand has --help.
";

/// Runs the command line; returns the process exit code.
pub fn main(argv: Vec<String>) -> i32 {
    let rest = argv.get(1..).unwrap_or(&[]);
    match rest.first().map(|s| s.as_str()) {
        Some("translate") => translate::main(&rest[1..]),
        Some("run") => run::main(&rest[1..]),
        Some("edit") => edit::main(&rest[1..]),
        Some("script") => script::main(&rest[1..]),
        Some("-h") | Some("--help") | Some("help") => {
            print!("{USAGE}");
            0
        }
        _ => crate::console::main(rest),
    }
}

/// Prints a failure (already in its final form, e.g. `PROG:LINE:COL: message`) on stderr and
/// returns exit code 1.
pub fn fail(msg: &str) -> i32 {
    let _ = writeln!(std::io::stderr(), "{msg}");
    1
}

/// Prints an error on stderr as `novanc: message` and returns exit code 2 (usage error).
pub fn usage_error(msg: &str) -> i32 {
    let _ = writeln!(std::io::stderr(), "novanc: {msg}");
    2
}
