//! The cycles, positioning and milling choices of docs/language.md, block by block. The
//! expected numbers are worked out in the comments from the sample tool data.

mod common;

use novanc::settings::MachineSettings;
use novanc::tooldata::sample_magazine;
use novanc::translator::translate_all;

/// The ISO lines (without N) of every block, statement by statement.
fn lines(src: &str) -> Vec<Vec<String>> {
    let st = MachineSettings::default();
    translate_all(src, &sample_magazine(), &st, [0, 0, 0])
        .unwrap_or_else(|e| panic!("{e}"))
        .iter()
        .map(common::iso_words)
        .collect()
}

const HEAD: &str = "DA1 = (100, 100, -400)\nP1 = (0, 0)\n";

#[test]
fn peck_drilling_goes_down_from_za_and_re_enters_half_a_millimetre_above() {
    // Tool 106: set length 150. Za = -400 + 2 = -398 (axis -248); Zb = -400 - 10 = -410
    // (axis -260). DH4: pecks to Za-4 = -402 (-252), -406 (-256), then Zb -410 (-260).
    // Between: rapid to Za, rapid to 0.5 above the last bottom (-251.5, -255.5).
    let l = lines(&format!("{HEAD}DRL, 106/DP10, DH4, DW2/DA1, P1"));
    assert_eq!(
        l[2],
        vec![
            "T02 M06",
            "G00 X100.000 Y100.000",
            "S1200 M03",
            "G00 Z-248.000",
            "G01 Z-252.000 F120",
            "G00 Z-248.000",
            "G00 Z-251.500",
            "G01 Z-256.000 F120",
            "G00 Z-248.000",
            "G00 Z-255.500",
            "G01 Z-260.000 F120",
            "G04 P2.000",
            "G00 Z-248.000",
        ]
    );
}

#[test]
fn chamfer_depth_from_the_point_angle() {
    // Tool 101 is a CD (90 degree spot): DI4 -> depth 2: Zb -402 tip, axis -402 + 110 = -292.
    let l = lines(&format!("{HEAD}DRL, 101/DI4/DA1, P1"));
    assert!(
        l[2].contains(&"G01 Z-292.000 F150".to_string()),
        "{:?}",
        l[2]
    );
    // Tool 106 is a DR (118 degrees): DI6 -> depth 3 / tan 59 = 1.80258: Zb -401.803 tip,
    // axis -251.803.
    let l = lines(&format!("{HEAD}DRL, 106/DI6/DA1, P1"));
    assert!(
        l[2].contains(&"G01 Z-251.803 F120".to_string()),
        "{:?}",
        l[2]
    );
}

#[test]
fn reaming_feeds_out_and_boring_restarts_the_spindle_over_the_next_hole() {
    // REM with tool 301 (T11, set 150, 400 rpm, F80): feed in to -260, dwell, feed out to -248.
    let l = lines(&format!("{HEAD}REM, 301/DP10, DW1/DA1, P1"));
    assert_eq!(
        &l[2][3..],
        &[
            "G00 Z-248.000",
            "G01 Z-260.000 F80",
            "G04 P1.000",
            "G01 Z-248.000 F80"
        ]
    );
    // BOR with tool 603 (T17, set 200, 620 rpm, F75) on two points: M05 at the bottom,
    // rapid out, then over the second point S620 M03 before going down.
    let l = lines(&format!("{HEAD}BOR, 603/DP10/DA1, P1, (20, 0)"));
    assert_eq!(
        l[2],
        vec![
            "T17 M06",
            "G00 X100.000 Y100.000",
            "S620 M03",
            "G00 Z-198.000",
            "G01 Z-210.000 F75",
            "M05",
            "G00 Z-198.000",
            "G00 X120.000",
            "S620 M03",
            "G01 Z-210.000 F75",
            "M05",
            "G00 Z-198.000",
        ]
    );
}

#[test]
fn moves_between_holes_rise_to_the_higher_clearance_first() {
    // P2 is 30 mm higher than P1. From P1 (Za -398) to P2 (Za -368) the tool rises first to
    // -368 (axis -218), then moves X; back to P1 it moves X at -368, then descends.
    let l = lines(&format!(
        "{HEAD}P2 = (50, 0, 30)\nDRL, 106/DP5/DA1, P1, P2, P1"
    ));
    let d = &l[3];
    let i = d
        .iter()
        .position(|x| x == "G00 X150.000")
        .expect("move to P2");
    assert_eq!(d[i - 1], "G00 Z-218.000", "rise before the move");
    let j = d
        .iter()
        .rposition(|x| x == "G00 X100.000")
        .expect("back to P1");
    assert_eq!(d[j - 1], "G00 Z-218.000", "retract of P2 is its Za");
    assert_eq!(d[j + 1], "G00 Z-248.000", "then down to P1's Za");
}

#[test]
fn go_gd_and_cl_never_move_sideways_below_where_the_tool_is() {
    // With tool 106 (set length 150) in the spindle after the DRL:
    // GO, DA1, 50, 0, 20: tip (150, 100, -380), axis Z -230: going up: Z first, then X.
    // GO, 150, 100, -390: going down: X Y (no change) then Z to -390 + 150 = -240.
    // GD, -10, 0, 5: up 5 first, then X.
    // CL: Z to 0, then X Y to 0.
    let l = lines(&format!(
        "{HEAD}DRL, 106/DP5/DA1, P1\nGO, DA1, 50, 0, 20\nGO, 150, 100, -390\nGD, -10, 0, 5\nCL"
    ));
    assert_eq!(l[3], vec!["G00 Z-230.000", "G00 X150.000"]);
    assert_eq!(l[4], vec!["G00 Z-240.000"]);
    assert_eq!(l[5], vec!["G00 Z-235.000", "G00 X140.000"]);
    assert_eq!(l[6], vec!["G00 Z0.000", "G00 X0.000 Y0.000"]);
}

#[test]
fn macros_patterns_and_intersections_as_designations() {
    // L1 along +X through P1, C1 radius 10 about P3 = (30, 5): meets the X axis at
    // x = 30 +- sqrt(100 - 25) = 30 +- 8.660. XS -> (21.340, 0); XL -> (38.660, 0).
    // PAT1 in DA1: NH4 about P1, R10, SA0 -> IA 90: (10,0), (0,10), (-10,0), (0,-10).
    let src = format!(
        "{HEAD}L1 = P1, A0\nP3 = (30, 5)\nC1 = P3, R10\nP4 = L1, C1, XS\nPAT1 = DA1, NH4, P1, R10\n\
         MAC1 = DA1, P4, (L1, C1, XL = P5)\nDRL, 106/DP5/MAC1, PAT1"
    );
    let l = lines(&src);
    let xy: Vec<&String> = l[8]
        .iter()
        .filter(|x| x.starts_with("G00 X") || x.starts_with("G00 Y"))
        .collect();
    assert_eq!(
        xy,
        vec![
            "G00 X121.340 Y100.000",
            "G00 X138.660",
            "G00 X110.000",
            "G00 X100.000 Y110.000",
            "G00 X90.000 Y100.000",
            "G00 X100.000 Y90.000",
        ]
    );
}

#[test]
fn milling_a_closed_contour_outside_rolls_round_the_corners() {
    // A 20 x 10 rectangle at DA1, counter-clockwise, RGT: the tool (end mill 402, diameter 8,
    // set 125, F600) is outside. Start (0, -4) -> (20, -4), arc about (20, 0) to (24, 0), ...
    let src = format!(
        "{HEAD}P2 = (20, 0)\nP3 = (20, 10)\nP4 = (0, 10)\nMIL, 402/DP3, RGT/DA1, P1, P2, P3, P4, P1"
    );
    let l = lines(&src);
    assert_eq!(
        l[5],
        vec![
            "T13 M06",
            "G00 X100.000 Y96.000",
            "S4000 M03",
            "G00 Z-273.000",
            "G01 Z-278.000 F600",
            "G01 X120.000 F600",
            "G03 X124.000 Y100.000 I0.000 J4.000 F600",
            "G01 Y110.000 F600",
            "G03 X120.000 Y114.000 I-4.000 J0.000 F600",
            "G01 X100.000 F600",
            "G03 X96.000 Y110.000 I0.000 J-4.000 F600",
            "G01 Y100.000 F600",
            "G03 X100.000 Y96.000 I4.000 J0.000 F600",
            "G00 Z-273.000",
        ]
    );
}

#[test]
fn milling_circles_inside_and_outside() {
    // C1 radius 20 about DA1's zero: LFT -> path radius 20 - 4 = 16, RGT -> 24, CCW from
    // 3 o'clock, a full circle (end = start).
    let l = lines(&format!(
        "{HEAD}C1 = P1, R20\nMIL, 402/DP3, LFT/DA1, C1\nMIL, 402/DP3, RGT/DA1, C1"
    ));
    assert!(
        l[3].contains(&"G03 X116.000 Y100.000 I-16.000 J0.000 F600".to_string()),
        "{:?}",
        l[3]
    );
    assert!(
        l[4].contains(&"G03 X124.000 Y100.000 I-24.000 J0.000 F600".to_string()),
        "{:?}",
        l[4]
    );
}
