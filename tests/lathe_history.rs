//! The lathe's MSG page (docs/lathe.md "MSG: the history"): the centre's alarm and message
//! history (`console::book::Log`), kept in the lathe's state directory. Every message the
//! console shows and each channel's fault or alarm go into it once, when they come; Ctrl+E
//! shows it over the mode's display, newest first, and it is still there after a restart.

mod common;

use novanc::lathe::console::LatheConsole;
use novanc::lathe::desc::LatheDesc;
use novanc::panel_model::{OpMode, Page, PanelEvent};
use novanc::store::history::Kind;
use novanc_panel::Key;

fn open(state: &std::path::Path) -> LatheConsole {
    LatheConsole::open(LatheDesc::citizen(), state, 20, 60, None)
        .unwrap_or_else(|e| panic!("{e}"))
        .0
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
    assert!(matches!(c.finish(None), None | Some(Ok(_))));
    // After a restart the history is the one kept on disk, the fault in it.
    let c = open(&dir);
    assert_eq!(entries(&c, Kind::Alarm), ["CH2 FAULT: chip jam"]);
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
        assert_eq!(
            entries(&c, Kind::Alarm).len(),
            round + 1,
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
