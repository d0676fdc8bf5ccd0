//! A lathe channel's interpreter state between reads (docs/lathe-gcode.md "What a channel
//! keeps"): MDI and the next program read from the state the last one left; RESET returns it
//! to power-on; the Fanuc dialect's #100–#199 by `common keep|clear`, #500–#999 kept across a
//! restart of the console; the programs' messages on the display when their block runs.

mod common;

use novanc::lathe::console::{LatheConsole, RunUntil};
use novanc::lathe::desc::LatheDesc;
use novanc::panel_model::PanelEvent;
use novanc::settings::Dialect;
use novanc::store::lathe::{LatheStore, Program};
use std::path::Path;

/// Stores `p` as channel 1's program in the lathe's stores at `state`.
fn save_program(state: &Path, d: &LatheDesc, p: &Program) {
    match LatheStore::open(state, d) {
        Ok(mut o) => o.store.save_program(0, p).unwrap_or_else(|e| panic!("{e}")),
        Err(e) => panic!("{e}"),
    }
}

/// The one-channel test lathe, its channel in `dialect`, RESET keeping #100–#199 if `keep`.
fn desc(dialect: Option<Dialect>, keep: Option<bool>) -> LatheDesc {
    let mut d = novanc::lathe::testkit::citizen_like(1);
    d.channels[0].dialect = dialect;
    d.channels[0].keep_common = keep;
    d
}

fn open(desc: &LatheDesc, state: &Path) -> LatheConsole {
    LatheConsole::open(desc.clone(), state, 20, 160, None)
        .unwrap_or_else(|e| panic!("{e}"))
        .0
}

/// MDI on the selected channel: `lines`, START, and the run to its end. The message START gave.
fn mdi(c: &mut LatheConsole, lines: &[&str]) -> String {
    let m = mdi_start(c, lines);
    c.run_for(600_000_000_000, RunUntil::Rest, || false);
    m
}

/// MDI on the selected channel: `lines`, then START, with no machine time after it. The
/// message START gave.
fn mdi_start(c: &mut LatheConsole, lines: &[&str]) -> String {
    c.handle(PanelEvent::Op(novanc::panel_model::OpMode::Mdi));
    for l in lines {
        c.handle(PanelEvent::Type(l.to_string()));
    }
    c.handle(PanelEvent::Start);
    c.message().to_string()
}

/// The tool post, pulses [X radius, Z].
fn at(c: &LatheConsole) -> [i64; 2] {
    c.tips()[0].0
}

#[test]
fn an_mdi_line_reads_in_the_feed_mode_the_program_left() {
    let state = common::temp_dir("lathe-state-g95");
    let d = desc(None, None);
    let p = Program {
        name: "G95.NGC".into(),
        // No M30: LinuxCNC's M2/M30 would return the channel to G94 (below).
        text: "G18 G7 G21 G90 G95\nM10\nG0 X30 Z5\nM11\n".into(),
        dialect: None,
    };
    save_program(&state, &d, &p);
    let mut c = open(&d, &state);
    c.handle(PanelEvent::Target(1));
    c.handle(PanelEvent::Start);
    assert_eq!(c.message(), "cycle start");
    c.run_for(60_000_000_000, RunUntil::Rest, || false);
    assert_eq!(c.counter().counts, [1]);
    // F0.1 per revolution, as the program's G95 left it (per minute it is refused).
    assert_eq!(mdi(&mut c, &["M3 S1000", "G1 X20 F0.1"]), "MDI CH1 runs");
    assert_eq!(at(&c), [10_000, 5_000]);
    // RESET: the channel is back at power-on, G94.
    c.handle(PanelEvent::Reset);
    let m = mdi(&mut c, &["M3 S1000", "G1 X24 F0.1"]);
    assert!(m.contains("F0.1 is below the slowest feed"), "{m}");
    assert_eq!(at(&c), [10_000, 5_000]);
}

#[test]
fn linuxcnc_m30_returns_the_feed_mode_to_g94_and_fanucs_keeps_it() {
    for (dialect, kept) in [(None, false), (Some(Dialect::Fanuc), true)] {
        let state = common::temp_dir("lathe-state-m30");
        let mut c = open(&desc(dialect, None), &state);
        assert_eq!(mdi(&mut c, &["G95 G0 X30. Z5.", "M30"]), "MDI CH1 runs");
        let m = mdi(&mut c, &["M3 S1000", "G1 X20. F0.1"]);
        assert_eq!(m == "MDI CH1 runs", kept, "{dialect:?}: {m}");
    }
}

#[test]
fn g91_in_one_mdi_run_holds_for_the_next_from_where_the_tool_stands() {
    let state = common::temp_dir("lathe-state-g91");
    let mut c = open(&desc(None, None), &state);
    mdi(&mut c, &["G0 X20 Z10"]);
    assert_eq!(at(&c), [10_000, 10_000]);
    mdi(&mut c, &["G91"]);
    mdi(&mut c, &["G0 X4 Z-2"]);
    // X4 on the diameter is 2 on the radius, from where the tool stands.
    assert_eq!(at(&c), [12_000, 8_000]);
    // The offsets of the tool in place hold for the next run too (its offsets are 0 here:
    // U and W move from the tip).
    mdi(&mut c, &["G90 T0101", "G0 X10 Z4"]);
    mdi(&mut c, &["G0 U2 W-1"]);
    assert_eq!(at(&c), [6_000, 3_000]);
}

#[test]
fn reset_makes_the_common_variables_vacant_unless_the_channel_keeps_them() {
    for (keep, x) in [(None, 0), (Some(false), 0), (Some(true), 5_000)] {
        let state = common::temp_dir("lathe-state-common");
        let mut c = open(&desc(Some(Dialect::Fanuc), keep), &state);
        mdi(&mut c, &["#100 = 5.", "G0 X[#100 * 2.] Z10."]);
        assert_eq!(at(&c), [5_000, 10_000]);
        // Without RESET the next MDI run still reads it.
        mdi(&mut c, &["G0 X[#100 * 4.]"]);
        assert_eq!(at(&c), [10_000, 10_000]);
        c.handle(PanelEvent::Reset);
        // Vacant: #0 times 2 is 0 (Fanuc's null arithmetic).
        mdi(&mut c, &["G0 X[#100 * 2.]"]);
        assert_eq!(at(&c)[0], x, "{keep:?}");
    }
}

#[test]
fn common_is_the_channels_or_the_machines_in_a_lathe_description() {
    let citizen = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("machines/citizen.machine"),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let lathe = |text: &str| match novanc::lathe::desc::parse(text) {
        Ok(novanc::lathe::desc::MachineDesc::Lathe(d)) => Ok(d),
        Ok(_) => Err("not a lathe".to_string()),
        Err(e) => Err(e),
    };
    let machine_wide = citizen.replacen("kind lathe\n", "kind lathe\ncommon keep\n", 1);
    let d = lathe(&machine_wide).unwrap_or_else(|e| panic!("{e}"));
    assert!(d.channels.iter().all(|c| c.keep_common == Some(true)));
    let one = machine_wide.replacen("channel SYSTEM-2\n", "channel SYSTEM-2\ncommon clear\n", 1);
    let d = lathe(&one).unwrap_or_else(|e| panic!("{e}"));
    let keeps: Vec<Option<bool>> = d.channels.iter().map(|c| c.keep_common).collect();
    assert_eq!(keeps, [Some(true), Some(false), Some(true)]);
    let twice = one.replacen(
        "channel SYSTEM-2\ncommon clear\n",
        "channel SYSTEM-2\ncommon clear\ncommon keep\n",
        1,
    );
    let e = lathe(&twice).err().unwrap_or_default();
    assert!(e.ends_with("common is given twice in this channel"), "{e}");
}

#[test]
fn a_message_shows_on_the_display_when_its_block_runs() {
    let state = common::temp_dir("lathe-state-msg");
    let rec = state.join("r.mcap");
    let mut c = LatheConsole::open(desc(None, None), &state, 20, 160, Some(&rec))
        .unwrap_or_else(|e| panic!("{e}"))
        .0;
    c.handle(PanelEvent::Op(novanc::panel_model::OpMode::Mdi));
    for l in [
        "G0 X20 Z10",
        "(msg, at the corner)",
        "G4 P2",
        "#1 = 3",
        "(print,count=#1)",
    ] {
        c.handle(PanelEvent::Type(l.to_string()));
    }
    c.handle(PanelEvent::Start);
    assert_eq!(c.message(), "MDI CH1 runs");
    // The rapid runs: the message waits for the dwell, the block after it.
    c.tick(1_000_000);
    // (The listing shows the MDI run's lines, the comment among them, since stop 40.)
    assert!(!c.frame_text().contains("CH1 MSG: at the corner"));
    c.run_for(1_500_000_000, RunUntil::Time, || false);
    // A MSG stays on the message line until acknowledged (stop 45, the centre's rule).
    assert_eq!(c.unacknowledged(), ["CH1 MSG: at the corner"]);
    assert!(c.frame_text().contains("CH1 MSG: at the corner"));
    // After the last block: shown when the program ends.
    c.run_for(600_000_000_000, RunUntil::Rest, || false);
    assert_eq!(c.message(), "CH1 PRINT: count=3.000000");
    // Recorded as the centre records them: each in the log, and the frame that shows it.
    assert!(matches!(c.finish(), Ok(Some(_))));
    let bytes = std::fs::read(&rec).unwrap_or_else(|e| panic!("{e}"));
    let mut logs = Vec::new();
    let mut frames = 0;
    for m in mcap::MessageStream::new(&bytes).unwrap_or_else(|e| panic!("{e}")) {
        let m = m.unwrap_or_else(|e| panic!("{e}"));
        let json = String::from_utf8_lossy(&m.data).into_owned();
        match m.channel.topic.as_str() {
            // The program's messages (the console's own are logged too, as the centre's are).
            "/foxglove/log" if json.contains("CH1 MSG") || json.contains("CH1 PRINT") => {
                logs.push(json)
            }
            "/panel/display" if json.contains("CH1 MSG: at the corner") => frames += 1,
            _ => {}
        }
    }
    assert_eq!(logs.len(), 2, "{logs:?}");
    assert!(
        logs[0].contains("\"message\":\"CH1 MSG: at the corner\""),
        "{}",
        logs[0]
    );
    assert!(logs[1].contains("CH1 PRINT: count=3.000000"), "{}", logs[1]);
    assert!(frames >= 1);
}

#[test]
fn fanucs_500_set_by_a_program_is_read_back_after_the_console_restarts() {
    let state = common::temp_dir("lathe-state-500");
    let d = desc(Some(Dialect::Fanuc), None);
    let p = Program {
        name: "O0500.NGC".into(),
        text: "#500 = #500 + 7.\n#501 = 3.5\nM10\nG0 X30. Z5.\nM11\n".into(),
        dialect: None,
    };
    save_program(&state, &d, &p);
    for (round, x) in [(1, 7_000), (2, 14_000)] {
        let mut c = open(&d, &state);
        c.handle(PanelEvent::Target(2));
        c.handle(PanelEvent::Start);
        assert_eq!(c.message(), "cycle start");
        c.run_for(60_000_000_000, RunUntil::Rest, || false);
        assert_eq!(c.counter().counts, [2]);
        // Two parts, one read: the program's #500 counts once per START.
        mdi(&mut c, &["G0 X[#500 * 2.] Z[#501]"]);
        assert_eq!(at(&c), [x, 3_500], "round {round}");
        // RESET leaves them (they are not common variables).
        c.handle(PanelEvent::Reset);
        mdi(&mut c, &["G0 X[#500 * 2.]"]);
        assert_eq!(at(&c)[0], x, "round {round}");
        let _ = c.finish();
    }
    // Stored in the channel's own stores: another channel of a machine would not see them.
    let o = LatheStore::open(&state, &d).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(o.params[0], [(500, 14.0), (501, 3.5)]);
}

#[test]
fn the_feed_mode_at_power_on_is_the_channels_else_its_dialects() {
    // Fanuc's G95 (a Fanuc 0i-T powers on in G99), LinuxCNC's G94; a `feed` line says last.
    for (dialect, per_rev, runs) in [
        (None, None, false),
        (Some(Dialect::Fanuc), None, true),
        (None, Some(true), true),
        (Some(Dialect::Fanuc), Some(false), false),
    ] {
        let state = common::temp_dir("lathe-state-feed");
        let mut d = desc(dialect, None);
        d.channels[0].per_rev = per_rev;
        let mut c = open(&d, &state);
        let m = mdi(&mut c, &["M3 S1000", "G1 X20. F0.1"]);
        assert_eq!(m == "MDI CH1 runs", runs, "{dialect:?} {per_rev:?}: {m}");
        // RESET returns to the same mode, from the other.
        mdi(&mut c, &[if runs { "G94" } else { "G95" }]);
        c.handle(PanelEvent::Reset);
        let m = mdi(&mut c, &["M3 S1000", "G1 X22. F0.1"]);
        assert_eq!(
            m == "MDI CH1 runs",
            runs,
            "after RESET {dialect:?} {per_rev:?}: {m}"
        );
    }
    let citizen = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("machines/citizen.machine"),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let text = citizen
        .replacen("kind lathe\n", "kind lathe\nfeed per-rev\n", 1)
        .replacen(
            "channel SYSTEM-3\n",
            "channel SYSTEM-3\nfeed per-minute\n",
            1,
        );
    let Ok(novanc::lathe::desc::MachineDesc::Lathe(d)) = novanc::lathe::desc::parse(&text) else {
        panic!("{text}");
    };
    let modes: Vec<Option<bool>> = d.channels.iter().map(|c| c.per_rev).collect();
    assert_eq!(modes, [Some(true), Some(true), Some(false)]);
    let bad = citizen.replacen("kind lathe\n", "kind lathe\nfeed per-second\n", 1);
    let e = novanc::lathe::desc::parse(&bad).err().unwrap_or_default();
    assert!(e.ends_with("feed takes per-rev or per-minute"), "{e}");
}

#[test]
fn a_channels_subroutine_path_finds_o_word_and_m98_subprograms_in_files() {
    let dir = common::temp_dir("lathe-state-subs");
    std::fs::write(
        dir.join("groove.ngc"),
        "o<groove> sub\nG0 X#1 Z#2\no<groove> endsub\n",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    std::fs::write(dir.join("100.ngc"), "O100\nG0 X12 Z3\nM99\n").unwrap_or_else(|e| panic!("{e}"));
    let program = "o<groove> call [20] [5]\nM98 P100\n";
    let citizen = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("machines/citizen.machine"),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let read = |text: &str| {
        let Ok(novanc::lathe::desc::MachineDesc::Lathe(d)) = novanc::lathe::desc::parse(text)
        else {
            panic!("{text}");
        };
        novanc::lathe::gcode::read_program(program, &d, 1, &Default::default())
            .map(|p| {
                p.iter()
                    .flat_map(|s| &s.blocks)
                    .map(|b| [b.end[0], b.end[2]])
                    .collect::<Vec<_>>()
            })
            .map_err(|e| e.to_string())
    };
    // Without a path: not found, at the call's line.
    let e = read(&citizen).err().unwrap_or_default();
    assert!(e.starts_with("1:"), "{e}");
    // The machine's line is every channel's; a channel's own comes first.
    let line = format!("subroutines {}\n", dir.display());
    let machine = citizen.replacen("kind lathe\n", &format!("kind lathe\n{line}"), 1);
    assert_eq!(read(&machine), Ok(vec![[10_000, 5_000], [6_000, 3_000]]));
    let channel = citizen.replacen(
        "channel SYSTEM-2\n",
        &format!("channel SYSTEM-2\n{line}"),
        1,
    );
    assert_eq!(read(&channel), Ok(vec![[10_000, 5_000], [6_000, 3_000]]));
    let other = citizen.replacen(
        "channel SYSTEM-3\n",
        &format!("channel SYSTEM-3\n{line}"),
        1,
    );
    assert!(read(&other).is_err());
}

/// "Nothing they typed is ever lost": the lines typed into a channel's MDI buffer are stored
/// as they are typed, as the centre's MDI buffer is, so a console that closes (or is killed:
/// tests/store_kill.rs) opens with them; START runs them and clears the buffer, stored too.
#[test]
fn the_mdi_lines_typed_survive_a_restart_until_they_run() {
    let state = common::temp_dir("lathe-state-mdi");
    let d = desc(None, None);
    let mut c = open(&d, &state);
    c.handle(PanelEvent::Op(novanc::panel_model::OpMode::Mdi));
    c.handle(PanelEvent::Type("G0 X30 Z20".into()));
    c.handle(PanelEvent::Type("G0 X36".into()));
    assert!(c.message().contains("2 lines"), "{}", c.message());
    drop(c);
    let mut c = open(&d, &state);
    c.handle(PanelEvent::Op(novanc::panel_model::OpMode::Mdi));
    let shown = c.frame_text();
    assert!(
        shown.contains("0001 G0 X30 Z20") && shown.contains("0002 G0 X36"),
        "{shown}"
    );
    c.handle(PanelEvent::Start);
    assert!(c.message().contains("MDI CH1 runs"), "{}", c.message());
    c.run_for(600_000_000_000, RunUntil::Rest, || false);
    assert_eq!(at(&c)[0], 18_000, "X36 as a diameter: the lines ran");
    drop(c);
    let mut c = open(&d, &state);
    let m = mdi_start(&mut c, &[]);
    assert!(m.contains("the buffer is empty"), "{m}");
}

/// What a real lathe keeps between two STARTs: an MDI `M3 S500` turns the spindle until M5,
/// RESET, M30 or E-STOP, and the coolant stays on until M9; the next MDI run goes on with them
/// (its feed per revolution at the spindle's speed, with no ramp from rest). Before, each
/// START began with the spindle stopped and the coolant off, while the screen still showed
/// the last run's spindle turning: the next G95 feed was refused ("the spindle stopped").
#[test]
fn the_spindle_and_coolant_turn_on_from_one_mdi_run_to_the_next_until_reset() {
    let state = common::temp_dir("lathe-state-spindle");
    let d = desc(Some(Dialect::Fanuc), None);
    let mut c = open(&d, &state);
    let ch = |c: &LatheConsole| c.view().channels[0].clone();
    assert_eq!(mdi(&mut c, &["G95 G97 M3 S500", "M8"]), "MDI CH1 runs");
    c.run_for(5_000_000_000, RunUntil::Time, || false);
    assert_eq!((ch(&c).rpm, ch(&c).coolant), (500.0, (false, true)));
    // The next run: the feed per revolution is accepted, the spindle is at 500 at once.
    assert_eq!(
        mdi_start(&mut c, &["G1 X30. F0.2"]),
        "MDI CH1 runs",
        "a G95 feed with the spindle turning"
    );
    c.tick(10_000_000);
    assert_eq!(ch(&c).rpm, 500.0, "no ramp from rest at START");
    assert_eq!(ch(&c).coolant, (false, true));
    c.run_for(600_000_000_000, RunUntil::Rest, || false);
    assert_eq!(at(&c)[0], 15_000, "X30 as a diameter");
    // M5 and M9 stop them, and the next run starts with them stopped.
    assert_eq!(mdi(&mut c, &["M5 M9"]), "MDI CH1 runs");
    c.run_for(5_000_000_000, RunUntil::Time, || false);
    assert_eq!((ch(&c).rpm, ch(&c).coolant), (0.0, (false, false)));
    // RESET stops them too.
    assert_eq!(mdi(&mut c, &["M3 S400 M7"]), "MDI CH1 runs");
    c.run_for(5_000_000_000, RunUntil::Time, || false);
    assert_eq!((ch(&c).rpm, ch(&c).coolant), (400.0, (true, false)));
    c.handle(PanelEvent::Reset);
    c.handle(PanelEvent::Reset);
    let m = mdi_start(&mut c, &["G95 G1 X20. F0.2"]);
    assert!(m.contains("spindle stopped"), "after RESET: {m}");
    // E-STOP stops them.
    c.handle(PanelEvent::Reset);
    assert_eq!(mdi(&mut c, &["M3 S400"]), "MDI CH1 runs");
    c.handle(PanelEvent::EStop);
    c.handle(PanelEvent::Reset);
    let m = mdi_start(&mut c, &["G95 G1 X20. F0.2"]);
    assert!(m.contains("spindle stopped"), "after E-STOP: {m}");
}

/// A lathe's digital outputs (stop 56; the mill's M64/M65): the channel's machine in the kernel
/// keeps them, the display says which are on after the coolant (`OUT 1 3`), and they keep their
/// values across RESET and E-STOP as the centre's do (docs/gcode.md "Inputs and outputs").
#[test]
fn m64_and_m65_set_a_lathe_channel_s_outputs_and_the_display_says_which() {
    let state = common::temp_dir("lathe-state-outputs");
    let d = desc(Some(Dialect::Fanuc), None);
    let mut c = open(&d, &state);
    let ch = |c: &LatheConsole| c.view().channels[0].clone();
    assert_eq!(mdi(&mut c, &["M8 M64 P1", "M64 P3"]), "MDI CH1 runs");
    assert_eq!(ch(&c).outputs, 0b1010);
    assert!(c.frame_text().contains("M08 OUT 1 3"), "{}", c.frame_text());
    assert_eq!(mdi(&mut c, &["M65 P1"]), "MDI CH1 runs");
    assert_eq!(ch(&c).outputs, 0b1000);
    c.handle(PanelEvent::EStop);
    c.handle(PanelEvent::Reset);
    assert_eq!(ch(&c).outputs, 0b1000, "kept across E-STOP and RESET");
    for (line, want) in [
        ("M64", "M64 needs P, the digital output 0 to 63"),
        (
            "M64 P64",
            "M64 P64: the digital output is a whole number 0 to 63",
        ),
        (
            "M65 P1.5",
            "M65 P1.5: the digital output is a whole number 0 to 63",
        ),
    ] {
        let m = mdi_start(&mut c, &[line]);
        assert!(m.contains(want), "{line}: {m}");
        c.handle(PanelEvent::Reset);
    }
    assert_eq!(ch(&c).outputs, 0b1000, "a refused line sets nothing");
}

/// M62/M63 (a digital output with the motion) and M67/M68 (an analog output, with the motion
/// or at once) on a lathe channel (stop 60; the mill's codes and the one kernel's outputs,
/// docs/gcode.md "Inputs and outputs"): each recorded on `/nc/io` with whether it went with
/// the motion, an output with the motion when its block is reached, after the move before it.
#[test]
fn m62_m63_m67_and_m68_set_a_lathe_channel_s_outputs_with_the_motion_or_at_once() {
    let state = common::temp_dir("lathe-state-synced-outputs");
    let rec = state.join("r.mcap");
    let d = desc(None, None);
    let mut c = LatheConsole::open(d, &state, 20, 160, Some(&rec))
        .unwrap_or_else(|e| panic!("{e}"))
        .0;
    let ch = |c: &LatheConsole| c.view().channels[0].clone();
    let lines = ["G0 X30 Z20", "M62 P2", "M67 E3 Q2.5", "G0 X40 M68 E4 Q7"];
    assert_eq!(mdi(&mut c, &lines), "MDI CH1 runs");
    assert_eq!(ch(&c).outputs, 0b100);
    assert_eq!(mdi(&mut c, &["M63 P2"]), "MDI CH1 runs");
    assert_eq!(ch(&c).outputs, 0);
    for (line, want) in [
        ("M62", "M62 needs P, the digital output 0 to 63"),
        ("M67 Q1", "M67 needs E, the analog output 0 to 63"),
        (
            "M68 E64 Q1",
            "M68 E64: the analog output is a whole number 0 to 63",
        ),
    ] {
        let m = mdi_start(&mut c, &[line]);
        assert!(m.contains(want), "{line}: {m}");
        // RESET clears the cycle the refusal left, then the MDI buffer.
        c.handle(PanelEvent::Reset);
        c.handle(PanelEvent::Reset);
    }
    assert!(c.finish().is_ok());
    let io = common::recorded(&rec, "/nc/io");
    let has = |i: usize, s: &str| io.get(i).is_some_and(|(_, t)| t.contains(s));
    assert!(
        has(0, r#""kind":"digital","index":2,"value":1,"synced":true"#)
            && has(1, r#""kind":"analog","index":3,"value":2.5,"synced":true"#)
            && has(2, r#""kind":"analog","index":4,"value":7,"synced":false"#)
            && has(3, r#""kind":"digital","index":2,"value":0,"synced":true"#)
            && io.len() == 4,
        "{io:#?}"
    );
    // The output with the motion waited for the rapid before it (well over a few ticks).
    assert!(io[0].0 > 10_000_000, "{io:#?}");
}

/// A cycle (AUTO) starts with every spindle stopped and the coolant off, whatever an MDI run
/// left turning: its programs close and open the chucks (M10/M11), which must never act on a
/// turning spindle, and command the spindle themselves.
#[test]
fn an_auto_cycle_starts_with_the_spindles_stopped_whatever_mdi_left() {
    let state = common::temp_dir("lathe-state-auto-spindle");
    let (mut c, _) = LatheConsole::open(LatheDesc::citizen(), &state, 20, 160, None).unwrap();
    assert_eq!(mdi(&mut c, &["M3 S500", "M8"]), "MDI CH1 runs");
    c.run_for(5_000_000_000, RunUntil::Time, || false);
    assert_eq!(c.view().channels[0].rpm, 500.0);
    c.handle(PanelEvent::Op(novanc::panel_model::OpMode::Auto));
    c.handle(PanelEvent::Start);
    assert_eq!(c.message(), "cycle start");
    // Run until CH1's chuck has closed on the bar (M10, line 7), a tick at a time.
    let mut closed_at = None;
    for _ in 0..20_000 {
        c.tick(1_000_000);
        let v = &c.view().channels[0];
        if v.chuck {
            closed_at = Some((v.rpm, v.coolant));
            break;
        }
    }
    // In the tick the chuck closed, the program's own M3 may have begun its ramp from rest.
    let (rpm, coolant) = closed_at.expect("the chuck closed");
    assert!(rpm < 10.0, "the chuck closed on a spindle at {rpm} rpm");
    assert_eq!(coolant, (false, false));
}

/// A spindle an MDI run left turning under G96 goes on turning under G96 in the next MDI run,
/// and that run's feed per revolution follows it. Before stop 39 the next run refused `G95 G1`
/// (`the spindle stopped: give M03 or M04`) while the spindle turned at 1,592 rpm; with only
/// that refusal lifted, the run's blocks carried no surface speed and the kernel let the
/// spindle run down under the feed, which never ended.
#[test]
fn a_spindle_left_turning_under_g96_feeds_the_next_mdi_runs_g95_move() {
    let state = common::temp_dir("lathe-state-g96-mdi");
    let mut c = open(&desc(None, None), &state);
    c.handle(PanelEvent::Op(novanc::panel_model::OpMode::Mdi));
    for l in ["G0 X20 Z10", "G96 S100 M3 D3000", "G4 P1"] {
        c.handle(PanelEvent::Type(l.to_string()));
    }
    c.handle(PanelEvent::Start);
    c.handle(PanelEvent::Wait);
    let rpm = |c: &LatheConsole| c.view().channels[0].rpm;
    // 100 m/min at a 10 mm radius.
    assert!((rpm(&c) - 1592.0).abs() < 1.0, "{}", rpm(&c));
    c.handle(PanelEvent::Type("G95 G1 W-1 F0.1".into()));
    c.handle(PanelEvent::Start);
    c.run_for(10_000_000_000, RunUntil::Rest, || false);
    assert_eq!(
        c.tips()[0].0[1],
        9_000,
        "{}\n{}",
        c.message(),
        c.frame_text()
    );
    assert!((rpm(&c) - 1592.0).abs() < 1.0, "{}", rpm(&c));
    assert!(c.wait_error().is_none());
    // After M05 the spindle is stopped for the next run, even while it still coasts down:
    // a feed per revolution is refused, and nothing turns it again.
    c.handle(PanelEvent::Type("M5".into()));
    c.handle(PanelEvent::Start);
    c.tick(10_000_000);
    c.handle(PanelEvent::Type("G95 G1 W-1 F0.1".into()));
    c.handle(PanelEvent::Start);
    c.run_for(10_000_000_000, RunUntil::Rest, || false);
    assert!(c.message().contains("spindle stopped"), "{}", c.message());
    assert_eq!(c.tips()[0].0[1], 9_000);
    assert!(
        rpm(&c) < 1592.0,
        "coasting down, not turned again: {}",
        rpm(&c)
    );
}

/// The screen shows what every channel's machine does, not only the channels a run has a
/// program for: CH2's spindle, left turning by its MDI `M3 S500`, turns on while CH1's MDI
/// runs, and CH2's display says so; E-STOP during that run is every channel's, and says so on
/// each. Before stop 41 a channel outside the MDI run showed `IDLE` and `S 0` whatever its
/// machine did: a spindle turning at 500 rpm was shown stopped.
#[test]
fn a_channel_outside_an_mdi_run_shows_what_its_machine_does() {
    let state = common::temp_dir("lathe-state-other-channel");
    let mut c = LatheConsole::open(LatheDesc::citizen(), &state, 20, 60, None)
        .unwrap_or_else(|e| panic!("{e}"))
        .0;
    c.handle(PanelEvent::Channel(1));
    assert_eq!(mdi(&mut c, &["M3 S500 M8"]), "MDI CH2 runs");
    c.run_for(3_000_000_000, RunUntil::Time, || false);
    let ch2 = |c: &LatheConsole| c.view().channels[1].clone();
    assert_eq!((ch2(&c).rpm, ch2(&c).coolant), (500.0, (false, true)));
    c.handle(PanelEvent::Channel(0));
    assert_eq!(mdi_start(&mut c, &["G4 P2"]), "MDI CH1 runs");
    c.run_for(500_000_000, RunUntil::Time, || false);
    assert_eq!(c.view().channels[0].state, "RUN");
    assert_eq!(ch2(&c).state, "IDLE");
    assert_eq!(
        (ch2(&c).rpm, ch2(&c).coolant),
        (500.0, (false, true)),
        "CH2's spindle turns on while CH1's MDI runs"
    );
    c.handle(PanelEvent::Channel(1));
    assert!(c.frame_text().contains("S   500"), "{}", c.frame_text());
    c.handle(PanelEvent::EStop);
    c.tick(10_000_000);
    let states: Vec<String> = c.view().channels.iter().map(|v| v.state.clone()).collect();
    assert_eq!(states, ["ESTOP", "ESTOP", "ESTOP"]);
}

/// A turret stands where its last program or MDI indexed it, and the screen says so from the
/// start of the next run: before stop 41 each new run's machine began at `T00` while the
/// reader went on applying the kept tool's offsets (the screen showed no tool with T03's
/// offsets in force). RESET cancels the reader's offsets and leaves the turret where it is, as
/// the centre's spindle keeps its tool: the screen goes on showing T03 (until stop 48 it
/// showed `T00`, a turret that had not turned), MODAL `T0300`, and the next run starts there.
#[test]
fn the_tool_indexed_stays_on_the_screen_into_the_next_run() {
    let state = common::temp_dir("lathe-state-tool-kept");
    let d = desc(None, None);
    let mut c = open(&d, &state);
    let tool = |c: &LatheConsole| c.view().channels[0].tool;
    assert_eq!(mdi(&mut c, &["T0303"]), "MDI CH1 runs");
    assert_eq!(tool(&c), 3);
    assert_eq!(mdi_start(&mut c, &["G4 P1"]), "MDI CH1 runs");
    c.tick(10_000_000);
    assert_eq!(tool(&c), 3, "the next run starts with T03 indexed");
    c.run_for(600_000_000_000, RunUntil::Rest, || false);
    assert_eq!(tool(&c), 3);
    c.handle(PanelEvent::Reset);
    assert_eq!(c.message(), "RESET: the cycle is cleared");
    assert_eq!(tool(&c), 3, "RESET does not turn the turret");
    c.press(novanc_panel::Key::Ctrl('g'));
    assert!(c.frame_text().contains("T0300"), "{}", c.frame_text());
    c.press(novanc_panel::Key::Ctrl('g'));
    assert_eq!(mdi_start(&mut c, &["G4 P1"]), "MDI CH1 runs");
    c.tick(10_000_000);
    assert_eq!(tool(&c), 3, "the next run starts where the turret stands");
}

/// The console's one kernel keeps a channel's alarm until RESET, as the centre's machine does
/// (Fanuc: an alarm is cleared by RESET): before stop 42 each MDI START spawned a fresh kernel,
/// and the next MDI run forgot the alarm of the last. START is refused and says why; nothing
/// moves; RESET clears it and the next MDI runs.
#[test]
fn an_alarm_holds_until_reset_across_mdi_runs() {
    let state = common::temp_dir("lathe-state-alarm-holds");
    let mut c = open(&LatheDesc::citizen(), &state);
    // A chuck code in MDI: an MDI run has no work flow, so the kernel's sync table refuses it.
    mdi(&mut c, &["M10"]);
    assert_eq!(c.view().channels[0].state, "ALARM", "{}", c.frame_text());
    let before = at(&c);
    let said = mdi(&mut c, &["G0 X30"]);
    assert_eq!(said, "CH1 START refused: alarm in force, press RESET");
    assert_eq!(at(&c), before, "nothing moves");
    assert_eq!(c.view().channels[0].state, "ALARM");
    c.handle(PanelEvent::Reset);
    assert_eq!(c.view().channels[0].state, "IDLE", "{}", c.message());
    assert_eq!(mdi(&mut c, &["G0 X30"]), "MDI CH1 runs");
    assert_eq!(at(&c)[0], 15_000, "X30 is a diameter: 15 mm radius");
}

/// E-STOP before anything has run is the kernel's, from the console's opening (stop 42): every
/// channel shows it from the kernel's state, and the recording has every channel's machine
/// from time 0 and the kernel's alarm on each (`/lathe/event`). Before stop 42 no kernel ran
/// until the first START or jog: the console latched the E-STOP itself, and the recording had
/// no channel state and no alarm of it.
#[test]
fn an_e_stop_before_any_run_is_the_kernels_and_is_recorded() {
    let state = common::temp_dir("lathe-state-estop-first");
    let mcap = state.join("r.mcap");
    let mut c = LatheConsole::open(LatheDesc::citizen(), &state, 20, 60, Some(&mcap))
        .unwrap_or_else(|e| panic!("{e}"))
        .0;
    c.handle(PanelEvent::EStop);
    c.handle(PanelEvent::WaitMs(100));
    let states: Vec<String> = c.view().channels.iter().map(|v| v.state.clone()).collect();
    assert_eq!(states, ["ESTOP", "ESTOP", "ESTOP"]);
    assert!(c.cycle().channels().iter().all(|s| s.status.estop));
    c.handle(PanelEvent::Reset);
    assert!(c.cycle().channels().iter().all(|s| !s.status.estop));
    c.finish().expect("finished").expect("a recording");
    let bytes = std::fs::read(&mcap).unwrap();
    let msgs: Vec<(String, u64, String)> = mcap::MessageStream::new(&bytes)
        .unwrap()
        .filter_map(Result::ok)
        .map(|m| {
            let text = String::from_utf8_lossy(&m.data).into_owned();
            (m.channel.topic.clone(), m.log_time, text)
        })
        .collect();
    for ch in 1..=3 {
        let of = format!("{{\"channel\":{ch},");
        assert!(
            msgs.iter()
                .any(|(t, at, m)| t == "/nc/state" && *at == 0 && m.starts_with(&of)),
            "CH{ch}'s machine is recorded from time 0"
        );
        assert!(
            msgs.iter().any(|(t, at, m)| t == "/lathe/event"
                && *at == 0
                && m.starts_with(&of)
                && m.contains("\"event\":\"alarm\"")
                && m.contains("EMERGENCY STOP")),
            "CH{ch}'s E-STOP alarm: {:?}",
            msgs.iter()
                .filter(|m| m.0 == "/lathe/event")
                .collect::<Vec<_>>()
        );
    }
}

/// The counters every console keeps (stop 45): the parts delivered in every batch, the last
/// cycle's time and the run time are in the lathe's state directory, and a restart shows them,
/// as the centre's POS page does; before, the lathe forgot its cycle time at a restart and kept
/// no run time. A run of MDI counts in the run time, not in the parts.
#[test]
fn the_cycle_time_and_the_run_hours_survive_a_restart() {
    let dir = common::temp_dir("lathe-counters");
    let d = LatheDesc::citizen();
    let mut c = open(&d, &dir);
    assert_eq!(c.cycle_time_ns(), None);
    c.handle(PanelEvent::Target(2));
    c.handle(PanelEvent::Start);
    c.run_for(600_000_000_000, RunUntil::Rest, || false);
    let k = c.counters();
    assert_eq!(k.parts, 2);
    let cycle = c.cycle_time_ns().expect("a cycle time");
    assert_eq!(k.last_cycle_ns, cycle);
    // Every part of the batch ran inside the run time, and the run time ends with the batch.
    assert!(k.run_ns >= 2 * cycle && k.run_ns <= c.machine_ns(), "{k:?}");
    c.run_for(5_000_000_000, RunUntil::Time, || false);
    assert_eq!(c.counters().run_ns, k.run_ns, "no run, no run time");
    assert!(c.finish().is_ok());

    let mut c = open(&d, &dir);
    assert_eq!(c.counters(), k);
    assert_eq!(c.cycle_time_ns(), Some(cycle));
    assert!(c.frame_text().contains("CYCLE"), "{}", c.frame_text());
    c.press(novanc_panel::Key::Ctrl('p'));
    let pos = c.frame_text();
    assert!(
        pos.contains(&format!("TOTAL 2 CYCLE {:.3} s", cycle as f64 * 1e-9)),
        "{pos}"
    );
    // An MDI run: its time is run time; it delivers no part.
    mdi(&mut c, &["G4 P2"]);
    let after = c.counters();
    assert_eq!(after.parts, 2);
    assert!(after.run_ns >= k.run_ns + 2_000_000_000, "{after:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A program's `(MSG, ...)` lives on the message line until acknowledged, on the lathe as on
/// the centre (stop 45): a key pressed for something else does not clear it unread; Esc
/// acknowledges it, and so does RESET. Before, it lived until the next key.
#[test]
fn a_program_message_lives_until_acknowledged() {
    let dir = common::temp_dir("lathe-msg-ack");
    let d = LatheDesc::citizen();
    let mut c = open(&d, &dir);
    mdi(&mut c, &["(MSG, check the chuck jaws)", "G4 P0.1"]);
    let line = |c: &LatheConsole| c.view().display.join("\n");
    let want = "CH1 MSG: check the chuck jaws (Esc acknowledges)";
    assert!(line(&c).contains(want), "{}", line(&c));
    assert_eq!(c.unacknowledged().len(), 1);
    // Another key: the message stays.
    c.press(novanc_panel::Key::Alt('w'));
    assert!(
        line(&c).contains("CH1 MSG: check the chuck jaws"),
        "{}",
        line(&c)
    );
    c.press(novanc_panel::Key::Esc);
    assert!(c.unacknowledged().is_empty());
    assert!(!line(&c).contains("check the chuck jaws"), "{}", line(&c));
    c.press(novanc_panel::Key::Esc);
    assert_eq!(c.message(), "Esc: no message to acknowledge");
    // RESET acknowledges too: the selected channel's messages, not another channel's.
    mdi(&mut c, &["(MSG, second)", "G4 P0.1"]);
    c.handle(PanelEvent::Channel(1));
    mdi(&mut c, &["(MSG, third)", "G4 P0.1"]);
    assert_eq!(c.unacknowledged(), ["CH1 MSG: second", "CH2 MSG: third"]);
    assert!(
        line(&c).contains("CH2 MSG: third (and 1 before it; Esc acknowledges)"),
        "{}",
        line(&c)
    );
    c.handle(PanelEvent::Reset);
    assert_eq!(c.unacknowledged(), ["CH1 MSG: second"]);
    c.handle(PanelEvent::Channel(0));
    c.handle(PanelEvent::Reset);
    assert!(c.unacknowledged().is_empty());
    // A PRINT is a diagnostic: it lives until the next key, as on the centre.
    mdi(&mut c, &["(PRINT, a diagnostic)", "G4 P0.1"]);
    assert!(c.unacknowledged().is_empty());
    let _ = std::fs::remove_dir_all(&dir);
}

/// A stop signal E-STOPs the lathe as it does the centre, whether a cycle runs or not: a
/// spindle an MDI run left turning stops, and the recording ends with every channel's spindle
/// at 0 and `EMERGENCY STOP` in its log. Until stop 48 only a cycle still running was stopped,
/// and the recording ended with CH1's spindle at 500 rpm and no E-STOP.
#[test]
fn a_stop_signal_e_stops_the_lathe_with_no_cycle_running() {
    let state = common::temp_dir("lathe-state-signal-idle");
    let mcap = state.join("r.mcap");
    let mut c = LatheConsole::open(LatheDesc::citizen(), &state, 20, 60, Some(&mcap))
        .unwrap_or_else(|e| panic!("{e}"))
        .0;
    assert_eq!(mdi(&mut c, &["M3 S500"]), "MDI CH1 runs");
    c.handle(PanelEvent::WaitMs(1000));
    assert!(c.frame_text().contains("S   500"), "{}", c.frame_text());
    c.close(Some("interrupted by SIGTERM"))
        .expect("closed")
        .expect("a recording");
    let bytes = std::fs::read(&mcap).unwrap();
    let mut last = std::collections::BTreeMap::new();
    let mut logs = Vec::new();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        let text = String::from_utf8_lossy(&m.data).into_owned();
        match m.channel.topic.as_str() {
            "/nc/state" => {
                let ch = text.split(',').next().unwrap_or_default().to_string();
                last.insert(ch, text);
            }
            "/foxglove/log" => logs.push(text),
            _ => {}
        }
    }
    assert_eq!(last.len(), 3, "{last:?}");
    for s in last.values() {
        assert!(s.contains("\"spindle\":0,"), "{s}");
    }
    assert!(
        logs.iter().any(|l| l.contains("EMERGENCY STOP")),
        "{logs:?}"
    );
}

/// A program zero moved by G92 in MDI holds for the MDI runs after it, until RESET or G92.1,
/// but a cycle's programs start with the zero at the work's: a shift typed at the panel does
/// not move the next cycle unasked (stop 50).
#[test]
fn a_g92_zero_holds_for_mdi_but_a_cycle_starts_at_the_works_zero() {
    let state = common::temp_dir("lathe-state-g92");
    let d = desc(None, None);
    let p = Program {
        name: "ZERO.NGC".into(),
        text: "G18 G7 G21 G90\nM10\nG0 X30 Z5\nM11\n".into(),
        dialect: None,
    };
    save_program(&state, &d, &p);
    let mut c = open(&d, &state);
    mdi(&mut c, &["G0 X20 Z10"]);
    assert_eq!(mdi(&mut c, &["G92 Z0"]), "MDI CH1 runs");
    mdi(&mut c, &["G0 Z-5"]);
    assert_eq!(
        at(&c),
        [10_000, 5_000],
        "the next MDI run reads from the moved zero"
    );
    c.handle(PanelEvent::Op(novanc::panel_model::OpMode::Auto));
    c.handle(PanelEvent::Target(1));
    c.handle(PanelEvent::Start);
    assert_eq!(c.message(), "cycle start");
    c.run_for(60_000_000_000, RunUntil::Rest, || false);
    assert_eq!(c.counter().counts, [1]);
    assert_eq!(at(&c), [15_000, 5_000], "the cycle's Z5 is the work's");
}

/// The programmed path the window draws (`LatheConsole::programmed`, stop 51) is what START
/// would run: each channel's stored program; in MDI the selected channel's MDI lines, read as
/// an MDI run reads them; the other channels keep their programs.
#[test]
fn the_programmed_path_is_what_start_would_run() {
    use novanc::block::Motion;
    use novanc::panel_model::OpMode;
    let d = common::temp_dir("lathe-programmed");
    let mut c = common::open_citizen(&d);
    let moves = |c: &LatheConsole, ch: usize| -> Vec<[i64; 3]> {
        let st = c.programmed(ch).expect("a channel").expect("it reads");
        st.iter()
            .flat_map(|s| &s.blocks)
            .filter(|b| matches!(b.motion, Motion::Rapid | Motion::Linear))
            .map(|b| [b.end[0], b.end[1], b.end[2]])
            .collect()
    };
    let auto: Vec<_> = (0..3).map(|ch| moves(&c, ch)).collect();
    assert!(auto.iter().all(|m| m.len() > 5), "{auto:?}");
    c.handle(PanelEvent::Op(OpMode::Mdi));
    c.handle(PanelEvent::Type("G8 G0 X30 Z20".into()));
    c.handle(PanelEvent::Type("G1 Z-5 F100".into()));
    // X30 Z20 then Z-5, radius mode: pulses [X radius, 0, Z].
    assert_eq!(moves(&c, 0), [[30_000, 0, 20_000], [30_000, 0, -5_000]]);
    assert_eq!(moves(&c, 1), auto[1], "CH2 keeps its program");
    // A line that does not read: no path, and why.
    c.handle(PanelEvent::Type("G1 Z-6 F0".into()));
    assert!(c.programmed(0).expect("a channel").is_err());
    // Back in AUTO: the stored program again.
    c.handle(PanelEvent::Op(OpMode::Auto));
    assert_eq!(moves(&c, 0), auto[0]);
    assert!(c.programmed(3).is_none());
}

/// PROGRAM READ on a lathe (stop 52): in DATA INPUT the typed path and the tape key (a
/// script's `tape PATH`) make the file the selected channel's program, journaled: a restart
/// finds it, START runs it. A punched tape image is decoded as the centre's reader decodes
/// it. Refused with the reason and nothing changed: another mode, a folder, a missing file,
/// a file that is neither text nor a tape, a cycle in progress. Before, a lathe had no way to
/// take a program from a file at its console.
#[test]
fn a_program_file_is_read_into_the_selected_channel_and_kept() {
    let state = common::temp_dir("lathe-program-read");
    // A shop lathe loaded by hand, whose programs do not work the chuck.
    let mut d = desc(Some(Dialect::Fanuc), None);
    d.manual = true;
    let file = state.join("shaft.nc");
    let text = "%\r\nO1234 (SHAFT)\r\nG94 G97 S800 M03\r\nG0 X20. Z2.\r\nG1 Z-10. F100.\r\nG0 X30.\r\nM30\r\n%\r\n";
    std::fs::write(&file, text).unwrap();
    let mut c = open(&d, &state);
    let before = c.programs()[0].clone();
    let said = |c: &mut LatheConsole, ev: PanelEvent| {
        c.handle(ev);
        c.message().to_string()
    };
    // Not in AUTO: the selector says where programs are read.
    let m = said(&mut c, PanelEvent::Tape(file.clone()));
    assert!(m.contains("turn the selector to DATA INPUT"), "{m}");
    assert_eq!(c.programs()[0], before);
    c.handle(PanelEvent::Op(novanc::panel_model::OpMode::Data));
    for (path, says) in [
        (state.clone(), "is a folder"),
        (state.join("none.nc"), "none.nc:"),
    ] {
        let m = said(&mut c, PanelEvent::Tape(path));
        assert!(
            m.contains("PROGRAM READ refused") && m.contains(says),
            "{m}"
        );
        assert!(m.contains("CH1's program unchanged"), "{m}");
        assert_eq!(c.programs()[0], before);
    }
    std::fs::write(state.join("Twice.nc"), "G0 X1.\n").unwrap();
    std::fs::write(state.join("twice.NC"), "G0 X2.\n").unwrap();
    let m = said(&mut c, PanelEvent::Tape(state.join("TWICE.NC")));
    assert!(m.contains("differ only in case"), "{m}");
    let bin = state.join("bin.nc");
    std::fs::write(&bin, [0x00, 0x13, 0xff, 0x41, 0x0a]).unwrap();
    let m = said(&mut c, PanelEvent::Tape(bin));
    assert!(m.contains("PROGRAM READ refused"), "{m}");
    assert_eq!(c.programs()[0], before);
    // The file: CH1's program, named after it, its line ends `\n`, in Fanuc's dialect. The
    // data keys type capitals: the path is found without regard to case.
    let caps = std::path::PathBuf::from(file.to_string_lossy().to_uppercase());
    assert!(!caps.exists());
    let m = said(&mut c, PanelEvent::Tape(caps));
    assert_eq!(m, "read shaft.nc (text): CH1's program SHAFT.NC, 8 lines");
    let p = c.programs()[0].clone();
    assert_eq!(p.name, "SHAFT.NC");
    assert_eq!(p.text, text.replace("\r\n", "\n"));
    assert_eq!(p.dialect, Some(Dialect::Fanuc));
    assert_eq!(c.pointer(0), 0);
    // Kept across a restart, and START runs it.
    drop(c);
    let mut c = open(&d, &state);
    assert_eq!(c.programs()[0], p);
    c.handle(PanelEvent::Op(novanc::panel_model::OpMode::Auto));
    c.handle(PanelEvent::Start);
    c.run_for(600_000_000_000, RunUntil::Rest, || false);
    assert_eq!(
        at(&c),
        [15_000, -10_000],
        "ends at X30 (diameter) Z-10: {}",
        c.message()
    );
    assert_eq!(c.counter().counts[0], 5, "the part target: {}", c.message());
    // A tape image punched from a program is decoded; a program that does not read says so.
    let tape = novanc::tape::punch(
        "G0 X20. Z2.\nG1 Z-10. F100. Q\n",
        &novanc::tape::PunchOptions {
            code: novanc::tape::Code::Iso,
            leader: 20,
            label: None,
        },
    )
    .unwrap();
    let image = state.join("bad.tape");
    std::fs::write(&image, tape).unwrap();
    c.handle(PanelEvent::Op(novanc::panel_model::OpMode::Data));
    let m = said(&mut c, PanelEvent::Tape(image));
    assert!(
        m.starts_with(
            "read bad.tape (ISO tape): CH1's program BAD, 2 lines; it does not read: line 2:"
        ),
        "{m}"
    );
    assert_eq!(c.programs()[0].text, "G0 X20. Z2.\nG1 Z-10. F100. Q\n");
    // While a cycle is loaded the programs are in use.
    c.handle(PanelEvent::Tape(file.clone()));
    c.handle(PanelEvent::Target(10));
    assert_eq!(c.message(), "part target 10");
    c.handle(PanelEvent::Op(novanc::panel_model::OpMode::Auto));
    c.handle(PanelEvent::Start);
    assert_eq!(c.message(), "cycle start");
    c.handle(PanelEvent::Stop);
    c.handle(PanelEvent::Op(novanc::panel_model::OpMode::Data));
    let m = said(&mut c, PanelEvent::Tape(file));
    assert!(m.contains("the programs are in use"), "{m}");
}

/// The punch key on a lathe (stop 52): in DATA INPUT the selected channel's program is punched
/// whole to the image the typed line names, as the centre punches its program, and reads back
/// as the same text; in another mode it is refused and the typed line stays.
#[test]
fn the_punch_key_punches_the_selected_channels_program() {
    let state = common::temp_dir("lathe-punch");
    let d = desc(Some(Dialect::Fanuc), None);
    let p = Program {
        name: "O1000.NC".into(),
        text: "O1000 (PIN)\nG94 G97 S800 M03\nG0 X20. Z2.\nG1 Z-10. F100.\nM30\n".into(),
        dialect: Some(Dialect::Fanuc),
    };
    save_program(&state, &d, &p);
    let mut c = open(&d, &state);
    let text = c.programs()[0].text.clone();
    let out = state.join("ch1.tape");
    let punch = |c: &mut LatheConsole, line: &str| {
        c.handle(PanelEvent::Type(line.into()));
        c.handle(PanelEvent::Press(novanc_panel::Key::Alt('u')));
        c.message().to_string()
    };
    let m = punch(&mut c, &out.display().to_string());
    assert!(
        m.starts_with("punch refused: it punches CH1's program in DATA INPUT (now AUTO)"),
        "{m}"
    );
    assert_eq!(c.entry(), out.display().to_string(), "the typed line stays");
    assert!(!out.exists());
    c.handle(PanelEvent::Op(novanc::panel_model::OpMode::Data));
    let m = punch(&mut c, &out.display().to_string());
    assert!(m.starts_with("punched "), "{m}");
    assert!(c.entry().is_empty());
    let back = novanc::tape::read_image(&std::fs::read(&out).unwrap(), Default::default()).unwrap();
    assert_eq!(back.code, Some(novanc::tape::Code::Iso));
    assert_eq!(back.text, text);
    // EIA, into a folder typed in capitals (the data keys' case).
    let eia = std::path::PathBuf::from(state.to_string_lossy().to_uppercase()).join("CH1.EIA");
    let m = punch(&mut c, &format!("{} EIA", eia.display()));
    assert!(m.contains("in the EIA code"), "{m}");
    let back = novanc::tape::read_image(
        &std::fs::read(state.join("CH1.EIA")).unwrap(),
        Default::default(),
    )
    .unwrap();
    assert_eq!(
        (back.code, back.text),
        (Some(novanc::tape::Code::Eia), text)
    );
}
