//! The limits of docs/language.md (*Limits*): each is accepted at the limit and refused past it
//! as `LINE:COL: reason` before the statement yields any block, and the translator yields
//! nothing after the error. The reproducers of issue 15 (exponential macros, a dwell and a feed
//! that never end, `IA0`, a 1 MB line) are among them.

mod common;

use novanc::settings::MachineSettings;
use novanc::tooldata::{parse_tape, parse_tcodes, sample_magazine, Magazine, SAMPLE_TCODES};
use novanc::translator::{
    Statement, TranslateError, Translator, MAX_BLOCKS, MAX_DESIGNATIONS, MAX_LINE_CHARS,
};
use std::time::{Duration, Instant};

use common::translate_error as error_with;

fn error_of(src: &str) -> TranslateError {
    error_with(src, sample_magazine())
}

fn expect(src: &str, line: u32, col: u32, words: &str) {
    let e = error_of(src);
    assert_eq!((e.line, e.col), (line, col), "{e}");
    assert!(e.message.contains(words), "'{e}' lacks '{words}'");
}

fn ok(src: &str) -> Vec<Statement> {
    Translator::new(
        src,
        sample_magazine(),
        MachineSettings::default(),
        [0, 0, 0],
    )
    .collect::<Result<_, _>>()
    .unwrap_or_else(|e| panic!("{e}"))
}

fn blocks(stmts: &[Statement]) -> usize {
    stmts.iter().map(|s| s.blocks.len()).sum()
}

const HEAD: &str = "DA1 = (200, 0, -450)\nP1 = (150, 130)\n";

/// The reproducer: `MAC1 = DA1, P1, P1`, then `MACn = MAC(n-1), MAC(n-1)` up to n = 30, never
/// used. MAC17 would stand for 196,608 designations.
#[test]
fn doubling_macros_are_refused_where_they_pass_the_limit_at_once() {
    let mut src = String::from(HEAD);
    src.push_str("MAC1 = DA1, P1, P1\n");
    for n in 2..=30 {
        src.push_str(&format!("MAC{n} = MAC{}, MAC{}\n", n - 1, n - 1));
    }
    let t = Instant::now();
    let e = error_of(&src);
    assert!(
        t.elapsed() < Duration::from_millis(500),
        "{:?}",
        t.elapsed()
    );
    assert_eq!(e.to_string(), format!(
        "19:16: the designations come to 196608 points and origins here, more than the {MAX_DESIGNATIONS} a statement or macro may stand for (a PAT counts its holes, a MAC all it stands for); split the work over several statements"
    ));
    // Up to MAC16 (98,304) the program translates, and using MAC16 machines every point.
    let head: String = src.lines().take(18).map(|l| format!("{l}\n")).collect();
    let stmts = ok(&format!("{head}DRL, 106/DP1/MAC16\n"));
    let holes = stmts[18]
        .blocks
        .iter()
        .filter(|b| b.motion == novanc::block::Motion::Linear)
        .count();
    assert_eq!(holes, 65_536, "two P1 per MAC1 copy, 32,768 copies");
}

#[test]
fn designations_are_counted_with_pattern_holes_up_to_the_limit() {
    let mut src = String::from(HEAD);
    src.push_str("PAT1 = DA1, NH10000, P1, R50\n");
    src.push_str("MAC1 = PAT1, PAT1, PAT1, PAT1, PAT1, PAT1, PAT1, PAT1, PAT1, PAT1\n");
    let at_limit = format!("{src}DRL, 106/DP1/MAC1\n");
    let stmts = ok(&at_limit);
    let feeds = stmts[4]
        .blocks
        .iter()
        .filter(|b| b.motion == novanc::block::Motion::Linear)
        .count();
    assert_eq!(feeds, 100_000);
    assert!(blocks(&stmts) > 300_000);
    expect(
        &format!("{src}DRL, 106/DP1/MAC1, DA1\n"),
        5,
        20,
        "come to 100001 points and origins",
    );
    expect(
        &format!("{src}MAC2 = P1, MAC1\n"),
        5,
        12,
        "come to 100001 points and origins",
    );
    expect(
        "P1 = (1, 1)\nPAT1 = NH10001, P1, R50\n",
        2,
        8,
        "from 1 to 10000",
    );
}

/// A chain of 100,000 macros, each naming the one before: defining and using it takes no
/// recursion (no stack overflow) and little memory.
#[test]
fn a_deep_chain_of_macros_is_safe() {
    let mut src = String::from(HEAD);
    src.push_str("MAC1 = DA1, P1\n");
    for n in 2..=100_000 {
        src.push_str(&format!("MAC{n} = MAC{}\n", n - 1));
    }
    src.push_str("DRL, 106/DP1/MAC100000\n");
    let stmts = ok(&src);
    assert_eq!(stmts[100_002].text, "DRL, 106/DP1/MAC100000");
    assert!(!stmts[100_002].blocks.is_empty());
}

#[test]
fn one_statement_makes_at_most_a_million_blocks() {
    // 1000 pecks a hole (3 blocks each): 334 holes pass the limit.
    let src = format!("{HEAD}PAT1 = DA1, NH400, P1, R50\nDRL, 106/DP98, DH0.1/PAT1\n");
    let t = Instant::now();
    let e = error_of(&src);
    assert!(t.elapsed() < Duration::from_secs(10), "{:?}", t.elapsed());
    assert_eq!(
        e.to_string(),
        format!("4:22: this statement makes more than {MAX_BLOCKS} blocks (the most one statement may make); split the work over several statements")
    );
    let src = format!("{HEAD}PAT1 = DA1, NH300, P1, R50\nDRL, 106/DP98, DH0.1/PAT1\n");
    let n = ok(&src)[3].blocks.len();
    assert!((850_000..=MAX_BLOCKS).contains(&n), "{n}");
    expect(
        &format!("{HEAD}DRL, 106/DP98, DH0.09/DA1, P1\n"),
        3,
        16,
        "more than 1000 pecks",
    );
}

/// Issue 20: a program's blocks are bounded as a G-code program's are (docs/limits.md); a
/// small budget here, the default being 20,000,000.
#[test]
fn a_program_makes_at_most_its_block_budget() {
    let mut src = format!("{HEAD}PAT1 = DA1, NH100, P1, R50\n");
    for _ in 0..10 {
        src.push_str("DRL, 106/DP1/PAT1\n");
    }
    let mut t = Translator::new(
        &src,
        sample_magazine(),
        MachineSettings::default(),
        [0, 0, 0],
    )
    .block_limit(1_000);
    let mut last = 0;
    let e = loop {
        match t.next() {
            Some(Ok(s)) => last = s.line,
            Some(Err(e)) => break e,
            None => panic!("no error"),
        }
    };
    assert!(e.line > last);
    assert!(t.next().is_none());
    assert_eq!(
        e.to_string(),
        "7:1: the program makes more than 1000 blocks (the most a program may make)"
    );
}

/// The reproducer `DRL, 106/DP20, DW1000000000/DA1, P1` never ended in `novanc run`.
#[test]
fn a_dwell_is_at_most_1000_seconds() {
    expect(
        &format!("{HEAD}DRL, 106/DP20, DW1000000000/DA1, P1\n"),
        3,
        16,
        "the dwell DW1000000000 is longer than the longest dwell, 1000 s",
    );
    expect(
        &format!("{HEAD}REM, 301/DP15, DW1000.001/DA1, P1\n"),
        3,
        16,
        "longer than the longest dwell",
    );
    let stmts = ok(&format!("{HEAD}DRL, 106/DP20, DW1000/DA1, P1\n"));
    let d = stmts[2].blocks.iter().map(|b| b.dwell_ns).max();
    assert_eq!(d, Some(1_000_000_000_000));
}

/// The reproducer `FR0.0000001` never ended in `novanc run`, and a feed below 0.0005 mm/min
/// printed as `F0`.
#[test]
fn a_feed_is_at_least_1_mm_per_minute_from_fr_or_the_tool_file() {
    expect(
        &format!("{HEAD}DRL, 106/DP20, FR0.0000001/DA1, P1\n"),
        3,
        16,
        "the feed rate FR0.0000001 is below the slowest feed, 1 mm/min",
    );
    expect(
        &format!("{HEAD}MIL, 402/DP5, FR0.999/DA1, P1, (160, 130)\n"),
        3,
        15,
        "below the slowest feed",
    );
    let stmts = ok(&format!("{HEAD}DRL, 106/DP20, FR1/DA1, P1\n"));
    let iso: Vec<String> = stmts[2]
        .blocks
        .iter()
        .map(|b| novanc::translator::iso_line(b, &MachineSettings::default()))
        .collect();
    assert!(iso.iter().any(|l| l.ends_with(" F1")), "{iso:?}");

    // A tool whose feed in the tool file is below the minimum: refused where it is used.
    let tape = "00106  DR  6.2  150.0  40.0  1200  0.0004  3.0\n";
    let m = Magazine::load(
        parse_tcodes(SAMPLE_TCODES, "m.tc", 24).unwrap(),
        &parse_tape(tape, "t.tt").unwrap(),
    );
    let e = error_with(&format!("{HEAD}DRL, 106/DP20/DA1, P1\n"), m.clone());
    assert_eq!(
        e.to_string(),
        "3:6: tool 00106 has a feed rate of 0.0004 mm/min in the tool file, below the slowest feed, 1 mm/min; give FR or revise the tool"
    );
    let stmts: Result<Vec<_>, _> = Translator::new(
        &format!("{HEAD}DRL, 106/DP20, FR50/DA1, P1\n"),
        m,
        MachineSettings::default(),
        [0, 0, 0],
    )
    .collect();
    assert!(stmts.is_ok());
}

/// The reproducer: `IA0` drilled the same hole NH times.
#[test]
fn pattern_holes_never_fall_on_one_spot() {
    expect(
        &format!("{HEAD}PAT1 = DA1, NH6, P1, R65, SA30, IA0\n"),
        3,
        33,
        "holes 1 and 2 of the pattern fall on the same spot: IA0 does not move on round the circle",
    );
    expect(
        &format!("{HEAD}PAT1 = DA1, NH3, P1, R65, IA180\n"),
        3,
        27,
        "holes 1 and 3 of the pattern fall on the same spot: 2 steps of IA180 make a whole number of turns",
    );
    expect(
        &format!("{HEAD}PAT1 = DA1, NH2, P1, R65, IA-720\n"),
        3,
        27,
        "IA-720 does not move on",
    );
    expect(
        &format!("{HEAD}PAT1 = DA1, NH6, P1, R0.0001\n"),
        3,
        22,
        "the radius R0.0001 is too small",
    );
    // A pattern may go round more than once if its holes stay apart; NH1 with IA0 is one hole.
    ok(&format!(
        "{HEAD}PAT1 = DA1, NH12, P1, R65, IA150\nDRL, 106/DP20/PAT1\n"
    ));
    ok(&format!(
        "{HEAD}PAT1 = DA1, NH1, P1, R65, IA0\nDRL, 106/DP20/PAT1\n"
    ));
}

#[test]
fn a_line_holds_at_most_10000_characters() {
    let pad = |n: usize| format!("DA1 = (1, 2, 3) ;{}\n", "x".repeat(n - 17));
    assert_eq!(pad(MAX_LINE_CHARS).chars().count(), MAX_LINE_CHARS + 1);
    ok(&pad(MAX_LINE_CHARS));
    let e = error_of(&format!("P1 = (1, 2)\n{}", pad(MAX_LINE_CHARS + 1)));
    assert_eq!(
        e.to_string(),
        "2:10001: the line is 10001 characters long; a line holds at most 10000 (split the statement: a MAC can hold part of a list)"
    );
    // Counted in characters, not bytes.
    let wide = format!("DA1 = (1, 2, 3) ;{}\n", "é".repeat(MAX_LINE_CHARS - 17));
    ok(&wide);
}

#[test]
fn computed_points_stay_within_a_million_kilometres() {
    let mut src = String::from("P1 = (1000000000, 0)\n");
    for n in 2..=1001 {
        src.push_str(&format!("P{n} = P{}(1000000000, 0)\n", n - 1));
    }
    let e = error_of(&src);
    assert_eq!((e.line, e.col), (1001, 1), "{e}");
    assert!(e.message.contains("this point lies too far away"), "{e}");
    // Nearly parallel lines meet very far away.
    expect(
        "P1 = (0, 0)\nP2 = (0, 1000000000)\nL1 = P1, A0\nL2 = P2, A0.000001\nP3 = L1, L2\n",
        5,
        1,
        "too far away",
    );
    let mut src = String::from("DA1 = (1000000000, 0, 0)\n");
    for n in 2..=1001 {
        src.push_str(&format!("DA{n} = DA{}, (1000000000, 0, 0)\n", n - 1));
    }
    expect(&src, 1001, 1, "too far away");
}

/// A byte order mark at the start of the text (PROGRAM READ keeps it in program memory) is
/// not part of the program; columns count from after it.
#[test]
fn a_leading_byte_order_mark_is_skipped() {
    let plain = ok(include_str!("../programs/tableb.ap"));
    let bom = ok(&format!(
        "\u{feff}{}",
        include_str!("../programs/tableb.ap")
    ));
    assert_eq!(plain, bom);
    expect(
        "\u{feff}P1 = (1, 2) #",
        1,
        13,
        "'#' is not part of the language",
    );
}
