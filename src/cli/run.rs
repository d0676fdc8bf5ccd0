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
use std::path::{Path, PathBuf};

const HELP: &str = "\
usage: novanc run PROG [--machine centre|centre4|FILE] [--tools TAPE] [--magazine TCODES]
                       [--state DIR] [--interpolator dda|error-proportional] [--ep-l PULSES]
                       [common options]
       novanc run [PROG] --state DIR [common options]
       novanc run --machine citizen|FILE DIR|PROG1 PROG2 .. [--parts N] [common options]

common options: [--record OUT.mcap] [--pulses on|off] [--realtime] [--feed-override PCT]
                [--block-delete] [--optional-stop] [--mtconnect ADDR:PORT|PORT]
                [--mtconnect-wait SECONDS]

Runs part programs headless on the pulse core, in AUTO to their end, and prints a summary.

On the machining centre, PROG is one program (source language, or ISO G-code by its name
.ngc/.nc/.iso or a first line of % or O and a number), run from machine zero with no tool in the
spindle; the summary gives the blocks executed, pulses per axis, final position (mm, machine
coordinates), machine time, and whether the recording is complete. The program is translated
while it runs, into the bounded block buffer B1; the run takes no block before B1 is full or the
translation is done, so an error found by then goes to stderr as PROG:LINE:COL: message with exit
code 1, and nothing moves. An error further on (in a program longer than B1) stops the run before
that statement, exit code 1. A block refused by the pulse core (travel limit, arc geometry) stops
the run with a message naming the statement, exit 1.

On a lathe (--machine citizen or a lathe description), the channel programs run in lockstep to
the part target: DIR holds one program per channel (.ngc, .nc or .iso, taken in name order), or
name them one per channel. Each channel starts with its tool post at the top of its travel. The
summary gives the parts, the machine time, and blocks, pulses and parts per channel, and with
--record whether the recording is complete, as on the centre. A program
error goes to stderr as PROG:LINE:COL: message, exit 1, and nothing moves; an alarm, a fault or a
deadlock stops the run with a message naming the channel, exit 1.

M00 (and M01 with --optional-stop) stops the program; with no operator here, the run goes on.

options on every machine:
  --record OUT.mcap     record the run to an MCAP file (docs/recording.md)
  --pulses on|off       off: the recording leaves out /nc/pulses (a long run's file is then
                        small); positions, blocks and states are kept (default on)
  --realtime            pace the machine clock to the wall clock (default: virtual time, as
                        fast as possible, deterministic)
  --feed-override PCT   feed override, 1-150 percent (default 100); rapids are not overridden
  --block-delete        skip lines that start with / (the BLOCK DELETE switch)
  --optional-stop       M01 stops (the OPTIONAL STOP switch; the run goes on)
  --mtconnect ADDR:PORT stream the machine to MTConnect agents (SHDR over TCP, docs/mtconnect.md;
                        port 7878 and loopback unless given); a lathe's channels are paths
  --mtconnect-wait S    before the run starts, wait up to S seconds for an agent
  --machine M           centre (the default), centre4 (with a rotary A), citizen, or a machine
                        description file (docs/lathe.md)
  --dialect D           fanuc or linuxcnc (docs/gcode.md)
  -h, --help            this help

on the machining centre:
  --tools TAPE          tool tape; default: the sample tape tooldata/tools.tt (embedded)
  --magazine TCODES     T-code table; default: the sample table tooldata/magazine.tc (embedded)
  --state DIR           use a console's memory (read, never changed): its tool file, T
                        codes and work offsets, and PROG names a program in it (else a
                        file); with no PROG, the program selected there
  --interpolator I      dda (default: LINE/PCHK with the KT ramps) or error-proportional
                        (seed 001: rates proportional to the remaining errors, exponential tail)
  --ep-l PULSES         the error-proportional interpolator's L (default 30000: the tail's
                        time constant L / 500 kHz = 60 ms, a servo of Kv 16.7/s)

on a lathe:
  --parts N             the part target (default 5)
  --state DIR           use the lathe console's stores (read, never changed): each channel's
                        tools as revised at OFS, its #500-#999 and its work offsets G54-G59
";

const OPTS: [Opt; 14] = [
    Opt::flag("--block-delete"),
    Opt::flag("--optional-stop"),
    Opt::value("--interpolator"),
    Opt::value("--ep-l"),
    Opt::value("--tools"),
    Opt::value("--magazine"),
    Opt::value("--state"),
    Opt::value("--record"),
    Opt::flag("--realtime"),
    Opt::value("--feed-override"),
    Opt::value("--pulses"),
    Opt::value("--parts"),
    Opt::flag("--help"),
    Opt::flag("-h"),
];

/// The options only the machining centre takes (a lathe's tools and interpolation are in its
/// description, and its `--state` is read below).
const CENTRE_ONLY: [&str; 4] = ["--tools", "--magazine", "--interpolator", "--ep-l"];

/// What `novanc run` takes on every machine.
struct Common {
    feed_override: u32,
    record_pulses: bool,
    clock: ClockMode,
    block_delete: bool,
    optional_stop: bool,
}

impl Common {
    fn read(args: &Args) -> Result<Common, String> {
        let feed_override = match args.value("--feed-override") {
            None => 100,
            Some(v) => match v.trim().parse::<u32>() {
                Ok(p) if (1..=150).contains(&p) => p,
                _ => {
                    return Err(format!(
                        "--feed-override: '{v}' is not a percentage from 1 to 150"
                    ))
                }
            },
        };
        let record_pulses = match args.value("--pulses").map(super::pulses_option) {
            None => true,
            Some(r) => r?,
        };
        Ok(Common {
            feed_override,
            record_pulses,
            clock: if args.flag("--realtime") {
                ClockMode::RealTime
            } else {
                ClockMode::Virtual
            },
            block_delete: args.flag("--block-delete"),
            optional_stop: args.flag("--optional-stop"),
        })
    }

    /// The slice of machine time run between two looks at a stop signal: an hour in virtual
    /// time (milliseconds of work), 50 ms in real time.
    fn slice_ns(&self, virtual_ns: u64) -> u64 {
        if self.clock == ClockMode::Virtual {
            virtual_ns
        } else {
            50_000_000
        }
    }
}

/// Runs `novanc run`; returns the exit code.
pub fn main(argv: &[String]) -> i32 {
    let (machine, argv) = match super::args::take_machine(argv) {
        Err(e) => return super::usage_error(&format!("run: {e}")),
        Ok(x) => x,
    };
    let (mtc, argv) = match super::mtconnect::take(&argv) {
        Ok(x) => x,
        Err(e) => return super::usage_error(&format!("run: {e}")),
    };
    let args = match Args::parse(&argv, &OPTS) {
        Ok(a) => a,
        Err(e) => return super::usage_error(&e),
    };
    if args.flag("--help") || args.flag("-h") {
        print!("{HELP}");
        return 0;
    }
    let common = match Common::read(&args) {
        Ok(c) => c,
        Err(e) => return super::usage_error(&e),
    };
    let base = match machine {
        super::args::Machine::Lathe(d) => {
            if let Some(o) = CENTRE_ONLY.iter().find(|o| args.value(o).is_some()) {
                return super::usage_error(&format!(
                    "run --machine {}: {o} is the machining centre's (a lathe's tools are in its description, revised in its console's --state, docs/lathe.md)",
                    d.name
                ));
            }
            return lathe(d, &args, &common, &mtc);
        }
        m => m.settings(),
    };
    if args.value("--parts").is_some() {
        return super::usage_error(
            "run: --parts is a lathe's part target (the centre runs its program once)",
        );
    }
    let Common {
        feed_override,
        record_pulses,
        clock,
        ..
    } = common;
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
    // The work offsets G54–G59 on every axis, a rotary axis's as the state directory keeps it.
    let systems: [[f64; crate::block::MAX_AXES]; 6] = std::array::from_fn(|cs| {
        let (o, b) = (offsets.0[cs], crate::gcode::state::system_base(cs));
        let kept = |n: usize| params.iter().find(|p| p.0 == n).map_or(0.0, |p| p.1);
        [o[0], o[1], o[2], kept(b + 4), kept(b + 5), kept(b + 6)]
    });
    let recorder = match args.value("--record") {
        None => None,
        Some(p) => match Recorder::start_with_info(
            Path::new(p),
            &settings,
            &RecordingInfo {
                program_name: prog.clone(),
                program_text: source.clone(),
                magazine: Some(magazine.clone()),
                work_offsets: systems,
                ..Default::default()
            },
        ) {
            Ok(r) => Some(r),
            Err(e) => return fail(&format!("novanc: cannot record to {p}: {e}")),
        },
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
    src.switches.block_delete = common.block_delete;
    src.switches.optional_stop = common.optional_stop;
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
        wpo: Some(crate::mtconnect::items::wpo_table(
            &systems,
            &settings.axis_list().collect::<Vec<_>>(),
        )),
        program_alarm: None,
        pulse_mm: settings.pulse_mm,
        // No console, no POS: positions in G54 (where a run starts), without the tool length.
        work_origin: systems[0],
        rotary_mask: settings.rotary_mask(),
        tooloffsets: Some(tool_table),
        waiting: false,
        fault: None,
        message: None,
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
    let slice = common.slice_ns(3_600_000_000_000);
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
                // A stop signal is an E-STOP, on every machine (a lathe's `run` too; before
                // stop 46 the centre was RESET).
                super::signals::on_signal(|| {
                    core.command(Command::EStop);
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
    let rec_line = recorder.map(|r| recording_end(r.finish(), &mut code));
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

/// `novanc run --machine M ...` on a lathe: its channel programs to the part target.
fn lathe(
    mut desc: crate::lathe::desc::LatheDesc,
    args: &Args,
    common: &Common,
    mtc: &super::mtconnect::MtcOpts,
) -> i32 {
    // `--state DIR`: the lathe console's stores, read and never changed: each channel's tools
    // as revised at OFS, its #500–#999 and its work offsets (docs/cli.md "On a lathe").
    let stored = match super::lathe_stores(&mut desc, args.value("--state")) {
        Ok(s) => s,
        Err(e) => return fail(&e),
    };
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
        block_delete: common.block_delete,
        optional_stop: common.optional_stop,
        // A batch from none made (Fanuc's #3901 reads 0, #3902 the target).
        parts: Some(crate::lathe::gcode::Parts::new(&[], target)),
    };
    let kept: Vec<_> = (0..desc.channels.len())
        .map(|c| {
            let kept = stored.get(c).map_or(&[][..], |v| &v[..]);
            crate::lathe::gcode::Kept::from_stores(&desc, c, kept)
        })
        .collect();
    let rec = match args.value("--record") {
        None => None,
        Some(p) => {
            let Some(settings) = crate::settings::MachineSettings::lathe_channel(&desc, 0) else {
                return fail("novanc: the machine has no channel");
            };
            let info = crate::lathe::console::recording_info(&desc, &texts, &kept);
            match Recorder::start_with_info(Path::new(p), &settings, &info) {
                Ok(r) => Some(r),
                Err(e) => return fail(&format!("novanc: cannot record to {p}: {e}")),
            }
        }
    };
    super::signals::install();
    let home: Vec<[i64; 2]> = (0..desc.channels.len())
        .map(|c| crate::lathe::console::home(&desc, c))
        .collect();
    let names: Vec<String> = texts.iter().map(|(n, _)| n.clone()).collect();
    let machine = crate::lathe::console::KernelSpec {
        pos: home,
        clock: common.clock,
        now_ns: 0,
        feed_override: common.feed_override,
        switches: Default::default(),
        op_mode: crate::panel_model::OpMode::Auto,
        look_ns: 0,
        sink: rec
            .as_ref()
            .map(|r| r.sink().with_pulses(common.record_pulses)),
    };
    let spec = crate::lathe::console::CycleSpec {
        texts,
        opts,
        target,
        mdi: None,
        manual: false,
        single_block: false,
        op_mode: crate::panel_model::OpMode::Auto,
        search: None,
    };
    // The kernel, then the programs loaded into it and started, as the console does.
    let made = crate::lathe::console::Cycle::idle(&desc, &kept, machine).and_then(|mut c| {
        let mut kept = kept;
        c.load(&desc, spec, &mut kept)?;
        c.start()?;
        Ok(c)
    });
    let mut cycle = match made {
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
    let mut feed = match super::mtconnect::Feed::start_on(mtc, "novanc run", true, 0) {
        Ok(f) => f,
        Err(e) => return fail(&format!("novanc run: {e}")),
    };
    if let Some(f) = feed.as_mut() {
        f.publish_cycle(&cycle, &names, desc.pulse_mm);
        if let Err(e) = f.wait(mtc) {
            return fail(&format!("novanc run: {e}"));
        }
        // Every change of every channel is published as the kernel makes it, in machine
        // time (docs/mtconnect.md "The lathe").
        cycle.set_watch(Some(f.lathe_watcher()));
    }
    // A second of machine time at a time (50 ms in real time), so that a stop signal is seen.
    let step = common.slice_ns(1_000_000_000);
    let mut interrupted = None;
    let outcome = loop {
        if common.clock == ClockMode::RealTime {
            // The kernel keeps its own time: look at it every slice, without spinning.
            std::thread::sleep(std::time::Duration::from_nanos(step));
        }
        let rest = cycle.run(step, crate::lathe::console::RunUntil::Rest);
        if let Some(f) = feed.as_mut() {
            f.publish_cycle(&cycle, &names, desc.pulse_mm);
        }
        if let Some(why) = super::signals::caught_reason() {
            // Every channel stops at once; one tick records it.
            cycle.estop();
            cycle.run(desc.tick_ns.max(1), crate::lathe::console::RunUntil::Time);
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
    // What stopped the run, on /foxglove/log, as the centre's `run` logs its alarm (before
    // stop 46 a lathe's recording did not say it): for an E-STOP the machine's own words.
    if let (Some(r), Err(e)) = (&rec, &outcome) {
        let estop = cycle.channels().iter().find(|c| c.status.estop);
        let message = estop
            .and_then(|c| c.status.alarm.clone())
            .unwrap_or_else(|| e.clone());
        r.sink().send(Event::Log {
            t_ns: cycle.now_ns(),
            level: level::ERROR,
            name: "novanc run".into(),
            message,
            file: names.first().cloned().unwrap_or_default(),
            line: 0,
        });
    }
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
        out += &recording_end(r.finish(), &mut code);
        out.push('\n');
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

/// The end of a run's recording as `novanc run` prints it on every machine (docs/cli.md):
/// `recording complete: yes` or `NO`, then the recording's summary, or the error that ended it
/// (said on stderr too, `code` then 1). Until stop 50 a lathe's run printed the summary alone.
fn recording_end(r: Result<crate::record::RecordSummary, String>, code: &mut i32) -> String {
    match r {
        Ok(sum) if sum.incomplete => format!("recording complete: NO\n{sum}"),
        Ok(sum) => format!("recording complete: yes\n{sum}"),
        Err(e) => {
            *code = fail(&format!("novanc: {e}"));
            format!("recording complete: NO\n{e}")
        }
    }
}

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

/// The summary printed at the end of a run (the interpolator named when it is not the DDA).
pub fn summary(st: &Status, s: &MachineSettings) -> String {
    let interp = match s.interpolator {
        crate::settings::Interpolator::Dda => String::new(),
        i => format!("interpolator: {} (L {} pulses)\n", i.name(), s.ep_l_pulses),
    };
    // The rotary axes: their pulses and positions in degrees, after Z (a 3-axis summary is as
    // it was).
    let (mut a_pulses, mut a_pos) = (String::new(), String::new());
    for a in s.axis_list().skip(3) {
        let l = crate::settings::AXIS_NAMES[a];
        a_pulses += &format!(" {l} {}", st.pulses[a]);
        a_pos += &format!(" {l} {:.3} deg", s.to_mm(st.pos[a]));
    }
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
