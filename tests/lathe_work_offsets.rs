//! A lathe channel's work offsets G54–G59 at the console (docs/lathe-gcode.md "Work offsets";
//! stop 57, when the lathe had one work system with Z 0 at the work face): revised on the OFS
//! page under the tools, used by MDI and by a program, set by a program's G10 L2 and kept with
//! the channel's parameters across a restart, the display's X and Z in the program's
//! coordinates beside the machine's, RESET back to G54 with the offsets kept, and a bad
//! revision refused with nothing changed. The positions are worked out by hand.

mod common;

use novanc::lathe::console::LatheConsole;
use novanc::lathe::desc::{parse, LatheDesc, MachineDesc};
use novanc::panel_model::{OpMode, Page, PanelEvent};
use novanc_panel::Key;

/// A shop lathe of one channel, loaded by hand, in Fanuc's dialect (system A): X travel -5 to
/// 200 (a radius), Z -600 to 100; three tools with no nose radius and no offsets, so that the
/// tip stands where the program says.
fn shop() -> LatheDesc {
    let text = "machine shop\nkind lathe\npulse 0.001\ntick 100\nloading manual\ndialect fanuc\n\
                channel PATH-1\ngcode system A\nx travel -5 200 rapid 18000 accel 3000\n\
                z travel -600 100 rapid 24000 accel 3000\nspindle max 6000 accel 3000 encoder 1024\n\
                tool 1 radius 0 tip 3\ntool 2 radius 0 tip 3\ntool 3 radius 0 tip 3\n";
    match parse(text) {
        Ok(MachineDesc::Lathe(d)) => d,
        other => panic!("{other:?}"),
    }
}

fn open(state: &std::path::Path) -> LatheConsole {
    LatheConsole::open(shop(), state, 20, 40, None)
        .unwrap_or_else(|e| panic!("{e}"))
        .0
}

/// Types `line` and enters it (INPUT).
fn enter(c: &mut LatheConsole, line: &str) {
    c.handle(PanelEvent::Type(line.into()));
}

/// An MDI run of `line` to its end.
fn mdi(c: &mut LatheConsole, line: &str) {
    c.handle(PanelEvent::Op(OpMode::Mdi));
    enter(c, line);
    c.handle(PanelEvent::Start);
    c.handle(PanelEvent::Wait);
}

/// The selected channel's tip: work and machine position, µm [X radius, Z].
fn tip(c: &LatheConsole) -> ([i64; 2], [i64; 2]) {
    let v = c.view();
    let ch = &v.channels[0];
    (ch.work_pos(), ch.pos)
}

fn shows(c: &LatheConsole, text: &str) -> bool {
    c.view().display.iter().any(|l| l.contains(text))
}

#[test]
fn work_offsets_are_revised_on_ofs_used_by_mdi_and_programs_and_kept() {
    let dir = common::temp_dir("lathe-work-offsets");
    let mut c = open(&dir);
    // OFS: under the three tools, G54 to G59. The cursor to G55's Z (row 5, the last
    // column), then INPUT; then a revision line for X (a diameter).
    c.handle(PanelEvent::OfsMode);
    assert_eq!(c.page(), Page::Ofs);
    for _ in 0..4 {
        c.press(Key::Down);
    }
    c.press(Key::Right);
    enter(&mut c, "-250.5");
    assert!(
        shows(&c, "G55            0.000>-250.500"),
        "{:#?}",
        c.view().display
    );
    enter(&mut c, "G55 X4. Z-300.");
    assert!(
        c.message()
            .starts_with("G55 X4 Z-300 (CH1): from the next START"),
        "{}",
        c.message()
    );
    assert!(shows(&c, "G55            4.000>-300.000"));
    // Refused, and nothing changed: beyond the limit, a seventh system.
    enter(&mut c, "G55 Z20000");
    assert!(c.message().contains("within ±10000 mm"), "{}", c.message());
    enter(&mut c, "G60 Z1");
    assert!(
        c.message().contains("the work offsets are G54 to G59"),
        "{}",
        c.message()
    );
    assert!(shows(&c, "G55            4.000>-300.000"));

    // MDI in G55: X20. Z2. is the machine's X24 (a diameter: 12 mm of radius) Z-298.
    mdi(&mut c, "G55 G0 X20. Z2.");
    assert_eq!(tip(&c), ([10_000, 2_000], [12_000, -298_000]));
    c.press(Key::Ctrl('p'));
    assert!(shows(&c, "WORK G55"), "{:#?}", c.view().display);
    // WORK, REL (no origin set: the machine's), MACH, TO GO.
    assert!(shows(&c, "X   20.000   24.000   24.000    0.000"));
    assert!(shows(&c, "Z    2.000 -298.000 -298.000    0.000"));
    // MODAL: the system in force and its offset (X a diameter).
    c.press(Key::Ctrl('g'));
    assert!(shows(&c, "G55 OFFSET Z-300 X4"), "{:#?}", c.view().display);
    c.press(Key::Ctrl('g'));
    // The next MDI run goes on in G55 (a channel keeps its modes); RESET goes back to G54
    // and keeps the offsets.
    mdi(&mut c, "G0 X30.");
    assert_eq!(tip(&c).1, [17_000, -298_000]);
    c.handle(PanelEvent::Reset);
    mdi(&mut c, "G0 X30. Z2.");
    assert_eq!(tip(&c), ([15_000, 2_000], [15_000, 2_000]));

    // A program sets G56 by G10 L2 and cuts in it; the cycle's blocks run at its zero.
    let prog = dir.join("p1.nc");
    std::fs::write(
        &prog,
        "%\nO0001\nG10 L2 P3 X0 Z-200.\nG56 G0 X30. Z5.\nT0101\nG99 M3 S500\nG1 X28. F0.2\n\
         G0 X40. Z10.\nM30\n%\n",
    )
    .unwrap();
    c.handle(PanelEvent::Op(OpMode::Data));
    c.handle(PanelEvent::Tape(prog.clone()));
    c.handle(PanelEvent::Op(OpMode::Auto));
    c.handle(PanelEvent::Start);
    c.handle(PanelEvent::Wait);
    assert_eq!(tip(&c), ([20_000, 10_000], [20_000, -190_000]));
    c.press(Key::Ctrl('p'));
    assert!(shows(&c, "WORK G56"), "{:#?}", c.view().display);
    c.close(None).unwrap();

    // A new session: the revised G55 and the program's G56 are kept; the channel starts in
    // G54.
    let mut c = open(&dir);
    c.handle(PanelEvent::OfsMode);
    assert!(
        shows(&c, "G55            4.000 -300.000"),
        "{:#?}",
        c.view().display
    );
    assert!(shows(&c, "G56            0.000 -200.000"));
    mdi(&mut c, "G56 G0 X50. Z0");
    assert_eq!(tip(&c), ([25_000, 0], [25_000, -200_000]));
    c.close(None).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
}

/// A move a work offset would take past the travel is refused before anything moves, and says
/// where: the machine's Z, not the program's.
#[test]
fn a_work_offset_that_takes_the_tool_past_its_travel_is_refused_before_it_moves() {
    let dir = common::temp_dir("lathe-work-travel");
    let mut c = open(&dir);
    c.handle(PanelEvent::OfsMode);
    enter(&mut c, "G57 Z-590.");
    let before = tip(&c);
    mdi(&mut c, "G57 G0 X20. Z-20.");
    assert!(c.message().contains("travel"), "{}", c.message());
    assert_eq!(tip(&c), before);
    c.close(None).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
}

/// Setting up by touching the face (docs/lathe-gcode.md "Work offsets"): tool 1, with a Z
/// offset of -1.5, stands where the operator brought it (here by MDI); `Z0` INPUT on G54's
/// row of the OFS page (Fanuc's MEASURE) makes that G54's Z0. The display then reads the
/// programmed point, Z0 and after `G0 Z5.` Z5, as a Fanuc's ABSOLUTE does (the tool's offset
/// and the zero taken off the tip), the machine's Z beside it. (Fanuc's G10 L20 is another
/// thing, its additional work systems, and is refused: `tests/lathe_real.rs`; LinuxCNC's is
/// the same measure, `tests/golden/lathe_rs274/work_offsets.ngc`.)
#[test]
fn touching_the_face_and_measuring_makes_the_work_zero_and_the_display_reads_the_program() {
    let dir = common::temp_dir("lathe-work-touch");
    let mut c = open(&dir);
    c.handle(PanelEvent::OfsMode);
    enter(&mut c, "T1 Z-1.5");
    mdi(&mut c, "T0101 G0 X50. Z-123.4");
    // The tip: -123.4 less 1.5 of the tool's offset; the display: the programmed -123.4.
    assert_eq!(tip(&c), ([25_000, -123_400], [25_000, -124_900]));
    c.handle(PanelEvent::OfsMode);
    // The cursor down past the three tools onto G54, then right onto its Z.
    for _ in 0..3 {
        c.press(Key::Down);
    }
    c.press(Key::Right);
    enter(&mut c, "Z0");
    assert!(
        c.message()
            .starts_with("measured, T01 at Z0: G54 X0 Z-123.4 (CH1): from the next START"),
        "{}",
        c.message()
    );
    assert!(
        shows(&c, "G54            0.000>-123.400"),
        "{:#?}",
        c.view().display
    );
    assert_eq!(tip(&c), ([25_000, 0], [25_000, -124_900]));
    // X alike, on the diameter: the tool at X50 reads X40 after `X40.` on G54's X.
    c.press(Key::Left);
    enter(&mut c, "X40.");
    assert_eq!(tip(&c), ([20_000, 0], [25_000, -124_900]));
    enter(&mut c, "X50.");
    assert_eq!(tip(&c), ([25_000, 0], [25_000, -124_900]));
    mdi(&mut c, "G0 Z5.");
    assert_eq!(tip(&c), ([25_000, 5_000], [25_000, -119_900]));
    assert!(c.view().display[1].starts_with("X   50.000 Z    5.000"));
    c.close(None).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
}

/// Measuring a tool (Fanuc's MEASURE on the tool offsets): with the tool in place where it
/// cut, `X49.9` INPUT on its row (the diameter just measured) sets its X offset so the display
/// reads X49.9 there, `Z0` on its row its Z offset from a face at Z0; a tool not in place is
/// refused with how to measure it.
#[test]
fn a_tool_is_measured_where_it_stands_on_its_row_of_the_ofs_page() {
    let dir = common::temp_dir("lathe-tool-measure");
    let mut c = open(&dir);
    mdi(&mut c, "T0101 G0 X50. Z-10.");
    assert_eq!(tip(&c), ([25_000, -10_000], [25_000, -10_000]));
    c.handle(PanelEvent::OfsMode);
    // The cursor starts on T01's X.
    enter(&mut c, "X49.9");
    assert!(
        c.message()
            .starts_with("measured, T01 at X49.9: T01 revised"),
        "{}",
        c.message()
    );
    assert!(
        shows(&c, "T01 0.000 3>   0.100   0.000"),
        "{:#?}",
        c.view().display
    );
    assert_eq!(tip(&c), ([24_950, -10_000], [25_000, -10_000]));
    c.press(Key::Right);
    enter(&mut c, "Z0");
    assert!(
        shows(&c, "T01 0.000 3    0.100>-10.000"),
        "{:#?}",
        c.view().display
    );
    assert_eq!(tip(&c), ([24_950, 0], [25_000, -10_000]));
    // T02 is not in place.
    c.press(Key::Down);
    enter(&mut c, "Z0");
    assert!(
        c.message()
            .starts_with("measure T02 refused: the tool in place is T01"),
        "{}",
        c.message()
    );
    assert!(shows(&c, "T02 0.000 3    0.000>  0.000"));
    c.close(None).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
}
