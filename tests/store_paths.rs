//! The state directory's files and paths (issue 20): a symlink planted in the state directory
//! is never written through (`journal.log`, `lock`), a read-only state directory opens for
//! reading with every change refused, and a lock file that cannot be opened is named.
//!
//! The read-only cases run in a child process of this test binary (`NOVANC_PATHS_CHILD`),
//! as the user `nobody` when the tests run as root (root ignores file modes).

mod common;

use novanc::store::{Stores, Target};
use std::fs;
use std::path::Path;

#[test]
fn a_journal_symlink_is_not_appended_through() {
    let _serial = common::serial();
    let d = common::temp_dir("store-paths-journal-link");
    let state = d.join("state");
    let outside = d.join("outside.log");
    drop(Stores::open(&state, 24).unwrap());
    // The (empty) journal moved out and linked back: a valid journal with nothing to replay,
    // so open appends to it as it is.
    fs::rename(state.join("journal.log"), &outside).unwrap();
    std::os::unix::fs::symlink(&outside, state.join("journal.log")).unwrap();
    let before = fs::read(&outside).unwrap();
    {
        let (mut s, w) = Stores::open(&state, 24).unwrap();
        assert!(w.is_empty(), "{w:?}");
        for l in ["IA*", "IB*", "IC*"] {
            s.edit(Target::Mdi, l, None).unwrap();
        }
    }
    assert!(
        fs::read(&outside).unwrap() == before,
        "written through the link"
    );
    let (s, w) = Stores::open(&state, 24).unwrap();
    assert_eq!(s.buffer(Target::Mdi).text(), "A\nB\nC\n", "{w:?}");
    assert!(!fs::symlink_metadata(state.join("journal.log"))
        .unwrap()
        .file_type()
        .is_symlink());
}

#[test]
fn a_lock_symlink_is_refused_and_creates_nothing() {
    let _serial = common::serial();
    let d = common::temp_dir("store-paths-lock-link");
    let state = d.join("state");
    fs::create_dir_all(&state).unwrap();
    let target = d.join("created-by-lock");
    std::os::unix::fs::symlink(&target, state.join("lock")).unwrap();
    let e = Stores::open(&state, 24).err().unwrap().message;
    assert!(
        e.starts_with(&format!(
            "cannot open the lock file {}: ",
            state.join("lock").display()
        )) && e.contains("is a symbolic link"),
        "{e}"
    );
    assert!(
        fs::symlink_metadata(&target).is_err(),
        "the link's target was created"
    );
    assert_eq!(
        fs::read_dir(&state).unwrap().count(),
        1,
        "nothing was written"
    );
}

/// The child: opens the stores of a directory it cannot write and tries to change them.
#[test]
fn child_on_a_read_only_directory() {
    let Some((what, d)) = common::child_on() else {
        return;
    };
    match what.as_str() {
        "read-only" => {
            let (mut s, w) = Stores::open(&d, 24).unwrap();
            assert_eq!(s.buffer(Target::Mdi).text(), "A\nB\n", "{w:?}");
            assert!(
                w.iter()
                    .any(|w| w.contains("read-only") && w.contains("every change is refused")),
                "{w:?}"
            );
            let e = s.edit(Target::Mdi, "IC*", None).unwrap_err().to_string();
            assert!(
                e.starts_with("not saved (")
                    && e.contains("read-only")
                    && e.ends_with("; nothing was changed"),
                "{e}"
            );
            assert_eq!(s.buffer(Target::Mdi).text(), "A\nB\n");
            let e = s.new_program("NEW").unwrap_err().to_string();
            assert!(e.starts_with("not saved ("), "{e}");
            assert_eq!(s.program_names(), ["TABLEB"]);
        }
        "lock" => {
            let e = Stores::open(&d, 24).err().unwrap().message;
            assert!(
                e.starts_with(&format!(
                    "cannot open the lock file {}: ",
                    d.join("lock").display()
                )),
                "{e}"
            );
        }
        _ => panic!("unknown child {what:?}"),
    }
    println!("\nchild done");
}

fn run_child(what: &str, d: &Path) {
    common::run_child_on("child_on_a_read_only_directory", what, d, true);
}

/// A state directory nobody may write (no lock file in it either, and a journal to replay)
/// opens on what it holds; every change is refused; not a byte changes.
#[test]
fn a_read_only_state_directory_opens_for_reading() {
    let _serial = common::serial();
    for keep_lock in [false, true] {
        let d = common::temp_dir(if keep_lock {
            "store-paths-ro-lock"
        } else {
            "store-paths-ro"
        });
        let state = d.join("state");
        {
            let (mut s, _) = Stores::open(&state, 24).unwrap();
            s.edit(Target::Mdi, "IA*", None).unwrap();
            s.edit(Target::Mdi, "IB*", None).unwrap();
        }
        if !keep_lock {
            fs::remove_file(state.join("lock")).unwrap();
        }
        for e in fs::read_dir(&state).unwrap() {
            common::chmod(&e.unwrap().path(), 0o444);
        }
        common::chmod(&state, 0o555);
        common::chmod(&d, 0o755);
        let before = common::contents(&state);
        run_child("read-only", &state);
        assert_eq!(common::contents(&state), before, "the directory changed");
        common::chmod(&state, 0o755);
    }
}

/// A lock file this user cannot open (another user's, mode 600) is named in the refusal.
#[test]
fn an_unopenable_lock_file_is_named() {
    let _serial = common::serial();
    let d = common::temp_dir("store-paths-lock-owner");
    let state = d.join("state");
    drop(Stores::open(&state, 24).unwrap());
    common::chmod(&state.join("lock"), 0o000);
    common::chmod(&state, 0o777);
    run_child("lock", &state);
    common::chmod(&state, 0o755);
}

/// Item 5 through the stores: a symlink planted at a writer's temporary name (the program
/// times' `.program-times.tmp-PID`) is removed, never written through.
#[test]
fn a_symlink_planted_at_a_temporary_name_is_not_written_through() {
    let _serial = common::serial();
    let d = common::temp_dir("store-paths-temp-link");
    let state = d.join("state");
    let victim = d.join("victim");
    fs::write(&victim, "precious").unwrap();
    let (mut s, _) = Stores::open(&state, 24).unwrap();
    for name in ["program-times", "state.snap", "journal.log"] {
        let tmp = state.join(format!(".{name}.tmp-{}", std::process::id()));
        std::os::unix::fs::symlink(&victim, tmp).unwrap();
    }
    s.set_journal_limit(1);
    s.new_program("P1").unwrap();
    s.new_program("P2").unwrap();
    assert_eq!(fs::read_to_string(&victim).unwrap(), "precious");
    drop(s);
    let (s, _) = Stores::open(&state, 24).unwrap();
    assert_eq!(s.program_names(), ["P1", "P2", "TABLEB"]);
    assert!(s
        .program_list()
        .iter()
        .any(|p| p.name == "P2" && p.changed_s.is_some()));
}
