//! Jogging: CONTINUOUS at the jog feed up to the travel limit, STEP and HANDLE increments
//! queued one after the other; all only with the program stopped.

use super::{axis_name, Jog, Machine};
use crate::pulse_core::motion::{speed_pulses_ns, Motion};

impl Machine {
    /// The travel limits of `axis` if a jog may start now.
    pub(super) fn jog_check(&mut self, axis: usize) -> Option<(i64, i64)> {
        if axis > 2 {
            self.notice = Some(format!("no axis {axis}"));
            return None;
        }
        if self.estop {
            self.notice = Some("emergency stop: press RESET".into());
            return None;
        }
        if self.run != 0 || self.current.is_some() {
            self.notice = Some("jog refused: the program is running (press RESET)".into());
            return None;
        }
        Some(self.settings.travel_pulses(axis))
    }
    pub(super) fn start_jog(&mut self, axis: usize, d: i64, release: bool) {
        let mut delta = [0; 3];
        delta[axis] = d;
        let v = speed_pulses_ns(self.settings.jog_mm_min, self.settings.pulse_mm);
        self.jog = Some(Jog {
            motion: Motion::linear(delta, v, self.accel, self.now),
            release,
        });
    }
    pub(super) fn next_increment(&mut self) {
        if self.jog.is_some() {
            return;
        }
        while let Some((axis, pulses)) = self.increments.pop_front() {
            let (lo, hi) = self.settings.travel_pulses(axis);
            let to = self.out.pos[axis] + pulses;
            if to < lo || to > hi {
                self.notice = Some(format!(
                    "{} jog refused: {:.3} mm is beyond the travel limit",
                    axis_name(axis),
                    self.settings.to_mm(to)
                ));
                continue;
            }
            self.start_jog(axis, pulses, false);
            return;
        }
    }
}
