//! The Table B golden listing (`programs/tableb.ap` with the sample tool data), checked by hand:
//! every number below is derived in the comments from docs/language.md and the sample tool data, not
//! copied from the translator's output.

mod common;

use novanc::block::Motion;
use novanc::settings::MachineSettings;
use novanc::tooldata::sample_magazine;
use novanc::translator::{iso_program, translate_all, Statement};

const TABLEB: &str = include_str!("../programs/tableb.ap");
const GOLDEN: &str = include_str!("golden/tableb.iso");

fn translate() -> Vec<Statement> {
    translate_all(
        TABLEB,
        &sample_magazine(),
        &MachineSettings::default(),
        [0, 0, 0],
    )
    .expect("Table B translates")
}

/// The ISO lines of the statement on source line `line`, without their N words.
fn lines_of(stmts: &[Statement], line: u32) -> Vec<String> {
    common::iso_words(stmts.iter().find(|s| s.line == line).expect("statement"))
}

#[test]
fn the_printed_program_matches_the_golden_listing() {
    let out = iso_program(&translate(), &MachineSettings::default());
    assert_eq!(out, GOLDEN, "tests/golden/tableb.iso differs");
    assert!(out.starts_with("G21 G90 G17"));
    assert!(out.ends_with("M30\n"));
}

#[test]
fn definitions_yield_statements_without_blocks() {
    let s = translate();
    let lines: Vec<u32> = s.iter().map(|s| s.line).collect();
    // Lines 1-9 are Table B; line 10 is the end of program the translator adds.
    assert_eq!(lines, vec![1, 2, 3, 4, 5, 6, 7, 8, 9, 10]);
    for def in [1, 2, 4, 7] {
        assert!(s[def - 1].blocks.is_empty(), "line {def} is a definition");
    }
    assert_eq!(s[0].text, "DA1 = (200, 0, -450)");
    // Every block names its statement and the N words run 1, 2, 3, ... through the program.
    let mut n = 0;
    for st in &s {
        for b in &st.blocks {
            n += 1;
            assert_eq!((b.seq, b.stmt), (n, st.line));
        }
    }
}

#[test]
fn bor_610_with_sdp_rapids_into_the_bore() {
    // Tool 610 is in T01 (magazine.tc): BB, diameter 40, set length 220, 400 rpm, 60 mm/min,
    // normal depth 25. The machine starts at machine zero with no tool: Z is already at 0, so
    // the tool change is just T01 M06.
    // P1 in DA1: X = 200 + 150 = 350, Y = 0 + 130 = 130.
    // The surface is DA1.z + 0 = -450. SDP with no value = the tool's normal depth 25, so the
    // rapid advance ends at tip -450 - 25 = -475: axis -475 + 220 = -255.
    // DP35: Zb = -450 - 35 = -485 tip, axis -485 + 220 = -265, at F60.
    // BOR: spindle stop at the bottom, then rapid to Zc = Za = axis -255.
    assert_eq!(
        lines_of(&translate(), 3),
        vec![
            "T01 M06",
            "G00 X350.000 Y130.000",
            "S400 M03",
            "G00 Z-255.000",
            "G01 Z-265.000 F60",
            "M05",
            "G00 Z-255.000",
        ]
    );
}

#[test]
fn drl_106_on_pat1_drills_the_six_holes_of_spec_4() {
    // PAT1 = DA1, NH6, P1, R65, SA30, IA60: holes at P1 + 65(cos a, sin a), a = 30, 90, ...
    // which docs/language.md gives relative to DA1 as (206.292, 162.5), (150, 195), (93.708, 162.5),
    // (93.708, 97.5), (150, 65), (206.292, 97.5); plus DA1 (200, 0): machine X 406.292 Y 162.5,
    // X 350 Y 195, X 293.708 Y 162.5, X 293.708 Y 97.5, X 350 Y 65, X 406.292 Y 97.5.
    // Tool 106 is T02: DR 6.2, set length 150, 1200 rpm, 120 mm/min.
    // Tool change: rapid Z to machine zero (from -255), the spindle is already stopped by the
    // BOR (no M05), T02 M06.
    // Za = -450 + SCL 2 = -448 tip: axis -448 + 150 = -298. Zb = -450 - 20 = -470 tip: axis
    // -320. Zc = Za. Between holes the tool stays at Za (the same surface everywhere), and only
    // the axes that move are printed (X stays 293.708 from hole 3 to 4).
    let mut want = vec![
        "G00 Z0.000",
        "T02 M06",
        "G00 X406.292 Y162.500",
        "S1200 M03",
    ];
    let moves = [
        "G00 X350.000 Y195.000",
        "G00 X293.708 Y162.500",
        "G00 Y97.500",
        "G00 X350.000 Y65.000",
        "G00 X406.292 Y97.500",
    ];
    want.extend(["G00 Z-298.000", "G01 Z-320.000 F120", "G00 Z-298.000"]);
    for m in moves {
        want.extend([m, "G01 Z-320.000 F120", "G00 Z-298.000"]);
    }
    assert_eq!(lines_of(&translate(), 5), want);
}

#[test]
fn tap_208_on_pat1_reverses_at_the_bottom() {
    // Tool 208 is T03: TP M8, set length 150, 300 rpm, 375 mm/min (pitch 1.25 x 300).
    // The spindle runs (from DRL), so the change is Z0, M05, T03 M06. The last hole of the
    // DRL left X at 406.292, so the first TAP move prints only Y162.5.
    // Za = -448 tip: axis -298. Zb = -450 - 16 = -466 tip: axis -466 + 150 = -316.
    // TAP: feed in, M04 at the bottom, feed out to Za, M03 again (with S300).
    let l = lines_of(&translate(), 6);
    assert_eq!(
        &l[..9],
        &[
            "G00 Z0.000",
            "M05",
            "T03 M06",
            "G00 Y162.500",
            "S300 M03",
            "G00 Z-298.000",
            "G01 Z-316.000 F375",
            "M04",
            "G01 Z-298.000 F375",
        ]
    );
    assert_eq!(l[9], "S300 M03");
    // Each later hole: X Y at Za (already there, so no Z move), feed in, M04, feed out, M03.
    assert_eq!(
        l.len(),
        10 + 5 * 5,
        "six holes: 10 lines with the change, then 5 each"
    );
    assert_eq!(l[10], "G00 X350.000 Y195.000");
}

#[test]
fn drl_105_and_tap_206_on_the_three_points_with_z_minus_5() {
    // P2 = (25, 20, -5) in DA1: X 225, Y 20, surface -450 - 5 = -455.
    // P3 = P2(0,30) = (25, 50, -5): Y 50. P4 = P3(0,170) = (25, 220, -5): Y 220.
    // Tool 105 is T04: DR 5.0, set length 140, 1600 rpm, 140 mm/min.
    // Za = -455 + 2 = -453 tip: axis -313. Zb = -455 - 15 = -470 tip: axis -330.
    let l = lines_of(&translate(), 8);
    assert_eq!(
        l,
        vec![
            "G00 Z0.000",
            "M05",
            "T04 M06",
            "G00 X225.000 Y20.000",
            "S1600 M03",
            "G00 Z-313.000",
            "G01 Z-330.000 F140",
            "G00 Z-313.000",
            "G00 Y50.000",
            "G01 Z-330.000 F140",
            "G00 Z-313.000",
            "G00 Y220.000",
            "G01 Z-330.000 F140",
            "G00 Z-313.000",
        ]
    );
    // Tool 206 is T05: TP M6, set length 140, 400 rpm, 400 mm/min.
    // Za axis -313 as above; Zb = -455 - 12 = -467 tip: axis -327. The tool changes at
    // X225 Y220 (where DRL ended), so the first move is back to Y20.
    let l = lines_of(&translate(), 9);
    assert_eq!(
        &l[..9],
        &[
            "G00 Z0.000",
            "M05",
            "T05 M06",
            "G00 Y20.000",
            "S400 M03",
            "G00 Z-313.000",
            "G01 Z-327.000 F400",
            "M04",
            "G01 Z-313.000 F400",
        ]
    );
}

#[test]
fn blocks_carry_pulses_and_motion_kinds() {
    // 1 pulse = 0.001 mm: the first PAT1 hole X 406.292 is 406292 pulses, and the feed to
    // Zb is -22 mm = -22000 pulses of Z alone.
    let s = translate();
    let drl = &s[4].blocks;
    let feed = drl
        .iter()
        .find(|b| b.motion == Motion::Linear)
        .expect("a feed");
    assert_eq!(feed.end, [406_292, 162_500, -320_000]);
    assert_eq!(feed.delta, [0, 0, -22_000]);
    assert_eq!(feed.feed, 120.0);
    let change = drl.iter().find(|b| b.m == Some(6)).expect("M06");
    assert_eq!((change.t, change.motion), (Some(2), Motion::Aux));
}

#[test]
fn the_program_ends_with_spindle_stop_retract_and_m30() {
    // Table B has 9 lines; the translator adds the end of program as line 10. The last TAP
    // hole (tool 206, set length 140) ends at Za = -453 tip, axis -313, with the spindle
    // forward again (S400 M03). So: M05 (spindle stop), G00 Z0.000 (up to machine zero, the
    // tool change height), then M30. The tool does not sit turning above the part.
    let s = translate();
    let last = s.last().expect("statements");
    assert_eq!((last.line, last.text.as_str()), (10, "(end of program)"));
    assert_eq!(lines_of(&s, 10), vec!["M05", "G00 Z0.000", "M30"]);
    // A program that only positions gets just M30: the tool stays where it was sent.
    let go = translate_all(
        "GO, 100, 100, -50\n",
        &sample_magazine(),
        &MachineSettings::default(),
        [0, 0, 0],
    )
    .expect("GO translates");
    assert_eq!(lines_of(&go, 2), vec!["M30"]);
}
