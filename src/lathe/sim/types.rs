//! The simulator's public status, event, outcome and statistics types (docs/lathe-sim.md
//! "The API", "Events").

use crate::lathe::ops::SpindleDir;
use std::fmt;

/// A channel's state as the display shows it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ChState {
    /// Not started yet (START begins).
    Idle,
    /// Running its program.
    Run,
    /// Stopped at a queue point (a waiting M code, a receive or a delivery).
    Wait,
    /// Feed hold.
    Hold,
    /// Stopped (M00/M01, or cleared by RESET); START continues.
    Stop,
    /// Stopped by an injected fault; RESET clears it.
    Fault,
    /// Stopped by an alarm (a check before a block); RESET clears it.
    Alarm,
    /// Emergency stop; RESET clears it.
    Estop,
    /// Finished: its part count reached the target.
    Done,
}

impl fmt::Display for ChState {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ChState::Idle => "IDLE",
            ChState::Run => "RUN",
            ChState::Wait => "WAIT",
            ChState::Hold => "HOLD",
            ChState::Stop => "STOP",
            ChState::Fault => "FAULT",
            ChState::Alarm => "ALARM",
            ChState::Estop => "ESTOP",
            ChState::Done => "DONE",
        })
    }
}

/// What a channel is waiting on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WaitOn {
    /// Another channel (0-based): "CH2 waits CH1".
    Channel(usize),
    /// The bar feeder (it has supplied the target's works).
    BarFeeder,
    /// Its own spindle reaching the commanded speed before a cut.
    Spindle,
    /// The spindle encoder's index before a thread pass.
    Index,
}

impl fmt::Display for WaitOn {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            WaitOn::Channel(c) => write!(f, "CH{}", c + 1),
            WaitOn::BarFeeder => f.write_str("BAR FEEDER"),
            WaitOn::Spindle => f.write_str("SPINDLE"),
            WaitOn::Index => f.write_str("INDEX"),
        }
    }
}

/// A channel's status snapshot.
#[derive(Clone, Debug, PartialEq)]
pub struct ChannelStatus {
    /// The channel's name.
    pub name: String,
    /// State.
    pub state: ChState,
    /// The fault or alarm text, or the stop's cause.
    pub reason: Option<String>,
    /// Index of the current step in the program.
    pub step: usize,
    /// Source line of the current step (0 past the end).
    pub line: u32,
    /// Tool tip position [X radius, Z], pulses.
    pub pos: [i64; 2],
    /// Spindle speed, rpm.
    pub rpm: f64,
    /// Spindle encoder count since power-on.
    pub encoder: u64,
    /// The work in the spindle.
    pub work: Option<u32>,
    /// True if the chuck is closed.
    pub chuck_closed: bool,
    /// Parts this channel has counted at its M02/M30.
    pub parts: u32,
    /// What it waits on, if it waits.
    pub waits_on: Option<WaitOn>,
    /// Every channel it waits for (at a waiting M code, all those not yet arrived; at a
    /// transfer, the other channel), 0-based.
    pub waits_for: Vec<usize>,
    /// The tool on the tool post (0 = none called).
    pub tool: u32,
    /// The spindle's commanded direction (with `rpm`, a signed speed: M04 negative).
    pub dir: SpindleDir,
}

/// One recorded event (drained by [`Lathe::drain_events`]).
#[derive(Clone, Debug, PartialEq)]
pub enum Event {
    /// A block started.
    Block {
        /// Channel, 0-based.
        ch: usize,
        /// Machine time, ns.
        t: u64,
        /// Source line.
        line: u32,
        /// Operation name ("rapid", "line", "arc", "thread", …).
        op: &'static str,
    },
    /// A position sample (every sample period while something changed, and at each block end).
    Sample {
        /// Channel.
        ch: usize,
        /// Machine time, ns.
        t: u64,
        /// [X radius, Z], pulses.
        pos: [i64; 2],
        /// Spindle rpm.
        rpm: f64,
        /// Path speed, mm/min.
        speed: f64,
    },
    /// A channel's display state changed.
    State {
        /// Channel.
        ch: usize,
        /// Machine time, ns.
        t: u64,
        /// New state.
        state: ChState,
        /// What it now waits on.
        waits_on: Option<WaitOn>,
    },
    /// A work passed from a chuck to another (`from` None = the bar feeder, `to` None = the
    /// unloader).
    Transfer {
        /// Machine time, ns.
        t: u64,
        /// Giving channel.
        from: Option<usize>,
        /// Receiving channel.
        to: Option<usize>,
        /// Work id.
        work: u32,
        /// Both chucks were closed on the work at the handover.
        both_closed: bool,
    },
    /// A thread pass synchronised to the encoder (its start, or its resumption).
    ThreadPass {
        /// Channel.
        ch: usize,
        /// Machine time, ns.
        t: u64,
        /// Source line.
        line: u32,
        /// The index count the pass is anchored to (a multiple of the encoder lines).
        index: u64,
        /// The encoder count at the tick the pass moved first.
        encoder: u64,
        /// True when resuming after a stop.
        resumed: bool,
    },
    /// A cutting block started, with the work in the spindle.
    CutStart {
        /// Channel.
        ch: usize,
        /// Machine time, ns.
        t: u64,
        /// Source line.
        line: u32,
        /// The work (never None: that is an alarm instead).
        work: Option<u32>,
    },
    /// A channel counted a part at its M02/M30.
    Part {
        /// Channel.
        ch: usize,
        /// Machine time, ns.
        t: u64,
        /// The channel's count.
        count: u32,
    },
    /// A fault was injected.
    Fault {
        /// Channel.
        ch: usize,
        /// Machine time, ns.
        t: u64,
        /// Reason.
        reason: String,
    },
    /// An alarm stopped a channel before a block.
    Alarm {
        /// Channel.
        ch: usize,
        /// Machine time, ns.
        t: u64,
        /// Source line.
        line: u32,
        /// Message.
        msg: String,
    },
}

/// How a headless run ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Outcome {
    /// Every channel finished; `parts` delivered to the unloader.
    Finished {
        /// Parts delivered.
        parts: u32,
    },
    /// A channel stopped (M00, hold, not started, or a 0 % feed override) and the others wait
    /// or are done.
    Stopped,
    /// A channel is faulted (the first one) and the others wait or are done.
    Fault {
        /// Channel.
        ch: usize,
        /// Reason.
        reason: String,
    },
    /// A channel is in alarm.
    Alarm {
        /// Channel.
        ch: usize,
        /// Message.
        msg: String,
    },
    /// Emergency stop.
    Estop,
    /// No channel can ever progress: each waits on another or is done.
    Deadlock {
        /// (channel, what it waits on) for every waiting channel.
        waits: Vec<(usize, WaitOn)>,
    },
    /// `max_ns` of machine time passed first.
    TimeLimit,
}

/// Statistics of one channel.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ChannelStats {
    /// Blocks started (a block refused by an alarm counts each try).
    pub blocks: u64,
    /// Pulses output per axis [X, Z].
    pub pulses: [u64; 2],
    /// Parts counted.
    pub parts: u32,
}

/// Statistics of the run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Stats {
    /// Parts delivered to the unloader.
    pub delivered: u32,
    /// Works the bar feeder supplied.
    pub supplied: u32,
    /// Machine time, ns.
    pub machine_ns: u64,
    /// Ticks run.
    pub ticks: u64,
    /// Cutting blocks refused on an empty spindle (alarms).
    pub empty_cut_alarms: u32,
    /// Per channel.
    pub channels: Vec<ChannelStats>,
}
