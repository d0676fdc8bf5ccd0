//! The bounds on what a program may cost, one set for the three readers: the source language
//! (`translator`), the mill's G-code (`gcode`) and the lathe's G-code (`lathe::gcode`)
//! (docs/limits.md). Each reader checks them where the words are read, before it generates
//! anything, and refuses the line with `LINE:COL: reason`.
//!
//! The numbers are the machine's reasons, not the reader's: B1 holds a whole statement's blocks
//! (`MAX_BLOCKS`), a feed below `MIN_FEED` prints as `F0` and never ends, the lathe simulator
//! steps every tick of machine time (`MAX_MOVE_S`).

use crate::block::TranslateError;

/// The most characters a line may hold, comment included.
pub const MAX_LINE_CHARS: usize = 10_000;

/// The most blocks one statement (a source statement or a G-code line, cycles expanded) may
/// make: B1 holds a whole statement's blocks.
pub const MAX_BLOCKS: usize = 1_000_000;

/// The most blocks one program may make, every repeat counted: twice `MAX_LINES`, room for a
/// program at the line bound with its canned cycles.
pub const MAX_PROGRAM_BLOCKS: u64 = 20_000_000;

/// The most lines a mill G-code program may execute, counting every line of the file it reads
/// (blank ones too) and every repeat of a subprogram.
pub const MAX_LINES: u64 = 10_000_000;

/// The most repeats an L word asks for (M98 L, canned-cycle L).
pub const MAX_REPEATS: u32 = 9_999;

/// The most pecks of one hole (`DH` of the source language, Q of G73/G83).
pub const MAX_PECKS: u32 = 1_000;

/// The longest dwell, seconds (`DW`, G04 P, a canned cycle's P, the lathe's G04 P).
pub const MAX_DWELL_S: f64 = 1_000.0;

/// The slowest feed per minute, mm/min (`FR`, a tool file's feed, F under G94): slower prints
/// as `F0` in a listing and takes a machine an unbounded time.
pub const MIN_FEED: f64 = 1.0;

/// The highest spindle speed S a block may carry, rpm.
pub const MAX_SPEED: f64 = 100_000.0;

/// The longest one feed move of a lathe program may take at its feed, seconds: the lathe
/// simulator steps every channel each tick of machine time, so a move's cost is its time.
pub const MAX_MOVE_S: f64 = 1_000.0;

/// The most lines a lathe program may have, and execute (G70 repeats of its profile lines
/// counted): a lathe program is read whole before it runs.
pub const LATHE_MAX_LINES: u64 = 1_000_000;

/// The most operations one lathe program may make (cycles included).
pub const LATHE_MAX_STEPS: usize = 2_000_000;

/// The most passes one G71 or G76 cycle may make.
pub const MAX_PASSES: usize = 2_000;

/// The error for line `line` if it holds more than [`MAX_LINE_CHARS`] characters, at the first
/// column past the limit; `hint` ends the message (how to split the line).
pub fn line_too_long(raw: &str, line: u32, hint: &str) -> Option<TranslateError> {
    if raw.len() <= MAX_LINE_CHARS {
        return None;
    }
    let n = raw.chars().count();
    (n > MAX_LINE_CHARS).then(|| TranslateError {
        line,
        col: MAX_LINE_CHARS as u32 + 1,
        message: format!(
            "the line is {n} characters long; a line holds at most {MAX_LINE_CHARS}{hint}"
        ),
    })
}

/// The message for a dwell of `text` (as written, e.g. `DW2000` or `P1001`) longer than
/// [`MAX_DWELL_S`].
pub fn dwell_too_long(text: &str) -> String {
    format!("the dwell {text} is longer than the longest dwell, {MAX_DWELL_S} s")
}

/// The message for a feed `text` (as written) below [`MIN_FEED`].
pub fn feed_too_slow(text: &str) -> String {
    format!("{text} is below the slowest feed, {MIN_FEED} mm/min")
}
