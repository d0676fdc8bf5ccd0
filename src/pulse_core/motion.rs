//! PGEN: pulse distribution for one motion, with the KT ramp.
//!
//! Timing (all machine time, ns, in f64 inside a motion and u64 on the pulses):
//! - A motion is a sequence of steps along the path. A linear step is one pulse of the major
//!   axis (LINE), with PCHK pulsing each minor axis when its ΣLF falls to 0 or below; its path
//!   length is ds = |delta| / |major| pulses. An arc step is one pulse of one or both axes of
//!   its plane, or (on a helix) of the normal axis; its ds is the length of path it advances,
//!   R·Δθ in the plane (see `arc.rs`).
//! - The path speed v ramps at the machine's constant acceleration a and is held to the
//!   target (feed × override, or 0 in a feed hold) and to √(2·a·remaining), so that every block
//!   ends at rest on its end point. The period KT of a step follows from the time the path
//!   position at the end of the step is reached, computed in closed form from the start of the
//!   phase of the ramp in force (the anchor), never summed step by step:
//!   - accelerating from (t₀, v₀, s₀): v² = v₀² + 2a(s − s₀), t = t₀ + (v − v₀)/a;
//!   - cruising at v₀: t = t₀ + (s − s₀)/v₀;
//!   - braking to a lower target: v² = v₀² − 2a(s − s₀), t = t₀ + (v₀ − v)/a;
//!   - braking for the end: v² = 2a·(remaining), t = t₀ + (v₀ − v)/a.
//!
//!   A phase ends where its speed meets the next limit (computed exactly, mid-step if need be),
//!   which anchors the next phase; a new target (override at an NCBR tick, feed hold, resume)
//!   anchors a new phase where the motion is. So a step's time depends only on the anchor and
//!   the step's position: the same whether the motion is run tick by tick or a whole block at
//!   once, and with no square root or division carried from step to step.
//! - A step's pulses carry the time at the end of the step. A step that would end at or after
//!   the horizon (the end of the current NCBR tick) is not taken yet.

use super::arc::{ArcStep, ArcStepper};
use super::pulse_out::PulseOut;
use super::spindle::{PhaseClock, Spindle};
use crate::block::{Axes, MAX_AXES};

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

/// The phase of the speed ramp in force.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Phase {
    /// Standing still (feed hold or override 0 at rest).
    Rest,
    /// Speeding up toward the target.
    Accel,
    /// At the target.
    Cruise,
    /// Slowing down toward a lower target (feed hold, override lowered).
    Brake,
    /// Slowing down so as to stop on the end point.
    End,
}

/// The speed ramp (KT control), in pulses and ns.
#[derive(Clone, Debug)]
struct Profile {
    a2: f64,
    inv_a: f64,
    /// Target speed: feed × override, or 0 in a feed hold.
    vt: f64,
    /// Path length of the whole motion.
    total: f64,
    phase: Phase,
    /// The anchor of the phase: time, speed and path position where it began.
    t0: f64,
    v0: f64,
    s0: f64,
    /// 1 / v0 (cruise).
    inv_v0: f64,
    /// Path position where the phase ends, and the phase that follows it.
    s_end: f64,
    next: Phase,
    /// After the last step taken: speed, time, path position.
    v: f64,
    t: f64,
    s: f64,
    /// The time of the next step, found at or past the horizon by the last `run` that stopped
    /// there (`Progress::Pending`); NaN when unknown. Any new anchor forgets it.
    pending_t: f64,
}

impl Profile {
    fn new(vt: f64, a: f64, total: f64, t0: u64) -> Profile {
        let mut p = Profile {
            a2: 2.0 * a,
            inv_a: 1.0 / a,
            vt,
            total,
            phase: Phase::Rest,
            t0: t0 as f64,
            v0: 0.0,
            s0: 0.0,
            inv_v0: 0.0,
            s_end: 0.0,
            next: Phase::Rest,
            v: 0.0,
            t: t0 as f64,
            s: 0.0,
            pending_t: f64::NAN,
        };
        p.anchor();
        p
    }

    /// Starts the phase that fits where the motion is now.
    fn anchor(&mut self) {
        self.pending_t = f64::NAN;
        let (v, s) = (self.v, self.s);
        let e2 = self.a2 * (self.total - s).max(0.0);
        let phase = if v > 0.0 && v * v > e2 {
            Phase::End
        } else if v < self.vt {
            Phase::Accel
        } else if v == self.vt {
            if v > 0.0 {
                Phase::Cruise
            } else {
                Phase::Rest
            }
        } else {
            Phase::Brake
        };
        self.begin(phase, self.t, v, s);
    }

    /// Begins `phase` at time `t`, speed `v`, path position `s`: where it ends and what follows.
    fn begin(&mut self, phase: Phase, t: f64, v: f64, s: f64) {
        self.phase = phase;
        self.t0 = t;
        self.v0 = v;
        self.s0 = s;
        self.inv_v0 = if v > 0.0 { 1.0 / v } else { 0.0 };
        let vt2 = self.vt * self.vt;
        (self.s_end, self.next) = match phase {
            Phase::Rest => (s, Phase::Rest),
            Phase::Accel => {
                // The first limit met: the target, or braking for the end.
                let sc = s + (vt2 - v * v) / self.a2;
                let sx = 0.5 * (self.total + s - v * v / self.a2);
                if sc <= sx {
                    (sc, Phase::Cruise)
                } else {
                    (sx, Phase::End)
                }
            }
            Phase::Cruise => (self.total - v * v / self.a2, Phase::End),
            // Both this braking and the end's lose v² at 2a per unit of path: begun below the
            // end's limit, it stays below.
            Phase::Brake => (
                s + (v * v - vt2) / self.a2,
                if self.vt > 0.0 {
                    Phase::Cruise
                } else {
                    Phase::Rest
                },
            ),
            Phase::End => (f64::INFINITY, Phase::Rest),
        };
    }

    /// Speed and time at path position `s1` in the phase in force, `rem` path left there.
    #[inline(always)]
    fn formula(&self, s1: f64, rem: f64) -> (f64, f64) {
        match self.phase {
            Phase::Cruise => self.cruise(s1, rem),
            Phase::Accel => self.accel(s1, rem),
            Phase::Brake => self.brake(s1, rem),
            Phase::End => self.end(s1, rem),
            Phase::Rest => (0.0, self.t0),
        }
    }

    /// Cruising at v₀: t = t₀ + (s − s₀)/v₀.
    #[inline(always)]
    fn cruise(&self, s1: f64, _rem: f64) -> (f64, f64) {
        (self.v0, self.t0 + (s1 - self.s0) * self.inv_v0)
    }

    /// Accelerating: v² = v₀² + 2a(s − s₀), t = t₀ + (v − v₀)/a.
    #[inline(always)]
    fn accel(&self, s1: f64, _rem: f64) -> (f64, f64) {
        let v = (self.v0 * self.v0 + self.a2 * (s1 - self.s0)).sqrt();
        (v, self.t0 + (v - self.v0) * self.inv_a)
    }

    /// Braking to a lower target: v² = v₀² − 2a(s − s₀), t = t₀ + (v₀ − v)/a.
    #[inline(always)]
    fn brake(&self, s1: f64, _rem: f64) -> (f64, f64) {
        let v = (self.v0 * self.v0 - self.a2 * (s1 - self.s0))
            .max(0.0)
            .sqrt();
        (v, self.t0 + (self.v0 - v) * self.inv_a)
    }

    /// Braking for the end: v² = 2a·remaining, t = t₀ + (v₀ − v)/a.
    #[inline(always)]
    fn end(&self, _s1: f64, rem: f64) -> (f64, f64) {
        let v = (self.a2 * rem).sqrt();
        (v, self.t0 + (self.v0 - v) * self.inv_a)
    }

    /// Moves on to the phase that follows the one in force, at its end.
    fn switch(&mut self) {
        let s = self.s_end;
        let (v, t) = match self.phase {
            Phase::Accel if self.next == Phase::Cruise => {
                (self.vt, self.t0 + (self.vt - self.v0) * self.inv_a)
            }
            Phase::Accel => {
                let v = (self.a2 * (self.total - s)).max(0.0).sqrt();
                (v, self.t0 + (v - self.v0) * self.inv_a)
            }
            Phase::Cruise => (self.v0, self.t0 + (s - self.s0) * self.inv_v0),
            Phase::Brake => (self.vt, self.t0 + (self.v0 - self.vt) * self.inv_a),
            Phase::End | Phase::Rest => (0.0, self.t0),
        };
        let t = t.max(self.t);
        if self.next == Phase::Rest {
            // Comes to rest before the next step's end: the last step taken stands.
            self.v = 0.0;
            self.t = t;
        }
        self.begin(self.next, t, v, s);
    }

    /// Takes the step to path position `s1` (`last`: the motion's last step): its time, if it
    /// ends before `h`; else why not (nothing of the step is taken).
    #[inline(always)]
    fn take(&mut self, s1: f64, last: bool, h: f64) -> Result<f64, Progress> {
        loop {
            match self.phase {
                Phase::Rest => {
                    if self.vt <= 0.0 {
                        return Err(Progress::AtRest);
                    }
                    self.v = 0.0;
                    self.anchor();
                }
                Phase::End => break,
                _ if s1 > self.s_end => self.switch(),
                _ => break,
            }
        }
        let rem = if last {
            0.0
        } else {
            (self.total - s1).max(0.0)
        };
        let (v, t) = self.formula(s1, rem);
        let t = if t < self.t { self.t } else { t };
        if t >= h {
            self.pending_t = t;
            return Err(Progress::Pending);
        }
        self.v = if last { 0.0 } else { v };
        self.t = t;
        self.s = s1;
        Ok(t)
    }
}

/// LINE / PCHK state of a linear move (positioning moves use it too).
#[derive(Clone, Debug)]
struct Linear {
    major: usize,
    dir: Axes<i8>,
    /// LB: the major-axis amount.
    lb: i64,
    /// L: each axis amount.
    l: Axes,
    /// ΣLF of each minor axis.
    sigma: Axes,
    minors: [usize; MAX_AXES - 1],
    n_minor: usize,
    steps_left: i64,
    ds: f64,
}

impl Linear {
    /// LINE/PCHK of `delta` pulses: the major axis (the largest amount, the first on a tie)
    /// and the minor axes with their ΣLF at LB.
    fn new(delta: Axes) -> Linear {
        let l = Axes::from_fn(|a| delta[a].abs());
        let mut major = 0;
        for a in 1..MAX_AXES {
            if l[a] > l[major] {
                major = a;
            }
        }
        let mut minors = [0; MAX_AXES - 1];
        let mut n_minor = 0;
        for (a, &la) in l.iter().enumerate() {
            if a != major && la > 0 {
                minors[n_minor] = a;
                n_minor += 1;
            }
        }
        // The path is along X Y Z; rotary axes moving alone are their own path (degrees, their
        // combined turn), as LinuxCNC's feed rule (docs/pulse-core.md, "Axes").
        let xyz = l[0] * l[0] + l[1] * l[1] + l[2] * l[2];
        let len = (if xyz > 0 {
            xyz
        } else {
            l[3] * l[3] + l[4] * l[4] + l[5] * l[5]
        } as f64)
            .sqrt();
        let lb = l[major];
        let ds = if lb > 0 { len / lb as f64 } else { 1.0 };
        let dir = Axes::from_fn(|a| delta[a].signum() as i8);
        Linear {
            major,
            dir,
            lb,
            l,
            sigma: Axes::splat(lb),
            minors,
            n_minor,
            steps_left: lb,
            ds,
        }
    }

    /// One step's pulses at time `tn`: the major axis, and each minor axis whose ΣLF falls to
    /// 0 or below (LB added back). `steps_left` is the caller's.
    #[inline(always)]
    fn pulse(&mut self, out: &mut PulseOut, tn: f64) {
        out.pulse_at(self.major, self.dir[self.major], tn);
        for &a in &self.minors[..self.n_minor] {
            self.sigma[a] -= self.l[a];
            if self.sigma[a] <= 0 {
                self.sigma[a] += self.lb;
                out.pulse_at(a, self.dir[a], tn);
            }
        }
    }
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
    /// The highest path speed the axes allow, pulses/ns (a rotary axis's own rate on a move
    /// that moves it: `axis_limits`); a new target is held to it.
    cap: f64,
    hold: bool,
}

/// The path speed (pulses/ns) and acceleration (pulses/ns²) at which no axis of `delta` moves
/// faster than its rate `rate` or accelerates harder than `accel` (X Y Z A B C, in the same
/// units; infinite: none of its own), on the path `Linear` measures: along X Y Z, or the
/// rotary axes' combined turn when X Y Z stand (LinuxCNC limits each axis so). Infinite for a
/// move of no axis with a limit of its own. One rule for every axis: a rotary axis's since
/// stop 54, a linear axis's since stop 58.
pub fn axis_limits(delta: &Axes, rate: &[f64; MAX_AXES], accel: &[f64; MAX_AXES]) -> (f64, f64) {
    let l = |a: usize| delta[a].unsigned_abs() as f64;
    let xyz = (l(0) * l(0) + l(1) * l(1) + l(2) * l(2)).sqrt();
    let len = if xyz > 0.0 {
        xyz
    } else {
        (l(3) * l(3) + l(4) * l(4) + l(5) * l(5)).sqrt()
    };
    let (mut v, mut a) = (f64::INFINITY, f64::INFINITY);
    for ax in 0..MAX_AXES {
        let d = l(ax);
        if d > 0.0 {
            v = v.min(rate[ax] * len / d);
            a = a.min(accel[ax] * len / d);
        }
    }
    (v, a)
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
    pub fn linear(delta: Axes, speed: f64, accel: f64, t0: u64) -> Motion {
        Motion::linear_within(delta, speed, accel, t0, (f64::INFINITY, f64::INFINITY))
    }

    /// [`Motion::linear`] within `(cap, accel_cap)`: its speed, now and after any override,
    /// and its acceleration held to them ([`axis_limits`]).
    pub fn linear_within(
        delta: Axes,
        speed: f64,
        accel: f64,
        t0: u64,
        (cap, accel_cap): (f64, f64),
    ) -> Motion {
        let ln = Linear::new(delta);
        let total = ln.lb as f64 * ln.ds;
        let speed = speed.min(cap);
        Motion {
            path: Path::Linear(ln),
            prof: Profile::new(speed, accel.min(accel_cap), total, t0),
            target: speed,
            cap,
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
            prof: Profile::new(speed, accel, s, t0),
            target: speed,
            cap: f64::INFINITY,
            hold: false,
        }
    }

    /// Sets the programmed speed (feed × override, at an NCBR tick).
    pub fn set_target(&mut self, speed: f64) {
        let speed = speed.min(self.cap);
        self.target = speed;
        self.prof.vt = if self.hold { 0.0 } else { speed };
        self.prof.anchor();
    }

    /// Feed hold on or off: decelerate to rest, or accelerate back to the target.
    pub fn set_hold(&mut self, hold: bool) {
        self.hold = hold;
        self.prof.vt = if hold { 0.0 } else { self.target };
        self.prof.anchor();
    }

    /// After a rest (feed hold), the next step is timed from `t` on, not from the last pulse
    /// before the rest.
    pub fn resume_at(&mut self, t: u64) {
        if self.prof.v == 0.0 {
            self.prof.t = self.prof.t.max(t as f64);
            self.prof.anchor();
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

    /// After a `run` that returned `Progress::Pending`, with no new target, hold or resume
    /// since: the time (ns) of the step it stopped before. A later `run` takes no step while
    /// its horizon is at or before it (the step's time depends only on the profile's anchor
    /// and the path position, which only a new target, hold or resume changes).
    pub fn pending_step_at(&self) -> Option<f64> {
        (!self.prof.pending_t.is_nan()).then_some(self.prof.pending_t)
    }

    /// Distributes pulses until the motion completes, stands still, or the next step would
    /// fall at or after `horizon`.
    pub fn run(&mut self, horizon: u64, out: &mut PulseOut) -> Progress {
        let h = horizon as f64;
        self.prof.pending_t = f64::NAN;
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
                let tn = match self.prof.take(self.prof.s + ds, *steps_left == 1, h) {
                    Ok(t) => t,
                    Err(p) => return p,
                };
                *s_left -= ds;
                *steps_left -= 1;
                *pending = None;
                if step.dx != 0 {
                    out.pulse_at(0, step.dx, tn);
                }
                if step.dy != 0 {
                    out.pulse_at(1, step.dy, tn);
                }
                if step.dz != 0 {
                    out.pulse_at(2, step.dz, tn);
                }
            },
        }
    }
}

/// Where a [`ThreadMotion`] is anchored on the spindle encoder.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Anchor {
    /// The next index after its start: a thread pass.
    Index,
    /// Where the encoder stands at its start: a rigid tap.
    Here,
    /// The phase where the pass before it ended, at time `t` (its last step), the block
    /// before it being a thread block that goes on (`Tap::Part`): the same groove, with no
    /// wait for an index.
    After {
        /// The encoder phase of the last step of the block before.
        phase: f64,
        /// Its time, ns.
        t: u64,
    },
}

/// A thread pass (G33; docs/pulse-core.md, "Thread passes"): LINE/PCHK stepping whose steps
/// are timed by the spindle encoder instead of a speed ramp. It waits for the next index
/// after its start; major-axis pulse k then falls when the encoder has turned k / lead
/// revolutions past that index (`lead` in major-axis pulses per revolution), the minor axis
/// following by PCHK (a taper). Neither the feed override nor a feed hold acts on it (the
/// machine defers the hold to the end of the pass). Replaces the lathe simulator's
/// `ThreadMove`, which follows the whole encoder counts tick by tick.
#[derive(Clone, Debug)]
pub struct ThreadMotion {
    ln: Linear,
    spindle: Spindle,
    /// `spindle.phase_clock()`, which times every step.
    clock: PhaseClock,
    /// The encoder phase the pass is anchored to: an index (a thread), where the encoder
    /// stood at the start (a rigid tap), or where the pass before it ended (a thread pass of
    /// several blocks: a taper into or out of the groove).
    anchor: f64,
    /// Anchored where the pass before it ended.
    continued: bool,
    /// Encoder counts per major-axis pulse, signed as the spindle turns.
    counts_per_step: f64,
    /// Time of the last step (or of the start), ns.
    t: f64,
}

impl ThreadMotion {
    /// A pass of `delta` pulses at `lead` major-axis pulses per revolution, started at `t0`
    /// with `spindle` turning: anchored to the first index at or after `t0` if `index`, else
    /// to the encoder where it stands at `t0` (a rigid tap, which needs no index).
    pub fn new(delta: Axes, lead: f64, spindle: Spindle, t0: u64, anchor: Anchor) -> ThreadMotion {
        let ln = Linear::new(delta);
        let sign = if spindle.target() < 0.0 { -1.0 } else { 1.0 };
        let counts_per_step = if lead > 0.0 {
            sign * f64::from(spindle.lines()) / lead
        } else {
            0.0
        };
        let (anchor, continued, t) = match anchor {
            // Where the pass before ended, its steps timed from its last one's time on (the
            // block itself starts at the next NCBR tick), so the groove goes on as one helix.
            Anchor::After { phase, t } => (phase, true, t.min(t0) as f64),
            Anchor::Index => (spindle.next_index(t0) as f64, false, t0 as f64),
            Anchor::Here => (spindle.phase_at(t0), false, t0 as f64),
        };
        ThreadMotion {
            ln,
            anchor,
            continued,
            clock: spindle.phase_clock(),
            spindle,
            counts_per_step,
            t,
        }
    }

    /// Whether the pass goes on from the one before it (`Anchor::After`), not from an index.
    pub fn continued(&self) -> bool {
        self.continued
    }

    /// The encoder phase of its last step: where a pass that goes on in the next block
    /// anchors it.
    pub fn end_phase(&self) -> f64 {
        self.anchor + self.ln.lb as f64 * self.counts_per_step
    }

    /// The encoder phase the pass is anchored to (an index: a whole number of revolutions).
    pub fn anchor(&self) -> f64 {
        self.anchor
    }

    /// When the encoder reaches the anchor (the pass's index), ns, and the encoder count at
    /// the pass's first step (|count|: a spindle in reverse counts down).
    pub fn index_and_first_count(&self) -> (u64, u64) {
        let at = |phase: f64| {
            self.spindle
                .time_at_phase(phase)
                .unwrap_or(self.t)
                .max(self.t)
        };
        let t_index = at(self.anchor);
        let first = at(self.anchor + self.counts_per_step);
        let count = self.spindle.phase_at(first as u64).floor().abs();
        (t_index as u64, count as u64)
    }

    /// The spindle changed its target (at an NCBR tick): the steps not yet taken follow it.
    pub fn set_spindle(&mut self, spindle: &Spindle) {
        self.spindle = spindle.clone();
        self.clock = spindle.phase_clock();
    }

    /// Distributes the steps whose encoder time falls before `horizon`.
    pub fn run(&mut self, horizon: u64, out: &mut PulseOut) -> Progress {
        let h = horizon as f64;
        while self.ln.steps_left > 0 {
            let k = self.ln.lb - self.ln.steps_left + 1;
            let phase = self.anchor + k as f64 * self.counts_per_step;
            let Some(t) = self.clock.time_at_phase(phase) else {
                return Progress::Pending;
            };
            let t = t.max(self.t);
            if t >= h {
                return Progress::Pending;
            }
            self.t = t;
            self.ln.steps_left -= 1;
            self.ln.pulse(out, t);
        }
        Progress::Done
    }

    /// Time of the last step, ns.
    pub fn last_t(&self) -> u64 {
        self.t as u64
    }

    /// Path speed now, mm/min: the lead's share of the spindle speed.
    pub fn speed_mm_min(&self, pulse_mm: f64) -> f64 {
        if self.ln.steps_left == 0 || self.counts_per_step == 0.0 {
            return 0.0;
        }
        let rev_per_min = self.spindle.rpm_at(self.t as u64).abs();
        let steps_per_min =
            rev_per_min * f64::from(self.spindle.lines()) / self.counts_per_step.abs();
        steps_per_min * self.ln.ds * pulse_mm
    }
}

/// Takes the steps of `ln` that lie in the phase in force (all but the last step of the
/// motion), timed by `f` (which must be that phase's `Profile::formula`). Whether it stopped at
/// the horizon.
#[inline(always)]
fn phase_run(
    ln: &mut Linear,
    prof: &mut Profile,
    h: f64,
    out: &mut PulseOut,
    f: impl Fn(&Profile, f64, f64) -> (f64, f64),
) -> bool {
    let (ds, lb) = (ln.ds, ln.lb);
    let (mut left, mut t, mut v) = (ln.steps_left, prof.t, prof.v);
    let (end, total) = (prof.s_end, prof.total);
    let mut pending = false;
    while left > 1 {
        let nl = left - 1;
        let s1 = (lb - nl) as f64 * ds;
        if s1 > end {
            break;
        }
        let (vn, tn) = f(prof, s1, (total - s1).max(0.0));
        let tn = if tn < t { t } else { tn };
        if tn >= h {
            pending = true;
            prof.pending_t = tn;
            break;
        }
        left = nl;
        t = tn;
        v = vn;
        ln.pulse(out, tn);
    }
    if left != ln.steps_left {
        prof.s = (lb - left) as f64 * ds;
        prof.t = t;
        prof.v = v;
        ln.steps_left = left;
    }
    pending
}

/// LINE: the major axis gets a pulse every step; PCHK gives each minor axis a pulse when its
/// ΣLF (starting at LB, less L each step) falls to 0 or below, and adds LB back.
#[inline(always)]
fn run_linear(ln: &mut Linear, prof: &mut Profile, h: f64, out: &mut PulseOut) -> Progress {
    let ds = ln.ds;
    let lb = ln.lb;
    loop {
        if ln.steps_left == 0 {
            return Progress::Done;
        }
        // Many steps of one phase: the same formula as `Profile::take`, one loop per phase.
        let pending = match prof.phase {
            Phase::Cruise => phase_run(ln, prof, h, out, Profile::cruise),
            Phase::Accel => phase_run(ln, prof, h, out, Profile::accel),
            Phase::End => phase_run(ln, prof, h, out, Profile::end),
            Phase::Brake => phase_run(ln, prof, h, out, Profile::brake),
            Phase::Rest => false,
        };
        if pending {
            return Progress::Pending;
        }
        let left = ln.steps_left - 1;
        let s1 = (lb - left) as f64 * ds;
        let tn = match prof.take(s1, left == 0, h) {
            Ok(t) => t,
            Err(p) => return p,
        };
        ln.steps_left = left;
        ln.pulse(out, tn);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_kt_ramp_is_constant_acceleration_and_ends_at_rest() {
        let a = accel_pulses_ns2(1000.0, 0.001);
        let fast = speed_pulses_ns(1e9, 0.001); // never reached in 20,000 pulses
        let mut m = Motion::linear([20_000, 0, 0].into(), fast, a, 0);
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
        let mut m = Motion::linear([0, 50_000, -20_000].into(), v, a, 0);
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
