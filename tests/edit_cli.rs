//! `novanc edit FILE -c 'CMDLINE' [-c ..] [--write]` (docs/cli.md), driven as a process.

mod common;

use common::novanc;

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

fn file(tag: &str, text: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("edit-cli");
    fs::create_dir_all(&d).unwrap();
    let p = d.join(format!("{tag}.ap"));
    fs::write(&p, text).unwrap();
    p
}

fn s(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

const PROG: &str = "DA1 = (200, 0, -450)\nP1 = (150, 130)\nDRL, 106/DP20/PAT1\n";

#[test]
fn y_output_goes_to_stdout_and_the_file_is_untouched_without_write() {
    let p = file("y", PROG);
    let o = novanc(&["edit", p.to_str().unwrap(), "-c", "L2Y", "-c", "SDRL$Y"]);
    assert_eq!(o.status.code(), Some(0), "{}", s(&o.stderr));
    assert_eq!(
        s(&o.stdout),
        "P1 = (150, 130)\nDRL, 106/DP20/PAT1\n, 106/DP20/PAT1\n"
    );
    assert_eq!(s(&o.stderr), "");
    assert_eq!(fs::read_to_string(&p).unwrap(), PROG);
}

#[test]
fn write_replaces_the_file_with_the_result() {
    let p = file("w", PROG);
    let o = novanc(&[
        "edit",
        p.to_str().unwrap(),
        "-c",
        "SDRL, $C106$105",
        "-c",
        "-99LK",
        "--write",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", s(&o.stderr));
    assert_eq!(
        fs::read_to_string(&p).unwrap(),
        "P1 = (150, 130)\nDRL, 105/DP20/PAT1\n"
    );
    assert_eq!(
        fs::read_dir(p.parent().unwrap())
            .unwrap()
            .filter(|e| {
                e.as_ref()
                    .unwrap()
                    .file_name()
                    .to_string_lossy()
                    .contains(".tmp-")
            })
            .count(),
        0,
        "no temporary file left"
    );
}

#[test]
fn a_failing_command_line_exits_1_and_leaves_the_file_unchanged() {
    let p = file("fail", PROG);
    let o = novanc(&[
        "edit",
        p.to_str().unwrap(),
        "-c",
        "Ixx",
        "-c",
        "LSxyz",
        "-c",
        "IN1*",
        "--write",
    ]);
    assert_eq!(o.status.code(), Some(1));
    let err = s(&o.stderr);
    assert!(
        err.starts_with("novanc edit: command line 2: command 2 'Sxyz': "),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1, "{err}");
    assert_eq!(fs::read_to_string(&p).unwrap(), PROG);
}

#[test]
fn a_pointer_off_the_buffer_is_an_error() {
    let p = file("off", PROG);
    let o = novanc(&["edit", p.to_str().unwrap(), "-c", "-1M", "--write"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        s(&o.stderr).starts_with("novanc edit: command line 1: command 1 '-1M': "),
        "{}",
        s(&o.stderr)
    );
    assert_eq!(fs::read_to_string(&p).unwrap(), PROG);
}

#[test]
fn help_and_usage_errors() {
    let o = novanc(&["edit", "--help"]);
    assert_eq!(o.status.code(), Some(0));
    assert!(s(&o.stdout).starts_with("usage: novanc edit FILE -c 'CMDLINE'"));
    let o = novanc(&["edit", "-c", "L"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(s(&o.stderr).contains("no FILE given"), "{}", s(&o.stderr));
    let o = novanc(&["edit", "a", "b"]);
    assert_eq!(o.status.code(), Some(2));
    let o = novanc(&["edit", "x.ap", "--frob"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(s(&o.stderr).contains("unknown option '--frob'"));
    let o = novanc(&["edit", "/nonexistent/x.ap", "-c", "L"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(s(&o.stderr).starts_with("novanc edit: cannot read /nonexistent/x.ap"));
}

#[test]
fn a_file_that_is_not_text_is_refused_unchanged() {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("edit-cli");
    fs::create_dir_all(&d).unwrap();
    let p = d.join("bin.ap");
    fs::write(&p, b"\xff\xfe\x00").unwrap();
    let o = novanc(&["edit", p.to_str().unwrap(), "-c", "Ix", "--write"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        s(&o.stderr).contains("bin.ap:1:1: the file is not UTF-8 text: byte 0xFF at byte offset 0"),
        "{}",
        s(&o.stderr)
    );
    assert_eq!(fs::read(&p).unwrap(), b"\xff\xfe\x00");
}

/// A fresh directory of its own (the tests run in parallel).
fn own_dir(tag: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("edit-cli-{tag}"));
    let _ = fs::remove_dir_all(&d);
    fs::create_dir_all(&d).unwrap();
    d
}

/// The pid of a process that has ended.
fn dead_pid() -> u32 {
    let mut c = Command::new("true").spawn().unwrap();
    let pid = c.id();
    c.wait().unwrap();
    pid
}

#[test]
fn write_goes_through_a_symlink_and_keeps_hard_links() {
    use std::os::unix::fs::MetadataExt;
    let d = own_dir("links");
    let real = d.join("real.ap");
    fs::write(&real, PROG).unwrap();
    let link = d.join("link.ap");
    std::os::unix::fs::symlink("real.ap", &link).unwrap();
    let o = novanc(&["edit", link.to_str().unwrap(), "-c", "IN1*", "--write"]);
    assert_eq!(o.status.code(), Some(0), "{}", s(&o.stderr));
    assert!(fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
    assert_eq!(fs::read_to_string(&real).unwrap(), format!("N1\n{PROG}"));
    // A second name for the same file: both see every write, through either name.
    let hard = d.join("hard.ap");
    fs::hard_link(&real, &hard).unwrap();
    let ino = fs::metadata(&real).unwrap().ino();
    for (p, cmd) in [(&hard, "IN2*"), (&link, "IN3*"), (&real, "K")] {
        let o = novanc(&["edit", p.to_str().unwrap(), "-c", cmd, "--write"]);
        assert_eq!(o.status.code(), Some(0), "{}", s(&o.stderr));
    }
    let want = format!("N2\nN1\n{PROG}");
    assert_eq!(fs::read_to_string(&real).unwrap(), want);
    assert_eq!(fs::read_to_string(&hard).unwrap(), want);
    assert_eq!(fs::metadata(&hard).unwrap().ino(), ino);
    assert_eq!(fs::metadata(&hard).unwrap().nlink(), 2);
    assert_eq!(common::names(&d), ["hard.ap", "link.ap", "real.ap"]);
}

#[test]
fn temporary_files_of_killed_writes_are_cleaned_up() {
    let d = own_dir("stale");
    let p = d.join("f.ap");
    fs::write(&p, PROG).unwrap();
    // What nine killed 31 MB writes left behind (their processes are gone).
    for _ in 0..9 {
        fs::write(d.join(format!(".f.ap.tmp-{}", dead_pid())), "partial").unwrap();
    }
    let o = novanc(&["edit", p.to_str().unwrap(), "-c", "IN1*", "--write"]);
    assert_eq!(o.status.code(), Some(0), "{}", s(&o.stderr));
    assert_eq!(common::names(&d), ["f.ap"]);

    // Kill real writes of a 4 MB file at random moments: the file is the old text or the new,
    // and no write leaves more than its own temporary file, which the next write removes.
    let big: String = (0..200_000).map(|i| format!("N{i:06} G01 X1\n")).collect();
    fs::write(&p, &big).unwrap();
    let mut seed = 0x5EED_0008u64;
    for round in 0..6u64 {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let mut c = common::novanc_command()
            .args(["edit", p.to_str().unwrap(), "-c", "IN1*", "--write"])
            .spawn()
            .unwrap();
        std::thread::sleep(std::time::Duration::from_micros((seed >> 33) % 40_000));
        let _ = c.kill();
        let _ = c.wait();
        let now = fs::read_to_string(&p).unwrap();
        assert!(
            now == big || now == format!("N1\n{big}"),
            "round {round}: torn file"
        );
        fs::write(&p, &big).unwrap();
        assert!(
            common::names(&d).len() <= 2,
            "round {round}: {:?}",
            common::names(&d)
        );
    }
    let o = novanc(&["edit", p.to_str().unwrap(), "-c", "L", "--write"]);
    assert_eq!(o.status.code(), Some(0), "{}", s(&o.stderr));
    assert_eq!(common::names(&d), ["f.ap"]);
}

#[test]
fn an_interrupted_rewrite_in_place_is_finished_by_the_next_edit() {
    let d = own_dir("torn");
    let p = d.join("f.ap");
    fs::write(&p, "N1 G00\nN2 X1").unwrap(); // cut short by the kill
    fs::hard_link(&p, d.join("g.ap")).unwrap();
    let left = d.join(format!(".f.ap.rewrite-{}", dead_pid()));
    fs::write(&left, "N1 G00\nN2 X10\nN3 Y20\n").unwrap();
    // The next edit (through the other name) copies the whole text in first, keeping what the
    // file held, says so, then makes its own edit.
    let o = novanc(&[
        "edit",
        d.join("g.ap").to_str().unwrap(),
        "-c",
        "IN0*",
        "--write",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", s(&o.stderr));
    let e = s(&o.stderr);
    assert!(
        e.starts_with("novanc edit: warning: an earlier 'novanc edit --write' (process ")
            && e.contains("was killed while rewriting")
            && e.contains("is now in the file, and what the file held is kept as f.ap.bad-"),
        "{e}"
    );
    assert_eq!(
        fs::read_to_string(&p).unwrap(),
        "N0\nN1 G00\nN2 X10\nN3 Y20\n"
    );
    let n = common::names(&d);
    assert_eq!(n.len(), 3, "{n:?}");
    assert!(n[1].starts_with("f.ap.bad-"), "{n:?}");
    assert_eq!(fs::read_to_string(d.join(&n[1])).unwrap(), "N1 G00\nN2 X1");
    // One whose copy had finished is removed quietly, also without --write.
    fs::write(&left, "N0\nN1 G00\nN2 X10\nN3 Y20\n").unwrap();
    let o = novanc(&["edit", p.to_str().unwrap(), "-c", "Y"]);
    assert_eq!(o.status.code(), Some(0));
    assert_eq!(s(&o.stderr), "");
    assert!(!left.exists());
}

/// Issue 20, items 1 and 2: twenty `novanc edit --write` of one file at once, on a file with
/// one name and on one with two hard links. They take turns on the file's lock: every one
/// exits 0, every edit is in the file, and the file is whole (no NUL, no line cut short).
#[test]
fn concurrent_writes_of_one_file_take_turns_and_lose_no_edit() {
    let body: String = (0..1000).map(|i| format!("N{i:04} G01 X{i}\n")).collect();
    for hard in [false, true] {
        let d = own_dir(if hard { "race-hard" } else { "race" });
        let p = d.join("f.ap");
        fs::write(&p, &body).unwrap();
        if hard {
            fs::hard_link(&p, d.join("g.ap")).unwrap();
        }
        let kids: Vec<_> = (0..20)
            .map(|i| {
                common::novanc_command()
                    .args(["edit", p.to_str().unwrap(), "-c"])
                    .arg(format!("IE{i:02}*"))
                    .arg("--write")
                    .stdout(std::process::Stdio::null())
                    .stderr(std::process::Stdio::piped())
                    .spawn()
                    .unwrap()
            })
            .collect();
        for k in kids {
            let o = k.wait_with_output().unwrap();
            assert_eq!(o.status.code(), Some(0), "{}", s(&o.stderr));
        }
        let text = fs::read_to_string(&p).unwrap();
        assert!(!text.contains('\0'), "hard {hard}: NUL bytes in the file");
        let mut edits: Vec<&str> = text.lines().take(20).collect();
        edits.sort_unstable();
        let want: Vec<String> = (0..20).map(|i| format!("E{i:02}")).collect();
        assert_eq!(edits, want, "hard {hard}: an edit is missing");
        assert!(text.ends_with(&body) && text.len() == body.len() + 20 * 4);
        if hard {
            assert_eq!(fs::read_to_string(d.join("g.ap")).unwrap(), text);
            assert_eq!(common::names(&d), ["f.ap", "g.ap"]);
        } else {
            assert_eq!(common::names(&d), ["f.ap"]);
        }
    }
}

/// A pipe or a directory given as FILE is refused at once, never waited on.
#[test]
fn a_pipe_or_a_directory_is_refused_not_waited_on() {
    let d = own_dir("special");
    let fifo = d.join("pipe.ap");
    assert!(Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    for p in [&fifo, &d] {
        // `timeout` ends a novanc that waits (exit 124) instead of hanging the test.
        let o = Command::new("timeout")
            .arg("10")
            .arg(env!("CARGO_BIN_EXE_novanc"))
            .args(["edit", p.to_str().unwrap(), "-c", "IX*", "--write"])
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(1), "{}", s(&o.stderr));
        assert!(
            s(&o.stderr).trim_end().ends_with(": not a regular file"),
            "{}",
            s(&o.stderr)
        );
    }
}
