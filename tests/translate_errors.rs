//! Bad input: every error carries LINE:COL and an operator's message, and the statement in
//! error yields no blocks (the translator hands out nothing after it).

mod common;

use common::translate_error as error_with;
use novanc::pulse_core::testkit::Rng;
use novanc::settings::MachineSettings;
use novanc::tooldata::{parse_tape, parse_tcodes, sample_magazine, Magazine};
use novanc::translator::{TranslateError, Translator};

/// Translates `src` statement by statement (`common::translate_error`).
fn error_of(src: &str) -> TranslateError {
    error_with(src, sample_magazine())
}

fn expect(src: &str, line: u32, col: u32, words: &str) {
    let e = error_of(src);
    assert_eq!((e.line, e.col), (line, col), "{e}");
    assert!(e.message.contains(words), "'{e}' lacks '{words}'");
    assert_eq!(e.to_string(), format!("{line}:{col}: {}", e.message));
}

const HEAD: &str = "DA1 = (200, 0, -450)\nP1 = (150, 130)\n";

#[test]
fn syntax_errors() {
    expect("DRL, 106/DP20/PAT", 1, 18, "expected the number of the PAT");
    expect("P1 = (150, 130", 1, 15, "not closed");
    expect("P1 = 150, 130)", 1, 14, "')' without a matching '('");
    expect("P1 = 150, 130", 1, 6, "expected '(' and coordinates");
    expect("FOO, 1, 2", 1, 1, "'FOO' is not a statement keyword");
    expect("DA1 = (1, 2)", 1, 12, "3 coordinates");
    expect("P1 = (1, 2) # x", 1, 13, "'#' is not part of the language");
    expect(
        &format!("{HEAD}DRL, 106/DP20, XX3/DA1, P1"),
        3,
        16,
        "'XX' is not a designation",
    );
    expect("GO, 1, 2", 1, 9, "expected ',' or '/'");
}

#[test]
fn undefined_names() {
    expect(
        &format!("{HEAD}DRL, 106/DP20/DA1, P9"),
        3,
        20,
        "P9 is not defined",
    );
    expect(
        &format!("{HEAD}DRL, 106/DP20/DA2, P1"),
        3,
        15,
        "DA2 is not defined",
    );
    expect(
        &format!("{HEAD}DRL, 106/DP20/PAT1"),
        3,
        15,
        "PAT1 is not defined",
    );
    expect("P2 = P1(0, 30)", 1, 6, "P1 is not defined");
    expect(
        &format!("{HEAD}MAC1 = DA1, P1, P2"),
        3,
        17,
        "P2 is not defined",
    );
    expect("P3 = L1, L2", 1, 6, "L1 is not defined");
}

#[test]
fn redefinition_is_forbidden() {
    expect(
        &format!("{HEAD}P1 = (0, 0)"),
        3,
        1,
        "P1 is already defined on line 2",
    );
    expect(
        &format!("{HEAD}P2 = (1, 1)\nDRL, 106/DP5/DA1, (P1(0,30)=P2)"),
        4,
        29,
        "P2 is already defined on line 3",
    );
    expect(
        "DA1 = (0, 0, 0)\nDA1 = (0, 0, 0)",
        2,
        1,
        "DA1 is already defined",
    );
}

#[test]
fn lines_and_circles_that_do_not_meet() {
    let lines = "P1 = (0, 0)\nP2 = (0, 10)\nL1 = P1, A30\nL2 = P2, A30\n";
    expect(&format!("{lines}P3 = L1, L2"), 5, 6, "parallel");
    let circles = "P1 = (0, 0)\nP2 = (100, 0)\nC1 = P1, R10\nC2 = P2, R10\n";
    expect(&format!("{circles}P3 = C1, C2, YL"), 5, 6, "do not meet");
    let inner = "P1 = (0, 0)\nC1 = P1, R10\nC2 = P1, R5\n";
    expect(&format!("{inner}P3 = C1, C2, YL"), 4, 6, "concentric");
    let miss = "P1 = (0, 0)\nP2 = (0, 20)\nC1 = P1, R10\nL1 = P2, A0\n";
    expect(&format!("{miss}P3 = L1, C1, XL"), 5, 6, "do not meet");
    expect("P1 = (0, 0)\nL1 = P1, P1", 2, 10, "the same");
    expect(
        "P1 = (0, 0)\nP2 = (1, 1)\nP3 = (2, 2)\nC1 = P1, P2, P3",
        4,
        6,
        "on one line",
    );
    expect("P1 = (0, 0)\nC1 = P1, R0", 2, 10, "greater than 0");
    // Two intersections with the same X: XL cannot choose.
    let vert = "P1 = (0, 0)\nC1 = P1, R10\nP2 = (3, 0)\nL1 = P2, A90\n";
    expect(&format!("{vert}P3 = L1, C1, XL"), 5, 6, "same X");
}

#[test]
fn tools_not_in_the_magazine() {
    expect(
        &format!("{HEAD}DRL, 999/DP5/DA1, P1"),
        3,
        6,
        "tool 00999 is not in the magazine",
    );
    // Tool 115 is on the tape but no T code holds it.
    expect(
        &format!("{HEAD}DRL, 115/DP5/DA1, P1"),
        3,
        6,
        "not in the magazine",
    );
    // A T code holds tool 777 but the tape has no record for it.
    let tape = parse_tape(novanc::tooldata::SAMPLE_TAPE, "tools.tt").unwrap();
    let tcodes = parse_tcodes("T01 00106\nT02 00777\n", "m.tc", 24).unwrap();
    let e = error_with(
        &format!("{HEAD}DRL, 777/DP5/DA1, P1"),
        Magazine::load(tcodes, &tape),
    );
    assert_eq!((e.line, e.col), (3, 6));
    assert!(e.message.contains("read the tool tape"), "{e}");
}

#[test]
fn depths_and_patterns() {
    expect(
        &format!("{HEAD}DRL, 106/DP0/DA1, P1"),
        3,
        10,
        "DP must be greater than 0",
    );
    expect(
        &format!("{HEAD}DRL, 106/DP-5/DA1, P1"),
        3,
        10,
        "DP must be greater than 0",
    );
    expect(&format!("{HEAD}DRL, 106/DA1, P1"), 3, 1, "needs a depth");
    expect(
        &format!("{HEAD}PAT1 = DA1, NH0, P1, R65, SA30, IA60"),
        3,
        13,
        "NH0",
    );
    expect(
        &format!("{HEAD}PAT1 = DA1, NH2.5, P1, R65"),
        3,
        13,
        "whole number",
    );
    expect(&format!("{HEAD}PAT1 = DA1, NH4, P1, R0"), 3, 22, "radius");
    expect(
        &format!("{HEAD}PAT1 = DA1, NH4, P1"),
        3,
        20,
        "needs a radius R",
    );
    expect(&format!("{HEAD}BOR, 610/DP20, SDP30/DA1, P1"), 3, 16, "SDP");
    expect(
        &format!("{HEAD}DRL, 106/DP20, DH0/DA1, P1"),
        3,
        16,
        "DH must be greater than 0",
    );
    expect(
        &format!("{HEAD}DRL, 106/DP20, SCL-1/DA1, P1"),
        3,
        16,
        "SCL must not be negative",
    );
    expect(
        &format!("{HEAD}DRL, 106/DP20, DW-1/DA1, P1"),
        3,
        16,
        "DW must not be negative",
    );
    expect(
        &format!("{HEAD}DRL, 106/DP20, FR0/DA1, P1"),
        3,
        16,
        "FR must be greater than 0",
    );
    expect(
        &format!("{HEAD}DRL, 106/DP20, DI3/DA1, P1"),
        3,
        16,
        "not both",
    );
    expect(
        &format!("{HEAD}DRL, 106/DI8/DA1, P1"),
        3,
        10,
        "larger than the tool",
    );
    expect(
        &format!("{HEAD}DRL, 106/DP20/DA1"),
        3,
        6,
        "nothing to machine",
    );
}

#[test]
fn modifiers_that_do_not_belong() {
    expect(
        &format!("{HEAD}DRL, 106/DP20, RGT/DA1, P1"),
        3,
        16,
        "RGT has no meaning in DRL",
    );
    expect(
        &format!("{HEAD}TAP, 208/DP10, DW1/DA1, P1"),
        3,
        16,
        "DW (dwell) has no meaning in TAP",
    );
    expect(
        &format!("{HEAD}REM, 301/DP10, DH2/DA1, P1"),
        3,
        16,
        "DH (peck step) has no meaning",
    );
    expect(
        &format!("{HEAD}MIL, 402/DP2, RGT, LFT/DA1, P1, (P1(5,0))"),
        3,
        20,
        "not both",
    );
    expect(
        &format!("{HEAD}C1 = P1, R5\nDRL, 106/DP5/DA1, C1"),
        4,
        19,
        "a circle is a milling contour",
    );
}

#[test]
fn milling_geometry_that_does_not_fit() {
    // A 1 mm wide slot milled inside with an 8 mm end mill.
    let slot = "DA1 = (200, 100, -450)\nP1 = (0, 0)\nP2 = (20, 0)\nP3 = (20, 1)\nP4 = (0, 1)\n";
    expect(
        &format!("{slot}MIL, 402/DP2, LFT/DA1, P1, P2, P3, P4"),
        6,
        32,
        "too large for the inside corner",
    );
    expect(
        &format!("{slot}C1 = P1, R3\nMIL, 402/DP2, LFT/DA1, C1"),
        7,
        24,
        "does not fit inside the circle",
    );
    expect(
        &format!("{slot}MIL, 402/DP2, LFT/DA1, P1"),
        6,
        24,
        "at least two points",
    );
}

#[test]
fn points_beyond_the_travel_limits() {
    // X: DA1 at X 990 and a point 20 further: X 1010 > 1000.
    expect(
        "DA1 = (990, 0, -450)\nP1 = (20, 10)\nDRL, 106/DP5/DA1, P1",
        3,
        19,
        "X1010.000 is beyond the X travel (0.000 to 1000.000 mm)",
    );
    // Z below: surface -800, Zb -805 tip, axis -805 + 150 = -655 < -600.
    expect(
        "DA1 = (100, 100, -800)\nP1 = (0, 0)\nDRL, 106/DP5/DA1, P1",
        3,
        19,
        "Z-",
    );
    // Z above: a surface at -100 with tool 106 (set length 150): Za = -98 + 150 = +52 > 0.
    expect(
        "DA1 = (100, 100, -100)\nP1 = (0, 0)\nDRL, 106/DP5/DA1, P1",
        3,
        19,
        "Z52.000 is beyond the Z travel",
    );
    // Y via the top of a circle: centre Y 790, radius 15: the start (3 o'clock) is inside the
    // limits but the arc reaches Y 805.
    expect(
        "DA1 = (500, 790, -450)\nP1 = (0, 0)\nC1 = P1, R15\nMIL, 402/DP2/DA1, C1",
        4,
        19,
        "Y805.000 is beyond",
    );
    // GO beyond, and GD from machine zero upward.
    expect("GO, 1200, 0, -100", 1, 1, "X1200.000");
    expect("GD, 0, 0, 5", 1, 1, "Z5.000");
}

#[test]
fn a_good_statement_before_the_error_is_whole() {
    let src = format!("{HEAD}DRL, 106/DP20/DA1, P1\nDRL, 106/DP20/DA1, P7");
    let mut t = Translator::new(
        &src,
        sample_magazine(),
        MachineSettings::default(),
        [0, 0, 0],
    );
    let lines: Vec<(u32, usize)> = t
        .by_ref()
        .take(3)
        .map(|s| {
            let s = s.unwrap();
            (s.line, s.blocks.len())
        })
        .collect();
    // T02 M06 (Z already at 0), X Y, S M03, Za, feed to Zb, retract: 6 blocks.
    assert_eq!(lines, vec![(1, 0), (2, 0), (3, 6)]);
    let e = t.next().unwrap().unwrap_err();
    assert_eq!((e.line, e.col), (4, 20));
    assert!(t.next().is_none());
}

#[test]
fn no_input_makes_the_translator_panic() {
    // Table B with random characters replaced, inserted and deleted, and random soup made of
    // the language's own pieces: every run must end in statements or an error, never a panic.
    let base = include_str!("../programs/tableb.ap");
    let pieces = [
        "DRL",
        "TAP",
        "MIL",
        "BOR",
        "REM",
        "P",
        "DA",
        "L",
        "C",
        "PAT",
        "MAC",
        "GO",
        "GD",
        "CL",
        "RGT",
        "LFT",
        "DP",
        "DI",
        "FR",
        "SS",
        "SCL",
        "SDP",
        "DW",
        "DH",
        "NH",
        "R",
        "SA",
        "IA",
        "A",
        "XL",
        "YS",
        "1",
        "2",
        "0",
        "-3",
        "106",
        "402",
        "99999999999",
        ".5",
        "(",
        ")",
        ",",
        "/",
        "=",
        " ",
        "\n",
        ";",
        "1e5",
        "é",
    ];
    let mut rng = Rng::new(0x00C0_FFEE);
    let (mut ok, mut failed) = (0, 0);
    for round in 0..3000 {
        let src = if round % 2 == 0 {
            let mut b: Vec<char> = base.chars().collect();
            for _ in 0..1 + rng.next_u64() % 4 {
                let i = (rng.next_u64() % b.len() as u64) as usize;
                let piece = pieces[(rng.next_u64() % pieces.len() as u64) as usize];
                match rng.next_u64() % 3 {
                    0 => {
                        b.remove(i);
                    }
                    1 => b.splice(i..i, piece.chars()).for_each(drop),
                    _ => b[i] = piece.chars().next().unwrap_or(' '),
                }
            }
            b.into_iter().collect::<String>()
        } else {
            (0..rng.next_u64() % 60)
                .map(|_| pieces[(rng.next_u64() % pieces.len() as u64) as usize])
                .collect::<String>()
        };
        let r = novanc::translator::translate_all(
            &src,
            &sample_magazine(),
            &MachineSettings::default(),
            [0, 0, 0],
        );
        match r {
            Ok(_) => ok += 1,
            Err(e) => {
                assert!(e.line >= 1 && e.col >= 1 && !e.message.is_empty(), "{e}");
                failed += 1;
            }
        }
    }
    assert!(ok > 0 && failed > 0, "ok {ok}, failed {failed}");
}

/// A SEARCH past the last statement is a value the console asks for (`Translator::past_end`),
/// not a message it reads; any other error leaves it `None`.
#[test]
fn a_search_past_the_end_is_a_typed_value() {
    use novanc::translator::PastEnd;
    let src = format!("{HEAD}\n; a comment\n");
    let mut t = Translator::new(
        &src,
        sample_magazine(),
        MachineSettings::default(),
        [0, 0, 0],
    )
    .resume_at(9);
    let e = t.by_ref().find_map(Result::err).expect("an error");
    let past = PastEnd { line: 9, lines: 4 };
    // Nothing after line 3 either: the blank line and the comment are no statements.
    assert_eq!(t.past_end(), Some(past), "{e}");
    assert_eq!(e.message, past.to_string());
    assert_eq!(
        past.to_string(),
        "no statement at or after line 9 (the program has 4 lines)"
    );
    let mut t = Translator::new(
        &format!("{HEAD}BOGUS\n"),
        sample_magazine(),
        MachineSettings::default(),
        [0, 0, 0],
    )
    .resume_at(3);
    assert!(t.by_ref().any(|r| r.is_err()));
    assert_eq!(t.past_end(), None);
}
