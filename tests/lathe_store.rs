//! The lathe's stores (`STATE/lathe-NAME/`, docs/lathe.md "Stores") under bad input and
//! faults (issue 20): a file that cannot be read is damage, never "missing" (it is kept aside,
//! said, and nothing the operator did not choose is written over it); a tool file with one
//! byte that is not UTF-8 is kept aside and said; a `parts` file with target 0 is damaged; a
//! machine name cannot leave the state directory; a read-only state directory opens for
//! reading with every change refused; a part target that cannot be stored is not taken.
//!
//! The read-only and the unreadable cases run in a child process of this test binary
//! (`NOVANC_LATHE_CHILD`), as the user `nobody` when the tests run as root; the full disk in
//! a child under a file size limit.

mod common;

use novanc::lathe::console::LatheConsole;
use novanc::lathe::desc::{parse, tool_line, LatheDesc, MachineDesc};
use novanc::panel_model::PanelEvent;
use novanc::store::lathe::{Counter, LatheStore, Program, CITIZEN_PROGRAMS};
use std::fs;
use std::path::{Path, PathBuf};

fn run_child(what: &str, d: &Path, unprivileged: bool) {
    common::run_child_on("child", what, d, unprivileged);
}

/// Makes `STATE/lathe-citizen/` hold the lathe's old store, as it was before the journal (the
/// program files its first open wrote), and nothing of the journaled store: the next open
/// migrates it.
fn old_store(state: &Path) -> PathBuf {
    let d = state.join("lathe-citizen");
    fs::create_dir_all(&d).unwrap();
    for f in ["state.snap", "journal.log"] {
        let _ = fs::remove_file(d.join(f));
    }
    for (i, (name, text)) in CITIZEN_PROGRAMS.iter().enumerate() {
        fs::write(
            d.join(format!("ch{}.prog", i + 1)),
            format!("{name}\n{text}"),
        )
        .unwrap();
    }
    d
}

/// Issue 22: an old lathe directory (whole files, no journal) is migrated into the journaled
/// store once: its programs, tools and counter are what the store opens with, they are
/// snapshotted, and the old files are not read again (a later change to them is ignored).
#[test]
fn an_old_lathe_directory_is_migrated_into_the_journal_once() {
    let _serial = common::serial();
    let state = common::temp_dir("lathe-store-migrate");
    let desc = LatheDesc::citizen();
    let d = old_store(&state);
    fs::write(d.join("ch2.prog"), "OLD2.NGC\nG0 X2\nM30\n").unwrap();
    let mut tools = desc.channels[2].tools.clone();
    tools[0].offset = [0.125, -0.5];
    tools[0].radius = 0.8;
    let text: String = tools.iter().map(|t| tool_line(t) + "\n").collect();
    fs::write(d.join("ch3.tools"), &text).unwrap();
    fs::write(d.join("parts"), "target 12\ncounts 4 4 3\n").unwrap();
    let want = |o: &novanc::store::lathe::Opened| {
        assert_eq!(o.programs[0].name, "SYSTEM1.NGC");
        assert_eq!(o.programs[1].name, "OLD2.NGC");
        assert_eq!(o.programs[1].text, "G0 X2\nM30\n");
        assert_eq!(o.tools[0], None);
        assert_eq!(o.tools[2].as_deref(), Some(&tools[..]));
        assert_eq!(
            o.counter,
            Counter {
                target: 12,
                counts: vec![4, 4, 3]
            }
        );
    };
    let o = LatheStore::open(&state, &desc).unwrap();
    assert!(o.warnings.is_empty(), "{:?}", o.warnings);
    want(&o);
    drop(o);
    assert!(d.join("state.snap").is_file() && d.join("journal.log").is_file());
    // Read once: the old files no longer count.
    fs::write(d.join("ch2.prog"), "LATER.NGC\n").unwrap();
    fs::write(d.join("parts"), "target 1\ncounts 0 0 0\n").unwrap();
    let mut o = LatheStore::open(&state, &desc).unwrap();
    assert!(o.warnings.is_empty(), "{:?}", o.warnings);
    want(&o);
    // Changes after the migration are journaled and replayed.
    o.store
        .save_counter(&Counter {
            target: 12,
            counts: vec![5, 4, 3],
        })
        .unwrap();
    drop(o);
    let o = LatheStore::open(&state, &desc).unwrap();
    assert_eq!(o.counter.counts, [5, 4, 3]);
}

/// Item 3: program files of the old store that cannot be read (a directory in its place, a
/// symlink loop, no permission) are never replaced by the embedded sample when migrated, and
/// nothing is written over them (issue 22: the journaled store never writes their names, so
/// the operator's program is stored even where a damaged file could not be kept aside).
#[test]
fn a_program_file_that_cannot_be_read_is_never_replaced_by_the_sample() {
    let _serial = common::serial();
    let state = common::temp_dir("lathe-store-unreadable");
    let desc = LatheDesc::citizen();
    let d = old_store(&state);
    fs::remove_file(d.join("ch1.prog")).unwrap();
    fs::create_dir(d.join("ch1.prog")).unwrap();
    fs::write(d.join("ch1.prog/inside"), "kept").unwrap();
    fs::remove_file(d.join("ch2.prog")).unwrap();
    std::os::unix::fs::symlink("ch2.prog", d.join("ch2.prog")).unwrap();
    let mut o = LatheStore::open(&state, &desc).unwrap();
    assert_eq!(
        o.programs[0].text, "",
        "channel 1 got a program it did not have"
    );
    assert_eq!(
        o.programs[1].text, "",
        "channel 2 got a program it did not have"
    );
    assert_eq!(o.warnings.len(), 2, "{:?}", o.warnings);
    assert!(
        o.warnings[0]
            .starts_with("channel 1: its program file ch1.prog is damaged (it cannot be read: ")
            && o.warnings[0].contains("it could not be kept aside")
            && o.warnings[0].ends_with("the channel starts empty"),
        "{}",
        o.warnings[0]
    );
    assert!(
        o.warnings[1].contains("ch2.prog is damaged (it cannot be read: ")
            && o.warnings[1].contains("it is kept as ch2.prog.bad-"),
        "{}",
        o.warnings[1]
    );
    let p = Program {
        name: "NEW.NGC".into(),
        text: "G0 X1\n".into(),
        dialect: None,
    };
    o.store.save_program(0, &p).unwrap();
    o.store.save_program(1, &p).unwrap();
    drop(o);
    let o = LatheStore::open(&state, &desc).unwrap();
    assert_eq!(o.programs[0], p);
    assert_eq!(o.programs[1], p);
    assert!(o.warnings.is_empty(), "{:?}", o.warnings);
    drop(o);
    // Nothing was written over either.
    assert_eq!(
        fs::read_to_string(d.join("ch1.prog/inside")).unwrap(),
        "kept"
    );
    assert!(fs::symlink_metadata(d.join("ch2.prog"))
        .unwrap()
        .file_type()
        .is_symlink());
    // No permission to read (as another user when the tests run as root).
    let state = common::temp_dir("lathe-store-unreadable-perm");
    let d = old_store(&state);
    fs::write(d.join("ch3.prog"), "MINE.NGC\nG0 X5\n").unwrap();
    common::chmod(&d.join("ch3.prog"), 0o000);
    common::chmod(&d, 0o777);
    for n in common::names(&d) {
        if n != "ch3.prog" {
            common::chmod(&d.join(n), 0o666);
        }
    }
    run_child("unreadable", &state, true);
    common::chmod(&d.join("ch3.prog"), 0o644);
    assert_eq!(
        fs::read_to_string(d.join("ch3.prog")).unwrap(),
        "MINE.NGC\nG0 X5\n"
    );
}

/// Item 4: one byte that is not UTF-8 in a tool file of the old store: kept aside and said,
/// with its place, when it is migrated.
#[test]
fn a_tool_file_with_a_byte_that_is_not_utf8_is_kept_aside_and_said() {
    let _serial = common::serial();
    let state = common::temp_dir("lathe-store-tools");
    let desc = LatheDesc::citizen();
    let d = old_store(&state);
    let mut tools = desc.channels[0].tools.clone();
    tools[0].offset[1] = -0.5;
    let path = d.join("ch1.tools");
    let mut b: Vec<u8> = tools
        .iter()
        .flat_map(|t| (tool_line(t) + "\n").into_bytes())
        .collect();
    let at = b.iter().position(|&c| c == b'r').unwrap();
    b[at] = 0xFF;
    fs::write(&path, &b).unwrap();
    let o = LatheStore::open(&state, &desc).unwrap();
    assert_eq!(o.tools[0], None);
    assert_eq!(o.warnings.len(), 1, "{:?}", o.warnings);
    let w = &o.warnings[0];
    assert!(
        w.starts_with(&format!(
            "channel 1: its tool file ch1.tools is damaged (1:{}: the file is not UTF-8 text: byte 0xFF",
            at + 1
        )) && w.contains("it is kept as ch1.tools.bad-")
            && w.contains("check the offsets on the OFS page before START"),
        "{w}"
    );
    let kept: Vec<String> = common::names(&d)
        .into_iter()
        .filter(|n| n.starts_with("ch1.tools.bad-"))
        .collect();
    assert_eq!(kept.len(), 1);
    assert_eq!(fs::read(d.join(&kept[0])).unwrap(), b);
    // The console shows it on screen at open.
    drop(o);
    let d = old_store(&state);
    fs::write(d.join("ch1.tools"), &b).unwrap();
    let (c, w) = LatheConsole::open(desc, &state, 20, 400, None).unwrap();
    assert_eq!(w.len(), 1);
    assert!(
        c.view().display.iter().any(|l| l.trim_end() == w[0]),
        "{:?}",
        c.view().display
    );
}

/// Item 17: a `parts` file of the old store with target 0 (or no target line) is damaged, not
/// taken, when it is migrated.
#[test]
fn a_parts_file_with_target_0_is_damaged() {
    let _serial = common::serial();
    let state = common::temp_dir("lathe-store-parts");
    let desc = LatheDesc::citizen();
    for (text, why) in [
        (
            "target 0\ncounts 0 0 0\n",
            "line 1: the target is not a number of parts from 1 to 999999",
        ),
        (
            "counts 1 1 1\n",
            "it lacks its 'target' or its 'counts' line",
        ),
        (
            "target 5\ncounts 1 1 1\ntarget 7\n",
            "line 3 is not one 'target N' and one 'counts ...' line",
        ),
    ] {
        let d = old_store(&state);
        fs::write(d.join("parts"), text).unwrap();
        let o = LatheStore::open(&state, &desc).unwrap();
        assert_eq!(
            o.counter,
            Counter {
                target: 5,
                counts: vec![0; 3]
            }
        );
        assert!(
            o.warnings.len() == 1
                && o.warnings[0]
                    .starts_with(&format!("the part counter file parts is damaged ({why})")),
            "{:?}",
            o.warnings
        );
    }
}

/// Item 16: a machine named with `/` or `..` is refused; nothing is made outside the state
/// directory.
#[test]
fn a_machine_name_cannot_leave_the_state_directory() {
    let _serial = common::serial();
    let d = common::temp_dir("lathe-store-name");
    let state = d.join("a/b/c/state");
    fs::create_dir_all(&state).unwrap();
    let text = fs::read_to_string("machines/citizen.machine")
        .unwrap()
        .replacen("machine citizen", "machine a/../../../../esc", 1);
    let e = parse(&text).unwrap_err();
    assert!(
        e.contains(": machine name 'a/../../../../esc' cannot name a file"),
        "{e}"
    );
    let mut desc = match parse(&text.replacen("a/../../../../esc", "ok", 1)) {
        Ok(MachineDesc::Lathe(l)) => l,
        other => panic!("{other:?}"),
    };
    for bad in ["a/../../../../esc", "..", ".hidden", "", "a\0b"] {
        desc.name = bad.to_string();
        let e = LatheStore::open(&state, &desc).unwrap_err();
        assert!(e.starts_with("machine name '"), "{e}");
    }
    assert_eq!(common::names(&d), ["a"]);
    assert_eq!(common::names(&state), Vec::<String>::new());
}

/// Item 17: a read-only lathe directory opens for reading; every change is refused.
#[test]
fn a_read_only_lathe_directory_opens_for_reading() {
    let _serial = common::serial();
    let state = common::temp_dir("lathe-store-ro");
    let desc = LatheDesc::citizen();
    let mut o = LatheStore::open(&state, &desc).unwrap();
    o.store
        .save_counter(&Counter {
            target: 7,
            counts: vec![2, 2, 1],
        })
        .unwrap();
    drop(o);
    let d = state.join("lathe-citizen");
    fs::remove_file(d.join("lock")).unwrap();
    for n in common::names(&d) {
        common::chmod(&d.join(n), 0o444);
    }
    common::chmod(&d, 0o555);
    let before = common::contents(&d);
    run_child("read-only", &state, true);
    assert!(common::contents(&d) == before, "the directory changed");
    common::chmod(&d, 0o755);
}

/// Item 15: a part target that cannot be stored (a full disk) is not taken: the display keeps
/// the old target, and so does the next start.
#[test]
fn a_part_target_that_cannot_be_stored_is_not_taken() {
    let _serial = common::serial();
    let state = common::temp_dir("lathe-store-target");
    drop(LatheStore::open(&state, &LatheDesc::citizen()).unwrap());
    run_child("full", &state, false);
    let o = LatheStore::open(&state, &LatheDesc::citizen()).unwrap();
    assert_eq!(o.counter.target, 5);
}

/// The children.
#[test]
fn child() {
    let Some((what, state)) = common::child_on() else {
        return;
    };
    let desc = LatheDesc::citizen();
    match what.as_str() {
        "unreadable" => {
            let o = LatheStore::open(&state, &desc).unwrap();
            assert_eq!(
                o.programs[2].text, "",
                "channel 3 got a program it did not have"
            );
            assert!(
                o.warnings.len() == 1
                    && o.warnings[0].starts_with("channel 3: its program file ch3.prog is damaged (it cannot be read: Permission denied"),
                "{:?}",
                o.warnings
            );
        }
        "read-only" => {
            let mut o = LatheStore::open(&state, &desc).unwrap();
            assert_eq!(o.counter.target, 7);
            assert_eq!(o.programs[0].name, "SYSTEM1.NGC");
            assert!(
                o.warnings.len() == 1
                    && o.warnings[0].contains("is read-only")
                    && o.warnings[0].contains("every change is refused"),
                "{:?}",
                o.warnings
            );
            let mut next = o.counter.clone();
            next.counts[0] += 1;
            let e = o.store.save_counter(&next).unwrap_err();
            assert!(
                e.starts_with(
                    "the part counter could not be stored: not saved (the state directory is read-only: "
                ),
                "{e}"
            );
            let e = o.store.save_program(0, &o.programs[1]).unwrap_err();
            assert!(e.contains("read-only"), "{e}");
        }
        "full" => {
            let (mut c, w) = LatheConsole::open(desc, &state, 20, 160, None).unwrap();
            assert!(w.is_empty(), "{w:?}");
            common::limit_file_size(1);
            c.handle(PanelEvent::Target(9));
            let v = c.view();
            assert!(v.title.contains("PARTS 0/5"), "{}", v.title);
            let shown = v.display.join("\n");
            assert!(
                shown.contains("the part counter could not be stored")
                    && shown.contains("the target is not changed"),
                "{shown}"
            );
        }
        _ => panic!("unknown child {what:?}"),
    }
    println!("\nchild done");
}

/// Issue 22: a description whose channel count changed (the machine file edited from three
/// channels to two) opens the journaled store without a panic: what does not fit the machine
/// (channel 3's program, a counter of three counts) is said and set aside, what fits is kept,
/// and the snapshot is kept aside (read as damaged: the operator sees what was dropped).
#[test]
fn a_store_of_three_channels_opened_with_two_says_what_does_not_fit() {
    let _serial = common::serial();
    let state = common::temp_dir("lathe-store-channels");
    let desc = LatheDesc::citizen();
    let mut o = LatheStore::open(&state, &desc).unwrap();
    let p = Program {
        name: "TWO.NGC".into(),
        text: "G0 X2\n".into(),
        dialect: None,
    };
    o.store.save_program(1, &p).unwrap();
    drop(o);
    drop(LatheStore::open(&state, &desc).unwrap()); // into the snapshot
    let mut two = desc.clone();
    two.channels.truncate(2);
    let o = LatheStore::open(&state, &two).unwrap();
    assert_eq!(o.programs.len(), 2);
    assert_eq!(o.programs[1], p);
    assert_eq!(o.counter.counts, [0, 0]);
    assert_eq!(o.warnings.len(), 2, "{:?}", o.warnings);
    assert!(o.warnings[1].contains("the journal was replayed onto what could be read"));
    let w = &o.warnings[0];
    assert!(
        !w.contains("generation is unknown")
            && w.contains("the header says 3 channels; this lathe has 2")
            && w.contains("channel 3 is not one of this lathe's 2")
            && w.contains("the part counter (it starts at 0 of 5)")
            && w.contains("It is kept as state.snap.bad-"),
        "{w}"
    );
}
