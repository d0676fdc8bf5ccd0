//! ISO G-code at the console (docs/gcode.md "At the console"): which language a text is in,
//! and the interpreter's state a run reads and the console keeps (docs/gcode.md "The
//! interpreter's state").
//!
//! - A program in program memory is G-code by its name (`.NGC`, `.NC`, `.ISO`, which PROGRAM
//!   READ keeps for such files) or its first line (`%`, `O` and a number):
//!   `gcode::is_gcode`.
//! - MDI text is G-code by the rule of [`mdi_is_gcode`].
//! - A G-code run starts from the console's interpreter state and hands back what it reads
//!   (ahead of the machine, as LinuxCNC's interpreter does): its persistent parameters, tool
//!   data and messages as it goes, its state when it ends. They are taken as soon as the run
//!   has started a block, or at its end; a run refused before anything moved changes nothing
//!   (its messages are still shown).

use super::Console;
use crate::block::{Statement, TranslateError};
use crate::gcode::state::{is_persistent, CompSide, InterpState};
use crate::gcode::{Event, GcodeSource};
use std::sync::{Arc, Mutex};

/// What a G-code run's source has read and the console has not yet taken: the events of its
/// lines (persistent parameters, tool data, messages) and, once the source has ended or been
/// dropped, the interpreter's state as it read it.
#[derive(Debug, Default)]
pub struct Fed {
    /// The lines' events, in order.
    pub events: Vec<Event>,
    /// The interpreter's state at the end of reading (the run's end, its error, or RESET).
    pub state: Option<InterpState>,
}

/// Where a run's source hands back what it read (shared with the translator thread).
pub type RunFeed = Arc<Mutex<Fed>>;

/// Whether MDI text is G-code: its first line that is not blank or a `;` comment starts with
/// `%`, `#`, `/`, `(`, or one letter followed by a number (`G0`, `N10`, `X-5`, `F[..]`,
/// `T#1`), and has no `,` and no `=` outside parentheses. Source statements never start so:
/// their keywords have two letters (`GO, 500, 300, -200`, `DRL, 106/...`, `CL`), and the
/// one-letter definitions (`P1 = ...`, `L1 = ...`, `C1 = ...`) hold `=`.
pub fn mdi_is_gcode(text: &str) -> bool {
    let Some(line) = text
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty() && !l.starts_with(';'))
    else {
        return false;
    };
    if line.starts_with(['%', '#', '/', '(']) {
        return true;
    }
    let mut chars = line.chars().filter(|c| !c.is_whitespace());
    let first = chars.next().is_some_and(|c| c.is_ascii_alphabetic());
    let second = chars
        .next()
        .is_some_and(|c| c.is_ascii_digit() || matches!(c, '.' | '+' | '-' | '[' | '#'));
    if !(first && second) {
        return false;
    }
    let mut depth = 0i32;
    for c in line.chars() {
        match c {
            '(' => depth += 1,
            ')' => depth -= 1,
            ',' | '=' if depth <= 0 => return false,
            ';' if depth <= 0 => break,
            _ => {}
        }
    }
    true
}

/// A G-code source that hands each statement's events to `feed` as it yields it, and its
/// state once it ends (its last statement, an error, or being dropped by RESET).
pub struct Feeding {
    /// The source.
    pub src: GcodeSource,
    /// Where the events and the state go.
    pub feed: RunFeed,
    /// The state has been handed back.
    pub handed: bool,
}

impl Feeding {
    fn hand(&mut self, state: bool) {
        let events = self.src.take_events();
        if events.is_empty() && !state {
            return;
        }
        if let Ok(mut f) = self.feed.lock() {
            f.events.extend(events);
            if state && !self.handed {
                f.state = Some(self.src.state().clone());
                self.handed = true;
            }
        }
    }
}

impl Iterator for Feeding {
    type Item = Result<Statement, TranslateError>;

    fn next(&mut self) -> Option<Self::Item> {
        let r = self.src.next();
        self.hand(!matches!(r, Some(Ok(_))));
        r
    }
}

impl Drop for Feeding {
    fn drop(&mut self) {
        self.hand(true);
    }
}

/// Whether the run loaded is G-code: only a G-code run has a feed, from its START to its end.
pub(super) fn gcode_run_loaded(c: &Console) -> bool {
    c.status.job.is_some() && c.run_feed.is_some()
}

/// Takes what the G-code run has read into the console: while it is loaded, once it has
/// started a block; after its end, whatever its source still hands back (after RESET the
/// translator thread drops the source a moment later).
pub(super) fn keep_read(c: &mut Console) {
    if c.run_feed.is_none() {
        return;
    }
    if c.status.job.is_some() {
        if c.status.blocks_done > 0 || c.status.in_block {
            c.feed_keep = true;
            take(c);
        }
    } else {
        // The run's end has been noted (`end_run`) before this is called.
        take(c);
    }
}

/// At a G-code run's end: what it read is taken, unless nothing moved (the run was refused:
/// its messages are still shown, nothing else changes).
pub(super) fn end_run(c: &mut Console, nothing_moved: bool) {
    if c.run_feed.is_none() {
        return;
    }
    c.feed_keep = !nothing_moved;
    take(c);
}

/// Before a new run: the last run's feed is taken one last time and let go.
pub(super) fn before_run(c: &mut Console) {
    take(c);
    c.run_feed = None;
    c.feed_back = false;
    c.reset_seen = false;
}

/// Takes the feed's events and state into the console: the messages shown and kept in the
/// history; when the run is to be kept, the persistent parameters and tool data journaled
/// and the state made the console's. The feed is let go once its state has come back and
/// the run has ended.
fn take(c: &mut Console) {
    let Some(feed) = c.run_feed.clone() else {
        return;
    };
    let (events, state) = match feed.lock() {
        Ok(mut f) => (std::mem::take(&mut f.events), f.state.take()),
        Err(_) => (Vec::new(), None),
    };
    let keep = c.feed_keep;
    let mut params: Vec<(usize, f64)> = Vec::new();
    for e in events {
        match e {
            Event::Param(n, v) if keep => params.push((n, v)),
            Event::Tool {
                t,
                length,
                diameter,
            } if keep => {
                if let Err(e) = c.mem.set_tool_size(t, length, diameter) {
                    super::book::program_message(c, "NOT KEPT", &format!("G10 T{t:02}: {e}"));
                }
            }
            Event::ToolOffsets {
                t,
                length,
                diameter,
                wear_length,
                wear_diameter,
            } if keep => {
                let v = [length, diameter, wear_length, wear_diameter];
                if let Err(e) = c.mem.set_tool_offsets(t, v) {
                    super::book::program_message(
                        c,
                        "NOT KEPT",
                        &format!("tool offset T{t:02}: {e}"),
                    );
                }
            }
            Event::Message { kind, text } => super::book::program_message(c, kind, &text),
            _ => {}
        }
    }
    journal_params(c, &params);
    if let Some(mut st) = state {
        if keep {
            if c.reset_seen {
                reset_state(&mut st, &c.cfg.settings);
            }
            // What no event said (the system selected, #5220) is kept with the rest.
            keep_persistent(c, &st);
            c.interp = st;
        }
        if c.status.job.is_none() {
            c.run_feed = None;
        } else {
            // Still loaded (the source reads ahead of the machine): the feed says it is G-code.
            c.feed_back = true;
        }
    } else if c.feed_back && c.status.job.is_none() {
        c.run_feed = None;
    }
}

/// The persistent parameters as the stores hold them (a parameter not kept is 0, #5220 1).
fn stored(c: &Console) -> impl Fn(usize) -> f64 {
    let kept: std::collections::HashMap<usize, f64> = c.mem.params().into_iter().collect();
    move |n| {
        kept.get(&n)
            .copied()
            .unwrap_or(if n == 5220 { 1.0 } else { 0.0 })
    }
}

/// Journals persistent parameters, together if the stores take them all; else one by one, a
/// value the stores refuse (beyond their limit) said on the display and left out.
fn journal_params(c: &mut Console, ps: &[(usize, f64)]) {
    if ps.is_empty() || c.mem.set_params(ps).is_ok() {
        return;
    }
    for &p in ps {
        if let Err(e) = c.mem.set_params(&[p]) {
            super::book::program_message(c, "NOT KEPT", &format!("#{}: {e}", p.0));
        }
    }
}

/// At a run's end in the Fanuc dialect: the hour clock #3002 as it reads now (the lamp lit
/// `lamp_ns` since the console started, plus what the stores kept and programs wrote),
/// journaled when it moved, so that it counts on after a restart as Fanuc's does through
/// power-off (docs/gcode.md "Fanuc dialect").
pub(super) fn keep_hour_clock(c: &mut Console, lamp_ns: u64) {
    if c.cfg.settings.dialect != crate::settings::Dialect::Fanuc {
        return;
    }
    let n = crate::gcode::state::HOUR_CLOCK;
    let hours = crate::gcode::sysvars::hour_clock(lamp_ns, &c.interp);
    if (hours - stored(c)(n)).abs() > 0.5e-6 {
        journal_params(c, &[(n, hours)]);
    }
}

/// The persistent parameters of `st` that the stores do not hold yet, journaled as one record.
fn keep_persistent(c: &mut Console, st: &InterpState) {
    let was = stored(c);
    let changed: Vec<(usize, f64)> = (5161..=5390)
        .filter(|&n| is_persistent(n) && (st.params[n] - was(n)).abs() > 0.5e-6)
        .map(|n| (n, st.params[n]))
        .collect();
    journal_params(c, &changed);
}

/// Before a G-code source is made from the console's state: what an ended run still hands
/// back is taken, and the persistent parameters as the stores hold them come into the state.
/// So a work offset set on the OFS page since takes effect, at once for the system in force
/// (as G10 L2 does). A value the state already holds (to the stores' millionth) is left as it
/// is, so a program's `#5221=` still waits for G54 to be selected again, as in LinuxCNC.
pub(super) fn before_read(c: &mut Console) {
    if c.run_feed.is_some() && c.status.job.is_none() {
        take(c);
    }
    let kept = stored(c);
    let st = &mut c.interp;
    let base = crate::gcode::state::system_base(st.modal.cs);
    let mut active = false;
    for n in (5161..=5390).filter(|&n| is_persistent(n) && n != 5220) {
        let v = kept(n);
        if (st.params[n] - v).abs() > 0.5e-6 {
            st.params[n] = v;
            active |= (base + 1..=base + 10).contains(&n);
        }
    }
    if active {
        st.select_system(st.modal.cs);
    }
}

/// RESET of the interpreter's state (docs/gcode.md "The interpreter's state"): the Fanuc
/// dialect's #100–#199 vacant unless the machine keeps them, cutter
/// compensation off, the call stack and the M70 saved states dropped, coolant off (RESET
/// turns the machine's off: LinuxCNC's M9 state after a reset), the other modal groups as
/// read; the position and the tool are the machine's at the next START.
pub(super) fn reset_state(st: &mut InterpState, settings: &crate::settings::MachineSettings) {
    // Fanuc's common variables #100–#199 are cleared (vacant) by RESET, unless the machine
    // keeps them (parameter 6001#6 CCV = 1: `common keep`).
    if !settings.fanuc.keep_common {
        st.fanuc_reset();
    }
    st.modal.mist = false;
    st.modal.flood = false;
    st.modal.comp = CompSide::Off;
    st.comp_radius = 0.0;
    st.comp_tool = None;
    st.call_level = 0;
    st.saved.clear();
    st.nurbs = None;
    // Fanuc's rigid tapping mode (M29) and coordinate rotation (G68) end at RESET.
    st.cycle.rigid = false;
    st.g68 = None;
}

/// The note while a run stands at a program stop: the last block carried M00 or M01, RUN is 0
/// and the run is loaded.
pub(super) fn program_stop_note(c: &Console) -> Option<String> {
    let s = &c.status;
    let m = s.executed.as_ref()?.m?;
    let stopped = s.job.is_some() && s.run == 0 && !s.hold && !s.in_block && !s.moving;
    if !stopped || !matches!(m, 0 | 1) {
        return None;
    }
    let what = if m == 0 {
        "program stop"
    } else {
        "optional stop"
    };
    Some(format!("M{m:02} {what}: START continues"))
}

/// What the display says when a switch is turned: it applies from the next new run.
pub(crate) fn switch_message(name: &str, on: bool) -> String {
    let state = if on { "on" } else { "off" };
    format!("{name} {state}: G-code programs, from the next START of a new run")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mdi_language_by_its_first_line() {
        for g in [
            "G0 X10",
            "g1 x5 f100",
            "G10 L2 P1 X100 Y50",
            "N10 G0 X1",
            "T1 M6",
            "#1=5",
            "/G0 X1",
            "(comment)\nG0 X1",
            "%",
            "X-5",
            "G0 X10 (fast, safe)",
            "; note\nM3 S1000",
        ] {
            assert!(mdi_is_gcode(g), "{g}");
        }
        for s in [
            "GO, 500, 300, -200",
            "GO,500,300,-200",
            "DRL, 106/DP20/PAT1",
            "CL",
            "P1 = (150, 130)",
            "L1 = P1, A30",
            "C1 = P1, 20",
            "DA1 = (200, 0, -450)",
            "",
            "; only a comment",
            "MIL, 103/DP5/RGT/P1/P2",
        ] {
            assert!(!mdi_is_gcode(s), "{s}");
        }
    }
}
