//! A journal append that fails (here: the file size limit, as on a full disk) is not an
//! accepted edit: the operator is told it was not saved, the buffer is as before, and the next
//! edit that fits is saved normally. Stores that need rewriting at open (a journal to compact,
//! a damaged tail) still open on a full disk, read as they are, refusing changes until there
//! is room. Runs in child processes, because the file size limit applies to the whole process.

mod common;

use novanc::store::{EditFailure, Stores, Target};
use std::path::{Path, PathBuf};

const CHILD_DIR: &str = "NOVANC_DISKFULL_TEST_DIR";
const CHILD_OPEN_DIR: &str = "NOVANC_DISKFULL_OPEN_DIR";
const CHILD_CONSOLE: &str = "NOVANC_DISKFULL_CONSOLE";

fn dir() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("store-diskfull")
}

/// The child: edits under a file size limit just above the journal's length.
#[test]
fn child_under_a_size_limit() {
    let Some(d) = std::env::var_os(CHILD_DIR) else {
        return;
    };
    let d = PathBuf::from(d);
    let (mut s, _) = Stores::open(&d, 24).unwrap();
    s.edit(Target::Mdi, "IGO, 1, 2, 3*", None).unwrap();
    let len = std::fs::metadata(d.join("journal.log")).unwrap().len();
    common::limit_file_size(len + 120);
    let big = format!("I{}*", "X".repeat(200));
    let before = (
        s.buffer(Target::Mdi).text(),
        s.buffer(Target::Mdi).pointer(),
    );
    match s.edit(Target::Mdi, &big, None) {
        Err(EditFailure::Store(e)) => {
            assert!(e.message.starts_with("not saved ("), "{e}");
            assert!(e.message.ends_with("; nothing was changed"), "{e}");
        }
        other => panic!("expected a store failure, got {other:?}"),
    }
    let after = (
        s.buffer(Target::Mdi).text(),
        s.buffer(Target::Mdi).pointer(),
    );
    assert_eq!(after, before);
    // A TOOL DATA READ that does not fit is refused the same way.
    let e = s
        .tool_read("00106 DR 9 150 40 1200 120 3\n", "t.tt")
        .unwrap_err();
    assert!(
        e.message
            .starts_with("the tool file was not changed: not saved"),
        "{e}"
    );
    assert_eq!(s.magazine().find(106).unwrap().1.diameter, 6.2);
    // A small edit still fits after the failed one (the journal was cut back).
    s.edit(Target::Mdi, "ICL*", None).unwrap();
    println!("\nchild done");
}

#[test]
fn a_failed_journal_write_is_reported_and_changes_nothing() {
    let d = dir();
    let _ = std::fs::remove_dir_all(&d);
    common::run_child(
        "child_under_a_size_limit",
        &[(CHILD_DIR, d.as_os_str())],
        false,
    );
    let (s, w) = Stores::open(&d, 24).unwrap();
    assert!(w.is_empty(), "{w:?}");
    assert_eq!(s.buffer(Target::Mdi).text(), "GO, 1, 2, 3\nCL\n");
    assert_eq!(s.magazine().find(106).unwrap().1.diameter, 6.2);
}

/// The child: opens stores that need compacting while nothing can be written.
#[test]
fn child_opens_on_a_full_disk() {
    let Some(d) = std::env::var_os(CHILD_OPEN_DIR) else {
        return;
    };
    let d = PathBuf::from(d);
    let journal = std::fs::read(d.join("journal.log")).unwrap();
    common::limit_file_size(1);
    let (mut s, w) = Stores::open(&d, 24).unwrap();
    assert_eq!(w.len(), 2, "{w:?}");
    assert!(
        w[0].contains("crash while writing") && w[0].contains("It is kept as journal.log.bad-"),
        "{}",
        w[0]
    );
    assert!(
        w[1].starts_with(&format!("cannot save to {} (", d.display()))
            && w[1].ends_with("the stores are open as they were read, nothing is lost, and changes are refused until there is room to save them"),
        "{}",
        w[1]
    );
    assert_eq!(s.buffer(Target::Mdi).text(), "A\nB\n");
    // Nothing was rewritten: the damaged journal is still there as it was.
    assert_eq!(std::fs::read(d.join("journal.log")).unwrap(), journal);
    match s.edit(Target::Mdi, "ID*", None) {
        Err(EditFailure::Store(e)) => {
            assert!(e.message.starts_with("not saved ("), "{e}");
            assert!(e.message.ends_with("; nothing was changed"), "{e}");
        }
        other => panic!("expected a store failure, got {other:?}"),
    }
    assert_eq!(s.buffer(Target::Mdi).text(), "A\nB\n");
    assert!(s
        .set_tcode(21, Some(999))
        .unwrap_err()
        .starts_with("not saved ("));
    assert_eq!(s.magazine().tcodes.tool_in(21), None);
    // Room again: the next change saves everything.
    common::limit_file_size(libc::RLIM_INFINITY);
    s.edit(Target::Mdi, "IE*", None).unwrap();
    println!("\nchild done");
}

#[test]
fn stores_open_on_a_full_disk_and_refuse_changes_until_there_is_room() {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("store-diskfull-open");
    let _ = std::fs::remove_dir_all(&d);
    {
        let (mut s, _) = Stores::open(&d, 24).unwrap();
        for l in ["IA*", "IB*", "IC*"] {
            s.edit(Target::Mdi, l, None).unwrap();
        }
    }
    // A torn last record (cut in its first copy), as a crash leaves it.
    let j = std::fs::read(d.join("journal.log")).unwrap();
    std::fs::write(d.join("journal.log"), &j[..j.len() - 30]).unwrap();
    common::run_child(
        "child_opens_on_a_full_disk",
        &[(CHILD_OPEN_DIR, d.as_os_str())],
        false,
    );
    let (s, w) = Stores::open(&d, 24).unwrap();
    assert!(w.is_empty(), "{w:?}");
    assert_eq!(s.buffer(Target::Mdi).text(), "A\nB\nE\n");
    assert_eq!(s.magazine().tcodes.tool_in(21), None);
}

/// The child: a console whose disk fills up; an edit is refused, and so is the message log.
#[test]
fn child_console_on_a_full_disk() {
    if std::env::var_os(CHILD_CONSOLE).is_none() {
        return;
    }
    let mut c = common::open("diskfull-console");
    let before = c.frame_text();
    common::limit_file_size(1);
    common::type_line(&mut c, "IG00 X1*");
    let shown = c.frame_text();
    let joined: String = shown.lines().map(str::trim).collect::<Vec<_>>().join(" ");
    let refused = joined
        .find("not saved (")
        .unwrap_or_else(|| panic!("the refusal is not shown:\n{shown}"));
    let history = joined
        .find("the message history was not saved")
        .unwrap_or_else(|| panic!("the history failure is not shown:\n{shown}"));
    assert!(refused < history, "the refusal comes first:\n{shown}");
    // The program is as it was: its first line is still the first line shown.
    assert!(shown.contains(" 1 >▌DA1 = (200, 0, -450)*"), "{shown}");
    assert!(before.contains(" 1 >▌DA1 = (200, 0, -450)*"), "{before}");
    println!("\nchild done");
}

/// Issue 20, item 15: on a full disk the operator sees that the edit was refused, first, and
/// then that the message history could not be saved either.
#[test]
fn a_refused_edit_is_shown_before_the_history_failure() {
    common::run_child(
        "child_console_on_a_full_disk",
        &[(CHILD_CONSOLE, std::ffi::OsStr::new("1"))],
        false,
    );
}

const CHILD_MOTION: &str = "NOVANC_DISKFULL_MOTION";

/// The child: on a full disk neither machine moves an axis its position memory cannot follow.
#[test]
fn child_motion_on_a_full_disk() {
    if std::env::var_os(CHILD_MOTION).is_none() {
        return;
    }
    use novanc::panel_model::{Axis, OpMode, PanelEvent};
    let mut c = common::open("diskfull-motion");
    let mut l = common::open_citizen(&common::temp_dir("diskfull-motion-lathe"));
    let posts = l.tips();
    common::limit_file_size(1);
    for ev in [
        PanelEvent::Op(OpMode::Continuous),
        PanelEvent::Jog(Axis::X, 1),
    ] {
        c.handle(ev.clone());
        l.handle(ev);
    }
    assert!(
        c.message()
            .starts_with("jog refused: the position could not be kept: "),
        "{}",
        c.message()
    );
    assert!(
        l.message()
            .starts_with("jog refused: the tool posts' positions could not be stored: "),
        "{}",
        l.message()
    );
    c.handle(PanelEvent::Home);
    assert!(
        c.message()
            .starts_with("HOME refused: the position could not be kept"),
        "{}",
        c.message()
    );
    l.handle(PanelEvent::Home);
    assert!(
        l.message().starts_with("CH1 HOME refused: the tool posts'"),
        "{}",
        l.message()
    );
    l.handle(PanelEvent::Op(OpMode::Auto));
    l.handle(PanelEvent::Start);
    assert!(
        l.message().starts_with("START refused: the tool posts'"),
        "{}",
        l.message()
    );
    c.handle(PanelEvent::Op(OpMode::Auto));
    c.handle(PanelEvent::Start);
    assert!(
        c.message()
            .starts_with("START refused: the position could not be kept"),
        "{}",
        c.message()
    );
    c.handle(PanelEvent::WaitMs(500));
    l.handle(PanelEvent::WaitMs(500));
    assert_eq!(l.tips(), posts, "a lathe's post moved");
    assert_eq!(
        c.core().status().machine_pos,
        [0; 3],
        "the centre's axes moved"
    );
    println!("\nchild done");
}

/// Stop 61: an axis moves only once its position memory says it moves, on both machines; on a
/// full disk a jog, HOME and START are refused with the store's reason and nothing moves
/// (before, the centre moved and said the position could not be kept).
#[test]
fn no_axis_moves_that_the_position_memory_cannot_follow() {
    common::run_child(
        "child_motion_on_a_full_disk",
        &[(CHILD_MOTION, std::ffi::OsStr::new("1"))],
        false,
    );
}
