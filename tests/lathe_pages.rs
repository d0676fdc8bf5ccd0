//! The lathe's pages beside OFS, the centre's: MSG (docs/lathe.md "MSG: the history"), the
//! alarm and message history (`console::book::Log`) kept in the lathe's state directory, every
//! message the console shows and each channel's fault or alarm put in it once, when they come,
//! shown by Ctrl+E newest first and still there after a restart; and MACRO (docs/lathe.md
//! "MACRO: a channel's variables", Ctrl+U), the selected channel's variables, set by INPUT,
//! #500–#999 stored, read by the channel's next program.

mod common;

use novanc::lathe::console::LatheConsole;
use novanc::lathe::desc::LatheDesc;
use novanc::panel_model::{OpMode, Page, PanelEvent};
use novanc::store::history::Kind;
use novanc_panel::Key;

use common::{open_citizen as open, recorded};

/// The Citizen's console on `state`, recording to `state/name`, and the recording's path.
fn open_recorded(state: &std::path::Path, name: &str) -> (LatheConsole, std::path::PathBuf) {
    let rec = state.join(name);
    let c = LatheConsole::open(LatheDesc::citizen(), state, 20, 60, Some(&rec))
        .unwrap_or_else(|e| panic!("{e}"))
        .0;
    (c, rec)
}

/// The history's entries of `kind`, oldest first.
fn entries(c: &LatheConsole, kind: Kind) -> Vec<String> {
    c.history()
        .iter()
        .filter(|e| e.kind == kind)
        .map(|e| e.text.clone())
        .collect()
}

#[test]
fn a_fault_and_the_messages_are_kept_once_and_shown_on_msg_after_a_restart() {
    let dir = common::temp_dir("lathe-history");
    let mut c = open(&dir);
    c.handle(PanelEvent::Target(1));
    c.handle(PanelEvent::Op(OpMode::Auto));
    c.handle(PanelEvent::Start);
    c.tick(200_000_000);
    c.handle(PanelEvent::Fault(1, "chip jam".into()));
    // The fault stands for many steps: it is put in the history once, when it comes.
    for _ in 0..20 {
        c.tick(10_000_000);
    }
    assert_eq!(entries(&c, Kind::Alarm), ["CH2 FAULT: chip jam"]);
    let said = entries(&c, Kind::Message);
    assert!(said.contains(&"part target 1".to_string()), "{said:?}");
    assert!(
        said.contains(&"CH2 FAULT: chip jam".to_string()),
        "{said:?}"
    );
    assert_eq!(
        said.iter().filter(|m| *m == "cycle start").count(),
        1,
        "{said:?}"
    );

    // Ctrl+E: the history over the mode's display, newest first; the channel's lines stay.
    for ch in "NOTE".chars() {
        c.press(Key::Char(ch));
    }
    c.press(Key::Ctrl('e'));
    assert_eq!(c.page(), Page::Msg);
    let d = c.view().display;
    assert!(d[0].trim_end().ends_with("MSG"), "{d:#?}");
    assert!(d[3].starts_with("MSG "), "{d:#?}");
    assert!(d[4].contains("CH2 FAULT: chip jam"), "{d:#?}");
    assert!(d[5].contains("ALARM CH2 FAULT: chip jam"), "{d:#?}");
    // Read only: Enter says so, and the typed line stays where it was typed.
    c.press(Key::Enter);
    assert!(c.message().contains("read only"), "{}", c.message());
    assert_eq!(
        c.view().display.last().map(|l| l.trim_end()),
        Some("> NOTE")
    );
    // What the key said is the newest entry; the arrows scroll the history, not a tool post.
    assert!(
        c.view().display[4].contains("read only"),
        "{:#?}",
        c.view().display
    );
    let tips = c.tips();
    c.press(Key::Down);
    c.press(Key::Down);
    assert!(
        c.view().display[4].contains(" ALARM CH2"),
        "{:#?}",
        c.view().display
    );
    assert_eq!(c.tips(), tips);
    c.press(Key::Up);
    let d = c.view().display;
    assert!(
        d[4].contains("CH2 FAULT: chip jam") && !d[4].contains("ALARM"),
        "{d:#?}"
    );
    // The page key again leaves it; so does a mode turned.
    c.press(Key::Ctrl('e'));
    assert_eq!(c.page(), Page::Mode);
    c.press(Key::Ctrl('e'));
    c.handle(PanelEvent::Op(OpMode::Mdi));
    assert_eq!(c.page(), Page::Mode);

    c.handle(PanelEvent::EStop);
    assert!(c.finish().is_ok());
    // After a restart the history is the one kept on disk, the fault and the E-STOP in it.
    let c = open(&dir);
    assert_eq!(
        entries(&c, Kind::Alarm),
        ["CH2 FAULT: chip jam", ESTOP_ALARM]
    );
    assert!(entries(&c, Kind::Message).len() >= said.len());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_fault_that_comes_again_in_a_new_cycle_is_kept_again() {
    let dir = common::temp_dir("lathe-history-again");
    let mut c = open(&dir);
    for round in 0..2 {
        c.handle(PanelEvent::Target(1));
        c.handle(PanelEvent::Op(OpMode::Auto));
        c.handle(PanelEvent::Start);
        c.tick(100_000_000);
        c.handle(PanelEvent::Fault(0, "door".into()));
        c.tick(100_000_000);
        // The fault of each round, and the E-STOP that ended the round before.
        assert_eq!(
            entries(&c, Kind::Alarm).len(),
            2 * round + 1,
            "{:?}",
            c.history()
        );
        // RESET of the machine after E-STOP clears the cycle.
        c.handle(PanelEvent::EStop);
        c.handle(PanelEvent::Reset);
        c.handle(PanelEvent::Reset);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_channels_fault_is_filed_under_that_channels_program() {
    let dir = common::temp_dir("lathe-history-file");
    let (mut c, rec) = open_recorded(&dir, "fault.mcap");
    c.handle(PanelEvent::Op(OpMode::Auto));
    c.handle(PanelEvent::Start);
    c.tick(200_000_000);
    // CH1 selected; the fault is CH2's.
    c.handle(PanelEvent::Fault(1, "chip jam".into()));
    c.tick(10_000_000);
    assert!(matches!(c.finish(), Ok(Some(_))));
    let filed: Vec<String> = recorded(&rec, "/foxglove/log")
        .into_iter()
        .map(|(_, json)| json)
        .filter(|json| json.contains("CH2 FAULT: chip jam"))
        .collect();
    // The message and the alarm, both under SYSTEM2's program (the message was filed under
    // the selected channel's, SYSTEM1's, before stop 40).
    assert_eq!(filed.len(), 2, "{filed:?}");
    for f in &filed {
        assert!(f.contains("\"file\":\"SYSTEM2.NGC\""), "{f}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn ofs_input_sets_the_cell_under_the_cursor_and_plus_input_adds_to_it() {
    let dir = common::temp_dir("lathe-ofs-cursor");
    let mut c = open(&dir);
    c.handle(PanelEvent::Op(OpMode::Continuous));
    c.press(Key::Ctrl('o'));
    assert_eq!(c.page(), Page::Ofs);
    let tips = c.tips();
    // The arrows move the cursor, not a tool post (the centre's rule under a page).
    c.press(Key::Down);
    c.press(Key::Down);
    c.press(Key::Right);
    assert_eq!(c.tips(), tips);
    let row = |c: &LatheConsole, t: &str| {
        c.view()
            .display
            .iter()
            .find(|l| l.starts_with(t))
            .map(|l| l.trim_end().to_string())
            .unwrap_or_default()
    };
    assert_eq!(row(&c, "T03"), "T03 0.200 2    0.000>  0.000");
    // INPUT: Z of T03 set to -0.1; +INPUT (Tab): 0.02 added to it.
    for k in "-0.1".chars() {
        c.press(Key::Char(k));
    }
    c.press(Key::Enter);
    assert!(c.message().starts_with("T03 revised"), "{}", c.message());
    for k in "0.02".chars() {
        c.press(Key::Char(k));
    }
    c.press(Key::Tab);
    assert_eq!(row(&c, "T03"), "T03 0.200 2    0.000> -0.080");
    assert_eq!(c.selected(), 0, "Tab with a value typed is +INPUT");
    // A value refused stays on the entry line, and changes nothing.
    c.press(Key::Left);
    c.press(Key::Left);
    c.press(Key::Char('7'));
    c.press(Key::Tab);
    assert!(c.message().contains("not added to"), "{}", c.message());
    assert_eq!(c.view().display.last().map(|l| l.trim_end()), Some("> 7"));
    c.press(Key::Backspace);
    // Stored: a restart has it.
    assert!(c.finish().is_ok());
    let mut c = open(&dir);
    assert_eq!(c.desc().channels[0].tools[2].offset, [0.0, -0.08]);
    // Tab with nothing typed turns the channel selector, on OFS as everywhere.
    c.press(Key::Ctrl('o'));
    c.press(Key::Tab);
    assert_eq!(c.selected(), 1);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The keypad's +INPUT key (`plusinput`) is one event on both machines: on OFS and MACRO it
/// adds to the cell under the cursor, even with nothing typed (it never turns the channel
/// selector, as the keyboard's Tab does then); elsewhere it is refused and the line stays.
/// Before stop 46 the lathe's keypad had no +INPUT, and its MACRO page took Tab as INPUT.
#[test]
fn the_plus_input_key_adds_on_a_page_and_never_turns_the_channel() {
    let (dir, mut c, mut m) = common::both_machines("plus-input");
    c.press(Key::Ctrl('o'));
    c.handle(PanelEvent::PlusInput);
    assert_eq!(c.selected(), 0, "{}", c.message());
    assert!(c.message().contains("type"), "{}", c.message());
    // T01's X offset (the cursor's cell, a diameter): 0.02 added.
    let x = c.desc().channels[0].tools[0].offset[0];
    for k in "0.02".chars() {
        c.handle(PanelEvent::Key(k));
    }
    c.handle(PanelEvent::PlusInput);
    let now = c.desc().channels[0].tools[0].offset[0];
    assert!(
        ((now - x) * 2.0 - 0.02).abs() < 1e-9,
        "{x} -> {now}: {}",
        c.message()
    );
    assert_eq!(c.entry(), "");
    // MACRO: +INPUT adds to the variable, by the key and by the keyboard's Tab.
    c.press(Key::Ctrl('u'));
    assert_eq!(c.page(), Page::Macro);
    c.handle(PanelEvent::Type("#500=2".into()));
    for k in "3".chars() {
        c.handle(PanelEvent::Key(k));
    }
    c.handle(PanelEvent::PlusInput);
    assert!(c.message().ends_with("#500 = 5"), "{}", c.message());
    c.handle(PanelEvent::Key('1'));
    c.press(Key::Tab);
    assert!(c.message().ends_with("#500 = 6"), "{}", c.message());
    assert_eq!(c.selected(), 0);
    // On the mode display: refused, the line kept, on both machines.
    c.press(Key::Ctrl('u'));
    c.handle(PanelEvent::Op(OpMode::Mdi));
    m.handle(PanelEvent::Op(OpMode::Mdi));
    for k in "G0X1".chars() {
        c.handle(PanelEvent::Key(k));
        m.handle(PanelEvent::Key(k));
    }
    c.handle(PanelEvent::PlusInput);
    m.handle(PanelEvent::PlusInput);
    for (entry, said) in [
        (c.entry().to_string(), c.message()),
        (m.view().entry, m.message()),
    ] {
        assert_eq!(entry, "G0X1");
        assert!(said.starts_with("+INPUT refused"), "{said}");
    }
    assert_eq!(c.selected(), 0);
    // The centre's OFS: the key adds as its Tab does.
    m.handle(PanelEvent::Op(OpMode::Auto));
    m.handle(PanelEvent::Press(Key::Ctrl('o')));
    m.handle(PanelEvent::Type("1".into()));
    let before = m.frame_text();
    m.handle(PanelEvent::Key('1'));
    m.handle(PanelEvent::PlusInput);
    assert_ne!(m.frame_text(), before);
    assert!(m.message().starts_with("T01"), "{}", m.message());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn tab_is_plus_input_on_a_page_with_a_value_typed_and_else_the_channel_selector_on_both_machines() {
    // One rule (stop 47): before, a lathe's Tab turned the channel, and cleared the line
    // typed, on every page but OFS and MACRO, and the centre's Tab was +INPUT on every page
    // with nothing typed too.
    let (dir, mut c, mut m) = common::both_machines("tab-rule");
    // A lathe's MSG page with a value typed: +INPUT, refused there (no cells to add to), the
    // line kept, the channel as it was.
    c.press(Key::Ctrl('e'));
    assert_eq!(c.page(), Page::Msg);
    c.handle(PanelEvent::Key('5'));
    c.press(Key::Tab);
    assert_eq!(c.selected(), 0, "{}", c.message());
    assert_eq!(c.entry(), "5", "{}", c.message());
    // With nothing typed: the channel selector, on a page as on the mode display.
    c.handle(PanelEvent::Rubout);
    c.press(Key::Tab);
    assert_eq!(c.selected(), 1, "{}", c.message());
    // Off the pages, a line typed: the channel turns and the line stays, now the next
    // channel's (before stop 47 the turn cleared it).
    c.press(Key::Ctrl('e'));
    c.handle(PanelEvent::Op(OpMode::Mdi));
    for k in "G0X1".chars() {
        c.handle(PanelEvent::Key(k));
    }
    c.press(Key::Tab);
    assert_eq!(c.selected(), 2, "{}", c.message());
    assert_eq!(c.entry(), "G0X1");
    c.press(Key::Enter);
    assert_eq!(c.mdi_lines(2), ["G0X1"], "{}", c.message());
    // The centre's POS with a value typed: +INPUT, which POS takes as INPUT.
    m.handle(PanelEvent::Press(Key::Ctrl('p')));
    for k in "PARTS 3".chars() {
        m.handle(PanelEvent::Key(k));
    }
    m.handle(PanelEvent::Press(Key::Tab));
    assert_eq!(m.view().entry, "", "{}", m.message());
    assert!(
        m.message().to_lowercase().contains("parts 3"),
        "{}",
        m.message()
    );
    // With nothing typed, on a page: its one channel has no next; the key says so.
    m.handle(PanelEvent::Press(Key::Ctrl('o')));
    m.handle(PanelEvent::Press(Key::Tab));
    assert!(
        m.message().contains("key Tab does nothing"),
        "{}",
        m.message()
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn pos_shows_the_tip_and_what_is_left_of_the_block() {
    let dir = common::temp_dir("lathe-pos");
    let mut c = open(&dir);
    c.handle(PanelEvent::Op(OpMode::Auto));
    c.handle(PanelEvent::Start);
    c.tick(2_600_000_000);
    c.handle(PanelEvent::Override(10));
    c.press(Key::Ctrl('p'));
    assert_eq!(c.page(), Page::Pos);
    for _ in 0..3 {
        c.tick(300_000_000);
        let v = c.view();
        let ch = &v.channels[0];
        let st = &c.cycle().channels()[0].status.clone();
        let end = st.executing.as_ref().and_then(|e| e.block()).map(|b| b.end);
        let end = end.unwrap_or_else(|| panic!("no block in execution: {:#?}", v.display));
        assert!(st.in_block && ch.state == "RUN", "{:#?}", v.display);
        // The tip and what is left of the block add up to the block's end, and the page shows
        // both as the plasma shows X: a diameter.
        assert_eq!(
            [ch.pos[0] + ch.to_go[0], ch.pos[1] + ch.to_go[1]],
            [end[0], end[2]]
        );
        assert_ne!(ch.to_go, [0, 0]);
        // The work position (the Citizen's offsets are 0: the machine's), the machine's, and
        // what is left.
        let mm = |p: i64| p as f64 * c.desc().pulse_mm;
        assert_eq!(ch.work_pos(), ch.pos);
        // The centre's table (since stop 59): WORK, REL (its origin 0 until set), MACH,
        // TO GO.
        let x = format!(
            "X{:>9.3}{:>9.3}{:>9.3}{:>9.3}",
            mm(ch.pos[0] * 2),
            mm(ch.pos[0] * 2),
            mm(ch.pos[0] * 2),
            mm(ch.to_go[0] * 2)
        );
        assert!(
            v.display.iter().any(|l| l.trim_end() == x),
            "{x}\n{:#?}",
            v.display
        );
    }
    // The page key again leaves it.
    c.press(Key::Ctrl('p'));
    assert_eq!(c.page(), Page::Mode);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_mdi_run_lists_what_it_runs_with_its_block_marked() {
    let dir = common::temp_dir("lathe-mdi-listing");
    let mut c = open(&dir);
    c.handle(PanelEvent::Channel(1));
    c.handle(PanelEvent::Op(OpMode::Mdi));
    for l in ["G0 X30 Z5", "G0 X20 Z2", "G0 X40 Z20"] {
        c.handle(PanelEvent::Type(l.into()));
    }
    c.handle(PanelEvent::Start);
    c.tick(250_000_000);
    // The buffer is cleared at START; the display lists the run (it went blank before stop 40).
    assert!(c.mdi_lines(1).is_empty());
    let d = c.view().display;
    let listed: Vec<&str> = d
        .iter()
        .map(|l| l.trim_end())
        .filter(|l| l.contains(" G0 "))
        .collect();
    assert_eq!(
        listed,
        [">0001 G0 X30 Z5", " 0002 G0 X20 Z2", " 0003 G0 X40 Z20"],
        "{d:#?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_message_said_inside_a_long_wait_is_kept_at_its_blocks_start() {
    let dir = common::temp_dir("lathe-msg-time");
    let (mut c, rec) = open_recorded(&dir, "msg.mcap");
    c.handle(PanelEvent::Op(OpMode::Mdi));
    for l in ["G0 X20 Z10", "(msg, here)", "G4 P2", "G0 X40 Z20"] {
        c.handle(PanelEvent::Type(l.into()));
    }
    c.handle(PanelEvent::Start);
    // One wait to rest: the kernel runs it in its thread in one go (since stop 40).
    c.handle(PanelEvent::Wait);
    assert!(c.at_rest() && c.wait_error().is_none());
    let said: Vec<u64> = c
        .history()
        .iter()
        .filter(|e| e.text == "CH1 MSG: here")
        .map(|e| e.machine_ns)
        .collect();
    assert_eq!(said.len(), 1, "{:?}", c.history());
    assert!(matches!(c.finish(), Ok(Some(_))));
    // The dwell's start, as the recording has it: the message is kept at that instant, to the
    // nanosecond, not at the wait's end (or the 10 ms step the console saw it in before).
    let dwell: Vec<u64> = recorded(&rec, "/nc/block")
        .into_iter()
        .filter(|(_, json)| json.contains("G04"))
        .map(|(t, _)| t)
        .collect();
    assert_eq!(dwell, said);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The E-STOP as the history keeps it (the centre's entry).
const ESTOP_ALARM: &str = "EMERGENCY STOP: pulses stopped; press RESET";

#[test]
fn an_estop_is_the_machines_alarm_said_while_in_force_and_kept_once() {
    let dir = common::temp_dir("lathe-history-estop");
    let mut c = open(&dir);
    // With no cycle loaded: in force until RESET, shown on every channel, START refused.
    c.handle(PanelEvent::EStop);
    c.tick(10_000_000);
    assert_eq!(c.message(), ESTOP_ALARM);
    assert!(c.view().channels.iter().all(|ch| ch.state == "ESTOP"));
    c.handle(PanelEvent::Op(OpMode::Auto));
    c.handle(PanelEvent::Start);
    assert!(c.message().starts_with("START refused"), "{}", c.message());
    c.tick(10_000_000);
    assert!(c.at_rest());
    c.handle(PanelEvent::Reset);
    assert!(c.view().channels.iter().all(|ch| ch.state == "IDLE"));
    assert_eq!(entries(&c, Kind::Alarm), [ESTOP_ALARM]);

    // In a cycle: the machine's alarm, said as on the centre, not the last channel's (before
    // stop 40 the message line said `CH3 ALARM: EMERGENCY STOP ...`), and kept once.
    c.handle(PanelEvent::Target(1));
    c.handle(PanelEvent::Start);
    c.tick(3_000_000_000);
    c.handle(PanelEvent::EStop);
    for _ in 0..20 {
        c.tick(10_000_000);
        assert_eq!(c.message(), ESTOP_ALARM);
    }
    assert!(c.view().channels.iter().all(|ch| ch.state == "ESTOP"));
    assert_eq!(entries(&c, Kind::Alarm), [ESTOP_ALARM, ESTOP_ALARM]);
    assert!(
        !entries(&c, Kind::Message)
            .iter()
            .any(|m| m.contains(ESTOP_ALARM)),
        "{:?}",
        c.history()
    );
    c.handle(PanelEvent::Reset);
    assert_ne!(c.message(), ESTOP_ALARM);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The X and Z a channel's tool tip stands at after MDI `line` runs on channel 1.
fn after_mdi(c: &mut LatheConsole, line: &str) -> [i64; 2] {
    c.handle(PanelEvent::Op(OpMode::Mdi));
    c.handle(PanelEvent::Type(line.into()));
    c.handle(PanelEvent::Start);
    c.handle(PanelEvent::Wait);
    let t = c.tips()[0].0;
    c.handle(PanelEvent::Reset);
    t
}

#[test]
fn a_variable_set_on_macro_is_stored_and_read_by_the_channels_next_program() {
    let dir = common::temp_dir("lathe-macro");
    let mut c = open(&dir);
    c.press(Key::Ctrl('u'));
    assert_eq!(c.page(), Page::Macro);
    let d = c.view().display;
    assert!(d[0].trim_end().ends_with("MACRO"), "{d:#?}");
    assert!(d[3].starts_with("MACRO CH1"), "{d:#?}");
    assert!(d[4].starts_with(">#1 "), "{d:#?}");
    for ch in "#500=12.5".chars() {
        c.press(Key::Char(ch));
    }
    c.press(Key::Enter);
    assert_eq!(c.message(), "CH1 #500 = 12.5");
    let d = c.view().display;
    assert!(
        d.iter()
            .any(|l| l.starts_with(">#500") && l.trim_end().ends_with("12.5")),
        "{d:#?}"
    );
    // A value that is not one is refused, and what was typed stays.
    for ch in "1e99".chars() {
        c.press(Key::Char(ch));
    }
    c.press(Key::Enter);
    assert!(
        c.message().starts_with("MACRO refused: "),
        "{}",
        c.message()
    );
    assert_eq!(
        c.view().display.last().map(|l| l.trim_end()),
        Some("> 1E99")
    );
    c.handle(PanelEvent::Type(String::new()));
    // The arrows move the cursor, not a tool post.
    let tips = c.tips();
    c.press(Key::Down);
    assert!(c.view().display.iter().any(|l| l.starts_with(">#501")));
    assert_eq!(c.tips(), tips);

    // The channel's next program reads it, as it reads a program's own #500.
    let by_var = after_mdi(&mut c, "G0 X#500 Z5");
    let by_hand = after_mdi(&mut c, "G0 X12.5 Z5");
    assert_eq!(by_var, by_hand);
    assert_ne!(by_var, tips[0].0, "the MDI run moved");
    let by_other = after_mdi(&mut c, "G0 X20 Z5");
    assert_ne!(by_other, by_var);
    assert!(c.finish().is_ok());

    // Stored: after a restart the channel still has it.
    let mut c = open(&dir);
    c.press(Key::Ctrl('u'));
    c.handle(PanelEvent::Type("#500".into()));
    let d = c.view().display;
    assert!(
        d.iter()
            .any(|l| l.starts_with(">#500") && l.trim_end().ends_with("12.5")),
        "{d:#?}"
    );
    // Not while a cycle is under way: its programs read the variables at START.
    c.handle(PanelEvent::Target(1));
    c.handle(PanelEvent::Op(OpMode::Auto));
    c.handle(PanelEvent::Start);
    c.tick(100_000_000);
    c.press(Key::Ctrl('u'));
    c.handle(PanelEvent::Type("#501=3".into()));
    assert!(
        c.message().contains("a cycle is under way"),
        "{}",
        c.message()
    );
    assert_eq!(
        c.view().display.last().map(|l| l.trim_end()),
        Some("> #501=3")
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The title's `CYCLE`: the time from one part delivered at the unloader to the next (the
/// batch's first from its START), as the kernel's part events in the recording have them.
#[test]
fn the_cycle_time_is_the_time_between_the_last_two_parts_delivered() {
    let dir = common::temp_dir("lathe-cycle-time");
    let (mut c, rec) = open_recorded(&dir, "r.mcap");
    assert_eq!(c.cycle_time_ns(), None);
    assert!(!c.view().title.contains("CYCLE"));
    c.handle(PanelEvent::Target(3));
    c.handle(PanelEvent::Op(OpMode::Auto));
    c.handle(PanelEvent::Start);
    c.handle(PanelEvent::Wait);
    let shown = c.cycle_time_ns().expect("a cycle time after three parts");
    let title = c.view().title;
    assert!(
        title.contains(&format!("CYCLE {:.3} s", shown as f64 * 1e-9)),
        "{title}"
    );
    let unloader = c.desc().unloader;
    assert!(c.finish().is_ok());
    let parts: Vec<u64> = recorded(&rec, "/lathe/event")
        .into_iter()
        .filter(|(_, j)| {
            j.contains("\"event\":\"part\"") && j.contains(&format!("\"channel\":{unloader},"))
        })
        .map(|(t, _)| t)
        .collect();
    assert_eq!(parts.len(), 3, "{parts:?}");
    assert_eq!(shown, parts[2] - parts[1]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// MODAL (Ctrl+G): the selected channel's modal state as its last read left it, what the next
/// MDI line starts from (G91 held from one MDI run to the next), with the centre's switches.
#[test]
fn modal_shows_what_the_channels_last_read_left_in_force() {
    let dir = common::temp_dir("lathe-modal");
    let mut c = open(&dir);
    c.handle(PanelEvent::Op(OpMode::Mdi));
    c.handle(PanelEvent::Type("G91 G95 F0.1 S800 M3".into()));
    c.handle(PanelEvent::Type("G1 W-1".into()));
    c.handle(PanelEvent::Start);
    c.handle(PanelEvent::Wait);
    c.handle(PanelEvent::Override(70));
    c.press(Key::Ctrl('g'));
    assert_eq!(c.page(), Page::Modal);
    let d = c.view().display;
    assert!(d[0].trim_end().ends_with("MODAL"), "{d:#?}");
    assert!(d[3].starts_with("MODAL CH1 the state in force"), "{d:#?}");
    assert!(d[4].starts_with("G01 G91 G7 G21 G95 G97"), "{d:#?}");
    assert!(d[5].starts_with("F0.1 S800 M03 T--"), "{d:#?}");
    assert!(
        d.iter().any(|l| l.contains("FEED OVR 70%")),
        "the switches, in the centre's words: {d:#?}"
    );
    // Another channel's: as at power-on.
    c.press(Key::Tab);
    let d = c.view().display;
    assert!(d[3].starts_with("MODAL CH2"), "{d:#?}");
    assert!(d[4].starts_with("G-- G90"), "{d:#?}");
    // RESET returns the channel's state to power-on (docs/lathe-gcode.md).
    c.press(Key::Tab);
    c.press(Key::Tab);
    c.handle(PanelEvent::Reset);
    c.press(Key::Ctrl('g'));
    c.press(Key::Ctrl('g'));
    assert!(
        c.view().display[4].starts_with("G-- G90"),
        "{:#?}",
        c.view().display
    );
    // A cycle under G96: its spindle turns, and MODAL says so (no rpm is programmed there;
    // the first version said M05).
    c.handle(PanelEvent::Target(1));
    c.handle(PanelEvent::Op(OpMode::Auto));
    c.handle(PanelEvent::Start);
    let mut seen = false;
    for _ in 0..2_000 {
        c.tick(10_000_000);
        c.press(Key::Ctrl('g'));
        let d = c.view().display;
        c.press(Key::Ctrl('g'));
        if d[4].contains("G96") && d[1].split_whitespace().last() != Some("0") {
            assert!(d[3].contains("at the end of the cycle's read"), "{d:#?}");
            assert!(d[5].contains(" M03 "), "{d:#?}");
            seen = true;
            break;
        }
    }
    assert!(seen, "no G96 cut seen");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Every key of the terminal, in every position of the selector and on every page, with a
/// cycle running and without: the console never panics, the display keeps its size, and a key
/// that the lathe has no use for says so (none is dropped in silence).
#[test]
fn every_key_in_every_mode_and_page_acts_or_says_why() {
    let dir = common::temp_dir("lathe-every-key");
    let mut c = open(&dir);
    let keys = common::all_keys();
    let pages = [
        None,
        Some(Key::Ctrl('o')),
        Some(Key::Ctrl('e')),
        Some(Key::Ctrl('u')),
        Some(Key::Ctrl('g')),
    ];
    let modes = [
        OpMode::Auto,
        OpMode::Mdi,
        OpMode::Data,
        OpMode::Continuous,
        OpMode::Handle,
        OpMode::Step,
        OpMode::Single,
    ];
    let mut silent = Vec::new();
    for running in [false, true] {
        for m in modes {
            for p in pages {
                for &k in &keys {
                    c.handle(PanelEvent::Reset);
                    if running && c.cycle().is_over() {
                        c.handle(PanelEvent::Target(999));
                        c.handle(PanelEvent::Op(OpMode::Auto));
                        c.handle(PanelEvent::Start);
                        c.tick(50_000_000);
                    }
                    c.handle(PanelEvent::Op(m));
                    if let Some(pk) = p {
                        c.press(pk);
                    }
                    let before = c.view().display;
                    let typed = before.last().is_some_and(|l| l.trim_end() != ">");
                    c.press(k);
                    c.tick(1_000_000);
                    let v = c.view();
                    assert_eq!(v.display.len(), 20, "{k:?} in {m:?} {p:?}");
                    assert!(v.display.iter().all(|l| l.chars().count() == 60));
                    // Silent and right so: a page's cursor key at its end (the centre's rule),
                    // RUBOUT or EOB with nothing typed.
                    let at_end = matches!(c.page(), Page::Msg | Page::Macro)
                        && novanc::console::keys::is_cursor_key(k);
                    let nothing_typed = matches!(k, Key::Backspace | Key::Enter) && !typed;
                    // A selector key for the position it is at: the selector does not move
                    // (the centre's rule, one for both since stop 43).
                    let same = matches!(k, Key::Alt(d) if OpMode::ALL.get((d as usize).wrapping_sub('1' as usize)) == Some(&m));
                    if v.display == before
                        && !same
                        && c.message().is_empty()
                        && !v.help
                        && !at_end
                        && !nothing_typed
                    {
                        silent.push(format!("{k:?} in {m:?} page {p:?} running {running}"));
                    }
                    if v.help {
                        c.press(Key::F(8));
                    }
                }
            }
        }
    }
    assert!(
        silent.is_empty(),
        "keys that changed nothing and said nothing:\n{}",
        silent.join("\n")
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The history's levels are every console's (stop 45, docs/recording.md "Levels"): the
/// machine's refusal of an operator action is a WARNING on the lathe too (its queued STEP that
/// would leave the travel, said `CH1 X jog refused: ...`), a message the console says is INFO.
/// Before, the lathe wrote every message at INFO.
#[test]
fn a_machine_refusal_is_a_warning_in_the_lathe_recording() {
    let dir = common::temp_dir("lathe-log-levels");
    let (mut c, rec) = open_recorded(&dir, "levels.mcap");
    // From the top of X, the third STEP of X+ leaves the travel when its turn comes.
    let script = "op STEP\nwheelscale 1000\njog X-\njog X-\nwait\njog X+\njog X+\njog X+\nwait\n";
    for ev in novanc::lathe::console::events::parse_script(script, 3).unwrap() {
        c.handle(ev);
    }
    assert!(
        c.message().starts_with("CH1 X jog refused:"),
        "{}",
        c.message()
    );
    // The next action puts the message shown into the history.
    c.press(Key::Alt('w'));
    assert!(matches!(c.finish(), Ok(Some(_))));
    let logs: Vec<String> = recorded(&rec, "/foxglove/log")
        .into_iter()
        .map(|(_, json)| json)
        .collect();
    let at = |text: &str| -> Vec<&String> { logs.iter().filter(|l| l.contains(text)).collect() };
    let refused = at("CH1 X jog refused:");
    assert!(!refused.is_empty(), "{logs:#?}");
    for l in refused {
        assert!(l.contains("\"level\":3,"), "{l}");
    }
    let said = at("STEP CH1 X- 1.000 mm");
    assert!(!said.is_empty(), "{logs:#?}");
    for l in said {
        assert!(l.contains("\"level\":2,"), "{l}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The POS page takes the centre's words on the lathe (stop 59): `X`, `X12.5` (a diameter),
/// `Z-3`, `XZ` set the selected channel's relative position, shown in the centre's REL column;
/// `TARGET n` sets the batch's target and `PARTS n` the total; a line POS cannot read stays on
/// the entry line with the words it takes, and is not an MDI line (before, a line typed under
/// POS went to the selector's use).
#[test]
fn pos_takes_the_centres_words_for_each_channels_relative_position() {
    let dir = common::temp_dir("lathe-pos-rel");
    let mut c = open(&dir);
    c.handle(PanelEvent::Op(OpMode::Mdi));
    c.press(Key::Ctrl('p'));
    assert_eq!(c.page(), Page::Pos);
    // The row of `axis`: WORK, REL, MACH, TO GO.
    let row = |c: &LatheConsole, axis: &str| -> Vec<f64> {
        let d = c.view().display;
        // (The summary line above it starts `X   70.000 Z`.)
        let l = (d.iter().rev())
            .find(|l| l.starts_with(axis))
            .unwrap_or_else(|| panic!("{d:#?}"));
        l[1..]
            .split_whitespace()
            .map(|v| v.parse().unwrap())
            .collect()
    };
    let x_mach = row(&c, "X")[2];
    let z_mach = row(&c, "Z")[2];
    assert_eq!(
        row(&c, "X")[1],
        x_mach,
        "REL is MACH until an origin is set"
    );
    for (line, said, x_rel, z_rel) in [
        ("X", "relative X preset to 0.000", 0.0, z_mach),
        ("x12.5", "relative X preset to 12.500", 12.5, z_mach),
        ("Z-3", "relative Z preset to -3.000", 12.5, -3.0),
        ("XZ", "relative X Z zeroed", 0.0, 0.0),
    ] {
        c.handle(PanelEvent::Type(line.into()));
        assert_eq!(c.message(), said);
        assert_eq!((row(&c, "X")[1], row(&c, "Z")[1]), (x_rel, z_rel), "{line}");
        assert_eq!(c.entry(), "");
    }
    // Not POS's: kept, with the words it takes; not an MDI line.
    for k in "G0X1".chars() {
        c.handle(PanelEvent::Key(k));
    }
    c.handle(PanelEvent::Eob);
    assert!(c.message().starts_with("POS: type X"), "{}", c.message());
    assert!(
        c.message().contains("XZ, PARTS n, TARGET n,"),
        "{}",
        c.message()
    );
    assert!(
        c.message()
            .ends_with("(POS is up: Ctrl+P puts it down for MDI)"),
        "{}",
        c.message()
    );
    assert_eq!(c.entry(), "G0X1");
    assert!(c.mdi_lines(0).is_empty());
    for _ in 0..4 {
        c.handle(PanelEvent::Rubout);
    }
    // Each channel has its own origin.
    c.handle(PanelEvent::Channel(1));
    assert_eq!(row(&c, "X")[1], row(&c, "X")[2]);
    c.handle(PanelEvent::Channel(0));
    assert_eq!(row(&c, "X")[1], 0.0);
    // The counters.
    c.handle(PanelEvent::Type("TARGET 7".into()));
    assert_eq!((c.message(), c.counter().target), ("part target 7", 7));
    c.handle(PanelEvent::Type("PARTS 12".into()));
    assert_eq!((c.message(), c.counters().parts), ("parts 12", 12));
    c.handle(PanelEvent::Type("TARGET 0".into()));
    assert!(c.message().contains("1 to 999999"), "{}", c.message());
    assert_eq!((c.entry(), c.counter().target), ("TARGET 0", 7));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_msg_page_under_a_long_message_marks_an_entry_it_cuts() {
    let dir = common::temp_dir("lathe-msg-cut");
    let mut c = open(&dir);
    // Entries of three or four lines each, and a message of several lines under them.
    let why = "the bar feeder stopped with the bar half out of the guide tube and the collet open";
    c.handle(PanelEvent::Target(1));
    c.handle(PanelEvent::Op(OpMode::Auto));
    c.handle(PanelEvent::Start);
    c.tick(200_000_000);
    for ch in 0..3 {
        c.handle(PanelEvent::Fault(ch, why.into()));
    }
    c.press(Key::Ctrl('e'));
    // The oldest entry shown goes on below the page's room: its last line shown says so
    // (before stop 60 the plasma dropped its last line without a mark).
    let d = c.view().display;
    let body: Vec<&str> = d[4..d.len() - 2].iter().map(|l| l.trim_end()).collect();
    let last = body.iter().rposition(|l| !l.is_empty());
    let last = last.map(|i| body[i]).unwrap_or_default();
    assert!(last.ends_with('\u{2026}'), "{d:#?}");
    // Scrolled down two entries, the rest of it is shown, and nothing is marked.
    c.press(Key::Down);
    c.press(Key::Down);
    let d = c.view().display;
    assert!(d.iter().all(|l| !l.contains('\u{2026}')), "{d:#?}");
    assert!(d.iter().any(|l| l.contains("collet open")), "{d:#?}");
    // A message of two lines under the page: the page has a line less, and still marks it.
    c.press(Key::Home);
    c.handle(PanelEvent::Fault(1, why.into()));
    let d = c.view().display;
    let n = d.len();
    assert!(d[n - 3].trim_end().starts_with("CH2 FAULT"), "{d:#?}");
    assert!(d[n - 4].trim_end().ends_with('\u{2026}'), "{d:#?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The terminal's plasma (12 lines of 40): POS whole under a message of one line; under a
/// longer message its last line shown ends in the cut mark. Before stop 60 a page longer than
/// the room lost its last lines without a mark.
#[test]
fn pos_fits_the_terminals_plasma_and_a_cut_is_marked() {
    let dir = common::temp_dir("lathe-pos-fit");
    let mut c = LatheConsole::open(LatheDesc::citizen(), &dir, 12, 40, None)
        .unwrap_or_else(|e| panic!("{e}"))
        .0;
    c.press(Key::Ctrl('p'));
    c.handle(PanelEvent::Type("JOG 250".into()));
    let d = c.view().display;
    assert_eq!(d.len(), 12, "{d:#?}");
    for want in [
        "POS CH1  X DIAMETER  PARTS 0/5",
        "JOG 250 mm/min",
        "TOTAL 0 ",
    ] {
        assert!(d.iter().any(|l| l.contains(want)), "{want}: {d:#?}");
    }
    assert!(d.iter().all(|l| !l.contains('\u{2026}')), "{d:#?}");
    // A refusal of two lines: TOTAL goes, and the line above the message says so.
    c.handle(PanelEvent::Type("JOG 99999".into()));
    let d = c.view().display;
    assert!(d[9].starts_with("JOG refused"), "{d:#?}");
    assert!(d[8].trim_end().ends_with('\u{2026}'), "{d:#?}");
    let _ = std::fs::remove_dir_all(&dir);
}
