//! Operator commands: START, STOP (feed hold), RESET, E-STOP, override, SINGLE BLOCK, jog, and
//! the run's lifecycle they drive (`docs/pulse-core.md`, "Operator commands").

use super::{axis_name, EndCause, Machine};
use crate::block::Axes;
use crate::pulse_core::{Command, RunKind};

impl Machine {
    /// Applies an operator command at the current machine time.
    pub fn command(&mut self, c: Command) {
        self.commands += 1;
        // The notice answers the latest operator action: a new action starts without one.
        if !c.keeps_notice() {
            self.notice = None;
        }
        // The cycle-start lamp's time so far is counted in the state it had (#3002).
        self.lamp();
        match c {
            Command::Start(kind) => self.start(kind),
            Command::Stop
                if self.in_tap
                    && self.run != 0
                    && !self.hold
                    && self
                        .current
                        .as_ref()
                        .is_some_and(|c| c.block.thread.is_some()) =>
            {
                // A thread pass geared to the spindle cannot stop in the groove: the hold
                // comes at the end of the pass (Fanuc: feed hold in threading).
                self.hold_after_tap = true;
                self.notice = Some(
                    "STOP during a thread pass: the feed hold comes at the end of the pass".into(),
                );
            }
            Command::Stop if self.in_tap && self.run != 0 && !self.hold => {
                // A tap stopped in the hole breaks: the hold waits until the tap is back out
                // at R with the spindle forward (Fanuc's G84; docs/pulse-core.md "Tapping").
                self.hold_after_tap = true;
                self.notice = Some(
                    "STOP during tapping: the tap feeds out to R and the spindle turns forward, then the feed hold".into(),
                );
            }
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
                if let Some(r) = &mut self.ret {
                    // The return stops too; START finishes it from where it stands.
                    r.motion.set_hold(true);
                    self.hold = true;
                }
            }
            Command::Reset => {
                self.abandon();
                // The program position comes back to the axes (docs/pulse-core.md, "Machine
                // lock").
                self.out.unshift();
                self.estop = false;
                self.estop_at = None;
                self.alarm = None;
                self.notice = None;
            }
            Command::Abandon => self.abandon(),
            Command::EStop => {
                self.out.flush();
                self.current = None;
                self.jog = None;
                // A reference return (HOME) has no run to abandon: it stops here too.
                self.ret = None;
                self.ret_queue.clear();
                self.increments.clear();
                if let Some(j) = &self.job {
                    if !self.estop {
                        self.estop_at = Some((j.kind, j.last.as_ref().map_or(0, |e| e.stmt.line)));
                    }
                    self.end_run(EndCause::Abandoned);
                }
                self.run = 0;
                self.hold = false;
                self.in_tap = false;
                self.hold_after_tap = false;
                self.estop = true;
                self.spindle = 0;
                self.spindle_dir = 0;
                // The drive is cut: the spindle stops at once (the encoder keeps its count).
                self.sp.halt(self.now);
                self.coolant = (false, false);
                self.alarm = Some("EMERGENCY STOP: pulses stopped; press RESET".into());
                self.send_position();
            }
            Command::Override(p) => self.pending_override = Some(p.min(150)),
            Command::SingleBlock(b) => self.single_block = b,
            Command::RapidOverride(p) => {
                if matches!(p, 0 | 25 | 50 | 100) {
                    self.rapid_override = p;
                    self.retarget();
                } else {
                    self.notice = Some(format!(
                        "rapid override {p} % refused: F0 (0), 25, 50 or 100"
                    ));
                }
            }
            Command::SpindleOverride(p) => {
                if (50..=120).contains(&p) && p.is_multiple_of(10) {
                    self.spindle_override = p;
                    self.spindle_sync(self.now);
                } else {
                    self.notice = Some(format!(
                        "spindle override {p} % refused: 50 to 120 in steps of 10"
                    ));
                }
            }
            Command::JogFeed(f) => self.set_jog_feed(f),
            Command::DryRun(on) => {
                self.dry_run = on;
                self.retarget();
            }
            Command::MachineLock(on) => {
                if self.lock_change_allowed("MACHINE LOCK") {
                    self.machine_lock = on;
                    self.set_lock();
                }
            }
            Command::ZNeglect(on) => {
                if self.lock_change_allowed("Z NEGLECT") {
                    self.z_neglect = on;
                    self.set_lock();
                }
            }
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
                        self.note_manual_move();
                        self.start_jog(axis, d, true, self.now);
                    }
                }
            }
            Command::JogAlive(ms) => {
                let until = self.now + u64::from(ms) * 1_000_000;
                if let Some(j) = self.jog.as_mut().filter(|j| j.release) {
                    j.deadline = Some(until);
                }
            }
            Command::JogRelease => {
                if let Some(j) = &mut self.jog {
                    if j.release {
                        j.motion.set_hold(true);
                    }
                }
            }
            Command::Input {
                digital,
                index,
                value,
            } => self.set_input(digital, index, value),
            Command::Home => self.home(),
            Command::SetTool(t) => {
                if self.current.is_none() && self.job.is_none() {
                    self.tool = t;
                    self.selected_t = t;
                    self.tool_len = self.set_length_of(t);
                }
            }
            Command::Increment { axis, pulses } => {
                if self.jog_check(axis).is_some() && pulses != 0 {
                    self.increments.push_back((axis, pulses));
                    self.next_increment(self.now);
                }
            }
        }
        self.lamp();
        self.send_state();
    }

    /// MACHINE LOCK and Z NEGLECT change only with no run loaded and nothing moving (a run is
    /// either locked all through or not at all); if not, the notice says why.
    fn lock_change_allowed(&mut self, name: &str) -> bool {
        if self.job.is_some()
            || self.current.is_some()
            || self.jog.is_some()
            || !self.increments.is_empty()
        {
            self.notice = Some(format!(
                "{name} refused: a run is loaded or an axis is moving; RESET or finish it first"
            ));
            return false;
        }
        true
    }

    /// The axes MACHINE LOCK (every one, the rotary axes too) and Z NEGLECT (Z) hold back,
    /// from the next pulse. Until stop 53 the lock was X Y Z only, and a locked run turned a
    /// rotary table (found by the operator sequences on a trunnion).
    fn set_lock(&mut self) {
        let (l, z) = (self.machine_lock, self.z_neglect);
        self.out.set_lock(Axes::from_fn(|a| l || (a == 2 && z)));
    }

    /// RESET without clearing an e-stop or alarm: the run is abandoned, the axes stop where
    /// they are, the spindle stops.
    fn abandon(&mut self) {
        self.out.flush();
        self.current = None;
        self.jog = None;
        self.increments.clear();
        if self.job.is_some() {
            self.end_run(EndCause::Abandoned);
        }
        self.run = 0;
        self.hold = false;
        self.in_tap = false;
        self.hold_after_tap = false;
        self.just_completed = false;
        self.ret = None;
        self.ret_queue.clear();
        self.spindle = 0;
        self.spindle_dir = 0;
        self.spindle_sync(self.now);
        self.coolant = (false, false);
        self.send_position();
    }

    fn start(&mut self, kind: RunKind) {
        if self.estop {
            self.notice = Some("START refused: EMERGENCY STOP in force, press RESET".into());
            return;
        }
        if self.alarm.is_some() {
            self.notice = Some("START refused: alarm in force, press RESET".into());
            return;
        }
        if self.jog.is_some() || !self.increments.is_empty() {
            self.notice = Some("START refused: a manual move is in progress".into());
            return;
        }
        let Some(job) = &self.job else {
            self.notice = None;
            self.begin_run(kind);
            return;
        };
        if job.kind != kind {
            self.notice = Some(format!(
                "START refused: an {} run is loaded; press RESET first",
                job.kind.name()
            ));
            return;
        }
        let resting = self.hold || (self.run == 0 && self.current.is_none());
        if !resting {
            self.notice = Some(match &self.current {
                Some(c) => format!(
                    "START ignored: N{} is still executing; press START again when it stops",
                    c.block.seq
                ),
                None => "START ignored: the program is running".into(),
            });
            return;
        }
        self.notice = None;
        self.run = kind.flag();
        self.just_completed = false;
        let back = self.job.as_mut().and_then(|j| j.return_to.take());
        if let Some(to) = back {
            if to != self.out.pos || self.ret.is_some() {
                // Manual intervention: back to where the run stopped first, Z-safe, at the
                // jog feed; the run resumes when the return is complete.
                self.hold = true;
                if let Some(r) = &mut self.ret {
                    r.motion.set_hold(false);
                    r.motion.resume_at(self.now);
                } else {
                    let r = self.settings.retract_axis;
                    self.ret_queue = return_path(self.out.pos, to, r).into();
                    self.next_return(self.now);
                }
                if let Some(j) = &mut self.job {
                    j.return_to = Some(to);
                }
                return;
            }
        }
        self.resume_held(self.now);
    }

    /// HOME: the reference return to the settings' reference point, the retract axis first
    /// (docs/pulse-core.md, "Position memory and the reference return"). A refusal names the
    /// switch that is on (a lathe's channel has no Z NEGLECT to name).
    fn home(&mut self) {
        let why = if self.estop {
            Some("HOME refused: EMERGENCY STOP in force, press RESET")
        } else if self.job.is_some() {
            Some("HOME refused: a run is loaded; RESET first")
        } else if self.machine_lock {
            Some("HOME refused: MACHINE LOCK is on")
        } else if self.z_neglect {
            Some("HOME refused: Z NEGLECT is on")
        } else if self.current.is_some() || self.jog.is_some() || self.ret.is_some() {
            Some("HOME refused: an axis is moving")
        } else {
            None
        };
        if let Some(w) = why {
            self.notice = Some(w.into());
            return;
        }
        self.out.unshift();
        let s = &self.settings;
        let to = Axes::from_fn(|a| s.to_pulses(s.reference_mm[a]));
        self.ret_queue = return_path(self.out.pos, to, s.retract_axis).into();
        self.next_return(self.now);
    }

    /// A new run whose source failed before its first block: the run ends at once, nothing
    /// moved.
    pub fn refuse_run(&mut self, error: crate::block::TranslateError) {
        if self.job.as_ref().is_some_and(|j| j.started_blocks == 0) {
            self.end_run(EndCause::Error {
                error,
                nothing_moved: true,
            });
        }
    }

    /// Ends a feed hold: the held motion accelerates again from time `t`.
    pub(super) fn resume_held(&mut self, t: u64) {
        if self.hold {
            self.hold = false;
            if let Some(m) = self.current.as_mut().and_then(|c| c.motion.as_mut()) {
                m.set_hold(false);
                m.resume_at(t);
            }
        }
    }
}

/// The return from `from` to `to` in a safe order, `retract` the axis that takes the tool
/// away from the work (Z on the centre, X on a lathe): out first if the target is further out,
/// else across first and in last, so the tool never moves across the work nearer to it than
/// either point. The rotary axes turn with the others.
pub fn return_path(from: Axes, to: Axes, retract: usize) -> Vec<Axes> {
    let mid = if to[retract] > from[retract] {
        let mut m = from;
        m[retract] = to[retract];
        m
    } else {
        let mut m = to;
        m[retract] = from[retract];
        m
    };
    let mut out = Vec::new();
    for p in [mid, to] {
        if p != *out.last().unwrap_or(&from) {
            out.push(p);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_return_moves_the_retract_axis_out_first_and_in_last() {
        let a = |x: i64, y: i64, z: i64| Axes::from([x, y, z]);
        // The centre: Z up first; going down, X and Y first and Z last.
        assert_eq!(
            return_path(a(5, 6, -100), a(0, 0, 0), 2),
            vec![a(5, 6, 0), a(0, 0, 0)]
        );
        assert_eq!(
            return_path(a(5, 6, 0), a(1, 2, -50), 2),
            vec![a(1, 2, 0), a(1, 2, -50)]
        );
        // A lathe's channel (X index 0, Z index 2): X out to the top first, then Z; back into
        // a groove, Z across first and X in last.
        assert_eq!(
            return_path(a(10, 0, -5), a(35, 0, 60), 0),
            vec![a(35, 0, -5), a(35, 0, 60)]
        );
        assert_eq!(
            return_path(a(35, 0, 60), a(10, 0, -5), 0),
            vec![a(35, 0, -5), a(10, 0, -5)]
        );
        // Nothing to do, or one axis only: no empty legs.
        assert!(return_path(a(1, 2, 3), a(1, 2, 3), 2).is_empty());
        assert_eq!(return_path(a(1, 2, 3), a(1, 2, 9), 2), vec![a(1, 2, 9)]);
    }
}
