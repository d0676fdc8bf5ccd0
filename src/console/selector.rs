//! The operation selector turned: every console's one rule (docs/panel.md "Rules and
//! choices", docs/lathe.md "Keys"), the machining centre being a machine of one channel.
//!
//! - A turn leaves the page up, from a key as from a script's `op M`.
//! - A turn to the position the selector is at does nothing more: the line being typed stays
//!   (before stop 43 a lathe cleared it, and said the mode again).
//! - A turn to another position lets a CONTINUOUS jog go, and clears the entry line and the
//!   `Y` type-out: the line was typed for the mode left.
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
    f.entry.clear();
    f.y_output = None;
    if c.turned(was) || (runs(was) && runs(m)) || !c.channel_runs() {
        return;
    }
    c.command_all(Command::Stop);
    if c.channels().iter().any(|s| s.hold) {
        c.front().message = format!("feed hold: mode changed to {} while running", m.name());
    }
}
