//! `novanc edit FILE -c 'CMDLINE' [-c ..] [--write]` (docs/cli.md), driven as a process.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn file(tag: &str, text: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("edit-cli");
    fs::create_dir_all(&d).unwrap();
    let p = d.join(format!("{tag}.ap"));
    fs::write(&p, text).unwrap();
    p
}

fn novanc(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_novanc"))
        .args(args)
        .output()
        .unwrap()
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
