//! What the fuzz command (`tests/fuzz/main.rs`) found, each as a regression test with the seed
//! that found it. Findings about the language's limits and messages are in
//! `tests/translate_limits.rs` and `tests/bad_input.rs`.

mod common;

use novanc::store::{Stores, Target};

fn fresh(tag: &str) -> std::path::PathBuf {
    common::temp_dir(&format!("findings-{tag}"))
}

/// tape:0xd4262d85334ed688: a tape value with more than three decimals (diameter 0.0004) was
/// printed in the tool file as `0.0`, which is not a valid record, so after TOOL DATA READ no
/// revision of the tool file was accepted, and values were silently rounded.
#[test]
fn a_tape_value_with_many_decimals_is_kept_and_the_tool_file_stays_revisable() {
    let d = fresh("decimals");
    let (mut s, _) = Stores::open(&d, 24).unwrap();
    let tape = "00106  DR  0.0004  150.0  40.0  1200  120.1234  3.0\n";
    s.tool_read(tape, "t.tt").unwrap();
    let t02 = s.magazine().tools.get(2).cloned().unwrap();
    assert_eq!((t02.diameter, t02.feed), (0.0004, 120.1234));
    assert!(s
        .buffer(Target::ToolFile)
        .text()
        .contains("T02 00106  DR   0.0004"));
    // Revise another tool: the whole tool file is validated, T02's line included.
    s.edit(Target::ToolFile, "S00610$C400.0$410.0", None)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.magazine().tools.get(1).unwrap().speed, 410.0);
    assert_eq!(s.magazine().tools.get(2).unwrap().diameter, 0.0004);
    drop(s);
    let (s, _) = Stores::open(&d, 24).unwrap();
    assert_eq!(s.magazine().tools.get(2).cloned().unwrap(), t02);
    let _ = std::fs::remove_dir_all(&d);
}

/// gcode-program:0xd14c127aa8230984 and 0xb31776ed46eecc68: the G-code reader printed a NUL or
/// an ESC raw in its message (`a word letter was expected, not '\0'`), which a terminal shows
/// as nothing or acts on; it now names the character by its code point, as the source
/// language does (docs/language.md, *Limits*).
#[test]
fn a_control_character_in_gcode_is_named_not_printed() {
    let first_error = |src: &str| {
        common::gcode_source(src)
            .find_map(|r| r.err())
            .map(|e| e.to_string())
    };
    assert_eq!(
        first_error("G0 X1\n\u{0}\n").as_deref(),
        Some("2:1: U+0000 (a control character) is not part of the language (outside a comment)")
    );
    assert_eq!(
        first_error("G0 X\u{1b}[2J\n").as_deref(),
        Some("1:5: U+001B (a control character) is not part of the language (outside a comment)")
    );
}

/// gcode-program:0xd52d3b0b0ba488d6, 0xe5ef9760d22862a2 and 0xcfdc141d99389558 (stop 49): a
/// G38.2 whose target is beyond the travel was refused, and the next read answered the probe
/// the refused line had asked for, a second error (`the probe move ended without contact`)
/// after the refusal. A refused line asks the machine nothing; the source ends at its error.
#[test]
fn a_refused_probe_line_is_not_answered_after_its_refusal() {
    for src in [
        "G38.2 M9 X99999999999999999999 F300 G40\nG0 X1\nM30\n",
        "F300 Z2 G20 G38.2\nG0 X1\nM30\n",
    ] {
        let all: Vec<_> = common::gcode_source(src).collect();
        assert_eq!(all.len(), 1, "{src}: {all:?}");
        let e = all[0].as_ref().unwrap_err().to_string();
        assert!(e.contains("beyond the"), "{e}");
    }
}

/// stores:0xb7c2ff5f060ceddc (stop 52): an editor insertion in front of a tool file line made
/// the refusal quote the whole line it found (`found '106106…'`, thousands of characters); it
/// is now quoted as every message quotes text, cut with its length.
#[test]
fn a_tool_file_line_in_a_refusal_is_cut_as_every_quoted_text() {
    let d = fresh("toolfile-quote");
    let (mut s, _) = Stores::open(&d, 24).unwrap();
    let e = s
        .edit(Target::ToolFile, &format!("I{}$", "106".repeat(400)), None)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("line 1 must start with T01 (found '106106"),
        "{e}"
    );
    assert!(
        e.contains("…(1203 characters)") && e.chars().count() < 300,
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&d);
}
