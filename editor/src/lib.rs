//! The NC editor core (docs/editor.md; patent lines 437–485, Figs. 21–29): a text buffer with a
//! pointer, and atomic command lines of `L M K D I S C Y`. Pure: no I/O, no threads.
//!
//! The operator's reference and every choice made: `docs/editor.md`.
//! Modules: `parse` (command line → commands), `exec` (atomic run with an undo log), `text`
//! (chunked store with character and EOB counts), `view` (the display around the pointer).

use std::fmt;

// Lets `tests/model.rs` name this crate when it is compiled as a unit test too.
#[cfg(test)]
extern crate self as novanc_editor;

mod exec;
#[cfg(test)]
mod exec_tests;
/// The property test of `tests/model.rs`, run again here with tiny chunks.
#[cfg(test)]
#[path = "../tests/model.rs"]
mod model_tests;
mod parse;
mod text;
mod view;

pub use view::View;

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
            parse::cut(&self.command),
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
    text: text::Text,
    pointer: usize,
}

impl Buffer {
    /// An empty buffer, pointer at 0.
    pub fn new() -> Buffer {
        Buffer::default()
    }

    /// A buffer holding `text`, pointer at 0.
    pub fn from_text(text: &str) -> Buffer {
        Buffer {
            text: text::Text::from_str(text),
            pointer: 0,
        }
    }

    /// Length in characters.
    pub fn len(&self) -> usize {
        self.text.len()
    }

    /// Whether the buffer is empty.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The pointer, in characters from the start.
    pub fn pointer(&self) -> usize {
        self.pointer
    }

    /// Moves the pointer to `pos`, clamped to the buffer (0..=len).
    pub fn set_pointer(&mut self, pos: usize) {
        self.pointer = pos.min(self.len());
    }

    /// The whole text.
    pub fn text(&self) -> String {
        self.text.slice(0, self.len())
    }

    /// The whole text in one shared allocation (copied once, for another thread).
    pub fn text_shared(&self) -> std::sync::Arc<str> {
        self.text.to_shared()
    }

    /// The characters `start..end` (clamped to the buffer).
    pub fn slice(&self, start: usize, end: usize) -> String {
        self.text.slice(start, end)
    }

    /// Number of lines (blocks), counted as `str::lines` does: a last line without EOB counts,
    /// the empty place after a final EOB does not.
    pub fn line_count(&self) -> usize {
        let eobs = self.text.eob_count();
        let len = self.len();
        if len > 0 && self.text.line_start(eobs) < len {
            eobs + 1
        } else {
            eobs
        }
    }

    /// 0-based index of the line holding character position `pos` (the EOBs before it;
    /// `pos` is clamped). After a final EOB this is `line_count()`.
    pub fn line_of(&self, pos: usize) -> usize {
        self.text.line_of(pos)
    }

    /// Character position where line `line` (0-based) starts; past the last line, the length.
    pub fn line_start(&self, line: usize) -> usize {
        self.text.line_start(line)
    }

    /// Bytes of memory held by the text store (for the benchmark's memory figure).
    pub fn heap_bytes(&self) -> usize {
        self.text.heap_bytes()
    }

    /// The lines around the pointer for a display of `rows` × `cols`, EOB shown as `*`.
    pub fn view(&self, rows: usize, cols: usize) -> View {
        view::view(self, rows, cols)
    }

    /// Runs one command line atomically: on any failure the buffer and pointer are unchanged.
    pub fn execute(&mut self, line: &str, opts: &ExecOptions) -> Result<Outcome, EditError> {
        exec::execute(self, line, opts)
    }
}

/// Parses a command line into commands (`*` = EOB in text, `$` ends a text argument).
pub fn parse(line: &str) -> Result<Vec<Command>, EditError> {
    parse::parse(line)
}
