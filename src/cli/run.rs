//! `novanc run` (docs/cli.md): translate-check a part program, run it headless to completion on the
//! pulse core (virtual time, or real time with `--realtime`), optionally recording it, and print
//! a summary.

use super::args::{Args, Opt};
use super::fail;
use crate::pulse_core::{ClockMode, Command, PulseCore, RunKind, Status};
use crate::record::Recorder;
use crate::settings::MachineSettings;
use crate::translator::translate_all;
use std::path::Path;
use std::time::Duration;

const HELP: &str = "\
usage: novanc run PROG [--tools TAPE] [--magazine TCODES] [--record OUT.mcap]
                       [--realtime] [--feed-override PCT]

Runs the part program PROG headless on the pulse core, from machine zero with no tool in the
spindle, in AUTO to its end, and prints a summary: blocks executed, pulses per axis, final
position (mm, machine coordinates), machine time, and whether the recording is complete.

The whole program is translated first: an error there goes to stderr as PROG:LINE:COL: message
with exit code 1, and nothing moves. A block refused by the pulse core (travel limit, arc
geometry) stops the run with a message naming the statement, exit code 1.

options:
  --tools TAPE          tool tape; default: the sample tape tooldata/tools.tt (embedded)
  --magazine TCODES     T-code table; default: the sample table tooldata/magazine.tc (embedded)
  --record OUT.mcap     record the run to an MCAP file (docs/recording.md)
  --realtime            pace the machine clock to the wall clock (default: virtual time, as
                        fast as possible, deterministic)
  --feed-override PCT   feed override, 1-150 percent (default 100); rapids are not overridden
  -h, --help            this help
";

const OPTS: [Opt; 7] = [
    Opt::value("--tools"),
    Opt::value("--magazine"),
    Opt::value("--record"),
    Opt::flag("--realtime"),
    Opt::value("--feed-override"),
    Opt::flag("--help"),
    Opt::flag("-h"),
];

/// Runs `novanc run`; returns the exit code.
pub fn main(argv: &[String]) -> i32 {
    let args = match Args::parse(argv, &OPTS) {
        Ok(a) => a,
        Err(e) => return super::usage_error(&e),
    };
    if args.flag("--help") || args.flag("-h") {
        print!("{HELP}");
        return 0;
    }
    let prog = match args.positional.as_slice() {
        [p] => p.clone(),
        [] => return super::usage_error("run: which program? (see --help)"),
        _ => return super::usage_error("run takes one program (see --help)"),
    };
    let feed_override = match args.value("--feed-override") {
        None => 100,
        Some(v) => match v.trim().parse::<u32>() {
            Ok(p) if (1..=150).contains(&p) => p,
            _ => {
                return super::usage_error(&format!(
                    "--feed-override: '{v}' is not a percentage from 1 to 150"
                ))
            }
        },
    };
    let settings = MachineSettings::default();
    let magazine = match super::translate::load_magazine(
        args.value("--tools"),
        args.value("--magazine"),
        &settings,
    ) {
        Ok(m) => m,
        Err(e) => return fail(&e),
    };
    let source = match super::translate::read(&prog) {
        Ok(s) => s,
        Err(e) => return fail(&e),
    };
    // Nothing moves unless the whole program translates.
    if let Err(e) = translate_all(&source, &magazine, &settings, [0, 0, 0]) {
        return fail(&format!("{prog}:{e}"));
    }
    let recorder = match args.value("--record") {
        None => None,
        Some(p) => match Recorder::start(Path::new(p), &settings) {
            Ok(r) => Some(r),
            Err(e) => return fail(&format!("novanc: cannot record to {p}: {e}")),
        },
    };
    let clock = if args.flag("--realtime") {
        ClockMode::RealTime
    } else {
        ClockMode::Virtual
    };
    let core = PulseCore::spawn(settings.clone(), clock, recorder.as_ref().map(|r| r.sink()));
    core.set_magazine(magazine.clone());
    core.set_panel_modes("AUTO", "SEARCH");
    core.command(Command::Override(feed_override));
    core.load_program(&source, magazine, [0, 0, 0]);
    core.command(Command::Start(RunKind::Auto));
    let status = loop {
        match core.wait_idle(Duration::from_secs(3600)) {
            Some(st) => break Some(st),
            None if core.is_running() => continue,
            None => break None,
        }
    };
    drop(core);
    let Some(status) = status else {
        return fail("novanc: the pulse core stopped unexpectedly");
    };
    let rec_line = recorder.map(|r| match r.finish() {
        Ok(sum) if sum.incomplete => format!("recording complete: NO\n{sum}"),
        Ok(sum) => format!("recording complete: yes\n{sum}"),
        Err(e) => format!("recording complete: NO\nRECORDING INCOMPLETE: {e}"),
    });
    print!("{}", summary(&status, &settings));
    if let Some(l) = rec_line {
        println!("{l}");
    }
    match &status.alarm {
        Some(a) => fail(&format!("{prog}:{a}")),
        None => 0,
    }
}

/// The summary printed at the end of a run.
pub fn summary(st: &Status, s: &MachineSettings) -> String {
    format!(
        "blocks executed: {}\npulses: X {} Y {} Z {}\nfinal position: X {:.3} Y {:.3} Z {:.3} mm\nmachine time: {:.3} s\n",
        st.blocks_done,
        st.pulses[0],
        st.pulses[1],
        st.pulses[2],
        s.to_mm(st.pos[0]),
        s.to_mm(st.pos[1]),
        s.to_mm(st.pos[2]),
        st.machine_ns as f64 * 1e-9
    )
}
