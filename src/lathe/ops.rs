//! Lathe operations: what one channel's lathe G-code program becomes, and all the channel
//! simulator knows of the language (docs/lathe.md "Operations").
//!
//! Coordinates are the controlled point (the imaginary tool tip P of the thesis, seed 003 lines
//! 2552–2560) in the channel's work coordinates, in pulses of the machine's pulse size:
//! - X is a **radius** from the spindle centreline (the reader divides diameters by 2);
//! - Z is along the spindle, 0 at the work face.
//!
//! Arcs are in the Z–X plane. `ccw` is counter-clockwise with Z drawn to the right and X
//! upwards, that is turning from +Z towards +X (G18's turn, `Plane::XZ.turn_axes()`).

/// How a feed move's rate is given.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Feed {
    /// G94: mm per minute along the path.
    PerMin(f64),
    /// G95: mm per spindle revolution along the path (the rate follows the spindle).
    PerRev(f64),
}

/// The spindle's direction.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SpindleDir {
    /// M05.
    #[default]
    Stop,
    /// M03, clockwise seen from the tailstock end.
    Cw,
    /// M04.
    Ccw,
}

/// How the spindle speed is given.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SpeedMode {
    /// G97: revolutions per minute.
    Rpm(f64),
    /// G96: constant surface speed in m/min at the tool tip's diameter, never above
    /// `limit_rpm` (the D word, or the machine's maximum).
    Css {
        /// Surface speed, m/min.
        m_per_min: f64,
        /// Spindle speed limit, rpm.
        limit_rpm: f64,
    },
}

/// One operation of a channel's program.
#[derive(Clone, Debug, PartialEq)]
pub enum Op {
    /// G00 positioning at the rapid rate to `end` [X radius, Z] pulses. Never a cut.
    Rapid {
        /// End point, pulses.
        end: [i64; 2],
    },
    /// G01 straight cut to `end`.
    Line {
        /// End point, pulses.
        end: [i64; 2],
        /// The feed.
        feed: Feed,
    },
    /// G02/G03 arc cut in the Z–X plane to `end` about the absolute `centre`.
    Arc {
        /// End point, pulses.
        end: [i64; 2],
        /// Centre, absolute pulses [X, Z].
        centre: [i64; 2],
        /// Counter-clockwise from +Z towards +X (see the module comment).
        ccw: bool,
        /// The feed.
        feed: Feed,
    },
    /// G33 (and each pass of G76): a thread pass from where the tool is to `end`. The move
    /// starts at the spindle encoder's index, and Z then follows the encoder: `lead` mm of Z per
    /// revolution, X in proportion (a taper thread).
    Thread {
        /// End point, pulses.
        end: [i64; 2],
        /// Lead, mm per revolution.
        lead: f64,
    },
    /// G04 dwell, ns of machine time.
    Dwell {
        /// Duration, ns.
        ns: u64,
    },
    /// The spindle's full commanded state after an M03/M04/M05, S, G96 or G97.
    Spindle {
        /// Direction.
        dir: SpindleDir,
        /// Speed.
        mode: SpeedMode,
    },
    /// T word: the tool post indexes to tool `tool` (its nose radius and tip position apply
    /// from here).
    Tool {
        /// Tool number.
        tool: u32,
    },
    /// A waiting M code (M100–M199): the channel stops here until every channel in `with`
    /// (bit i = channel i+1, always including its own) has reached the same code.
    Wait {
        /// The M code.
        m: u32,
        /// Channels that meet here, bit i = channel i+1.
        with: u8,
    },
    /// M10: close the chuck. On an empty spindle this is the receive block's queue point:
    /// it waits until the supplier (the bar feeder, or the previous channel at its M11)
    /// offers a work, closes on it, then waits until the supplier has let go.
    ChuckClose,
    /// M11: open the chuck. Holding a work, this is the delivery block's queue point: it
    /// waits until the receiver (the next channel at its M10, or the unloader) has closed
    /// on the work, then opens.
    ChuckOpen,
    /// M00 (or M01 with OPTIONAL STOP on): the channel stops; START continues.
    Stop {
        /// True for M01.
        optional: bool,
    },
    /// M02/M30: end of the program. The channel counts the work it has finished, then
    /// rewinds for the next work, or finishes when its count reaches the target.
    End {
        /// True for M30.
        m30: bool,
    },
}

impl Op {
    /// True for the operations that cut (a machining block): a feed move, an arc or a thread
    /// pass. These must never start on an empty spindle.
    pub fn cuts(&self) -> bool {
        matches!(self, Op::Line { .. } | Op::Arc { .. } | Op::Thread { .. })
    }

    /// The end point of a motion, if this is one.
    pub fn end(&self) -> Option<[i64; 2]> {
        match self {
            Op::Rapid { end }
            | Op::Line { end, .. }
            | Op::Arc { end, .. }
            | Op::Thread { end, .. } => Some(*end),
            _ => None,
        }
    }
}

/// One operation with the source line it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct Step {
    /// 1-based source line.
    pub line: u32,
    /// The operation.
    pub op: Op,
}

/// A translated channel program: its source lines (for the display) and its steps.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LatheProgram {
    /// The program's name (its file name).
    pub name: String,
    /// The source text, one entry per line.
    pub lines: Vec<String>,
    /// The operations in order.
    pub steps: Vec<Step>,
}
