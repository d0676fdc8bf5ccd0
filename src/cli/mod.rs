//! The command line (docs/cli.md, a stable interface): one module per subcommand, each with a
//! `main(argv) -> exit code` and its own `--help`.

pub mod args;
pub mod console_opts;
pub mod edit;
pub mod lathe;
pub mod mtconnect;
pub mod run;
pub mod script;
pub mod signals;
pub mod tape;
pub mod translate;

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
  novanc run --machine citizen DIR [--parts N] [--record OUT.mcap]
  novanc tape read IMAGE [--block-parity] [--holes]
  novanc tape punch FILE --code iso|eia [--leader N] [--label TEXT] -o IMAGE

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
        Some("-h") | Some("--help") | Some("help") => {
            print!("{USAGE}");
            0
        }
        _ => console(rest),
    }
}

/// The interactive console (no subcommand): the terminal panel, or the window with `--window`.
fn console(argv: &[String]) -> i32 {
    if argv.iter().any(|a| a == "--window") {
        #[cfg(feature = "window")]
        {
            return window(argv);
        }
        #[cfg(not(feature = "window"))]
        {
            return usage_error(
                "this build has no window: run `novanc` for the terminal panel, or build with `cargo run --release --features window -- --window`",
            );
        }
    }
    if argv.iter().any(|a| a == "-h" || a == "--help") {
        print!("{}", crate::terminal::HELP);
        return 0;
    }
    let (dialect, argv) = match lathe::take_dialect(argv) {
        Ok(x) => x,
        Err(e) => return usage_error(&e),
    };
    let (mill, argv) = match lathe::take_machine(&argv) {
        Err(e) => return usage_error(&e),
        Ok(None) => (None, argv.to_vec()),
        Ok(Some((m, rest))) => match lathe::machine(&m) {
            Err(e) => return usage_error(&e),
            Ok(crate::lathe::desc::MachineDesc::Lathe(d)) => {
                if let Err(e) = lathe::lathe_dialect(dialect) {
                    return usage_error(&e);
                }
                return lathe::console(d, &rest);
            }
            Ok(crate::lathe::desc::MachineDesc::Mill(s)) => (Some(s), rest),
        },
    };
    let (mtc, argv) = match mtconnect::take(&argv) {
        Ok(x) => x,
        Err(e) => return usage_error(&e),
    };
    if mtc.wait.is_some() {
        return usage_error("--mtconnect-wait is for novanc run and novanc script");
    }
    let (mut cfg, rest) = match console_opts::config_from_args(&argv) {
        Ok(x) => x,
        Err(e) => return usage_error(&e),
    };
    if let Some(m) = &mill {
        lathe::apply_mill(&mut cfg.settings, m);
    }
    if let Some(d) = dialect {
        cfg.settings.dialect = d;
    }
    if let Some(r) = rest.first() {
        return usage_error(&format!("unexpected argument '{r}' (see --help)"));
    }
    crate::terminal::run_machine(None, cfg, &mtc)
}

/// `novanc --window`: the window's options, then the console's.
#[cfg(feature = "window")]
fn window(argv: &[String]) -> i32 {
    let mut opts = match crate::window::parse_options(argv) {
        Ok(o) => o,
        Err(e) => return usage_error(&e),
    };
    if opts.help {
        print!("{}", crate::window::HELP);
        return 0;
    }
    // `--machine` first: a lathe opens the lathe's window; the centre's axes go to the mill's.
    let (dialect, console_args) = match lathe::take_dialect(&opts.console_args) {
        Ok(x) => x,
        Err(e) => return usage_error(&e),
    };
    let (machine, args) = match lathe::take_machine(&console_args) {
        Err(e) => return usage_error(&e),
        Ok(None) => (None, console_args.clone()),
        Ok(Some((m, rest))) => match lathe::machine(&m) {
            Err(e) => return usage_error(&e),
            Ok(d) => (Some(d), rest),
        },
    };
    let (mtc, args) = match mtconnect::take(&args) {
        Ok(x) => x,
        Err(e) => return usage_error(&e),
    };
    if mtc.wait.is_some() {
        return usage_error("--mtconnect-wait is for novanc run and novanc script");
    }
    opts.mtc = mtc;
    let (mut cfg, rest) = match console_opts::config_from_args(&args) {
        Ok(x) => x,
        Err(e) => return usage_error(&e),
    };
    if let Some(a) = rest.first() {
        return usage_error(&format!(
            "unknown option '{a}' (see novanc --window --help)"
        ));
    }
    match machine {
        Some(crate::lathe::desc::MachineDesc::Lathe(d)) => match lathe::lathe_dialect(dialect) {
            Ok(()) => crate::window::lathe::run(d, cfg, opts),
            Err(e) => usage_error(&e),
        },
        Some(crate::lathe::desc::MachineDesc::Mill(m)) => {
            lathe::apply_mill(&mut cfg.settings, &m);
            if let Some(d) = dialect {
                cfg.settings.dialect = d;
            }
            crate::window::run(cfg, opts)
        }
        None => {
            if let Some(d) = dialect {
                cfg.settings.dialect = d;
            }
            crate::window::run(cfg, opts)
        }
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
