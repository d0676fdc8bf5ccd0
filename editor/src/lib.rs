//! The NC editor core (SPEC §5; patent lines 437–485, Figs. 21–29): a text buffer with a
//! pointer, and atomic command lines of `L M K D I S C Y`. Pure: no I/O, no threads.
//!
//! OWNER: editor work (issue 2).

use std::fmt;

/// The end-of-block character as stored in a buffer (shown as `*` on the display).
pub const EOB: char = '\n';

/// One editor command, parsed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Command {
    /// `nL`: pointer to the start of the n-th line after the current one.
    L(i64),
    /// `mM`: pointer m characters forward or back.
    M(i64),
    /// `nK`: kill lines.
    K(i64),
    /// `nD`: delete characters.
    D(i64),
    /// `Itext`: insert.
    I(String),
    /// `Stext`: search forward.
    S(String),
    /// `Cold$new`: substitute.
    C(String, String),
    /// `nY`: display n lines from the pointer.
    Y(i64),
}

/// A failed command line: which command (0-based, and as typed) and why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EditError {
    /// Index of the failing command in the line (0-based).
    pub index: usize,
    /// The failing command as typed.
    pub command: String,
    /// Why it failed.
    pub reason: String,
}

impl fmt::Display for EditError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "command {} '{}': {}",
            self.index + 1,
            self.command,
            self.reason
        )
    }
}

impl std::error::Error for EditError {}

/// A check of the whole buffer after a command line; an Err rejects the line.
pub type Validator<'a> = &'a dyn Fn(&Buffer) -> Result<(), String>;

/// What a caller may ask of one command line.
#[derive(Clone, Copy, Default)]
pub struct ExecOptions<'a> {
    /// The most lines `Y` may show (the display height); None = no limit (batch editing).
    pub y_max_lines: Option<usize>,
    /// Checks the buffer after the whole line ran; an Err rejects the line (rolled back).
    pub validator: Option<Validator<'a>>,
}

/// What a successful command line produced.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Outcome {
    /// Text shown by `Y` commands, in order.
    pub y_output: String,
    /// Whether the text changed (not just the pointer).
    pub changed: bool,
}

/// A text buffer with a pointer between characters (0..=len, counted in characters).
#[derive(Clone, Debug, Default)]
pub struct Buffer {
    _private: (),
}

impl Buffer {
    /// An empty buffer, pointer at 0.
    pub fn new() -> Buffer {
        todo!("editor")
    }

    /// A buffer holding `text`, pointer at 0.
    pub fn from_text(_text: &str) -> Buffer {
        todo!("editor")
    }

    /// Length in characters.
    pub fn len(&self) -> usize {
        todo!("editor")
    }

    /// Whether the buffer is empty.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The pointer, in characters from the start.
    pub fn pointer(&self) -> usize {
        todo!("editor")
    }

    /// The whole text.
    pub fn text(&self) -> String {
        todo!("editor")
    }

    /// The characters `start..end` (clamped to the buffer).
    pub fn slice(&self, _start: usize, _end: usize) -> String {
        todo!("editor")
    }

    /// Runs one command line atomically: on any failure the buffer and pointer are unchanged.
    pub fn execute(&mut self, _line: &str, _opts: &ExecOptions) -> Result<Outcome, EditError> {
        todo!("editor")
    }
}

/// Parses a command line into commands (`*` = EOB in text, `$` ends a text argument).
pub fn parse(_line: &str) -> Result<Vec<Command>, EditError> {
    todo!("editor")
}
