//! The command line on a lathe (`--machine citizen` or a lathe description; docs/lathe.md
//! "Headless" and docs/cli.md): `novanc run --machine M DIR|FILES`, `novanc script FILE
//! --machine M`, and the terminal console `novanc --machine M`.

use super::args::{Args, Opt};
use super::fail;
use crate::lathe::console::events::ScriptStep;
use crate::lathe::console::LatheConsole;
use crate::lathe::desc::{load, LatheDesc, MachineDesc};
use std::io::Write;
use std::path::{Path, PathBuf};

/// `--dialect fanuc|linuxcnc` out of `argv` (docs/gcode.md "Fanuc dialect"): the dialect,
/// if given, and the other arguments.
pub fn take_dialect(
    argv: &[String],
) -> Result<(Option<crate::settings::Dialect>, Vec<String>), String> {
    let (taken, rest) = super::args::take_values(argv, &["--dialect"])?;
    let d = match taken.last() {
        Some((_, v)) => Some(crate::settings::Dialect::parse(v).map_err(|e| format!("--{e}"))?),
        None => None,
    };
    Ok((d, rest))
}

/// A lathe's programs are read in LinuxCNC's dialect: `--dialect fanuc` is refused there.
pub fn lathe_dialect(d: Option<crate::settings::Dialect>) -> Result<(), String> {
    match d {
        Some(crate::settings::Dialect::Fanuc) => Err(
            "--dialect fanuc: the lathe's channels read LinuxCNC's dialect only (docs/gcode.md \"Fanuc dialect\")"
                .into(),
        ),
        _ => Ok(()),
    }
}

/// `--machine NAME` out of `argv`: the value and the other arguments. `None` when absent.
pub fn take_machine(argv: &[String]) -> Result<Option<(String, Vec<String>)>, String> {
    let mut rest = Vec::new();
    let mut found = None;
    let mut i = 0;
    while i < argv.len() {
        let a = &argv[i];
        if let Some(v) = a.strip_prefix("--machine=") {
            found = Some(v.to_string());
        } else if a == "--machine" {
            match argv.get(i + 1) {
                Some(v) => found = Some(v.clone()),
                None => {
                    return Err(
                        "--machine needs a value: citizen, centre or a description file".into(),
                    )
                }
            }
            i += 1;
        } else {
            rest.push(a.clone());
        }
        i += 1;
    }
    Ok(found.map(|m| (m, rest)))
}

/// Puts what a machining centre description gives (pulse size, travel, rapid rate,
/// acceleration, tool-change height, workpiece, M6 remap, dialect and its settings) into the console's settings,
/// keeping the rest (interpolator, B1, ...).
pub fn apply_mill(s: &mut crate::settings::MachineSettings, m: &crate::settings::MachineSettings) {
    s.pulse_mm = m.pulse_mm;
    s.travel_min_mm = m.travel_min_mm;
    s.travel_max_mm = m.travel_max_mm;
    s.rapid_mm_min = m.rapid_mm_min;
    s.accel_mm_s2 = m.accel_mm_s2;
    s.remap_m6 = m.remap_m6.clone();
    s.dialect = m.dialect;
    s.fanuc = m.fanuc;
    s.tool_change_z_mm = m.tool_change_z_mm;
    s.workpiece = m.workpiece.clone();
    s.spindle_max_rpm = m.spindle_max_rpm;
    s.spindle_accel_rpm_s = m.spindle_accel_rpm_s;
    s.spindle_encoder_lines = m.spindle_encoder_lines;
}

/// Loads a machine for a subcommand; a lathe or the centre's settings.
pub fn machine(name: &str) -> Result<MachineDesc, String> {
    load(name).map_err(|e| format!("--machine: {e}"))
}

const RUN_HELP: &str = "\
usage: novanc run --machine MACHINE DIR [--parts N] [--record OUT.mcap] [--optional-stop]
                                        [--block-delete] [--mtconnect ADDR:PORT|PORT]
                                        [--mtconnect-wait SECONDS]
       novanc run --machine MACHINE PROG1 PROG2 .. [options]

Runs a lathe's channel programs headless, in lockstep virtual time, to the part target, and
prints a summary: parts, machine time, blocks and pulses per channel. DIR holds one program per
channel (.ngc, .nc or .iso, taken in name order); or name them one per channel. Each channel
starts with its tool post at the top of its travel. A program error goes to stderr as
PROG:LINE:COL: message, exit 1, and nothing moves; an alarm, a fault or a deadlock stops the run
with a message naming the channel, exit 1. M00 (and M01 with --optional-stop) stops a channel;
with no operator here, the run goes on.

options:
  --parts N             the part target (default 5)
  --record OUT.mcap     record the run (docs/recording.md, \"Lathe recordings\")
  --optional-stop       M01 stops (and the run goes on)
  --block-delete        skip lines that start with /
  --mtconnect ADDR:PORT stream the machine to MTConnect agents, each channel a path
                        (SHDR over TCP, docs/mtconnect.md; port 7878 and loopback unless given)
  --mtconnect-wait S    before the cycle starts, wait up to S seconds for an agent
";

/// The channel programs of a headless lathe run: a directory's programs in name order, or the
/// files named.
fn program_files(pos: &[String], channels: usize) -> Result<Vec<PathBuf>, String> {
    let files: Vec<PathBuf> = match pos {
        [d] if Path::new(d).is_dir() => {
            let mut v: Vec<PathBuf> = std::fs::read_dir(d)
                .map_err(|e| format!("{d}: {e}"))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| {
                    p.is_file()
                        && p.extension().and_then(|e| e.to_str()).is_some_and(|e| {
                            matches!(e.to_ascii_lowercase().as_str(), "ngc" | "nc" | "iso")
                        })
                })
                .collect();
            v.sort();
            if v.len() != channels {
                return Err(format!(
                    "{d}: {} programs (.ngc, .nc, .iso) for {channels} channels: one per channel",
                    v.len()
                ));
            }
            v
        }
        [] => {
            return Err("which programs? (a directory with one per channel, or the files)".into())
        }
        files => {
            if files.len() != channels {
                return Err(format!(
                    "{} programs for {channels} channels: one per channel",
                    files.len()
                ));
            }
            files.iter().map(PathBuf::from).collect()
        }
    };
    Ok(files)
}

/// `novanc run --machine M ...` on a lathe; returns the exit code.
pub fn run(desc: LatheDesc, argv: &[String]) -> i32 {
    let (mtc, argv) = match super::mtconnect::take(argv) {
        Ok(x) => x,
        Err(e) => return super::usage_error(&format!("run --machine {}: {e}", desc.name)),
    };
    let argv = argv.as_slice();
    const OPTS: [Opt; 6] = [
        Opt::value("--parts"),
        Opt::value("--record"),
        Opt::flag("--optional-stop"),
        Opt::flag("--block-delete"),
        Opt::flag("--help"),
        Opt::flag("-h"),
    ];
    let args = match Args::parse(argv, &OPTS) {
        Ok(a) => a,
        Err(e) => return super::usage_error(&format!("run --machine {}: {e}", desc.name)),
    };
    if args.flag("--help") || args.flag("-h") {
        print!("{RUN_HELP}");
        return 0;
    }
    let target = match args.value("--parts").map(|v| v.trim().parse::<u32>()) {
        None => 5,
        Some(Ok(n)) if (1..=999_999).contains(&n) => n,
        Some(_) => return super::usage_error("--parts: a whole number of parts from 1 to 999999"),
    };
    let files = match program_files(&args.positional, desc.channels.len()) {
        Ok(f) => f,
        Err(e) => return super::usage_error(&e),
    };
    let mut texts = Vec::new();
    for f in &files {
        match std::fs::read(f) {
            Ok(b) => match String::from_utf8(b) {
                Ok(t) => texts.push((f.display().to_string(), t)),
                Err(_) => return fail(&format!("{}: not a text file", f.display())),
            },
            Err(e) => return fail(&format!("{}: {e}", f.display())),
        }
    }
    let opts = crate::lathe::gcode::ReadOptions {
        block_delete: args.flag("--block-delete"),
        optional_stop: args.flag("--optional-stop"),
    };
    let rec = match args.value("--record") {
        None => None,
        Some(p) => {
            let Some(settings) = crate::settings::MachineSettings::lathe_channel(&desc, 0) else {
                return fail("novanc: the machine has no channel");
            };
            match crate::record::Recorder::start(Path::new(p), &settings) {
                Ok(r) => Some(r),
                Err(e) => return fail(&format!("novanc: {e}")),
            }
        }
    };
    super::signals::install();
    let home: Vec<[i64; 2]> = (0..desc.channels.len())
        .map(|c| crate::lathe::console::home(&desc, c))
        .collect();
    let mut cycle = match crate::lathe::console::Cycle::new(
        &desc,
        &texts,
        &opts,
        target,
        false,
        0,
        &home,
        0,
        100,
        crate::pulse_core::ClockMode::Virtual,
        rec.as_ref().map(crate::record::Recorder::sink),
    ) {
        Ok(c) => c,
        Err(e) => {
            // A reading error: `CHn NAME:LINE:COL: message`; the name is the file.
            let msg = e.split_once(' ').map_or(e.as_str(), |(_, m)| m);
            if let Some(r) = rec {
                let _ = r.finish();
            }
            return fail(msg);
        }
    };
    let names: Vec<String> = texts.iter().map(|(n, _)| n.clone()).collect();
    let mut feed = match super::mtconnect::Feed::start_on(&mtc, "novanc run", true, 0) {
        Ok(f) => f,
        Err(e) => return fail(&format!("novanc run: {e}")),
    };
    if let Some(f) = feed.as_mut() {
        f.publish_cycle(&cycle, &names, desc.pulse_mm);
        if let Err(e) = f.wait(&mtc) {
            return fail(&format!("novanc run: {e}"));
        }
    }
    // A second of machine time at a time, so that a stop signal is seen; with an adapter,
    // 10 ms, each step's state published (docs/mtconnect.md "The lathe").
    let step = if feed.is_some() {
        10_000_000
    } else {
        1_000_000_000
    };
    let mut interrupted = None;
    let outcome = loop {
        let rest = cycle.run_until_rest(step);
        if let Some(f) = feed.as_mut() {
            f.publish_cycle(&cycle, &names, desc.pulse_mm);
        }
        if let Some(why) = super::signals::caught_reason() {
            // Every channel stops at once; one tick records it.
            cycle.estop();
            cycle.advance(desc.tick_ns.max(1));
            if let Some(f) = feed.as_mut() {
                f.publish_cycle(&cycle, &names, desc.pulse_mm);
            }
            interrupted = Some(why);
            break cycle.outcome();
        }
        if !rest {
            if cycle.now_ns() < 360_000_000_000_000 {
                continue;
            }
            break Err("stopped after 100 hours of machine time".into());
        }
        match cycle.outcome() {
            // M00/M01: no operator here to press START, so the run goes on.
            Ok(false) => {
                if let Err(e) = cycle.start() {
                    break Err(e);
                }
                if let Some(f) = feed.as_mut() {
                    f.publish_cycle(&cycle, &names, desc.pulse_mm);
                }
            }
            o => break o,
        }
    };
    let delivered = cycle.totals(desc.unloader).2;
    let mut out = format!(
        "machine: {} ({} channels)\nparts: {}\nmachine time: {:.3} s\n",
        desc.name,
        desc.channels.len(),
        delivered,
        cycle.finished_ns().unwrap_or(cycle.now_ns()) as f64 * 1e-9
    );
    for (i, c) in desc.channels.iter().enumerate() {
        let (blocks, pulses, parts) = cycle.totals(i);
        out += &format!(
            "CH{} {}: blocks {}, pulses X {} Z {}, parts {}\n",
            i + 1,
            c.name,
            blocks,
            pulses[0],
            pulses[1],
            parts
        );
    }
    let mut code = 0;
    // The kernel's thread holds a sink: it ends first, so everything it sent is written.
    drop(cycle);
    if let Some(r) = rec {
        match r.finish() {
            Ok(sum) => out += &format!("{sum}\n"),
            Err(line) => {
                out += &format!("{line}\n");
                code = 1;
            }
        }
    }
    print!("{out}");
    let err = outcome.err();
    if interrupted.is_some() {
        return super::signals::exit_code(1);
    }
    match err {
        Some(e) => fail(&format!("novanc: {e}")),
        None => code,
    }
}

const SCRIPT_HELP: &str = "\
usage: novanc script FILE --machine MACHINE [--state DIR] [--record OUT.mcap] [--rows N] [--cols N]
                           [--mtconnect ADDR:PORT|PORT] [--mtconnect-wait SECONDS]

Runs a lathe panel script (one event per line, # comments) in virtual time:
  op AUTO|MDI|DATA   channel N   type TEXT   start | stop | reset | estop
  fault N REASON     target N    override PCT   optionalstop on|off   blockdelete on|off   key NAME
  wait               until every channel is at rest (finished, stopped, waiting on a stopped
                     channel, faulted, or in E-STOP)
  wait ms T          let T milliseconds of machine time pass
  show               print the display (title, summary lines, plasma) between --- lines
A bad line stops the script before anything runs (exit 1).
--mtconnect streams the machine to MTConnect agents, each channel a path (docs/mtconnect.md):
the state is sent after every event and every 10 ms of machine time. --mtconnect-wait S waits
up to S seconds for an agent before the first event.
";

/// `novanc script FILE --machine M` on a lathe; returns the exit code.
pub fn script(desc: LatheDesc, argv: &[String]) -> i32 {
    if argv.iter().any(|a| a == "-h" || a == "--help") {
        print!("{SCRIPT_HELP}");
        return 0;
    }
    let (mtc, argv) = match super::mtconnect::take(argv) {
        Ok(x) => x,
        Err(e) => return super::usage_error(&format!("script: {e}")),
    };
    let argv = argv.as_slice();
    let has_state = argv
        .iter()
        .any(|a| a == "--state" || a.starts_with("--state="));
    let (cfg, rest) = match super::console_opts::config_from_args(argv) {
        Ok(x) => x,
        Err(e) => return super::usage_error(&format!("script: {e}")),
    };
    if let Err(e) = cfg.check() {
        return super::usage_error(&format!("script: {e}"));
    }
    let file = match rest.as_slice() {
        [f] if !f.starts_with('-') => PathBuf::from(f),
        _ => return super::usage_error("script: which script? (novanc script FILE --machine M)"),
    };
    let text = match std::fs::read_to_string(&file) {
        Ok(t) => t,
        Err(e) => return fail(&format!("novanc script: {}: {e}", file.display())),
    };
    let steps = match crate::lathe::console::events::parse_script(&text, desc.channels.len()) {
        Ok(s) => s,
        Err((line, e)) => return fail(&format!("novanc script: {}:{line}: {e}", file.display())),
    };
    let temp = (!has_state).then(|| {
        let d = std::env::temp_dir().join(format!("novanc-lathe-script-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        d
    });
    let state = temp.clone().unwrap_or(cfg.state_dir.clone());
    super::signals::install();
    let code = run_script(desc, &state, &cfg, steps, &mtc);
    if let Some(d) = temp {
        let _ = std::fs::remove_dir_all(d);
    }
    super::signals::exit_code(code)
}

fn run_script(
    desc: LatheDesc,
    state: &Path,
    cfg: &crate::console::ConsoleConfig,
    steps: Vec<ScriptStep>,
    mtc: &super::mtconnect::MtcOpts,
) -> i32 {
    let (mut c, warnings) =
        match LatheConsole::open(desc, state, cfg.rows, cfg.cols, cfg.record.as_deref()) {
            Ok(x) => x,
            Err(e) => return fail(&format!("novanc script: {e}")),
        };
    for w in warnings {
        eprintln!("novanc script: warning: {w}");
    }
    let mut feed = match super::mtconnect::Feed::start_on(mtc, "novanc script", true, 0) {
        Ok(f) => f,
        Err(e) => return fail(&format!("novanc script: {e}")),
    };
    if let Some(f) = feed.as_mut() {
        f.publish_lathe(&c);
        if let Err(e) = f.wait(mtc) {
            let _ = c.finish(None);
            return fail(&format!("novanc script: {e}"));
        }
    }
    let stdout = std::io::stdout();
    let mut out = stdout.lock();
    // A stop signal ends the script before its next line, and a wait between two steps of
    // 10 ms of machine time.
    let stop = super::signals::pending;
    for s in steps {
        if stop() {
            break;
        }
        match s {
            ScriptStep::Ev(ev) => {
                c.event(ev);
                if let Some(f) = feed.as_mut() {
                    f.publish_lathe(&c);
                }
            }
            ScriptStep::Wait => run_for(&mut c, 3_600_000_000_000_000, true, stop, &mut feed),
            ScriptStep::WaitMs(ms) => {
                run_for(&mut c, ms.saturating_mul(1_000_000), false, stop, &mut feed)
            }
            ScriptStep::Show => {
                let _ = writeln!(out, "--- display\n{}\n---", c.frame_text());
            }
        }
    }
    let _ = out.flush();
    let interrupted = super::signals::caught_reason();
    match c.finish(interrupted.as_deref()) {
        Some(Ok(line)) => {
            eprintln!("novanc script: {line}");
            0
        }
        Some(Err(line)) => {
            eprintln!("novanc script: {line}");
            1
        }
        None => 0,
    }
}

/// Runs the console for `limit_ns` of machine time (only until every channel is at rest with
/// `until_rest`) as `LatheConsole::run_for` does; with an adapter, in steps of 10 ms of
/// machine time, each step's state published (the kernel's watcher is the mill's only:
/// docs/mtconnect.md "The lathe").
fn run_for(
    c: &mut LatheConsole,
    limit_ns: u64,
    until_rest: bool,
    stop: fn() -> bool,
    feed: &mut Option<super::mtconnect::Feed>,
) {
    let Some(f) = feed.as_mut() else {
        c.run_for(limit_ns, until_rest, stop);
        return;
    };
    const STEP: u64 = 10_000_000;
    let mut used = 0;
    while used < limit_ns && !stop() {
        let n = STEP.min(limit_ns - used);
        let ran = c.run_for(n, until_rest, stop);
        used += n;
        f.publish_lathe(c);
        if until_rest && (ran < n || c.at_rest()) {
            break;
        }
    }
}

/// `novanc --machine M` on a lathe: the terminal console; returns the exit code.
pub fn console(desc: LatheDesc, argv: &[String]) -> i32 {
    let (mtc, argv) = match super::mtconnect::take(argv) {
        Ok(x) => x,
        Err(e) => return super::usage_error(&e),
    };
    if mtc.wait.is_some() {
        return super::usage_error("--mtconnect-wait is for novanc run and novanc script");
    }
    let (cfg, rest) = match super::console_opts::config_from_args(&argv) {
        Ok(x) => x,
        Err(e) => return super::usage_error(&e),
    };
    if let Err(e) = cfg.check() {
        return super::usage_error(&e);
    }
    if let Some(r) = rest.first() {
        return super::usage_error(&format!("unexpected argument '{r}' (see --help)"));
    }
    super::signals::install();
    let (mut c, warnings) = match LatheConsole::open_config(desc, &cfg) {
        Ok(x) => x,
        Err(e) => return fail(&format!("novanc: {e}")),
    };
    // At a terminal the kernel keeps the wall clock in its own thread.
    c.set_clock(crate::pulse_core::ClockMode::RealTime);
    let mut feed = match super::mtconnect::Feed::start_on(&mtc, "novanc", false, 0) {
        Ok(f) => f,
        Err(e) => {
            let _ = c.finish(None);
            return fail(&format!("novanc: {e}"));
        }
    };
    if let Some(f) = feed.as_mut() {
        f.publish_lathe(&c);
    }
    let (code, c) = crate::terminal::lathe::run(c, cfg.rows, cfg.cols, &mut feed);
    // A stop signal (said now that the terminal is back): E-STOP, the recording closed
    // `complete: false` with the signal named, exit 128 + N.
    let interrupted = super::signals::caught_reason();
    for w in warnings {
        eprintln!("novanc: warning at start: {w}");
    }
    if let Some(Ok(line) | Err(line)) = c.finish(interrupted.as_deref()) {
        eprintln!("novanc: {line}");
    }
    super::signals::exit_code(code)
}
