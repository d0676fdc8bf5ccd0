//! Bad input at the command line (issue 15): arguments that are not UTF-8, files with a byte
//! order mark, CR line ends, bad bytes and control characters, huge tokens, and the tape values
//! the language refuses. Each reproducer runs the binary and checks the message, the exit code,
//! and that nothing was written.

mod common;

use std::ffi::OsStr;
use std::fs;
use std::os::unix::ffi::OsStrExt;
use std::path::PathBuf;
use std::process::Output;

/// A fresh directory of this test process.
fn dir(tag: &str) -> PathBuf {
    common::temp_dir(&format!("bad-input-{tag}"))
}

fn novanc_in(cwd: &PathBuf, args: &[&OsStr]) -> Output {
    common::novanc_command()
        .args(args)
        .current_dir(cwd)
        .env("NOVANC_STATE", cwd.join("default-state"))
        .output()
        .unwrap()
}

fn os(b: &[u8]) -> &OsStr {
    OsStr::from_bytes(b)
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// Every entry of a directory, for "nothing was created".
fn listing(d: &PathBuf) -> Vec<Vec<u8>> {
    let mut v: Vec<Vec<u8>> = fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name().as_bytes().to_vec())
        .collect();
    v.sort();
    v
}

#[test]
fn an_argument_that_is_not_utf8_is_a_usage_error_naming_it() {
    let d = dir("args");
    fs::write(
        d.join(OsStr::from_bytes(b"caf\xe9.ap")),
        "DA1 = (0, 0, -100)\n",
    )
    .unwrap();
    fs::write(d.join("t.ap"), "N1 G00*\n").unwrap();
    let before = listing(&d);

    let o = novanc_in(&d, &[os(b"translate"), os(b"caf\xe9.ap")]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    assert_eq!(
        text(&o.stderr),
        "novanc: argument 2 'caf\\xE9.ap' is not UTF-8 text; novanc takes its arguments, file names included, as UTF-8 (rename the file)\n"
    );
    assert!(o.stdout.is_empty());

    let o = novanc_in(
        &d,
        &[
            os(b"edit"),
            os(b"t.ap"),
            os(b"-c"),
            os(b"I\xff"),
            os(b"--write"),
        ],
    );
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    assert!(
        text(&o.stderr).starts_with("novanc: argument 4 'I\\xFF' is not UTF-8 text"),
        "{}",
        text(&o.stderr)
    );
    assert_eq!(fs::read_to_string(d.join("t.ap")).unwrap(), "N1 G00*\n");

    let o = novanc_in(&d, &[os(b"--state"), os(b"st\xff")]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o.stderr));
    assert!(
        text(&o.stderr).starts_with("novanc: argument 2 'st\\xFF' is not UTF-8 text"),
        "{}",
        text(&o.stderr)
    );
    assert_eq!(listing(&d), before, "no state directory was made");
}

/// `novanc translate` on a file with these bytes.
fn translate(tag: &str, bytes: &[u8]) -> Output {
    let d = dir(tag);
    fs::write(d.join("p.ap"), bytes).unwrap();
    novanc_in(&d, &[os(b"translate"), os(b"p.ap")])
}

const TABLEB: &str = include_str!("../programs/tableb.ap");
const TABLEB_ISO: &str = include_str!("golden/tableb.iso");

#[test]
fn a_byte_order_mark_and_cr_line_ends_are_read_as_program_read_reads_them() {
    let mut bom = "\u{feff}".as_bytes().to_vec();
    bom.extend_from_slice(TABLEB.as_bytes());
    let o = translate("bom", &bom);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    assert_eq!(text(&o.stdout), TABLEB_ISO);

    let o = translate("cr", TABLEB.replace('\n', "\r").as_bytes());
    assert_eq!(o.status.code(), Some(0), "{}", text(&o.stderr));
    assert_eq!(text(&o.stdout), TABLEB_ISO);

    let o = translate("crlf", TABLEB.replace('\n', "\r\n").as_bytes());
    assert_eq!(text(&o.stdout), TABLEB_ISO);

    // A byte order mark anywhere else is named.
    let o = translate(
        "bom2",
        "DA1 = (0, 0, -100)\n\u{feff}P1 = (1, 2)\n".as_bytes(),
    );
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        text(&o.stderr),
        "p.ap:2:1: U+FEFF (a byte order mark) is not part of the language\n"
    );
    assert!(o.stdout.is_empty());
}

#[test]
fn a_file_that_is_not_utf8_is_refused_with_line_column_and_byte() {
    let o = translate("latin1", b"DA1 = (200, 0, -450)\r\nP1 = (1, \xe92)\n");
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        text(&o.stderr),
        "p.ap:2:10: the file is not UTF-8 text: byte 0xE9 at byte offset 31 (save it as UTF-8)\n"
    );
    assert!(o.stdout.is_empty());
}

#[test]
fn control_characters_are_named_not_printed() {
    let o = translate("nul", b"DA1 = (200, 0, -450)\nP1 = (1,\x002)\n");
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(
        text(&o.stderr),
        "p.ap:2:9: U+0000 (a control character) is not part of the language\n"
    );
    let o = translate("esc", b"P1 = (1, 2) \x1b[2J\n");
    assert_eq!(
        text(&o.stderr),
        "p.ap:1:13: U+001B (a control character) is not part of the language\n"
    );
}

#[test]
fn a_huge_token_gives_a_short_message() {
    // A 1 MB number: the line is refused by its length, in a line-sized message.
    let o = translate(
        "mb-line",
        format!("GO, {}, 0, 0\n", "9".repeat(1 << 20)).as_bytes(),
    );
    assert_eq!(o.status.code(), Some(1));
    let e = text(&o.stderr);
    assert!(e.len() < 200, "{e}");
    assert_eq!(
        e,
        "p.ap:1:10001: the line is 1048586 characters long; a line holds at most 10000 (split the statement: a MAC can hold part of a list)\n"
    );
    // Within the line limit, a long number or word is quoted cut.
    let o = translate(
        "long-num",
        format!("GO, {}, 0, 0\n", "9".repeat(9000)).as_bytes(),
    );
    assert_eq!(
        text(&o.stderr),
        format!(
            "p.ap:1:5: {}…(9000 characters) is too large (numbers go up to 1000000000)\n",
            "9".repeat(40)
        )
    );
    let o = translate(
        "long-word",
        format!("GO, {}\n", "Q".repeat(9000)).as_bytes(),
    );
    assert_eq!(
        text(&o.stderr),
        format!(
            "p.ap:1:5: expected x, found '{}…(9000 characters)'\n",
            "Q".repeat(40)
        )
    );
}

#[test]
fn a_tape_value_the_language_refuses_is_refused_on_the_tape() {
    let d = dir("tape");
    fs::write(d.join("p.ap"), TABLEB).unwrap();
    let sample = include_str!("../tooldata/tools.tt");
    for (bad, why) in [
        (
            "1e308",
            "'1e308' is not a number (digits with at most one decimal point, no exponent)",
        ),
        ("inf", "'inf' is not a number"),
        (
            "1234567890",
            "1234567890 is too large (numbers go up to 1000000000)",
        ),
        ("0x10", "'0x10' is not a number"),
    ] {
        let tape = sample.replacen("150.0", bad, 1);
        assert_ne!(tape, sample);
        fs::write(d.join("t.tt"), &tape).unwrap();
        let o = novanc_in(
            &d,
            &[os(b"translate"), os(b"p.ap"), os(b"--tools"), os(b"t.tt")],
        );
        assert_eq!(o.status.code(), Some(1), "{bad}");
        let e = text(&o.stderr);
        assert!(e.starts_with("t.tt:") && e.contains(why), "{bad}: {e}");
        assert!(o.stdout.is_empty());
    }
}
