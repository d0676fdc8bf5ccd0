//! Manual moves on the lathe console (docs/lathe.md "Moving a tool post by hand"): the
//! operation selector's CONTINUOUS, HANDLE and STEP positions move the selected channel's tool
//! post, X or Z, by every console's one rule (`crate::console::manual`), on the one kernel
//! (`Command::Jog`, `Command::Increment` to that channel's machine). Here is only what the
//! lathe's machine side gives that rule: which channel, where its tool post stands, when a
//! cycle refuses a move, and how an increment is run to rest in virtual time. X moves on its
//! radius.

use super::LatheConsole;
use crate::console::manual::ManualTarget;
use crate::panel_model::Axis;

/// The slices a CONTINUOUS tap's increment runs in, in virtual time, looked at between them.
const SETTLE_SLICE_NS: u64 = 10_000_000;

impl LatheConsole {
    /// The selected channel's tool post, if a manual move of its `axis` may begin now; if
    /// not, why (`Side::manual_target`).
    pub(super) fn manual_target(&mut self, axis: Axis, what: &str) -> Result<ManualTarget, String> {
        let ch = self.sel;
        if axis == Axis::Y {
            return Err(format!("{what} Y: the lathe's axes are X and Z"));
        }
        let c = &mut self.cycle;
        // The kernel's state now (in real time it runs on between the console's ticks).
        c.refresh();
        // With nothing loaded, a manual move in progress does not refuse the next: the machine
        // queues increments (a handwheel turned fast) and says why it refuses a jog, as the
        // centre's does. Before stop 43 every detent after the first was refused while the
        // tool post moved.
        if c.loaded() && !c.is_over() {
            return Err(if c.at_rest() {
                format!("{what} refused: a cycle is under way (RESET it first)")
            } else {
                format!("{what} refused: the machine is moving")
            });
        }
        // Checked from where the axes stand (the centre's rule after a run under MACHINE LOCK).
        let [x, z] = c.axes().get(ch).copied().unwrap_or_default();
        // The stores say the post moves before it can (the position memory, `posts.rs`).
        self.before_motion(&[ch])
            .map_err(|e| format!("{what} refused: {e}"))?;
        Ok(ManualTarget {
            ch,
            pos: [x, 0, z].into(),
            label: format!("CH{} ", ch + 1),
            x_radius: true,
        })
    }

    /// Virtual time: runs the kernel until channel `ch`'s manual move is at rest (the
    /// channel's run is over: the cycle's rest is not the axis's).
    pub(super) fn settle(&mut self, ch: usize) {
        let c = &mut self.cycle;
        let mut spent = 0;
        while spent < crate::console::manual::SETTLE_LIMIT_NS
            && c.channels()
                .get(ch)
                .is_some_and(|s| !s.status.idle || s.status.moving)
        {
            c.run(SETTLE_SLICE_NS, super::RunUntil::Time);
            spent += SETTLE_SLICE_NS;
        }
        self.now_ns = c.now_ns();
    }

    /// The STEP and handwheel increment, pulses.
    pub fn increment(&self) -> u32 {
        self.shell.front.wheel.1
    }
}
