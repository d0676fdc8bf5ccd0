//! The translator (automatic programming, AP): source statements to machine instruction
//! blocks (patent lines 283–357, Figs. 10–13, Tables 1, B and C; SPEC §4 and §6).
//!
//! OWNER: translator work (issue 3). The signatures below are the contract with the pulse core
//! and the console; the bodies are to be written.

use crate::block::Block;
use crate::settings::MachineSettings;
use crate::tooldata::Magazine;
use std::fmt;

/// A translation error at a statement: `LINE:COL: message`.
#[derive(Clone, Debug, PartialEq)]
pub struct TranslateError {
    /// 1-based source line.
    pub line: u32,
    /// 1-based column.
    pub col: u32,
    /// What is wrong, in a part programmer's words.
    pub message: String,
}

impl fmt::Display for TranslateError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}: {}", self.line, self.col, self.message)
    }
}

impl std::error::Error for TranslateError {}

/// One source statement and every block generated from it (what the display shows while
/// running: the statement, its blocks, and a marker on the executing one).
#[derive(Clone, Debug, PartialEq)]
pub struct Statement {
    /// 1-based source line.
    pub line: u32,
    /// The statement's source text.
    pub text: String,
    /// The blocks generated from it (empty for most definitions).
    pub blocks: Vec<Block>,
}

/// The translator as an iterator: one statement's blocks at a time, so that it can keep B1
/// full concurrently with execution. After an error it yields nothing more.
pub struct Translator {
    _source: String,
    _magazine: Magazine,
    _settings: MachineSettings,
    _start: [i64; 3],
}

impl Translator {
    /// A translator for `source`, looking tools up in `magazine`, starting with the machine at
    /// `start` (pulses) and no tool in the spindle.
    pub fn new(
        source: &str,
        magazine: Magazine,
        settings: MachineSettings,
        start: [i64; 3],
    ) -> Translator {
        Translator {
            _source: source.to_string(),
            _magazine: magazine,
            _settings: settings,
            _start: start,
        }
    }
}

impl Iterator for Translator {
    type Item = Result<Statement, TranslateError>;

    fn next(&mut self) -> Option<Self::Item> {
        todo!("translator")
    }
}

/// Translates a whole program; the first error fails it.
pub fn translate_all(
    source: &str,
    magazine: &Magazine,
    settings: &MachineSettings,
    start: [i64; 3],
) -> Result<Vec<Statement>, TranslateError> {
    Translator::new(source, magazine.clone(), settings.clone(), start).collect()
}

/// One block as an ISO 6983 word-address line in absolute mm with 3 decimals.
pub fn iso_line(_block: &Block, _settings: &MachineSettings) -> String {
    todo!("ISO printing")
}
