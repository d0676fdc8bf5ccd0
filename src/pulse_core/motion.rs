//! PGEN: pulse distribution for one motion, with the KT ramp.
//!
//! Timing (all machine time, ns, in f64 inside a motion and u64 on the pulses):
//! - A motion is a sequence of steps along the path. A linear step is one pulse of the major
//!   axis (LINE), with PCHK pulsing each minor axis when its ΣLF falls to 0 or below; its path
//!   length is ds = |delta| / |major| pulses. An arc step is one pulse of X, of Y, or of both;
//!   its ds is the length of circle it advances, R·Δθ (see `arc.rs`).
//! - The period KT of a step is ds / v. The path speed v ramps at the machine's constant
//!   acceleration a: across a step of length ds, v² changes by at most 2·a·ds, and the step
//!   takes 2·ds / (v + v') (exact for constant acceleration). The speed is held to the target
//!   (feed × override, or 0 in a feed hold) and to √(2·a·remaining) so that every block ends at
//!   rest on its end point; the last step always ends at speed 0.
//! - A step's pulses carry the time at the end of the step. A step that would end at or after
//!   the horizon (the end of the current NCBR tick) is not taken yet.

use super::arc::{ArcStep, ArcStepper};
use super::pulse_out::PulseOut;

/// What a call to `Motion::run` left the motion in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Progress {
    /// Every pulse is out: distribution complete (DEN).
    Done,
    /// The next step falls at or after the horizon.
    Pending,
    /// Standing still mid-motion: feed hold or override 0.
    AtRest,
}

/// The speed ramp (KT control): path speed in pulses per ns and time of the last step.
#[derive(Clone, Debug)]
struct Profile {
    v: f64,
    vt: f64,
    a: f64,
    a2: f64,
    t: f64,
}

impl Profile {
    /// Speed at the end of a step of length `ds` with `rem` path left after it; `None` when
    /// the machine stands still.
    #[inline(always)]
    fn step(&self, ds: f64, rem: f64, last: bool) -> Option<(f64, f64)> {
        let (v, vt) = (self.v, self.vt);
        let mut vn = if v == vt {
            v
        } else if v < vt {
            (v * v + self.a2 * ds).sqrt().min(vt)
        } else {
            (v * v - self.a2 * ds).max(0.0).sqrt().max(vt)
        };
        let lim = self.a2 * rem;
        if vn * vn > lim {
            vn = lim.max(0.0).sqrt();
        }
        if last {
            vn = 0.0;
        }
        let s = v + vn;
        if s > 0.0 {
            Some((vn, 2.0 * ds / s))
        } else if vt > 0.0 {
            // From rest to rest in one step: half accelerating, half braking.
            Some((0.0, 2.0 * ds / (self.a * ds).sqrt()))
        } else {
            None
        }
    }
}

/// LINE / PCHK state of a linear move (positioning moves use it too).
#[derive(Clone, Debug)]
struct Linear {
    major: usize,
    dir: [i8; 3],
    /// LB: the major-axis amount.
    lb: i64,
    /// L: each axis amount.
    l: [i64; 3],
    /// ΣLF of each minor axis.
    sigma: [i64; 3],
    minors: [usize; 2],
    n_minor: usize,
    steps_left: i64,
    ds: f64,
}

/// The stepping of one motion.
#[derive(Clone, Debug)]
enum Path {
    Linear(Linear),
    Arc {
        st: ArcStepper,
        pending: Option<ArcStep>,
        s_left: f64,
        steps_left: u64,
    },
}

/// One motion being distributed by PGEN.
#[derive(Clone, Debug)]
pub struct Motion {
    path: Path,
    prof: Profile,
    /// Programmed path speed after override, pulses/ns.
    target: f64,
    hold: bool,
}

/// Acceleration in pulses/ns² from mm/s² and the pulse length.
pub fn accel_pulses_ns2(accel_mm_s2: f64, pulse_mm: f64) -> f64 {
    accel_mm_s2 / pulse_mm / 1e18
}

/// Speed in pulses/ns from mm/min and the pulse length.
pub fn speed_pulses_ns(mm_min: f64, pulse_mm: f64) -> f64 {
    mm_min / 60.0 / pulse_mm / 1e9
}

impl Motion {
    /// A linear move of `delta` pulses starting at rest at time `t0`.
    pub fn linear(delta: [i64; 3], speed: f64, accel: f64, t0: u64) -> Motion {
        let l = [delta[0].abs(), delta[1].abs(), delta[2].abs()];
        let mut major = 0;
        for a in 1..3 {
            if l[a] > l[major] {
                major = a;
            }
        }
        let mut minors = [0; 2];
        let mut n_minor = 0;
        for (a, &la) in l.iter().enumerate() {
            if a != major && la > 0 {
                minors[n_minor] = a;
                n_minor += 1;
            }
        }
        let len = ((l[0] * l[0] + l[1] * l[1] + l[2] * l[2]) as f64).sqrt();
        let lb = l[major];
        let dir = [
            delta[0].signum() as i8,
            delta[1].signum() as i8,
            delta[2].signum() as i8,
        ];
        Motion {
            path: Path::Linear(Linear {
                major,
                dir,
                lb,
                l,
                sigma: [lb; 3],
                minors,
                n_minor,
                steps_left: lb,
                ds: if lb > 0 { len / lb as f64 } else { 1.0 },
            }),
            prof: Profile {
                v: 0.0,
                vt: speed,
                a: accel,
                a2: 2.0 * accel,
                t: t0 as f64,
            },
            target: speed,
            hold: false,
        }
    }

    /// An arc by `st`, starting at rest at time `t0`.
    pub fn arc(st: ArcStepper, speed: f64, accel: f64, t0: u64) -> Motion {
        let mut dry = st.clone();
        let (mut s, mut n) = (0.0, 0u64);
        while let Some(a) = dry.next_step() {
            s += a.ds;
            n += 1;
        }
        Motion {
            path: Path::Arc {
                st,
                pending: None,
                s_left: s,
                steps_left: n,
            },
            prof: Profile {
                v: 0.0,
                vt: speed,
                a: accel,
                a2: 2.0 * accel,
                t: t0 as f64,
            },
            target: speed,
            hold: false,
        }
    }

    /// Sets the programmed speed (feed × override, at an NCBR tick).
    pub fn set_target(&mut self, speed: f64) {
        self.target = speed;
        self.prof.vt = if self.hold { 0.0 } else { speed };
    }

    /// Feed hold on or off: decelerate to rest, or accelerate back to the target.
    pub fn set_hold(&mut self, hold: bool) {
        self.hold = hold;
        self.prof.vt = if hold { 0.0 } else { self.target };
    }

    /// After a rest (feed hold), the next step is timed from `t` on, not from the last pulse
    /// before the rest.
    pub fn resume_at(&mut self, t: u64) {
        if self.prof.v == 0.0 {
            self.prof.t = self.prof.t.max(t as f64);
        }
    }

    /// Whether a feed hold is in force on this motion.
    pub fn is_held(&self) -> bool {
        self.hold
    }

    /// Whether the path speed is 0.
    pub fn at_rest(&self) -> bool {
        self.prof.v == 0.0
    }

    /// Path speed, mm/min.
    pub fn speed_mm_min(&self, pulse_mm: f64) -> f64 {
        self.prof.v * 1e9 * 60.0 * pulse_mm
    }

    /// Time of the last step, ns.
    pub fn last_t(&self) -> u64 {
        self.prof.t as u64
    }

    /// Distributes pulses until the motion completes, stands still, or the next step would
    /// fall at or after `horizon`.
    pub fn run(&mut self, horizon: u64, out: &mut PulseOut) -> Progress {
        let h = horizon as f64;
        match &mut self.path {
            Path::Linear(ln) => run_linear(ln, &mut self.prof, h, out),
            Path::Arc {
                st,
                pending,
                s_left,
                steps_left,
            } => loop {
                if *steps_left == 0 {
                    return Progress::Done;
                }
                let step = match *pending {
                    Some(s) => s,
                    None => match st.next_step() {
                        Some(s) => {
                            *pending = Some(s);
                            s
                        }
                        None => {
                            *steps_left = 0;
                            return Progress::Done;
                        }
                    },
                };
                let ds = step.ds;
                let rem = *s_left - ds;
                let Some((vn, dt)) = self.prof.step(ds, rem, *steps_left == 1) else {
                    return Progress::AtRest;
                };
                let tn = self.prof.t + dt;
                if tn >= h {
                    return Progress::Pending;
                }
                self.prof.t = tn;
                self.prof.v = vn;
                *s_left = rem;
                *steps_left -= 1;
                *pending = None;
                let t = tn as u64;
                if step.dx != 0 {
                    out.pulse(0, step.dx, t);
                }
                if step.dy != 0 {
                    out.pulse(1, step.dy, t);
                }
            },
        }
    }
}

/// LINE: the major axis gets a pulse every step; PCHK gives each minor axis a pulse when its
/// ΣLF (starting at LB, less L each step) falls to 0 or below, and adds LB back.
#[inline(always)]
fn run_linear(ln: &mut Linear, prof: &mut Profile, h: f64, out: &mut PulseOut) -> Progress {
    let ds = ln.ds;
    let major = ln.major;
    let dmaj = ln.dir[major];
    loop {
        if ln.steps_left == 0 {
            return Progress::Done;
        }
        let rem = (ln.steps_left - 1) as f64 * ds;
        let Some((vn, dt)) = prof.step(ds, rem, ln.steps_left == 1) else {
            return Progress::AtRest;
        };
        let tn = prof.t + dt;
        if tn >= h {
            return Progress::Pending;
        }
        prof.t = tn;
        prof.v = vn;
        ln.steps_left -= 1;
        let t = tn as u64;
        out.pulse(major, dmaj, t);
        for &a in &ln.minors[..ln.n_minor] {
            ln.sigma[a] -= ln.l[a];
            if ln.sigma[a] <= 0 {
                ln.sigma[a] += ln.lb;
                out.pulse(a, ln.dir[a], t);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_kt_ramp_is_constant_acceleration_and_ends_at_rest() {
        let a = accel_pulses_ns2(1000.0, 0.001);
        let fast = speed_pulses_ns(1e9, 0.001); // never reached in 20,000 pulses
        let mut m = Motion::linear([20_000, 0, 0], fast, a, 0);
        let mut out = PulseOut::default();
        out.set_log(None, true);
        assert_eq!(m.run(u64::MAX, &mut out), Progress::Done);
        let p = out.take_capture();
        assert_eq!(p.len(), 20_000);
        // accelerating half: s = a t² / 2, so pulse k is at √(2k / a)
        for k in [1usize, 10, 100, 1000, 9000] {
            let want = (2.0 * k as f64 / a).sqrt();
            let got = p[k - 1].t_ns as f64;
            assert!(
                (got - want).abs() <= want * 1e-3 + 1.0,
                "pulse {k}: {got} vs {want}"
            );
        }
        // braking half mirrors it: ends at rest at 2·√(2·10,000 / a)
        let t_end = 2.0 * (2.0 * 10_000.0 / a).sqrt();
        let last = p[19_999].t_ns as f64;
        assert!((last - t_end).abs() <= t_end * 1e-3, "{last} vs {t_end}");
        assert!(m.at_rest());
    }

    #[test]
    fn a_hold_brakes_to_rest_and_a_resume_finishes_the_move() {
        let a = accel_pulses_ns2(1000.0, 0.001);
        let v = speed_pulses_ns(6000.0, 0.001);
        let mut m = Motion::linear([0, 50_000, -20_000], v, a, 0);
        let mut out = PulseOut::default();
        assert_eq!(m.run(200_000_000, &mut out), Progress::Pending);
        m.set_hold(true);
        assert_eq!(m.run(u64::MAX, &mut out), Progress::AtRest);
        let held = out.pos;
        assert!(held[1] > 0 && held[1] < 50_000);
        m.set_hold(false);
        assert_eq!(m.run(u64::MAX, &mut out), Progress::Done);
        assert_eq!(out.pos, [0, 50_000, -20_000]);
        assert_eq!(out.count, [0, 50_000, 20_000]);
    }
}
