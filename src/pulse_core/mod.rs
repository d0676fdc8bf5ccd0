//! The pulse core: a thread that owns the simulated machine (X, Y and Z servo axes and the
//! relay logic for M, S, T) and does the patent's NCBR (5 ms real-time clock) and PGEN (each
//! counter period KT: POUT, LINE, PCHK) work (seed 000 lines 357–430, 486–530; docs/pulse-core.md).
//!
//! Layout (one module, one job; see `docs/pulse-core.md` for the timing and every choice):
//! - [`Machine`] (`machine.rs`): the machine as a pure, deterministic state machine advanced
//!   NCBR tick by NCBR tick; tests and benchmarks drive it directly, without threads.
//! - `motion.rs`: PGEN for one motion: LINE/PCHK with ΣLF, the KT ramp.
//! - `arc.rs`: circular interpolation by integer circle stepping.
//! - `pulse_out.rs`: the axis counters and the pulse log (recording batches, test capture).
//! - `source.rs`: the reading side of B1 ([`BlockSource`], [`VecSource`]).
//! - `b1.rs`: the bounded B1 shared with the translator thread.
//! - `runner.rs`: [`PulseCore`], the thread around the machine (virtual or real time).
//! - `realtime.rs`: the real-time step queue (events released at their time; e-stop rollback).
//!
//! What the console uses: [`PulseCore::spawn`], [`PulseCore::load`], [`PulseCore::command`],
//! [`PulseCore::status`] (a cheap snapshot, republished after every NCBR tick),
//! [`PulseCore::wait_idle`] (the script's `wait`), [`PulseCore::settings`],
//! [`PulseCore::set_magazine`] (set lengths for the tool readout),
//! [`PulseCore::set_panel_modes`] (mode names recorded in `/nc/state`) and
//! [`PulseCore::set_position`]. Faults show in [`Status::alarm`] (RESET clears them); refused
//! operator actions that are not alarms show in [`Status::notice`].

mod arc;
mod block_buffer;
mod machine;
mod motion;
mod pulse_out;
mod realtime;
mod runner;
mod source;
pub mod testkit;

pub use self::arc::{ArcError, ArcStep, ArcStepper};
pub use self::machine::{axis_name, Machine};
pub use self::motion::{accel_pulses_ns2, speed_pulses_ns};
pub use self::pulse_out::{PulseRec, BATCH};
pub use self::runner::{PulseCore, RtStats};
pub use self::source::{BlockSource, Fetch, VecSource};

use crate::translator::Statement;
use std::sync::Arc;

/// How machine time relates to the wall clock.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ClockMode {
    /// As fast as possible, deterministic (tests, dry runs, benchmarks, scripts).
    Virtual,
    /// Paced to the wall clock, pulses generated at most one NCBR tick ahead.
    RealTime,
}

/// What RUN is set to by START: 1 = AUTO (program memory), 2 = MDI.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RunKind {
    /// RUN = 1.
    Auto,
    /// RUN = 2.
    Mdi,
}

/// One entry of the block buffer B1: a block, by index into the statement it came from.
#[derive(Clone, Debug)]
pub struct B1Entry {
    /// The statement and all its blocks.
    pub stmt: Arc<Statement>,
    /// Which of `stmt.blocks` this entry is.
    pub index: usize,
}

impl B1Entry {
    /// The block this entry names, if the index is valid.
    pub fn block(&self) -> Option<&crate::block::Block> {
        self.stmt.blocks.get(self.index)
    }
}

/// Operator commands to the pulse core.
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// Cycle start: RUN = 1 or 2; resumes after a feed hold.
    Start(RunKind),
    /// Feed hold: decelerate to rest mid-block.
    Stop,
    /// Abandon the run, empty B1, machine idle; clears an e-stop.
    Reset,
    /// Pulses stop within one PGEN period; RESET required.
    EStop,
    /// Feed override percent, from the next NCBR tick.
    Override(u32),
    /// SINGLE BLOCK on or off: RUN is cleared after each block.
    SingleBlock(bool),
    /// CONTINUOUS jog: move axis (0..3) in direction ±1 at the jog feed until `JogRelease`.
    Jog {
        /// Axis 0 = X, 1 = Y, 2 = Z.
        axis: usize,
        /// +1 or −1.
        dir: i8,
    },
    /// End a CONTINUOUS jog (decelerate).
    JogRelease,
    /// Move an axis by a signed number of pulses at the jog feed (STEP and HANDLE).
    Increment {
        /// Axis 0 = X, 1 = Y, 2 = Z.
        axis: usize,
        /// Signed number of pulses.
        pulses: i64,
    },
}

/// A snapshot of the machine, published at display rate.
#[derive(Clone, Debug, Default)]
pub struct Status {
    /// RUN flag: 0 stopped, 1 AUTO, 2 MDI.
    pub run: u8,
    /// Feed hold in force.
    pub hold: bool,
    /// Emergency stop in force.
    pub estop: bool,
    /// The alarm shown to the operator (travel limit, translation error, ...).
    pub alarm: Option<String>,
    /// Axis positions, pulses, machine coordinates.
    pub pos: [i64; 3],
    /// The statement and block index executing (or last executed).
    pub executing: Option<B1Entry>,
    /// Blocks completed in this run.
    pub blocks_done: u64,
    /// Pulses output per axis in this run.
    pub pulses: [u64; 3],
    /// T code in the spindle.
    pub tool: Option<u32>,
    /// Set length of the tool in the spindle, mm (0 for none).
    pub tool_set_length: f64,
    /// Spindle rpm, signed (negative = reverse), 0 stopped.
    pub spindle: i64,
    /// Feed override in force, percent.
    pub feed_override: u32,
    /// Machine time, ns.
    pub machine_ns: u64,
    /// Whether any axis is moving.
    pub moving: bool,
    /// Whether the program (translator and B1) has been run to its end.
    pub program_end: bool,
    /// Nothing happens until the next command: no motion, nothing pending, and RUN = 0 (or a
    /// feed hold at rest, or an emergency stop).
    pub idle: bool,
    /// A refused operator action that is not an alarm (jog at a limit, START before RESET).
    pub notice: Option<String>,
    /// SINGLE BLOCK in force.
    pub single_block: bool,
    /// Path speed, mm/min.
    pub speed_mm_min: f64,
    /// Messages (commands, loads, settings) the core has applied so far.
    pub commands_applied: u64,
}
