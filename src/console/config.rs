//! The console's configuration: where its memory lives, the machine settings, the clock, the
//! display size and an optional recording. The launcher (`cli`) fills it from the command line.

use crate::pulse_core::ClockMode;
use crate::settings::MachineSettings;
use std::path::PathBuf;

/// Smallest plasma display the display program can fill (lines).
pub const MIN_ROWS: usize = 6;
/// Largest plasma display (lines).
pub const MAX_ROWS: usize = 60;
/// Smallest plasma display (characters per line).
pub const MIN_COLS: usize = 32;
/// Largest plasma display (characters per line).
pub const MAX_COLS: usize = 160;

/// Everything a console needs to open.
#[derive(Clone, Debug)]
pub struct ConsoleConfig {
    /// State directory of program memory, MDI buffer, tool file and T-code table.
    pub state_dir: PathBuf,
    /// The machine settings.
    pub settings: MachineSettings,
    /// Real time (interactive) or virtual time (scripts, tests).
    pub clock: ClockMode,
    /// Plasma display lines (12 by default).
    pub rows: usize,
    /// Plasma display characters per line (40 by default).
    pub cols: usize,
    /// Record the session to this MCAP file.
    pub record: Option<PathBuf>,
    /// Record `/nc/pulses` (`--pulses on|off`, on by default).
    pub record_pulses: bool,
    /// Send the session's events here instead (tests read them back); ignored with `record`.
    pub sink: Option<crate::record::EventSink>,
    /// Asked during long virtual-time waits: true ends the wait early (a stop signal).
    pub interrupt: Option<fn() -> bool>,
}

impl ConsoleConfig {
    /// The default configuration on a state directory: 12×40 display, real time, no recording.
    pub fn new(state_dir: PathBuf) -> ConsoleConfig {
        ConsoleConfig {
            state_dir,
            settings: MachineSettings::default(),
            clock: ClockMode::RealTime,
            rows: 12,
            cols: 40,
            record: None,
            record_pulses: true,
            sink: None,
            interrupt: None,
        }
    }

    /// Rows of text a data page shows around the pointer (header, command, message and entry
    /// lines take the rest): what the editor's page moves step by.
    pub fn text_rows(&self) -> usize {
        self.rows.saturating_sub(4).max(1)
    }

    /// Checks the display size; the message names the bad value.
    pub fn check(&self) -> Result<(), String> {
        if !(MIN_ROWS..=MAX_ROWS).contains(&self.rows) {
            return Err(format!(
                "--rows {} is outside {MIN_ROWS}..={MAX_ROWS}",
                self.rows
            ));
        }
        if !(MIN_COLS..=MAX_COLS).contains(&self.cols) {
            return Err(format!(
                "--cols {} is outside {MIN_COLS}..={MAX_COLS}",
                self.cols
            ));
        }
        Ok(())
    }
}
