//! Running the machine from the console: START of AUTO, MDI and SINGLE BLOCK runs through the
//! pulse core (after validating the whole program with the translator), the tape reader,
//! jog/STEP/HANDLE, waiting for idle, and the session recording.

use super::{search, Console};
use crate::panel_model::{Axis, OpMode, PanelEvent};
use crate::pulse_core::{Command, RunKind};
use crate::record::{Event, EventSink, Recorder};
use crate::settings::MachineSettings;
use crate::store::Target;
use crate::translator::translate_all;
use std::path::Path;
use std::time::Duration;

/// START in AUTO, SINGLE BLOCK (kind Auto) or MDI (kind Mdi).
pub(super) fn start_program(c: &mut Console, kind: RunKind) {
    let single = c.op == OpMode::Single;
    if let Some(loaded) = c.loaded {
        if loaded == kind {
            c.core.command(Command::SingleBlock(single));
            c.core.command(Command::Start(kind));
            c.message.clear();
            return;
        }
        c.message = format!(
            "START refused: {} run is held; press RESET first",
            kind_name(loaded)
        );
        return;
    }
    let (target, what) = match kind {
        RunKind::Auto => (Target::Program, "program memory"),
        RunKind::Mdi => (Target::Mdi, "the MDI buffer"),
    };
    let source = c.mem.text(target);
    let magazine = c.mem.magazine();
    let stmts = match translate_all(&source, &magazine, &c.cfg.settings, c.status.pos) {
        Ok(s) => s,
        Err(e) => {
            let msg = format!("line {}:{}: {}", e.line, e.col, e.message);
            c.message = format!("START refused, nothing moved: {msg}");
            c.alarm = Some(msg);
            return;
        }
    };
    let mut stmts = stmts;
    c.started_at = None;
    if kind == RunKind::Auto {
        if let Some(sp) = c.search.take() {
            match search::plan(&stmts, sp.line, c.status.pos, &c.cfg.settings) {
                Ok(p) => {
                    stmts = p.statements;
                    c.started_at = Some(sp.line);
                }
                Err(e) => {
                    c.message = format!("START refused: {e}");
                    return;
                }
            }
        }
    }
    if stmts.iter().all(|s| s.blocks.is_empty()) {
        c.message = format!("nothing to run: {what} generates no blocks");
        return;
    }
    c.alarm = None;
    c.core.set_magazine(magazine);
    c.core.command(Command::Override(c.feed_override));
    c.core.load(Box::new(stmts.into_iter().map(Ok)));
    c.core.command(Command::SingleBlock(single));
    c.core.command(Command::Start(kind));
    c.loaded = Some(kind);
    c.message = match c.started_at {
        Some(l) => format!("running from line {l} (SEARCH)"),
        None => String::new(),
    };
}

/// "AUTO" or "MDI".
fn kind_name(k: RunKind) -> &'static str {
    match k {
        RunKind::Auto => "an AUTO",
        RunKind::Mdi => "an MDI",
    }
}

/// Reads the tape in the reader: its text and its name.
fn read_tape(c: &mut Console) -> Option<(String, String)> {
    let Some(path) = c.tape.clone() else {
        c.message = "the tape reader is empty: put a tape in (tape PATH)".into();
        return None;
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    match std::fs::read_to_string(&path) {
        Ok(t) => Some((t, name)),
        Err(e) => {
            c.message = format!("tape {name} cannot be read: {e}");
            None
        }
    }
}

/// PROGRAM READ: the tape becomes a program in program memory (named after the file) and the
/// current one.
pub(super) fn read_program_tape(c: &mut Console) {
    let Some((text, file)) = read_tape(c) else {
        return;
    };
    let name = program_name(&file);
    match c.mem.program_read(&name, &text) {
        Ok(()) => {
            let n = text.lines().count();
            c.search = None;
            c.message = format!("read {file}: program {name}, {n} lines");
        }
        Err(e) => c.message = format!("PROGRAM READ refused: {e}"),
    }
}

/// A program name from a tape file name: its stem, upper case, letters/digits only.
pub fn program_name(file: &str) -> String {
    let stem = Path::new(file)
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let n: String = stem
        .chars()
        .filter(|ch| ch.is_ascii_alphanumeric() || *ch == '_')
        .map(|ch| ch.to_ascii_uppercase())
        .take(16)
        .collect();
    if n.is_empty() {
        "TAPE".into()
    } else {
        n
    }
}

/// TOOL DATA READ: only the tape records of tools assigned to T codes are stored.
pub(super) fn read_tool_tape(c: &mut Console) {
    let Some((text, file)) = read_tape(c) else {
        return;
    };
    match c.mem.tool_read(&text, &file) {
        Ok(r) => {
            c.message = format!(
                "read {file}: {} T codes loaded, {} skipped",
                r.loaded.len(),
                r.skipped
            );
            let mut lines = Vec::new();
            if !r.missing.is_empty() {
                let m: Vec<String> = r.missing.iter().map(|t| format!("{t:05}")).collect();
                lines.push(format!("not on tape: {}", m.join(" ")));
            }
            c.read_report = lines;
            c.tool_focus = r.loaded.first().copied().unwrap_or(1);
        }
        Err(e) => c.message = format!("TOOL DATA READ refused, tool file unchanged: {e}"),
    }
}

/// Whether `pos` moved by `pulses` on `axis` stays inside the travel limits; if not, the
/// operator's message.
fn travel_check(s: &MachineSettings, pos: [i64; 3], axis: Axis, pulses: i64) -> Result<(), String> {
    let a = axis.index();
    let (lo, hi) = s.travel_pulses(a);
    let to = pos[a].saturating_add(pulses);
    if to < lo || to > hi {
        return Err(format!(
            "refused: {} would go to {:.3} mm, outside travel {:.3}..{:.3}",
            axis.letter(),
            s.to_mm(to),
            s.to_mm(lo),
            s.to_mm(hi)
        ));
    }
    Ok(())
}

/// Whether a manual move may start now; if not, the message says why.
fn manual_allowed(c: &mut Console, what: &str) -> bool {
    if c.status.estop {
        c.message = format!("{what} refused: EMERGENCY STOP in force, press RESET");
        return false;
    }
    if c.status.run != 0 {
        c.message = format!("{what} refused: a program is running");
        return false;
    }
    true
}

/// The handwheel: `n` detents on `axis` at the selected scale, in HANDLE only.
pub(super) fn wheel(c: &mut Console, axis: Axis, n: i32) {
    c.wheel.0 = axis;
    if c.op != OpMode::Handle {
        c.message = format!(
            "handwheel refused: turn the operation selector to HANDLE (now {})",
            super::display::op_name(c.op)
        );
        return;
    }
    if !manual_allowed(c, "handwheel") {
        return;
    }
    let pulses = n as i64 * c.wheel.1 as i64;
    if let Err(e) = travel_check(&c.cfg.settings, c.status.pos, axis, pulses) {
        c.message = e;
        return;
    }
    if pulses != 0 {
        c.core.command(Command::Increment {
            axis: axis.index(),
            pulses,
        });
    }
    c.message.clear();
}

/// A jog button: CONTINUOUS jogs while held, STEP moves one increment.
pub(super) fn jog(c: &mut Console, axis: Axis, dir: i8) {
    let dir: i8 = if dir < 0 { -1 } else { 1 };
    match c.op {
        OpMode::Continuous => {
            if !manual_allowed(c, "jog") {
                return;
            }
            let edge = if dir < 0 { 0 } else { 1 };
            let (lo, hi) = c.cfg.settings.travel_pulses(axis.index());
            let at = c.status.pos[axis.index()];
            if (edge == 0 && at <= lo) || (edge == 1 && at >= hi) {
                c.message = format!("jog refused: {} is at its travel limit", axis.letter());
                return;
            }
            c.core.command(Command::Jog {
                axis: axis.index(),
                dir,
            });
            c.jogging = true;
            c.message.clear();
        }
        OpMode::Step => {
            if !manual_allowed(c, "step") {
                return;
            }
            let pulses = dir as i64 * c.cfg.settings.to_pulses(c.cfg.settings.step_mm);
            if let Err(e) = travel_check(&c.cfg.settings, c.status.pos, axis, pulses) {
                c.message = e;
                return;
            }
            c.core.command(Command::Increment {
                axis: axis.index(),
                pulses,
            });
            c.message.clear();
        }
        OpMode::Handle => {
            c.message = "HANDLE: turn the handwheel (jog keys work in CONTINUOUS and STEP)".into()
        }
        _ => {
            c.message = format!(
                "jog refused in {}: use CONTINUOUS or STEP",
                super::display::op_name(c.op)
            )
        }
    }
}

/// Waits until RUN = 0, no axis moves, and every command sent has been applied (at most an
/// hour of wall-clock time).
pub(super) fn wait_idle(c: &mut Console) {
    match c.core.wait_idle(Duration::from_secs(3600)) {
        Some(st) => c.status = st,
        None => c.message = "wait: the machine did not come to rest within an hour".into(),
    }
}

/// The recording of a session (docs/recording.md): panel events and display frames go to the recorder;
/// the pulse core gets the same sink for blocks, positions, pulses and `/nc/state` (the
/// console tells it the selector positions).
pub(super) struct Recording {
    recorder: Option<Recorder>,
    sink: Option<EventSink>,
}

impl Recording {
    /// Starts recording to `path`, if given.
    pub fn start(path: Option<&Path>, settings: &MachineSettings) -> Result<Recording, String> {
        let recorder = match path {
            Some(p) => Some(Recorder::start(p, settings)?),
            None => None,
        };
        Ok(Recording {
            sink: recorder.as_ref().map(|r| r.sink()),
            recorder,
        })
    }

    /// The sink for the pulse core.
    pub fn sink(&self) -> Option<EventSink> {
        self.sink.clone()
    }

    /// Records an operator action as its script line.
    pub fn panel_event(&mut self, ev: &PanelEvent, t_ns: u64) {
        if let Some(s) = &self.sink {
            s.send(Event::PanelEvent {
                t_ns,
                event: super::display::script_line(ev),
            });
        }
    }

    /// Records a new display frame.
    pub fn display(&mut self, lines: &[String], t_ns: u64) {
        if let Some(s) = &self.sink {
            s.send(Event::Display {
                t_ns,
                lines: lines.iter().map(|l| l.trim_end().to_string()).collect(),
            });
        }
    }

    /// Closes the recording; its summary.
    pub fn finish(self) -> Result<Option<String>, String> {
        drop(self.sink);
        match self.recorder {
            Some(r) => r.finish().map(|s| Some(s.to_string())),
            None => Ok(None),
        }
    }
}
