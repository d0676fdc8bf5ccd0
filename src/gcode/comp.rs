//! Cutter radius compensation G41/G42 as LinuxCNC 2.9 joins it (docs/gcode.md "Cutter radius
//! compensation"): the tool centre runs one radius to the left (G41) or right (G42) of the
//! programmed XY path.
//!
//! - The entry move (the first XY move after G41/G42, a straight line longer than the radius)
//!   ends one radius off its own end point, square to its direction.
//! - Each move is held until the next one is known. At a convex corner the tool goes round the
//!   programmed corner point on an arc of the tool radius; at a concave corner the held move's
//!   end is moved back to where the two offset paths cross. A held straight move that would
//!   have to run backwards, or a held arc that would have to sweep further, gouges: an error.
//! - An arc the tool is inside of must be larger than the tool's radius.
//! - The exit move (the first move after G40) runs from the last offset point to its
//!   programmed end point.
//!
//! Moves without X or Y (Z only), S, T and M functions and dwells wait behind the held move;
//! the Z-only moves follow its end when a concave corner moves it, as in LinuxCNC.

use super::canon::Canon;
use super::exec::Exec;
use crate::block::{Plane, TranslateError};

/// Corners turning by less than this (radians) are taken as tangent.
const TANGENT: f64 = 0.05;

/// The smallest radius compensation may leave an arc, or give a corner arc, in pulses: the
/// pulse core steps arcs of 2 pulses or more (`canon`), and rounding the start and the centre
/// to pulses may take up to 1.5 more.
pub const MIN_RADIUS_PULSES: f64 = 4.0;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Phase {
    Off,
    Entry,
    On,
    Exit,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Geo {
    Line,
    Arc { c: [f64; 2], rc: f64, ccw: bool },
}

#[derive(Clone, Debug, PartialEq)]
struct Held {
    canon: Canon,
    line: u32,
    col: u32,
    /// Offset start of the move.
    start: [f64; 2],
    /// Offset end as first computed.
    end: [f64; 2],
    /// Programmed end point (the corner) and the tangent there.
    corner: [f64; 2],
    tangent: [f64; 2],
    geo: Geo,
}

/// The compensation state.
#[derive(Clone, Debug, PartialEq)]
pub struct Comp {
    phase: Phase,
    /// +1 left (G41), −1 right (G42).
    side: f64,
    r: f64,
    held: Option<Held>,
    /// What came after the held move: Z-only moves (which follow its end when it moves, as in
    /// LinuxCNC) and S, T, M functions and dwells, in order.
    queue: Vec<(Canon, u32, u32)>,
}

impl Default for Comp {
    fn default() -> Self {
        Comp {
            phase: Phase::Off,
            side: 1.0,
            r: 0.0,
            held: None,
            queue: Vec::new(),
        }
    }
}

fn unit(v: [f64; 2]) -> [f64; 2] {
    let n = v[0].hypot(v[1]);
    if n == 0.0 {
        [0.0, 0.0]
    } else {
        [v[0] / n, v[1] / n]
    }
}

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

fn add_k(a: [f64; 2], k: f64, d: [f64; 2]) -> [f64; 2] {
    [a[0] + k * d[0], a[1] + k * d[1]]
}

fn left(d: [f64; 2]) -> [f64; 2] {
    [-d[1], d[0]]
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

impl Comp {
    /// G41 or G42 is in force (or its exit move is still to come).
    pub fn active(&self) -> bool {
        self.phase != Phase::Off
    }

    /// G40 was given and its exit move has not been made.
    pub fn pending_exit(&self) -> bool {
        self.phase == Phase::Exit
    }

    /// G41 (`left`) or G42 with the tool's radius.
    pub fn on(&mut self, left: bool, radius: f64, _col: u32) {
        self.side = if left { 1.0 } else { -1.0 };
        self.r = radius;
        self.phase = Phase::Entry;
    }

    /// G40: the next XY move is the exit move (none is needed if no move was made yet).
    pub fn off(&mut self, _col: u32) {
        self.phase = match self.phase {
            Phase::On => Phase::Exit,
            _ => Phase::Off,
        };
    }

    /// Emits the held move as it stands, and what is queued behind it.
    pub fn flush(&mut self, x: &mut Exec) {
        if let Some(h) = self.held.take() {
            let end = h.end;
            self.emit_held(x, h, end);
        }
    }

    /// Emits the held move ending at `end`, then the queue, its Z-only moves at `end` too.
    fn emit_held(&mut self, x: &mut Exec, mut h: Held, end: [f64; 2]) {
        set_end(&mut h.canon, end);
        x.out.push((h.canon, h.line, h.col));
        for (mut c, line, col) in self.queue.drain(..) {
            if matches!(c, Canon::Rapid(_) | Canon::Feed(..)) {
                set_end(&mut c, end);
            }
            x.out.push((c, line, col));
        }
    }

    /// An S, T or M function or a dwell: after the held move if there is one.
    pub fn aux(&mut self, x: &mut Exec, c: Canon, col: u32) {
        if self.held.is_some() {
            self.queue.push((c, x.n, col));
        } else {
            x.push(c, col);
        }
    }

    /// A straight move from `from` to `to` (programmed, machine mm).
    pub fn line(
        &mut self,
        x: &mut Exec,
        from: [f64; 3],
        to: [f64; 3],
        rapid: bool,
        feed: f64,
        col: u32,
    ) -> Result<(), TranslateError> {
        let mk = |e: [f64; 3]| {
            if rapid {
                Canon::Rapid(e)
            } else {
                Canon::Feed(e, feed)
            }
        };
        let (c, p) = ([from[0], from[1]], [to[0], to[1]]);
        let xy_move = dist(c, p) > 1e-9;
        match self.phase {
            Phase::Off => {
                x.push(mk(to), col);
                return Ok(());
            }
            Phase::Exit => {
                // The exit move: from the last offset point to the programmed point.
                self.flush(x);
                x.push(mk(to), col);
                if xy_move {
                    self.phase = Phase::Off;
                }
                return Ok(());
            }
            _ => {}
        }
        if !xy_move {
            // A Z-only move: queued behind the held move, it will follow that move's end.
            match &self.held {
                Some(h) => {
                    let e = [h.end[0], h.end[1], to[2]];
                    self.queue.push((mk(e), x.n, col));
                }
                None => x.push(mk(to), col),
            }
            return Ok(());
        }
        let d = unit(sub(p, c));
        let n = left(d);
        if self.phase == Phase::Entry {
            let len = dist(c, p);
            if len <= self.r {
                return Err(x.err(
                    col,
                    format!(
                        "the entry move of cutter compensation ({} mm) is not longer than the tool radius ({:.4} mm)",
                        crate::input_text::fixed(len, 4),
                        self.r
                    ),
                ));
            }
            let e = add_k(p, self.side * self.r, n);
            self.held = Some(Held {
                canon: mk([e[0], e[1], to[2]]),
                line: x.n,
                col,
                start: c,
                end: e,
                corner: p,
                tangent: d,
                geo: Geo::Line,
            });
            self.phase = Phase::On;
            return Ok(());
        }
        let s2 = add_k(c, self.side * self.r, n);
        let e2 = add_k(p, self.side * self.r, n);
        let start = self.join(x, s2, d, Geo::Line, feed, col)?;
        self.held = Some(Held {
            canon: mk([e2[0], e2[1], to[2]]),
            line: x.n,
            col,
            start,
            end: e2,
            corner: p,
            tangent: d,
            geo: Geo::Line,
        });
        Ok(())
    }

    /// An arc from `s` to `e` about `centre` (programmed, machine mm).
    #[allow(clippy::too_many_arguments)]
    pub fn arc(
        &mut self,
        x: &mut Exec,
        s: [f64; 3],
        e: [f64; 3],
        centre: [f64; 3],
        plane: Plane,
        ccw: bool,
        feed: f64,
        col: u32,
    ) -> Result<(), TranslateError> {
        let canon = |end: [f64; 3]| Canon::Arc {
            end,
            centre,
            plane,
            ccw,
            feed,
        };
        match self.phase {
            Phase::Off => {
                x.push(canon(e), col);
                return Ok(());
            }
            Phase::Entry => {
                return Err(x.err(
                    col,
                    "the first move after G41/G42 must be a straight line (G00 or G01), not an arc",
                ));
            }
            Phase::Exit => {
                return Err(x.err(
                    col,
                    "the move after G40 must be a straight line (G00 or G01), not an arc",
                ));
            }
            Phase::On => {}
        }
        let c = [centre[0], centre[1]];
        let (s2d, e2d) = ([s[0], s[1]], [e[0], e[1]]);
        let rr = dist(s2d, c);
        let inside = (self.side > 0.0) == ccw;
        let rc = if inside { rr - self.r } else { rr + self.r };
        let min = MIN_RADIUS_PULSES * x.settings.pulse_mm;
        if inside && rc <= 0.0 {
            return Err(x.err(
                col,
                format!(
                    "gouge: cutter compensation puts the tool (radius {:.4} mm) inside this arc of radius {rr:.4} mm, which is not larger than the tool",
                    self.r
                ),
            ));
        }
        if inside && rc < min {
            return Err(x.err(
                col,
                format!(
                    "cutter compensation (tool radius {:.4} mm) leaves this arc of radius {rr:.4} mm a radius of {rc:.4} mm, too small to cut (at least {min:.4} mm)",
                    self.r
                ),
            ));
        }
        let rs = unit(sub(s2d, c));
        let re = unit(sub(e2d, c));
        let tan = |r: [f64; 2]| if ccw { left(r) } else { [r[1], -r[0]] };
        let s2 = add_k(c, rc, rs);
        let e2 = add_k(c, rc, re);
        let geo = Geo::Arc { c, rc, ccw };
        let start = self.join(x, s2, tan(rs), geo, feed, col)?;
        self.held = Some(Held {
            canon: Canon::Arc {
                end: [e2[0], e2[1], e[2]],
                centre,
                plane,
                ccw,
                feed,
            },
            line: x.n,
            col,
            start,
            end: e2,
            corner: e2d,
            tangent: tan(re),
            geo,
        });
        Ok(())
    }

    /// Joins the held move to a new one starting (offset) at `s2` with tangent `t2`: emits the
    /// held move (moved back at a concave corner) and, at a convex corner, the arc round it.
    /// Returns where the new move starts.
    fn join(
        &mut self,
        x: &mut Exec,
        s2: [f64; 2],
        t2: [f64; 2],
        geo2: Geo,
        feed: f64,
        col: u32,
    ) -> Result<[f64; 2], TranslateError> {
        let Some(h) = self.held.take() else {
            return Ok(s2);
        };
        let t1 = h.tangent;
        let cross = t1[0] * t2[1] - t1[1] * t2[0];
        let dot = t1[0] * t2[0] + t1[1] * t2[1];
        let turn = cross.atan2(dot) * self.side;
        if turn.abs() <= TANGENT && dist(h.end, s2) < 1e-6 + self.r * TANGENT {
            let start = h.end;
            self.emit_held(x, h, start);
            return Ok(start);
        }
        if turn < 0.0 {
            // Convex: round the programmed corner.
            let (e1, corner) = (h.end, h.corner);
            self.emit_held(x, h, e1);
            let z = x
                .out
                .iter()
                .rev()
                .find_map(|(c, _, _)| match c {
                    Canon::Rapid(e) | Canon::Feed(e, _) | Canon::Arc { end: e, .. } => Some(e[2]),
                    _ => None,
                })
                .unwrap_or(0.0);
            if dist(e1, s2) > 1e-9 {
                x.push(
                    Canon::Arc {
                        end: [s2[0], s2[1], z],
                        centre: [corner[0], corner[1], z],
                        plane: Plane::XY,
                        ccw: self.side < 0.0,
                        feed,
                    },
                    col,
                );
            }
            return Ok(s2);
        }
        // Concave: where the two offset paths cross, nearest the corner.
        let near = [(h.end[0] + s2[0]) / 2.0, (h.end[1] + s2[1]) / 2.0];
        let pts: Vec<[f64; 2]> = match (h.geo, geo2) {
            (Geo::Line, Geo::Line) => {
                let den = t1[0] * t2[1] - t1[1] * t2[0];
                if den.abs() < 1e-12 {
                    vec![]
                } else {
                    let w = sub(s2, h.end);
                    let k = (w[0] * t2[1] - w[1] * t2[0]) / den;
                    vec![add_k(h.end, k, t1)]
                }
            }
            (Geo::Line, Geo::Arc { c, rc, .. }) => super::geom::line_circle(h.end, t1, c, rc)
                .into_iter()
                .map(|k| add_k(h.end, k, t1))
                .collect(),
            (Geo::Arc { c, rc, .. }, Geo::Line) => super::geom::line_circle(s2, t2, c, rc)
                .into_iter()
                .map(|k| add_k(s2, k, t2))
                .collect(),
            (Geo::Arc { c: c1, rc: r1, .. }, Geo::Arc { c: c2, rc: r2, .. }) => {
                super::geom::circle_circle(c1, r1, c2, r2)
            }
        };
        let Some(p) = pts
            .into_iter()
            .min_by(|a, b| dist(*a, near).total_cmp(&dist(*b, near)))
        else {
            return Err(x.err(col, "gouge: the offset paths of this concave corner do not meet; the tool cannot reach it"));
        };
        match h.geo {
            Geo::Line => {
                // Against the programmed direction, as LinuxCNC: a held move that would run
                // against it gouges.
                let d0 = h.tangent;
                let d1 = sub(p, h.start);
                if d0[0] * d1[0] + d0[1] * d1[1] < 0.0 {
                    return Err(x.err(col, format!(
                        "gouge: the concave corner after line {} cannot be reached by the tool without cutting into the part",
                        h.line
                    )));
                }
            }
            Geo::Arc { c, ccw, .. } => {
                let sweep = |e: [f64; 2]| {
                    let a0 = (h.start[1] - c[1]).atan2(h.start[0] - c[0]);
                    let a1 = (e[1] - c[1]).atan2(e[0] - c[0]);
                    let d = if ccw { a1 - a0 } else { a0 - a1 };
                    d.rem_euclid(std::f64::consts::TAU)
                };
                if sweep(p) > sweep(h.end) + 0.0254 {
                    return Err(x.err(col, format!(
                        "gouge: the arc of line {} would have to go past its end to reach this concave corner",
                        h.line
                    )));
                }
            }
        }
        self.emit_held(x, h, p);
        Ok(p)
    }
}

fn set_end(c: &mut Canon, p: [f64; 2]) {
    if let Canon::Rapid(e) | Canon::Feed(e, _) | Canon::Arc { end: e, .. } = c {
        e[0] = p[0];
        e[1] = p[1];
    }
}
