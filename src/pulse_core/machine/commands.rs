//! Operator commands: START, STOP (feed hold), RESET, E-STOP, override, SINGLE BLOCK, jog.

use super::{axis_name, Machine};
use crate::pulse_core::{Command, RunKind};

impl Machine {
    /// Applies an operator command at the current machine time.
    pub fn command(&mut self, c: Command) {
        self.commands += 1;
        match c {
            Command::Start(kind) => self.start(kind),
            Command::Stop => {
                if self.run != 0 && !self.hold {
                    self.hold = true;
                    if let Some(m) = self.current.as_mut().and_then(|c| c.motion.as_mut()) {
                        m.set_hold(true);
                    }
                }
                if let Some(j) = &mut self.jog {
                    j.motion.set_hold(true);
                    j.release = true;
                }
                self.increments.clear();
            }
            Command::Reset => {
                self.out.flush();
                self.current = None;
                self.jog = None;
                self.increments.clear();
                self.run = 0;
                self.hold = false;
                self.estop = false;
                self.alarm = None;
                self.notice = None;
                self.just_completed = false;
                self.spindle = 0;
                self.send_position();
            }
            Command::EStop => {
                self.out.flush();
                self.current = None;
                self.jog = None;
                self.increments.clear();
                self.run = 0;
                self.hold = false;
                self.estop = true;
                self.spindle = 0;
                self.alarm = Some("EMERGENCY STOP: press RESET".into());
                self.send_position();
            }
            Command::Override(p) => self.pending_override = Some(p.min(150)),
            Command::SingleBlock(b) => self.single_block = b,
            Command::Jog { axis, dir } => {
                if self.jog.is_some() || !self.increments.is_empty() {
                    self.notice = Some("jog in progress".into());
                } else if let Some(lim) = self.jog_check(axis) {
                    let (lo, hi) = lim;
                    let target = if dir > 0 { hi } else { lo };
                    let d = target - self.out.pos[axis];
                    if dir == 0 || d == 0 || d.signum() != i64::from(dir.signum()) {
                        self.notice = Some(format!("{}: at the travel limit", axis_name(axis)));
                    } else {
                        self.start_jog(axis, d, true);
                    }
                }
            }
            Command::JogRelease => {
                if let Some(j) = &mut self.jog {
                    if j.release {
                        j.motion.set_hold(true);
                    }
                }
            }
            Command::Increment { axis, pulses } => {
                if self.jog_check(axis).is_some() && pulses != 0 {
                    self.increments.push_back((axis, pulses));
                    self.next_increment();
                }
            }
        }
        self.send_state();
    }

    fn start(&mut self, kind: RunKind) {
        if self.estop || self.alarm.is_some() {
            self.notice = Some("press RESET first".into());
            return;
        }
        if self.jog.is_some() {
            self.notice = Some("jog in progress".into());
            return;
        }
        let flag = match kind {
            RunKind::Auto => 1,
            RunKind::Mdi => 2,
        };
        self.notice = None;
        if self.hold {
            self.hold = false;
            if let Some(m) = self.current.as_mut().and_then(|c| c.motion.as_mut()) {
                m.set_hold(false);
            }
            return;
        }
        if self.run == 0 {
            self.run = flag;
            self.just_completed = false;
        }
    }
}
