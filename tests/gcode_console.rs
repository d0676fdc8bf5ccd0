//! ISO G-code programs at the console (docs/gcode.md "At the console"): PROGRAM READ keeps a
//! G-code file's language, AUTO and SINGLE BLOCK run it from the machine's actual state with
//! the ISO line as the source statement, SEARCH, and MDI lines in either language.

mod common;

use common::{audit, open, p, shows, type_line};
use novanc::block::MachineState;
use novanc::console::Console;
use novanc::gcode::{GcodeSource, Switches, WorkOffsets};
use novanc::panel_model::{DataMode, OpMode, PanelEvent as E};
use std::path::{Path, PathBuf};

fn repo(f: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(f)
}

/// PROGRAM READ of a file at the console.
fn read_program(c: &mut Console, path: &Path) {
    c.handle(E::Op(OpMode::Data));
    c.handle(E::Data(DataMode::Read));
    c.handle(E::Tape(path.to_path_buf()));
    c.handle(E::Start);
    c.handle(E::Wait);
}

/// A G-code file written to a fresh directory.
fn gfile(name: &str, text: &str) -> PathBuf {
    let p = common::temp_dir("gfile").join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// The blocks a G-code text makes from machine zero with no tool, zero offsets.
fn expected_ends(text: &str, c: &Console) -> Vec<[i64; 3]> {
    GcodeSource::new(
        text.into(),
        c.magazine(),
        c.settings().clone(),
        MachineState::at([0, 0, 0]),
        WorkOffsets::default(),
        Switches::default(),
    )
    .map(|s| s.unwrap())
    .flat_map(|s| s.blocks.into_iter().map(|b| b.end.xyz()))
    .collect()
}

#[test]
fn program_read_keeps_the_language_and_auto_runs_the_gcode_program() {
    let mut c = open("g-auto");
    let text = std::fs::read_to_string(repo("programs/pocket.ngc")).unwrap();
    read_program(&mut c, &repo("programs/pocket.ngc"));
    assert_eq!(c.program_name(), "POCKET.NGC", "{}", c.frame_text());
    assert_eq!(c.program_text(), text);
    let want = expected_ends(&text, &c);
    c.handle(E::Op(OpMode::Auto));
    c.handle(E::Start);
    c.handle(E::Wait);
    assert!(shows(&c, "program end"), "{}", c.frame_text());
    assert!(!c.view().lamps.alarm, "{}", c.frame_text());
    let ends: Vec<[i64; 3]> = audit(&c).iter().map(|e| e.end.xyz()).collect();
    assert_eq!(
        ends, want,
        "the machine ran the blocks the G-code source makes"
    );
}

#[test]
fn single_block_shows_the_iso_line_as_the_source_statement() {
    let mut c = open("g-single");
    let f = gfile(
        "single.ngc",
        "G21 G90\nG0 X10 Y20\nG1 Z-5 F300\nG0 Z0\nM30\n",
    );
    read_program(&mut c, &f);
    // No % and no O number: the name keeps it G-code, and the PROG page says so.
    assert_eq!(c.program_name(), "SINGLE.NGC");
    common::keys(&mut c, &["Ctrl+d"]);
    assert!(
        c.frame_text()
            .lines()
            .any(|l| l.contains("SINGLE.NGC") && l.contains("ISO")),
        "{}",
        c.frame_text()
    );
    common::keys(&mut c, &["Ctrl+d"]);
    c.handle(E::Op(OpMode::Single));
    c.handle(E::Start);
    c.handle(E::Wait);
    // The first line with blocks is line 2.
    assert!(shows(&c, "G0 X10 Y20"), "{}", c.frame_text());
    assert_eq!(c.status().pos, [p(10.0), p(20.0), 0]);
    c.handle(E::Start);
    c.handle(E::Wait);
    assert!(shows(&c, "G1 Z-5 F300"), "{}", c.frame_text());
    assert_eq!(c.status().pos, [p(10.0), p(20.0), p(-5.0)]);
    c.handle(E::Op(OpMode::Auto));
    c.handle(E::Start);
    c.handle(E::Wait);
    assert!(shows(&c, "program end"), "{}", c.frame_text());
    assert_eq!(c.status().pos, [p(10.0), p(20.0), 0]);
}

#[test]
fn a_gcode_program_starts_from_the_machines_actual_position() {
    let mut c = open("g-actual");
    // Incremental moves: the result depends on where the machine is at START.
    let f = gfile("inc.ngc", "G91 G0 X5 Y-5\nM30\n");
    read_program(&mut c, &f);
    c.handle(E::Op(OpMode::Mdi));
    type_line(&mut c, "G0 X100 Y50 Z-10");
    c.handle(E::Start);
    c.handle(E::Wait);
    assert_eq!(c.status().pos, [p(100.0), p(50.0), p(-10.0)]);
    c.handle(E::Op(OpMode::Auto));
    c.handle(E::Start);
    c.handle(E::Wait);
    assert!(shows(&c, "program end"), "{}", c.frame_text());
    assert_eq!(c.status().pos, [p(105.0), p(45.0), p(-10.0)]);
}

#[test]
fn search_positions_a_gcode_program() {
    let mut c = open("g-search");
    let f = gfile(
        "search.ngc",
        "G21 G90\nG0 X10 Y10\nG0 X20 Y30\nG1 Z-2 F100\nG0 Z0\nM30\n",
    );
    read_program(&mut c, &f);
    c.handle(E::Data(DataMode::Search));
    type_line(&mut c, "G1 Z-2");
    assert!(shows(&c, "AUTO starts at line 4"), "{}", c.frame_text());
    c.handle(E::Op(OpMode::Auto));
    c.handle(E::Start);
    c.handle(E::Wait);
    assert!(shows(&c, "program end"), "{}", c.frame_text());
    let a = audit(&c);
    // The restore goes to X20 Y30 (line 3's point) without visiting X10 Y10 (line 2).
    assert!(a.iter().all(|e| e.end[..2] != [p(10.0), p(10.0)]), "{a:?}");
    assert!(
        a.iter().any(|e| e.end == [p(20.0), p(30.0), p(-2.0)]),
        "{a:?}"
    );
}

#[test]
fn mdi_takes_gcode_lines_and_source_statements() {
    let mut c = open("g-mdi");
    c.handle(E::Op(OpMode::Mdi));
    // Each line typed, START, and where the machine ends.
    for (line, want) in [
        ("G0 X10 Y20 Z-5", [10.0, 20.0, -5.0]),
        ("GO, 100, 50, -20", [100.0, 50.0, -20.0]),
        ("G91 G1 X-1 F100", [99.0, 50.0, -20.0]),
    ] {
        type_line(&mut c, line);
        c.handle(E::Start);
        c.handle(E::Wait);
        assert_eq!(c.status().pos, want.map(p), "{line}:\n{}", c.frame_text());
    }
}

#[test]
fn a_bad_gcode_line_in_mdi_says_where_and_moves_nothing() {
    let mut c = open("g-mdi-bad");
    c.handle(E::Op(OpMode::Mdi));
    for (line, why) in [
        ("G0 X10 G1 Y5", "modal group"),
        ("G1 X10", "F"),
        ("G0 X[1/0]", "zero"),
        ("G10 L2 P10 X1", "P"),
    ] {
        let before = (c.status().pos, c.work_offsets());
        type_line(&mut c, line);
        c.handle(E::Start);
        c.handle(E::Wait);
        assert!(
            shows(&c, "START refused, nothing moved: line 1:"),
            "{line}:\n{}",
            c.frame_text()
        );
        assert!(shows(&c, why), "{line}:\n{}", c.frame_text());
        assert_eq!((c.status().pos, c.work_offsets()), before, "{line}");
        c.handle(E::Reset);
    }
}

const STOPS: &str = "G21 G90\nG0 X10\nM0\nG0 X20\n/G0 X30\nM1\nG0 X40\nM30\n";

#[test]
fn m00_stops_the_run_after_its_block_and_start_continues() {
    let mut c = open("g-m00");
    read_program(&mut c, &gfile("stops.ngc", STOPS));
    c.handle(E::Op(OpMode::Auto));
    c.handle(E::Start);
    c.handle(E::Wait);
    assert_eq!(c.status().pos, [p(10.0), 0, 0], "{}", c.frame_text());
    assert!(c.status().job.is_some() && c.status().run == 0);
    assert!(
        shows(&c, "M00 program stop: START continues"),
        "{}",
        c.frame_text()
    );
    c.handle(E::Start);
    c.handle(E::Wait);
    // OPTIONAL STOP off: M01 does not stop; BLOCK DELETE off: the / line runs.
    assert!(shows(&c, "program end"), "{}", c.frame_text());
    let xs: Vec<i64> = audit(&c).iter().map(|e| e.end[0]).collect();
    assert!(xs.contains(&p(30.0)), "{xs:?}");
}

#[test]
fn the_switches_skip_slash_lines_and_stop_at_m01() {
    let mut c = open("g-switches");
    read_program(&mut c, &gfile("stops.ngc", STOPS));
    common::keys(&mut c, &["Alt+b"]);
    assert!(shows(&c, "BLOCK DELETE on"), "{}", c.frame_text());
    c.handle(E::OptionalStop(true));
    c.handle(E::Op(OpMode::Auto));
    assert!(
        shows(&c, "/DEL M01"),
        "the state line shows both:\n{}",
        c.frame_text()
    );
    c.handle(E::Start);
    c.handle(E::Wait);
    c.handle(E::Start);
    c.handle(E::Wait);
    assert_eq!(c.status().pos, [p(20.0), 0, 0], "{}", c.frame_text());
    assert!(
        shows(&c, "M01 optional stop: START continues"),
        "{}",
        c.frame_text()
    );
    c.handle(E::Start);
    c.handle(E::Wait);
    assert!(shows(&c, "program end"), "{}", c.frame_text());
    let xs: Vec<i64> = audit(&c).iter().map(|e| e.end[0]).collect();
    assert!(!xs.contains(&p(30.0)), "block delete skipped X30: {xs:?}");
    assert_eq!(c.status().pos[0], p(40.0));
    // The keys turn them off again.
    common::keys(&mut c, &["Alt+b", "Alt+o"]);
    assert!(
        !shows(&c, "/DEL") && !shows(&c, " M01"),
        "{}",
        c.frame_text()
    );
}

/// Found by the operator-sequence test: SEARCH to a line before any Z move, with another
/// (shorter) tool in the spindle low down, went back down to the machine's Z with the longer
/// tool, putting the tip below anything programmed. Z now stays at machine zero.
#[test]
fn search_before_any_z_move_leaves_z_at_machine_zero() {
    let mut c = open("g-search-z");
    let f = gfile(
        "tool.ngc",
        "G21 G90\nT1 M6\nG43 H1\nG0 X10 Y10\nG0 Z-300\nM30\n",
    );
    read_program(&mut c, &f);
    // Tool 2 in the spindle, low down.
    c.handle(E::Op(OpMode::Mdi));
    type_line(&mut c, "T2 M6");
    c.handle(E::Start);
    c.handle(E::Wait);
    type_line(&mut c, "G53 G0 Z-400");
    c.handle(E::Start);
    c.handle(E::Wait);
    assert_eq!(c.status().tool, Some(2));
    c.handle(E::Op(OpMode::Data));
    c.handle(E::Data(DataMode::Search));
    type_line(&mut c, "3");
    audit(&c);
    c.handle(E::Op(OpMode::Auto));
    c.handle(E::Start);
    c.handle(E::Wait);
    assert!(shows(&c, "program end"), "{}", c.frame_text());
    let len = c.magazine().tools.get(1).unwrap().length();
    let ends = audit(&c);
    let low = ends.iter().map(|e| e.end[2]).min().unwrap();
    assert_eq!(
        low,
        p(-300.0 + len),
        "the lowest Z is the one programmed: {ends:?}"
    );
    assert_eq!(c.status().tool, Some(1));
}

#[test]
fn a_gcode_program_starts_with_the_tool_in_the_spindle() {
    let mut c = open("g-tool");
    // G43 without H takes the tool in the spindle, which an MDI tool change put there.
    read_program(&mut c, &gfile("len.ngc", "G43\nG0 Z-300\nM30\n"));
    c.handle(E::Op(OpMode::Mdi));
    type_line(&mut c, "T2 M6");
    c.handle(E::Start);
    c.handle(E::Wait);
    assert_eq!(c.status().tool, Some(2));
    c.handle(E::Op(OpMode::Auto));
    c.handle(E::Start);
    c.handle(E::Wait);
    assert!(shows(&c, "program end"), "{}", c.frame_text());
    let len = c.magazine().tools.get(2).unwrap().set_length;
    assert_eq!(c.status().pos[2], p(-300.0 + len));
}

#[test]
fn a_gcode_program_is_edited_with_the_editor_commands_and_the_edit_survives_a_restart() {
    let mut c = open("g-edit");
    let dir = c.config().state_dir.clone();
    read_program(&mut c, &gfile("ed.ngc", "G0 X10 Y20\nM30\n"));
    c.handle(E::Data(DataMode::Revise));
    type_line(&mut c, "CX10$X12");
    assert!(shows(&c, "ok"), "{}", c.frame_text());
    c.finish().unwrap();
    let mut cfg = novanc::console::ConsoleConfig::new(dir);
    cfg.clock = novanc::pulse_core::ClockMode::Virtual;
    let mut c = Console::open(cfg).unwrap().0;
    assert_eq!(c.program_name(), "ED.NGC");
    assert_eq!(c.program_text(), "G0 X12 Y20\nM30\n");
    c.handle(E::Op(OpMode::Auto));
    c.handle(E::Start);
    c.handle(E::Wait);
    assert_eq!(c.status().pos, [p(12.0), p(20.0), 0], "{}", c.frame_text());
}

/// A G-code run takes a tool's length when G43 is read (as LinuxCNC): a length revised on OFS
/// between single blocks does not move that run's blocks, and the message says so instead of
/// the source language's "from the next block"; the next run uses it.
#[test]
fn an_ofs_length_revised_during_a_gcode_run_says_it_applies_from_the_next_run() {
    let mut c = open("g-ofs");
    let text =
        "G21 G90\nG10 L2 P1 Z-450\nG54\nT2 M6\nG43 H2\nG0 X10 Y20 Z20\nG1 Z-5 F300\nG0 Z20\nM30\n";
    read_program(&mut c, &gfile("ofs.ngc", text));
    c.handle(E::Op(OpMode::Single));
    c.handle(E::Start);
    c.handle(E::Wait);
    let want = expected_ends(text, &c);
    common::keys(&mut c, &["Ctrl+O", "Down"]);
    type_line(&mut c, "155");
    assert_eq!(c.magazine().tools.get(2).unwrap().set_length, 155.0);
    assert!(
        shows(&c, "from the next run; this G-code run keeps"),
        "{}",
        c.frame_text()
    );
    c.handle(E::Op(OpMode::Auto));
    c.handle(E::Start);
    c.handle(E::Wait);
    assert!(shows(&c, "program end"), "{}", c.frame_text());
    let ends: Vec<[i64; 3]> = audit(&c).iter().map(|e| e.end.xyz()).collect();
    assert_eq!(ends, want, "the run kept the length G43 read");
}

/// The state line cut on the 40-column plasma (all switches on, the error-proportional
/// interpolator) still says ESTOP and HOLD: what the machine is doing comes before the switches.
#[test]
fn the_state_line_keeps_estop_and_hold_ahead_of_the_switches() {
    let mut cfg = novanc::console::ConsoleConfig::new(common::temp_dir("g-state-line"));
    cfg.clock = novanc::pulse_core::ClockMode::Virtual;
    cfg.settings.interpolator = novanc::settings::Interpolator::ErrorProportional;
    let mut c = Console::open(cfg).unwrap().0;
    c.handle(E::BlockDelete(true));
    c.handle(E::OptionalStop(true));
    c.handle(E::Op(OpMode::Auto));
    c.handle(E::Start);
    c.handle(E::WaitMs(3000));
    c.handle(E::Stop);
    c.handle(E::Wait);
    let last = |c: &Console| c.view().display.last().cloned().unwrap_or_default();
    assert!(last(&c).contains(" HOLD"), "{}", c.frame_text());
    c.handle(E::EStop);
    let line = last(&c);
    assert!(line.contains(" ESTOP /DEL"), "{}", c.frame_text());
    assert!(line.chars().count() <= 40, "{line}");
}

/// Coolant is the machine's: MDI M8 turns it on in the pulse core and MODAL shows it; RESET
/// turns it off there (LinuxCNC's M9 state after a reset) and the interpreter's state follows
/// (MODAL shows M9); M7, M8 then M9 in MDI go through the core as well.
#[test]
fn reset_leaves_the_coolant_off_as_the_machine_has_it() {
    let mut c = common::open("gcode-coolant");
    common::mdi(&mut c, "S500 M3 M8");
    assert_eq!(c.status().coolant, (false, true));
    common::keys(&mut c, &["Ctrl+G"]);
    assert!(common::shows(&c, "M3 M8"), "{}", c.frame_text());
    common::keys(&mut c, &["F11"]);
    c.handle(novanc::panel_model::PanelEvent::Wait);
    assert_eq!(c.status().coolant, (false, false));
    assert!(common::shows(&c, "M9"), "{}", c.frame_text());
    assert!(!common::shows(&c, "M8"), "{}", c.frame_text());
    common::keys(&mut c, &["Ctrl+G"]);
    common::mdi(&mut c, "M7");
    assert_eq!(c.status().coolant, (true, false), "{}", c.frame_text());
    common::mdi(&mut c, "M8");
    assert_eq!(c.status().coolant, (true, true));
    common::mdi(&mut c, "M9");
    assert_eq!(c.status().coolant, (false, false));
}
