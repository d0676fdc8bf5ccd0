//! Unit tests of every command and its edges (docs/editor.md).

use crate::{Buffer, ExecOptions, Outcome};

/// Runs `line` on a buffer of `text` with the pointer at `at`; returns the result and buffer.
fn run(text: &str, at: usize, line: &str) -> (Result<Outcome, crate::EditError>, Buffer) {
    let mut b = Buffer::from_text(text);
    b.set_pointer(at);
    let r = b.execute(line, &ExecOptions::default());
    (r, b)
}

/// Asserts `line` succeeds and leaves `text` with the pointer at `ptr`.
fn ok(text: &str, at: usize, line: &str, want: &str, ptr: usize) {
    let (r, b) = run(text, at, line);
    assert!(r.is_ok(), "{line}: {r:?}");
    assert_eq!((b.text().as_str(), b.pointer()), (want, ptr), "{line}");
}

/// Asserts `line` fails with `reason` and leaves the buffer as it was.
fn fails(text: &str, at: usize, line: &str, msg: &str) {
    let (r, b) = run(text, at, line);
    let e = r.expect_err(line);
    assert_eq!(e.to_string(), msg);
    assert_eq!((b.text().as_str(), b.pointer()), (text, at), "{line}");
}

const T: &str = "N1 G00\nN2 X10\nN3 Y20\n";

#[test]
fn l_moves_by_lines_and_stops_at_the_ends() {
    ok(T, 0, "L", T, 7);
    ok(T, 3, "2L", T, 14);
    ok(T, 3, "9L", T, 21);
    ok(T, 10, "0L", T, 7);
    ok(T, 10, "-L", T, 0);
    ok(T, 16, "-1L", T, 7);
    ok(T, 16, "-9L", T, 0);
    ok(T, 21, "L", T, 21);
    ok(T, 21, "-L", T, 14);
    ok(T, 0, "0L", T, 0);
    ok("", 0, "L-L0L", "", 0);
    ok("ab", 1, "L", "ab", 2);
}

#[test]
fn m_moves_by_chars_and_must_stay_in_the_buffer() {
    ok(T, 0, "5M", T, 5);
    ok(T, 5, "-5M", T, 0);
    ok(T, 0, "21M", T, 21);
    ok(T, 0, "M", T, 1);
    ok(T, 0, "0M", T, 0);
    fails(
        T,
        0,
        "-M",
        "command 1 '-M': pointer would leave the buffer (pointer 0, length 21)",
    );
    fails(
        T,
        20,
        "2M",
        "command 1 '2M': pointer would leave the buffer (pointer 20, length 21)",
    );
    fails(
        "",
        0,
        "M",
        "command 1 'M': pointer would leave the buffer (pointer 0, length 0)",
    );
}

#[test]
fn k_kills_lines() {
    ok(T, 0, "K", "N2 X10\nN3 Y20\n", 0);
    ok(T, 3, "K", "N1 N2 X10\nN3 Y20\n", 3);
    ok(T, 7, "5K", "N1 G00\n", 7);
    ok(T, 10, "0K", "N1 G00\nX10\nN3 Y20\n", 7);
    ok(T, 10, "-K", "X10\nN3 Y20\n", 0);
    ok(T, 21, "-2K", "N1 G00\n", 7);
    ok(T, 21, "K", T, 21);
    ok(T, 0, "0K", T, 0);
    ok("", 0, "K0K-K", "", 0);
    ok("abc", 1, "K", "a", 1);
}

#[test]
fn d_deletes_chars_or_fails() {
    ok(T, 0, "3D", &T[3..], 0);
    ok(T, 3, "-3D", &T[3..], 0);
    ok(T, 0, "0D", T, 0);
    ok(T, 20, "D", "N1 G00\nN2 X10\nN3 Y20", 20);
    fails(
        T,
        20,
        "2D",
        "command 1 '2D': only 1 characters after the pointer",
    );
    fails(
        T,
        2,
        "-3D",
        "command 1 '-3D': only 2 characters before the pointer",
    );
    fails(
        "",
        0,
        "D",
        "command 1 'D': only 0 characters after the pointer",
    );
}

#[test]
fn i_inserts_and_moves_the_pointer_after() {
    ok(T, 7, "IN15 M03*", "N1 G00\nN15 M03\nN2 X10\nN3 Y20\n", 15);
    ok("", 0, "Iabc", "abc", 3);
    ok("xy", 2, "Iz$I*", "xyz\n", 4);
    ok("xy", 0, "I", "xy", 0);
    ok("x", 1, r"I\*\$", "x*$", 3);
}

#[test]
fn s_searches_forward_inclusive() {
    ok(T, 0, "SX10", T, 13);
    ok(T, 10, "SX10", T, 13);
    ok(T, 0, "S*N3", T, 16);
    ok(T, 0, "SN1", T, 2);
    ok(T, 0, "SN$SN", T, 8);
    fails(T, 1, "SN1", "command 1 'SN1': 'N1' not found");
    // Letters match either case (TECO's default): the language has no case.
    ok(T, 0, "Sn1", T, 2);
    ok(T, 0, "Sx10", T, 13);
    fails(T, 0, "Sn9", "command 1 'Sn9': 'n9' not found");
    fails(T, 21, "S*", "command 1 'S*': '*' not found");
    fails("", 0, "Sa", "command 1 'Sa': 'a' not found");
    fails(T, 0, "S$", "command 1 'S$': search text is empty");
    fails(T, 0, "S", "command 1 'S': search text is empty");
}

#[test]
fn c_substitutes_and_deletes() {
    ok(T, 0, "CX10$X25", "N1 G00\nN2 X25\nN3 Y20\n", 13);
    ok(T, 0, "CX10$X25$L", "N1 G00\nN2 X25\nN3 Y20\n", 14);
    ok(T, 0, "C X10$", "N1 G00\nN2\nN3 Y20\n", 9);
    ok(T, 0, "C*N2 X10$", "N1 G00\nN3 Y20\n", 6);
    ok(T, 0, "cG00$G01", "N1 G01\nN2 X10\nN3 Y20\n", 6);
    ok("aXb", 3, "-3MCX$", "ab", 1);
    ok(T, 0, "cg00$G01", "N1 G01\nN2 X10\nN3 Y20\n", 6);
    fails(T, 0, "cg09$G01", "command 1 'cg09$G01': 'g09' not found");
    fails(T, 0, "C$x", "command 1 'C$': search text is empty");
    fails(
        T,
        0,
        "CX10",
        "command 1 'CX10': C needs old$new: no $ after the old text",
    );
}

/// Runs `line` with options; returns the Y output.
fn y(text: &str, at: usize, line: &str, max: Option<usize>) -> String {
    let mut b = Buffer::from_text(text);
    b.set_pointer(at);
    let opts = ExecOptions {
        y_max_lines: max,
        validator: None,
    };
    let out = b.execute(line, &opts).expect(line);
    assert_eq!(
        (b.text().as_str(), b.pointer()),
        (text, at),
        "Y must not move"
    );
    assert!(!out.changed);
    out.y_output
}

#[test]
fn y_displays_without_moving() {
    assert_eq!(y(T, 0, "Y", None), "N1 G00\n");
    assert_eq!(y(T, 3, "2Y", None), "G00\nN2 X10\n");
    assert_eq!(y(T, 0, "9Y", None), T);
    assert_eq!(y(T, 0, "9Y", Some(2)), "N1 G00\nN2 X10\n");
    assert_eq!(y(T, 0, "9Y", Some(0)), "");
    assert_eq!(y(T, 10, "0Y", None), "N2 \n");
    assert_eq!(y(T, 10, "-Y", None), "N1 G00\nN2 \n");
    assert_eq!(y(T, 10, "-9Y", Some(1)), "N1 G00\n");
    assert_eq!(y(T, 21, "Y", None), "");
    assert_eq!(y("ab", 1, "YY", None), "b\nb\n");
    assert_eq!(y("", 0, "Y0Y-Y", None), "");
}

#[test]
fn a_failing_second_command_changes_nothing() {
    fails(T, 7, "IN15*$SQQ$K", "command 2 'SQQ$': 'QQ' not found");
    fails(T, 7, "K3MX", "command 3 'X': unknown command 'X'");
    fails(
        T,
        7,
        "KIa$-99D",
        "command 3 '-99D': only 8 characters before the pointer",
    );
    fails(
        T,
        0,
        "KKK K-100M",
        "command 5 '-100M': pointer would leave the buffer (pointer 0, length 0)",
    );
}

#[test]
fn outcome_says_whether_text_changed() {
    let (r, _) = run(T, 0, "L M SX$ Y");
    assert!(!r.unwrap().changed);
    let (r, _) = run(T, 0, "IX");
    assert!(r.unwrap().changed);
    let (r, _) = run(T, 0, "I0KD-D");
    assert!(r.unwrap().changed);
    let (r, b) = run(T, 0, "   ");
    assert_eq!(r.unwrap(), Outcome::default());
    assert_eq!(b.text(), T);
}

#[test]
fn the_validator_rejects_the_whole_line() {
    let no_q = |b: &Buffer| {
        if b.text().contains('Q') {
            Err("a Q is not allowed".to_string())
        } else {
            Ok(())
        }
    };
    let opts = ExecOptions {
        y_max_lines: None,
        validator: Some(&no_q),
    };
    let mut b = Buffer::from_text(T);
    b.set_pointer(3);
    let e = b.execute("IZ$IQ$L", &opts).unwrap_err();
    assert_eq!(e.to_string(), "command 2 'IQ$': a Q is not allowed");
    assert_eq!((b.text().as_str(), b.pointer()), (T, 3));
    assert!(b.execute("IZ$L", &opts).is_ok());
    assert_eq!(b.text(), "N1 ZG00\nN2 X10\nN3 Y20\n");
    let bad = |_: &Buffer| Err("never".to_string());
    let opts = ExecOptions {
        y_max_lines: None,
        validator: Some(&bad),
    };
    assert!(
        b.execute("L-L", &opts).is_ok(),
        "pointer moves are not validated"
    );
}

#[test]
fn non_ascii_text_is_counted_in_characters() {
    ok("ñé€\nü", 0, "Sé", "ñé€\nü", 2);
    ok("ñé€\nü", 0, "L", "ñé€\nü", 4);
    ok("ñé€\nü", 1, "D", "ñ€\nü", 1);
    ok("ñé€\nü", 5, "-2D", "ñé€", 3);
    ok("ñé€\nü", 0, "Cé€$ß", "ñß\nü", 2);
    ok("ñé€\nü", 3, "K", "ñé€ü", 3);
    ok("ñé€\nü", 2, "K", "ñéü", 2);
    fails(
        "ñé€",
        0,
        "4M",
        "command 1 '4M': pointer would leave the buffer (pointer 0, length 3)",
    );
}

#[test]
fn line_helpers() {
    let b = Buffer::from_text(T);
    assert_eq!(b.line_count(), 3);
    assert_eq!(Buffer::from_text("a\nb").line_count(), 2);
    assert_eq!(Buffer::new().line_count(), 0);
    assert_eq!(Buffer::from_text("\n").line_count(), 1);
    assert_eq!(
        (
            b.line_of(0),
            b.line_of(6),
            b.line_of(7),
            b.line_of(21),
            b.line_of(99)
        ),
        (0, 0, 1, 3, 3)
    );
    assert_eq!(
        (
            b.line_start(0),
            b.line_start(1),
            b.line_start(3),
            b.line_start(9)
        ),
        (0, 7, 21, 21)
    );
    let mut b = b;
    b.set_pointer(999);
    assert_eq!(b.pointer(), 21);
    assert_eq!(b.slice(3, 6), "G00");
    assert_eq!(b.slice(19, 99), "0\n");
    assert_eq!(b.slice(9, 3), "");
}

#[test]
fn view_shows_lines_around_the_pointer() {
    let mut b = Buffer::from_text("a\nbb\nccc\ndddd\ne");
    b.set_pointer(7);
    let v = b.view(3, 10);
    assert_eq!(v.lines, vec!["bb*", "ccc*", "dddd*"]);
    assert_eq!(
        (v.pointer_row, v.pointer_col, v.first_line, v.first_col),
        (1, 2, 1, 0)
    );
    b.set_pointer(0);
    let v = b.view(3, 10);
    assert_eq!(v.lines, vec!["a*", "bb*", "ccc*"]);
    assert_eq!((v.pointer_row, v.pointer_col, v.first_line), (0, 0, 0));
    b.set_pointer(b.len());
    let v = b.view(3, 10);
    assert_eq!(v.lines, vec!["ccc*", "dddd*", "e"]);
    assert_eq!((v.pointer_row, v.pointer_col, v.first_line), (2, 1, 2));
    b.set_pointer(11);
    let v = b.view(1, 2);
    assert_eq!(v.lines, vec!["dd"]);
    assert_eq!(
        (v.pointer_row, v.pointer_col, v.first_line, v.first_col),
        (0, 1, 3, 1)
    );
    let v = Buffer::new().view(4, 8);
    assert_eq!(v.lines, vec![""]);
    assert_eq!(Buffer::new().view(0, 0).lines.len(), 0);
}

#[test]
fn any_typing_never_panics_and_a_failure_changes_nothing() {
    const KEYS: &[char] = &[
        'L', 'M', 'K', 'D', 'I', 'S', 'C', 'Y', 'l', 's', 'c', '0', '1', '2', '9', '+', '-', '$',
        '*', '\\', ' ', 'é', '\n', 'Q', 'a', '€',
    ];
    let mut state = 99u64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state as usize
    };
    for _ in 0..20_000 {
        let text: String = (0..next() % 20)
            .map(|_| KEYS[next() % KEYS.len()])
            .collect();
        let line: String = (0..next() % 12)
            .map(|_| KEYS[next() % KEYS.len()])
            .collect();
        let mut b = Buffer::from_text(&text);
        b.set_pointer(next() % (text.len() + 1));
        let at = b.pointer();
        let opts = ExecOptions {
            y_max_lines: Some(next() % 3),
            validator: None,
        };
        if let Err(e) = b.execute(&line, &opts) {
            assert_eq!((b.text(), b.pointer()), (text.clone(), at), "{line:?}: {e}");
            assert!(e
                .to_string()
                .starts_with(&format!("command {} '", e.index + 1)));
        }
        assert!(b.pointer() <= b.len());
    }
    for line in [
        "9223372036854775807L",
        "-9223372036854775807L",
        "9223372036854775807K",
        "-9223372036854775807K",
        "9223372036854775807Y",
        "-9223372036854775807Y",
        "-9223372036854775807M",
        "9223372036854775807D",
        "-9223372036854775807D",
        "-9223372036854775808D",
    ] {
        let mut b = Buffer::from_text(T);
        b.set_pointer(10);
        let _ = b.execute(line, &ExecOptions::default());
        assert!(b.pointer() <= b.len(), "{line}");
    }
}

#[test]
fn the_examples_of_docs_editor_md_hold() {
    ok(T, 0, "L", T, 7);
    ok(T, 0, "2L", T, 14);
    ok(T, 0, "9L", T, 21);
    ok(T, 0, "SX10$ 0L", T, 7);
    ok(T, 0, "L K", "N1 G00\nN3 Y20\n", 7);
    ok(T, 0, "SX$ 0K", "N1 G00\n10\nN3 Y20\n", 7);
    ok(T, 0, "L IN15 M03*", "N1 G00\nN15 M03\nN2 X10\nN3 Y20\n", 15);
    ok(T, 0, "CX10$X25", "N1 G00\nN2 X25\nN3 Y20\n", 13);
    ok(T, 0, "C X10$", "N1 G00\nN2\nN3 Y20\n", 9);
    ok(T, 0, "C*N2 X10$", "N1 G00\nN3 Y20\n", 6);
    ok(T, 0, "3D", "G00\nN2 X10\nN3 Y20\n", 0);
    ok(T, 0, "L -D", "N1 G00N2 X10\nN3 Y20\n", 6);
    ok(T, 0, "IX$$L", "XN1 G00\nN2 X10\nN3 Y20\n", 8);
    fails(T, 0, "IN15*$SQQ$K", "command 2 'SQQ$': 'QQ' not found");
    fails(T, 0, "3 L", "command 1 '3': count without a command letter");
    fails(
        T,
        0,
        "L -$",
        "command 2 '-': count without a command letter",
    );
}
