//! The command line (docs/cli.md, a stable interface): one module per subcommand, each with a
//! `main(argv) -> exit code` and its own `--help`.

pub mod args;
pub mod console_opts;
pub mod edit;
pub mod mtconnect;
pub mod run;
pub mod script;
pub use crate::signals;
pub mod tape;
pub mod translate;

use crate::console::ConsoleConfig;
use crate::lathe::desc::LatheDesc;
use std::io::Write;

const USAGE: &str = "\
novanc: CNC operator console

usage:
  novanc [--state DIR] [--rows N] [--cols N]   interactive console (terminal)
  novanc --machine citizen [--state DIR]       the Citizen lathe's console (docs/lathe.md)
  novanc --window                              the console in an egui window (feature \"window\")
  novanc translate PROG [--tools TAPE] [--magazine TCODES]
  novanc run PROG [--tools ..] [--magazine ..] [--record OUT.mcap] [--realtime] [--feed-override PCT]
  novanc edit FILE -c 'CMDLINE' [-c ..] [--write]
  novanc script FILE [--record OUT.mcap] [--machine citizen]
  novanc run --machine citizen DIR [--parts N] [--record ..] [--realtime] [--feed-override PCT]
  novanc tape read IMAGE [--block-parity] [--holes]
  novanc tape punch FILE --code iso|eia [--leader N] [--label TEXT] -o IMAGE
  novanc mtconnect-devices [--machine M]      the MTConnect device file of the machine

Each subcommand has --help.
";

/// Runs the command line from the process's arguments, which may not be UTF-8: an argument that
/// is not is refused as a usage error (exit 2) naming it, with its bad bytes shown as `\xHH`.
pub fn main_os(args: impl IntoIterator<Item = std::ffi::OsString>) -> i32 {
    use std::os::unix::ffi::OsStrExt;
    let mut argv = Vec::new();
    for (i, a) in args.into_iter().enumerate() {
        match a.into_string() {
            Ok(s) => argv.push(s),
            Err(os) => {
                return usage_error(&format!(
                    "argument {i} '{}' is not UTF-8 text; novanc takes its arguments, file names included, as UTF-8 (rename the file)",
                    crate::input_text::escape_bytes(os.as_bytes())
                ))
            }
        }
    }
    main(argv)
}

/// Runs the command line; returns the process exit code.
pub fn main(argv: Vec<String>) -> i32 {
    let rest = argv.get(1..).unwrap_or(&[]);
    match rest.first().map(|s| s.as_str()) {
        Some("translate") => translate::main(&rest[1..]),
        Some("run") => run::main(&rest[1..]),
        Some("edit") => edit::main(&rest[1..]),
        Some("script") => script::main(&rest[1..]),
        Some("tape") => tape::main(&rest[1..]),
        Some("mtconnect-devices") => mtconnect::devices_main(&rest[1..]),
        Some("-h") | Some("--help") | Some("help") => {
            print!("{USAGE}");
            0
        }
        _ => console(rest),
    }
}

/// The interactive console (no subcommand) of whatever machine `--machine` describes (the
/// centre's, or a lathe's with its channel selector): the terminal panel, or the window with
/// `--window`.
fn console(argv: &[String]) -> i32 {
    #[cfg(feature = "window")]
    if argv.iter().any(|a| a == "--window") {
        let opts = match crate::window::parse_options(argv) {
            Ok(o) => o,
            Err(e) => return usage_error(&e),
        };
        if opts.help {
            print!("{}", crate::window::HELP);
            return 0;
        }
        return match console_args(&opts.console_args, "novanc --window --help") {
            Err(code) => code,
            Ok((lathe, cfg, mtc)) => {
                crate::window::run(lathe, cfg, crate::window::WindowOptions { mtc, ..opts })
            }
        };
    }
    #[cfg(not(feature = "window"))]
    if argv.iter().any(|a| a == "--window") {
        return usage_error(
            "this build has no window: run `novanc` for the terminal panel, or build with `cargo run --release --features window -- --window`",
        );
    }
    if argv.iter().any(|a| a == "-h" || a == "--help") {
        print!("{}", crate::terminal::HELP);
        return 0;
    }
    match console_args(argv, "--help") {
        Err(code) => code,
        Ok((lathe, cfg, mtc)) => crate::terminal::run_machine(lathe, cfg, &mtc),
    }
}

/// The console's arguments, parsed once for the terminal and the window: the machine (a
/// lathe's description, or `None`: the centre's settings are in the configuration), the
/// console's configuration and the MTConnect adapter's options. `Err`: a usage error, said,
/// as its exit code; `help` is where an unknown argument's message sends the operator.
fn console_args(
    argv: &[String],
    help: &str,
) -> Result<(Option<LatheDesc>, ConsoleConfig, mtconnect::MtcOpts), i32> {
    let (machine, argv) = args::take_machine(argv).map_err(|e| usage_error(&e))?;
    let (mtc, argv) = mtconnect::take(&argv).map_err(|e| usage_error(&e))?;
    if mtc.wait.is_some() {
        return Err(usage_error(
            "--mtconnect-wait is for novanc run and novanc script",
        ));
    }
    let (mut cfg, rest) = console_opts::config_from_args(&argv).map_err(|e| usage_error(&e))?;
    if let Some(a) = rest.first() {
        return Err(usage_error(&format!(
            "unexpected argument '{a}' (see {help})"
        )));
    }
    machine.apply(&mut cfg.settings);
    cfg.check().map_err(|e| usage_error(&e))?;
    match machine {
        args::Machine::Lathe(d) => Ok((Some(d), cfg, mtc)),
        args::Machine::Centre(..) => Ok((None, cfg, mtc)),
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

/// `--pulses on|off` (docs/cli.md): whether a recording keeps `/nc/pulses`.
pub(crate) fn pulses_option(v: &str) -> Result<bool, String> {
    match v.to_ascii_lowercase().as_str() {
        "on" => Ok(true),
        "off" => Ok(false),
        _ => Err(format!("--pulses takes on or off, not '{v}'")),
    }
}

/// `--state DIR` of `novanc run` and `novanc translate` on a lathe (docs/cli.md "On a
/// lathe"): the lathe console's stores read without a lock or a write, each channel's tools as
/// revised at OFS put in `desc`; each channel's kept parameters (#500–#999, the work offsets)
/// returned for its reads (`lathe::gcode::Kept::from_stores`). No `DIR`: nothing.
pub(crate) fn lathe_stores(
    desc: &mut crate::lathe::desc::LatheDesc,
    dir: Option<&str>,
) -> Result<Vec<Vec<(usize, f64)>>, String> {
    let Some(dir) = dir else {
        return Ok(Vec::new());
    };
    let v = crate::store::lathe::LatheView::read(std::path::Path::new(dir), desc)
        .map_err(|e| format!("--state {dir}: {e}"))?;
    for w in &v.warnings {
        eprintln!("novanc: warning: {dir}: {w}");
    }
    for (c, t) in desc.channels.iter_mut().zip(v.tools) {
        if let Some(t) = t {
            c.tools = t;
        }
    }
    Ok(v.params)
}
