//! Manual moves on the lathe console (docs/lathe.md "Moving a tool post by hand"): the
//! operation selector's CONTINUOUS, HANDLE and STEP positions move the selected channel's tool
//! post, X or Z, as the centre's do, on the one kernel (`Command::Jog`, `Command::Increment`
//! to that channel's machine) and with the centre's key rule (`crate::console::keys::HeldJog`):
//! in CONTINUOUS a tapped key moves one increment and a held key jogs until it is let go; in
//! HANDLE a detent of the handwheel moves one increment; in STEP a key moves one increment.
//! The increment is the centre's (`x1 x10 x100 x1000` pulses, Alt+w or `wheelscale N`); X
//! moves on its radius.

use super::{glue, LatheConsole, MsgLife};
use crate::console::keys::JogPress;
use crate::panel_model::{Axis, OpMode, PanelEvent};
use crate::pulse_core::{ClockMode, Command};
use crate::settings::MachineSettings;
use std::time::Instant;

/// Machine time an increment gets to come to rest in virtual time (the centre's).
const STEP_LIMIT_NS: u64 = 60_000_000_000;

/// The slices it runs in, looked at between them.
const STEP_SLICE_NS: u64 = 10_000_000;

/// A manual move that may begin: the channel, the kernel's axis index and its settings.
struct Ready {
    ch: usize,
    axis: usize,
    settings: MachineSettings,
}

impl LatheConsole {
    /// A jog event (`PanelEvent::Jog`, recorded as `jog X+`): in STEP one increment of the
    /// selected channel's X or Z; in CONTINUOUS the axis jogs until released (a held key:
    /// until it is let go) or its travel limit; refused, with the reason, in another mode, in
    /// E-STOP, with a cycle under way, or past the travel. Nothing else moves.
    pub(super) fn jog(&mut self, axis: Axis, dir: i8) {
        match self.mode {
            OpMode::Step => {
                let pulses = i64::from(dir.signum()) * i64::from(self.increment);
                self.increment_move(axis, pulses, "STEP");
            }
            OpMode::Continuous => self.begin_jog(axis, dir),
            OpMode::Handle => {
                self.message =
                    "HANDLE: turn the handwheel (Alt+, Alt+.; the jog keys turn it on their axis)"
                        .into()
            }
            _ => {
                self.message = format!(
                    "jog {}: turn to CONTINUOUS (Alt+1), HANDLE (Alt+5) or STEP (Alt+6) to move a tool post by hand",
                    axis.letter()
                )
            }
        }
    }

    /// The handwheel (`PanelEvent::Wheel`, recorded as `wheel X 3`): `n` detents of the
    /// selected channel's X or Z, an increment each, in HANDLE only.
    pub(super) fn wheel(&mut self, axis: Axis, n: i32) {
        self.wheel_axis = axis;
        if self.mode != OpMode::Handle {
            self.message = format!(
                "handwheel refused: turn the operation selector to HANDLE (Alt+5; now {})",
                self.mode.word()
            );
            return;
        }
        let pulses = i64::from(n) * i64::from(self.increment);
        self.increment_move(axis, pulses, "HANDLE");
    }

    /// A jog key pressed in CONTINUOUS, as a terminal reports it (the centre's rule,
    /// `HeldJog`): a tap moves one increment, a held key jogs until it stops repeating.
    pub(super) fn hold_jog(&mut self, k: novanc_panel::Key, axis: Axis, dir: i8) {
        let virtual_time = self.clock == ClockMode::Virtual;
        match self.jog_key.press(axis, dir, Instant::now(), virtual_time) {
            JogPress::KeepAlive => {
                if let (Some(ch), Some(c)) = (self.jogging, self.cycle.as_mut()) {
                    let _ = c.manual(ch, Command::JogAlive(crate::console::deadman_ms()));
                }
            }
            JogPress::Begin => {
                // The tap's increment may still be moving: the jog begins on a later repeat.
                if let Some(c) = self.cycle.as_mut() {
                    c.refresh();
                }
                let moving = self
                    .cycle
                    .as_ref()
                    .is_some_and(|c| c.channels().get(self.sel).is_some_and(|s| s.status.moving));
                if !moving {
                    self.handle(PanelEvent::Jog(axis, dir));
                    self.jog_key.began(self.jogging.is_some());
                }
            }
            JogPress::Tap { release } => {
                if release {
                    self.release_jog();
                }
                self.record_event(&PanelEvent::Press(k));
                self.say("", MsgLife::NextAction);
                let pulses = i64::from(dir.signum()) * i64::from(self.increment);
                self.increment_move(axis, pulses, "CONTINUOUS");
                self.after();
            }
        }
    }

    /// Once a frame: a held CONTINUOUS key that stopped repeating lets its jog go; a jog a
    /// front end's button holds is kept alive (docs/panel.md "The jog deadman").
    pub(super) fn keep_jog(&mut self) {
        if self.jog_key.expired(Instant::now()) {
            self.record_event(&PanelEvent::JogRelease);
            self.release_jog();
        }
        if let (Some(ch), true, Some(c)) = (
            self.jogging,
            self.jog_key.is_none() && self.clock == ClockMode::RealTime,
            self.cycle.as_mut(),
        ) {
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
        self.release_jog_if(self.jogging.is_some() || !self.jog_key.is_none());
    }

    fn release_jog_if(&mut self, tell: bool) {
        if !tell {
            return;
        }
        self.jog_key.clear();
        // Always told (to the selected channel when none is known to jog): a jog the console
        // lost track of must still stop.
        let ch = self.jogging.take().unwrap_or(self.sel);
        if let Some(c) = self.cycle.as_mut() {
            let _ = c.manual(ch, Command::JogRelease);
        }
    }

    /// Whether a manual move of the selected channel's `axis` may begin now; if not, the
    /// message says why.
    fn manual_ready(&mut self, axis: Axis, what: &str) -> Option<Ready> {
        let ch = self.sel;
        let a = match axis {
            Axis::X => 0,
            Axis::Z => 2,
            Axis::Y => {
                self.message = format!("{what} Y: the lathe's axes are X and Z");
                return None;
            }
        };
        if self.estop() {
            self.message = format!("{what} refused: EMERGENCY STOP in force, press RESET");
            return None;
        }
        if let Some(c) = self.cycle.as_mut() {
            // The kernel's state now (in real time it runs on between the console's ticks).
            c.refresh();
            if !c.is_over() {
                self.message = if c.at_rest() {
                    format!("{what} refused: a cycle is under way (RESET it first)")
                } else {
                    format!("{what} refused: the machine is moving")
                };
                return None;
            }
        }
        let settings = MachineSettings::lathe_channel(&self.desc, ch)?;
        if self.cycle.is_none() {
            if let Err(e) = self.begin_manual() {
                self.message = e;
                return None;
            }
        }
        Some(Ready {
            ch,
            axis: a,
            settings,
        })
    }

    /// `pulses` on the selected channel's `axis` at jog feed (STEP, a tap in CONTINUOUS, the
    /// handwheel), checked against the travel first; in virtual time run to rest.
    fn increment_move(&mut self, axis: Axis, pulses: i64, what: &str) {
        let Some(r) = self.manual_ready(axis, what) else {
            return;
        };
        let [x, z] = self.pos[r.ch];
        if let Err(e) = crate::console::travel_check(&r.settings, [x, 0, z].into(), axis, pulses) {
            // X is a radius on the lathe (the display shows its diameter).
            self.message = format!("{what} {}", e.replacen("X would", "X (a radius) would", 1));
            return;
        }
        let Some(c) = self.cycle.as_mut() else {
            return;
        };
        if let Err(e) = c.manual(
            r.ch,
            Command::Increment {
                axis: r.axis,
                pulses,
            },
        ) {
            self.message = format!("{what} refused: {e}");
            return;
        }
        if self.clock == ClockMode::Virtual {
            // The increment runs to rest (the channel's run is over: the cycle's rest is not
            // the axis's).
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
        let scale = self.increment;
        let detents = pulses.unsigned_abs() / u64::from(scale.max(1));
        self.say(
            format!(
                "{what} CH{} {}{} {}{}",
                r.ch + 1,
                axis.letter(),
                if pulses < 0 { '-' } else { '+' },
                if detents > 1 {
                    format!("{detents} × ")
                } else {
                    String::new()
                },
                crate::console::increment_text(&r.settings, scale)
            ),
            MsgLife::NextAction,
        );
    }

    /// CONTINUOUS: the selected channel's `axis` jogs at jog feed until released or at its
    /// travel limit (a real-time jog also stops by itself when nothing keeps it alive).
    fn begin_jog(&mut self, axis: Axis, dir: i8) {
        let dir: i8 = if dir < 0 { -1 } else { 1 };
        let Some(r) = self.manual_ready(axis, "jog") else {
            return;
        };
        let (lo, hi) = r.settings.travel_pulses(r.axis);
        let at = self.pos[r.ch][if r.axis == 0 { 0 } else { 1 }];
        if (dir < 0 && at <= lo) || (dir > 0 && at >= hi) {
            self.message = format!("jog refused: {} is at its travel limit", axis.letter());
            return;
        }
        let Some(c) = self.cycle.as_mut() else {
            return;
        };
        if let Err(e) = c.manual(r.ch, Command::Jog { axis: r.axis, dir }) {
            self.message = format!("jog refused: {e}");
            return;
        }
        self.jogging = Some(r.ch);
        if self.clock == ClockMode::RealTime {
            // Hold-to-run: the key's repeats keep the jog alive, or the kernel stops it.
            let _ = c.manual(r.ch, Command::JogAlive(crate::console::deadman_ms()));
        }
        self.say(
            format!(
                "CONTINUOUS CH{} {}{}: jogging",
                r.ch + 1,
                axis.letter(),
                if dir < 0 { '-' } else { '+' },
            ),
            MsgLife::WhileRunning,
        );
    }

    /// `wheelscale N` or Alt+w: the STEP and handwheel increment, x1, x10, x100 or x1000
    /// pulses.
    pub(super) fn set_increment(&mut self, scale: u32) {
        if !crate::console::SCALES.contains(&scale) {
            self.message = format!("increment x{scale}: only x1, x10, x100, x1000");
            return;
        }
        self.increment = scale;
        if let Some(s) = MachineSettings::lathe_channel(&self.desc, self.sel) {
            self.message = format!(
                "increment {}: STEP, HANDLE and a CONTINUOUS tap",
                crate::console::increment_text(&s, scale)
            );
        }
    }

    /// The STEP and handwheel increment, pulses.
    pub fn increment(&self) -> u32 {
        self.increment
    }

    /// The next increment (Alt+w), after x1000 x1 again.
    pub(super) fn next_increment(&self) -> u32 {
        let s = crate::console::SCALES;
        let i = s.iter().position(|&k| k == self.increment).unwrap_or(0);
        s[(i + 1) % s.len()]
    }

    /// A kernel for manual moves when none is loaded: the selected channel's, with nothing to
    /// run, every tool post where it stands, the spindles and coolant as they are.
    fn begin_manual(&mut self) -> Result<(), String> {
        let n = self.desc.channels.len();
        let mut texts = vec![(String::new(), String::new()); n];
        texts[self.sel] = (format!("MANUAL CH{}", self.sel + 1), String::new());
        let spec = glue::CycleSpec {
            left: self.left.clone(),
            texts,
            opts: Default::default(),
            target: 1,
            mdi: Some(self.sel),
            pos: self.pos.clone(),
            started_ns: self.now_ns,
            feed_override: self.feed_override,
            clock: self.clock,
            sink: self.recorder.sink(),
            manual: true,
            single_block: false,
        };
        let mut kept = self.kept.clone();
        let mut c = glue::Cycle::new(&self.desc, spec, &mut kept)?;
        if self.watch.is_some() {
            c.set_watch(self.watch.clone());
        }
        self.cycle = Some(c);
        Ok(())
    }
}
