//! The canonical moves the interpreter produces (machine millimetres, absolute), and their
//! conversion into machine instruction blocks in pulses with the travel check
//! (docs/gcode.md "The listing").

pub use crate::block::Io;
use crate::block::{Axes, Block, Motion, Plane, Tap, TranslateError};
use crate::settings::MachineSettings;

/// One canonical action, in machine coordinates (mm): where the spindle's gauge line goes.
#[derive(Clone, Debug, PartialEq)]
pub enum Canon {
    /// G00 to a point.
    Rapid([f64; 3]),
    /// G01 to a point at a feed, mm/min.
    Feed([f64; 3], f64),
    /// G33: a straight thread pass to the point, geared to the spindle's encoder at this lead,
    /// mm per revolution (docs/pulse-core.md "Thread passes (G33)").
    Thread([f64; 3], f64),
    /// G02/G03 to `end` about `centre` (absolute, mm; its normal coordinate unused).
    Arc {
        /// End point.
        end: [f64; 3],
        /// Centre.
        centre: [f64; 3],
        /// Plane.
        plane: Plane,
        /// G03.
        ccw: bool,
        /// Feed, mm/min.
        feed: f64,
    },
    /// G00 (`feed` None) or G01 at `feed` mm/min (deg/min for rotary axes alone) to `end` with
    /// the rotary axes A, B and C to `abc` degrees (docs/gcode.md "Rotary axes"; an axis the
    /// machine has not stays 0).
    Turn {
        /// End point X Y Z.
        end: [f64; 3],
        /// A, B and C, degrees (machine).
        abc: [f64; 3],
        /// Feed of a G01.
        feed: Option<f64>,
    },
    /// G04 for seconds.
    Dwell(f64),
    /// A probe move (G38.2 … G38.5 ×10) to a point at a feed; it ends where the probe
    /// tripped (the interpreter has asked the machine where).
    Probe([f64; 3], f64, u16),
    /// An input or output action.
    Io(Io),
    /// Marks the blocks that follow as a tap's (`Tap::Part`), the next one as its last
    /// (`Tap::End`), or none (`Tap::No`); makes no block.
    Tap(Tap),
    /// Nothing to do but answer with the machine's clocks when reached (a Fanuc #3001/#3002
    /// read in a run, `Block::clocks`).
    Clocks,
    /// S, T and M functions.
    Aux {
        /// Spindle speed.
        s: Option<u32>,
        /// T code.
        t: Option<u32>,
        /// M code.
        m: Option<u8>,
    },
}

/// Turns canonical actions into blocks: positions in whole pulses, `delta` the exact
/// difference of consecutive ends, sequence numbers counted on.
pub struct Emitter {
    /// Machine position, pulses, after the last block.
    pub pos: Axes,
    /// The last sequence number.
    pub seq: u32,
    /// What the blocks made now belong to (a tap's, [`Canon::Tap`]).
    pub tap: Tap,
    /// The travel limits in pulses and the settings they were worked out from: worked out
    /// again only when those change (six roundings a line otherwise).
    limits: Option<(Travel, [(i64, i64); 3])>,
}

/// `st.travel_pulses` for the three axes. Not inlined: the compiler would work the six
/// roundings out for every call of `emit`, before it looks whether they are needed (an arc
/// needs them).
#[cold]
#[inline(never)]
fn travel_pulses(st: &MachineSettings) -> [(i64, i64); 3] {
    [0, 1, 2].map(|a| st.travel_pulses(a))
}

/// What the travel limits in pulses are worked out from: the pulse and the limits in mm.
type Travel = (f64, Axes<f64>, Axes<f64>);

impl Emitter {
    /// An emitter with the machine at `pos` (pulses), the last sequence number `seq`.
    pub fn new(pos: impl Into<Axes>, seq: u32, tap: Tap) -> Emitter {
        Emitter {
            pos: pos.into(),
            seq,
            tap,
            limits: None,
        }
    }

    /// `st.travel_pulses` for the three axes.
    fn limits(&mut self, st: &MachineSettings) -> [(i64, i64); 3] {
        let key = (st.pulse_mm, st.travel_min_mm, st.travel_max_mm);
        match self.limits {
            Some((k, l)) if k == key => l,
            _ => {
                let l = travel_pulses(st);
                self.limits = Some((key, l));
                l
            }
        }
    }

    /// Appends the blocks of `items` (each with its source line and column) to `out`, checking
    /// travel; on an error nothing is appended and the position is unchanged.
    pub fn emit(
        &mut self,
        items: &[(Canon, u32, u32)],
        st: &MachineSettings,
        out: &mut Vec<Block>,
    ) -> Result<(), TranslateError> {
        let (pos0, seq0, tap0, n0) = (self.pos, self.seq, self.tap, out.len());
        let r = self.emit_inner(items, st, out);
        if r.is_err() {
            self.pos = pos0;
            self.seq = seq0;
            self.tap = tap0;
            out.truncate(n0);
        }
        r
    }

    fn emit_inner(
        &mut self,
        items: &[(Canon, u32, u32)],
        st: &MachineSettings,
        out: &mut Vec<Block>,
    ) -> Result<(), TranslateError> {
        let inv = 1.0 / st.pulse_mm;
        // A point in pulses, if each of its `axes` is a finite number within reach of a pulse
        // count (far beyond any travel is refused as beyond it, with its real size).
        let p3 = |v: [f64; 3], axes: &[usize]| -> Result<[i64; 3], String> {
            let p = [v[0] * inv, v[1] * inv, v[2] * inv];
            // The usual point: every coordinate a number within reach (NaN fails the test).
            if p.iter().all(|x| x.abs() <= 1e15) {
                return Ok([round(p[0]), round(p[1]), round(p[2])]);
            }
            for &a in axes {
                if !v[a].is_finite() {
                    let name = ["X", "Y", "Z"][a];
                    return Err(format!(
                        "{name} of this move is not a finite number: the arithmetic on its words overflowed"
                    ));
                }
                if (v[a] * inv).abs() > 1e15 {
                    return Err(beyond(st, a, v[a]));
                }
            }
            Ok([round(v[0] * inv), round(v[1] * inv), round(v[2] * inv)])
        };
        let limits = self.limits(st);
        let check_point = |st: &MachineSettings, p: [i64; 3]| check_in(st, &limits, p);
        for (c, line, col) in items {
            let err = |message: String| TranslateError {
                line: *line,
                col: *col,
                message,
            };
            if let Canon::Tap(t) = c {
                self.tap = *t;
                continue;
            }
            // Made in place at the end of `out` (not made aside and copied in); taken back
            // off for an action that moves nowhere, and left for `emit` to cut on an error.
            out.push(Block::aux(0, *line, self.pos));
            let Some(b) = out.last_mut() else {
                continue;
            };
            b.tap = self.tap;
            match c {
                Canon::Rapid(e)
                | Canon::Feed(e, _)
                | Canon::Probe(e, _, _)
                | Canon::Thread(e, _) => {
                    let end = p3(*e, &[0, 1, 2]).map_err(err)?;
                    if end == self.pos.xyz() && !matches!(c, Canon::Probe(..)) {
                        out.pop();
                        continue;
                    }
                    b.end = Axes::with_rotary(end, self.pos.rotary());
                    match c {
                        Canon::Feed(_, f) => {
                            b.motion = Motion::Linear;
                            b.feed = *f;
                        }
                        Canon::Thread(_, lead) => {
                            b.motion = Motion::Linear;
                            b.feed = *lead;
                            b.feed_mode = crate::block::FeedMode::PerRev;
                            b.thread = Some(*lead);
                        }
                        Canon::Probe(_, f, g) => {
                            b.motion = Motion::Linear;
                            b.feed = *f;
                            b.probe = Some(*g);
                        }
                        _ => b.motion = Motion::Rapid,
                    }
                    check_point(st, end).map_err(err)?;
                }
                Canon::Turn { end, abc, feed } => {
                    let e = p3(*end, &[0, 1, 2]).map_err(err)?;
                    let abc = abc.map(|a| round(a * inv));
                    let to = Axes::with_rotary(e, abc);
                    if to == self.pos {
                        out.pop();
                        continue;
                    }
                    b.end = to;
                    match feed {
                        Some(f) => {
                            b.motion = Motion::Linear;
                            b.feed = *f;
                        }
                        None => b.motion = Motion::Rapid,
                    }
                    check_point(st, e).map_err(err)?;
                    for (r, &a) in abc.iter().enumerate() {
                        let i = crate::block::FIRST_ROTARY + r;
                        if st.rotary(i) && !st.wrapped(i) {
                            let (lo, hi) = st.travel_pulses(i);
                            if a < lo || a > hi {
                                return Err(err(beyond(st, i, st.to_mm(a))));
                            }
                        }
                    }
                }
                Canon::Io(io) => b.io = Some(*io),
                Canon::Arc {
                    end,
                    centre,
                    plane,
                    ccw,
                    feed,
                } => {
                    let [a0, a1, _] = plane.axes();
                    let e = p3(*end, &[0, 1, 2]).map_err(err)?;
                    let c = p3(*centre, &[a0, a1]).map_err(err)?;
                    // Far beyond any travel: refused before any integer arithmetic on it.
                    if c.iter()
                        .chain(e.iter())
                        .any(|v| v.abs() > 1_000_000_000_000)
                    {
                        return Err(err("arc centre or end point out of all range".to_string()));
                    }
                    let s = self.pos.xyz();
                    let rad = |p: [i64; 3], c: [i64; 3]| {
                        ((p[a0] - c[a0]) as f64).hypot((p[a1] - c[a1]) as f64)
                    };
                    // Rounding to pulses may part the radii; take the nearest pulse centre
                    // that keeps them within one pulse of each other.
                    let mut best = c;
                    let mut diff = (rad(s, c) - rad(e, c)).abs();
                    // Only an arc programmed on its circle is nudged; a spiral stays as given.
                    // (Asked only of radii that parted: two square roots an arc otherwise.)
                    let radius_mm = |p: [f64; 3]| (p[a0] - centre[a0]).hypot(p[a1] - centre[a1]);
                    let on_circle = || {
                        let s_mm = [st.to_mm(s[0]), st.to_mm(s[1]), st.to_mm(s[2])];
                        (radius_mm(s_mm) - radius_mm(*end)).abs() < 0.5 * st.pulse_mm
                    };
                    if diff > 1.0 && on_circle() {
                        for du in -1..=1 {
                            for dv in -1..=1 {
                                let mut cc = c;
                                cc[a0] += du;
                                cc[a1] += dv;
                                let d = (rad(s, cc) - rad(e, cc)).abs();
                                if d < diff {
                                    diff = d;
                                    best = cc;
                                }
                            }
                        }
                    }
                    let radius = rad(s, best);
                    if radius > 100_000_000.0 {
                        return Err(err(format!(
                            "arc radius {:.3} mm is over the 100 m the pulse core steps",
                            st.to_mm(radius as i64)
                        )));
                    }
                    if radius < 2.0 {
                        return Err(err(format!(
                            "arc radius {:.4} mm is below 2 pulses",
                            st.to_mm(radius as i64)
                        )));
                    }
                    b.end = Axes::with_rotary(e, self.pos.rotary());
                    b.motion = if *ccw { Motion::ArcCcw } else { Motion::ArcCw };
                    b.plane = *plane;
                    b.center = Some([best[a0] - s[a0], best[a1] - s[a1]]);
                    b.feed = *feed;
                    check_point(st, e).map_err(err)?;
                    check_arc(st, &limits, s, e, best, *plane, *ccw).map_err(err)?;
                }
                Canon::Dwell(secs) => {
                    b.motion = Motion::Dwell;
                    b.dwell_ns = (secs * 1e9).round().max(0.0) as u64;
                }
                Canon::Aux { s, t, m } => {
                    b.s = *s;
                    b.t = *t;
                    b.m = *m;
                }
                Canon::Clocks => b.clocks = true,
                Canon::Tap(_) => {
                    out.pop();
                    continue;
                }
            }
            if self.tap == Tap::End {
                self.tap = Tap::No;
            }
            self.seq += 1;
            b.seq = self.seq;
            b.delta = Axes::from_fn(|a| b.end[a] - self.pos[a]);
            self.pos = b.end;
            if out.len() == 1 {
                // The first block is made: room for exactly the rest (at most one block an
                // action; no doubling), reserved only now so that a line refused at its first
                // block never holds room for a million.
                out.reserve_exact(items.len().saturating_sub(1));
            }
        }
        Ok(())
    }
}

/// `x.round() as i64` (half away from zero) without the library call: `x − trunc(x)` is exact
/// below 2^52, beyond any travel in pulses.
#[inline]
fn round(x: f64) -> i64 {
    let i = x as i64;
    let f = x - i as f64;
    if f >= 0.5 {
        i.saturating_add(1)
    } else if f <= -0.5 {
        i.saturating_sub(1)
    } else {
        i
    }
}

/// A point inside the travel limits given in pulses, or why not.
#[inline]
fn check_in(st: &MachineSettings, limits: &[(i64, i64); 3], p: [i64; 3]) -> Result<(), String> {
    for axis in 0..3 {
        let (lo, hi) = limits[axis];
        if p[axis] < lo || p[axis] > hi {
            return Err(beyond(st, axis, st.to_mm(p[axis])));
        }
    }
    Ok(())
}

/// The message for machine coordinate `mm` of `axis` beyond its travel.
fn beyond(st: &MachineSettings, axis: usize, mm: f64) -> String {
    let name = crate::settings::AXIS_NAMES[axis];
    format!(
        "{name}{} (machine) is beyond the {name} travel ({:.3} to {:.3} {})",
        crate::input_text::fixed(mm, 3),
        st.travel_min_mm[axis],
        st.travel_max_mm[axis],
        if st.rotary(axis) { "degrees" } else { "mm" },
    )
}

/// The axis points (centre ± R) an arc sweeps over must be inside the travel too (`limits`,
/// the travel in pulses).
fn check_arc(
    st: &MachineSettings,
    limits: &[(i64, i64); 3],
    s: [i64; 3],
    e: [i64; 3],
    c: [i64; 3],
    plane: Plane,
    ccw: bool,
) -> Result<(), String> {
    let [u, v] = plane.turn_axes();
    let r = ((s[u] - c[u]) as f64).hypot((s[v] - c[v]) as f64);
    // The four axis points of the whole circle, as the sweep below works them out: the
    // cosine and sine of a quarter turn are 1, 0 or −1 to within 2e-16, which moves no
    // point of a radius up to the 100 m the emitter allows by half a pulse. All four inside
    // the travel: so is any part of the circle, and the angles (two `atan2`, a tenth of the
    // work of a program of arcs) are not needed.
    if r <= 1e9 {
        let k = r.round() as i64;
        let inside = [(k, 0), (0, k), (-k, 0), (0, -k)].iter().all(|&(du, dv)| {
            let mut p = s;
            p[u] = c[u] + du;
            p[v] = c[v] + dv;
            check_in(st, limits, p).is_ok()
        });
        if inside {
            return Ok(());
        }
    }
    check_sweep(st, limits, s, e, c, plane, ccw, r)
}

/// [`check_arc`] by the angles: the axis points within the arc's sweep, radius `r`.
#[allow(clippy::too_many_arguments)]
fn check_sweep(
    st: &MachineSettings,
    limits: &[(i64, i64); 3],
    s: [i64; 3],
    e: [i64; 3],
    c: [i64; 3],
    plane: Plane,
    ccw: bool,
    r: f64,
) -> Result<(), String> {
    use std::f64::consts::{FRAC_PI_2, TAU};
    let [u, v] = plane.turn_axes();
    let a = |p: [i64; 3]| ((p[v] - c[v]) as f64).atan2((p[u] - c[u]) as f64);
    let (a0, a1) = (a(s), a(e));
    let mut sweep = if ccw { a1 - a0 } else { a0 - a1 }.rem_euclid(TAU);
    if s[u] == e[u] && s[v] == e[v] {
        sweep = TAU;
    }
    for k in 0..4 {
        let q = k as f64 * FRAC_PI_2;
        let d = if ccw { q - a0 } else { a0 - q }.rem_euclid(TAU);
        if d <= sweep {
            let mut p = s;
            p[u] = c[u] + (r * q.cos()).round() as i64;
            p[v] = c[v] + (r * q.sin()).round() as i64;
            check_in(st, limits, p)?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An arc whose whole circle is inside the travel is passed without its angles; the
    /// answer (and the message of a point beyond) is the sweep's for any arc, near the
    /// travel's edges or far inside.
    #[test]
    fn the_circle_inside_gives_the_sweeps_answer() {
        let st = MachineSettings::default();
        let limits = travel_pulses(&st);
        let mut rng = crate::pulse_core::testkit::Rng::new(21);
        let (mut passed, mut refused) = (0, 0);
        for i in 0..20_000 {
            let plane = [Plane::XY, Plane::XZ, Plane::YZ][i % 3];
            let [u, v] = plane.turn_axes();
            // Centres spread over the travel and a little beyond, radii up to a metre.
            let mut c = [0i64; 3];
            for (a, x) in c.iter_mut().enumerate() {
                let (lo, hi) = limits[a];
                *x = rng.range(lo - 20_000, hi + 20_000);
            }
            let r = 2.0 + rng.unit() * [100.0, 10_000.0, 1_000_000.0][i % 3];
            let (t0, t1) = (rng.unit() * 7.0, rng.unit() * 7.0);
            let mut s = c;
            let mut e = c;
            s[u] += (r * t0.cos()).round() as i64;
            s[v] += (r * t0.sin()).round() as i64;
            e[u] += (r * t1.cos()).round() as i64;
            e[v] += (r * t1.sin()).round() as i64;
            let ccw = i % 2 == 0;
            let rs = ((s[u] - c[u]) as f64).hypot((s[v] - c[v]) as f64);
            let fast = check_arc(&st, &limits, s, e, c, plane, ccw);
            let sweep = check_sweep(&st, &limits, s, e, c, plane, ccw, rs);
            assert_eq!(fast, sweep, "{s:?} {e:?} {c:?} {plane:?} {ccw}");
            if fast.is_ok() {
                passed += 1;
            } else {
                refused += 1;
            }
        }
        assert!(passed > 1000 && refused > 1000, "{passed} {refused}");
    }

    #[test]
    fn round_is_half_away_from_zero_like_f64_round() {
        for x in [
            0.0,
            0.49999999999999994,
            0.5,
            1.5,
            2.5,
            -0.5,
            -1.5,
            -2.4999,
            123456.5,
            -7.0,
            1e15 + 0.5,
        ] {
            assert_eq!(round(x), x.round() as i64, "{x}");
        }
    }
}
