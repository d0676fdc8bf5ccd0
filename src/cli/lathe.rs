//! The command line on a lathe (`--machine citizen` or a lathe description; docs/lathe.md
//! "Headless" and docs/cli.md): `novanc run --machine M DIR|FILES` and `novanc script FILE
//! --machine M`. The console `novanc --machine M` is every machine's (`super::console`).

use super::args::{Args, Opt};
use super::fail;
use crate::lathe::console::{LatheConsole, RunUntil};
use crate::lathe::desc::LatheDesc;
use crate::panel_model::PanelEvent;
use std::path::{Path, PathBuf};

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
        // A batch from none made (Fanuc's #3901 reads 0, #3902 the target).
        parts: Some(crate::lathe::gcode::Parts::new(&[], target)),
    };
    let rec = match args.value("--record") {
        None => None,
        Some(p) => {
            let Some(settings) = crate::settings::MachineSettings::lathe_channel(&desc, 0) else {
                return fail("novanc: the machine has no channel");
            };
            let info = crate::lathe::console::recording_info(&desc, &texts);
            match crate::record::Recorder::start_with_info(Path::new(p), &settings, &info) {
                Ok(r) => Some(r),
                Err(e) => return fail(&format!("novanc: {e}")),
            }
        }
    };
    super::signals::install();
    let home: Vec<[i64; 2]> = (0..desc.channels.len())
        .map(|c| crate::lathe::console::home(&desc, c))
        .collect();
    let names: Vec<String> = texts.iter().map(|(n, _)| n.clone()).collect();
    let spec = crate::lathe::console::CycleSpec {
        left: Vec::new(),
        texts,
        opts,
        target,
        mdi: None,
        pos: home,
        started_ns: 0,
        feed_override: 100,
        clock: crate::pulse_core::ClockMode::Virtual,
        sink: rec.as_ref().map(crate::record::Recorder::sink),
    };
    let mut kept: Vec<_> = (0..desc.channels.len())
        .map(|c| crate::lathe::gcode::Kept::power_on(&desc, c, None))
        .collect();
    let mut cycle = match crate::lathe::console::Cycle::new(&desc, spec, &mut kept) {
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
    let mut feed = match super::mtconnect::Feed::start_on(&mtc, "novanc run", true, 0) {
        Ok(f) => f,
        Err(e) => return fail(&format!("novanc run: {e}")),
    };
    if let Some(f) = feed.as_mut() {
        f.publish_cycle(&cycle, &names, desc.pulse_mm);
        if let Err(e) = f.wait(&mtc) {
            return fail(&format!("novanc run: {e}"));
        }
        // Every change of every channel is published as the kernel makes it, in machine
        // time (docs/mtconnect.md "The lathe").
        cycle.set_watch(Some(f.lathe_watcher()));
    }
    // A second of machine time at a time, so that a stop signal is seen.
    let step = 1_000_000_000;
    let mut interrupted = None;
    let outcome = loop {
        let rest = cycle.run(step, RunUntil::Rest);
        if let Some(f) = feed.as_mut() {
            f.publish_cycle(&cycle, &names, desc.pulse_mm);
        }
        if let Some(why) = super::signals::caught_reason() {
            // Every channel stops at once; one tick records it.
            cycle.estop();
            cycle.run(desc.tick_ns.max(1), RunUntil::Time);
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

/// `novanc script FILE --machine M` on a lathe, once `cli::script::main` has read the
/// arguments and the script: opens the console on `cfg` (its state directory, display size and
/// recording), starts the MTConnect adapter, and plays the events with the one runner.
pub(super) fn run_script(
    desc: LatheDesc,
    cfg: &crate::console::ConsoleConfig,
    steps: Vec<PanelEvent>,
    mtc: &super::mtconnect::MtcOpts,
) -> i32 {
    let (mut c, warnings) = match LatheConsole::open_config(desc, cfg) {
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
        // Every change of every channel inside a wait is published as the kernel makes it,
        // in machine time (docs/mtconnect.md "The lathe").
        c.set_watch(Some(f.lathe_watcher()));
    }
    // A stop signal ends the script before its next line, and a wait between two steps of
    // 10 ms of machine time (`cfg.interrupt`, taken by `open_config`).
    super::script::play(c, steps, feed)
}
