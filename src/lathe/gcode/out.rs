//! The emitter (docs/lathe-gcode.md "Tool offsets", "Nose-radius compensation", "Travel"):
//! programmed moves in mm become the kernel's blocks (`crate::block`, the one interface between
//! the language readers and the kernel) in pulses of the imaginary tip P, with the tool's
//! offsets added, G41/G42 applied, and every point checked against the channel's travel.
//!
//! - X (a radius) is axis 0, Z axis 2, Y stays 0; arcs are in `Plane::XZ`, their centre
//!   relative to the start as (I, K), counter-clockwise (G03) turning from +Z towards +X
//!   (`Plane::XZ.turn_axes()` is Z → X);
//! - a per-revolution feed is `feed_mode: PerRev`; G96 is `css` on every block while it is in
//!   force (it is modal, as the kernel reads it); a thread pass is a `Linear` block with
//!   `thread` (its lead, also its per-revolution feed);
//! - the spindle's state is M3/M4/M5 with `s` (G97) or `css` (G96); a tool is `t` alone (a
//!   turret indexes, no M6);
//! - M10, M11 and the waiting M codes are `sync` blocks; M00/M01 are m 0/1 (the reader has
//!   already dropped M01 with OPTIONAL STOP off); the end is m 2 or 30, and nothing follows it;
//! - the blocks of one source line make one statement (a G70 repeating a profile line makes a
//!   statement of that line again).
//!
//! Internally points are in the turning order of G18, `[Z, X]` (X a radius), so that a
//! counter-clockwise arc turns from +Z towards +X.

use super::comp;
use super::MAX_STEPS;
use crate::block::{Block, Css, FeedMode, Motion, Plane, Statement, Sync, Tap, TranslateError};
use crate::gcode::comp::{Comp, Held as _, Sink};
use crate::lathe::desc::{ChannelDesc, LatheDesc, ToolDesc};
use crate::limits::{MAX_MOVE_S, MIN_FEED};

/// A feed move's rate: mm per minute (G94) or mm per revolution (G95), as a block has it.
pub type Feed = (f64, FeedMode);

/// A block with no motion, for the reader to fill in (its place is set when it is emitted).
pub fn aux() -> Block {
    Block::aux(0, 0, [0, 0, 0])
}

/// A waiting M code's or the chuck's block.
pub fn sync(s: Sync) -> Block {
    Block {
        sync: Some(s),
        ..aux()
    }
}

/// An M code's block (M00, M01, M02, M30; the coolant's M07, M08, M09).
pub fn m(code: u8) -> Block {
    Block {
        m: Some(code),
        ..aux()
    }
}

/// What a programmed move is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Kind {
    /// G00.
    Rapid,
    /// G01.
    Line(Feed),
    /// G02/G03 about the absolute centre `[Z, X]` mm.
    Arc {
        /// Centre, `[Z, X]` mm.
        c: [f64; 2],
        /// Counter-clockwise (G03).
        ccw: bool,
        /// The feed.
        feed: Feed,
    },
    /// G33 or a G76 pass, lead mm per revolution.
    Thread(f64),
}

/// One programmed move, `[Z, X]` mm, X a radius.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mv {
    /// What it is.
    pub kind: Kind,
    /// Start point.
    pub start: [f64; 2],
    /// End point.
    pub end: [f64; 2],
    /// Source line.
    pub line: u32,
    /// Column of the word that made the move.
    pub col: u32,
}

/// What nose-radius compensation (the mill's `crate::gcode::comp::Comp`, LinuxCNC's rules)
/// holds and hands on for the lathe: the nose centre's moves in `[X, 0, Z]` mm (X a radius,
/// before the tool's offsets), and blocks without motion that wait behind them.
#[derive(Clone, Debug, PartialEq)]
pub enum Item {
    /// G00 to a point.
    Rapid([f64; 3]),
    /// G01 to a point.
    Line([f64; 3], Feed),
    /// G02/G03 to `end` about `centre`.
    Arc {
        /// End point.
        end: [f64; 3],
        /// Centre.
        centre: [f64; 3],
        /// Counter-clockwise (G03).
        ccw: bool,
        /// The feed.
        feed: Feed,
    },
    /// A block without motion.
    Op(Box<Block>),
}

impl crate::gcode::comp::Held for Item {
    type Feed = Feed;
    const NAMES: (&'static str, &'static str) = ("nose-radius compensation", "nose");
    fn straight(rapid: bool, end: [f64; 3], feed: Feed) -> Item {
        if rapid {
            Item::Rapid(end)
        } else {
            Item::Line(end, feed)
        }
    }
    fn arc(end: [f64; 3], centre: [f64; 3], _plane: Plane, ccw: bool, feed: Feed) -> Item {
        Item::Arc {
            end,
            centre,
            ccw,
            feed,
        }
    }
    fn end(&self) -> Option<[f64; 3]> {
        match self {
            Item::Rapid(e) | Item::Line(e, _) | Item::Arc { end: e, .. } => Some(*e),
            Item::Op(_) => None,
        }
    }
    fn set_end(&mut self, p: [f64; 3]) {
        if let Item::Rapid(e) | Item::Line(e, _) | Item::Arc { end: e, .. } = self {
            *e = p;
        }
    }
}

/// What compensation has handed on and the emitter has not yet emitted, and the line it is
/// reading (compensation charges its refusals to it).
#[derive(Debug, Default)]
struct Handed {
    line: u32,
    pulse_mm: f64,
    items: Vec<(Item, u32, u32)>,
}

impl Sink<Item> for Handed {
    fn line(&self) -> u32 {
        self.line
    }
    fn put(&mut self, item: Item, line: u32, col: u32) {
        self.items.push((item, line, col));
    }
    fn pulse_mm(&self) -> f64 {
        self.pulse_mm
    }
}

/// A point `[Z, X]` as compensation has it, `[X, 0, Z]`.
fn xyz(p: [f64; 2]) -> [f64; 3] {
    [p[1], 0.0, p[0]]
}

/// A point `[X, 0, Z]` as the emitter has it, `[Z, X]`.
fn zx(p: [f64; 3]) -> [f64; 2] {
    [p[2], p[0]]
}

/// Why the exit move must be straight.
const EXIT: &str = "the move after G40 (the exit move) must be a straight line (G00 or G01)";

/// Why the entry move on the other side must be straight.
const SIDE_CHANGE: &str = "the move after G41/G42 changed the side (the entry move on the other side) must be a straight line (G00 or G01)";

/// The emitter's state.
pub struct Out<'a> {
    desc: &'a LatheDesc,
    chan: &'a ChannelDesc,
    ch: usize,
    /// The statements so far (their text is filled in at the end, from the source lines).
    pub statements: Vec<Statement>,
    /// The blocks so far.
    blocks: usize,
    /// The programmed position of P, `[Z, X]` mm (before offsets and compensation).
    pub pos: [f64; 2],
    /// The tool in place and whether its offsets apply.
    tool: Option<(ToolDesc, bool)>,
    /// G41 (true) or G42 (false) in force.
    comp_side: Option<bool>,
    /// Nose-radius compensation: the mill's, LinuxCNC's rules, in the Z–X plane (on from the
    /// entry move, the first after G41/G42, with the nose radius of the tool then in place).
    comp: Comp<Item>,
    /// What it handed on, to emit.
    handed: Handed,
    /// From the nose centre to the imaginary tip P, `[Z, X]` mm: R·v(tip) of the tool the entry
    /// move found.
    tip_shift: [f64; 2],
    /// Where P stands after what compensation has handed on, `[Z, X]` mm.
    comp_at: [f64; 2],
    /// The next move must be a straight line, and why: the exit move after G40, or the entry
    /// move on the other side after G41/G42 changed it.
    straight_next: Option<&'static str>,
    /// G41.1/G42.1's nose radius (mm) and tip, in place of the tool's.
    dynamic: Option<(f64, u8)>,
    /// G71 collects its profile here instead of emitting it.
    pub capture: Option<Vec<Mv>>,
    /// Where the last emitted move ended, pulses [X, Z].
    at: [i64; 2],
    /// The spindle speed programmed last, rpm or G96's (the reader's order), for the time a
    /// feed per revolution takes.
    speed: (f64, Option<Css>),
    /// G96 as the emitted blocks have it in force (the order of the blocks: a spindle block
    /// held behind moves under compensation takes effect where it is emitted).
    css: Option<Css>,
    /// M02 or M30 was emitted: nothing follows it.
    ended: bool,
    /// What the blocks emitted now belong to (a G84 tap's, docs/pulse-core.md "Tapping"):
    /// set by [`Out::set_tap`], back to `Tap::No` after the block marked `Tap::End`.
    tap: Tap,
    /// The feed codes, per minute and per revolution, the messages name: G94 and G95 (G code
    /// system B), or G98 and G99 (system A).
    pub feed_codes: (&'static str, &'static str),
}

impl<'a> Out<'a> {
    /// A new emitter with the tool at the channel's reference position.
    pub fn new(desc: &'a LatheDesc, ch: usize) -> Out<'a> {
        let chan = &desc.channels[ch.min(desc.channels.len().saturating_sub(1))];
        Out {
            desc,
            chan,
            ch,
            statements: Vec::new(),
            blocks: 0,
            pos: [chan.axes[1].travel[1], chan.axes[0].travel[1]],
            tool: None,
            comp_side: None,
            comp: Comp::default(),
            handed: Handed {
                pulse_mm: desc.pulse_mm,
                ..Default::default()
            },
            tip_shift: [0.0; 2],
            comp_at: [0.0; 2],
            straight_next: None,
            dynamic: None,
            capture: None,
            at: super::home(desc, ch),
            speed: (0.0, None),
            css: None,
            ended: false,
            tap: Tap::No,
            feed_codes: ("G94", "G95"),
        }
    }

    fn err(line: u32, col: u32, message: impl Into<String>) -> TranslateError {
        TranslateError {
            line,
            col,
            message: message.into(),
        }
    }

    /// Whether G41 or G42 is in force.
    pub fn comp_on(&self) -> bool {
        self.comp_side.is_some()
    }

    /// G41 (true) or G42 (false), if either is in force.
    pub fn comp_side(&self) -> Option<bool> {
        self.comp_side
    }

    /// The tool in place.
    pub fn tool(&self) -> Option<&ToolDesc> {
        self.tool.as_ref().map(|t| &t.0)
    }

    /// The offsets of the tool in place, `[Z, X]` mm (X a radius), what [`Out::emit`] adds to a
    /// programmed point; zero without a tool or with its offsets off (T0100).
    pub fn offset(&self) -> [f64; 2] {
        match &self.tool {
            Some((t, true)) => [t.offset[1], t.offset[0]],
            _ => [0.0, 0.0],
        }
    }

    /// Turns the offsets of the tool in place on or off (G43, G49); false without a tool.
    pub fn set_offsets(&mut self, on: bool) -> bool {
        match self.tool.as_mut() {
            Some(t) => {
                t.1 = on;
                true
            }
            None => false,
        }
    }

    /// Whether the tool in place has its offsets applied (T0101, not T0100).
    pub fn offsets_on(&self) -> bool {
        self.tool.as_ref().is_some_and(|t| t.1)
    }

    /// The tool in place, by number, and whether its offsets apply.
    pub fn tool_in_place(&self) -> Option<(u32, bool)> {
        self.tool.as_ref().map(|(t, o)| (t.number, *o))
    }

    /// The tool post stands at `at` (pulses [X, Z]) before the first line: the programmed
    /// position is P less the offsets of the tool in place.
    pub fn start_at(&mut self, at: [i64; 2]) {
        let off = match &self.tool {
            Some((t, true)) => t.offset,
            _ => [0.0, 0.0],
        };
        self.at = at;
        let mm = |p: i64| p as f64 * self.desc.pulse_mm;
        self.pos = [mm(at[1]) - off[1], mm(at[0]) - off[0]];
    }

    /// Puts a tool in place (its offsets applying if `offsets`).
    pub fn set_tool(&mut self, t: ToolDesc, offsets: bool) {
        if self.capture.is_some() {
            return;
        }
        self.tool = Some((t, offsets));
    }

    /// Emits one block: its sequence number, its line and where it starts and ends.
    fn push(&mut self, line: u32, col: u32, mut b: Block) -> Result<(), TranslateError> {
        if self.ended {
            return Ok(());
        }
        if self.blocks >= MAX_STEPS {
            return Err(Self::err(
                line,
                col,
                format!("the program makes more than {MAX_STEPS} operations"),
            ));
        }
        self.blocks += 1;
        let start = [self.at[0], 0, self.at[1]];
        b.tap = self.tap;
        if self.tap == Tap::End {
            self.tap = Tap::No;
        }
        b.seq = self.blocks as u32;
        b.stmt = line;
        if b.motion == Motion::Aux || b.motion == Motion::Dwell {
            b.end = start.into();
        }
        if matches!(b.m, Some(3..=5)) {
            self.css = b.css;
        }
        b.css = self.css;
        b.delta = [b.end[0] - start[0], 0, b.end[2] - start[2]].into();
        self.at = [b.end[0], b.end[2]];
        self.ended = matches!(b.m, Some(2 | 30));
        match self.statements.last_mut() {
            Some(s) if s.line == line => s.blocks.push(b),
            _ => self.statements.push(Statement {
                line,
                text: String::new(),
                blocks: vec![b],
            }),
        }
        Ok(())
    }

    /// Marks the blocks emitted from now on as a tap's (`Tap::Part`), the next one as its last
    /// (`Tap::End`, after which the marks stop), or none: the mill's `Canon::Tap`, for G84.
    pub fn set_tap(&mut self, t: Tap) {
        self.tap = t;
    }

    /// A block without motion (a tool, a wait, the chuck, a stop, a dwell, the end). Under
    /// compensation it waits behind the held moves; in a G71 profile it is dropped.
    pub fn op(&mut self, line: u32, col: u32, b: Block) -> Result<(), TranslateError> {
        if self.capture.is_some() {
            return Ok(());
        }
        // M00, M01, M02 and M30 emit what compensation holds as it stands (LinuxCNC's flush).
        if matches!(b.m, Some(0 | 1 | 2 | 30)) {
            self.handed.line = line;
            self.comp.flush(&mut self.handed, col)?;
            self.drain()?;
        }
        if matches!(b.m, Some(2 | 30)) {
            self.comp = Comp::default();
            self.comp_side = None;
            self.straight_next = None;
            self.dynamic = None;
        }
        if self.comp.offsetting() {
            self.handed.line = line;
            self.comp.aux(&mut self.handed, Item::Op(Box::new(b)), col);
            return self.drain();
        }
        self.push(line, col, b)
    }

    /// The spindle's full commanded state after an M03/M04/M05, S, G96 or G97: `m` 3, 4 or 5
    /// at `rpm` (G97) or at G96's surface speed.
    /// The spindle already turning when the read begins (the machine's, as the last cycle
    /// left it): `rpm` under G97, or `css`; no block (the machine turns it already).
    pub fn set_speed(&mut self, rpm: f64, css: Option<Css>) {
        self.speed = (rpm, css);
        // Under G96 every block carries the surface speed, from the first (before stop 39 the
        // blocks of a read begun with the spindle turning under G96 carried none, and the
        // kernel let the spindle run down under a feed per revolution).
        self.css = css;
    }

    pub fn spindle(
        &mut self,
        line: u32,
        col: u32,
        m: u8,
        rpm: f64,
        css: Option<Css>,
    ) -> Result<(), TranslateError> {
        if self.capture.is_some() {
            return Ok(());
        }
        self.speed = (rpm, css);
        let b = Block {
            m: Some(m),
            s: css
                .is_none()
                .then(|| rpm.clamp(0.0, f64::from(u32::MAX)) as u32),
            css,
            ..aux()
        };
        self.op(line, col, b)
    }

    /// G41 (`left`) or G42.
    pub fn comp_start(&mut self, left: bool, line: u32, col: u32) -> Result<(), TranslateError> {
        if self.capture.is_some() {
            return Ok(());
        }
        if self.straight_next == Some(EXIT) {
            return Err(Self::err(
                line,
                col,
                "G41/G42 after G40 before its exit move: give the exit move first",
            ));
        }
        if let Some(side) = self.comp_side {
            self.dynamic = None;
            if side != left {
                // The thesis (seed 003, line 2556): the side may change from block to block
                // without G40. The held moves end one radius off their last point; the next
                // move is a new entry move on the other side.
                self.handed.line = line;
                let entered = self.comp.entered();
                self.comp.off(&mut self.handed, col)?;
                self.drain()?;
                self.comp = Comp::default();
                self.comp_side = Some(left);
                if entered {
                    self.straight_next = Some(SIDE_CHANGE);
                }
            }
            return Ok(());
        }
        if self.tool.is_none() {
            return Err(Self::err(
                line,
                col,
                "nose-radius compensation needs a tool: give a T word first",
            ));
        }
        self.comp_side = Some(left);
        Ok(())
    }

    /// LinuxCNC's G41.1 (`left`) or G42.1: compensation with a nose of `radius` mm and tip
    /// `tip` (Fanuc's chart) given on the line, whatever tool is in place.
    pub fn comp_start_dynamic(
        &mut self,
        left: bool,
        radius: f64,
        tip: u8,
        line: u32,
        col: u32,
    ) -> Result<(), TranslateError> {
        if self.capture.is_some() {
            return Ok(());
        }
        if self.straight_next == Some(EXIT) {
            return Err(Self::err(
                line,
                col,
                "G41.1/G42.1 after G40 before its exit move: give the exit move first",
            ));
        }
        if self.comp_side.is_some() {
            return Err(Self::err(
                line,
                col,
                "G41.1/G42.1 with compensation in force: give G40 first",
            ));
        }
        self.comp_side = Some(left);
        self.dynamic = Some((radius, tip));
        Ok(())
    }

    /// G40: what compensation holds is emitted, the last move ending one radius off its
    /// end; the next move, the exit move, runs from there to its programmed end and must be
    /// straight.
    pub fn comp_stop(&mut self, line: u32, col: u32) -> Result<(), TranslateError> {
        if self.capture.is_some() {
            return Ok(());
        }
        if self.comp.entered() {
            self.straight_next = Some(EXIT);
        }
        self.handed.line = line;
        self.comp.off(&mut self.handed, col)?;
        self.comp = Comp::default();
        self.comp_side = None;
        self.dynamic = None;
        self.drain()
    }

    /// G20 (`inch`) or G21: compensation states its tolerances in the program's units.
    pub fn set_inch(&mut self, inch: bool) {
        self.comp.set_inch(inch);
    }

    /// One programmed move from `pos` to `mv.end`.
    pub fn motion(&mut self, mut mv: Mv) -> Result<(), TranslateError> {
        mv.start = self.pos;
        if self.capture.is_none() {
            self.check_time(&mv)?;
        }
        self.pos = mv.end;
        if let Some(cap) = self.capture.as_mut() {
            if cap.len() >= super::MAX_PASSES * 4 {
                return Err(Self::err(
                    mv.line,
                    mv.col,
                    format!(
                        "the cycle's profile is too long (more than {} moves)",
                        super::MAX_PASSES * 4
                    ),
                ));
            }
            cap.push(mv);
            return Ok(());
        }
        if let Some(why) = self.straight_next.take() {
            if matches!(mv.kind, Kind::Arc { .. }) {
                return Err(Self::err(mv.line, mv.col, why));
            }
        }
        let Some(left) = self.comp_side else {
            return self.emit(&mv);
        };
        if let Kind::Thread(_) = mv.kind {
            return Err(Self::err(
                mv.line,
                mv.col,
                "threading with nose-radius compensation in force: give G40 first",
            ));
        }
        let len = (mv.end[0] - mv.start[0]).hypot(mv.end[1] - mv.start[1]);
        let arc = matches!(mv.kind, Kind::Arc { .. });
        if len < 1e-9 && !arc {
            return Ok(());
        }
        if !self.comp.active() {
            // The entry move: compensation takes the nose radius and tip of the tool in place.
            let (r, tip) = match (self.dynamic, self.tool()) {
                (Some(d), _) => d,
                (None, Some(t)) => (t.radius, t.tip),
                (None, None) => (0.0, 0),
            };
            if r <= 0.0 {
                return self.emit(&mv);
            }
            self.comp.on(left, r, Plane::XZ);
            let v = comp::tip_vector(tip);
            self.tip_shift = [v[0] * r, v[1] * r];
            self.comp_at = mv.start;
            if let (Kind::Arc { feed, .. }, true) = (mv.kind, v != [0.0, 0.0]) {
                // An entry arc starts from the nose centre where the tool stands: P first moves
                // onto that arc's start, a feed move R·v(tip) long, as LinuxCNC's
                // convert_arc_comp1 makes it ("otherwise, the arc isn't an arc").
                let to = [
                    mv.start[0] + self.tip_shift[0],
                    mv.start[1] + self.tip_shift[1],
                ];
                let first = Mv {
                    kind: Kind::Line(feed),
                    end: to,
                    ..mv
                };
                self.comp_at = to;
                self.emit(&first)?;
            }
        }
        self.handed.line = mv.line;
        let (s, e) = (xyz(mv.start), xyz(mv.end));
        let h = &mut self.handed;
        match mv.kind {
            Kind::Rapid => self
                .comp
                .line(h, s, e, true, (0.0, FeedMode::PerMin), mv.col)?,
            Kind::Line(f) => self.comp.line(h, s, e, false, f, mv.col)?,
            Kind::Arc { c, ccw, feed } => {
                (self.comp).arc(h, s, e, xyz(c), Plane::XZ, ccw, feed, mv.col)?
            }
            Kind::Thread(_) => {}
        }
        self.drain()
    }

    /// Emits what compensation has handed on: its moves of the nose centre as moves of P (the
    /// tip vector added), and the blocks that waited behind them.
    fn drain(&mut self) -> Result<(), TranslateError> {
        let sh = self.tip_shift;
        let p = |q: [f64; 3]| {
            let q = zx(q);
            [q[0] + sh[0], q[1] + sh[1]]
        };
        for (item, line, col) in std::mem::take(&mut self.handed.items) {
            let kind = match item {
                Item::Op(b) => {
                    self.push(line, col, *b)?;
                    continue;
                }
                Item::Rapid(_) => Kind::Rapid,
                Item::Line(_, f) => Kind::Line(f),
                Item::Arc {
                    centre, ccw, feed, ..
                } => Kind::Arc {
                    c: p(centre),
                    ccw,
                    feed,
                },
            };
            let end = p(item.end().unwrap_or_default());
            let mv = Mv {
                kind,
                start: self.comp_at,
                end,
                line,
                col,
            };
            self.comp_at = end;
            self.emit(&mv)?;
        }
        Ok(())
    }

    /// At the end of the text: emits what compensation still holds.
    pub fn finish(&mut self) -> Result<(), TranslateError> {
        // A refusal is charged to the last line read, at its start (the mill's rule).
        self.comp.flush(&mut self.handed, 1)?;
        self.drain()
    }

    /// Emits one move of P, adding the tool's offsets and checking the travel.
    fn emit(&mut self, mv: &Mv) -> Result<(), TranslateError> {
        let off = self.offset();
        let e = [mv.end[0] + off[0], mv.end[1] + off[1]];
        self.check_travel(e, mv)?;
        let end = [self.desc.pulses(e[1]), self.desc.pulses(e[0])];
        let mut b = Block {
            end: [end[0], 0, end[1]].into(),
            ..aux()
        };
        let feed = |b: &mut Block, (f, mode): Feed| {
            b.feed = f;
            b.feed_mode = mode;
        };
        match mv.kind {
            Kind::Rapid => b.motion = Motion::Rapid,
            Kind::Line(f) => {
                b.motion = Motion::Linear;
                feed(&mut b, f);
            }
            Kind::Thread(lead) => {
                b.motion = Motion::Linear;
                feed(&mut b, (lead, FeedMode::PerRev));
                b.thread = Some(lead);
            }
            Kind::Arc { c, ccw, feed: f } => {
                let c = [c[0] + off[0], c[1] + off[1]];
                self.check_arc_travel(c, e, ccw, mv)?;
                b.motion = if ccw { Motion::ArcCcw } else { Motion::ArcCw };
                b.plane = Plane::XZ;
                // (I, K) from the start: the plane's axes in X Y Z order.
                b.center = Some([
                    self.desc.pulses(c[1]) - self.at[0],
                    self.desc.pulses(c[0]) - self.at[1],
                ]);
                feed(&mut b, f);
            }
        }
        if end == self.at {
            // A move that does not move in pulses is dropped: above all an arc, which would
            // read as a full circle (a tiny corner join of the compensation, rounded).
            let full = matches!(mv.kind, Kind::Arc { .. })
                && (mv.end[0] - mv.start[0]).abs() < 1e-9
                && (mv.end[1] - mv.start[1]).abs() < 1e-9;
            if !full {
                return Ok(());
            }
        }
        self.push(mv.line, mv.col, b)
    }

    /// A feed move at its feed: per minute at least the slowest feed, and at most
    /// [`MAX_MOVE_S`] long at the spindle speed programmed (the slowest it turns along the move
    /// under G96), since the simulator steps every tick of it (docs/limits.md).
    fn check_time(&self, mv: &Mv) -> Result<(), TranslateError> {
        let (s, e) = (mv.start, mv.end);
        let (per_rev, len, far) = match mv.kind {
            Kind::Rapid => return Ok(()),
            Kind::Line(f) => (
                f,
                (e[0] - s[0]).hypot(e[1] - s[1]),
                s[1].abs().max(e[1].abs()),
            ),
            Kind::Thread(lead) => (
                (lead, FeedMode::PerRev),
                (e[0] - s[0]).hypot(e[1] - s[1]),
                s[1].abs().max(e[1].abs()),
            ),
            Kind::Arc { c, ccw, feed } => {
                let r = (s[0] - c[0]).hypot(s[1] - c[1]);
                (
                    feed,
                    r * crate::gcode::geom::sweep(s, e, c, ccw),
                    c[1].abs() + r,
                )
            }
        };
        let mm_min = match per_rev {
            (f, FeedMode::PerMin) => {
                if f < MIN_FEED {
                    return Err(Self::err(
                        mv.line,
                        mv.col,
                        format!(
                            "{} ({} reads F per minute: {} reads it per revolution)",
                            crate::limits::feed_too_slow(&format!(
                                "F{}",
                                crate::input_text::short_number(f)
                            )),
                            self.feed_codes.0,
                            self.feed_codes.1
                        ),
                    ));
                }
                f
            }
            (f, FeedMode::PerRev) => {
                let rpm = match self.speed {
                    (r, None) => r,
                    (
                        _,
                        Some(Css {
                            m_per_min,
                            limit_rpm,
                        }),
                    ) => {
                        let at = m_per_min * 1000.0 / (std::f64::consts::TAU * far);
                        if at.is_finite() {
                            at.min(limit_rpm)
                        } else {
                            limit_rpm
                        }
                    }
                };
                f * rpm
            }
        };
        let secs = len / mm_min * 60.0;
        if secs.is_nan() || secs <= MAX_MOVE_S {
            return Ok(());
        }
        let why = if mm_min > 0.0 {
            format!(
                "this move takes {} s at the feed in force ({} mm/min)",
                crate::input_text::fixed(secs, 0),
                crate::input_text::short_number(mm_min)
            )
        } else {
            "this move never ends at the feed in force: the spindle stands at 0 rpm".to_string()
        };
        Err(Self::err(
            mv.line,
            mv.col,
            format!("{why}, more than the {MAX_MOVE_S} s one move may take"),
        ))
    }

    fn check_travel(&self, p: [f64; 2], mv: &Mv) -> Result<(), TranslateError> {
        for (axis, v, name) in [(0usize, p[1], "X"), (1, p[0], "Z")] {
            let t = self.chan.axes[axis].travel;
            if !(v >= t[0] - 1e-9 && v <= t[1] + 1e-9) {
                let what = if axis == 0 { " (radius)" } else { "" };
                return Err(Self::err(
                    mv.line,
                    mv.col,
                    format!(
                        "{name} {}{what} is outside channel {}'s {name} travel {} to {} mm",
                        crate::input_text::fixed(v, 3),
                        self.ch + 1,
                        t[0],
                        t[1]
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The arc's extreme points within its sweep must be inside the travel too.
    fn check_arc_travel(
        &self,
        c: [f64; 2],
        e: [f64; 2],
        ccw: bool,
        mv: &Mv,
    ) -> Result<(), TranslateError> {
        let r = (e[0] - c[0]).hypot(e[1] - c[1]);
        let s = [
            self.at[1] as f64 * self.desc.pulse_mm,
            self.at[0] as f64 * self.desc.pulse_mm,
        ];
        let a0 = (s[1] - c[1]).atan2(s[0] - c[0]);
        let sweep = crate::gcode::geom::sweep(s, e, c, ccw);
        for k in 0..4 {
            let q = k as f64 * std::f64::consts::FRAC_PI_2;
            let d = if ccw { q - a0 } else { a0 - q };
            let d = d.rem_euclid(std::f64::consts::TAU);
            if d < sweep {
                let p = [c[0] + r * q.cos(), c[1] + r * q.sin()];
                self.check_travel(p, mv)?;
            }
        }
        Ok(())
    }
}
