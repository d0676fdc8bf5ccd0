//! The interpreter's state at the console (docs/gcode.md "The interpreter's state"): MDI and
//! AUTO read from one state that outlives each run, the persistent parameters survive a
//! restart, a refused run changes nothing, G10 L1 keeps tool data, and a program's messages
//! reach the MSG page.

mod common;

use common::{keys, mdi, open, p, reopen, shows, type_line};
use novanc::console::Console;
use novanc::panel_model::{DataMode, OpMode, PanelEvent as E};

/// Whether a line of the display reads `words` (spaces between columns collapsed).
fn table_shows(c: &Console, words: &str) -> bool {
    c.frame_text()
        .lines()
        .any(|l| l.split_whitespace().collect::<Vec<_>>().join(" ") == words)
}

/// Reads `text` as program `name` into program memory (PROGRAM READ from a file).
fn read_program(c: &mut Console, name: &str, text: &str) {
    let f = common::temp_dir("state-prog").join(name);
    std::fs::write(&f, text).unwrap();
    c.handle(E::Op(OpMode::Data));
    c.handle(E::Data(DataMode::Read));
    c.handle(E::Tape(f));
    c.handle(E::Start);
    c.handle(E::Wait);
}

/// Reads `text` as program `name` and runs it in AUTO to its end.
fn run_program(c: &mut Console, name: &str, text: &str) {
    read_program(c, name, text);
    c.handle(E::Op(OpMode::Auto));
    c.handle(E::Start);
    c.handle(E::Wait);
}

#[test]
fn g91_in_one_mdi_line_makes_the_next_move_incremental() {
    let mut c = open("state-g91");
    mdi(&mut c, "G0 X10 Y5");
    assert_eq!(c.status().pos[0], p(10.0));
    mdi(&mut c, "G91");
    mdi(&mut c, "G0 X5");
    assert_eq!(c.status().pos[..2], [p(15.0), p(5.0)], "{}", c.frame_text());
    mdi(&mut c, "G90");
    mdi(&mut c, "G0 X5");
    assert_eq!(c.status().pos[0], p(5.0));
}

#[test]
fn a_programs_tool_length_offset_holds_for_the_next_mdi_move() {
    let mut c = open("state-g43");
    let len = c.magazine().tools.get(2).expect("T02 has data").length();
    assert!(len > 1.0);
    let prog = "%\nG10 L2 P1 Z-450\nG54 G43 H2\nG0 Z20\nM30\n%\n";
    run_program(&mut c, "G43.NGC", prog);
    assert!(shows(&c, "program end"), "{}", c.frame_text());
    assert!((c.status().pos[2] - p(-430.0 + len)).abs() <= 1);
    mdi(&mut c, "G0 Z10");
    // The tip, not the gauge line, at Z10 of the work system.
    assert!(
        (c.status().pos[2] - p(-440.0 + len)).abs() <= 1,
        "{} vs {}",
        c.status().pos[2],
        p(-440.0 + len)
    );
    // M30 reset what LinuxCNC resets: a program's G91 does not reach the next MDI line.
    run_program(&mut c, "G91.NGC", "%\nG91 G0 X1\nM30\n%\n");
    mdi(&mut c, "G0 X5");
    assert_eq!(c.status().pos[0], p(5.0));
}

#[test]
fn g92_survives_a_restart_of_the_console() {
    let mut c = open("state-g92");
    let dir = c.config().state_dir.clone();
    mdi(&mut c, "G0 X20 Y30");
    mdi(&mut c, "G92 X0 Y0");
    c.finish().unwrap();
    let mut c = reopen(&dir);
    // The machine starts at its zero again; X10 of the G92 frame is machine X30.
    mdi(&mut c, "G0 X10");
    assert_eq!(c.status().pos[0], p(30.0), "{}", c.frame_text());
    // novanc translate --state reads the console's memory with its G92 as well.
    let prog = common::temp_dir("state-g92-cli").join("x10.ngc");
    std::fs::write(&prog, "G0 X10\nM30\n").unwrap();
    let out = common::novanc_command()
        .args([
            "translate",
            prog.to_str().unwrap(),
            "--state",
            dir.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("N1 G00 X30.000"),
        "{text}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // G92.1 cancels it, and that persists too.
    mdi(&mut c, "G92.1");
    c.finish().unwrap();
    let mut c = reopen(&dir);
    mdi(&mut c, "G0 X10");
    assert_eq!(c.status().pos[0], p(10.0));
}

#[test]
fn a_named_global_set_in_one_run_is_read_in_the_next_and_printed_on_msg() {
    let mut c = open("state-global");
    let prog = "%\n\
        o100 if [EXISTS[#<_count>]]\n\
        #<_count> = [#<_count> + 1]\n\
        o100 else\n\
        #<_count> = 1\n\
        o100 endif\n\
        (print,count=#<_count>)\n\
        G0 X1\n\
        M30\n%\n";
    run_program(&mut c, "COUNT.NGC", prog);
    assert!(shows(&c, "count=1"), "{}", c.frame_text());
    c.handle(E::Op(OpMode::Auto));
    c.handle(E::Start);
    c.handle(E::Wait);
    assert!(shows(&c, "PRINT: count=2"), "{}", c.frame_text());
    // The MSG page keeps both, newest first.
    keys(&mut c, &["Ctrl+e"]);
    let f = c.frame_text();
    let two = f.find("count=2").expect(&f);
    let one = f.find("count=1").expect(&f);
    assert!(two < one, "{f}");
}

#[test]
fn a_run_refused_before_moving_leaves_the_state_unchanged() {
    let mut c = open("state-refused");
    // G20, G91 and a G92 on the first lines, then a feed move without F.
    c.handle(E::Op(OpMode::Data));
    c.handle(E::Data(DataMode::Mdi));
    type_line(&mut c, "IG20 G91*G92 X7*#<_kept>=1*G1 X1*");
    c.handle(E::Op(OpMode::Mdi));
    c.handle(E::Start);
    c.handle(E::Wait);
    assert!(
        shows(&c, "START refused, nothing moved"),
        "{}",
        c.frame_text()
    );
    let st = c.interp_state();
    assert!(!st.modal.inch && !st.modal.incremental);
    assert_eq!(st.g92, [0.0; 3]);
    assert!(!st.named.contains_key("_kept"));
    c.handle(E::Reset);
    mdi(&mut c, "G0 X1");
    assert_eq!(c.status().pos[0], p(1.0), "{}", c.frame_text());
}

#[test]
fn g10_l1_keeps_the_tool_length_in_the_tool_file() {
    let mut c = open("state-g10l1");
    let dir = c.config().state_dir.clone();
    let wear = c.magazine().tools.get(3).expect("T03 has data").wear_length;
    mdi(&mut c, "G10 L1 P3 Z123.5");
    assert!(shows(&c, "program end"), "{}", c.frame_text());
    let r = c.magazine().tools.get(3).cloned().unwrap();
    assert!((r.length() - 123.5).abs() < 1e-9, "{r:?}");
    assert!((r.set_length - (123.5 - wear)).abs() < 1e-9);
    c.finish().unwrap();
    let c = reopen(&dir);
    assert!((c.magazine().tools.get(3).unwrap().length() - 123.5).abs() < 1e-9);
}

#[test]
fn reset_turns_compensation_off_and_keeps_the_modal_groups() {
    let mut c = open("state-reset");
    mdi(&mut c, "G91 G20");
    c.handle(E::Reset);
    let st = c.interp_state();
    assert!(st.modal.incremental && st.modal.inch);
    mdi(&mut c, "G0 X1");
    assert_eq!(c.status().pos[0], p(25.4));
}

/// SEARCH shows the state it rebuilt by reading from the top (G codes, offsets, G92, tool,
/// spindle, coolant), and its restore does not first put back a tool the line searched to
/// changes anyway.
#[test]
fn search_shows_the_rebuilt_state_and_restores_no_tool_the_line_changes() {
    let mut c = open("state-search");
    let text = "%\nG10 L2 P2 X5 Z-450\nG55\nT2 M6\nG43 H2\nM3 S1200\nM8\nG0 X10 Y10 Z20\nG91\nT3 M6\nG90 G43 H3\nG0 Z20\nM30\n%\n";
    read_program(&mut c, "SRCH.NGC", text);
    c.handle(E::Data(DataMode::Search));
    // Line 8 (G0 X10 Y10 Z20): the restore puts T02 in the spindle first.
    type_line(&mut c, "8");
    let before = c.frame_text();
    assert!(
        before.contains("G0 G17 G90 G94 G21 G40 G43 G99 G55 G64"),
        "{before}"
    );
    assert!(before.contains("G55 X5.000 Y0.000 Z-450.000"), "{before}");
    assert!(before.contains("T02 H"), "{before}");
    assert!(before.contains("S1200 M3 M8"), "{before}");
    assert!(before.contains("T02"), "{before}");
    // Line 10 (T3 M6) changes the tool itself: no T02 first.
    type_line(&mut c, "10");
    let at = c.frame_text();
    assert!(at.contains("G91"), "{at}");
    assert!(!at.contains("T02") && !at.contains("T2 "), "{at}");
    c.handle(E::Op(OpMode::Auto));
    c.handle(E::Start);
    c.handle(E::Wait);
    assert!(shows(&c, "program end"), "{}", c.frame_text());
    assert_eq!(c.status().tool, Some(3));
}

/// The OFS page sets G59.1 to G59.3 as it sets G54 to G59, keeps them across a restart, and
/// shows G92 when it is in force; MDI uses them.
#[test]
fn the_ofs_page_sets_g59_3_and_shows_g92() {
    let mut c = open("state-ofs93");
    let dir = c.config().state_dir.clone();
    keys(&mut c, &["Ctrl+o"]);
    type_line(&mut c, "G59.3 X12.5 Y3 Z-100");
    assert!(
        shows(&c, "G59.3 X12.500 Y3.000 Z-100.000"),
        "{}",
        c.frame_text()
    );
    keys(&mut c, &["Ctrl+o"]);
    mdi(&mut c, "G59.3 G0 X0 Y0 Z0");
    assert_eq!(
        c.status().pos,
        [p(12.5), p(3.0), p(-100.0)],
        "{}",
        c.frame_text()
    );
    mdi(&mut c, "G92 X1");
    // X1 at machine X12.5: G92 X offset -1.
    keys(&mut c, &["Ctrl+o"]);
    assert!(
        table_shows(&c, "G92 -1.000 0.000 0.000"),
        "{}",
        c.frame_text()
    );
    c.finish().unwrap();
    let mut c = reopen(&dir);
    // G59.3 is still the system in force, and G92 still on.
    mdi(&mut c, "G0 X0 Y0");
    assert_eq!(c.status().pos[..2], [p(11.5), p(3.0)], "{}", c.frame_text());
    keys(
        &mut c,
        &[
            "Ctrl+o", "End", "Down", "Down", "Down", "Down", "Down", "Down", "Down", "Down",
        ],
    );
    assert!(
        table_shows(&c, "G59.3 >12.500 3.000 -100.000"),
        "{}",
        c.frame_text()
    );
}

/// A persistent parameter the stores cannot keep (beyond their limit) is said, and left out:
/// the next run reads the value the stores hold.
#[test]
fn a_parameter_the_stores_refuse_is_said_and_not_kept() {
    let mut c = open("state-refused-param");
    mdi(&mut c, "#5222 = 7");
    mdi(&mut c, "#5221 = 2000000");
    assert!(shows(&c, "NOT KEPT: #5221"), "{}", c.frame_text());
    assert_eq!(c.work_offsets().0[0], [0.0, 7.0, 0.0]);
    mdi(&mut c, "G54 G0 X1 Y0");
    assert_eq!(c.status().pos[..2], [p(1.0), p(7.0)], "{}", c.frame_text());
}
