//! The pulse core: a thread that owns the simulated machine (X, Y and Z servo axes and the
//! relay logic for M, S, T) and the run in progress, and does the patent's NCBR (5 ms
//! real-time clock) and PGEN (each counter period KT: POUT, LINE, PCHK) work (seed 000 lines
//! 357–430, 486–530). The timing and every choice are in `docs/pulse-core.md`.
//!
//! The core owns the run: the blocks being run (read from the block buffer, B1), the modal
//! state they run in (tool in the spindle, spindle, feed) and the position. Every block carries
//! its absolute end point and the core moves to it from where the machine actually is. START
//! after a feed hold resumes the held block; START with no run loaded starts a new one from the
//! program source the caller hands over; a START that cannot act says why in
//! [`Status::notice`]. The core knows [`Block`](crate::block::Block) and the machine settings,
//! nothing of any programming language.
//!
//! Layout (one module, one job):
//! - [`Machine`] (`machine/`): the machine as a pure, deterministic state machine advanced NCBR
//!   tick by NCBR tick; tests and benchmarks drive it directly, without threads.
//! - `motion.rs`: PGEN for one motion: LINE/PCHK with ΣLF, the KT ramp.
//! - `arc.rs`: circular interpolation by integer circle stepping.
//! - `drive.rs`: the seam: a block's motion by the DDA or the error-proportional interpolator.
//! - `ep/`: the error-proportional interpolator of seed 001 (Pratt & Whitney).
//! - `pulse_out.rs`: the axis counters and the pulse log (recording batches, test capture).
//! - `source.rs`: the reading side of B1 ([`BlockSource`], [`VecSource`]).
//! - `block_buffer.rs`: the bounded B1 shared with the translator thread.
//! - `runner.rs`: [`PulseCore`], the thread around the machine (virtual or real time).
//! - `realtime.rs`: the real-time step queue (events released at their time; e-stop rollback).
//! - `kernel.rs`: [`Kernel`], N channels (one [`Machine`] each) on one NCBR clock.
//! - `sync.rs`: the [`SyncTable`] between channels: waiting M codes, handovers, chuck
//!   interlock, part counter.

mod arc;
mod block_buffer;
mod drive;
pub mod ep;
mod kernel;
mod machine;
mod motion;
mod pulse_out;
mod realtime;
mod runner;
mod source;
pub mod spindle;
mod sync;
pub mod testkit;

pub use self::arc::{ArcError, ArcStep, ArcStepper};
pub use self::block_buffer::{Answer, BlockBuffer, MachineLink, MakeRun, StatementIter};
pub use self::drive::Drive;
pub use self::kernel::{ChannelView, Kernel, KernelEvent, Outcome, MAX_CHANNELS};
pub use self::machine::{as_executed, axis_name, BlockEnd, Machine, Mark, Reached, Signals, Until};
pub use self::motion::Progress;
pub use self::motion::{accel_pulses_ns2, speed_pulses_ns};
pub use self::pulse_out::{PulseRec, BATCH};
pub use self::runner::{ChannelStatus, PulseCore, RtStats};
pub use self::source::{BlockSource, ChannelSource, Fetch, VecSource};
pub use self::sync::{AtPoint, Decision, SyncTable, Transfer, WaitOn, WorkFlow};

use crate::block::Axes;
use crate::block::{Block, Statement, TranslateError};
use std::sync::Arc;

/// How machine time relates to the wall clock.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ClockMode {
    /// Deterministic and stepped: machine time passes only when the caller waits for it
    /// (`wait`, `wait ms`, `wait block`), as fast as the machine can compute (tests, dry runs,
    /// benchmarks, scripts).
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

impl RunKind {
    /// The RUN flag value.
    pub fn flag(self) -> u8 {
        match self {
            RunKind::Auto => 1,
            RunKind::Mdi => 2,
        }
    }

    /// "AUTO" or "MDI".
    pub fn name(self) -> &'static str {
        match self {
            RunKind::Auto => "AUTO",
            RunKind::Mdi => "MDI",
        }
    }
}

/// One entry of the block buffer B1: a block, by index into the statement it came from.
#[derive(Clone, Debug)]
pub struct BlockEntry {
    /// The statement and all its blocks.
    pub stmt: Arc<Statement>,
    /// Which of `stmt.blocks` this entry is.
    pub index: usize,
}

impl BlockEntry {
    /// The block this entry names, if the index is valid.
    pub fn block(&self) -> Option<&Block> {
        self.stmt.blocks.get(self.index)
    }
}

/// Operator commands to the pulse core.
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// Cycle start: resumes a held or single-blocked run of this kind; with no run loaded,
    /// starts a new one from the source the caller has loaded (RUN = 1 or 2).
    Start(RunKind),
    /// Feed hold: decelerate to rest mid-block.
    Stop,
    /// Abandon the run, empty B1, machine idle; clears an e-stop and the alarm.
    Reset,
    /// Abandon the run (DATA INPUT clears RUN): as RESET, but an e-stop stays in force.
    Abandon,
    /// Pulses stop within one PGEN period; RESET required.
    EStop,
    /// Feed override percent, from the next NCBR tick.
    Override(u32),
    /// SINGLE BLOCK on or off: RUN is cleared after each block.
    SingleBlock(bool),
    /// Rapid override: 0 (F0, the settings' `rapid_f0_mm_min`), 25, 50 or 100 %, on every
    /// rapid, jog and return, at once; another value is refused with a notice.
    RapidOverride(u32),
    /// Spindle override: 50–120 % in steps of 10, at once; another value is refused with a
    /// notice.
    SpindleOverride(u32),
    /// DRY RUN on or off: feed moves at the jog feed (times the feed override), rapids
    /// unchanged; at once.
    DryRun(bool),
    /// MACHINE LOCK on or off: the program position moves, the axes do not
    /// (docs/pulse-core.md, "Machine lock").
    MachineLock(bool),
    /// Z NEGLECT on or off: machine lock for Z alone.
    ZNeglect(bool),
    /// The jog feed, mm/min (at most the rapid rate): of the jogs, increments and returns
    /// started from now on, on the channel told (the panel's jog feed and rapid jog, POS's
    /// `JOG`). Not a finite positive number: ignored.
    JogFeed(f64),
    /// CONTINUOUS jog: move axis (0..3) in direction ±1 at the jog feed until `JogRelease`.
    Jog {
        /// Axis 0 = X, 1 = Y, 2 = Z.
        axis: usize,
        /// +1 or −1.
        dir: i8,
    },
    /// End a CONTINUOUS jog (decelerate).
    JogRelease,
    /// A held jog key repeated: the CONTINUOUS jog in progress goes on for at most this many
    /// milliseconds of machine time unless another `JogAlive` comes, then decelerates as on
    /// `JogRelease`. A front end that stops sending (frozen, killed, its terminal gone) so
    /// lets the axis stop on its own (docs/pulse-core.md, "The jog deadman"). Ignored with no
    /// jog in progress.
    JogAlive(u32),
    /// Move an axis by a signed number of pulses at the jog feed (STEP and HANDLE).
    Increment {
        /// Axis 0 = X, 1 = Y, 2 = Z.
        axis: usize,
        /// Signed number of pulses.
        pulses: i64,
    },
    /// Reference return (HOME): Z up to machine zero, then X and Y to machine zero, at the jog
    /// feed (the rapid override acting), with the machine at rest and no run loaded.
    Home,
    /// The tool in the spindle as the position memory kept it across a restart (with the
    /// machine at rest and no run loaded): no tool change, only what the core knows.
    SetTool(Option<u32>),
    /// Sets a simulated input (a panel script's `input`): digital P`index` (`value` 0 or 1)
    /// or analog E`index`, 0–63, which M66 reads.
    Input {
        /// Digital (P) or analog (E).
        digital: bool,
        /// Input 0–63 (others are ignored).
        index: u8,
        /// For a digital input, on when not 0.
        value: f64,
    },
}

impl Command {
    /// Whether the command answers no operator action of its own: an override or switch
    /// turned, SINGLE BLOCK, an input. The machine keeps its notice across it (the answer to
    /// the last action, a START ignored say), and the console keeps that notice as shown:
    /// forgetting it was shown would show it again after what it spoke of (a DRY RUN turned
    /// after a START ignored in a block showed "START ignored" again once the block had
    /// ended; found by the random operator sequences, seed 1592591039). One list for both.
    pub fn keeps_notice(&self) -> bool {
        matches!(
            self,
            Command::Override(_)
                | Command::SingleBlock(_)
                | Command::Input { .. }
                | Command::RapidOverride(_)
                | Command::SpindleOverride(_)
                | Command::DryRun(_)
                | Command::MachineLock(_)
                | Command::ZNeglect(_)
                | Command::JogFeed(_)
        )
    }
}

/// The run loaded in the core, as the status tells it.
#[derive(Clone, Debug, PartialEq)]
pub struct RunInfo {
    /// AUTO or MDI.
    pub kind: RunKind,
    /// The run's number (1 for the first run of the core).
    pub id: u64,
    /// Machine time at its START, ns.
    pub started_ns: u64,
    /// Where the run came to rest before the operator moved the axes by hand; START returns
    /// there first (manual intervention, `docs/pulse-core.md`).
    pub return_to: Option<Axes>,
    /// The return to `return_to` is in progress.
    pub returning: bool,
}

/// How a run ended.
#[derive(Clone, Debug, PartialEq)]
pub struct RunEnd {
    /// The run's number.
    pub id: u64,
    /// AUTO or MDI.
    pub kind: RunKind,
    /// Blocks it completed.
    pub blocks: u64,
    /// Machine time from its START to its end, ns.
    pub machine_ns: u64,
    /// The time the cycle-start lamp had been lit since the machine started, at the run's
    /// end, ns (Fanuc's #3002 counts it).
    pub lamp_ns: u64,
    /// Why it ended, if not at the end of its program.
    pub cause: EndCause,
}

/// Why a run ended.
#[derive(Clone, Debug, PartialEq)]
pub enum EndCause {
    /// The end of the program (or M30).
    ProgramEnd,
    /// The program source stopped at this error. `nothing_moved`: it was found before the
    /// first block, so the run never started.
    Error {
        /// The error.
        error: TranslateError,
        /// No block of the run was started.
        nothing_moved: bool,
    },
    /// RESET, DATA INPUT or E-STOP abandoned it.
    Abandoned,
    /// The core refused a block (travel limit, arc geometry): see the alarm.
    Alarm,
}

/// Told every channel's state at every change of state of one of them while the machine runs
/// in virtual time ([`PulseCore::set_watch`]): the centre's streaming kernel tells its one
/// channel as it changes (with no sync view); a kernel's channels are told in machine-time order, each status's `machine_ns` the
/// time of the change. Called on the pulse core thread, so it must be quick.
pub type Watcher = std::sync::Arc<dyn Fn(&[ChannelStatus]) + Send + Sync>;

/// A snapshot of the machine, published at display rate and after every message.
#[derive(Clone, Debug, Default)]
pub struct Status {
    /// RUN flag: 0 stopped, 1 AUTO, 2 MDI.
    pub run: u8,
    /// Feed hold in force.
    pub hold: bool,
    /// Emergency stop in force.
    pub estop: bool,
    /// With an E-STOP in force that abandoned a run: that run's kind and the source line of the
    /// block it was in (0: none), shown until RESET.
    pub estop_at: Option<(RunKind, u32)>,
    /// A fault that needs RESET (e-stop, travel limit, arc geometry).
    pub alarm: Option<String>,
    /// Program positions, pulses, machine coordinates: where the program (and the screen)
    /// stands. The axes stand at `machine_pos`; the two differ only on axes moved under
    /// MACHINE LOCK or Z NEGLECT, until RESET or the next run.
    pub pos: Axes,
    /// Axis positions, pulses, machine coordinates: where the axes really are.
    pub machine_pos: Axes,
    /// The run loaded (running, held or stopped between single blocks), if any.
    pub job: Option<RunInfo>,
    /// The block executing, or the last one executed, in the loaded run.
    pub executing: Option<BlockEntry>,
    /// The executing (or last executed) block as the machine runs it: its Z moved by a tool
    /// length revised during the run (`as_executed`).
    pub executed: Option<crate::block::Block>,
    /// How much longer, pulses, the tool in the spindle is now than the loaded run's blocks
    /// were translated for (0 with no run loaded).
    pub length_shift: i64,
    /// Whether `executing` is in progress (false: it is complete).
    pub in_block: bool,
    /// The latest run's end, once it has ended.
    pub last_end: Option<RunEnd>,
    /// Runs begun so far (the latest run's number).
    pub runs: u64,
    /// Blocks completed in the current (or last) run.
    pub blocks_done: u64,
    /// Pulses output per axis in the current (or last) run.
    pub pulses: Axes<u64>,
    /// T code in the spindle.
    pub tool: Option<u32>,
    /// The T code a tool change (M06) in progress is putting in the spindle.
    pub changing_tool: Option<u32>,
    /// Set length of the tool in the spindle, mm (0 for none).
    pub tool_set_length: f64,
    /// Spindle rpm, signed (negative = reverse), 0 stopped: the programmed speed times the
    /// spindle override.
    pub spindle: i64,
    /// The programmed spindle rpm, signed, 0 stopped (what a program source goes on from).
    pub spindle_programmed: i64,
    /// The spindle's commanded direction: 1 M03, -1 M04, 0 M05 or stopped (under G96, where no
    /// rpm is programmed, the one word of the direction; a spindle coasting down after M05
    /// has 0).
    pub spindle_dir: i8,
    /// Feed override in force, percent.
    pub feed_override: u32,
    /// The machine stands still in a feed move at feed override 0: nothing but the operator
    /// (raising the override, RESET, E-STOP) moves it on.
    pub stalled: bool,
    /// The rapid and spindle overrides, DRY RUN, MACHINE LOCK, Z NEGLECT in force, and
    /// whether a tap holds the overrides at 100 % (the switches keep their positions in
    /// `feed_override` and `switches.spindle_override`): what `/nc/state` records.
    pub switches: crate::record::Switches,
    /// STOP was pressed during a tap: the feed hold takes effect once the tap is back out of
    /// the hole with the spindle forward (docs/pulse-core.md, "Tapping").
    pub hold_after_tap: bool,
    /// Machine time, ns.
    pub machine_ns: u64,
    /// Whether any axis is moving.
    pub moving: bool,
    /// A return moves the axes (HOME's reference return, or the way back to a held run after
    /// a manual move), or is queued.
    pub returning: bool,
    /// Whether the last run ended at the end of its program.
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
    /// The simulated inputs (M66 reads them).
    pub inputs: Signals,
    /// The outputs (M62–M65, M67, M68 set them).
    pub outputs: Signals,
    /// M19: the spindle stands oriented at this angle, degrees (M3, M4, M5 end it).
    pub orient: Option<f64>,
    /// Coolant mist (M7) and flood (M8) on; M9, M2, M30, RESET and E-STOP turn both off.
    pub coolant: (bool, bool),
    /// Messages (commands, loads, settings) the core has applied so far.
    pub commands_applied: u64,
}

impl Status {
    /// The machine's state for a program source to translate from: a new run starts from
    /// where the axes are (after a run under MACHINE LOCK, not where the program left off);
    /// with a run loaded, from the program position.
    pub fn machine_state(&self) -> crate::block::MachineState {
        crate::block::MachineState {
            pos: if self.job.is_some() {
                self.pos
            } else {
                self.machine_pos
            },
            tool: self.tool,
            spindle: self.spindle_programmed,
            mist: self.coolant.0,
            flood: self.coolant.1,
        }
    }
}
