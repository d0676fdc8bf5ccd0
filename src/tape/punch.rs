//! The tape punch (docs/tape.md, "Punching a tape"): a text becomes an image of leader, label,
//! rewind stop and end of block, one block per line, the closing rewind stop and a trailer.
//! Every block gets an even number of characters (a pad the reader passes over), so a tape
//! punched here passes the block-parity check.

use super::code::{Code, Frame, Meaning};
use std::fmt;

/// How to punch.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PunchOptions {
    /// The code.
    pub code: Code,
    /// Blank frames before the data, and as many after it (at least 1; 10 frames = 1 inch).
    pub leader: usize,
    /// The label punched before the opening rewind stop, if any.
    pub label: Option<String>,
}

/// The default leader: 100 frames, 10 inches (25 cm) of blank tape.
pub const DEFAULT_LEADER: usize = 100;

/// The longest leader the punch accepts, frames (10,000 frames = 25 m of tape).
pub const MAX_LEADER: usize = 10_000;

/// Why a text cannot be punched.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PunchError {
    /// The line, 1-based (0 for the label).
    pub line: usize,
    /// The character's column, 1-based.
    pub col: usize,
    /// The character.
    pub ch: char,
    /// Why.
    pub reason: String,
}

impl fmt::Display for PunchError {
    /// `LINE:COL: 'ç' has no code in EIA (docs/tape.md)` (`label:COL:` for the label).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.line == 0 {
            write!(f, "label:{}: {}", self.col, self.reason)
        } else {
            write!(f, "{}:{}: {}", self.line, self.col, self.reason)
        }
    }
}

impl std::error::Error for PunchError {}

/// Punches `text` (lines ended by `\n`; the last line's `\n` may be missing, it is punched with
/// its end of block all the same) as a tape image.
pub fn punch(text: &str, opts: &PunchOptions) -> Result<Vec<u8>, PunchError> {
    let code = opts.code;
    let leader = opts.leader.clamp(1, MAX_LEADER);
    let mut out = Vec::with_capacity(text.len() + text.len() / 8 + 2 * leader + 16);
    out.resize(leader, 0);
    if let Some(label) = &opts.label {
        let mut frames = Vec::new();
        encode_line(code, label, 0, &mut frames)?;
        out.extend_from_slice(&frames);
    }
    out.push(code.rewind_stop().0);
    out.push(code.eob().0);
    let body = text.strip_suffix('\n').unwrap_or(text);
    if !text.is_empty() {
        let mut block = Vec::new();
        for (n, line) in body.split('\n').enumerate() {
            block.clear();
            encode_line(code, line, n + 1, &mut block)?;
            out.extend_from_slice(&block);
            // The block's characters and its end of block: an even number (block parity).
            if block.len() % 2 == 0 {
                out.push(code.pad().0);
            }
            out.push(code.eob().0);
        }
    }
    out.push(code.rewind_stop().0);
    out.resize(out.len() + leader, 0);
    Ok(out)
}

/// Appends the frames of one line (no end of block); EIA letters get the case shifts their
/// case needs (the case is upper at the start of every block).
fn encode_line(code: Code, line: &str, n: usize, out: &mut Vec<u8>) -> Result<(), PunchError> {
    let mut lower = false;
    for (col, c) in line.chars().enumerate() {
        let frame = code.frame_of(c).ok_or_else(|| PunchError {
            line: n,
            col: col + 1,
            ch: c,
            reason: unpunchable(code, c, n == 0),
        })?;
        if let (Some((upper, small)), true) = (code.case_shifts(), c.is_ascii_alphabetic()) {
            let want_lower = c.is_ascii_lowercase();
            if want_lower != lower {
                out.push(if want_lower { small.0 } else { upper.0 });
                lower = want_lower;
            }
        }
        out.push(frame.0);
    }
    Ok(())
}

/// Why `c` cannot be punched.
fn unpunchable(code: Code, c: char, label: bool) -> String {
    match c {
        '%' if code == Code::Iso => {
            "'%' is the rewind stop; it cannot be punched inside a block".to_string()
        }
        '\r' => {
            "a carriage return: the end of block is LF alone (convert the file to LF line endings)"
                .to_string()
        }
        '\n' if label => "the label is one line".to_string(),
        c if c.is_control() => format!(
            "the control character U+{:04X} has no code in {} (docs/tape.md)",
            c as u32,
            code.name()
        ),
        c => format!("'{c}' has no code in {} (docs/tape.md)", code.name()),
    }
}

/// The frames of a whole tape drawn one per line, channel 8 on the left (`Frame::row`), with
/// each frame's meaning: for docs and for `novanc tape read --holes`.
pub fn draw(image: &[u8], code: Code) -> String {
    let mut s = String::with_capacity(image.len() * 40);
    let mut lower = false;
    for (i, &b) in image.iter().enumerate() {
        let f = Frame(b);
        let what = match code.meaning(f) {
            Meaning::Blank => "blank".to_string(),
            Meaning::RubOut => "rub-out".to_string(),
            Meaning::PassedOver(n) => format!("{n} (passed over)"),
            Meaning::EndOfBlock => {
                lower = false;
                "EOB".to_string()
            }
            Meaning::RewindStop => "rewind stop".to_string(),
            Meaning::UpperCase => {
                lower = false;
                "upper case".to_string()
            }
            Meaning::LowerCase => {
                lower = true;
                "lower case".to_string()
            }
            Meaning::Char(' ') => "space".to_string(),
            Meaning::Char('\t') => "tab".to_string(),
            Meaning::Char(c) if lower => c.to_ascii_lowercase().to_string(),
            Meaning::Char(c) => c.to_string(),
            Meaning::ParityError => "PARITY ERROR".to_string(),
            Meaning::NotInCode => "NOT IN THE CODE".to_string(),
        };
        s.push_str(&format!("{:>7}  {}  {what}\n", i + 1, f.row()));
    }
    s
}
