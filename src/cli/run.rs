//! `novanc run` (docs/cli.md): translate-check a part program, run it headless to completion on the
//! pulse core (virtual time, or real time with `--realtime`), optionally recording it, and print
//! a summary.

use super::args::{Args, Opt};
use super::fail;
use crate::console::RunSource;
use crate::pulse_core::{
    ClockMode, Command, EndCause, PulseCore, Reached, RunEnd, RunKind, Status,
};
use crate::record::foxglove::{alarm_line, level};
use crate::record::{Event, Recorder, RecordingInfo};
use crate::settings::MachineSettings;
use std::path::Path;

const HELP: &str = "\
usage: novanc run PROG [--machine centre|centre4|FILE] [--tools TAPE] [--magazine TCODES] [--record OUT.mcap]
                       [--pulses on|off] [--realtime] [--feed-override PCT]
                       [--interpolator dda|error-proportional] [--ep-l PULSES]
                       [--mtconnect ADDR:PORT|PORT] [--mtconnect-wait SECONDS]
       novanc run [PROG] --state DIR [--record ..] [--realtime] [--feed-override PCT] [..]

Runs the part program PROG (source language, or ISO G-code by its name .ngc/.nc/.iso or a
first line of % or O and a number) headless on the pulse core, from machine zero with no tool in the
spindle, in AUTO to its end, and prints a summary: blocks executed, pulses per axis, final
position (mm, machine coordinates), machine time, and whether the recording is complete.

The program is translated while it runs, into the bounded block buffer B1; the run takes no
block before B1 is full or the translation is done, so an error found by then goes to stderr as
PROG:LINE:COL: message with exit code 1, and nothing moves. An error further on (in a program
longer than B1) stops the run before that statement, exit code 1. A block refused by the pulse
core (travel limit, arc geometry) stops the run with a message naming the statement, exit 1.

options:
  --machine M           the machining centre's description: centre (the default), centre4
                        (with a rotary A) or a file (docs/lathe.md); a lathe (citizen) runs its channel programs:
                        see novanc run --machine citizen --help
  --tools TAPE          tool tape; default: the sample tape tooldata/tools.tt (embedded)
  --magazine TCODES     T-code table; default: the sample table tooldata/magazine.tc (embedded)
  --state DIR           use a console's memory (read, never changed): its tool file, T
                        codes and work offsets, and PROG names a program in it (else a
                        file); with no PROG, the program selected there
  --record OUT.mcap     record the run to an MCAP file (docs/recording.md)
  --pulses on|off       off: the recording leaves out /nc/pulses (a long run's file is then
                        small); positions, blocks and states are kept (default on)
  --realtime            pace the machine clock to the wall clock (default: virtual time, as
                        fast as possible, deterministic)
  --feed-override PCT   feed override, 1-150 percent (default 100); rapids are not overridden
  --block-delete        G-code: skip lines that start with / (the BLOCK DELETE switch)
  --interpolator I      dda (default: LINE/PCHK with the KT ramps) or error-proportional
                        (seed 001: rates proportional to the remaining errors, exponential tail)
  --ep-l PULSES         the error-proportional interpolator's L (default 30000: the tail's
                        time constant L / 500 kHz = 60 ms, a servo of Kv 16.7/s)
  -h, --help            this help
";

const OPTS: [Opt; 12] = [
    Opt::flag("--block-delete"),
    Opt::value("--interpolator"),
    Opt::value("--ep-l"),
    Opt::value("--tools"),
    Opt::value("--magazine"),
    Opt::value("--state"),
    Opt::value("--record"),
    Opt::flag("--realtime"),
    Opt::value("--feed-override"),
    Opt::value("--pulses"),
    Opt::flag("--help"),
    Opt::flag("-h"),
];

/// Runs `novanc run`; returns the exit code.
pub fn main(argv: &[String]) -> i32 {
    let (base, argv) = match super::args::take_machine(argv) {
        Err(e) => return super::usage_error(&format!("run: {e}")),
        Ok((super::args::Machine::Lathe(d), rest)) => return super::lathe::run(d, &rest),
        Ok((m, rest)) => (m.settings(), rest),
    };
    let (mtc, argv) = match super::mtconnect::take(&argv) {
        Ok(x) => x,
        Err(e) => return super::usage_error(&format!("run: {e}")),
    };
    let argv = argv.as_slice();
    let args = match Args::parse(argv, &OPTS) {
        Ok(a) => a,
        Err(e) => return super::usage_error(&e),
    };
    if args.flag("--help") || args.flag("-h") {
        print!("{HELP}");
        return 0;
    }
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
    let record_pulses = match args.value("--pulses").map(super::pulses_option) {
        None => true,
        Some(Ok(on)) => on,
        Some(Err(e)) => return super::usage_error(&e),
    };
    let mut settings = base;
    if let Some(i) = args.value("--interpolator") {
        match crate::settings::Interpolator::parse(i) {
            Ok(i) => settings.interpolator = i,
            Err(e) => return super::usage_error(&format!("--interpolator: {e}")),
        }
    }
    if let Some(l) = args.value("--ep-l") {
        match crate::settings::parse_ep_l(l) {
            Ok(l) => settings.ep_l_pulses = l,
            Err(e) => return super::usage_error(&format!("--ep-l: {e}")),
        }
    }
    let (prog, source, magazine, offsets, params) =
        match super::translate::program_and_tools(&args, &mut settings, "run") {
            Ok(x) => x,
            Err(code) => return code,
        };
    super::signals::install();
    let recorder = match args.value("--record") {
        None => None,
        Some(p) => match Recorder::start_with_info(
            Path::new(p),
            &settings,
            &RecordingInfo {
                program_name: prog.clone(),
                program_text: source.clone(),
                magazine: Some(magazine.clone()),
                work_offsets: offsets.0,
                ..Default::default()
            },
        ) {
            Ok(r) => Some(r),
            Err(e) => return fail(&format!("novanc: cannot record to {p}: {e}")),
        },
    };
    let clock = if args.flag("--realtime") {
        ClockMode::RealTime
    } else {
        ClockMode::Virtual
    };
    let core = PulseCore::spawn(
        settings.clone(),
        clock,
        recorder
            .as_ref()
            .map(|r| r.sink().with_pulses(record_pulses)),
    );
    core.set_magazine(magazine.clone());
    let tool_table =
        crate::mtconnect::items::tool_table(&crate::mtconnect::feed::tool_offsets(&magazine));
    // A headless run is a memory operation in AUTO (Fanuc's MEM mode): no data-processing
    // selector is turned, so the data mode recorded is MEMORY (docs/recording.md).
    core.set_panel_modes("AUTO", "MEMORY");
    core.command(Command::Override(feed_override));
    let mut src = RunSource::program(&prog, source.into(), magazine, settings.clone());
    src.offsets = offsets;
    if !params.is_empty() {
        // A console's memory: its G92, system in force and homes too.
        src.interp = Some(crate::gcode::InterpState::with_persistent(
            &params, [0.0; 3], None,
        ));
    }
    src.switches.block_delete = args.flag("--block-delete");
    // o<name> call finds name.ngc beside the program file, as novanc translate does.
    src.subroutines = Some(std::sync::Arc::new(crate::gcode::SubPrograms {
        programs: Vec::new(),
        path: crate::gcode::SubPath(super::translate::subroutine_path(&prog, &[])),
    }));
    let mut feed = match super::mtconnect::Feed::start(&mtc, "novanc run", &core) {
        Ok(f) => f,
        Err(e) => return fail(&format!("novanc run: {e}")),
    };
    let modes = crate::mtconnect::Modes {
        mode: crate::mtconnect::items::controller_mode(crate::panel_model::OpMode::Auto),
        program: prog.clone(),
        partcount: 0,
        wpo: Some(crate::mtconnect::items::wpo_table(&src.offsets.0)),
        program_alarm: None,
        pulse_mm: settings.pulse_mm,
        // No console, no POS: positions in G54 (where a run starts), without the tool length.
        work_origin: src.offsets.0[0],
        tooloffsets: Some(tool_table),
        waiting: false,
        fault: None,
    };
    if let Some(f) = feed.as_mut() {
        f.publish_status(&core.status(), modes.clone());
        if let Err(e) = f.wait(&mtc) {
            return fail(&format!("novanc run: {e}"));
        }
    }
    core.start(RunKind::Auto, Some(src.make_run()));
    // The machine runs a slice of machine time at a time, so a stop signal is seen between
    // slices: an hour of machine time in virtual time (milliseconds of work), 50 ms in real
    // time.
    let slice = if clock == ClockMode::Virtual {
        3_600_000_000_000
    } else {
        50_000_000
    };
    let status = loop {
        let (reached, st) = core.run_until_idle(slice);
        if let Some(f) = feed.as_mut() {
            f.publish_status(&st, modes.clone());
        }
        if !core.is_running() {
            break None;
        }
        match reached {
            Reached::Limit => {
                super::signals::on_signal(|| {
                    core.command(Command::Reset);
                });
                if super::signals::caught().is_some() {
                    break Some(core.status());
                }
            }
            Reached::Idle if st.job.is_some() && st.run == 0 && !st.hold && st.alarm.is_none() => {
                // A program stop (M00): no operator here to press START, so the run goes on.
                core.start(RunKind::Auto, None);
            }
            _ => break Some(st),
        }
    };
    drop(core);
    let Some(status) = status else {
        return fail("novanc: the pulse core stopped unexpectedly");
    };
    let source_error = match &status.last_end {
        Some(RunEnd {
            cause:
                EndCause::Error {
                    error,
                    nothing_moved,
                },
            ..
        }) => Some((error.clone(), *nothing_moved)),
        _ => None,
    };
    // The run's alarm or program error on /foxglove/log, where the run ended.
    if let Some(r) = &recorder {
        let log = |message: String, line: u32| Event::Log {
            t_ns: status.machine_ns,
            level: level::ERROR,
            name: "novanc run".into(),
            message,
            file: prog.clone(),
            line,
        };
        if let Some((e, _)) = &source_error {
            r.sink().send(log(e.to_string(), e.line));
        }
        if let Some(a) = &status.alarm {
            r.sink().send(log(a.clone(), alarm_line(a)));
        }
    }
    if let Some((e, true)) = &source_error {
        // Nothing moved: the program is refused, as a translation error.
        if let Some(r) = recorder {
            let _ = r.finish();
        }
        return fail(&format!("{prog}:{e}"));
    }
    let mut code = 0;
    let rec_line = recorder.map(|r| match r.finish() {
        Ok(sum) if sum.incomplete => format!("recording complete: NO\n{sum}"),
        Ok(sum) => format!("recording complete: yes\n{sum}"),
        Err(e) => {
            code = fail(&format!("novanc: {e}"));
            format!("recording complete: NO\n{e}")
        }
    });
    print!("{}", summary(&status, &settings));
    if let Some(l) = rec_line {
        println!("{l}");
    }
    if let Some((e, _)) = source_error {
        return super::signals::exit_code(fail(&format!(
            "{prog}:{e} (the run stopped at this statement: nothing after it ran)"
        )));
    }
    super::signals::exit_code(match &status.alarm {
        Some(a) => fail(&format!("{prog}:{a}")),
        None => code,
    })
}

/// The summary printed at the end of a run (the interpolator named when it is not the DDA).
pub fn summary(st: &Status, s: &MachineSettings) -> String {
    let interp = match s.interpolator {
        crate::settings::Interpolator::Dda => String::new(),
        i => format!("interpolator: {} (L {} pulses)\n", i.name(), s.ep_l_pulses),
    };
    // A rotary A: its pulses and its position in degrees, after Z (a 3-axis summary is as it was).
    let (a_pulses, a_pos) = if s.axes > 3 {
        (
            format!(" A {}", st.pulses[3]),
            format!(" A {:.3} deg", s.to_mm(st.pos[3])),
        )
    } else {
        (String::new(), String::new())
    };
    interp + &format!(
        "blocks executed: {}\npulses: X {} Y {} Z {}{a_pulses}\nfinal position: X {:.3} Y {:.3} Z {:.3} mm{a_pos}\nmachine time: {:.3} s\n",
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
