//! The lathe G-code reader's refusals (docs/lathe-gcode.md): every one names its line and
//! column and says why in a part programmer's words. The seeded no-panic test is
//! tests/lathe_gcode_fuzz.rs.

use novanc::block::Motion;
use novanc::lathe::desc::LatheDesc;
use novanc::lathe::gcode::{read_program, ReadOptions};
use novanc::settings::Dialect;

fn desc() -> LatheDesc {
    let mut d = LatheDesc::citizen();
    for c in &mut d.channels {
        c.axes[0].travel = [-1.0, 100.0];
        c.axes[1].travel = [-200.0, 200.0];
    }
    d
}

fn error(text: &str, desc: &LatheDesc) -> String {
    match read_program(text, desc, 0, &ReadOptions::default()) {
        Ok(p) => panic!("read without error: {text:?} → {p:?}"),
        Err(e) => e.to_string(),
    }
}

/// The cases (program, "line:col", part of the message) read on `desc` that are not refused
/// at their place or not for their reason, each told.
fn misplaced(desc: &LatheDesc, cases: Vec<(String, &str, &str)>) -> Vec<String> {
    let mut bad = Vec::new();
    for (text, at, needle) in cases {
        let e = error(&text, desc);
        let place_ok = if at.contains(':') {
            e.starts_with(&format!("{at}: "))
        } else {
            e.contains(':')
        };
        if !place_ok || !e.contains(needle) {
            let head: String = text.chars().take(60).collect();
            bad.push(format!("{head:?}\n   want {at}: …{needle}…\n   got  {e}"));
        }
    }
    bad
}

const S: &str = "T0101 M3 S1000\n";

/// (program, "line:col", part of the message).
fn cases() -> Vec<(String, &'static str, &'static str)> {
    let s = |t: &str| format!("{S}{t}");
    let long_profile = {
        let mut t = String::from("G0 X90 Z2\nG71 U1 R0\nG71 P1 Q2 F100\nN1 G0 X10\n");
        for k in 0..8001 {
            t.push_str(&format!("G1 Z{}\n", -0.01 * k as f64));
        }
        t.push_str("N2 G1 X20\n");
        t
    };
    let many_lines = {
        let mut t = String::from("G0 X20 Z2\n");
        for _ in 0..1100 {
            t.push_str("G70 P1 Q2\n");
        }
        t.push_str("M30\nN1 G4 P0\n");
        for _ in 0..998 {
            t.push_str("G4 P0\n");
        }
        t.push_str("N2 G4 P0\n");
        t
    };
    let many_steps = {
        let mut t = s("G0 X20 Z5\n");
        for _ in 0..260 {
            t.push_str("G0 Z5\nG76 P1 Z-1 I-0.5 J0.001 K1.999\n");
        }
        t
    };
    vec![
        ("G17\n".into(), "1:1", "the lathe works in G18 (Z–X) only"),
        ("G19 G0 X1\n".into(), "1:1", "plane the lathe does not have"),
        ("G59.1\n".into(), "1:1", "the lathe's work systems are G54 to G59"),
        ("G10 L2 X1\n".into(), "1:1", "G10 L2 needs P, the work system: P1 (G54) to P6 (G59)"),
        ("G10 L2 P7 X1\n".into(), "1:8", "G10 L2 P7: the lathe's work systems are G54 to G59, P1 to P6"),
        ("G10 L1 P1 X1\n".into(), "1:5", "G10 L1: a lathe program cannot set a tool offset"),
        ("G10 P1 X1\n".into(), "1:1", "G10 needs L: L2 (a work offset) or L20"),
        ("G10 L2 P1\n".into(), "1:1", "G10 L2 names no axis: give X or Z"),
        ("G10 L20 P1 W1\n".into(), "1:12", "U and W are increments"),
        ("G10 L2 P1 X1 R5\n".into(), "1:14", "a lathe's is not turned"),
        ("G10 L2 P1 Z20000\n".into(), "1:11", "G10 L2: the work offset's Z would be 20000 mm, beyond the 10000 mm"),
        ("#5223 = 1\n".into(), "1:1", "#5223: set a work offset with G10 L2 P1–P6"),
        ("T1 M6\nG0 X1 Z1\nG41\nG10 L2 P1 Z1\n".into(), "4:1", "G10 L2 of the work system in force under nose-radius compensation: give G40 first"),
        ("T1 M6\nG0 X1 Z1\nG41\nG55\n".into(), "4:1", "G55 under nose-radius compensation: give G40 first"),
        ("G73\n".into(), "1:1", "G73 is Fanuc's pattern repeating, read in Fanuc's dialect only"),
        (
            "G90.1\n".into(),
            "1:1",
            "arc centres I and K from the arc's start only: G91.1",
        ),
        ("M6\n".into(), "1:1", "M06 without a tool: give T"),
        ("M7 M8\n".into(), "1:4", "in the same modal group"),
        (
            "G0 Y5\n".into(),
            "1:4",
            "unknown word Y (the lathe has the axes X and Z",
        ),
        ("G0 X1 G1 Z1\n".into(), "1:7", "same modal group"),
        ("G1 X10 F0\n".into(), "1:8", "the feed must be above 0"),
        (
            "G96 S100 D0\n".into(),
            "1:10",
            "G96 speed limit must be above 0",
        ),
        (
            "G96 S100 D9000\n".into(),
            "1:10",
            "at most the spindle's maximum 6000 rpm",
        ),
        ("S-5\n".into(), "1:1", "S-5: the speed must not be negative"),
        (
            "S9000 M3\n".into(),
            "1:1",
            "above channel 1's spindle maximum of 6000 rpm",
        ),
        ("G96 S9000\nG97\n".into(), "2:1", "(G97)"),
        ("T1.5\n".into(), "1:1", "a tool is T and 1 to 4 digits"),
        (
            "T9\n".into(),
            "1:1",
            "tool 9 is not on channel 1's tool post (it has 1, 2, 3)",
        ),
        ("T0102\n".into(), "1:1", "offset 2 is not tool 1's"),
        (
            s("G42\nT0202\n"),
            "3:1",
            "change tools with nose-radius compensation off",
        ),
        (
            "M100 P1.5\n".into(),
            "1:6",
            "lists channels by their digits",
        ),
        (
            "M100 P14\n".into(),
            "1:6",
            "channel 4 does not exist (the machine has channels 1 to 3)",
        ),
        ("M100 P23\n".into(), "1:6", "must list its own channel 1"),
        ("G4\n".into(), "1:1", "G04 needs P, the dwell in seconds"),
        (
            "G4 P-1\n".into(),
            "1:4",
            "G04 P-1: the dwell must not be negative",
        ),
        // Issue 20: the limits the three readers share (docs/limits.md).
        (
            "G4 P1001\n".into(),
            "1:4",
            "the dwell P1001 is longer than the longest dwell, 1000 s",
        ),
        (
            format!("G0 X{}\n", "9".repeat(309)),
            "1:5",
            "…(309 characters) is too large for a number",
        ),
        (
            s("G1 X10 Z1 F0.5\n"),
            "2:1",
            "F0.5 is below the slowest feed, 1 mm/min (G94 reads F per minute: G95 reads it per revolution)",
        ),
        (
            s("G95 G1 X10 Z1 F0.000001\n"),
            "2:5",
            "more than the 1000 s one move may take",
        ),
        (
            s("G33 X40 Z-60 K0.0000001\n"),
            "2:1",
            "more than the 1000 s one move may take",
        ),
        (
            format!("{}G0 X1\n", "\n".repeat(1_000_000)),
            "1000001:1",
            "the program has 1000001 lines, more than the 1000000 a lathe program may have",
        ),
        ("X10\n".into(), "1:1", "X or Z without a motion mode"),
        (
            "G0 X10 Z1\nI5\n".into(),
            "2:1",
            "I, K or R without an X or Z end point",
        ),
        (
            "G0 X10 Q5\n".into(),
            "1:8",
            "the Q word is not used by anything on this line",
        ),
        ("G0 X10 K5\n".into(), "1:8", "the K word is not used"),
        ("G0 X10 U2\n".into(), "1:8", "X and U on one line"),
        ("G0 Z10 W2\n".into(), "1:8", "Z and W on one line"),
        (
            "G8 G0 X9999999\n".into(),
            "1:1",
            "the end point is not a reasonable number",
        ),
        (
            "G1 X10\n".into(),
            "1:1",
            "a feed move without a feed: give F",
        ),
        (
            "G95 G1 X10 F0.1\n".into(),
            "1:5",
            "feed per revolution (G95) with the spindle stopped",
        ),
        (
            "G0 X20 Z0\nG2 X30 Z-5 R5 I1 F1\n".into(),
            "2:1",
            "both R and I/K",
        ),
        (
            "G0 X20 Z0\nG2 X40 Z-5 R1 F1\n".into(),
            "2:1",
            "R 1.0000 is too small",
        ),
        (
            "G0 X20 Z0\nG2 X20 Z0 R5 F1\n".into(),
            "2:1",
            "an R arc cannot end where it starts",
        ),
        (
            "G0 X20 Z0\nG2 X30 Z-5 I0 K-3 F1\n".into(),
            "2:1",
            "the end point is not on the arc",
        ),
        (
            "G0 X20 Z0\nG2 X20 Z0 I0 K0 F1\n".into(),
            "2:1",
            "the arc's radius is zero",
        ),
        (
            "G0 X20 Z0\nG2 X30 Z-5 F1\n".into(),
            "2:1",
            "an arc needs its centre",
        ),
        (s("G0 X20 Z0\nG33 Z-5\n"), "3:1", "G33 needs K"),
        (
            s("G0 X20 Z0\nG33 Z-5 K0\n"),
            "3:9",
            "the lead must be above 0",
        ),
        (
            "G0 X20 Z0\nG33 Z-5 K1\n".into(),
            "2:1",
            "G33 with the spindle stopped",
        ),
        (s("G0 X20 Z0\nG33 X22 K1\n"), "3:1", "G33 needs a Z move"),
        (
            s("G0 X20 Z5\nG42 G0 X10 Z2\nG1 Z0 F1\nG40\nG41\n"),
            "6:1",
            "G41/G42 after G40 before its exit move",
        ),
        (
            "G42\n".into(),
            "1:1",
            "nose-radius compensation needs a tool",
        ),
        (
            s("G0 X20 Z5\nG42 G0 X10 Z2\nG33 Z-5 K1\n"),
            "4:1",
            "threading with nose-radius compensation in force",
        ),
        (
            s("G0 X20 Z5\nG42 G0 X10 Z2\nG1 Z0 F1\nG40 G2 X20 Z-5 R5\n"),
            "5:5",
            "the exit move) must be a straight line",
        ),
        (
            s("G0 X20 Z5\nG42 G1 X20 Z4.5 F1\n"),
            "3:5",
            "is not longer than the nose radius (0.8000 mm)",
        ),
        (
            "G0 X250 Z0\n".into(),
            "1:1",
            "X 125.000 (radius) is outside channel 1's X travel -1 to 100 mm",
        ),
        (
            "G0 X20 Z300\n".into(),
            "1:1",
            "Z 300.000 is outside channel 1's Z travel -200 to 200 mm",
        ),
        (
            "G0 X190 Z0\nG1 F100\nG3 X190 Z-20 R10\n".into(),
            "3:1",
            "X 105.000 (radius) is outside",
        ),
        (
            s("G0 X20 Z5\nG42 G0 X10 Z2\nG1 Z0 F1\nG2 X11 Z-0.5 R0.5\nG40 G0 X40\n"),
            "5:1",
            "puts the nose (radius 0.8000 mm) inside this arc of radius 0.5000 mm",
        ),
        (
            "G0 X20 Z5\nG42.1 L2\n".into(),
            "2:1",
            "G41.1/G42.1 needs D, the nose's diameter",
        ),
        (
            "G0 X20 Z5\nG42.1 D0.8 L12\n".into(),
            "2:12",
            "L12: the orientation is 0 to 9",
        ),
        (
            s("G0 X20 Z5\nG42 G0 X10 Z2\nG41.1 D0.8\n"),
            "4:1",
            "G41.1/G42.1 with compensation in force: give G40 first",
        ),
        (
            s("G0 X30 Z5\nG42 G0 X20 Z2\nG1 Z-10 F1\nX18\nZ-10.5\nX20\nZ-20\nG40 G0 X40\n"),
            "7:1",
            "gouge: the concave corner after line 6 cannot be reached by the nose",
        ),
        (
            s("G8 G0 X5 Z5\nG42 G0 X2 Z2\nG1 Z-10 F1\nG2 X3 Z-9 R1\nG40 G0 X10\n"),
            "5:1",
            "gouge: the corner between the straight move before and this arc",
        ),
        (
            s("G0 X20 Z5\nG76 Z-10 I-1 J0.1 K0.5\n"),
            "3:1",
            "G76 needs P",
        ),
        (
            s("G0 X20 Z5\nG76 P1 X10 Z-10 I-1 J0.1 K0.5\n"),
            "3:8",
            "takes no X word",
        ),
        (
            s("G0 X20 Z5\nG42\nG76 P1 Z-10 I-1 J0.1 K0.5\n"),
            "4:1",
            "G76 with nose-radius compensation in force",
        ),
        (
            "G0 X20 Z5\nG76 P1 Z-10 I-1 J0.1 K0.5\n".into(),
            "2:1",
            "G76 with the spindle stopped",
        ),
        (
            s("G0 X20 Z5\nG76 P0 Z-10 I-1 J0.1 K0.5\n"),
            "3:5",
            "P, the pitch, must be above 0",
        ),
        (
            s("G0 X20 Z5\nG76 P1 Z-10 I-1 J0 K0.5\n"),
            "3:17",
            "J, the first cut's depth",
        ),
        (
            s("G0 X20 Z5\nG76 P1 Z-10 I-1 J0.1 K0.05\n"),
            "3:22",
            "K, the thread's depth, must be greater than J",
        ),
        (
            s("G0 X20 Z5\nG76 P1 Z-10 I0 J0.1 K0.5\n"),
            "3:13",
            "I, the peak's offset",
        ),
        (
            s("G0 X20 Z5\nG76 P1 Z-10 I-1 J0.1 K0.5 R0.5\n"),
            "3:27",
            "R, the depth degression",
        ),
        (
            s("G0 X20 Z5\nG76 P1 Z-10 I-1 J0.1 K0.5 H1.5\n"),
            "3:27",
            "H, the spring passes",
        ),
        (
            s("G0 X20 Z5\nG76 P1 Z-10 I-1 J0.1 K0.5 Q95\n"),
            "3:27",
            "Q, the compound angle, must be 0 to below 90",
        ),
        (
            s("G0 X20 Z5\nG76 P1 Z-10 I-1 J0.1 K0.5 E-1\n"),
            "3:27",
            "E, the taper ends' length along Z, must be 0 or more",
        ),
        (
            s("G0 X20 Z5\nG76 P1 Z-10 I-1 J0.1 K0.5 E8 L3\n"),
            "3:27",
            "G76 E: the taper ends are as long as the thread",
        ),
        (
            s("G0 X20 Z5\nG76 P1 Z-10 I-1 J0.1 K0.5 L7\n"),
            "3:27",
            "L must be 0 to 3",
        ),
        (
            s("G0 X20 Z5\nG76 P1 Z5 I-1 J0.1 K0.5\n"),
            "3:8",
            "a thread needs a length",
        ),
        (
            s("G0 X20 Z5\nG76 P1 Z-10 I-1 J0.0001 K0.5\n"),
            "3:1",
            "G76 makes more than 2000 passes",
        ),
        (
            "G70 P1.5 Q2\n".into(),
            "1:5",
            "G70 P1.5: a sequence number N",
        ),
        ("G70 P1 Q2\n".into(), "1:5", "G70 P1: no line N1"),
        (
            "G70 P2 Q1\nN1 G0 X1\nN2 G0 X2\n".into(),
            "1:1",
            "line Q comes before line P",
        ),
        (
            "G70 P1 Q2\nN1 G0 X10\nN2 G71 U1\n".into(),
            "3:4",
            "G71 inside a G70/G71 profile",
        ),
        (
            "G70 P1 Q2\nN1 G0 X10\nN2 M30\n".into(),
            "3:4",
            "M30 inside a G70/G71 profile",
        ),
        ("G71 R1\n".into(), "1:1", "G71 (first block) needs U"),
        (
            "G71 U0\n".into(),
            "1:5",
            "G71 U, the depth of cut, must be above 0",
        ),
        (
            "G71 U1 R-1\n".into(),
            "1:8",
            "G71 R, the retract, must not be negative",
        ),
        (
            "G71 P1 Q2\nN1 G0 X1\nN2 G1 Z1\n".into(),
            "1:1",
            "needs its depth of cut: the first G71 block",
        ),
        (
            "G71 Q100 X20 Z2 D0.5 I0.2 R1\n".into(),
            "1:1",
            "G71 Q without P is LinuxCNC's own G71 form",
        ),
        (
            s("G42\nG71 U1\nG71 P1 Q2\n"),
            "4:1",
            "G71 with nose-radius compensation in force",
        ),
        (
            "N1 G0 X10\nN2 G1 Z-5 F100\nG71 U1\nG71 P1 Q2 F100\n".into(),
            "4:1",
            "must follow the G71 line",
        ),
        (
            "G0 X40 Z2\nG71 U1\nG71 P1 Q2\nN1 G0 X10\nN2 G1 Z-5\n".into(),
            "3:1",
            "roughs at the feed in force: give F",
        ),
        (
            "G0 X40 Z2\nG71 U1\nG71 P1 Q2 F1\nN1 (nothing)\nN2 G4 P0\n".into(),
            "3:1",
            "has no move",
        ),
        // A G71 profile whose first line names Z is Fanuc's type II (stop 56), whose first
        // move may go in towards the part; G72's must still move Z only, and type II's must
        // not move away from the part.
        (
            "G0 X40 Z2\nG72 W1\nG72 P1 Q2 F1\nN1 G0 X10 Z0\nN2 G1 X5\n".into(),
            "4:4",
            "first move must move Z only",
        ),
        (
            "G0 X40 Z2\nG71 U1\nG71 P1 Q2 F1\nN1 G0 X10 Z4\nN2 G1 Z-5\n".into(),
            "4:4",
            "its first move turns back in Z",
        ),
        (
            "G0 X40 Z2\nG71 U1\nG71 P1 Q2 F1\nN1 G0 X10\nN2 G1 X20\n".into(),
            "4:4",
            "must move along Z after its first move",
        ),
        (
            "G0 X40 Z2\nG71 U1\nG71 P1 Q3 F1\nN1 G0 X10\nG1 X20 Z-5\nN3 G1 X15 Z-10\n".into(),
            "6:4",
            "turns back in X",
        ),
        (
            "G0 X40 Z2\nG71 U1\nG71 P1 Q3 F1\nN1 G0 X10\nG1 X20 Z-5\nN3 G1 X25 Z-3\n".into(),
            "6:4",
            "turns back in Z",
        ),
        (
            "G0 X40 Z2\nG71 U1\nG71 P1 Q3 F1\nN1 G0 X10\nG1 Z-5\nN3 G3 X10 Z-15 R5\n".into(),
            "6:4",
            "an arc that turns back",
        ),
        (
            s("G0 X40 Z2\nG71 U1\nG71 P1 Q3 F1\nN1 G0 X10\nG1 Z-5\nN3 G33 X20 Z-15 K1\n"),
            "7:4",
            "G33 in a G71 profile",
        ),
        (
            "G0 X20 Z2\nG71 U1\nG71 P1 Q2 U4 F1\nN1 G0 X18\nN2 G1 Z-5\n".into(),
            "3:1",
            "must be outside the stock",
        ),
        (
            "G0 X40 Z2\nG71 U0.0001\nG71 P1 Q2 F1\nN1 G0 X10\nN2 G1 Z-5\n".into(),
            "3:1",
            "G71 would make more than 2000 passes",
        ),
        (long_profile, "8004:1", "the cycle's profile is too long (more than 8000 moves)"),
        (
            many_lines,
            "1",
            "the program executes more than 1000000 lines",
        ),
        (
            many_steps,
            "2",
            "the program makes more than 2000000 operations",
        ),
    ]
}

#[test]
fn every_refusal_names_its_place_and_says_why() {
    let bad = misplaced(&desc(), cases());
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

/// [`desc`] with channel 1 in Fanuc's dialect, in G code system A or B.
fn fanuc(system_a: bool) -> LatheDesc {
    let mut d = desc();
    d.channels[0].dialect = Some(Dialect::Fanuc);
    d.channels[0].system_a = system_a;
    d
}

#[test]
fn system_a_and_fanucs_g76_refusals_name_their_place_and_say_why() {
    let s = |t: &str| format!("{S}{t}");
    let a = vec![
        (s("G91 G0 U1.\n"), "2:1", "G code system A has no G91"),
        (s("G95\n"), "2:1", "G98 per minute and G99 per revolution"),
        (
            s("G50 U1. S2000\n"),
            "2:5",
            "G50 U: shifting the coordinate system by increments is not supported",
        ),
        (s("G50\n"), "2:1", "G50 needs S"),
        (
            s("G50 S7000\n"),
            "2:5",
            "at most the spindle's maximum 6000 rpm",
        ),
        (
            s("G0 X40. Z2.\nG90 X30. Z-10.\n"),
            "3:1",
            "a feed move without a feed",
        ),
        (
            s("G0 X40. Z2.\nG90 X30. Z2. F100\n"),
            "3:1",
            "G90 ends where the tool stands in Z",
        ),
        (
            s("G0 X40. Z2.\nG94 X40. Z-2. F100\n"),
            "3:1",
            "G94 ends where the tool stands in X",
        ),
        (
            "G0 X40. Z2.\nG92 X30. Z-10. F1.5\n".into(),
            "2:1",
            "G92 with the spindle stopped",
        ),
        (
            s("G0 X40. Z2.\nG92 X30. Z-10. F150\n"),
            "3:16",
            "G92 needs F, the lead",
        ),
        (
            s("G0 X40. Z2.\nG71 U1. R0\nG71 P1 Q2 F100\nN1 G0 X10.\nN2 G90 X20. Z-5.\n"),
            "6:4",
            "G90 inside a G70/G71 profile",
        ),
        (
            s("G0 X40. Z5.\nG42 G0 X30. Z2.\nG90 X20. Z-10. F100\n"),
            "4:1",
            "G90 with nose-radius compensation",
        ),
        (
            s("G98 G0 X40. Z2.\nG1 Z-5. F0.08\n"),
            "3:1",
            "(G98 reads F per minute: G99 reads it per revolution)",
        ),
        (
            "G99 G0 X40. Z2.\nG1 Z-5. F0.1\n".into(),
            "2:1",
            "a feed per revolution (G99) with the spindle stopped",
        ),
        (
            s("G0 X24. Z5.\nG76 X18. Z-20. P920 Q350 F1.5\n"),
            "3:1",
            "needs Fanuc's first G76 block",
        ),
        (
            s("G76 P021060 Q150 R0.05 F1\n"),
            "2:24",
            "G76 P Q R (Fanuc's first block) takes no F word",
        ),
        (s("G76 P1000000\n"), "2:5", "six digits mmrraa"),
        (s("G76 P001060\n"), "2:5", "m the finishing passes 01 to 99"),
        (s("G76 P010090\n"), "2:5", "a the tool's angle 00 to 80"),
        (
            s("G76 P1 Z-10. I-1 J0.1 K0.5\n"),
            "2:18",
            "G76 J: a word of LinuxCNC's one-block G76",
        ),
        (
            s("G0 X24. Z5.\nG76 P010060\nG76 X18. Z-20. P0.92 Q350 F1.5\n"),
            "4:16",
            "a whole number of least increments",
        ),
        (
            s("G0 X24. Z5.\nG76 P010060\nG76 X18. Z-20. P920 F1.5\n"),
            "4:1",
            "G76 (second block) needs Q",
        ),
        (
            s("G0 X24. Z5.\nG76 P010060 R1.\nG76 X18. Z-20. P920 Q350 F1.5\n"),
            "4:16",
            "greater than the finishing allowance",
        ),
        (
            s("G0 X19. Z5.\nG76 P010060\nG76 X18. Z-20. P920 Q350 F1.5\n"),
            "4:1",
            "must stand clear of the thread",
        ),
        (
            s("G0 X24. Z5.\nG76 P019960\nG76 X18. Z-5. P920 Q350 F1.5\n"),
            "4:1",
            "the chamfer",
        ),
        (
            s("G0 X24. Z5.\nG76 P010060\nG76 X18. Z-20. P920 Q1 F1.5\n"),
            "4:1",
            "G76 makes more than 2000 passes",
        ),
        (
            s("G0 X24. Z5.\nG76 P010060\nG76 X18. Z-20. P920 Q350\n"),
            "4:1",
            "G76 needs F, the lead",
        ),
        (
            "G0 X24. Z5.\nG76 P010060\nG76 X18. Z-20. P920 Q350 F1.5\n".into(),
            "3:1",
            "G76 with the spindle stopped",
        ),
    ];
    let bad = misplaced(&fanuc(true), a);
    assert!(bad.is_empty(), "{}", bad.join("\n"));
    // In system B (Fanuc's dialect without the line), G50 and G98/G99 are system A's.
    let b = vec![
        (s("G50 S3000\n"), "2:1", "G50 is Fanuc's G code system A"),
        (
            s("G99\n"),
            "2:1",
            "G98 and G99 are the feeds of Fanuc's G code system A",
        ),
        (
            s("G76 P1 Z-10. I-1 J0.1 K0.5\n"),
            "2:18",
            "G76 J: a word of LinuxCNC's one-block G76",
        ),
    ];
    let bad = misplaced(&fanuc(false), b);
    assert!(bad.is_empty(), "{}", bad.join("\n"));
}

#[test]
fn a_program_missing_g95_is_refused_at_its_first_feed() {
    // The sample program with its G95 left out reads F0.08 per minute: ten hours of machine
    // time a part (23.5 s of CPU). It is refused at the feed, saying why.
    let path = format!(
        "{}/programs/citizen/system1.ngc",
        env!("CARGO_MANIFEST_DIR")
    );
    let Ok(text) = std::fs::read_to_string(&path) else {
        panic!("{path} is missing");
    };
    let text = text.replace(" G95", "");
    let e = read_program(&text, &LatheDesc::citizen(), 0, &ReadOptions::default())
        .err()
        .map(|e| e.to_string());
    assert_eq!(
        e.as_deref(),
        Some("12:1: F0.08 is below the slowest feed, 1 mm/min (G94 reads F per minute: G95 reads it per revolution)")
    );
}

#[test]
fn a_missing_channel_is_refused() {
    let e = read_program("G0 X1.\n", &desc(), 5, &ReadOptions::default());
    assert_eq!(
        e.err().map(|e| e.to_string()),
        Some("1:1: channel 6 does not exist (the machine has 3)".to_string())
    );
}

#[test]
fn a_bad_pulse_size_is_refused() {
    let mut d = desc();
    d.pulse_mm = 0.0;
    let e = read_program("G0 X1.\n", &d, 0, &ReadOptions::default());
    assert_eq!(
        e.err().map(|e| e.to_string()),
        Some("1:1: the machine's pulse size is not a positive number".to_string())
    );
}

#[test]
fn the_citizen_samples_read_on_their_channels() {
    let d = LatheDesc::citizen();
    for ch in 0..d.channels.len() {
        let path = format!(
            "{}/programs/citizen/system{}.ngc",
            env!("CARGO_MANIFEST_DIR"),
            ch + 1
        );
        let Ok(text) = std::fs::read_to_string(&path) else {
            panic!("{path} is missing");
        };
        match read_program(&text, &d, ch, &ReadOptions::default()) {
            Ok(p) => assert!(
                p.iter()
                    .flat_map(|s| &s.blocks)
                    .any(|b| matches!(b.motion, Motion::Linear | Motion::ArcCw | Motion::ArcCcw)),
                "{path}: no cutting block"
            ),
            Err(e) => panic!("{path}: {e}"),
        }
    }
}
