//! ISO G-code at the console (docs/gcode.md "At the console"): which language a text is in,
//! and the G10 work-offset changes a run makes, kept in the stores once the run has moved.
//!
//! - A program in program memory is G-code by its name (`.NGC`, `.NC`, `.ISO`, which PROGRAM
//!   READ keeps for such files) or its first line (`%`, `O` and a number):
//!   `gcode::is_gcode`.
//! - MDI text is G-code by the rule of [`mdi_is_gcode`].
//! - A G-code run's G10 changes are collected as its source reads them (ahead of the
//!   machine, as LinuxCNC's interpreter does). They go to the stores as soon as the run has
//!   started a block, or at its end; a run refused before anything moved changes nothing.

use super::Console;
use crate::block::{Statement, TranslateError};
use crate::gcode::{GcodeSource, OffsetChange};
use std::sync::{Arc, Mutex};

/// The G10 changes a run's source has read and the console has not yet kept.
pub type OffsetFeed = Arc<Mutex<Vec<OffsetChange>>>;

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

/// A G-code source that hands each statement's G10 changes to `feed` as it yields it.
pub struct Feeding {
    /// The source.
    pub src: GcodeSource,
    /// Where the changes go.
    pub feed: OffsetFeed,
}

impl Iterator for Feeding {
    type Item = Result<Statement, TranslateError>;

    fn next(&mut self) -> Option<Self::Item> {
        let r = self.src.next();
        let changes = self.src.take_offset_changes();
        if !changes.is_empty() {
            if let Ok(mut f) = self.feed.lock() {
                f.extend(changes);
            }
        }
        r
    }
}

/// Whether the run loaded is G-code: only a G-code run has a feed for its G10 changes, from
/// its START to its end.
pub(super) fn gcode_run_loaded(c: &Console) -> bool {
    c.status.job.is_some() && c.offset_feed.is_some()
}

/// Keeps the loaded run's G10 changes in the stores once it has started a block; a failure to
/// save is said on the display.
pub(super) fn keep_offsets(c: &mut Console) {
    let Some(feed) = &c.offset_feed else { return };
    let moved = c.status.blocks_done > 0 || c.status.in_block;
    if c.status.job.is_none() || !moved {
        return;
    }
    let changes: Vec<OffsetChange> = match feed.lock() {
        Ok(mut f) => std::mem::take(&mut *f),
        Err(_) => return,
    };
    commit(c, &changes);
}

/// At a run's end: its G10 changes are kept, unless nothing moved (the run was refused).
pub(super) fn end_offsets(c: &mut Console, nothing_moved: bool) {
    let Some(feed) = c.offset_feed.take() else {
        return;
    };
    let changes: Vec<OffsetChange> = match feed.lock() {
        Ok(mut f) => std::mem::take(&mut *f),
        Err(_) => return,
    };
    if !nothing_moved {
        commit(c, &changes);
    }
}

fn commit(c: &mut Console, changes: &[OffsetChange]) {
    for ch in changes {
        if let Err(e) = c.mem.set_work_offset(ch.system, ch.offset) {
            c.message = format!("G10: G{} not saved: {e}", 54 + ch.system);
        }
    }
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
pub(super) fn switch_message(name: &str, on: bool) -> String {
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
