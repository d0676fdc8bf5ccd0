//! The console's configuration: where its memory lives, the machine settings, the clock, the
//! display size and an optional recording; parsed from the command line.

use crate::cli::args::{Args, Opt};
use crate::nc::ClockMode;
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
        }
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

/// The options the console understands (other options are left to the caller).
const OPTS: [&str; 4] = ["--state", "--rows", "--cols", "--record"];

/// Parses `--state DIR`, `--rows N`, `--cols N` and `--record OUT.mcap` out of `argv`; returns
/// the configuration (real time, default settings) and every other argument, in order.
pub fn config_from_args(argv: &[String]) -> Result<(ConsoleConfig, Vec<String>), String> {
    let mut mine = Vec::new();
    let mut rest = Vec::new();
    let mut i = 0;
    while i < argv.len() {
        let a = &argv[i];
        let name = a.split_once('=').map(|(n, _)| n).unwrap_or(a.as_str());
        if OPTS.contains(&name) {
            mine.push(a.clone());
            if !a.contains('=') {
                if let Some(v) = argv.get(i + 1) {
                    mine.push(v.clone());
                    i += 1;
                }
            }
        } else {
            rest.push(a.clone());
        }
        i += 1;
    }
    let opts: Vec<Opt> = OPTS
        .iter()
        .map(|n| Opt {
            name: n,
            takes_value: true,
        })
        .collect();
    let args = Args::parse(&mine, &opts)?;
    let state = match args.value("--state") {
        Some(d) => PathBuf::from(d),
        None => super::memory::default_state_dir(),
    };
    let mut cfg = ConsoleConfig::new(state);
    if let Some(r) = args.value("--rows") {
        cfg.rows = r
            .parse()
            .map_err(|_| format!("--rows '{r}' is not a whole number"))?;
    }
    if let Some(c) = args.value("--cols") {
        cfg.cols = c
            .parse()
            .map_err(|_| format!("--cols '{c}' is not a whole number"))?;
    }
    cfg.record = args.value("--record").map(PathBuf::from);
    cfg.check()?;
    Ok((cfg, rest))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(s: &[&str]) -> Vec<String> {
        s.iter().map(|x| x.to_string()).collect()
    }

    #[test]
    fn parses_console_options_and_keeps_the_rest() {
        let (cfg, rest) = config_from_args(&v(&[
            "--state",
            "/tmp/s",
            "--window",
            "--rows=16",
            "--cols",
            "48",
            "x.txt",
        ]))
        .unwrap();
        assert_eq!(cfg.state_dir, PathBuf::from("/tmp/s"));
        assert_eq!((cfg.rows, cfg.cols), (16, 48));
        assert_eq!(rest, v(&["--window", "x.txt"]));
        assert!(cfg.record.is_none());
    }

    #[test]
    fn refuses_bad_sizes_and_missing_values() {
        let e = config_from_args(&v(&["--state", "/t", "--rows", "3"])).unwrap_err();
        assert!(e.contains("--rows 3"), "{e}");
        let e = config_from_args(&v(&["--state", "/t", "--cols", "x"])).unwrap_err();
        assert!(e.contains("not a whole number"), "{e}");
        let e = config_from_args(&v(&["--state"])).unwrap_err();
        assert!(e.contains("needs a value"), "{e}");
    }
}
