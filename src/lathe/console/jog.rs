//! Manual moves on the lathe console (docs/lathe.md "Moving a tool post by hand"): the
//! operation selector's CONTINUOUS, HANDLE and STEP positions move the selected channel's tool
//! post, X or Z, as the centre's do, on the one kernel (`Command::Jog`, `Command::Increment`
//! to that channel's machine) and with the centre's key rule (`crate::console::front::HeldJog`):
//! in CONTINUOUS a tapped key moves one increment and a held key jogs until it is let go; in
//! HANDLE a detent of the handwheel moves one increment; in STEP a key moves one increment.
//! The increment is the centre's (`x1 x10 x100 x1000` pulses, Alt+w or `wheelscale N`); X
//! moves on its radius.

use super::LatheConsole;
use crate::console::front::JogPress;
use crate::console::manual::{self, Move};
use crate::console::MsgLife;
use crate::panel_model::{Axis, OpMode, PanelEvent};
use crate::pulse_core::{ClockMode, Command};
use crate::settings::MachineSettings;
use std::time::Instant;

/// Machine time an increment gets to come to rest in virtual time (the centre's).
const STEP_LIMIT_NS: u64 = 60_000_000_000;

/// The slices it runs in, looked at between them.
const STEP_SLICE_NS: u64 = 10_000_000;

/// A manual move that may begin: the channel and its settings.
struct Ready {
    ch: usize,
    settings: MachineSettings,
}

impl LatheConsole {
    /// A jog event (`PanelEvent::Jog`, recorded as `jog X+`): in STEP one increment of the
    /// selected channel's X or Z; in CONTINUOUS the axis jogs until released (a held key:
    /// until it is let go) or its travel limit; refused, with the reason, in another mode, in
    /// E-STOP, with a cycle under way, or past the travel (every console's rule,
    /// `crate::console::manual`). Nothing else moves.
    pub(super) fn jog(&mut self, axis: Axis, dir: i8) {
        let what = if self.front.op == OpMode::Step {
            "STEP"
        } else {
            "jog"
        };
        match manual::jog(self.front.op, axis, dir, self.front.wheel.1) {
            Ok(mv) => self.manual_move(axis, mv, what),
            Err(e) => self.front.message = e,
        }
    }

    /// The handwheel (`PanelEvent::Wheel`, recorded as `wheel X 3`): `n` detents of the
    /// selected channel's X or Z, an increment each, in HANDLE only.
    pub(super) fn wheel(&mut self, axis: Axis, n: i32) {
        self.front.wheel.0 = axis;
        match manual::wheel(self.front.op, n, self.front.wheel.1) {
            Ok(0) => {}
            Ok(pulses) => self.manual_move(axis, Move::Increment(pulses), "HANDLE"),
            Err(e) => self.front.message = e,
        }
    }

    /// A jog key pressed in CONTINUOUS, as a terminal reports it (the centre's rule,
    /// `HeldJog`): a tap moves one increment, a held key jogs until it stops repeating.
    pub(super) fn hold_jog(&mut self, k: novanc_panel::Key, axis: Axis, dir: i8) {
        let virtual_time = self.cycle.clock() == ClockMode::Virtual;
        match self
            .front
            .jog_key
            .press(axis, dir, Instant::now(), virtual_time)
        {
            JogPress::KeepAlive => {
                if let Some(ch) = self.jogging {
                    let _ = self
                        .cycle
                        .manual(ch, Command::JogAlive(crate::console::deadman_ms()));
                }
            }
            JogPress::Begin => {
                // The tap's increment may still be moving: the jog begins on a later repeat.
                self.cycle.refresh();
                let moving = (self.cycle.channels().get(self.sel)).is_some_and(|s| s.status.moving);
                if !moving {
                    self.handle(PanelEvent::Jog(axis, dir));
                    self.front.jog_key.began(self.jogging.is_some());
                }
            }
            JogPress::Tap { release } => {
                if release {
                    self.release_jog();
                }
                self.record_event(&PanelEvent::Press(k));
                self.say("", MsgLife::NextKey);
                let pulses = i64::from(dir.signum()) * i64::from(self.front.wheel.1);
                self.manual_move(axis, Move::Increment(pulses), "CONTINUOUS");
                self.after();
            }
        }
    }

    /// Once a frame: a held CONTINUOUS key that stopped repeating lets its jog go; a jog a
    /// front end's button holds is kept alive (docs/panel.md "The jog deadman").
    pub(super) fn keep_jog(&mut self) {
        if self.front.jog_key.expired(Instant::now()) {
            self.record_event(&PanelEvent::JogRelease);
            self.release_jog();
        }
        if let (Some(ch), true) = (
            self.jogging,
            self.front.jog_key.is_none() && self.cycle.clock() == ClockMode::RealTime,
        ) {
            let c = &mut self.cycle;
            // A jog held by a front end's button (the window's): each frame keeps it alive,
            // so a front end that stops drawing lets the kernel stop it. A jog that has come
            // to rest (its travel limit, the deadman) is not told every frame after.
            if c.channels().get(ch).is_some_and(|s| s.status.moving) {
                let _ = c.manual(ch, Command::JogAlive(crate::console::deadman_ms()));
            }
        }
    }

    /// Lets a continuous jog go (`JogRelease`, a key let go): the axis decelerates to rest.
    pub(super) fn release_jog(&mut self) {
        self.release_jog_if(true);
    }

    /// A mode or channel turned lets a jog go, when one was begun or a key is held (the
    /// centre's rule: the kernel is not told when nothing jogs).
    pub(super) fn release_any_jog(&mut self) {
        self.release_jog_if(self.jogging.is_some() || !self.front.jog_key.is_none());
    }

    fn release_jog_if(&mut self, tell: bool) {
        if !tell {
            return;
        }
        self.front.jog_key.clear();
        // Always told (to the selected channel when none is known to jog): a jog the console
        // lost track of must still stop.
        let ch = self.jogging.take().unwrap_or(self.sel);
        let _ = self.cycle.manual(ch, Command::JogRelease);
    }

    /// Whether a manual move of the selected channel's `axis` may begin now; if not, the
    /// message says why.
    fn manual_ready(&mut self, axis: Axis, what: &str) -> Option<Ready> {
        let ch = self.sel;
        if axis == Axis::Y {
            self.front.message = format!("{what} Y: the lathe's axes are X and Z");
            return None;
        }
        if self.estop() {
            self.front.message = format!("{what} refused: EMERGENCY STOP in force, press RESET");
            return None;
        }
        let c = &mut self.cycle;
        // The kernel's state now (in real time it runs on between the console's ticks).
        c.refresh();
        // With nothing loaded, a manual move in progress does not refuse the next: the machine
        // queues increments (a handwheel turned fast) and says why it refuses a jog, as the
        // centre's does. Before stop 43 every detent after the first was refused while the
        // tool post moved.
        if c.loaded() && !c.is_over() {
            self.front.message = if c.at_rest() {
                format!("{what} refused: a cycle is under way (RESET it first)")
            } else {
                format!("{what} refused: the machine is moving")
            };
            return None;
        }
        let settings = MachineSettings::lathe_channel(&self.desc, ch)?;
        Some(Ready { ch, settings })
    }

    /// A manual move the selector allowed (`manual::jog`, `manual::wheel`, a CONTINUOUS
    /// tap) of the selected channel's `axis`, checked against the travel first: an increment
    /// at jog feed, run to rest in virtual time; or a CONTINUOUS jog until released or at the
    /// travel limit (a real-time jog also stops by itself when nothing keeps it alive).
    fn manual_move(&mut self, axis: Axis, mv: Move, what: &str) {
        let Some(r) = self.manual_ready(axis, what) else {
            return;
        };
        // Checked from where the axes stand (the centre's rule after a run under MACHINE LOCK).
        let [x, z] = self.cycle.axes().get(r.ch).copied().unwrap_or_default();
        if let Err(e) = manual::check(&r.settings, [x, 0, z].into(), axis, mv) {
            // X is a radius on the lathe (the display shows its diameter).
            self.front.message = match mv {
                Move::Increment(_) => {
                    format!("{what} {}", e.replacen("X would", "X (a radius) would", 1))
                }
                Move::Jog(_) => e,
            };
            return;
        }
        let c = &mut self.cycle;
        let a = axis.index();
        let sent = match mv {
            Move::Increment(pulses) => c.manual(r.ch, Command::Increment { axis: a, pulses }),
            Move::Jog(dir) => c.manual(r.ch, Command::Jog { axis: a, dir }),
        };
        if let Err(e) = sent {
            self.front.message = format!("{what} refused: {e}");
            return;
        }
        let sign = |n: i64| if n < 0 { '-' } else { '+' };
        match mv {
            Move::Jog(dir) => {
                self.jogging = Some(r.ch);
                if c.clock() == ClockMode::RealTime {
                    // Hold-to-run: the key's repeats keep the jog alive, or the kernel stops it.
                    let _ = c.manual(r.ch, Command::JogAlive(crate::console::deadman_ms()));
                }
                self.say(
                    format!(
                        "CONTINUOUS CH{} {}{}: jogging",
                        r.ch + 1,
                        axis.letter(),
                        sign(i64::from(dir))
                    ),
                    MsgLife::WhileRunning,
                );
            }
            Move::Increment(pulses) => {
                if c.clock() == ClockMode::Virtual {
                    // The increment runs to rest (the channel's run is over: the cycle's rest
                    // is not the axis's).
                    let mut spent = 0;
                    while spent < STEP_LIMIT_NS
                        && c.channels()
                            .get(r.ch)
                            .is_some_and(|s| !s.status.idle || s.status.moving)
                    {
                        c.run(STEP_SLICE_NS, super::RunUntil::Time);
                        spent += STEP_SLICE_NS;
                    }
                    self.now_ns = c.now_ns();
                }
                let scale = self.front.wheel.1;
                let detents = pulses.unsigned_abs() / u64::from(scale.max(1));
                self.say(
                    format!(
                        "{what} CH{} {}{} {}{}",
                        r.ch + 1,
                        axis.letter(),
                        sign(pulses),
                        if detents > 1 {
                            format!("{detents} × ")
                        } else {
                            String::new()
                        },
                        manual::increment_text(&r.settings, scale)
                    ),
                    MsgLife::NextKey,
                );
            }
        }
    }

    /// The STEP and handwheel increment, pulses.
    pub fn increment(&self) -> u32 {
        self.front.wheel.1
    }
}
