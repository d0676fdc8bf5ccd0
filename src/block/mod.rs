//! Machine instruction blocks: the narrow interface between the translator (AP) and the pulse
//! core (NCBR/PGEN), held in the block buffer B1 (patent lines 283–357; docs/pulse-core.md).
//!
//! A block carries the axis amounts in pulses with their signs (direction and feed amount),
//! the motion kind, the feed rate and the M, S and T functions (claim 7). It also keeps the
//! absolute end point the translator computed, so that it can print as an ISO 6983 line
//! ([`iso`]).
//!
//! This module is the whole of what the pulse core knows of the program sources: blocks, the
//! statements they were generated from (as an opaque line number and text for the display),
//! and the error a source stops at. See `docs/pulse-core.md`.

pub mod iso;

pub use iso::{iso_line, iso_program, IsoWriter};

use std::fmt;

/// The most axes a channel has: X, Y, Z and the rotary axes A, B and C. Axis arrays are this
/// long; a machine uses X, Y, Z and the rotary axes its description gives
/// ([`crate::settings::MachineSettings::has_axis`]), and the rest stay 0 (docs/pulse-core.md,
/// "Axes").
pub const MAX_AXES: usize = 6;

/// The index of the first rotary axis, A (B is 4, C 5).
pub const FIRST_ROTARY: usize = 3;

/// One value per axis, X Y Z A B C, indexed 0 = X … 3 = A, 4 = B, 5 = C: positions, amounts and
/// counters of the kernel. An array of [`MAX_AXES`] (it derefs to it, so indexing and the
/// array's methods work); axes a machine does not have stay 0. It equals an X Y Z array
/// `[x, y, z]` when its rotary axes are 0, and prints as one then (and as `[x, y, z, a]` with
/// only A turned), so that what a 3-axis machine shows and records is unchanged.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct Axes<T = i64>(pub [T; MAX_AXES]);

impl<T> std::ops::Deref for Axes<T> {
    type Target = [T; MAX_AXES];
    #[inline(always)]
    fn deref(&self) -> &[T; MAX_AXES] {
        &self.0
    }
}

impl<T> std::ops::DerefMut for Axes<T> {
    #[inline(always)]
    fn deref_mut(&mut self) -> &mut [T; MAX_AXES] {
        &mut self.0
    }
}

impl<T: Copy + Default> Axes<T> {
    /// X, Y and Z (what the linear geometry works in).
    pub fn xyz(self) -> [T; 3] {
        [self.0[0], self.0[1], self.0[2]]
    }

    /// X, Y and Z with A `a` (B and C 0).
    pub fn with_a(xyz: [T; 3], a: T) -> Axes<T> {
        Axes::with_rotary(xyz, [a, T::default(), T::default()])
    }

    /// X, Y and Z with the rotary axes A, B and C at `abc`.
    pub fn with_rotary(xyz: [T; 3], abc: [T; 3]) -> Axes<T> {
        Axes([xyz[0], xyz[1], xyz[2], abc[0], abc[1], abc[2]])
    }

    /// A, B and C.
    pub fn rotary(self) -> [T; 3] {
        [self.0[3], self.0[4], self.0[5]]
    }

    /// Each axis by `f` of its index.
    #[inline(always)]
    pub fn from_fn(f: impl FnMut(usize) -> T) -> Axes<T> {
        Axes(std::array::from_fn(f))
    }

    /// Every axis `v`.
    pub fn splat(v: T) -> Axes<T> {
        Axes([v; MAX_AXES])
    }
}

impl<T: Copy + Default> From<[T; 3]> for Axes<T> {
    /// X Y Z, with A 0.
    fn from(v: [T; 3]) -> Axes<T> {
        Axes::with_a(v, T::default())
    }
}

impl<T> From<[T; MAX_AXES]> for Axes<T> {
    fn from(v: [T; MAX_AXES]) -> Axes<T> {
        Axes(v)
    }
}

impl<T: PartialEq + Default> PartialEq<[T; 3]> for Axes<T> {
    /// Equal to X Y Z when A, B and C are 0.
    fn eq(&self, o: &[T; 3]) -> bool {
        self.0[..3] == o[..] && self.0[FIRST_ROTARY..].iter().all(|v| *v == T::default())
    }
}

impl<T: PartialEq + Default> PartialEq<[T; 4]> for Axes<T> {
    /// Equal to X Y Z A when B and C are 0.
    fn eq(&self, o: &[T; 4]) -> bool {
        self.0[..4] == o[..] && self.0[4..].iter().all(|v| *v == T::default())
    }
}

impl PartialEq<Axes<i64>> for [i64; 3] {
    fn eq(&self, o: &Axes<i64>) -> bool {
        o == self
    }
}

impl<T: PartialEq> PartialEq<[T; MAX_AXES]> for Axes<T> {
    fn eq(&self, o: &[T; MAX_AXES]) -> bool {
        self.0 == *o
    }
}

impl<T: std::fmt::Debug + PartialEq + Default> std::fmt::Debug for Axes<T> {
    /// `[x, y, z]` when A, B and C are 0 (as a 3-axis array printed), else up to the last
    /// rotary axis not 0 (`[x, y, z, a]` with only A turned).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let n = (FIRST_ROTARY..MAX_AXES)
            .rev()
            .find(|&i| self.0[i] != T::default())
            .map_or(3, |i| i + 1);
        f.debug_list().entries(&self.0[..n]).finish()
    }
}

/// The motion a block commands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Motion {
    /// Positioning at the rapid rate (G00), distributed by POUT.
    Rapid,
    /// Linear contouring at the block's feed (G01), distributed by LINE and PCHK.
    Linear,
    /// Clockwise arc (G02) in the block's plane, seen from the positive end of its normal.
    ArcCw,
    /// Counter-clockwise arc (G03) in the block's plane, seen from the positive end of its
    /// normal.
    ArcCcw,
    /// Dwell for `dwell_ns` of machine time (G04).
    Dwell,
    /// No motion: only M, S and T functions.
    Aux,
}

/// The plane of an arc: G17 (XY), G18 (XZ) or G19 (YZ).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Plane {
    /// G17: X and Y, normal Z.
    #[default]
    XY,
    /// G18: X and Z, normal Y.
    XZ,
    /// G19: Y and Z, normal X.
    YZ,
}

impl Plane {
    /// The plane's two axes in X Y Z order, then its normal axis (0 = X, 1 = Y, 2 = Z).
    pub fn axes(self) -> [usize; 3] {
        match self {
            Plane::XY => [0, 1, 2],
            Plane::XZ => [0, 2, 1],
            Plane::YZ => [1, 2, 0],
        }
    }

    /// The plane's axes in the order in which a counter-clockwise turn (seen from the positive
    /// end of the normal) goes from the first to the second: X→Y, Z→X, Y→Z.
    pub fn turn_axes(self) -> [usize; 2] {
        match self {
            Plane::XY => [0, 1],
            Plane::XZ => [2, 0],
            Plane::YZ => [1, 2],
        }
    }

    /// The G code that selects the plane.
    pub fn g_code(self) -> &'static str {
        match self {
            Plane::XY => "G17",
            Plane::XZ => "G18",
            Plane::YZ => "G19",
        }
    }
}

/// One machine instruction block.
#[derive(Clone, Debug, PartialEq)]
pub struct Block {
    /// Block sequence number (the ISO `N` word), from 1.
    pub seq: u32,
    /// Source statement line (1-based) the block was generated from.
    pub stmt: u32,
    /// The motion kind.
    pub motion: Motion,
    /// Signed axis amounts in pulses, X, Y, Z, A: direction and feed amount.
    pub delta: Axes,
    /// Absolute machine position in pulses at the end of the block, as translated.
    pub end: Axes,
    /// Arc centre relative to the start point, pulses, in the two axes of `plane` in X Y Z
    /// order: (I, J) in XY, (I, K) in XZ, (J, K) in YZ; only for arcs. An arc whose `delta` is
    /// zero in both axes of its plane is a full circle; a `delta` along the plane's normal
    /// makes it a helix.
    pub center: Option<[i64; 2]>,
    /// The plane of an arc (G17 XY, the default; G18 XZ; G19 YZ); ignored by other motions.
    pub plane: Plane,
    /// Feed rate, mm/min, before override (0 for rapid, dwell and aux blocks).
    pub feed: f64,
    /// Dwell time, ns (only for `Motion::Dwell`).
    pub dwell_ns: u64,
    /// Spindle speed S, rpm, if the block sets it.
    pub s: Option<u32>,
    /// T code to select, if the block calls a tool.
    pub t: Option<u32>,
    /// Miscellaneous function M (3 forward, 4 reverse, 5 stop, 6 tool change, 30 end; from
    /// G-code also 0 stop, 1 optional stop, 2 end, 8 and 9 coolant).
    pub m: Option<u8>,
    /// Z follows the length of the tool in the spindle: the translator worked its Z out as
    /// tool-tip Z plus the tool's length. A length revised after translation (OFS during a
    /// hold or between single blocks) moves a block with Z motion by the difference, and a
    /// block without keeps the Z the machine is at (docs/pulse-core.md, "Tool length revised
    /// during a run"). False for moves to machine zero and for sources that apply a revised
    /// length only when asked (G-code's G43).
    pub tool_z: bool,
    /// An input or output the block sets or waits on (M62–M68, M19, M48–M53), done when the
    /// block is reached.
    pub io: Option<Io>,
    /// A probe move (G38.2 … G38.5 ×10: 382 … 385; Fanuc's G31 skip: 310, as G38.3): the
    /// move stops where the probe trips.
    pub probe: Option<u16>,
    /// The block is part of a tap (TAP, G84, G74): the feed is geared to the spindle, so the
    /// feed and spindle overrides are held at 100 % and a feed hold waits for the tap to be
    /// back out with the spindle forward (docs/pulse-core.md, "Tapping").
    pub tap: Tap,
    /// How `feed` is given: per minute (G94, the default) or per spindle revolution (G95, mm
    /// per revolution, the rate following the spindle's actual speed).
    pub feed_mode: FeedMode,
    /// G96 constant surface speed: the spindle speed follows the tool tip's distance from the
    /// spindle centreline (axis X) so that the surface moves at `m_per_min`, never above
    /// `limit_rpm`; `s` is then unset. None: G97, `s` is rpm.
    pub css: Option<Css>,
    /// A thread pass (G33, each pass of G76): the move waits for the spindle encoder's index,
    /// then its longest axis follows the encoder at `lead` mm per revolution and the other
    /// follows in proportion (a taper thread). Only with `Motion::Linear`. A thread block
    /// whose `tap` is `Tap::Part` goes on in the next thread block, which then starts where
    /// the encoder stands at its end rather than at an index (a G76 taper end, a chamfer).
    pub thread: Option<f64>,
    /// A meeting point with the machine's other channels (the kernel's sync table): a waiting
    /// M code, a chuck close that receives a work, a chuck open that delivers one.
    pub sync: Option<Sync>,
    /// The core answers the source with its clocks when this block ends (a Fanuc #3001/#3002
    /// read in a run: reading waits until the machine has executed every block before the
    /// line, docs/gcode.md "Fanuc dialect"). Set only on a block with nothing else to do.
    pub clocks: bool,
}

/// How a block's feed is given.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FeedMode {
    /// G94: mm per minute along the path.
    #[default]
    PerMin,
    /// G95: mm per spindle revolution along the path.
    PerRev,
}

/// G96 constant surface speed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Css {
    /// Surface speed, m/min.
    pub m_per_min: f64,
    /// Spindle speed limit, rpm (the D word, or the machine's maximum).
    pub limit_rpm: f64,
}

/// A block's meeting point with other channels (seed 004: receive, delivery and the waiting M
/// codes; lines 136–142, 288–304, 330–378).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sync {
    /// A waiting M code (M100–M199): the channel waits here until every channel in `with`
    /// (bit i = channel i+1, its own included) has reached the same code.
    Wait {
        /// The M code.
        m: u32,
        /// The channels that meet, bit i = channel i+1.
        with: u8,
    },
    /// M10, close the chuck: on an empty spindle, the receive point (wait for the supplier's
    /// offer, close on the work, wait until the supplier has let go).
    ChuckClose,
    /// M11, open the chuck: holding a work, the delivery point (wait until the receiver has
    /// closed on it, then open).
    ChuckOpen,
}

/// Whether a block belongs to a tap or a thread pass of several blocks, and which
/// (docs/pulse-core.md, "Tapping", "Thread passes").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Tap {
    /// Not a tap's; a thread block: the last of its pass.
    #[default]
    No,
    /// A tap's feed in, spindle reversal, dwell or feed out; a thread block: the pass goes on
    /// in the next block.
    Part,
    /// The tap's last block: the spindle forward again, the tap out of the hole.
    End,
}

/// An input or output action of a block (docs/gcode.md "Inputs and outputs").
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Io {
    /// M62/M63 (with the motion) or M64/M65 (at once): digital output `index` on or off.
    Digital {
        /// Output 0–63.
        index: u8,
        /// On (M62, M64) or off.
        on: bool,
        /// Synchronised with motion (M62/M63).
        synced: bool,
    },
    /// M67 (with the motion) or M68 (at once): analog output `index` to `value`.
    Analog {
        /// Output 0–63.
        index: u8,
        /// The value.
        value: f64,
        /// Synchronised with motion (M67).
        synced: bool,
    },
    /// M66: wait on input `index` (digital P or analog E) in `mode` (L0–L4) at most `timeout` s.
    Wait {
        /// Digital (P) or analog (E).
        digital: bool,
        /// Input 0–63.
        index: u8,
        /// L: 0 immediate, 1 rise, 2 fall, 3 high, 4 low.
        mode: u8,
        /// Q, seconds.
        timeout: f64,
    },
    /// M19: orient the spindle to `angle` degrees (P: 0 nearest, 1 forward, 2 backward).
    Orient {
        /// R, degrees.
        angle: f64,
        /// P.
        dir: u8,
    },
    /// M48–M51: whether the feed and the speed overrides act.
    Overrides {
        /// The feed override acts.
        feed: bool,
        /// The speed override acts.
        speed: bool,
    },
}

impl Block {
    /// A block with no motion and no functions, to fill in field by field.
    pub fn aux(seq: u32, stmt: u32, end: impl Into<Axes>) -> Block {
        Block {
            seq,
            stmt,
            motion: Motion::Aux,
            delta: Axes::default(),
            end: end.into(),
            center: None,
            plane: Plane::XY,
            feed: 0.0,
            dwell_ns: 0,
            s: None,
            t: None,
            m: None,
            tool_z: false,
            io: None,
            probe: None,
            tap: Tap::No,
            feed_mode: FeedMode::PerMin,
            css: None,
            thread: None,
            sync: None,
            clocks: false,
        }
    }

    /// The arc centre relative to the start as (I, J, K) pulses, 0 along the plane's normal;
    /// `None` for a block without a centre.
    pub fn centre3(&self) -> Option<[i64; 3]> {
        let c = self.center?;
        let [a, b, _] = self.plane.axes();
        let mut v = [0; 3];
        v[a] = c[0];
        v[b] = c[1];
        Some(v)
    }

    /// The absolute machine position in pulses where the block starts.
    pub fn start(&self) -> Axes {
        Axes::from_fn(|i| self.end[i] - self.delta[i])
    }
}

/// An error at a source statement: `LINE:COL: message`. Every program source (the
/// source-language translator, later the G-code reader) reports its errors with it.
#[derive(Clone, Debug, PartialEq)]
pub struct TranslateError {
    /// 1-based source line.
    pub line: u32,
    /// 1-based column.
    pub col: u32,
    /// What is wrong, in a part programmer's words.
    pub message: String,
}

impl fmt::Display for TranslateError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}: {}", self.line, self.col, self.message)
    }
}

impl std::error::Error for TranslateError {}

/// One source statement and every block generated from it (what the display shows while
/// running: the statement, its blocks, and a marker on the executing one). To the pulse core
/// the line and text are opaque: it passes them on, it never reads them.
#[derive(Clone, Debug, PartialEq)]
pub struct Statement {
    /// 1-based source line (0 for a statement the console or the core made, e.g. a return).
    pub line: u32,
    /// The statement's source text.
    pub text: String,
    /// The blocks generated from it (empty for most definitions).
    pub blocks: Vec<Block>,
}

/// The machine's actual state where a program source starts translating: where the axes are,
/// which tool is in the spindle and how the spindle turns. The pulse core reports it; SEARCH
/// and MDI translate from it, so the blocks start from where the machine really is.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MachineState {
    /// Axis positions, pulses, machine coordinates.
    pub pos: Axes,
    /// T code of the tool in the spindle, if any.
    pub tool: Option<u32>,
    /// Spindle speed, rpm, signed (negative = reverse), 0 stopped.
    pub spindle: i64,
    /// Mist coolant on (M7; M9 and RESET turn it off).
    pub mist: bool,
    /// Flood coolant on (M8; M9 and RESET turn it off).
    pub flood: bool,
}

impl MachineState {
    /// A machine at `pos` with no tool in the spindle, the spindle stopped, coolant off.
    pub fn at(pos: impl Into<Axes>) -> MachineState {
        MachineState {
            pos: pos.into(),
            tool: None,
            spindle: 0,
            mist: false,
            flood: false,
        }
    }
}
