//! The G-code part of the operator-sequence test (tests/operator_sequences.rs): one session
//! in three runs `programs/tableb.ngc` (read at the console by PROGRAM READ) instead of Table B
//! in the source language, and MDI takes G-code lines too.
//!
//! Table B in G-code commands the same lowest tip Z as the source language (-485 mm: the bore,
//! Z-35 in G54 Z-450 under G43). One difference is modelled, not waived: G-code's Z carries
//! the tool length G43 read when the line was translated (as LinuxCNC), so a length revised
//! on the OFS page during a G-code run does not move that run's blocks, and the tip goes lower
//! by the increase until the next run. [`revised_in_run`] lowers the bound by exactly that.

/// The program a G-code session runs.
pub const PROGRAM: &str = "programs/tableb.ngc";

/// G-code MDI lines and the lowest tool-tip Z each commands, mm (G53: machine coordinates of
/// the gauge line, so the tip is that less the tool length, at most 230 mm plus wear).
pub const MDI: [(&str, f64); 4] = [
    ("G53 G0 Z0", -235.0),
    ("G53 G0 X300 Y200", 0.0),
    ("G53 G1 Z-200 F800", -435.0),
    ("G10 L2 P2 X10 Y20 Z-30", 0.0),
];

/// SEARCH targets in the G-code program (text found in it).
pub const SEARCH: [&str; 4] = ["G81", "G84", "T4 M6", "G85"];

/// Work offset lines typed on the OFS page (Table B sets G54 itself with G10).
pub const OFFSETS: [&str; 3] = ["G54 X1", "G55 X100 Y50 Z-300", "G59 Z-1"];

/// The tip bound after a tool's length went from `before` to `after` mm with a G-code run
/// loaded: lower by the increase.
pub fn revised_in_run(lowest_mm: f64, before: f64, after: f64) -> f64 {
    lowest_mm - (after - before).max(0.0)
}

/// A G-code text as the Fanuc dialect reads it the same: a decimal point added to every whole
/// number of a length word (X Y Z I J K R Q), outside comments (Fanuc reads `X150` as 150
/// least increments, 0.150 mm; docs/gcode.md "Fanuc dialect").
pub fn fanuc_text(text: &str) -> String {
    let mut out = String::with_capacity(text.len() + text.len() / 8);
    let mut chars = text.chars().peekable();
    let mut comment = false;
    while let Some(c) = chars.next() {
        out.push(c);
        match c {
            '(' => comment = true,
            ')' => comment = false,
            'X' | 'Y' | 'Z' | 'I' | 'J' | 'K' | 'R' | 'Q' if !comment => {
                if let Some(&s) = chars.peek().filter(|s| **s == '-' || **s == '+') {
                    out.push(s);
                    chars.next();
                }
                let mut digits = false;
                while let Some(&d) = chars.peek().filter(|d| d.is_ascii_digit()) {
                    out.push(d);
                    chars.next();
                    digits = true;
                }
                if digits && chars.peek() != Some(&'.') {
                    out.push('.');
                }
            }
            _ => {}
        }
    }
    out
}
