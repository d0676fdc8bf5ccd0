//! Regression tests for the operator sequences of "The core owns the run", each by its keys as
//! the issue reproduced it, through the same `Console` the terminal drives (virtual time). Every
//! block end is checked against its programmed point (`common::audit`).

mod common;

use common::{audit, keys, open, p, shows, type_line};
use novanc::panel_model::PanelEvent as E;
use novanc::pulse_core::EndCause;

/// Defect 1: Hold and resume after a finished run: the second START runs the program from the top
/// once; a hold and resume in its BOR does not run anything twice or shift the rest.
#[test]
fn hold_and_resume_after_a_finished_run_shifts_nothing() {
    let mut c = open("defect1");
    keys(&mut c, &["Alt+2", "F9"]);
    c.handle(E::Wait);
    let first = audit(&c);
    assert_eq!(first.len(), 101);
    assert!(shows(&c, "program end: 101 blocks"));
    keys(&mut c, &["F9"]);
    c.handle(E::WaitBlock(5));
    assert!(shows(&c, ">N5 G01 Z-265.000 F60"), "{}", c.frame_text());
    keys(&mut c, &["F10"]);
    c.handle(E::Wait);
    assert!(c.status().hold);
    keys(&mut c, &["F9"]);
    c.handle(E::Wait);
    let second = audit(&c);
    let seqs: Vec<u32> = second.iter().map(|e| e.seq).collect();
    assert_eq!(
        seqs,
        (1..=101).collect::<Vec<_>>(),
        "each block once, in order"
    );
    let tap = second.iter().find(|e| e.seq == 36).unwrap();
    assert_eq!(tap.end[2], p(-316.0), "the M8 tap's bottom");
    assert!(shows(&c, "program end: 101 blocks"));
    assert_eq!(c.status().last_end.as_ref().map(|e| e.id), Some(2));
}

/// Defect 1, in MDI: Run an MDI drilling to its end, run it again, hold and resume in the G01: the hole
/// is drilled once and the run ends at Z0 after its `G00 Z0.000`.
#[test]
fn mdi_hold_and_resume_after_a_finished_run() {
    let mut c = open("defect1mdi");
    keys(&mut c, &["Alt+4", "F7"]);
    type_line(&mut c, "IDRL, 105/DP20, FR60/(220, 20, -450)");
    assert_eq!(c.frame_text().lines().last(), Some("> _"));
    keys(&mut c, &["Alt+3", "F9"]);
    c.handle(E::Wait);
    assert_eq!(audit(&c).len(), 9);
    keys(&mut c, &["F9"]);
    // T04 is in the spindle and the tool above the hole: spindle, down, then the feed, N3.
    c.handle(E::WaitBlock(3));
    assert!(shows(&c, ">N3 G01 Z-330.000 F60"), "{}", c.frame_text());
    c.handle(E::WaitMs(2000));
    keys(&mut c, &["F10"]);
    c.handle(E::Wait);
    keys(&mut c, &["F9"]);
    c.handle(E::Wait);
    let run = audit(&c);
    let n = run.len() as u32;
    assert_eq!(
        run.iter().map(|e| e.seq).collect::<Vec<_>>(),
        (1..=n).collect::<Vec<_>>()
    );
    assert_eq!(
        run.iter().filter(|e| e.end[2] == p(-330.0)).count(),
        1,
        "drilled once"
    );
    assert_eq!(c.status().pos[2], 0, "ends at Z0 after G00 Z0.000");
    assert!(shows(&c, &format!("program end: {n} blocks")));
}

/// Defect 2: MDI `GO` puts the tip of the tool in the spindle where the statement says.
#[test]
fn mdi_go_positions_the_tip_of_the_tool_in_the_spindle() {
    let mut c = open("defect2");
    keys(&mut c, &["Alt+4", "F7"]);
    type_line(&mut c, "IDRL, 105/DP20, FR60/(220, 20, -450)");
    keys(&mut c, &["Alt+3", "F9"]);
    c.handle(E::Wait);
    assert_eq!(c.status().tool, Some(4));
    assert_eq!(c.status().tool_set_length, 140.0);
    keys(&mut c, &["Alt+4", "F7"]);
    type_line(&mut c, "0LKIGO, 500, 300, -200");
    keys(&mut c, &["Alt+3", "F9"]);
    c.handle(E::Wait);
    audit(&c);
    let pos = c.status().pos;
    assert_eq!(pos, [p(500.0), p(300.0), p(-200.0 + 140.0)], "tip at -200");
    assert!((c.view().tip_mm[2] + 200.0).abs() < 1e-9);
}

/// Defect 3: SEARCH with another tool in the spindle: the run changes to the statement's tool and
/// never puts the tip below what the program commands; no X Y rapid below machine zero Z
/// before the statement's own approach.
#[test]
fn search_restores_for_the_tool_in_the_spindle() {
    let mut c = open("defect3");
    keys(&mut c, &["Alt+7"]);
    for _ in 0..4 {
        keys(&mut c, &["F9"]);
        c.handle(E::Wait);
    }
    assert_eq!(c.status().tool, Some(1), "T01 (220 mm) in the spindle");
    assert_eq!(
        c.status().pos,
        [p(350.0), p(130.0), p(-255.0)],
        "down at the bore"
    );
    keys(&mut c, &["F11", "Alt+4", "F1"]);
    type_line(&mut c, "DRL, 105");
    assert!(shows(&c, "AUTO starts at line 8"), "{}", c.frame_text());
    assert!(shows(&c, "G00 Z0.000"), "{}", c.frame_text());
    audit(&c);
    keys(&mut c, &["Alt+2", "F9"]);
    c.handle(E::Wait);
    let run = audit(&c);
    assert!(c.status().alarm.is_none(), "{:?}", c.status().alarm);
    // The first block raises Z to machine zero; the tool change to T04 follows.
    assert_eq!(run[0].end[2], 0);
    let lowest_tip = -470.0; // DRL 105: surface -455, DP15
    let t04 = p(140.0);
    let t01 = p(220.0);
    for e in &run {
        let set = if e.seq == 0 { t01 } else { t04 };
        assert!(
            e.pos[2] - set >= p(lowest_tip),
            "N{}: tip {}",
            e.seq,
            e.pos[2] - set
        );
    }
    assert!(shows(&c, "program end"));
}

/// Defect 4: E-STOP, STOP and RESET act while the help screen is up.
#[test]
fn the_relay_panel_acts_on_the_help_screen() {
    let mut c = open("defect4");
    keys(&mut c, &["Alt+2", "F9"]);
    c.handle(E::WaitMs(6000));
    assert!(c.status().moving || c.status().in_block);
    keys(&mut c, &["F8"]);
    assert!(c.view().help != 0);
    keys(&mut c, &["F12"]);
    assert!(c.status().estop, "E-STOP acted");
    assert!(c.view().help == 0);
    keys(&mut c, &["F11", "F9"]);
    c.handle(E::WaitMs(6000));
    keys(&mut c, &["F8", "F10"]);
    assert!(c.status().hold, "STOP acted");
    keys(&mut c, &["F8", "F11"]);
    assert!(c.status().job.is_none(), "RESET acted");
    // Issue 23: a key that closes the help also acts.
    keys(&mut c, &["F8", "F9"]);
    assert!(
        c.view().help == 0 && c.status().job.is_some(),
        "START closes the help and starts"
    );
}

/// Defect 5: A jog between single blocks: START returns to where the run stopped before the next
/// block, and the display says so until it does.
#[test]
fn a_jog_between_single_blocks_is_undone_before_the_next_block() {
    let mut c = open("defect5");
    keys(&mut c, &["Alt+7", "F9"]);
    c.handle(E::Wait);
    keys(&mut c, &["F9"]);
    c.handle(E::Wait);
    assert_eq!(c.status().pos[0], p(350.0));
    keys(&mut c, &["Alt+6"]);
    for _ in 0..10 {
        keys(&mut c, &["Right"]);
        c.handle(E::Wait);
    }
    assert_eq!(c.status().pos[0], p(351.0));
    keys(&mut c, &["Alt+2"]);
    assert!(
        shows(
            &c,
            "JOGGED X+1.000: START returns to X350.000 Y130.000 Z0.000 first"
        ),
        "{}",
        c.frame_text()
    );
    keys(&mut c, &["F9"]);
    c.handle(E::Wait);
    let run = audit(&c);
    let bore = run.iter().find(|e| e.seq == 5).unwrap();
    assert_eq!(bore.pos[0], p(350.0), "the bore is cut at X350");
    assert!(!shows(&c, "JOGGED"));
    assert!(shows(&c, "program end: 101 blocks"));
}

/// Defect 6: While the terminal is too small every key but the relay panel is ignored, and the
/// notice says so.
#[test]
fn keys_do_not_act_while_the_terminal_is_too_small() {
    let mut c = open("defect6");
    let before = c.program_text();
    c.set_screen_fits(false);
    keys(&mut c, &["Alt+4", "F3", "L", "K", "Enter", "Alt+2", "F9"]);
    assert_eq!(c.program_text(), before, "program memory unchanged");
    assert!(c.status().job.is_none(), "nothing started");
    assert_eq!(
        c.view().ignored.as_deref(),
        Some("key F9 ignored: the terminal is too small")
    );
    keys(&mut c, &["F12"]);
    assert!(c.status().estop, "E-STOP acts");
    c.set_screen_fits(true);
    assert!(c.view().ignored.is_none());
}

/// Each run reports its own end with its own block count and machine time, also the second.
#[test]
fn each_run_reports_its_own_end() {
    let mut c = open("ends");
    keys(&mut c, &["Alt+4", "F7"]);
    type_line(&mut c, "IDRL, 105/DP20, FR60/(220, 20, -450)");
    keys(&mut c, &["Alt+3", "F9"]);
    c.handle(E::Wait);
    let first = c.status().last_end.clone().unwrap();
    let msg1 = c.frame_text();
    c.handle(E::WaitMs(30_000));
    keys(&mut c, &["F9"]);
    assert!(!shows(&c, "program end"), "the old end is not shown again");
    c.handle(E::Wait);
    let second = c.status().last_end.clone().unwrap();
    assert_eq!((first.id, second.id), (1, 2));
    assert_eq!(second.blocks, 7);
    assert_eq!(second.cause, EndCause::ProgramEnd);
    // The second run starts with T04 already in the spindle: no tool change, so it is shorter,
    // and its time does not include the first run's or the 30 s between them.
    assert!(
        second.machine_ns < first.machine_ns,
        "{second:?} vs {first:?}"
    );
    let want = format!(
        "program end: 7 blocks in {:.1} s",
        second.machine_ns as f64 / 1e9
    );
    assert!(shows(&c, &want), "{}\nfirst:\n{msg1}", c.frame_text());
}

/// One RESET after E-STOP clears the alarm, and START works at once; the lamp and START agree.
/// E-STOP is said once on the message line, as its alarm: before stop 41 the line read
/// `EMERGENCY STOP: pulses stopped; press RESET / ALARM EMERGENCY STOP: pulses stopped; press
/// RESET` (what the machine does, then the same words as the alarm).
#[test]
fn one_reset_clears_an_emergency_stop() {
    let mut c = open("estop");
    keys(&mut c, &["Alt+2", "F9"]);
    c.handle(E::WaitMs(5000));
    keys(&mut c, &["F12"]);
    assert!(c.view().lamps.alarm && c.view().lamps.estop);
    let f = c.frame_text();
    assert_eq!(f.matches("EMERGENCY STOP").count(), 1, "{f}");
    assert!(f.contains("ALARM EMERGENCY STOP: pulses stopped;"), "{f}");
    keys(&mut c, &["F9"]);
    assert!(
        c.status().job.is_none(),
        "START refused while the lamp is lit"
    );
    keys(&mut c, &["F11"]);
    assert!(!c.view().lamps.alarm && !c.view().lamps.estop);
    keys(&mut c, &["F9"]);
    assert!(
        c.status().job.is_some() && c.status().run == 1,
        "START works"
    );
}

/// A translation alarm clears when the program is fixed, without a START.
#[test]
fn a_program_alarm_clears_when_the_program_is_fixed() {
    let mut c = open("alarmfix");
    keys(&mut c, &["Alt+4", "F3"]);
    type_line(&mut c, "CDP35$DP0");
    keys(&mut c, &["Alt+2", "F9"]);
    assert!(c.view().lamps.alarm);
    assert!(
        shows(&c, "START refused, nothing moved: line 3"),
        "{}",
        c.frame_text()
    );
    assert_eq!(c.status().pos, [0, 0, 0]);
    keys(&mut c, &["Alt+4", "F3"]);
    assert!(c.view().lamps.alarm, "still in error on every page");
    type_line(&mut c, "0LCDP0$DP35");
    assert!(!c.view().lamps.alarm, "fixed: {}", c.frame_text());
    assert!(c.program_alarm().is_none());
}

/// After RESET and SEARCH the AUTO page shows what START will run; the MDI page shows the MDI
/// buffer, not the last AUTO statement.
#[test]
fn the_run_page_shows_what_start_will_run() {
    let mut c = open("runpage");
    keys(&mut c, &["Alt+2", "F9"]);
    c.handle(E::WaitMs(20_000));
    keys(&mut c, &["F11", "Alt+4", "F1"]);
    type_line(&mut c, "8");
    keys(&mut c, &["Alt+2"]);
    let first = c.frame_text().lines().next().unwrap_or("").to_string();
    assert_eq!(first, "TABLEB from line 8: press START");
    keys(&mut c, &["Alt+3"]);
    let first = c.frame_text().lines().next().unwrap_or("").to_string();
    assert_eq!(first, "MDI buffer: press START");
    assert!(!shows(&c, "BOR"), "{}", c.frame_text());
}

/// A long message wraps; a line that is cut ends with the mark.
#[test]
fn long_messages_wrap_and_cut_lines_are_marked() {
    let mut c = open("wrap");
    keys(&mut c, &["Alt+4", "F3"]);
    type_line(&mut c, "SDA1, P1$-1DI9");
    keys(&mut c, &["Alt+2"]);
    assert!(
        c.frame_text().contains("(P2(0,30)=P3), …"),
        "a cut program line is marked: {}",
        c.frame_text()
    );
    keys(&mut c, &["F9"]);
    let text = c.frame_text();
    assert!(
        shows(&c, "is not defined (define it on an earlier line)"),
        "{text}"
    );
    for l in text.lines() {
        assert!(l.chars().count() <= 40);
    }
}

/// A START pressed in SINGLE BLOCK during the tool change is refused with a message.
#[test]
fn start_during_a_single_block_tool_change_says_why() {
    let mut c = open("sbstart");
    keys(&mut c, &["Alt+7", "F9"]);
    c.handle(E::WaitMs(1000));
    keys(&mut c, &["F9"]);
    assert!(
        shows(
            &c,
            "START ignored: N1 is still executing; press START again when it stops"
        ),
        "{}",
        c.frame_text()
    );
    c.handle(E::Wait);
    assert_eq!(audit(&c).len(), 1, "exactly one block");
}

/// Found by the operator-sequence test: a CONTINUOUS tap right after a refused action (which
/// left the core's notice set) was taken as refused and never released, so the axis ran to its
/// travel limit. A tap now moves one increment (0.1 mm by default), whatever came before.
#[test]
fn a_continuous_tap_after_a_refused_action_stops() {
    let mut c = open("tapnotice");
    keys(&mut c, &["Alt+7", "F9", "F9"]);
    assert!(shows(&c, "START ignored"), "{}", c.frame_text());
    c.handle(E::Wait);
    let z = c.status().pos[2];
    keys(&mut c, &["Alt+1", "PgDn"]);
    c.handle(E::Wait);
    let moved = z - c.status().pos[2];
    assert_eq!(moved, p(0.1), "the tap moved {moved} pulses");
}

/// Issue 23: SINGLE BLOCK, START three times, then AUTO while N3 (`S400 M03`) executes: the
/// block START was pressed for completes and the run stops; START then continues in AUTO. The
/// screen says "press START" only while the machine stands waiting for it.
#[test]
fn auto_during_a_single_block_stops_after_it_until_start() {
    let mut c = open("sbauto");
    keys(&mut c, &["Alt+7", "F9"]);
    c.handle(E::Wait);
    keys(&mut c, &["F9"]);
    c.handle(E::Wait);
    keys(&mut c, &["F9"]);
    c.handle(E::WaitBlock(3));
    assert!(shows(&c, ">N3 S400 M03"), "{}", c.frame_text());
    assert!(c.status().in_block, "N3 is executing");
    keys(&mut c, &["Alt+2"]);
    assert!(
        !shows(&c, "press START"),
        "N3 still executes: {}",
        c.frame_text()
    );
    c.handle(E::Wait);
    let run = audit(&c);
    assert_eq!(
        run.iter().map(|e| e.seq).collect::<Vec<_>>(),
        vec![1, 2, 3],
        "nothing after N3 without START"
    );
    assert_eq!(c.status().pos[2], 0, "Z has not come down (N4)");
    assert!(shows(&c, "press START"), "{}", c.frame_text());
    keys(&mut c, &["F9"]);
    c.handle(E::Wait);
    assert!(shows(&c, "program end: 101 blocks"), "{}", c.frame_text());
    assert!(!shows(&c, "press START to continue"), "{}", c.frame_text());
}

/// Issue 23: during the return after a manual intervention the HOLD lamp is out (the machine
/// moves), and neither "returning" nor "START ignored" outlives what it describes.
#[test]
fn the_return_and_start_ignored_do_not_outlive_what_they_describe() {
    let mut c = open("retlamp");
    keys(&mut c, &["Alt+7"]);
    for _ in 0..4 {
        keys(&mut c, &["F9"]);
        c.handle(E::Wait);
    }
    assert_eq!(c.status().pos[2], p(-255.0), "N4 down");
    keys(&mut c, &["Alt+6"]);
    for _ in 0..30 {
        keys(&mut c, &["PgUp"]);
        c.handle(E::Wait);
    }
    assert_eq!(c.status().pos[2], p(-252.0));
    keys(&mut c, &["Alt+7", "F9"]);
    c.handle(E::WaitMs(50));
    assert!(c.status().moving, "the return is under way");
    assert!(
        c.status().job.as_ref().is_some_and(|j| j.returning),
        "returning"
    );
    let v = c.view();
    assert!(!v.lamps.hold, "HOLD lamp lit while Z feeds back down");
    assert!(v.lamps.run);
    assert!(!c.frame_text().contains(" HOLD"), "{}", c.frame_text());
    assert!(shows(&c, "returning"), "{}", c.frame_text());
    c.handle(E::WaitBlock(5));
    assert!(c.status().job.as_ref().is_some_and(|j| !j.returning));
    assert!(!shows(&c, "returning"), "{}", c.frame_text());
    // START while N5 executes is ignored; the note goes with N5.
    keys(&mut c, &["F9"]);
    assert!(shows(&c, "START ignored"), "{}", c.frame_text());
    c.handle(E::Wait);
    assert!(!c.status().in_block);
    assert!(!shows(&c, "START ignored"), "{}", c.frame_text());
}

/// Issue 23: a key that closes the help screen also acts.
#[test]
fn a_key_that_closes_help_also_acts() {
    let mut c = open("helpkey");
    keys(&mut c, &["Alt+4", "F3", "F8", "L"]);
    assert!(!c.help_shown());
    assert_eq!(c.view().entry, "L", "the letter is typed");
    keys(&mut c, &["F8", "F8", "K"]);
    assert!(!c.help_shown());
    assert_eq!(c.view().entry, "LK");
    keys(&mut c, &["F8", "Alt+2"]);
    assert_eq!(c.view().op_mode, novanc::panel_model::OpMode::Auto);
}

/// Issue 23: a key that does nothing in this mode says so.
#[test]
fn a_key_that_does_nothing_says_so() {
    let mut c = open("deadkeys");
    // (In DATA INPUT, Delete is the editor's: docs/editor.md, "Cursor keys".)
    for (mode, k) in [("Alt+2", "Delete"), ("Alt+2", "Tab"), ("Alt+4", "Tab")] {
        keys(&mut c, &[mode, k]);
        assert!(
            shows(&c, &format!("key {k} does nothing")),
            "{k}: {}",
            c.frame_text()
        );
    }
}

/// Issue 23: a value typed on OFS while the machine moves is kept on the entry line with the
/// reason; INPUT once at rest applies it.
#[test]
fn an_ofs_value_refused_while_moving_stays_on_the_entry_line() {
    let mut c = open("ofsmove");
    keys(&mut c, &["Alt+2", "F9"]);
    c.handle(E::WaitMs(6000));
    assert!(c.status().moving);
    keys(&mut c, &["Ctrl+o", "Down", "1", "5", "5", "Enter"]);
    assert!(shows(&c, "OFS refused"), "{}", c.frame_text());
    assert_eq!(c.view().entry, "155", "the value is kept");
    assert!(shows(&c, "> 155_"), "{}", c.frame_text());
    keys(&mut c, &["F10"]);
    c.handle(E::Wait);
    keys(&mut c, &["Enter"]);
    assert_eq!(c.view().entry, "");
    assert!(shows(&c, "T02 LEN 155.000"), "{}", c.frame_text());
}

/// Found by the operator-sequence test's screen check (issue 23): after a START ignored, a
/// feed override key showed the core's old notice again, and it stayed after the run ended.
#[test]
fn an_override_does_not_bring_back_an_old_notice() {
    let mut c = open("noticeback");
    keys(&mut c, &["Alt+2", "F9", "F9"]);
    assert!(shows(&c, "START ignored"), "{}", c.frame_text());
    keys(&mut c, &["Alt+="]);
    assert!(!shows(&c, "START ignored"), "{}", c.frame_text());
    c.handle(E::WaitBlock(3));
    assert!(!shows(&c, "START ignored"), "{}", c.frame_text());
}

/// Issue 23, key-to-screen time: the terminal saves the counters a run's end changes after it
/// has written the frame (RESET's answer is not held up by the disk), and they are saved then,
/// or at the session's end at the latest.
#[test]
fn the_terminal_saves_the_counters_after_the_frame() {
    let mut c = open("aftersave");
    let dir = c.config().state_dir.clone();
    let file = dir.join(novanc::store::history::COUNTERS);
    let read = || std::fs::read_to_string(&file).unwrap_or_default();
    c.set_saves_after_frame(true);
    keys(&mut c, &["Alt+2", "F9"]);
    c.handle(E::WaitMs(5000));
    let before = read();
    keys(&mut c, &["F11"]);
    assert_eq!(read(), before, "not yet: the frame comes first");
    c.frame_written();
    let after = read();
    assert_ne!(after, before, "the run's time is counted and saved");
    keys(&mut c, &["F9"]);
    c.handle(E::WaitMs(5000));
    keys(&mut c, &["F11"]);
    let _ = c.finish();
    assert_ne!(read(), after, "saved at the end of the session");
}

/// E-STOP during the reference return (HOME) stops the axes there: the return has no run to
/// abandon, and it went on moving to machine zero after E-STOP (found by the operator-sequence
/// test's E-STOP in every state).
#[test]
fn estop_during_home_stops_the_reference_return() {
    let mut c = open("estop-home");
    common::mdi(&mut c, "G53 G0 X300 Y200 Z-100");
    assert_eq!(c.status().machine_pos, [p(300.0), p(200.0), p(-100.0)]);
    keys(&mut c, &["Alt+0"]);
    assert!(shows(&c, "HOME: reference return"), "{}", c.frame_text());
    c.handle(E::WaitMs(100));
    assert!(c.status().moving, "HOME moves");
    keys(&mut c, &["F12"]);
    let at = c.status().machine_pos;
    c.handle(E::WaitMs(2000));
    assert_eq!(c.status().machine_pos, at, "an axis moved after E-STOP");
    assert!(!c.status().moving && c.status().estop);
}

/// A program's `(MSG,...)` (the operator message of Fanuc's #3006 kind) lives until it is
/// acknowledged: other keys (an override, a page, a mode, a stray letter) leave it on the
/// message line; Esc acknowledges it, and so does RESET.
#[test]
fn a_program_message_stays_until_acknowledged() {
    let mut c = open("msg-ack");
    common::mdi(&mut c, "G0 X10 (MSG, check the vise)");
    assert!(shows(&c, "MSG: check the vise"), "{}", c.frame_text());
    for k in ["Alt+=", "Ctrl+P", "Ctrl+P", "Alt+2", "x", "F8", "F9"] {
        keys(&mut c, &[k]);
        c.handle(E::Wait);
        assert!(
            shows(&c, "MSG: check the vise"),
            "gone after {k}:\n{}",
            c.frame_text()
        );
    }
    keys(&mut c, &["Esc"]);
    assert!(!shows(&c, "MSG: check the vise"), "{}", c.frame_text());
    keys(&mut c, &["Esc"]);
    assert!(shows(&c, "no message to acknowledge"), "{}", c.frame_text());
    common::mdi(&mut c, "G0 X20 (MSG, turn the part)");
    keys(&mut c, &["Alt+-"]);
    assert!(shows(&c, "MSG: turn the part"), "{}", c.frame_text());
    keys(&mut c, &["F11"]);
    assert!(
        !shows(&c, "MSG: turn the part"),
        "RESET acknowledges it\n{}",
        c.frame_text()
    );
}

/// A full entry line refuses the next key and says so on every console and every screen that
/// types (stop 41: the centre's pages dropped the 241st key in silence, while DATA INPUT, MDI
/// and the lathe said it): no key is lost without a word.
#[test]
fn a_full_entry_line_says_so_wherever_the_data_keys_type() {
    use novanc::lathe::console::LatheConsole;
    use novanc::lathe::desc::LatheDesc;
    use novanc::panel_model::OpMode;
    use novanc_panel::Key;
    const FULL: &str = "the command line is full (240 characters)";
    // The centre: DATA INPUT, MDI and the OFS page.
    for (name, setup) in [
        ("data", vec![]),
        ("mdi", vec![E::Op(OpMode::Mdi)]),
        ("ofs page", vec![E::Press(Key::Ctrl('o'))]),
    ] {
        let mut c = open(&format!("full-entry-{}", name.replace(' ', "-")));
        for ev in setup {
            c.handle(ev);
        }
        for _ in 0..240 {
            c.press(Key::Char('1'));
        }
        assert_eq!(c.view().entry.len(), 240, "{name}");
        assert_ne!(c.message(), FULL, "{name}");
        c.press(Key::Char('2'));
        assert_eq!(c.view().entry, "1".repeat(240), "{name}");
        assert_eq!(c.message(), FULL, "{name}");
    }
    // The lathe: MDI and its OFS page.
    for (name, page) in [("mdi", false), ("ofs", true)] {
        let dir = common::temp_dir(&format!("full-entry-lathe-{name}"));
        let mut c = LatheConsole::open(LatheDesc::citizen(), &dir, 20, 60, None)
            .unwrap_or_else(|e| panic!("{e}"))
            .0;
        c.handle(E::Op(OpMode::Mdi));
        if page {
            c.press(Key::Ctrl('o'));
        }
        for _ in 0..241 {
            c.press(Key::Char('1'));
        }
        assert_eq!(c.message(), FULL, "lathe {name}");
    }
}

/// A page key shows a screen and takes nothing back: the line being typed stays on the entry
/// line, on both machines (stop 41: the centre cleared it, the lathe kept it). A turn of the
/// selector still clears it, on both.
#[test]
fn a_page_key_keeps_the_line_being_typed_on_both_machines() {
    use novanc::lathe::console::LatheConsole;
    use novanc::lathe::desc::LatheDesc;
    use novanc::panel_model::OpMode;
    use novanc_panel::Key;
    let mut c = open("page-keeps-entry");
    c.handle(E::Op(OpMode::Mdi));
    c.handle(E::Key('X'));
    c.handle(E::Key('1'));
    for k in [Key::Ctrl('p'), Key::Ctrl('o'), Key::Ctrl('o')] {
        c.press(k);
        assert_eq!(c.view().entry, "X1", "after {k:?}");
    }
    c.handle(E::Op(OpMode::Auto));
    assert_eq!(c.view().entry, "");
    let dir = common::temp_dir("page-keeps-entry-lathe");
    let mut l = LatheConsole::open(LatheDesc::citizen(), &dir, 20, 60, None)
        .unwrap_or_else(|e| panic!("{e}"))
        .0;
    l.handle(E::Op(OpMode::Mdi));
    l.handle(E::Key('X'));
    l.handle(E::Key('1'));
    let entry = |l: &LatheConsole| l.view().display.last().unwrap().trim_end().to_string();
    for k in [Key::Ctrl('p'), Key::Ctrl('o'), Key::Ctrl('o')] {
        l.press(k);
        assert_eq!(entry(&l), "> X1", "after {k:?}: {}", l.frame_text());
    }
    l.handle(E::Op(OpMode::Auto));
    assert_eq!(entry(&l), ">");
}

/// Found by the random operator sequences (seed 1592591039, stop 43): a START ignored during a
/// block in SINGLE BLOCK was said again once the block had ended, when a switch was turned
/// (DRY RUN): the console forgot that it had shown the machine's notice, which the machine
/// keeps across a switch. The screen said START was ignored with the run standing still.
#[test]
fn a_switch_turned_does_not_bring_back_a_start_ignored() {
    let mut c = open("defect-notice");
    keys(&mut c, &["Alt+7", "F9"]);
    let mut ignored = false;
    for _ in 0..3 {
        keys(&mut c, &["F9"]);
        if shows(&c, "START ignored") {
            ignored = true;
            break;
        }
    }
    assert!(ignored, "{}", c.frame_text());
    c.handle(E::Wait);
    assert!(!c.status().in_block, "the block has ended");
    keys(&mut c, &["Alt+2", "Alt+d"]);
    assert!(shows(&c, "DRY RUN on"), "{}", c.frame_text());
    assert!(!shows(&c, "START ignored"), "{}", c.frame_text());
    keys(&mut c, &["Alt+d", "Alt+f"]);
    assert!(!shows(&c, "START ignored"), "{}", c.frame_text());
}

/// The screen says what moves with no run loaded, from the machine's state (stop 44): a jog,
/// STEP or handwheel move is `JOG: an axis moves by hand` (the centre said nothing), HOME's
/// return is HOME's words even once another key has cleared the message, and a jog after a
/// HOME stopped short by E-STOP is a jog, not HOME.
#[test]
fn what_moves_without_a_run_is_said_by_the_state() {
    use novanc::panel_model::{Axis, OpMode};
    let mut c = open("what-moves-by-hand");
    c.handle(E::Op(OpMode::Continuous));
    c.handle(E::Jog(Axis::X, 1));
    c.handle(E::WaitMs(300));
    assert!(shows(&c, "CONTINUOUS X+: jogging"), "{}", c.frame_text());
    c.handle(E::Override(90));
    assert!(
        shows(&c, "JOG: an axis moves by hand"),
        "{}",
        c.frame_text()
    );
    c.handle(E::JogRelease);
    c.handle(E::Wait);
    assert!(!shows(&c, "JOG:"), "{}", c.frame_text());
    c.handle(E::Home);
    c.handle(E::WaitMs(50));
    c.handle(E::Override(100));
    assert!(
        shows(&c, "HOME: reference return, Z first, then X and Y") && !shows(&c, "JOG:"),
        "{}",
        c.frame_text()
    );
    c.handle(E::EStop);
    c.handle(E::Reset);
    c.handle(E::Op(OpMode::Step));
    c.handle(E::Jog(Axis::Y, 1));
    c.handle(E::Override(90));
    assert!(
        shows(&c, "JOG: an axis moves by hand") && !shows(&c, "HOME"),
        "{}",
        c.frame_text()
    );
    c.handle(E::Wait);
    assert!(!shows(&c, "JOG:"), "{}", c.frame_text());
}
