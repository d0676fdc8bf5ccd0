//! The operation selector turned: every console's one rule (docs/panel.md "Rules and
//! choices", docs/lathe.md "Keys"), the machining centre being a machine of one channel.
//!
//! - A turn leaves the page up, from a key as from a script's `op M`.
//! - A turn to the position the selector is at does nothing more: the line being typed stays
//!   (before stop 43 a lathe cleared it, and said the mode again).
//! - A turn to another position lets a CONTINUOUS jog go, and clears the entry line and the
//!   `Y` type-out: the line was typed for the mode left (kept, an editor command typed for the
//!   program would run on the tool file after a turn). A line so cleared is said, never lost in
//!   silence: `the line typed in MDI, 'G0X12', is cleared (Up recalls it in MDI)`, and an MDI
//!   line goes to the recall (stop 49; before, it went without a word).
//! - The machine's own rule for the turn comes next (`Side::turned`): the centre's DATA INPUT
//!   clears RUN (seed lines 441–443); AUTO and SINGLE BLOCK turn single block on either
//!   machine.
//! - A turn to any other position while a channel runs is a feed hold on every channel (a
//!   Fanuc stops automatic operation when its mode is turned), said once a channel holds (a
//!   thread pass or a tap holds at its end, and says so itself).

use super::side::Side;
use crate::panel_model::OpMode;
use crate::pulse_core::Command;

/// Whether `m` runs a program: AUTO or SINGLE BLOCK.
pub(crate) fn runs(m: OpMode) -> bool {
    matches!(m, OpMode::Auto | OpMode::Single)
}

/// Turns the operation selector to `m`.
pub(crate) fn turn<C: Side>(c: &mut C, m: OpMode) {
    c.leave_page();
    let was = c.front().op;
    if m == was {
        return;
    }
    super::manual::release(c, false);
    let f = c.front();
    f.op = m;
    f.y_output = None;
    let typed = std::mem::take(&mut f.entry);
    let mdi = was == OpMode::Mdi;
    if !(c.turned(was) || (runs(was) && runs(m)) || !c.channel_runs()) {
        c.command_all(Command::Stop);
        if c.channels().iter().any(|s| s.hold) {
            c.front().message = format!("feed hold: mode changed to {} while running", m.name());
        }
    }
    if !typed.trim().is_empty() {
        // What the machine says of the turn (a hold's notice) first, the cleared line after
        // it: said after, it is not replaced.
        c.refresh();
    }
    cleared(c, typed, was.name(), mdi);
}

/// A selector's turn has cleared the line `typed` in `mode`: said after what the turn says, and,
/// typed in MDI (`mdi`), kept for recall.
pub(crate) fn cleared<C: Side>(c: &mut C, typed: String, mode: &str, mdi: bool) {
    if typed.trim().is_empty() {
        return;
    }
    if mdi {
        c.recall().remember(&typed);
    }
    let shown: String = match typed.chars().count() {
        n if n > 24 => typed.chars().take(23).chain(['…']).collect(),
        _ => typed,
    };
    let recall = if mdi { " (Up recalls it in MDI)" } else { "" };
    let now = c.now_ns();
    let said = format!("the line typed in {mode}, '{shown}', is cleared{recall}");
    c.front().say_failure(&said, now);
}
