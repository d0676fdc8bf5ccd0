//! Words, good and bad, that the G-code fuzz tests make programs of (`tests/gcode_fuzz.rs`,
//! the fuzz command's G-code family).

/// Each a word or a piece of a line: valid codes, broken numbers, odd characters.
/// Fanuc Custom Macro B fragments (docs/gcode.md "Fanuc dialect"), added to [`FRAGMENTS`]
/// for the Fanuc dialect's fuzz family.
pub const FANUC_FRAGMENTS: &[&str] = &[
    "GOTO 10",
    "GOTO 20",
    "N10",
    "N20",
    "IF [#1 EQ #0] GOTO 10",
    "IF [#2 LT 3] THEN #2=#2+1",
    "IF [#0 NE 0] THEN #3000=1 (ALARM)",
    "WHILE [#2 LT 5] DO1",
    "WHILE [#3 GT 0] DO2",
    "END1",
    "END2",
    "DO3",
    "END3",
    "#1=#0",
    "#2=#2+1",
    "#3=BCD[#2]",
    "#500=#500+1",
    "#100=FIX[-#2]",
    "#3006=1 (STOP)",
    "G65 P100 X1. Y2 A#1",
    "G65 P100 L2 R5.",
    "X10",
    "X#0",
    "Y[ATAN[1]/[-1]]",
];

pub const FRAGMENTS: &[&str] = &[
    "G0",
    "G1",
    "G2",
    "G3",
    "G4 P0.1",
    "G17",
    "G18",
    "G19",
    "G20",
    "G21",
    "G90",
    "G91",
    "G28",
    "G53",
    "G54",
    "G55",
    "G59",
    "G10 L2 P2",
    "G10 L20 P1",
    "G40",
    "G41 D13",
    "G42 D14",
    "G43 H2",
    "G49",
    "G73",
    "G81",
    "G82",
    "G83",
    "G84",
    "G85",
    "G86",
    "G89",
    "G5",
    "G5.1",
    "G5.2",
    "G5.3",
    "G80",
    "G98",
    "G99",
    "X10",
    "Y-5.5",
    "Z2",
    "X[1+2]",
    "Y[#1*2]",
    "I5",
    "J-3",
    "K2",
    "R7",
    "R-7",
    "Q1.5",
    "P0.3",
    "L3",
    "F300",
    "S1000",
    "T13",
    "M3",
    "M4",
    "M5",
    "M6",
    "M8",
    "M9",
    "M0",
    "M1",
    "M2",
    "M30",
    "M98 P100",
    "M99",
    "#1=5",
    "#2=[#1/0]",
    "X[SQRT[-1]]",
    "(comment)",
    ";rest",
    "/",
    "%",
    "O100",
    "N10",
    "X[ATAN[1]/[0]]",
    "X[[[[[[1]]]]]]",
    "X--1",
    "#[#1]=3",
    "A1",
    "B-45.5",
    "C720",
    "A-0",
    "G53 C0",
    "G91 B10 C-10",
    // The rotary axes' offsets (stop 54).
    "G10 L2 P1 A90 C-30",
    "G10 L20 P0 B0 C359",
    "G10 L20 P2 C400",
    "G92 A0 C10",
    "G52 B5",
    "G92 C-360",
    "G10 L1 P1 A5",
    "G92.1 C0",
    "X#5424 Y#<_c> Z#<_abs_a>",
    // Remapped machine M codes (stop 55; the fuzz's machine remaps M31 and M101 now and then).
    "M31",
    "M8 F200 M31 G4 P0.1 G1 X2",
    "M101 G0 X1",
    "M31 M33",
    "G92",
    "G38.2",
    "X",
    "[",
    "]",
    "é",
    "X1.2.3",
    "O<x> sub",
    "GOTO 5",
    "X99999999999999999999",
    "Q0.0001",
    "L9999",
    "P1e9",
    "\u{0}",
    "\u{1b}",
    "\u{feff}",
];

/// Numbers at the edges of what a value can be (issue 20, docs/limits.md): 309 digits (past
/// the largest float), 1e308 and 1.7e308, denormals (4.9e-324, 1e-320), negative zero, 1e17
/// (where 0.1 is below a float's step), 1e-12, the repeat bound and past it, 1e30, and
/// ordinary values.
pub fn extreme_numbers() -> Vec<String> {
    let mut v: Vec<String> = [
        "-0",
        "-0.0",
        "0",
        "0.000000000001",
        "0.000001",
        "0.5",
        "1",
        "2.5",
        "-5",
        "10",
        "-50",
        "100",
        "999",
        "1000",
        "1000.0001",
        "9999",
        "10000",
        "100000000000000000",
        "99999999999999984",
        "1000000000000000000000000000000",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    v.push("9".repeat(309));
    v.push(format!("1{}", "0".repeat(308)));
    v.push(format!("-17{}", "0".repeat(307)));
    v.push(format!("0.{}49", "0".repeat(323)));
    v.push(format!("0.{}1", "0".repeat(319)));
    v
}

/// A program of up to 12 lines whose values are drawn from [`extreme_numbers`]: moves, arcs,
/// cutter compensation, every canned cycle with extreme R, Q, P and L, dwells, feeds, spindle
/// speeds and parameters. `below(n)` draws a number in `0..n`.
pub fn extreme_program(mut below: impl FnMut(usize) -> usize) -> String {
    let nums = extreme_numbers();
    let n = |below: &mut dyn FnMut(usize) -> usize| nums[below(nums.len())].clone();
    let mut s = String::from("G0 X500 Y400 Z-300\nT13 M6\nM3 S1000\n");
    for _ in 0..1 + below(12) {
        let line = match below(12) {
            0 => format!(
                "G0 X{} Y{} Z{}",
                n(&mut below),
                n(&mut below),
                n(&mut below)
            ),
            1 => format!("G1 X{} F{}", n(&mut below), n(&mut below)),
            2 => format!("G4 P{}", n(&mut below)),
            3 | 4 => {
                let g = [73, 81, 82, 83, 84, 85, 86, 89][below(8)];
                format!(
                    "G{g} X{} Y{} Z{} R{} Q{} P{} L{} F{}",
                    n(&mut below),
                    n(&mut below),
                    n(&mut below),
                    n(&mut below),
                    n(&mut below),
                    n(&mut below),
                    n(&mut below),
                    n(&mut below)
                )
            }
            5 => format!(
                "G2 X{} Y{} R{} F{}",
                n(&mut below),
                n(&mut below),
                n(&mut below),
                n(&mut below)
            ),
            6 => format!("G41 D13 G1 X{} Y{} F100", n(&mut below), n(&mut below)),
            7 => "G40 G0 X500 Y400".to_string(),
            8 => format!("#1={}", n(&mut below)),
            9 => format!("G0 X[#1*{}]", n(&mut below)),
            10 => ["G91", "G90", "G20", "G21", "G80", "G98", "G99"][below(7)].to_string(),
            _ => format!("S{} M3", n(&mut below)),
        };
        s.push_str(&line);
        s.push('\n');
    }
    s.push_str("M30\n");
    s
}
