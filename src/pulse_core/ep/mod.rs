//! The error-proportional interpolator of seed 001 (Pratt & Whitney), beside the DDA: one
//! motion's pulse trains, each axis at f_a · E_axis / (E_m + L), where f_a is the rate at
//! which the feed-rate regulator opens the error gates, E_axis the axis's remaining error
//! (commanded end less interpolated position), E_m the largest and L the constant of adder
//! 100. All axes reach their end at once; near the end the gates open every cycle and the
//! motion decays exponentially (time constant L / f_r) onto the exact end point.
//!
//! Machine time is simulated cycle by cycle (`EP_CYCLE_NS`), a pulse carrying the time of its
//! recirculation cycle. Arcs run the registers as the patent draws them (`run_cycles`). Lines
//! run them in a fast form that does work only where a gate opens and jumps the tail to the
//! next pulse (`run_line`), with the very same pulses at the very same times (tested against
//! `run_cycles`, `the_fast_line_form_changes_no_pulse`). Both jump in closed form over shut
//! cycles while the feed-rate counter fills to stage 6. docs/pulse-core.md, "The
//! error-proportional interpolator".

pub mod arc;
pub mod registers;

use self::arc::ArcPlan;
use self::registers::{rank, FeedCounter, ResidueRegister};
use super::motion::Progress;
use super::pulse_out::PulseOut;
use crate::settings::EP_CYCLE_NS;

/// Fixed point of the feed-rate pulse accumulator: 32 fraction bits.
const FRAC: u32 = 32;
const MASK: u64 = (1 << FRAC) - 1;

/// One motion distributed by the error-proportional interpolator.
#[derive(Clone, Debug)]
pub struct EpMotion {
    /// Remaining error of each axis, pulses (comparators 57–59: commanded less interpolated).
    e: [i64; 3],
    /// Recirculation circuits 98x, 98y, 98z.
    reg: [ResidueRegister; 3],
    /// Feed-rate counter 81 and iteration memory 87.
    counter: FeedCounter,
    /// L, pulses.
    l: i64,
    /// L + E_m in force.
    c: i64,
    /// Each axis's rank by error magnitude (0 = G, 1 = M, 2 = S): its counting weight.
    rank_of: [usize; 3],
    /// The axes in rank order.
    order: [usize; 3],
    /// Time of the next recirculation cycle, ns, and its number (the gate's phase).
    next_t: u64,
    cycle: u64,
    /// Feed-rate pulses: accumulator and increment per cycle (32 fraction bits), and the
    /// increment of the programmed feed (`inc` is 0 in a hold).
    acc: u64,
    inc: u64,
    target_inc: u64,
    /// Programmed path speed, pulses/ns.
    target: f64,
    hold: bool,
    resting: bool,
    last_t: u64,
    /// An arc: the chord and perpendicular method (`arc.rs`).
    arc: Option<Box<ArcPlan>>,
    /// The registers of an arc count in 1/2¹⁶ pulse (their constant is (L + E_m) · 2¹⁶).
    shift: u32,
    /// Closed-form jumps on (off only to test that they change nothing).
    jumps: bool,
    /// An arc: each axis's last pulse direction (0 after it turned round).
    arc_dir: [i8; 3],
    /// A line: the axes whose register left the band upward in the last cycle, so that the
    /// pulse detector 101 sent their pulse at once; the pulse the next cycle's two equal signs
    /// make is that one, not another (`ResidueRegister` is the hardware; docs/pulse-core.md,
    /// "Path accuracy").
    owed: u8,
    /// A line, the fast form of the registers (`run_line`): each axis's residue as the fraction
    /// u in [0, L + E_m) that a shut cycle's swing leaves unchanged, and the sign memories as
    /// bits relative to the cycle's parity (sign 99 = bit XOR the parity of `cycle`).
    u: [i64; 3],
    sign_bits: u8,
}

/// Feed-rate pulses per cycle, fixed point, for a path speed in pulses/ns.
fn inc_of(speed: f64) -> u64 {
    let per_cycle = (speed * EP_CYCLE_NS as f64).max(0.0);
    (per_cycle * (1u64 << FRAC) as f64) as u64
}

impl EpMotion {
    /// A motion of `delta` pulses at the path speed `speed` (pulses/ns), with the constant
    /// `l` (pulses, at least 1), its first recirculation cycle at `t0`.
    pub fn linear(delta: [i64; 3], speed: f64, l: i64, t0: u64) -> EpMotion {
        let l = l.max(1);
        let em = delta.iter().map(|d| d.abs()).max().unwrap_or(0);
        let c = l + em;
        let mut m = EpMotion {
            e: delta,
            // The residues start half way, so the quantisation is centred on the path.
            reg: [ResidueRegister::new(c / 2); 3],
            counter: FeedCounter::default(),
            l,
            c,
            rank_of: [0; 3],
            order: [0; 3],
            next_t: t0,
            cycle: 0,
            acc: 0,
            inc: 0,
            target_inc: 0,
            target: speed,
            hold: false,
            resting: false,
            last_t: t0,
            arc: None,
            shift: 0,
            jumps: true,
            arc_dir: [0; 3],
            owed: 0,
            u: [c / 2; 3],
            // Every memory 99 set (RR = C/2 ≥ 0) before cycle 0, whose parity is 0.
            sign_bits: 0b111,
        };
        m.rerank();
        m.set_target(speed);
        m
    }

    /// An arc in its plane by `plan`, from `pos`, at the path speed `speed` (pulses/ns).
    pub fn arc(plan: ArcPlan, pos: [i64; 3], speed: f64, l: i64, t0: u64) -> EpMotion {
        let t = plan.target();
        let mut delta = [0i64; 3];
        delta[plan.axes[0]] = t[0] - pos[plan.axes[0]];
        delta[plan.axes[1]] = t[1] - pos[plan.axes[1]];
        if let (Some(n), Some(z)) = (plan.normal_axis(), plan.normal_target()) {
            delta[n] = z - pos[n];
        }
        let mut m = EpMotion::linear(delta, speed, l, t0);
        m.arc = Some(Box::new(plan));
        m.shift = arc::SHIFT;
        m.reg = [ResidueRegister::new((m.c << arc::SHIFT) / 2); 3];
        m.rank_of = [0; 3];
        m.rerank();
        m
    }

    /// Comparator 93, with one pulse of hysteresis: the ranks change only when an axis's
    /// error exceeds that of an axis ranked above it by more than one pulse. Without it, axes
    /// with equal errors swap ranks at every pulse (one pulses a cycle before the other) and
    /// the counter is charged G's weight twice: a line at 45° in three axes ran 17 % slow.
    #[inline(always)]
    fn rerank(&mut self) {
        let mag = match &self.arc {
            None => [self.e[0].abs(), self.e[1].abs(), self.e[2].abs()],
            Some(a) => {
                let sp = a.speeds([self.e[a.axes[0]], self.e[a.axes[1]]]);
                let mut m = [0; 3];
                m[a.axes[0]] = sp[0];
                m[a.axes[1]] = sp[1];
                if let Some(n) = a.normal_axis() {
                    m[n] = sp[2];
                }
                m
            }
        };
        let o = self.order;
        if self.rank_of == [0, 0, 0] || mag[o[1]] > mag[o[0]] + 1 || mag[o[2]] > mag[o[1]] + 1 {
            self.order = rank(mag);
            for (i, &a) in self.order.iter().enumerate() {
                self.rank_of[a] = i;
            }
        }
    }

    /// Sets the programmed path speed (feed × override, at an NCBR tick), pulses/ns.
    pub fn set_target(&mut self, speed: f64) {
        self.target = speed;
        self.target_inc = inc_of(speed);
        if !self.hold {
            self.inc = self.target_inc;
            if self.inc > 0 {
                self.resting = false;
            }
        }
    }

    /// Feed hold on or off: the gates freeze (no gate opens, the feed-rate pulses stop); a
    /// pulse already decided by the last gate still comes out.
    pub fn set_hold(&mut self, hold: bool) {
        self.hold = hold;
        self.inc = if hold { 0 } else { self.target_inc };
        if !hold && self.inc > 0 {
            self.resting = false;
        }
    }

    /// After a rest, the next cycle is at `t` or later.
    pub fn resume_at(&mut self, t: u64) {
        self.next_t = self.next_t.max(t);
    }

    /// Whether a feed hold is in force.
    pub fn is_held(&self) -> bool {
        self.hold
    }

    /// Standing still mid-motion (feed hold, or override 0 with the counter run down).
    pub fn at_rest(&self) -> bool {
        self.resting
    }

    /// Time of the last pulse (or of the rest), ns.
    pub fn last_t(&self) -> u64 {
        self.last_t
    }

    /// The remaining errors, pulses.
    pub fn errors(&self) -> [i64; 3] {
        self.e
    }

    /// Commanded path speed, pulses/ns: the programmed feed while the regulator governs,
    /// f_r · |E| / (E_m + L) once the gates open every cycle; 0 at rest.
    pub fn speed(&self) -> f64 {
        if self.resting || self.hold || self.e == [0; 3] {
            return 0.0;
        }
        let n = self.e.iter().map(|&v| (v * v) as f64).sum::<f64>().sqrt();
        let sat = n / self.c as f64 / EP_CYCLE_NS as f64;
        sat.min(self.target)
    }

    /// Path speed, mm/min.
    pub fn speed_mm_min(&self, pulse_mm: f64) -> f64 {
        self.speed() * 1e9 * 60.0 * pulse_mm
    }

    /// With the counter below stage 6 and a feed (`inc` > 0): the cycles before the one whose
    /// feed-rate pulse brings it to stage 6, all with the gates shut.
    fn shut_cycles_before_stage_6(&self) -> u64 {
        let n = (32 - self.counter.k) as u64;
        let pulses = n.div_ceil(registers::W_FEED as u64);
        let need = (pulses << FRAC).saturating_sub(self.acc);
        need.div_ceil(self.inc).max(1) - 1
    }

    /// Jumps `skip` cycles in which no gate opened and no register pulsed: their feed-rate
    /// pulses counted at once, the clock and the gate's phase moved on.
    fn skip(&mut self, skip: u64) {
        if skip > 0 {
            let total = self.acc as u128 + self.inc as u128 * skip as u128;
            self.counter.feed((total >> FRAC).min(64) as u64);
            self.acc = (total as u64) & MASK;
            self.cycle = self.cycle.wrapping_add(skip);
            self.next_t += skip * EP_CYCLE_NS;
        }
    }

    /// No gate can open: a feed hold, or override 0 with the counter run down below stage 6.
    #[inline(always)]
    fn frozen(&self) -> bool {
        self.hold || (self.inc == 0 && self.counter.k < 32)
    }

    /// One cycle's feed-rate pulses into the counter.
    #[inline(always)]
    fn feed_cycle(&mut self) {
        self.acc += self.inc;
        let n = self.acc >> FRAC;
        if n <= 1 {
            // The usual feed (below f_r): at most one feed-rate pulse, counted without a
            // branch (they come as good as at random against the gate's phase).
            self.counter.k += registers::W_FEED * (n as i32) * (self.counter.k < 240) as i32;
        } else {
            self.counter.feed(n);
        }
        self.acc &= MASK;
    }

    #[inline(always)]
    fn all_in_band(&self) -> bool {
        let c = self.c << self.shift;
        // Without short circuits: three compares, one branch.
        self.reg[0].in_band(c) & self.reg[1].in_band(c) & self.reg[2].in_band(c)
    }

    /// Distributes pulses until the motion completes, stands still, or the next cycle falls
    /// at or after `horizon`.
    pub fn run(&mut self, horizon: u64, out: &mut PulseOut) -> Progress {
        if self.arc.is_none() && self.jumps {
            self.run_line(horizon, out)
        } else {
            self.run_cycles(horizon, out)
        }
    }

    /// The registers as the patent draws them (`ResidueRegister`), one recirculation cycle at
    /// a time: every arc, and a line with the jumps off (the reference `run_line` is tested
    /// against). Arcs jump only over shut cycles.
    fn run_cycles(&mut self, horizon: u64, out: &mut PulseOut) -> Progress {
        const T: u64 = EP_CYCLE_NS;
        if self.e == [0; 3] {
            return Progress::Done;
        }
        loop {
            if self.next_t >= horizon {
                return Progress::Pending;
            }
            let frozen = self.frozen();
            let in_band = self.all_in_band();
            if frozen && in_band {
                self.resting = true;
                return Progress::AtRest;
            }
            if !frozen && in_band && self.jumps {
                // Cycles before the horizon after this one, computed only where a jump
                // needs it (the every-second-cycle regime checks with one multiply).
                let room = |next_t: u64| (horizon - next_t - 1) / T;
                let skip = if self.counter.k >= 128 {
                    // Gates every cycle: an arc's tangent turns at each pulse, nothing to jump.
                    0
                } else if self.counter.k < 32 {
                    let s = self.shut_cycles_before_stage_6().min(room(self.next_t));
                    for a in 0..3 {
                        self.reg[a].swing(s, self.c << self.shift);
                    }
                    s
                } else {
                    // Gates every second or fourth cycle: the shut cycles before the next
                    // open one, unless a feed-rate pulse arrives among them.
                    let d = if self.counter.k >= 64 {
                        self.cycle & 1
                    } else {
                        (4 - (self.cycle & 3)) & 3
                    };
                    // Feed-rate pulses arriving among them are counted in one go, as long as
                    // they leave the gate's rate as it is (the count stays below the next
                    // stage that opens the gate more often).
                    let s = if self.next_t + d * T < horizon {
                        d
                    } else {
                        room(self.next_t)
                    };
                    let next_stage = if self.counter.k >= 64 { 128 } else { 64 };
                    let n = (self.acc + s * self.inc) >> FRAC;
                    if s > 0 && self.counter.k + registers::W_FEED * (n as i32) < next_stage {
                        for a in 0..3 {
                            self.reg[a].swing(s, self.c << self.shift);
                        }
                        s
                    } else {
                        0
                    }
                };
                self.skip(skip);
            }
            // One recirculation cycle.
            let t = self.next_t;
            self.feed_cycle();
            let gate = !self.hold && self.counter.gate(self.cycle);
            let c = self.c;
            let mut any = false;
            if let Some(arc) = &mut self.arc {
                // The tangent E + A, A = E turned outward · E_m / 2h_n, into signed registers
                // counting in 1/2¹⁶ pulse.
                let [u, v] = arc.axes;
                let n = 3 - u - v;
                let g = if gate {
                    arc.gated([self.e[u], self.e[v], self.e[n]], c)
                } else {
                    [0, 0, 0]
                };
                for (a, ga) in [(u, g[0]), (v, g[1]), (n, g[2])] {
                    // An axis turning round (its share now against its last pulse): the
                    // register after a pulse one way stands at the edge of the band for the
                    // other way, and would chatter; it keeps its place in the band, but no
                    // nearer than a quarter pulse to the edge the new way
                    // (`ResidueRegister::turned`).
                    let bit = 1u8 << a;
                    let cc = c << arc::SHIFT;
                    if ga.signum() as i8 == -self.arc_dir[a] && ga != 0 {
                        self.reg[a] = self.reg[a].turned(cc, ga.signum());
                        self.arc_dir[a] = 0;
                        // A pulse sent early stands: the register goes on after it.
                        self.owed &= !bit;
                    }
                    let mut p = self.reg[a].cycle(ga, cc);
                    if self.owed & bit != 0 {
                        // The two equal signs of a number that left the band: the pulse that
                        // already went out.
                        self.owed &= !bit;
                        if p == 0 {
                            // Not confirmed (cannot happen without a turn, which resets).
                            self.reg[a] = ResidueRegister::new(cc / 2);
                        }
                        p = 0;
                    }
                    if p == 0 {
                        // The number left the band: the pulse goes out now, as on a line.
                        let r = self.reg[a];
                        if r.positive && r.rr >= cc {
                            p = 1;
                            self.owed |= bit;
                        } else if !r.positive && r.rr < -cc {
                            p = -1;
                            self.owed |= bit;
                        }
                    }
                    if p != 0 {
                        self.arc_dir[a] = p;
                        self.e[a] -= p as i64;
                        out.pulse_at_ns(a, p, t);
                        self.counter.command(self.rank_of[a]);
                        any = true;
                    }
                }
                if any {
                    let e2 = [self.e[u], self.e[v]];
                    if e2 == [0, 0] || e2[0] * e2[0] + e2[1] * e2[1] < arc.switch2() {
                        if let Some(d) = arc.advance() {
                            self.e[u] += d[0];
                            self.e[v] += d[1];
                            self.e[n] += d[2];
                        }
                    }
                }
            } else {
                for a in 0..3 {
                    // The register works on the error's magnitude; the pulse goes the error's way.
                    let ea = self.e[a];
                    let g = if gate { ea.abs() } else { 0 };
                    let dir = if ea < 0 { -1 } else { 1 };
                    let bit = 1u8 << a;
                    let mut p = self.reg[a].cycle(g, c) * dir;
                    if self.owed & bit != 0 {
                        // Two equal signs after a number that left the band: the pulse that
                        // already went out.
                        self.owed &= !bit;
                        p = 0;
                    }
                    if p == 0 && self.reg[a].positive && self.reg[a].rr >= c {
                        // The number left the band upward: the next cycle is certain to end
                        // with the same sign (it subtracts at most L + E_m and adds a gated
                        // error ≥ 0), so the detector sends the pulse now.
                        self.owed |= bit;
                        p = dir;
                    }
                    if p != 0 {
                        self.e[a] -= p as i64;
                        out.pulse_at_ns(a, p, t);
                        self.counter.command(self.rank_of[a]);
                        any = true;
                    }
                }
            }
            self.cycle = self.cycle.wrapping_add(1);
            self.next_t += T;
            if any {
                self.last_t = t;
                let em = self.e[0].abs().max(self.e[1].abs()).max(self.e[2].abs());
                let c1 = self.l + em;
                if c1 < c {
                    for r in &mut self.reg {
                        r.clamp(c << self.shift, c1 << self.shift);
                    }
                } else if c1 > c {
                    // An arc's commanded point moved on: E_m grew.
                    for r in &mut self.reg {
                        r.rescale(c << self.shift, c1 << self.shift);
                    }
                }
                self.c = c1;
                if em == 0 {
                    return Progress::Done;
                }
                self.rerank();
            } else if self.hold {
                self.last_t = self.last_t.max(t);
            }
        }
    }
}

impl EpMotion {
    /// A line, with the registers in their fast form: the same pulses at the same times as
    /// `run_cycles` (tested, `the_fast_line_form_changes_no_pulse`), with the work done only
    /// in the cycles where a gate opens.
    ///
    /// In a cycle with the gate shut a register in the band only swings round zero: RR ≥ 0
    /// becomes RR − C and RR < 0 becomes RR + C. So u = RR after a positive end and RR + C
    /// after a negative one does not change, and the sign memory flips; kept relative to the
    /// cycle's parity, the flip is no work either. A gate adds the error to u; the number
    /// leaves the band (a pulse, at once or owed) exactly when u reaches C, and u then drops
    /// by C. What the signs still decide is the clamp when E_m falls (`ResidueRegister::clamp`):
    /// after a positive end u is capped at the new C − 1, after a negative end it drops by the
    /// fall (RR stays, the next swing adds the smaller C), and an owed number gains the fall
    /// (the next cycle subtracts the smaller C).
    fn run_line(&mut self, horizon: u64, out: &mut PulseOut) -> Progress {
        const T: u64 = EP_CYCLE_NS;
        if self.e == [0; 3] {
            return Progress::Done;
        }
        loop {
            if self.next_t >= horizon {
                return Progress::Pending;
            }
            let frozen = self.frozen();
            if self.owed == 0 {
                if frozen {
                    self.resting = true;
                    return Progress::AtRest;
                }
                let room = |next_t: u64| (horizon - next_t - 1) / T;
                let c = self.c;
                let skip = if self.counter.k >= 128 {
                    // Gates every cycle (the counter only rises without a pulse): the cycles
                    // before the first register reaches C, if no register does next cycle.
                    let mag = [self.e[0].abs(), self.e[1].abs(), self.e[2].abs()];
                    let soon = (0..3).any(|a| self.u[a] + mag[a] >= c);
                    if soon {
                        0
                    } else {
                        let m = (0..3)
                            .filter(|&a| mag[a] > 0)
                            .map(|a| ((c - self.u[a]) as u64).div_ceil(mag[a] as u64))
                            .min()
                            .unwrap_or(u64::MAX);
                        let s = (m - 1).min(room(self.next_t));
                        for (u, m) in self.u.iter_mut().zip(mag) {
                            *u += m * s as i64;
                        }
                        s
                    }
                } else if self.counter.k < 32 {
                    self.shut_cycles_before_stage_6().min(room(self.next_t))
                } else {
                    0
                };
                self.skip(skip);
            }
            // One recirculation cycle.
            let t = self.next_t;
            self.feed_cycle();
            let gate = !self.hold && self.counter.gate(self.cycle);
            if gate || self.owed != 0 {
                let c = self.c;
                // Sign memories at the end of the last cycle; "positive and in the band".
                let parity = if self.cycle & 1 == 1 { 0b111 } else { 0 };
                let strict = (self.sign_bits ^ parity) & !self.owed & 0b111;
                let mut pulses = 0u8;
                for a in 0..3 {
                    let g = if gate { self.e[a].abs() } else { 0 };
                    let u = self.u[a] + g;
                    let p = u >= c;
                    self.u[a] = if p { u - c } else { u };
                    pulses |= (p as u8) << a;
                }
                // A positive end stays positive (no flip) after an owed number, or after a
                // pulse at once; a number that left the band from a negative end, or again
                // from an owed one, is owed.
                self.sign_bits ^= self.owed | (strict & pulses);
                self.owed = pulses & !strict;
                if pulses != 0 {
                    for a in 0..3 {
                        if pulses & (1 << a) != 0 {
                            let dir: i8 = if self.e[a] < 0 { -1 } else { 1 };
                            self.e[a] -= dir as i64;
                            out.pulse_at_ns(a, dir, t);
                            self.counter.command(self.rank_of[a]);
                        }
                    }
                    self.last_t = t;
                    let em = self.e[0].abs().max(self.e[1].abs()).max(self.e[2].abs());
                    let c1 = self.l + em;
                    if c1 < c {
                        let fall = c - c1;
                        let strict = (self.sign_bits ^ !parity) & !self.owed & 0b111;
                        for a in 0..3 {
                            let bit = 1u8 << a;
                            self.u[a] = if self.owed & bit != 0 {
                                self.u[a] + fall
                            } else if strict & bit != 0 {
                                self.u[a].min(c1 - 1)
                            } else {
                                (self.u[a] - fall).max(0)
                            };
                        }
                    }
                    self.c = c1;
                    self.cycle = self.cycle.wrapping_add(1);
                    self.next_t += T;
                    if em == 0 {
                        return Progress::Done;
                    }
                    self.rerank();
                    continue;
                }
            }
            if self.hold {
                self.last_t = self.last_t.max(t);
            }
            self.cycle = self.cycle.wrapping_add(1);
            self.next_t += T;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pulse_core::motion::speed_pulses_ns;

    fn run_all(m: &mut EpMotion) -> Vec<crate::pulse_core::PulseRec> {
        let mut out = PulseOut::default();
        out.set_log(None, true);
        assert_eq!(m.run(u64::MAX, &mut out), Progress::Done);
        out.take_capture()
    }

    #[test]
    fn a_line_ends_exactly_with_every_axis_together() {
        let v = speed_pulses_ns(1000.0, 0.001);
        let mut m = EpMotion::linear([20_000, -7_000, 3_001], v, 30_000, 0);
        let p = run_all(&mut m);
        let mut pos = [0i64; 3];
        for r in &p {
            pos[r.axis as usize] += r.dir as i64;
        }
        assert_eq!(pos, [20_000, -7_000, 3_001]);
        assert_eq!(p.len(), 30_001);
        // The last pulses of every axis are in the tail, close to each other in time.
        let last = |a: u8| p.iter().rev().find(|r| r.axis == a).unwrap().t_ns;
        let end = last(0).max(last(1)).max(last(2));
        assert!(
            end - last(1) < end / 5,
            "{} {} {}",
            last(0),
            last(1),
            last(2)
        );
    }

    /// The fast form of a line's registers (`run_line`) gives exactly the pulses, at exactly
    /// the times, of the registers as the patent draws them cycle by cycle (`run_cycles`),
    /// through random horizons, holds, resumes and feed changes (override, down to 0), with L
    /// from 1 pulse up.
    #[test]
    fn the_fast_line_form_changes_no_pulse() {
        let mut rng = crate::pulse_core::testkit::Rng::new(11);
        for case in 0..300 {
            let feed = [20.0, 300.0, 2000.0, 10_000.0, 12_000.0][case % 5];
            // Long lines at the fast feeds (the literal registers take every cycle).
            let big = [50, 3_000, 40_000][case % 3].min(if feed < 1000.0 { 3_000 } else { 40_000 });
            let mut delta = [0i64; 3];
            while delta == [0; 3] {
                for d in &mut delta {
                    *d = if rng.range(0, 3) == 0 {
                        0
                    } else {
                        rng.range(-big, big)
                    };
                }
            }
            let l = [1, 2, 3, 100, 2_000, 30_000][case % 6];
            let v = speed_pulses_ns(feed, 0.001);
            let mut fast = EpMotion::linear(delta, v, l, 0);
            let mut slow = fast.clone();
            slow.jumps = false;
            let (mut of, mut os) = (PulseOut::default(), PulseOut::default());
            of.set_log(None, true);
            os.set_log(None, true);
            let mut horizon = 0u64;
            for step in 0..400 {
                horizon += rng.range(1, 2_000_000) as u64;
                let (pf, ps) = (fast.run(horizon, &mut of), slow.run(horizon, &mut os));
                assert_eq!(pf, ps, "case {case} step {step}: {delta:?} F{feed} L {l}");
                assert_eq!(
                    of.take_capture(),
                    os.take_capture(),
                    "case {case} step {step}"
                );
                assert_eq!(fast.errors(), slow.errors());
                if pf == Progress::Done {
                    break;
                }
                match rng.range(0, 9) {
                    0 => {
                        let h = !fast.is_held();
                        fast.set_hold(h);
                        slow.set_hold(h);
                    }
                    1 => {
                        let k = [0.0, 0.3, 1.0, 1.2][rng.range(0, 3) as usize];
                        fast.set_target(v * k);
                        slow.set_target(v * k);
                    }
                    _ => {}
                }
                if pf == Progress::AtRest {
                    fast.set_hold(false);
                    slow.set_hold(false);
                    fast.set_target(v);
                    slow.set_target(v);
                    fast.resume_at(horizon);
                    slow.resume_at(horizon);
                }
            }
            for m in [&mut fast, &mut slow] {
                m.set_hold(false);
                m.set_target(v);
                m.resume_at(horizon);
            }
            assert_eq!(
                fast.run(u64::MAX, &mut of),
                slow.run(u64::MAX, &mut os),
                "case {case}"
            );
            assert_eq!(
                of.take_capture(),
                os.take_capture(),
                "case {case} to the end"
            );
            assert_eq!(of.pos, delta, "case {case}: the end exact");
            assert_eq!(os.pos, delta);
        }
    }

    #[test]
    fn a_hold_freezes_and_a_resume_loses_no_pulse() {
        let v = speed_pulses_ns(3000.0, 0.001);
        let mut m = EpMotion::linear([0, 50_000, -20_000], v, 30_000, 0);
        let mut out = PulseOut::default();
        assert_eq!(m.run(200_000_000, &mut out), Progress::Pending);
        m.set_hold(true);
        assert_eq!(m.run(u64::MAX, &mut out), Progress::AtRest);
        let held = out.pos;
        assert!(held[1] > 0 && held[1] < 50_000);
        assert!(m.at_rest());
        m.set_hold(false);
        m.resume_at(1_000_000_000);
        assert_eq!(m.run(u64::MAX, &mut out), Progress::Done);
        assert_eq!(out.pos, [0, 50_000, -20_000]);
        assert_eq!(out.count, [0, 50_000, 20_000]);
    }
}
