//! The operator pages (docs/panel.md, "Pages"), each rule with the message the operator sees
//! and what is kept across a restart: POS presets and counters (with the part-count target),
//! PROG select/copy/rename/delete (journaled, refused with a run loaded), OFS INPUT and
//! +INPUT (refused values change nothing), MSG history across a restart, MDI recall.

mod common;

use common::{keys, shows, temp_dir, type_line};
use novanc::console::{Console, ConsoleConfig};
use novanc::panel_model::{Page, PanelEvent};
use novanc::pulse_core::ClockMode;
use novanc_panel::Key;
use std::path::Path;

fn open_in(dir: &Path) -> Console {
    let mut cfg = ConsoleConfig::new(dir.to_path_buf());
    cfg.clock = ClockMode::Virtual;
    Console::open(cfg).unwrap().0
}

#[test]
fn pos_zeroes_and_presets_the_relative_position_in_two_keys() {
    let dir = temp_dir("pages-pos");
    let mut c = open_in(&dir);
    keys(&mut c, &["Alt+6", "Right"]);
    c.handle(PanelEvent::Wait);
    keys(&mut c, &["Right", "Ctrl+P"]);
    c.handle(PanelEvent::Wait);
    assert_eq!(c.status().pos[0], 200);
    assert_eq!(c.view().page, Page::Pos);
    // X Enter: two keys.
    type_line(&mut c, "X");
    assert!(
        shows(&c, "relative X preset to 0.000"),
        "{}",
        c.frame_text()
    );
    // On POS the arrows still jog: the relative X follows, the machine X too.
    keys(&mut c, &["Right"]);
    c.handle(PanelEvent::Wait);
    let f = c.frame_text();
    let x = f.lines().find(|l| l.starts_with("X ")).unwrap().to_string();
    let cols: Vec<&str> = x.split_whitespace().collect();
    assert_eq!(cols[2], "0.100", "REL X after one more increment: {x}");
    assert_eq!(cols[3], "0.300", "MACH X: {x}");
    type_line(&mut c, "Y12.5");
    assert!(shows(&c, "relative Y preset to 12.500"));
    type_line(&mut c, "Q7");
    assert!(shows(&c, "POS: type X"), "{}", c.frame_text());
    // In MDI a line typed under POS is POS's: the refusal says how to put the page down.
    c.handle(PanelEvent::Op(novanc::panel_model::OpMode::Mdi));
    keys(&mut c, &["Ctrl+P"]);
    type_line(&mut c, "G0X1");
    assert!(
        c.message()
            .ends_with("(POS is up: Ctrl+P puts it down for MDI)"),
        "{}",
        c.message()
    );
}

#[test]
fn the_part_counter_counts_auto_runs_keeps_across_a_restart_and_stops_at_its_target() {
    let dir = temp_dir("pages-parts");
    {
        let mut c = open_in(&dir);
        keys(&mut c, &["Ctrl+P"]);
        type_line(&mut c, "TARGET 2");
        keys(&mut c, &["Ctrl+P", "Alt+2"]);
        for _ in 0..2 {
            keys(&mut c, &["F9"]);
            c.handle(PanelEvent::Wait);
        }
        assert!(
            shows(&c, "part count target reached (2/2)"),
            "{}",
            c.frame_text()
        );
        // The next AUTO START is refused and nothing moves.
        let runs = c.status().runs;
        keys(&mut c, &["F9"]);
        assert_eq!(c.status().runs, runs);
        assert!(shows(&c, "START refused: part count target reached"));
    }
    // The counters are kept: still refused after a restart; PARTS 0 lets it run again.
    let mut c = open_in(&dir);
    keys(&mut c, &["Ctrl+P"]);
    assert!(shows(&c, "PARTS 2/2"), "{}", c.frame_text());
    keys(&mut c, &["Ctrl+P", "Alt+2", "F9"]);
    assert!(shows(&c, "START refused: part count target reached"));
    keys(&mut c, &["Ctrl+P"]);
    type_line(&mut c, "PARTS 0");
    keys(&mut c, &["Ctrl+P", "F9"]);
    c.handle(PanelEvent::Wait);
    assert!(shows(&c, "program end"), "{}", c.frame_text());
    // MDI runs are not parts and are never stopped by the target.
    keys(&mut c, &["Ctrl+P"]);
    assert!(shows(&c, "PARTS 1/2"), "{}", c.frame_text());
}

#[test]
fn prog_copies_renames_and_deletes_after_a_confirmation_and_it_is_journaled() {
    let dir = temp_dir("pages-prog");
    {
        let mut c = open_in(&dir);
        keys(&mut c, &["Ctrl+D"]);
        type_line(&mut c, "C part2");
        assert!(shows(&c, "TABLEB copied as PART2"), "{}", c.frame_text());
        type_line(&mut c, "R P3");
        assert!(shows(&c, "renamed P3"), "{}", c.frame_text());
        // The cursor to TABLEB, and a delete asks first; anything else keeps it.
        keys(&mut c, &["Down"]);
        type_line(&mut c, "D");
        assert!(
            shows(&c, "delete TABLEB? D Enter again"),
            "{}",
            c.frame_text()
        );
        type_line(&mut c, "x");
        type_line(&mut c, "D");
        type_line(&mut c, "D");
        assert!(shows(&c, "program TABLEB deleted"), "{}", c.frame_text());
        // The last program is never deleted.
        type_line(&mut c, "D");
        type_line(&mut c, "D");
        assert!(shows(&c, "PROG refused"), "{}", c.frame_text());
    }
    let mut c = open_in(&dir);
    keys(&mut c, &["Ctrl+D"]);
    let f = c.frame_text();
    assert!(f.contains("P3") && !f.contains("TABLEB"), "{f}");
    assert!(c.program_text().contains("DRL, 106"));
}

#[test]
fn prog_is_refused_with_a_run_loaded_and_nothing_changes() {
    let mut c = common::open("pages-prog-run");
    keys(&mut c, &["Alt+7", "F9"]);
    c.handle(PanelEvent::Wait);
    assert!(c.status().job.is_some());
    keys(&mut c, &["Ctrl+D"]);
    type_line(&mut c, "C X2");
    assert!(shows(&c, "PROG refused: a run is loaded; RESET first"));
    assert!(!c.frame_text().contains("X2 "), "{}", c.frame_text());
}

#[test]
fn ofs_input_sets_plus_input_adds_and_a_refused_value_changes_nothing() {
    let dir = temp_dir("pages-ofs");
    {
        let mut c = open_in(&dir);
        keys(&mut c, &["Ctrl+O", "Down"]);
        type_line(&mut c, "155");
        assert_eq!(c.magazine().tools.get(2).unwrap().set_length, 155.0);
        // +INPUT: Tab adds.
        for ch in "-0.25".chars() {
            c.handle(PanelEvent::Key(ch));
        }
        keys(&mut c, &["Tab"]);
        assert_eq!(c.magazine().tools.get(2).unwrap().set_length, 154.75);
        // A value the validator refuses: the reason, and no change.
        let before = c.magazine();
        type_line(&mut c, "-3");
        assert!(shows(&c, "OFS refused"), "{}", c.frame_text());
        assert_eq!(c.magazine(), before);
        type_line(&mut c, "abc");
        assert!(shows(&c, "'abc' is not a number"), "{}", c.frame_text());
        assert_eq!(c.magazine(), before);
    }
    // Journaled like any tool revision.
    let c = open_in(&dir);
    assert_eq!(c.magazine().tools.get(2).unwrap().set_length, 154.75);
}

#[test]
fn the_message_history_is_kept_across_a_restart_newest_first() {
    let dir = temp_dir("pages-msg");
    {
        let mut c = open_in(&dir);
        keys(&mut c, &["F12", "F11"]);
    }
    let mut c = open_in(&dir);
    keys(&mut c, &["Ctrl+E"]);
    let f = c.frame_text();
    let reset = f.find("reset: machine idle").expect(&f);
    let estop = f.find("ALARM EMERGENCY STOP").expect(&f);
    assert!(reset < estop, "newest first:\n{f}");
}

#[test]
fn mdi_typing_sets_the_buffer_and_up_recalls_a_refused_line() {
    let mut c = common::open("pages-mdi");
    keys(&mut c, &["Alt+3"]);
    type_line(&mut c, "GO, 500, 300, -200");
    assert!(
        shows(&c, "MDI buffer set: START runs it"),
        "{}",
        c.frame_text()
    );
    keys(&mut c, &["F9"]);
    c.handle(PanelEvent::Wait);
    // Held in the middle of a second MDI run: a new line is refused, and Up brings it back.
    type_line(&mut c, "GO, 400, 300, -100");
    keys(&mut c, &["F9"]);
    keys(&mut c, &["F10"]);
    type_line(&mut c, "GO, 10, 10, -10");
    assert!(
        shows(&c, "MDI refused: a run is loaded"),
        "{}",
        c.frame_text()
    );
    keys(&mut c, &["Up"]);
    assert!(
        c.view().entry.contains("GO, 10, 10, -10"),
        "{:?}",
        c.view().entry
    );
}

/// Home and End on OFS: the first T code, and the work offsets (G54, after the last T code),
/// without paging through the magazine.
#[test]
fn ofs_home_and_end_reach_the_first_tool_and_the_work_offsets() {
    let mut c = common::open("pages-ofs-home-end");
    keys(&mut c, &["Ctrl+O", "End"]);
    let f = c.frame_text();
    assert!(
        f.contains("OFS WORK") && f.contains("G54        >0.000"),
        "{f}"
    );
    keys(&mut c, &["Home"]);
    let f = c.frame_text();
    assert!(f.contains("T01 00610        40> 220.000"), "{f}");
}

/// The POS line a row starts with (`X `, `TOOL`), and the heading.
fn pos_line(c: &Console, start: &str) -> String {
    let f = c.frame_text();
    f.lines()
        .find(|l| l.trim_start().starts_with(start))
        .unwrap_or_else(|| panic!("no {start} line:\n{f}"))
        .to_string()
}

/// POS shows the work position in the system the console's interpreter has in force (G55
/// here, selected by MDI) with its name, G92 included, not always G54.
#[test]
fn pos_shows_the_work_position_in_the_active_system_with_its_name() {
    let mut c = common::open("pages-pos-g55");
    common::mdi(&mut c, "G10 L2 P2 X100 Y20 Z-50");
    common::mdi(&mut c, "G55 G0 X5 Y6 Z7");
    keys(&mut c, &["Ctrl+P"]);
    assert!(
        pos_line(&c, "WORK").contains("WORK G55"),
        "{}",
        c.frame_text()
    );
    let x = pos_line(&c, "X ");
    let cols: Vec<&str> = x.split_whitespace().collect();
    assert_eq!(cols[1], "5.000", "WORK X in G55: {x}");
    assert_eq!(cols[3], "105.000", "MACH X: {x}");
    let z = pos_line(&c, "Z ");
    assert_eq!(z.split_whitespace().nth(1), Some("7.000"), "{z}");
    // G92 shifts the work position further and is named beside the system.
    keys(&mut c, &["Ctrl+P"]);
    common::mdi(&mut c, "G92 X0");
    keys(&mut c, &["Ctrl+P"]);
    assert!(
        pos_line(&c, "G55+G92").contains("REL"),
        "{}",
        c.frame_text()
    );
    let x = pos_line(&c, "X ");
    assert_eq!(x.split_whitespace().nth(1), Some("0.000"), "{x}");
}

/// A tool length revised on OFS while a run is loaded is not in force until the next block
/// (the next run for a G-code run): POS shows the length in force and marks the revised one
/// as pending.
#[test]
fn pos_marks_a_revised_length_not_yet_in_force() {
    let mut c = common::open("pages-pos-pending");
    let path = temp_dir("pages-pos-pending-src").join("len.ngc");
    std::fs::write(
        &path,
        "G21 G90\nG10 L2 P1 Z-450\nG54\nT2 M6\nG43 H2\nG0 X10 Y20 Z20\nG1 Z-5 F300\nG0 Z20\nM30\n",
    )
    .unwrap();
    c.handle(PanelEvent::Op(novanc::panel_model::OpMode::Data));
    c.handle(PanelEvent::Data(novanc::panel_model::DataMode::Read));
    c.handle(PanelEvent::Tape(path));
    c.handle(PanelEvent::Start);
    c.handle(PanelEvent::Wait);
    c.handle(PanelEvent::Op(novanc::panel_model::OpMode::Single));
    // Single blocks until T02 is in the spindle and the run stands between blocks.
    for _ in 0..4 {
        c.handle(PanelEvent::Start);
        c.handle(PanelEvent::Wait);
        if c.status().tool == Some(2) {
            break;
        }
    }
    assert_eq!(c.status().tool, Some(2), "{}", c.frame_text());
    let old = c.magazine().tools.get(2).unwrap().set_length;
    keys(&mut c, &["Ctrl+O", "Down"]);
    type_line(&mut c, "155");
    assert_eq!(c.magazine().tools.get(2).unwrap().set_length, 155.0);
    keys(&mut c, &["Ctrl+P"]);
    let tool = pos_line(&c, "TOOL");
    assert!(
        tool.contains(&format!("T02 length {old:.3}")),
        "{}",
        c.frame_text()
    );
    assert!(
        pos_line(&c, "T02 155.000").contains("pending: next run"),
        "{}",
        c.frame_text()
    );
    // The run's end puts it in force; the mark goes.
    keys(&mut c, &["Ctrl+P"]);
    c.handle(PanelEvent::Op(novanc::panel_model::OpMode::Auto));
    c.handle(PanelEvent::Start);
    c.handle(PanelEvent::Wait);
    keys(&mut c, &["Ctrl+P"]);
    assert!(
        pos_line(&c, "TOOL").contains("T02 length 155.000"),
        "{}",
        c.frame_text()
    );
    assert!(!c.frame_text().contains("pending"), "{}", c.frame_text());
}

/// The tip readout (the panel's and the window's `tip Z`, `PanelView::tip_mm`) takes the tool
/// length POS's WORK Z takes: the tool file's with no run loaded (what the next run uses), the
/// one in force while a revised one is pending.
#[test]
fn the_tip_readout_uses_the_length_work_z_uses() {
    let mut c = common::open("pages-tip-length");
    common::mdi(&mut c, "T2 M6");
    assert_eq!(c.status().tool, Some(2), "{}", c.frame_text());
    let tip_and_work = |c: &mut Console| {
        keys(c, &["Ctrl+P"]);
        let z = pos_line(c, "Z ");
        let work: f64 = z.split_whitespace().nth(1).unwrap().parse().unwrap();
        keys(c, &["Ctrl+P"]);
        let v = c.view();
        (v.tip_mm[2], v.axis_mm[2], work)
    };
    // G54 is at machine zero: the work Z is the tip's machine Z.
    let (tip, axis, work) = tip_and_work(&mut c);
    let len = c.magazine().tools.get(2).unwrap().length();
    assert!((tip - (axis - len)).abs() < 1e-6 && (work - tip).abs() < 1e-3);
    keys(&mut c, &["Ctrl+O", "Down"]);
    type_line(&mut c, "155");
    keys(&mut c, &["Ctrl+O"]);
    let len = c.magazine().tools.get(2).unwrap().length();
    let (tip, axis, work) = tip_and_work(&mut c);
    assert!(
        (tip - (axis - len)).abs() < 1e-6,
        "tip Z {tip} with the revised length {len} at Z {axis}"
    );
    assert!((work - tip).abs() < 1e-3, "WORK Z {work}, tip Z {tip}");
}

/// OFS MEASURE: a work offset set so that the position here reads the value typed (touch-off),
/// and a tool's length set by touching its tip to a known height; both journaled.
#[test]
fn ofs_measure_sets_a_work_offset_and_a_tool_length_from_the_position() {
    let dir = temp_dir("pages-measure");
    {
        let mut c = open_in(&dir);
        common::mdi(&mut c, "G10 L2 P1 Z-450");
        common::mdi(&mut c, "T2 M6");
        common::mdi(&mut c, "G53 G0 X120 Y80 Z-300");
        assert_eq!(c.status().tool, Some(2), "{}", c.frame_text());
        keys(&mut c, &["Ctrl+O", "Down"]);
        // The tip touches a surface 50 mm above G54's zero: the gauge line is 100 above it.
        type_line(&mut c, "MEASURE Z50");
        assert_eq!(
            c.magazine().tools.get(2).unwrap().set_length,
            100.0,
            "{}",
            c.frame_text()
        );
        // Refusals change nothing and say why.
        let before = c.magazine();
        type_line(&mut c, "MEASURE X3");
        assert!(shows(&c, "OFS MEASURE refused"), "{}", c.frame_text());
        type_line(&mut c, "MEASURE Zq");
        assert!(shows(&c, "OFS MEASURE refused"), "{}", c.frame_text());
        keys(&mut c, &["Down"]);
        type_line(&mut c, "MEASURE Z1");
        assert!(
            shows(&c, "T03 is not in the spindle (T02 is)"),
            "{}",
            c.frame_text()
        );
        assert_eq!(c.magazine(), before);
        // X Y touch-off in G55 from a tool row, by name; then on its row, X alone.
        type_line(&mut c, "measure G55 X10 Y-5");
        assert!(shows(&c, "G55 X110.000 Y85.000"), "{}", c.frame_text());
        type_line(&mut c, "MEASURE X3");
        assert!(shows(&c, "G55 X117.000 Y85.000"), "{}", c.frame_text());
        keys(&mut c, &["Ctrl+O", "Ctrl+P"]);
        let z = pos_line(&c, "Z ");
        assert_eq!(z.split_whitespace().nth(1), Some("50.000"), "{z}");
    }
    let mut c = open_in(&dir);
    assert_eq!(c.magazine().tools.get(2).unwrap().set_length, 100.0);
    common::mdi(&mut c, "G55");
    keys(&mut c, &["Ctrl+P"]);
    assert!(
        pos_line(&c, "WORK").contains("WORK G55"),
        "{}",
        c.frame_text()
    );
}

/// MODAL (Ctrl-G) shows the G codes of every group in force, F, the work system, the tool in
/// the spindle and the switches; it follows MDI and the SINGLE BLOCK selector, and is read only.
#[test]
fn the_modal_page_shows_the_state_in_force_and_the_switches() {
    let mut c = common::open("pages-modal");
    common::mdi(&mut c, "G55 G91 G18 F250");
    keys(&mut c, &["Ctrl+G"]);
    assert_eq!(c.view().page, Page::Modal);
    let f = c.frame_text();
    for want in [
        "G18",
        "G91",
        "G55",
        "F250",
        "FEED OVR 100%",
        "SINGLE BLOCK off",
    ] {
        assert!(f.contains(want), "{want}:\n{f}");
    }
    // Turning the selector leaves the page (a script's word as the key; before stop 39 the
    // word left it up), so the page key brings it back.
    c.handle(PanelEvent::Op(novanc::panel_model::OpMode::Single));
    assert_eq!(c.view().page, Page::Mode);
    keys(&mut c, &["Ctrl+G", "Alt+-"]);
    let f = c.frame_text();
    assert!(f.contains("SINGLE BLOCK ON"), "{f}");
    assert!(f.contains("FEED OVR 90%"), "{f}");
    type_line(&mut c, "G54");
    assert!(
        shows(&c, "MODAL: the state is read only"),
        "{}",
        c.frame_text()
    );
    keys(&mut c, &["Ctrl+G"]);
    assert_eq!(c.view().page, Page::Mode);
}

/// The machine time one STEP increment of X takes (from the keys to the end of the move).
fn step_time(c: &mut Console) -> u64 {
    let t0 = c.status().machine_ns;
    keys(c, &["Right"]);
    c.handle(PanelEvent::Wait);
    c.status().machine_ns - t0
}

/// POS `JOG 100` selects the jog feed and `JOG RAPID` rapid jog: a STEP increment takes the
/// time of that feed; a value out of range is refused and changes nothing.
#[test]
fn pos_selects_the_jog_feed_and_rapid_jog() {
    let mut c = common::open("pages-jog");
    keys(&mut c, &["Alt+6"]);
    let normal = step_time(&mut c);
    keys(&mut c, &["Ctrl+P"]);
    type_line(&mut c, "JOG 100");
    assert!(shows(&c, "jog feed 100 mm/min"), "{}", c.frame_text());
    assert!(
        pos_line(&c, "JOG").starts_with("JOG 100 mm/min"),
        "{}",
        c.frame_text()
    );
    let slow = step_time(&mut c);
    assert!(
        slow >= 60_000_000 && slow > 2 * normal,
        "0.1 mm at 100 mm/min: {slow} ns, at 1000: {normal} ns"
    );
    type_line(&mut c, "JOG RAPID");
    assert!(shows(&c, "rapid jog: 12000 mm/min"), "{}", c.frame_text());
    assert!(
        pos_line(&c, "JOG").starts_with("JOG RAPID 12000"),
        "{}",
        c.frame_text()
    );
    let fast = step_time(&mut c);
    assert!(fast <= normal, "rapid {fast} ns, jog {normal} ns");
    type_line(&mut c, "JOG 0");
    assert!(shows(&c, "JOG refused"), "{}", c.frame_text());
    assert!(
        pos_line(&c, "JOG").starts_with("JOG RAPID"),
        "{}",
        c.frame_text()
    );
    type_line(&mut c, "JOG");
    assert!(shows(&c, "jog feed 100 mm/min"), "{}", c.frame_text());
    assert_eq!(c.status().pos[0], 300);
}

/// In a source-language run held in a feed, a length revised on OFS applies from the next
/// block: POS marks it `pending: next block` until that block starts, then shows it in force.
#[test]
fn pos_marks_a_length_revised_in_a_hold_until_the_next_block() {
    let mut c = common::open("pages-pos-next-block");
    keys(&mut c, &["Alt+2", "F9"]);
    c.handle(PanelEvent::WaitBlock(5));
    c.handle(PanelEvent::WaitMs(400));
    keys(&mut c, &["F10"]);
    c.handle(PanelEvent::Wait);
    let t = c.status().tool.expect("a tool in the spindle");
    let old = c.magazine().tools.get(t).unwrap().length();
    keys(&mut c, &["Ctrl+O"]);
    let set = c.magazine().tools.get(t).unwrap().set_length;
    type_line(&mut c, &format!("{:.3}", set + 0.5));
    assert!(shows(&c, "from the next block"), "{}", c.frame_text());
    keys(&mut c, &["Ctrl+P"]);
    assert!(
        pos_line(&c, "TOOL").contains(&format!("length {old:.3}")),
        "{}",
        c.frame_text()
    );
    assert!(
        pos_line(&c, &format!("T{t:02} {:.3}", old + 0.5)).contains("pending: next block"),
        "{}",
        c.frame_text()
    );
    let v = c.view();
    assert!(
        (v.tip_mm[2] - (v.axis_mm[2] - old)).abs() < 1e-6,
        "the tip readout takes the length in force, as WORK Z does"
    );
    let done = c.status().blocks_done;
    keys(&mut c, &["F9"]);
    // Until the next block has started, the run still going.
    for _ in 0..240 {
        if c.status().blocks_done > done {
            break;
        }
        c.handle(PanelEvent::WaitMs(250));
    }
    assert!(
        c.status().job.is_some() && c.status().blocks_done > done,
        "{done} {} {:?}\n{}",
        c.status().blocks_done,
        c.status().job.is_some(),
        c.frame_text()
    );
    assert!(!c.frame_text().contains("pending"), "{}", c.frame_text());
    assert!(
        pos_line(&c, "TOOL").contains(&format!("length {:.3}", old + 0.5)),
        "{}",
        c.frame_text()
    );
}

/// Issue 23, position memory: after a restart the machine position and the tool in the spindle
/// are where they were (they said X0 Y0 Z0 and no tool), and no reference return is asked for.
#[test]
fn a_restart_keeps_the_position_and_the_tool_in_the_spindle() {
    let dir = temp_dir("posmem-restart");
    let (pos, tool) = {
        let mut c = open_in(&dir);
        common::mdi(&mut c, "T2 M6");
        common::mdi(&mut c, "G0 X123.456 Y78.9");
        let st = c.status();
        assert_eq!(st.tool, Some(2));
        let keep = (st.pos, st.tool);
        c.finish().unwrap();
        keep
    };
    assert_eq!(pos[0], 123_456);
    let mut c = open_in(&dir);
    assert_eq!(c.status().pos, pos);
    assert_eq!(c.status().tool, tool);
    assert!(!shows(&c, "reference return"), "{}", c.frame_text());
    // AUTO runs at once (no reference return owed).
    keys(&mut c, &["Alt+2", "F9"]);
    assert!(!shows(&c, "START refused"), "{}", c.frame_text());
}

/// The jog feed chosen on POS is kept across a restart (in the position memory's file): the
/// console comes back with `JOG 100`, and a STEP takes that feed's time; then with rapid jog.
#[test]
fn the_jog_feed_is_kept_across_a_restart() {
    let dir = temp_dir("pages-jog-kept");
    {
        let mut c = open_in(&dir);
        keys(&mut c, &["Ctrl+P"]);
        type_line(&mut c, "JOG 100");
        assert!(shows(&c, "jog feed 100 mm/min"), "{}", c.frame_text());
        c.finish().unwrap();
    }
    let mut c = open_in(&dir);
    keys(&mut c, &["Alt+6", "Ctrl+P"]);
    assert!(
        pos_line(&c, "JOG").starts_with("JOG 100 mm/min"),
        "{}",
        c.frame_text()
    );
    let slow = step_time(&mut c);
    assert!(slow >= 60_000_000, "0.1 mm at 100 mm/min: {slow} ns");
    type_line(&mut c, "JOG RAPID");
    drop(c);
    let mut c = open_in(&dir);
    keys(&mut c, &["Ctrl+P"]);
    assert!(
        pos_line(&c, "JOG").starts_with("JOG RAPID 12000"),
        "{}",
        c.frame_text()
    );
    // `JOG` goes back from rapid jog to the feed kept with it.
    type_line(&mut c, "JOG");
    assert!(shows(&c, "jog feed 100 mm/min"), "{}", c.frame_text());
}

/// Every key that acts on a page is in the recording's `/panel/event` once, whether the
/// terminal pressed it or a script's `key NAME` gave it: a replay types the same revision.
/// Before stop 39 the terminal's keys on a page (the data keys, INPUT) were not recorded at
/// all, and a script's page key twice.
#[test]
fn the_keys_typed_on_a_page_are_recorded_once_each() {
    for script in [false, true] {
        let dir = common::temp_dir(&format!("page-keys-rec-{script}"));
        let rec = dir.join("r.mcap");
        let mut cfg = ConsoleConfig::new(dir.join("state"));
        cfg.clock = ClockMode::Virtual;
        cfg.record = Some(rec.clone());
        let mut c = Console::open(cfg).unwrap().0;
        let keys = [
            Key::Ctrl('o'),
            Key::Char('5'),
            Key::Enter,
            Key::F(8),
            Key::Alt('c'),
        ];
        for k in keys {
            if script {
                c.handle(PanelEvent::Press(k));
            } else {
                c.press(k);
            }
        }
        c.finish().unwrap();
        let events: Vec<String> = common::recorded(&rec, "/panel/event")
            .into_iter()
            .map(|(_, e)| e)
            .collect();
        let want: Vec<String> = ["Ctrl+o", "5", "Enter", "F8", "Alt+c"]
            .iter()
            .map(|k| format!("{{\"event\":\"key {k}\"}}"))
            .collect();
        assert_eq!(events, want, "script {script}");
    }
}

/// Every key of the terminal in every position of the operation selector, on every page, with
/// a program run loaded and without: the display changes (what the key did, or the message
/// that says why not) or the help comes up; none is dropped in silence. A page's cursor key at
/// its end, and RUBOUT or EOB with nothing typed, are silent and right so.
#[test]
fn every_key_in_every_mode_and_page_acts_or_says_why() {
    use novanc::panel_model::{DataMode, OpMode};
    let mut c = common::open("every-key");
    let keys = common::all_keys();
    let pages = [
        None,
        Some('p'),
        Some('d'),
        Some('o'),
        Some('e'),
        Some('g'),
        Some('t'),
        Some('u'),
    ];
    let mut silent = Vec::new();
    for running in [false, true] {
        for m in OpMode::ALL {
            for p in pages {
                for &k in &keys {
                    c.handle(PanelEvent::Reset);
                    c.handle(PanelEvent::Op(m));
                    if running {
                        c.handle(PanelEvent::Op(OpMode::Single));
                        c.handle(PanelEvent::Start);
                        c.handle(PanelEvent::Wait);
                        c.handle(PanelEvent::Op(m));
                    }
                    if let Some(pk) = p {
                        c.press(Key::Ctrl(pk));
                    }
                    let before = c.view();
                    let typed = !before.entry.is_empty();
                    c.press(k);
                    // Machine time passes (virtual: nothing moves between two keys otherwise).
                    c.handle(PanelEvent::WaitMs(20));
                    let v = c.view();
                    assert!(v.display.iter().all(|l| l.chars().count() == 40));
                    let at_end = p.is_some() && novanc::console::keys::is_cursor_key(k);
                    let nothing_typed = matches!(k, Key::Backspace | Key::Enter) && !typed;
                    // A selector key for the position it is at: the selector does not move.
                    let same = matches!(k, Key::Alt(d) if OpMode::ALL.get((d as usize).wrapping_sub('1' as usize)) == Some(&m))
                        || matches!(k, Key::F(n @ 1..=7) if DataMode::ALL[n as usize - 1] == before.data_mode);
                    if v == before
                        && !same
                        && c.message().is_empty()
                        && !c.help_shown()
                        && !at_end
                        && !nothing_typed
                    {
                        silent.push(format!("{k:?} in {m:?} page {p:?} running {running}"));
                    }
                    if c.help_shown() {
                        c.press(Key::F(8));
                        c.press(Key::F(8));
                    }
                }
            }
        }
    }
    assert!(
        silent.is_empty(),
        "{} keys changed nothing and said nothing:\n{}",
        silent.len(),
        silent.join("\n")
    );
}

/// A selector turned leaves a page whether a key or a script's `op`/`data` word turned it, as
/// the lathe's does (a script's `op AUTO` left the PROG page up before stop 39).
#[test]
fn a_selector_turned_by_a_script_leaves_the_page() {
    use novanc::panel_model::{DataMode, OpMode};
    let mut c = common::open("script-turn-page");
    for ev in [
        PanelEvent::Op(OpMode::Auto),
        PanelEvent::Op(OpMode::Data),
        PanelEvent::Data(DataMode::Mdi),
    ] {
        c.press(Key::Ctrl('d'));
        assert_eq!(c.view().page, Page::Prog);
        c.handle(ev.clone());
        assert_eq!(c.view().page, Page::Mode, "{ev:?}");
    }
}

/// A page's refused INPUT stays on the entry line beside the reason, whatever words the
/// reason uses, and an INPUT that acts clears it. Before stop 46 the centre kept a page's line
/// only when its reason contained "refused": `PARTS many` or `Q7` on POS, a bad MACRO value, a
/// line on the read-only MSG page were dropped.
#[test]
fn a_page_keeps_every_line_it_refuses() {
    let mut c = common::open("pages-kept");
    let refused = [
        ("Ctrl+P", "Q7", "POS: type X"),
        ("Ctrl+P", "PARTS many", "PARTS takes a whole number"),
        ("Ctrl+P", "X1e9", "is not a position in mm"),
        ("Ctrl+P", "JOG 0", "JOG refused"),
        ("Ctrl+E", "G55", "MSG: the history is read only"),
        ("Ctrl+G", "G55", "MODAL: the state is read only"),
        ("Ctrl+T", "P99 ON", "I/O: refused"),
        ("Ctrl+O", "1.2.3", "OFS refused"),
        ("Ctrl+D", "X NAME", "PROG refused"),
    ];
    for (page, line, why) in refused {
        // A page key shows its page, or, pressed on it, goes back to the mode display.
        let shown = c.view().page;
        keys(&mut c, &[page]);
        if c.view().page == Page::Mode {
            assert_ne!(shown, Page::Mode);
            keys(&mut c, &[page]);
        }
        type_line(&mut c, line);
        assert!(
            c.message().contains(why),
            "{page} '{line}': {:?}\n{}",
            c.message(),
            c.frame_text()
        );
        assert_eq!(c.view().entry, line, "{page}: the refused line stays");
    }
    // A line that acts leaves the entry line empty.
    keys(&mut c, &["Ctrl+P"]);
    assert_eq!(c.view().page, Page::Pos);
    type_line(&mut c, "PARTS 3");
    assert!(shows(&c, "parts 3"), "{}", c.frame_text());
    assert_eq!(c.view().entry, "");
}
