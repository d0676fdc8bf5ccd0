//! Cutter radius compensation G41/G42 as LinuxCNC 2.9's rs274 joins it (docs/gcode.md "Cutter
//! radius compensation"): the tool centre runs one radius to the left (G41) or right (G42) of
//! the programmed XY path.
//!
//! - **Entry** (the first move after G41/G42): a straight move ends one radius off its own end
//!   point, square to its direction; an arc ends one radius off its programmed end, on an arc
//!   from where the tool stands whose centre lies on the line from that end to the programmed
//!   centre. Either must end farther than the tool's radius from where it starts.
//! - **Held moves.** Each move waits in a queue until the next one is known, with what comes
//!   after it (moves without X or Y, S, M functions, dwells). At a **convex** corner the held
//!   move is emitted as it is and an arc of the tool's radius goes round the programmed corner
//!   (a rapid goes straight to where that arc would end). At a **concave** corner every move
//!   in the queue has its XY end moved back to where the two offset paths meet, by LinuxCNC's
//!   formulas for line–line, arc–line, line–arc and arc–arc; a straight move that would then
//!   run backwards, or an arc that would have to sweep further, gouges: an error.
//! - **Exit.** G40 emits what is held; the next move starts from there, uncompensated, and
//!   must be straight.
//!
//! The geometry is in machine millimetres in the XY plane; the tolerances that LinuxCNC states
//! in the program's units take them from `set_inch`.

use super::canon::Canon;
use super::exec::Exec;
use super::geom::{angle, dist, polar};
use crate::block::{Plane, TranslateError};
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// Corners turning by less than this (radians) are taken as tangent (LinuxCNC's
/// TOLERANCE_CONCAVE_CORNER).
const SMALL: f64 = 0.05;

/// How much further (radians) a held arc may sweep to reach a concave corner before it gouges,
/// under G21 and under G20 (LinuxCNC states it in the program's units).
const SWEEP_SLACK_MM: f64 = 0.0254;
const SWEEP_SLACK_INCH: f64 = 0.001;

/// The most a held arc's radius may change when its end moves (0.01 of the program's unit):
/// more is LinuxCNC's "invalid arc with mismatched radii".
const RADIUS_SLACK: f64 = 0.01;

/// The smallest radius compensation may leave an arc, in pulses: the pulse core steps arcs of
/// 2 pulses or more (`canon`), and rounding the start and the centre to pulses may take up to
/// 1.5 more.
pub const MIN_RADIUS_PULSES: f64 = 4.0;

/// The side the tool is on (LinuxCNC's cutter_comp_side).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Side {
    Off,
    Left,
    Right,
}

/// What a queued item is, for moving its end.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Geo {
    /// A straight move, with the direction LinuxCNC keeps for its gouge check (the motion's
    /// XY direction; for the entry move, the offset's).
    Line { dir: [f64; 2] },
    /// An arc about `c` (the programmed centre), counter-clockwise if `ccw`; `sweep` is the
    /// programmed arc's signed sweep (LinuxCNC's original_turns; 0 for a corner arc, whose
    /// end never moves).
    Arc { c: [f64; 2], ccw: bool, sweep: f64 },
    /// Not a move: S, M functions, dwells, I/O.
    Other,
}

#[derive(Clone, Debug, PartialEq)]
struct Queued<T> {
    canon: T,
    line: u32,
    col: u32,
    geo: Geo,
}

impl<T: Held> Queued<T> {
    /// The end point in the plane's coordinates (`ax`: the plane's axes, then its normal).
    fn end(&self, ax: [usize; 3]) -> [f64; 2] {
        match self.canon.end() {
            Some(e) => [e[ax[0]], e[ax[1]]],
            None => [0.0, 0.0],
        }
    }
}

/// What compensation holds and hands on: a machine's canonical items, the mill's [`Canon`] or
/// the lathe's (`crate::lathe::gcode::out::Item`). Moves are built and their ends moved
/// through it; anything else (S, M functions, dwells) only waits behind the held moves.
pub trait Held: Clone + std::fmt::Debug + PartialEq {
    /// A feed move's rate as the machine's reader has it.
    type Feed: Copy + std::fmt::Debug + PartialEq;
    /// How the messages name the compensation and the tool whose radius it keeps
    /// (`cutter compensation`, `tool`).
    const NAMES: (&'static str, &'static str);
    /// G00 (`rapid`) or G01 to `end`.
    fn straight(rapid: bool, end: [f64; 3], feed: Self::Feed) -> Self;
    /// G02/G03 to `end` about `centre` in `plane`.
    fn arc(end: [f64; 3], centre: [f64; 3], plane: Plane, ccw: bool, feed: Self::Feed) -> Self;
    /// A move's end point (None: not a move).
    fn end(&self) -> Option<[f64; 3]>;
    /// Moves a move's end point (nothing for what is not a move).
    fn set_end(&mut self, end: [f64; 3]);
}

impl Held for Canon {
    type Feed = f64;
    const NAMES: (&'static str, &'static str) = ("cutter compensation", "tool");
    fn straight(rapid: bool, e: [f64; 3], feed: f64) -> Canon {
        if rapid {
            Canon::Rapid(e)
        } else {
            Canon::Feed(e, feed)
        }
    }
    fn arc(end: [f64; 3], centre: [f64; 3], plane: Plane, ccw: bool, feed: f64) -> Canon {
        Canon::Arc {
            end,
            centre,
            plane,
            ccw,
            feed,
        }
    }
    fn end(&self) -> Option<[f64; 3]> {
        match self {
            Canon::Rapid(e) | Canon::Feed(e, _) | Canon::Arc { end: e, .. } => Some(*e),
            _ => None,
        }
    }
    fn set_end(&mut self, p: [f64; 3]) {
        if let Canon::Rapid(e) | Canon::Feed(e, _) | Canon::Arc { end: e, .. } = self {
            *e = p;
        }
    }
}

/// Where compensation hands on what it emits, and what it asks of the line being read: the
/// mill's line execution (`Exec`) or the lathe's emitter.
pub trait Sink<T> {
    /// The line being read.
    fn line(&self) -> u32;
    /// Hands on `item`, charged to `line` and `col`.
    fn put(&mut self, item: T, line: u32, col: u32);
    /// The machine's pulse, mm.
    fn pulse_mm(&self) -> f64;
    /// An error at column `col` of the line being read.
    fn error(&self, col: u32, message: impl Into<String>) -> TranslateError {
        TranslateError {
            line: self.line(),
            col,
            message: message.into(),
        }
    }
    /// Hands on `item`, charged to the line being read.
    fn put_now(&mut self, item: T, col: u32) {
        let n = self.line();
        self.put(item, n, col)
    }
}

impl Sink<Canon> for Exec<'_> {
    fn line(&self) -> u32 {
        self.n
    }
    fn put(&mut self, item: Canon, line: u32, col: u32) {
        self.out.push((item, line, col));
    }
    fn pulse_mm(&self) -> f64 {
        self.settings.pulse_mm
    }
}

/// The compensation state: LinuxCNC's side, radius and first-move flag, its queue of held
/// moves and the start of the move at the queue's front (its "endpoint").
#[derive(Clone, Debug, PartialEq)]
pub struct Comp<T = Canon> {
    side: Side,
    r: f64,
    /// The plane compensation works in (G17 or G18, as LinuxCNC's).
    plane: Plane,
    /// Its axes in the order a counter-clockwise turn goes from the first to the second (XY:
    /// X, Y; XZ: Z, X), then its normal: the geometry below is worked in these coordinates.
    ax: [usize; 3],
    /// No compensated move made yet since G41/G42 (the next is the entry).
    first: bool,
    /// G40 ended compensation after a compensated move: the next move must be straight.
    arc_not_allowed: bool,
    /// G40 ended compensation after a compensated move, and no move has been made since.
    exit_pending: bool,
    /// G20 in force (the tolerances LinuxCNC states in the program's units).
    inch: bool,
    /// Where the tool centre is (after the queued moves), machine mm.
    cur: [f64; 3],
    /// The programmed XY point of the last compensated move.
    prog: [f64; 2],
    queue: Vec<Queued<T>>,
    /// The item at the queue's front when it was last emitted: LinuxCNC reads it when it
    /// meets a concave corner with an empty queue (after M00, M01 or M60 emitted it).
    last_front: Option<Queued<T>>,
    /// Where the move at the queue's front starts, when known (LinuxCNC's endpoint).
    endpoint: Option<[f64; 2]>,
}

impl<T> Default for Comp<T> {
    fn default() -> Self {
        Comp {
            side: Side::Off,
            r: 0.0,
            plane: Plane::XY,
            ax: [0, 1, 2],
            first: true,
            arc_not_allowed: false,
            exit_pending: false,
            inch: false,
            cur: [0.0; 3],
            prog: [0.0; 2],
            queue: Vec::new(),
            last_front: None,
            endpoint: None,
        }
    }
}

/// The signed sweep (radians, counter-clockwise positive) of an arc from `a` to `b` about `c`
/// that turns counter-clockwise if `ccw` (LinuxCNC's find_turn for one turn).
fn find_turn(a: [f64; 2], c: [f64; 2], ccw: bool, b: [f64; 2]) -> f64 {
    let mut alpha = angle(c, a);
    let mut beta = angle(c, b);
    if ccw {
        if beta <= alpha {
            beta += TAU;
        }
        beta - alpha
    } else {
        if alpha <= beta {
            alpha += TAU;
        }
        beta - alpha
    }
}

/// A gouge, charged to the line that reveals it.
fn gouge<T: Held>(x: &impl Sink<T>, col: u32, what: &str) -> TranslateError {
    x.error(
        col,
        format!(
            "gouge: {what} cannot be reached by the {} without cutting into the part",
            T::NAMES.1
        ),
    )
}

impl<T: Held> Comp<T> {
    /// A machine point's coordinates in the compensation plane.
    fn uv(&self, p: [f64; 3]) -> [f64; 2] {
        [p[self.ax[0]], p[self.ax[1]]]
    }

    /// The machine point at `p` in the plane and `n` along its normal.
    fn at(&self, p: [f64; 2], n: f64) -> [f64; 3] {
        let mut o = [0.0; 3];
        o[self.ax[0]] = p[0];
        o[self.ax[1]] = p[1];
        o[self.ax[2]] = n;
        o
    }

    /// The coordinate along the plane's normal (Z in G17, Y in G18).
    fn normal(&self, p: [f64; 3]) -> f64 {
        p[self.ax[2]]
    }

    /// An arc in the compensation plane ending at `end`, about `c`.
    fn plane_arc(&self, end: [f64; 3], c: [f64; 2], ccw: bool, feed: T::Feed) -> T {
        T::arc(end, self.at(c, self.normal(end)), self.plane, ccw, feed)
    }

    /// G41 or G42 is in force (LinuxCNC's cutter_comp_side is not OFF), whatever the radius.
    pub fn active(&self) -> bool {
        self.side != Side::Off
    }

    /// G40 ended compensation after a compensated move and no move has been made since: the
    /// machine stands at the last offset point, off the programmed one.
    pub fn pending_exit(&self) -> bool {
        self.exit_pending
    }

    /// Compensation has made its entry move (on, with a radius above 0): G40 then emits what
    /// it holds.
    pub fn entered(&self) -> bool {
        self.offsetting() && !self.first
    }

    /// Compensation moves the tool (on, with a radius above 0).
    pub fn offsetting(&self) -> bool {
        self.side != Side::Off && self.r > 0.0
    }

    /// The program's units, for the tolerances LinuxCNC states in them.
    pub fn set_inch(&mut self, inch: bool) {
        self.inch = inch;
    }

    /// G41 (`left`) or G42 with the tool's radius (mm, not negative), in `plane` (G17 or G18;
    /// the caller refuses G19).
    pub fn on(&mut self, left: bool, radius: f64, plane: Plane) {
        self.plane = plane;
        self.ax = match plane {
            Plane::XZ => [2, 0, 1],
            _ => [0, 1, 2],
        };
        self.side = if left { Side::Left } else { Side::Right };
        self.r = radius;
        self.first = true;
    }

    /// G40: what is held is emitted; the next move starts from the last offset point and must
    /// be straight (none of this if no compensated move was made).
    pub fn off(&mut self, x: &mut impl Sink<T>, col: u32) -> Result<(), TranslateError> {
        if self.offsetting() && !self.first {
            let cur = self.uv(self.cur);
            self.move_ends_and_emit(x, cur, col)?;
            self.arc_not_allowed = true;
            self.exit_pending = true;
        }
        self.side = Side::Off;
        self.first = true;
        Ok(())
    }

    /// Emits what is held as it stands (LinuxCNC's flush at M00, M01, M02, M30 and M60, and
    /// before an input is read).
    pub fn flush(&mut self, x: &mut impl Sink<T>, col: u32) -> Result<(), TranslateError> {
        if self.queue.is_empty() {
            return Ok(());
        }
        let cur = self.uv(self.cur);
        self.move_ends_and_emit(x, cur, col)
    }

    /// An S, T or M function, a dwell or an I/O action: after the held move if there is one.
    pub fn aux(&mut self, x: &mut impl Sink<T>, c: T, col: u32) {
        if self.queue.is_empty() {
            x.put_now(c, col);
        } else {
            self.queue.push(Queued {
                canon: c,
                line: x.line(),
                col,
                geo: Geo::Other,
            });
        }
    }

    fn enqueue(&mut self, x: &impl Sink<T>, canon: T, col: u32, geo: Geo) {
        self.queue.push(Queued {
            canon,
            line: x.line(),
            col,
            geo,
        });
    }

    /// Emits the queue as it stands (LinuxCNC's dequeue_canons): the start of what comes next
    /// is unknown to the gouge checks until it is set.
    fn emit(&mut self, x: &mut impl Sink<T>) {
        self.endpoint = None;
        if let Some(f) = self.queue.first() {
            self.last_front = Some(f.clone());
        }
        for q in self.queue.drain(..) {
            x.put(q.canon, q.line, q.col);
        }
    }

    /// Moves the XY end of every queued move to `p`, refusing a move that would then run
    /// backwards or sweep further than programmed, then emits them
    /// (LinuxCNC's move_endpoint_and_flush). The next move starts at `p`.
    fn move_ends_and_emit(
        &mut self,
        x: &mut impl Sink<T>,
        p: [f64; 2],
        col: u32,
    ) -> Result<(), TranslateError> {
        let comp = T::NAMES.0;
        let unit = if self.inch { 25.4 } else { 1.0 };
        let ax = self.ax;
        for q in &mut self.queue {
            match q.geo {
                Geo::Arc { c, ccw, sweep } => {
                    let r1 = dist(q.end(ax), c);
                    let r2 = dist(p, c);
                    if (r1 - r2).abs() > RADIUS_SLACK * unit {
                        return Err(x.error(col, format!(
                            "{comp} cannot join the arc of line {} here: its end would move off its circle (radius {r1:.4} mm, then {r2:.4} mm)",
                            q.line
                        )));
                    }
                    if let Some(start) = self.endpoint {
                        let slack = if self.inch {
                            SWEEP_SLACK_INCH
                        } else {
                            SWEEP_SLACK_MM
                        };
                        if sweep != 0.0 && find_turn(start, c, ccw, p).abs() > sweep.abs() + slack {
                            return Err(gouge(
                                x,
                                col,
                                &format!(
                                    "the arc of line {} would have to go past its end: the concave corner after it",
                                    q.line
                                ),
                            ));
                        }
                    }
                }
                Geo::Line { dir } => {
                    if let Some(start) = self.endpoint {
                        let d = [p[0] - start[0], p[1] - start[1]];
                        if dir[0] * d[0] + dir[1] * d[1] < 0.0 {
                            return Err(gouge(
                                x,
                                col,
                                &format!("the concave corner after line {}", q.line),
                            ));
                        }
                    }
                }
                Geo::Other => continue,
            }
            if let Some(mut e) = q.canon.end() {
                e[ax[0]] = p[0];
                e[ax[1]] = p[1];
                q.canon.set_end(e);
            }
        }
        self.emit(x);
        self.endpoint = Some(p);
        Ok(())
    }

    /// The held move LinuxCNC looks at to choose a concave corner's formula.
    fn front(&self) -> Option<&Queued<T>> {
        self.queue.first().or(self.last_front.as_ref())
    }

    /// A straight move from `from` to `to` (programmed, machine mm).
    #[allow(clippy::too_many_arguments)]
    pub fn line(
        &mut self,
        x: &mut impl Sink<T>,
        from: [f64; 3],
        to: [f64; 3],
        rapid: bool,
        feed: T::Feed,
        col: u32,
    ) -> Result<(), TranslateError> {
        let (comp, tool) = T::NAMES;
        self.arc_not_allowed = false;
        self.exit_pending = false;
        if !self.offsetting() {
            x.put_now(T::straight(rapid, to, feed), col);
            return Ok(());
        }
        let (c, p) = (self.uv(from), self.uv(to));
        let left = self.side == Side::Left;
        let r = self.r;
        if self.first {
            let len = dist(c, p);
            if len <= r {
                return Err(x.error(
                    col,
                    format!(
                        "the entry move of {comp} ({} mm) is not longer than the {tool} radius ({:.4} mm)",
                        crate::input_text::fixed(len, 4),
                        r
                    ),
                ));
            }
            let a = angle(c, p) + if left { FRAC_PI_2 } else { -FRAC_PI_2 };
            let e = polar(p, r, a);
            self.endpoint = Some(c);
            let canon = T::straight(rapid, self.at(e, self.normal(to)), feed);
            self.enqueue(
                x,
                canon,
                col,
                Geo::Line {
                    dir: [a.cos(), a.sin()],
                },
            );
            self.first = false;
            self.cur = self.at(e, self.normal(to));
            self.prog = p;
            return Ok(());
        }
        let op = self.prog;
        let cur = self.uv(self.cur);
        if p == op {
            // No XY motion: it waits behind the held move and follows its end.
            let canon = T::straight(rapid, self.at(cur, self.normal(to)), feed);
            self.enqueue(x, canon, col, Geo::Line { dir: [0.0, 0.0] });
            self.cur = self.at(cur, self.normal(to));
            return Ok(());
        }
        let mut theta = angle(op, cur);
        let mut alpha = angle(op, p);
        let (beta, gamma) = if left {
            if theta < alpha {
                theta += TAU;
            }
            (theta - alpha - FRAC_PI_2, FRAC_PI_2)
        } else {
            if alpha < theta {
                alpha += TAU;
            }
            (alpha - theta - FRAC_PI_2, -FRAC_PI_2)
        };
        let end = polar(p, r, alpha + gamma);
        let mid = polar(op, r, alpha + gamma);
        let front_arc = match self.front().map(|q| q.geo) {
            Some(Geo::Arc { c, ccw, .. }) => Some((c, ccw)),
            _ => None,
        };
        // An "h": going over a round top onto a line that turns back beside it. LinuxCNC keeps
        // the tool above and beside it (a concave corner) rather than looping round.
        let h_shape = beta > PI - SMALL
            && front_arc.is_some_and(|(_, ccw)| ccw != left)
            && !self.queue.is_empty();
        let concave = !(-SMALL..=PI + SMALL).contains(&beta) || h_shape;
        let cz = self.normal(self.cur);
        if !concave && beta > SMALL {
            // Convex: round the programmed corner (a rapid goes straight to the arc's end).
            self.move_ends_and_emit(x, cur, col)?;
            let c = if rapid {
                T::straight(true, self.at(mid, cz), feed)
            } else {
                self.plane_arc(self.at(mid, cz), op, !left, feed)
            };
            x.put_now(c, col);
            self.endpoint = Some(mid);
        } else if concave {
            let q = self.front().map(|q| (q.geo, q.end(self.ax)));
            let meet = match q.map_or(Geo::Other, |q| q.0) {
                Geo::Arc {
                    c: pc, ccw: pccw, ..
                } => {
                    // Arc to line: where the held arc's offset circle meets the new offset line.
                    let oldrad = dist(pc, q.map_or([0.0; 2], |q| q.1));
                    let base = angle(op, p);
                    let th = if pccw {
                        base + FRAC_PI_2
                    } else {
                        base - FRAC_PI_2
                    };
                    let phi = angle(op, pc);
                    let inside = pccw == left;
                    let uncomp = if inside { oldrad + r } else { oldrad - r };
                    let d = uncomp * (th - phi).cos();
                    let l = if inside { d - r } else { d + r } / oldrad;
                    if !(-1.0..=1.0).contains(&l) {
                        return Err(gouge(
                            x,
                            col,
                            "the corner between the arc before and this straight move",
                        ));
                    }
                    let a = if inside == pccw {
                        -l.acos() + th + PI
                    } else {
                        l.acos() + th + PI
                    };
                    polar(pc, oldrad, a)
                }
                _ => {
                    // Line to line: back along the held move by the corner's retreat.
                    let half = (beta + PI) / 2.0;
                    if half == 0.0 {
                        return Err(x.error(
                            col,
                            format!("a corner of zero degrees cannot be cut with {comp}"),
                        ));
                    }
                    polar(cur, r / half.tan(), theta + gamma)
                }
            };
            if meet.iter().any(|v| !v.is_finite()) {
                return Err(x.error(
                    col,
                    format!("{comp}'s offset path is not a finite number here"),
                ));
            }
            self.move_ends_and_emit(x, meet, col)?;
        } else {
            // Tangent: on from where the held move ends.
            self.emit(x);
            self.endpoint = Some(cur);
        }
        let canon = T::straight(rapid, self.at(end, self.normal(to)), feed);
        self.enqueue(
            x,
            canon,
            col,
            Geo::Line {
                dir: [p[0] - op[0], p[1] - op[1]],
            },
        );
        self.cur = self.at(end, self.normal(to));
        self.prog = p;
        Ok(())
    }

    /// An arc from `s` to `e` about `centre` (programmed, machine mm).
    #[allow(clippy::too_many_arguments)]
    pub fn arc(
        &mut self,
        x: &mut impl Sink<T>,
        s: [f64; 3],
        e: [f64; 3],
        centre: [f64; 3],
        plane: Plane,
        ccw: bool,
        feed: T::Feed,
        col: u32,
    ) -> Result<(), TranslateError> {
        let (comp, tool) = T::NAMES;
        if self.arc_not_allowed {
            return Err(x.error(
                col,
                "the move after G40 must be a straight line (G00 or G01), not an arc",
            ));
        }
        self.exit_pending = false;
        if !self.offsetting() {
            x.put_now(T::arc(e, centre, plane, ccw, feed), col);
            return Ok(());
        }
        let left = self.side == Side::Left;
        let r = self.r;
        let c = self.uv(centre);
        let ep = self.uv(e);
        let inside = ccw == left;
        // The arc's radius as programmed: from the start for the entry, to the end otherwise.
        let rr = if self.first {
            dist(c, self.uv(s))
        } else {
            dist(c, ep)
        };
        if inside && rr <= r {
            return Err(x.error(
                col,
                format!(
                    "gouge: {comp} puts the {tool} (radius {r:.4} mm) inside this arc of radius {rr:.4} mm, which is not larger than the {tool}"
                ),
            ));
        }
        let min = MIN_RADIUS_PULSES * x.pulse_mm();
        if inside && rr - r < min {
            return Err(x.error(
                col,
                format!(
                    "{comp} ({tool} radius {r:.4} mm) leaves this arc of radius {rr:.4} mm a radius of {:.4} mm, too small to cut (at least {min:.4} mm)",
                    rr - r
                ),
            ));
        }
        // Where the tool ends: one radius from the programmed end, toward the centre if inside.
        let gamma = if inside { angle(ep, c) } else { angle(c, ep) };
        let new_end = polar(ep, r, gamma);
        if self.first {
            return self.entry_arc(x, s, e, c, ccw, feed, col, new_end);
        }
        let op = self.prog;
        let cur = self.uv(self.cur);
        let theta = angle(op, cur) + if left { -FRAC_PI_2 } else { FRAC_PI_2 };
        let mut delta = angle(op, c);
        let alpha = if ccw {
            delta - FRAC_PI_2
        } else {
            delta + FRAC_PI_2
        };
        let mut beta = if left { theta - alpha } else { alpha - theta };
        if beta > 1.5 * PI {
            beta -= TAU;
        } else if beta < -FRAC_PI_2 {
            beta += TAU;
        }
        if !inside {
            delta += PI;
        }
        let concave = !(-SMALL..=PI + SMALL).contains(&beta)
            // A convex corner on a tangent join, as atop the middle of an "m".
            || ((beta - PI).abs() < SMALL && !inside);
        let geo = Geo::Arc {
            c,
            ccw,
            sweep: find_turn(op, c, ccw, ep),
        };
        let canon = self.plane_arc(self.at(new_end, self.normal(e)), c, ccw, feed);
        let cz = self.normal(self.cur);
        if concave {
            let arc_radius = dist(c, ep);
            let front = self.front().cloned();
            let meet = match front.as_ref().map(|q| (q.geo, q.end(self.ax))) {
                Some((
                    Geo::Arc {
                        c: pc, ccw: pccw, ..
                    },
                    pend,
                )) => {
                    // Arc to arc: where the two offset circles meet.
                    let oldrad = dist(pc, pend);
                    let newrad = if inside {
                        arc_radius - r
                    } else {
                        arc_radius + r
                    };
                    let cc = dist(pc, c);
                    if oldrad == 0.0 || cc == 0.0 {
                        return Err(x.error(
                            col,
                            format!(
                                "{comp} cannot join two arcs about the same centre at a corner"
                            ),
                        ));
                    }
                    let a = (oldrad * oldrad + cc * cc - newrad * newrad) / (2.0 * oldrad * cc);
                    if !(-1.0..=1.0).contains(&a) {
                        return Err(gouge(
                            x,
                            col,
                            "the corner between the arc before and this arc",
                        ));
                    }
                    let pull = a.acos();
                    let dir = angle(pc, c);
                    let prev_inside = pccw == left;
                    let d = if prev_inside == ccw {
                        dir + pull
                    } else {
                        dir - pull
                    };
                    polar(pc, oldrad, d)
                }
                _ => {
                    // Line to arc: where the held line's offset meets this arc's offset circle.
                    let cy = arc_radius * (beta - FRAC_PI_2).sin();
                    let (from_centre, toward) = if inside {
                        (arc_radius - r, cy + r)
                    } else {
                        (arc_radius + r, cy - r)
                    };
                    let l = toward / from_centre;
                    if !(-1.0..=1.0).contains(&l) {
                        return Err(gouge(
                            x,
                            col,
                            "the corner between the straight move before and this arc",
                        ));
                    }
                    let a = match (inside, ccw) {
                        (true, true) => theta + l.asin(),
                        (true, false) => theta - l.asin(),
                        (false, true) => theta + PI - l.asin(),
                        (false, false) => theta + PI + l.asin(),
                    };
                    polar(c, from_centre, a)
                }
            };
            if meet.iter().any(|v| !v.is_finite()) {
                return Err(x.error(
                    col,
                    format!("{comp}'s offset path is not a finite number here"),
                ));
            }
            self.move_ends_and_emit(x, meet, col)?;
        } else if beta > SMALL {
            // Convex: an arc round the programmed corner, then this arc.
            let mid = polar(op, r, delta);
            self.emit(x);
            x.put_now(self.plane_arc(self.at(mid, cz), op, !left, feed), col);
            self.endpoint = Some(mid);
        } else {
            self.emit(x);
            self.endpoint = Some(cur);
        }
        self.enqueue(x, canon, col, geo);
        self.cur = self.at(new_end, self.normal(e));
        self.prog = ep;
        Ok(())
    }

    /// The entry arc (LinuxCNC's convert_arc_comp1): from where the tool stands to `new_end`,
    /// its centre where the line from `new_end` toward the programmed centre `c` is as far
    /// from both ends.
    #[allow(clippy::too_many_arguments)]
    fn entry_arc(
        &mut self,
        x: &mut impl Sink<T>,
        s: [f64; 3],
        e: [f64; 3],
        c: [f64; 2],
        ccw: bool,
        feed: T::Feed,
        col: u32,
        new_end: [f64; 2],
    ) -> Result<(), TranslateError> {
        let (comp, tool) = T::NAMES;
        let start = self.uv(s);
        let len = dist(start, self.uv(e));
        if len <= self.r {
            return Err(x.error(
                col,
                format!(
                    "the entry arc of {comp} ends {} mm from its start, not farther than the {tool} radius ({:.4} mm)",
                    crate::input_text::fixed(len, 4),
                    self.r
                ),
            ));
        }
        let half = dist(start, new_end) / 2.0;
        let ab = angle(new_end, c);
        let a = angle(new_end, start) - ab;
        if a.cos().abs() < 1e-6 {
            return Err(x.error(
                col,
                format!(
                    "the entry arc of {comp} has no circle from where the {tool} stands to one {tool} radius ({:.4} mm) off its end",
                    self.r
                ),
            ));
        }
        let centre = polar(new_end, half / a.cos(), ab);
        if centre.iter().any(|v| !v.is_finite()) {
            return Err(x.error(
                col,
                format!("{comp}'s offset path is not a finite number here"),
            ));
        }
        let canon = self.plane_arc(self.at(new_end, self.normal(e)), centre, ccw, feed);
        let geo = Geo::Arc {
            c: centre,
            ccw,
            sweep: find_turn(start, centre, ccw, new_end),
        };
        self.enqueue(x, canon, col, geo);
        self.first = false;
        self.prog = self.uv(e);
        self.cur = self.at(new_end, self.normal(e));
        Ok(())
    }
}
