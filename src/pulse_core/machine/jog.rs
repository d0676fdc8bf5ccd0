//! Manual moves: CONTINUOUS at the jog feed up to the travel limit, STEP and HANDLE increments
//! queued one after the other; and the return to where the run stopped.
//!
//! Manual intervention (`docs/pulse-core.md`): with a run loaded but at rest (a feed hold at
//! rest, or stopped between single blocks) the operator may move the axes by hand. The core
//! notes where the run stood; the next START first returns there (Z-safe, at the jog feed) and
//! only then resumes, so every block still ends on its programmed point.

use super::{axis_name, Jog, Machine, Phase};
use crate::block::Axes;
use crate::pulse_core::drive::Drive;

impl Machine {
    /// The travel limits of `axis` if a manual move may start now; if not, says why.
    pub(super) fn jog_check(&mut self, axis: usize) -> Option<(i64, i64)> {
        if !self.settings.has_axis(axis) {
            self.notice = Some(format!("this machine has no {} axis", axis_name(axis)));
            return None;
        }
        if self.estop {
            self.notice = Some("emergency stop: press RESET".into());
            return None;
        }
        if let Some(c) = &self.current {
            let at_rest = self.hold
                && c.phase == Phase::Move
                && c.motion.as_ref().is_some_and(|m| m.at_rest());
            if !at_rest {
                let why = match c.phase {
                    Phase::Sync => "the channel waits at a sync point (STOP first)",
                    Phase::Spindle { .. } => {
                        "the chuck waits for the spindle to stop or reach its speed"
                    }
                    Phase::PreAux | Phase::PostAux => {
                        "an auxiliary function (tool change or spindle) is in progress"
                    }
                    Phase::Move if self.hold => "the feed hold is still braking",
                    Phase::Move => "the program is running (STOP first)",
                };
                self.notice = Some(format!("jog refused: {why}"));
                return None;
            }
        } else if self.run != 0 && !self.hold {
            self.notice = Some("jog refused: the program is running (STOP first)".into());
            return None;
        }
        if self.job.is_none() {
            // After a run under MACHINE LOCK: a manual move starts from where the axes are,
            // and the travel limits are theirs (docs/pulse-core.md, "Machine lock").
            self.out.unshift();
        }
        if self.settings.wrapped(axis) {
            // A wrapped rotary axis turns without end: a CONTINUOUS jog runs until released
            // (a million degrees each way is the bound of one jog).
            let far = self.settings.to_pulses(1_000_000.0);
            let at = self.out.pos[axis];
            return Some((at.saturating_sub(far), at.saturating_add(far)));
        }
        Some(self.settings.travel_pulses(axis))
    }

    /// A manual move begins while a run is loaded: remember where the run stood, and drop a
    /// return that was under way (START plans it again from the new position).
    pub(super) fn note_manual_move(&mut self) {
        let pos = self.out.pos;
        if let Some(j) = &mut self.job {
            if j.return_to.is_none() {
                j.return_to = Some(pos);
            }
            self.ret = None;
            self.ret_queue.clear();
        }
    }

    pub(super) fn start_jog(&mut self, axis: usize, d: i64, release: bool, t0: u64) {
        let mut delta = Axes::default();
        delta[axis] = d;
        let top = self.rapid_top(&delta);
        let v = self.rapid_speed(self.settings.jog_mm_min.min(top));
        self.jog = Some(Jog {
            motion: Drive::dda_linear(&self.settings, delta, v, self.accel, t0),
            top,
            release,
            deadline: None,
        });
    }

    /// Starts the next queued STEP/HANDLE increment at time `t`.
    pub(super) fn next_increment(&mut self, t: u64) {
        if self.jog.is_some() {
            return;
        }
        while let Some((axis, pulses)) = self.increments.pop_front() {
            let (lo, hi) = self.settings.travel_pulses(axis);
            let to = self.out.pos[axis] + pulses;
            if !self.settings.wrapped(axis) && (to < lo || to > hi) {
                self.notice = Some(format!(
                    "{} jog refused: {:.3} {} is beyond the travel limit",
                    axis_name(axis),
                    self.settings.to_mm(to),
                    self.settings.unit(axis)
                ));
                continue;
            }
            self.note_manual_move();
            self.start_jog(axis, pulses, false, t);
            return;
        }
    }

    /// Starts the next leg of the return at time `t`; when none is left, the run resumes.
    pub(super) fn next_return(&mut self, t: u64) {
        while let Some(to) = self.ret_queue.pop_front() {
            let pos = self.out.pos;
            let delta = Axes::from_fn(|a| to[a] - pos[a]);
            if delta == [0; 3] {
                continue;
            }
            let top = self.rapid_top(&delta);
            let v = self.rapid_speed(self.settings.jog_mm_min.min(top));
            self.ret = Some(Jog {
                motion: Drive::dda_linear(&self.settings, delta, v, self.accel, t),
                top,
                release: false,
                deadline: None,
            });
            return;
        }
        if let Some(j) = &mut self.job {
            j.return_to = None;
        }
        self.send_position();
        self.resume_held(t);
    }
}
