//! The stores the controller remembers across restarts: program memory, the MDI buffer, the
//! tool file and the T-code table (patent Table A; SPEC §2). Every accepted edit is journaled and
//! fsynced before it is acknowledged.
//!
//! OWNER: memory and data entry work (issue 2). The signatures below are the contract with the
//! console; the bodies are to be written.

use crate::tooldata::Magazine;
use std::fmt;
use std::path::{Path, PathBuf};

/// Which buffer an edit applies to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    /// The current part program in program memory (PROGRAM REVISION).
    Program,
    /// The MDI buffer (MDI).
    Mdi,
    /// The tool file, one T code per line (TOOL DATA REVISION).
    ToolFile,
}

/// A store failure (I/O, or a refused edit), with the operator's message.
#[derive(Clone, Debug, PartialEq)]
pub struct StoreError {
    /// What happened.
    pub message: String,
}

impl fmt::Display for StoreError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

/// Program memory, MDI buffer, tool file and T-code table, persisted in a state directory.
pub struct Stores {
    _private: (),
}

impl Stores {
    /// The state directory: `NOVANC_STATE`, else `$XDG_STATE_HOME/novanc`, else
    /// `~/.local/state/novanc`.
    pub fn default_dir() -> PathBuf {
        todo!("stores")
    }

    /// Opens (or creates, on the embedded defaults) the stores in `dir`, replaying the journal.
    /// Returns warnings to show the operator (for example a corrupt journal tail skipped).
    pub fn open(_dir: &Path, _capacity: u32) -> Result<(Stores, Vec<String>), StoreError> {
        todo!("stores")
    }
}

/// The magazine (T-code table and tool file) the translator uses.
pub fn magazine_of(_s: &Stores) -> Magazine {
    todo!("stores")
}
