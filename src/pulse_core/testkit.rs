//! Hand-made blocks, and the project's one small seeded PRNG (every test, fuzz family and
//! benchmark that draws random numbers uses this `Rng`), for tests and benchmarks (no
//! translator needed).

use crate::block::{Block, Motion};

/// splitmix64: a small, seeded, deterministic PRNG.
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator from a seed.
    pub fn new(seed: u64) -> Rng {
        Rng(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A uniform integer in `lo..=hi`.
    pub fn range(&mut self, lo: i64, hi: i64) -> i64 {
        let span = (hi - lo + 1).max(1) as u64;
        lo + (self.next_u64() % span) as i64
    }

    /// A uniform float in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A uniform float in [lo, hi).
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + self.unit() * (hi - lo)
    }

    /// A uniform integer in `0..n` (0 if n is 0).
    pub fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.next_u64() % n as u64) as usize
        }
    }

    /// True with probability `p`.
    pub fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }

    /// One of `items` (which must not be empty).
    pub fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

/// A block of `motion` moving `delta` pulses from `start`, at `feed` mm/min.
pub fn block(seq: u32, motion: Motion, start: [i64; 3], delta: [i64; 3], feed: f64) -> Block {
    let mut b = Block::aux(
        seq,
        seq,
        [
            start[0] + delta[0],
            start[1] + delta[1],
            start[2] + delta[2],
        ],
    );
    b.motion = motion;
    b.delta = delta.into();
    b.feed = feed;
    b
}

/// A G01 block.
pub fn linear(seq: u32, start: [i64; 3], delta: [i64; 3], feed: f64) -> Block {
    block(seq, Motion::Linear, start, delta, feed)
}

/// A G02 (`ccw` false) or G03 arc block with the centre `center` relative to the start.
pub fn arc(
    seq: u32,
    start: [i64; 3],
    delta: [i64; 2],
    center: [i64; 2],
    ccw: bool,
    feed: f64,
) -> Block {
    let m = if ccw { Motion::ArcCcw } else { Motion::ArcCw };
    let mut b = block(seq, m, start, [delta[0], delta[1], 0], feed);
    b.center = Some(center);
    b
}

/// A chain of linear blocks through `points` (absolute pulses), the first point being the
/// start.
pub fn polyline(points: &[[i64; 3]], feed: f64) -> Vec<Block> {
    points
        .windows(2)
        .enumerate()
        .map(|(i, w)| {
            let d = [w[1][0] - w[0][0], w[1][1] - w[0][1], w[1][2] - w[0][2]];
            linear(i as u32 + 1, w[0], d, feed)
        })
        .collect()
}

/// The position after all the pulses of each distinct time (one PGEN step, or one
/// recirculation cycle), with that time, from `start`: the path the pulses trace.
pub fn steps(start: [i64; 3], pulses: &[super::PulseRec]) -> Vec<(u64, [i64; 3])> {
    let mut out = Vec::new();
    let mut p = start;
    let mut i = 0;
    while i < pulses.len() {
        let t = pulses[i].t_ns;
        while i < pulses.len() && pulses[i].t_ns == t {
            p[pulses[i].axis as usize] += pulses[i].dir as i64;
            i += 1;
        }
        out.push((t, p));
    }
    out
}

/// An arc block in `plane` from `start` to `end` (absolute pulses) about the centre `center`
/// (absolute; its normal coordinate ignored), G03 if `ccw`: a helix if the normal axis moves.
pub fn plane_arc(
    plane: crate::block::Plane,
    start: [i64; 3],
    end: [i64; 3],
    center: [i64; 3],
    ccw: bool,
    feed: f64,
) -> Block {
    let [a0, a1, _] = plane.axes();
    let mut b = Block::aux(1, 1, end);
    b.motion = if ccw { Motion::ArcCcw } else { Motion::ArcCw };
    b.plane = plane;
    b.delta = [end[0] - start[0], end[1] - start[1], end[2] - start[2]].into();
    b.center = Some([center[a0] - start[a0], center[a1] - start[a1]]);
    b.feed = feed;
    b
}

/// Random arc angles, radians: a start angle, the end angle a sweep of 5 % to 95 % of a turn
/// away (a whole turn if `full`), counter-clockwise if `ccw`, and the sweep. Draws the start
/// angle, then the sweep.
pub fn arc_angles(rng: &mut Rng, full: bool, ccw: bool) -> (f64, f64, f64) {
    use std::f64::consts::TAU;
    let th0 = rng.unit() * TAU;
    let sweep = if full {
        TAU
    } else {
        (0.05 + rng.unit() * 0.9) * TAU
    };
    (th0, if ccw { th0 + sweep } else { th0 - sweep }, sweep)
}

/// The start and end points of an arc about `centre` in `plane`: the start `r` pulses out at
/// angle `th0`, the end `r_end` out at `th1` (angles from the plane's first turn axis towards
/// its second), rounded to pulses; a full circle ends where it starts.
pub fn arc_ends(
    plane: crate::block::Plane,
    centre: [i64; 3],
    (r, th0): (f64, f64),
    (r_end, th1): (f64, f64),
    full: bool,
) -> ([i64; 3], [i64; 3]) {
    let [u, v] = plane.turn_axes();
    let mut s = centre;
    s[u] += (r * th0.cos()).round() as i64;
    s[v] += (r * th0.sin()).round() as i64;
    let mut e = if full { s } else { centre };
    if !full {
        e[u] += (r_end * th1.cos()).round() as i64;
        e[v] += (r_end * th1.sin()).round() as i64;
    }
    (s, e)
}
