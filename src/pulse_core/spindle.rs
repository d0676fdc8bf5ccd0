//! The spindle as a kernel object (issue 22; docs/pulse-core.md, "The spindle"): its actual
//! speed ramping at a constant acceleration towards the target the machine sets (the
//! commanded speed after the override, or the constant-surface-speed rpm of the tool's X),
//! and the encoder it turns, with an index once per revolution.
//!
//! Everything is closed-form from the last change of target (the anchor: time, rpm, encoder
//! phase), as the path ramps of `motion.rs` are: the speed at any time, the encoder count at
//! any time and, inverting it, the time at which the encoder reaches a phase (what a thread
//! pass steps by). Speeds are signed rpm (negative = reverse, M4); the encoder counts up
//! turning forward and down in reverse, `lines` counts per revolution, the index at every
//! multiple of `lines`. Replaces the lathe simulator's per-tick spindle integration
//! (`lathe/sim/exec.rs` `spindle`, `target_rpm`, `at_speed`, deleted in issue 22), which the
//! kernel did not copy.

use crate::settings::MachineSettings;

/// ns per minute.
const NS_MIN: f64 = 60e9;

/// One spindle: its parameters, its target, and its actual speed and encoder from the anchor.
#[derive(Clone, Debug, PartialEq)]
pub struct Spindle {
    /// Acceleration, rpm/s; 0 = the speed changes at once.
    accel: f64,
    /// Encoder counts per revolution (≥ 1).
    lines: u32,
    /// Target speed, signed rpm.
    target: f64,
    /// The anchor: time (ns), signed rpm and encoder phase (counts) at the last change of
    /// target.
    t0: f64,
    rpm0: f64,
    phase0: f64,
}

impl Spindle {
    /// A spindle at rest at time 0, encoder 0, with the machine's parameters.
    pub fn new(s: &MachineSettings) -> Spindle {
        Spindle {
            accel: if s.spindle_accel_rpm_s.is_finite() {
                s.spindle_accel_rpm_s.max(0.0)
            } else {
                0.0
            },
            lines: s.spindle_encoder_lines.max(1),
            target: 0.0,
            t0: 0.0,
            rpm0: 0.0,
            phase0: 0.0,
        }
    }

    /// Encoder counts per revolution.
    pub fn lines(&self) -> u32 {
        self.lines
    }

    /// Whether the speed ramps (an acceleration is set) rather than changing at once.
    pub fn ramps(&self) -> bool {
        self.accel > 0.0
    }

    /// The target speed, signed rpm.
    pub fn target(&self) -> f64 {
        self.target
    }

    /// Sets the target at time `t` (ns, not before the anchor): the ramp starts from the
    /// speed and encoder phase at `t`. The same target again changes nothing.
    pub fn set_target(&mut self, t: u64, rpm: f64) {
        let rpm = if rpm.is_finite() { rpm } else { 0.0 };
        if rpm == self.target {
            return;
        }
        let t = (t as f64).max(self.t0);
        let (r, p) = (self.rpm_at_f(t), self.phase_at_f(t));
        self.t0 = t;
        self.rpm0 = r;
        self.phase0 = p;
        self.target = rpm;
    }

    /// Turning at `rpm` (signed) at time `t`, already at that speed, its target: a spindle that
    /// was turning before this machine's clock began (a lathe channel's new cycle goes on with
    /// the spindle the last one left turning). The encoder keeps its phase.
    pub fn preset(&mut self, t: u64, rpm: f64) {
        let rpm = if rpm.is_finite() { rpm } else { 0.0 };
        let t = (t as f64).max(self.t0);
        self.phase0 = self.phase_at_f(t);
        self.t0 = t;
        self.rpm0 = rpm;
        self.target = rpm;
    }

    /// Stops at once at time `t` (E-STOP: the drive is cut, the encoder keeps its count).
    pub fn halt(&mut self, t: u64) {
        let t = (t as f64).max(self.t0);
        self.phase0 = self.phase_at_f(t);
        self.t0 = t;
        self.rpm0 = 0.0;
        self.target = 0.0;
    }

    /// Signed acceleration of the ramp in force (rpm/ns) and its duration from the anchor (ns).
    fn ramp(&self) -> (f64, f64) {
        let d = self.target - self.rpm0;
        if d == 0.0 || self.accel <= 0.0 {
            return (0.0, 0.0);
        }
        let a = self.accel * 1e-9;
        (a * d.signum(), d.abs() / a)
    }

    fn rpm_at_f(&self, t: f64) -> f64 {
        let tau = (t - self.t0).max(0.0);
        let (a, dur) = self.ramp();
        if tau >= dur {
            self.target
        } else {
            self.rpm0 + a * tau
        }
    }

    /// Encoder phase (counts, fractional) at time `t`: the anchor's plus ∫rpm.
    fn phase_at_f(&self, t: f64) -> f64 {
        let tau = (t - self.t0).max(0.0);
        let (a, dur) = self.ramp();
        let k = f64::from(self.lines) / NS_MIN;
        let in_ramp = tau.min(dur);
        let p = self.rpm0 * in_ramp + 0.5 * a * in_ramp * in_ramp;
        self.phase0 + k * (p + self.target * (tau - in_ramp))
    }

    /// Whether the speed is at the target from time `t` on (the ramp is over, or there is
    /// none): `rpm_at` then gives exactly `target` for `t` and every later time.
    pub fn steady_at(&self, t: u64) -> bool {
        let (_, dur) = self.ramp();
        (t as f64 - self.t0).max(0.0) >= dur
    }

    /// The actual speed at time `t`, signed rpm.
    pub fn rpm_at(&self, t: u64) -> f64 {
        self.rpm_at_f(t as f64)
    }

    /// The encoder phase at time `t`, counts (fractional).
    pub fn phase_at(&self, t: u64) -> f64 {
        self.phase_at_f(t as f64)
    }

    /// The encoder count at time `t` (whole counts; negative after turning in reverse).
    pub fn count_at(&self, t: u64) -> i64 {
        self.phase_at_f(t as f64).floor() as i64
    }

    /// At speed (the spindle speed arrival signal): the target is not 0 and the actual speed
    /// is within 1 % of it (at least 1 rpm), the lathe simulator's rule.
    pub fn at_speed(&self, t: u64) -> bool {
        let tg = self.target;
        tg != 0.0 && (self.rpm_at(t) - tg).abs() <= (0.01 * tg.abs()).max(1.0)
    }

    /// The first time at or after `t` at which the spindle is at speed with the target in
    /// force; `None` for a target of 0.
    pub fn ready_at(&self, t: u64) -> Option<u64> {
        if self.target == 0.0 {
            return None;
        }
        if self.at_speed(t) {
            return Some(t);
        }
        let (a, dur) = self.ramp();
        if a == 0.0 {
            return Some(t);
        }
        let tol = (0.01 * self.target.abs()).max(1.0);
        // The ramp reaches target ∓ tol this long before its end.
        let t_in = self.t0 + (dur - tol / a.abs()).max(0.0);
        Some((t_in.ceil() as u64).max(t))
    }

    /// The time (ns) at which a spindle commanded to stop (a target of 0: M5, M30, M19) stands
    /// still, its speed 0 at the end of the ramp down (the zero-speed signal): the anchor if it
    /// was at rest already or stops at once (no ramp). `None` for a target that is not 0.
    pub fn stops_at(&self) -> Option<u64> {
        if self.target != 0.0 {
            return None;
        }
        let (_, dur) = self.ramp();
        Some((self.t0 + dur).ceil() as u64)
    }

    /// The time (ns, fractional) at which the encoder phase reaches `phase`, turning the way
    /// the target turns (`None` if it never does: stopped, or the phase lies behind).
    pub fn time_at_phase(&self, phase: f64) -> Option<f64> {
        self.phase_clock().time_at_phase(phase)
    }

    /// What `time_at_phase` needs of the spindle as it is now, worked out once: a thread
    /// pass asks it for every step.
    pub fn phase_clock(&self) -> PhaseClock {
        let s = self.target.signum();
        let k = f64::from(self.lines) / NS_MIN;
        // Mirrored so that the spindle turns forward: rpm r0 ≥ 0 wanted.
        let (r0, tg) = (s * self.rpm0, s * self.target);
        let (a, dur) = self.ramp();
        let a = s * a;
        PhaseClock {
            s,
            k,
            r0,
            tg,
            a,
            dur,
            in_ramp: r0 * dur + 0.5 * a * dur * dur,
            t0: self.t0,
            phase0: self.phase0,
        }
    }

    /// The next index (a multiple of `lines`) at or after the phase at time `t`, in the
    /// direction the target turns.
    pub fn next_index(&self, t: u64) -> i64 {
        let n = f64::from(self.lines);
        let p = self.phase_at(t) / n;
        let i = if self.target < 0.0 {
            p.floor()
        } else {
            p.ceil()
        };
        (i * n) as i64
    }
}

/// [`Spindle::time_at_phase`] for one state of the spindle (`Spindle::phase_clock`): the
/// ramp and the constants it uses, each computed as before, so the times are the same to the
/// bit; only the work per call is less.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhaseClock {
    /// The sign of the target (0: stopped), and the encoder counts per rpm·ns.
    s: f64,
    k: f64,
    /// The anchor's speed and the target, mirrored to turn forward; the mirrored acceleration
    /// (rpm/ns), the ramp's duration (ns) and the rpm·ns turned during it.
    r0: f64,
    tg: f64,
    a: f64,
    dur: f64,
    in_ramp: f64,
    /// The anchor's time (ns) and encoder phase (counts).
    t0: f64,
    phase0: f64,
}

impl PhaseClock {
    /// The time (ns, fractional) at which the encoder phase reaches `phase`, turning the way
    /// the target turns (`None` if it never does: stopped, or the phase lies behind).
    #[inline]
    pub fn time_at_phase(&self, phase: f64) -> Option<f64> {
        let s = self.s;
        if s == 0.0 {
            return None;
        }
        let (r0, tg, a, dur, in_ramp) = (self.r0, self.tg, self.a, self.dur, self.in_ramp);
        let need = s * (phase - self.phase0) / self.k; // rpm·ns still to turn
        if need <= 0.0 {
            return Some(self.t0);
        }
        if need <= in_ramp {
            // r0·τ + a·τ²/2 = need, the smaller root in the stable form.
            let disc = r0 * r0 + 2.0 * a * need;
            let den = r0 + disc.max(0.0).sqrt();
            if den > 0.0 {
                return Some(self.t0 + 2.0 * need / den);
            }
            return None;
        }
        if tg <= 0.0 {
            return None;
        }
        Some(self.t0 + dur + (need - in_ramp) / tg)
    }
}

/// The constant-surface-speed rpm at `radius_mm` from the spindle centre for `m_per_min`,
/// capped by `limit_rpm` (the lathe simulator's `target_rpm`, moved here).
pub fn css_rpm(m_per_min: f64, limit_rpm: f64, radius_mm: f64) -> f64 {
    let rpm = if radius_mm > 1e-9 {
        1000.0 * m_per_min / (std::f64::consts::TAU * radius_mm)
    } else {
        f64::INFINITY
    };
    let r = rpm.min(limit_rpm);
    if r.is_finite() {
        r.max(0.0)
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spindle(accel: f64, lines: u32) -> Spindle {
        Spindle::new(&MachineSettings {
            spindle_accel_rpm_s: accel,
            spindle_encoder_lines: lines,
            ..MachineSettings::builtin()
        })
    }

    #[test]
    fn the_ramp_takes_delta_over_accel_and_the_encoder_integrates_the_speed() {
        let mut s = spindle(6000.0, 1024);
        s.set_target(1_000_000, 3000.0);
        // 3000 rpm at 6000 rpm/s: 0.5 s.
        let end = 1_000_000 + 500_000_000;
        assert_eq!(s.rpm_at(end), 3000.0);
        assert!((s.rpm_at(end - 1_000_000) - 2994.0).abs() < 1e-6);
        assert_eq!(s.rpm_at(1_000_000 + 250_000_000), 1500.0);
        // ∫rpm over the ramp: 3000/2 rpm × 0.5 s = 12.5 rev; then 1 s at 3000 rpm = 50 rev.
        let lines = 1024.0;
        assert!((s.phase_at(end) - 12.5 * lines).abs() < 1e-6);
        assert_eq!(s.count_at(end + 1_000_000_000), (62.5 * lines) as i64);
        // At speed within 1 %: 30 rpm = 5 ms before the end.
        assert_eq!(s.ready_at(0), Some(end - 5_000_000));
        assert!(!s.at_speed(end - 5_000_001) && s.at_speed(end - 5_000_000));
        assert_eq!(s.stops_at(), None);
        // Back down to 1000 rpm from t = 2 s: ramp of 1/3 s.
        s.set_target(2_000_000_000, 1000.0);
        assert_eq!(s.rpm_at(2_000_000_000 + 1_000_000_000 / 3 + 1), 1000.0);
        // Stopped (M5) at t = 3 s: 1000 rpm coasts down at 6000 rpm/s in 1/6 s.
        s.set_target(3_000_000_000, 0.0);
        let stop = 3_000_000_000 + 1_000_000_000 / 6 + 1;
        assert_eq!(s.stops_at(), Some(stop));
        assert!(s.rpm_at(stop - 1_000) > 0.0 && s.rpm_at(stop) == 0.0);
        assert_eq!(spindle(0.0, 1024).stops_at(), Some(0));
    }

    #[test]
    fn the_time_at_a_phase_inverts_the_encoder() {
        let mut s = spindle(4000.0, 1000);
        s.set_target(0, -2000.0);
        for p in [-1.0, -500.0, -8333.0, -20_000.0, -123_456.0] {
            let t = s.time_at_phase(p).unwrap_or(f64::NAN);
            assert!((s.phase_at_f(t) - p).abs() < 1e-6, "{p}: {t}");
        }
        assert_eq!(
            s.next_index(300_000_000),
            -(s.phase_at(300_000_000) / -1000.0).ceil() as i64 * 1000
        );
        let mut still = spindle(0.0, 1000);
        assert_eq!(still.time_at_phase(10.0), None);
        still.set_target(0, 600.0);
        // 600 rpm × 1000 lines = 10 counts/ms.
        assert_eq!(still.time_at_phase(10.0), Some(1_000_000.0));
        assert_eq!(still.ready_at(7), Some(7));
    }

    #[test]
    fn css_follows_the_radius_then_the_limit() {
        // 150 m/min at 10 mm: 2387.3 rpm.
        assert!((css_rpm(150.0, 4000.0, 10.0) - 2387.324).abs() < 1e-3);
        assert_eq!(css_rpm(150.0, 4000.0, 1.0), 4000.0);
        assert_eq!(css_rpm(150.0, 4000.0, 0.0), 4000.0);
        assert_eq!(css_rpm(150.0, f64::INFINITY, 0.0), 0.0);
    }
}
