//! The block emitter: the machine as the translator tracks it (position in pulses, tool in the
//! spindle, spindle state) and the blocks of one statement as they are generated for B1
//! (patent Fig. 10B step (6): the cycle table output to B1 as machine instruction blocks).
//!
//! Every absolute point is converted to whole pulses once; `delta` is the exact difference of
//! consecutive ends, so no rounding drift accumulates. Z is the machine axis: tool-tip Z plus
//! the set length of the tool in the spindle.

use super::TranslateError;
use crate::block::{Block, Motion};
use crate::settings::MachineSettings;

/// The spindle as the translator last commanded it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Spindle {
    /// Stopped (M05, or never started).
    Stopped,
    /// Running forward (M03) at this speed.
    Forward(u32),
    /// Running in reverse (M04).
    Reverse,
}

/// The tool in the spindle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Loaded {
    /// Its T code (magazine pocket).
    pub tcode: u32,
    /// Its set length in pulses (carried by the Z axis).
    pub set: i64,
}

/// The machine state the translator carries from statement to statement.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Machine {
    /// Axis position, pulses.
    pub pos: [i64; 3],
    /// Where the rotary axes A, B and C stand, pulses: the source language does not move them,
    /// so every block keeps them (docs/language.md).
    pub abc: [i64; 3],
    /// The tool in the spindle.
    pub tool: Option<Loaded>,
    /// The spindle.
    pub spindle: Spindle,
    /// Tool-tip Z (pulses) of the clearance plane of the hole or contour last left, if the
    /// last thing done was a cycle; moves to the next hole rise at least to it.
    pub clear: Option<i64>,
    /// Sequence number of the last block.
    pub seq: u32,
}

impl Machine {
    /// The set length in pulses of the tool in the spindle (0 with none).
    pub fn set(&self) -> i64 {
        self.tool.map_or(0, |t| t.set)
    }

    /// The tool-tip Z in pulses.
    pub fn tip(&self) -> i64 {
        self.pos[2] - self.set()
    }
}

/// The blocks of one statement under construction, on a working copy of the machine.
pub struct Out<'s> {
    /// Working machine state (committed only when the statement is complete and checked).
    pub m: Machine,
    /// The blocks so far.
    pub blocks: Vec<Block>,
    /// For each block, the column of the designation it serves (for error messages).
    pub cols: Vec<u32>,
    /// The column blocks are charged to now.
    pub col: u32,
    /// The statement's source line.
    pub line: u32,
    /// The machine settings.
    pub settings: &'s MachineSettings,
}

impl<'s> Out<'s> {
    /// Starts a statement at `line` on machine state `m`.
    pub fn new(m: Machine, line: u32, settings: &'s MachineSettings) -> Out<'s> {
        Out {
            m,
            blocks: Vec::new(),
            cols: Vec::new(),
            col: 1,
            line,
            settings,
        }
    }

    /// mm to pulses.
    pub fn p(&self, mm: f64) -> i64 {
        self.settings.to_pulses(mm)
    }

    /// An error at this statement.
    pub fn err(&self, col: u32, message: String) -> TranslateError {
        TranslateError {
            line: self.line,
            col,
            message,
        }
    }

    fn push(&mut self, mut b: Block) {
        self.m.seq += 1;
        b.tool_z = self.m.tool.is_some();
        b.seq = self.m.seq;
        b.stmt = self.line;
        // The source language is X Y Z (docs/language.md): A, B and C stay where they are.
        for (r, &v) in self.m.abc.iter().enumerate() {
            b.end[3 + r] = v;
        }
        b.delta = [
            b.end[0] - self.m.pos[0],
            b.end[1] - self.m.pos[1],
            b.end[2] - self.m.pos[2],
        ]
        .into();
        self.m.pos = b.end.xyz();
        self.blocks.push(b);
        self.cols.push(self.col);
    }

    fn motion(&mut self, motion: Motion, end: [i64; 3], feed: f64) {
        if end == self.m.pos {
            return;
        }
        let mut b = Block::aux(0, 0, end);
        b.motion = motion;
        b.feed = feed;
        self.push(b);
    }

    /// G00 to an axis position (nothing if already there).
    pub fn rapid(&mut self, end: [i64; 3]) {
        self.motion(Motion::Rapid, end, 0.0);
    }

    /// G01 at `feed` mm/min to an axis position (nothing if already there).
    pub fn feed(&mut self, end: [i64; 3], feed: f64) {
        self.motion(Motion::Linear, end, feed);
    }

    /// G00 of Z alone to machine zero, then of X Y at machine zero when `xy` is given: moves
    /// that do not depend on the tool's length (tool change, CL, the end of the program).
    pub fn rapid_home(&mut self, xy: Option<[i64; 2]>) {
        for end in [
            Some([self.m.pos[0], self.m.pos[1], 0]),
            xy.map(|[x, y]| [x, y, 0]),
        ]
        .into_iter()
        .flatten()
        {
            let n = self.blocks.len();
            self.rapid(end);
            if let Some(b) = self.blocks.get_mut(n) {
                b.tool_z = false;
            }
        }
    }

    /// G00 of Z alone to tool-tip Z `tip` (pulses).
    pub fn rapid_tip(&mut self, tip: i64) {
        let z = tip + self.m.set();
        self.rapid([self.m.pos[0], self.m.pos[1], z]);
    }

    /// G01 of Z alone to tool-tip Z `tip` (pulses).
    pub fn feed_tip(&mut self, tip: i64, feed: f64) {
        let z = tip + self.m.set();
        self.feed([self.m.pos[0], self.m.pos[1], z], feed);
    }

    /// G02/G03 in the XY plane to `end` (axis pulses) about `centre` (absolute, pulses).
    pub fn arc(&mut self, end: [i64; 3], centre: [i64; 2], ccw: bool, feed: f64) {
        let mut b = Block::aux(0, 0, end);
        b.motion = if ccw { Motion::ArcCcw } else { Motion::ArcCw };
        b.center = Some([centre[0] - self.m.pos[0], centre[1] - self.m.pos[1]]);
        b.feed = feed;
        self.push(b);
    }

    /// G04 dwell of `secs` seconds.
    pub fn dwell(&mut self, secs: f64) {
        let mut b = Block::aux(0, 0, self.m.pos);
        b.motion = Motion::Dwell;
        b.dwell_ns = (secs * 1e9).round() as u64;
        self.push(b);
    }

    /// An auxiliary block: S, T and one M function.
    pub fn aux(&mut self, s: Option<u32>, t: Option<u32>, m: Option<u8>) {
        let mut b = Block::aux(0, 0, self.m.pos);
        b.s = s;
        b.t = t;
        b.m = m;
        self.push(b);
    }

    /// Spindle forward at `s` unless it already runs so (`S.. M03`).
    pub fn spindle_forward(&mut self, s: u32) {
        if self.m.spindle != Spindle::Forward(s) {
            self.aux(Some(s), None, Some(3));
            self.m.spindle = Spindle::Forward(s);
        }
    }

    /// Checks every block end (and the extent of every arc) against the travel limits.
    pub fn check_travel(&self, start: [i64; 3]) -> Result<(), TranslateError> {
        let st = self.settings;
        let limits = [0, 1, 2].map(|a| st.travel_pulses(a));
        let mut from = start;
        for (b, &col) in self.blocks.iter().zip(&self.cols) {
            self.check_point(b.end.xyz(), &limits, col)?;
            if let Some(c) = b.center {
                let centre = [from[0] + c[0], from[1] + c[1]];
                for p in arc_extremes(from, b.end.xyz(), centre, b.motion == Motion::ArcCcw) {
                    self.check_point(p, &limits, col)?;
                }
            }
            from = b.end.xyz();
        }
        Ok(())
    }

    fn check_point(
        &self,
        p: [i64; 3],
        limits: &[(i64, i64); 3],
        col: u32,
    ) -> Result<(), TranslateError> {
        let st = self.settings;
        for (axis, name) in ["X", "Y", "Z"].iter().enumerate() {
            let (lo, hi) = limits[axis];
            if p[axis] < lo || p[axis] > hi {
                return Err(self.err(
                    col,
                    format!(
                        "{name}{:.3} is beyond the {name} travel ({:.3} to {:.3} mm){}",
                        st.to_mm(p[axis]),
                        st.travel_min_mm[axis],
                        st.travel_max_mm[axis],
                        if axis == 2 {
                            " (machine Z = tool-tip Z + set length)"
                        } else {
                            ""
                        }
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// The points where an arc reaches its extreme X or Y (the quadrant points it sweeps over).
fn arc_extremes(from: [i64; 3], to: [i64; 3], c: [i64; 2], ccw: bool) -> Vec<[i64; 3]> {
    use std::f64::consts::{PI, TAU};
    let (sx, sy) = ((from[0] - c[0]) as f64, (from[1] - c[1]) as f64);
    let (ex, ey) = ((to[0] - c[0]) as f64, (to[1] - c[1]) as f64);
    let r = sx.hypot(sy).max(ex.hypot(ey));
    let a0 = sy.atan2(sx);
    let a1 = ey.atan2(ex);
    let mut sweep = if ccw { a1 - a0 } else { a0 - a1 };
    sweep = sweep.rem_euclid(TAU);
    if sweep < 1e-12 {
        sweep = TAU; // same start and end: a full circle
    }
    let mut out = Vec::new();
    for k in 0..4 {
        let q = k as f64 * PI / 2.0;
        let d = if ccw { q - a0 } else { a0 - q }.rem_euclid(TAU);
        if d <= sweep {
            let (dx, dy) = match k {
                0 => (r, 0.0),
                1 => (0.0, r),
                2 => (-r, 0.0),
                _ => (0.0, -r),
            };
            out.push([c[0] + dx.round() as i64, c[1] + dy.round() as i64, to[2]]);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arc_extremes_follow_the_sweep() {
        // A quarter arc CCW from (10,0) to (0,10) about the origin crosses no other quadrant point.
        let e = arc_extremes([10, 0, 0], [0, 10, 0], [0, 0], true);
        assert_eq!(e, vec![[10, 0, 0], [0, 10, 0]]);
        // The same ends CW go the long way round, over (-10,0) and (0,-10).
        let e = arc_extremes([10, 0, 0], [0, 10, 0], [0, 0], false);
        assert_eq!(e.len(), 4);
        // A full circle reaches all four.
        assert_eq!(arc_extremes([10, 0, 0], [10, 0, 0], [0, 0], true).len(), 4);
    }

    #[test]
    fn delta_is_the_difference_of_ends_and_zero_moves_are_dropped() {
        let st = MachineSettings::default();
        let m = Machine {
            pos: [5, 5, 5],
            abc: [0; 3],
            tool: None,
            spindle: Spindle::Stopped,
            clear: None,
            seq: 10,
        };
        let mut o = Out::new(m, 3, &st);
        o.rapid([5, 5, 5]);
        o.feed([8, 1, 5], 100.0);
        o.dwell(0.5);
        assert_eq!(o.blocks.len(), 2);
        assert_eq!(o.blocks[0].delta, [3, -4, 0]);
        assert_eq!((o.blocks[0].seq, o.blocks[0].stmt), (11, 3));
        assert_eq!(o.blocks[1].dwell_ns, 500_000_000);
        assert!(o.check_travel([5, 5, 5]).is_err(), "Z +0.005 is above Z0");
    }
}
