//! STEP on the lathe console (docs/lathe.md "STEP: moving a tool post by hand"): the jog keys
//! move the selected channel's tool post one increment, X or Z, as the centre's STEP does, on
//! the one kernel (`Command::Increment` to that channel's machine). The increment is the
//! centre's (`x1 x10 x100 x1000` pulses, Alt+w or `wheelscale N`); X moves on its radius.

use super::events::Mode;
use super::{glue, LatheConsole, MsgLife};
use crate::panel_model::Axis;
use crate::pulse_core::{ClockMode, Command};
use crate::settings::MachineSettings;

/// Machine time an increment gets to come to rest in virtual time (the centre's).
const STEP_LIMIT_NS: u64 = 60_000_000_000;

/// The slices it runs in, looked at between them.
const STEP_SLICE_NS: u64 = 10_000_000;

impl LatheConsole {
    /// A jog key (`PanelEvent::Jog`, recorded as `jog X+`): in STEP, one increment of the
    /// selected channel's X or Z; refused, with the reason, in another mode, in E-STOP, with a
    /// cycle under way, or past the travel. Nothing else moves.
    pub(super) fn jog(&mut self, axis: Axis, dir: i8) {
        if self.mode != Mode::Step {
            self.message = format!(
                "jog {}: turn to STEP (Alt+6) to move a tool post by hand",
                axis.letter()
            );
            return;
        }
        let ch = self.sel;
        let a = match axis {
            Axis::X => 0,
            Axis::Z => 2,
            Axis::Y => {
                self.message = "jog Y: the lathe's axes are X and Z".into();
                return;
            }
        };
        if self.estop() {
            self.message = "jog refused: EMERGENCY STOP in force, press RESET".into();
            return;
        }
        if let Some(c) = &self.cycle {
            if !c.is_over() {
                self.message = if c.at_rest() {
                    "jog refused: a cycle is under way (RESET it first)".into()
                } else {
                    "jog refused: the machine is moving".into()
                };
                return;
            }
        }
        let Some(settings) = MachineSettings::lathe_channel(&self.desc, ch) else {
            return;
        };
        let pulses = i64::from(dir.signum()) * i64::from(self.increment);
        let [x, z] = self.pos[ch];
        if let Err(e) = crate::console::travel_check(&settings, [x, 0, z].into(), axis, pulses) {
            // X is a radius on the lathe (the display shows its diameter).
            self.message = format!("jog {}", e.replacen("X would", "X (a radius) would", 1));
            return;
        }
        if self.cycle.is_none() {
            if let Err(e) = self.begin_manual() {
                self.message = e;
                return;
            }
        }
        let Some(c) = self.cycle.as_mut() else {
            return;
        };
        if let Err(e) = c.manual(ch, Command::Increment { axis: a, pulses }) {
            self.message = format!("jog refused: {e}");
            return;
        }
        if self.clock == ClockMode::Virtual {
            // The increment runs to rest (the channel's run is over: the cycle's rest is not
            // the axis's).
            let mut spent = 0;
            while spent < STEP_LIMIT_NS
                && c.channels()
                    .get(ch)
                    .is_some_and(|s| !s.status.idle || s.status.moving)
            {
                c.run(STEP_SLICE_NS, super::RunUntil::Time);
                spent += STEP_SLICE_NS;
            }
            self.now_ns = c.now_ns();
        }
        self.say(
            format!(
                "STEP CH{} {}{} {}",
                ch + 1,
                axis.letter(),
                if dir < 0 { '-' } else { '+' },
                crate::console::increment_text(&settings, self.increment)
            ),
            MsgLife::NextAction,
        );
    }

    /// `wheelscale N` or Alt+w: the STEP increment, x1, x10, x100 or x1000 pulses.
    pub(super) fn set_increment(&mut self, scale: u32) {
        if !crate::console::SCALES.contains(&scale) {
            self.message = format!("increment x{scale}: only x1, x10, x100, x1000");
            return;
        }
        self.increment = scale;
        if let Some(s) = MachineSettings::lathe_channel(&self.desc, self.sel) {
            self.message = format!(
                "increment {}: STEP",
                crate::console::increment_text(&s, scale)
            );
        }
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
        texts[self.sel] = (format!("STEP CH{}", self.sel + 1), String::new());
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
