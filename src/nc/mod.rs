//! The pulse core: a thread that owns the simulated machine (X, Y, Z servo axes and the relay
//! logic for M, S, T) and does the patent's NCBR (5 ms real-time clock) and PGEN (each counter
//! period KT: POUT, LINE, PCHK) work (seed 000 lines 357–430, 486–530; SPEC §6).
//!
//! OWNER: pulse core work (issue 4). The signatures below are the contract with the console;
//! the bodies are to be written.

use crate::ap::Statement;
use crate::record::EventSink;
use crate::settings::MachineSettings;
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
    Jog { axis: usize, dir: i8 },
    /// End a CONTINUOUS jog (decelerate).
    JogRelease,
    /// Move an axis by a signed number of pulses at the jog feed (STEP and HANDLE).
    Increment { axis: usize, pulses: i64 },
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
}

/// The handle to the pulse core thread.
pub struct PulseCore {
    _private: (),
}

impl PulseCore {
    /// Starts the pulse core thread.
    pub fn spawn(
        _settings: MachineSettings,
        _clock: ClockMode,
        _sink: Option<EventSink>,
    ) -> PulseCore {
        todo!("pulse core")
    }

    /// Loads a program: a translator thread fills B1 from these statements, concurrently
    /// with execution, waiting when B1 is full. Replaces any loaded program.
    pub fn load(
        &self,
        _statements: Box<dyn Iterator<Item = Result<Statement, crate::ap::TranslateError>> + Send>,
    ) {
        todo!("pulse core")
    }

    /// Sends an operator command.
    pub fn command(&self, _c: Command) {
        todo!("pulse core")
    }

    /// The latest status snapshot.
    pub fn status(&self) -> Status {
        todo!("pulse core")
    }
}
