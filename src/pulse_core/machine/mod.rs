//! The simulated machine as a pure, deterministic state machine: NCBR every NCBR period of
//! machine time, PGEN inside each tick, the relay logic for M, S and T, the operator commands
//! and the run being executed. Tests drive it directly; the pulse core thread only wraps it.
//!
//! Timing of one NCBR tick at machine time t (period P, 5 ms by default):
//! 1. a new feed override takes effect (the target speed of the motion in force changes);
//! 2. if RUN ≠ 0, no feed hold, no return after a manual move, and the last block is complete
//!    (DEN and auxiliary function complete): in SINGLE BLOCK RUN is cleared; otherwise the next
//!    block is read from B1, checked against the travel limits from where the machine is, and
//!    started (its auxiliary functions first);
//! 3. PGEN distributes every pulse whose time falls in [t, t + P);
//! 4. pending pulse batches are flushed and, while moving, the position is recorded.
//!
//! A block that completes mid-tick leaves the machine at rest until the next tick reads the
//! following block (as the patent's NCBR does).
//!
//! **Whole blocks at once.** With nothing recorded, no override pending and no manual move,
//! the ticks inside a block change nothing but time, so [`Machine::run`] distributes the block
//! in one PGEN call and sets the clock to the tick where it completes. The pulses and times are
//! the same as tick by tick (tested); a dry run then costs pulses, not ticks.

use super::block_buffer::Answer;
use super::drive::Drive;
use super::motion::{accel_pulses_ns2, speed_pulses_ns, Anchor, Progress};
use super::pulse_out::{PulseOut, PulseRec};
use super::source::{BlockSource, Fetch};
use super::spindle::{css_rpm, Spindle};
use super::{BlockEntry, EndCause, RunEnd, RunKind};
use crate::block::{Axes, Block, Css, FeedMode, MachineState, Motion as Kind};
use crate::record::{Event, EventSink};
use crate::settings::MachineSettings;
use crate::tooldata::Magazine;
use crate::workpiece::{along, Touch};
use check::{arc_stepper, check_block};
use std::collections::VecDeque;

mod check;
mod commands;
mod jog;
mod report;

pub use check::axis_name;

/// Sends an event to the recording (lossless in virtual time, see `pulse_out::emit`).
fn send_ev(s: &EventSink, lossless: &std::cell::Cell<bool>, ev: Event) {
    super::pulse_out::emit(s, ev, lossless);
}

/// Where the executing block is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Phase {
    /// Auxiliary functions before the motion (T, M06, S, M03, M04), until `until`.
    PreAux,
    /// The motion (or the dwell, until `until`).
    Move,
    /// Auxiliary functions after the motion (M05, M30), until `until`.
    PostAux,
    /// A chuck point (M10, M11) reached with the spindle not yet giving its signal: commanded
    /// stopped but still coasting down (zero speed), or commanded turning but not yet at speed
    /// (speed arrival). The machine arrives at the sync point at the NCBR tick `until`, the
    /// first with the signal on; `pre` is the block's PreAux duration, kept for `Sync`
    /// (docs/pulse-core.md, "Chuck and spindle").
    Spindle { pre: u64 },
    /// A channel's sync point (`Block::sync`): waiting for the kernel's sync table to release
    /// it (docs/pulse-core.md, "Channels"); `until` holds the PreAux duration meanwhile.
    Sync,
}

/// The block being executed.
#[derive(Clone, Debug)]
struct Current {
    entry: BlockEntry,
    /// A copy of the entry's block, its amounts taken from where the machine was at its start.
    block: Block,
    phase: Phase,
    until: u64,
    motion: Option<Drive>,
    /// The set length of the tool in the spindle before the tool data was revised while this
    /// block ran (the block goes on with the length it was planned with).
    len_planned: Option<f64>,
    /// A probe block: whether the probe finds what it seeks on the way, and already at the
    /// start (answered with the position when the block ends).
    probe: Option<(bool, bool)>,
    /// An M66 block: the wait on an input, and its value once read (`None` until then, or
    /// on a timeout).
    wait: Option<InputWait>,
    /// The block's auxiliary functions are done; the pre-auxiliary phase goes on only while
    /// a cut waits for the spindle to be at speed.
    pre_done: bool,
    /// A feed per revolution: the path speed last set from the spindle's speed, pulses/ns.
    per_rev_v: Option<f64>,
}

/// 64 digital and 64 analog signals: the machine's simulated inputs (P0–P63 and E0–E63, set
/// by [`Command::Input`](crate::pulse_core::Command::Input), read by M66) or its outputs
/// (M62–M65 digital, M67/M68 analog).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Signals {
    /// Bit `n`: digital signal `n` is on.
    pub digital: u64,
    /// Analog signals 0–63.
    pub analog: [f64; 64],
}

impl Default for Signals {
    fn default() -> Signals {
        Signals {
            digital: 0,
            analog: [0.0; 64],
        }
    }
}

impl Signals {
    /// Sets input `index` (ignored past 63); a digital one is on when `value` is not 0.
    pub fn set(&mut self, digital: bool, index: u8, value: f64) {
        let i = usize::from(index);
        if i >= 64 {
            return;
        }
        if digital {
            if value != 0.0 {
                self.digital |= 1 << i;
            } else {
                self.digital &= !(1 << i);
            }
        } else if value.is_finite() {
            self.analog[i] = value;
        }
    }

    /// The value of input `index`: a digital one 0 or 1.
    pub fn get(&self, digital: bool, index: u8) -> f64 {
        let i = usize::from(index) & 63;
        if digital {
            f64::from(u8::from(self.digital >> i & 1 == 1))
        } else {
            self.analog[i]
        }
    }
}

/// M66 in progress (docs/gcode.md, "Signals and outputs").
#[derive(Clone, Copy, Debug)]
struct InputWait {
    digital: bool,
    index: u8,
    /// L: 0 immediate, 1 rise, 2 fall, 3 high, 4 low.
    mode: u8,
    timeout_ns: u64,
    /// For a rise (fall): the input has been seen low (high) since the block started.
    armed: bool,
    /// The value read when the wait ended; `None` while waiting, or after a timeout.
    value: Option<f64>,
}

impl InputWait {
    /// Looks at the input now: whether the wait is over (its value kept).
    fn look(&mut self, inputs: &Signals) -> bool {
        let v = inputs.get(self.digital, self.index);
        let high = v != 0.0;
        let met = match self.mode {
            0 => true,
            1 => {
                let m = self.armed && high;
                self.armed |= !high;
                m
            }
            2 => {
                let m = self.armed && !high;
                self.armed |= high;
                m
            }
            3 => high,
            _ => !high,
        };
        if met {
            self.value = Some(v);
        }
        met
    }
}

/// A manual move in progress (CONTINUOUS, STEP or HANDLE), or the return to where the run
/// stopped.
#[derive(Clone, Debug)]
struct Jog {
    /// Manual moves and returns always use the DDA with its ramps.
    motion: Drive,
    /// The fastest its axes allow, mm/min (`rapid_top`): its full speed is the jog feed held
    /// to it, and the rapid override a share of that, as of a rapid's.
    top: f64,
    /// CONTINUOUS: stop and drop the rest once at rest.
    release: bool,
    /// Machine time at which a CONTINUOUS jog kept alive by `JogAlive` decelerates unless
    /// another comes.
    deadline: Option<u64>,
}

/// The run loaded: running, held, or stopped between single blocks.
#[derive(Clone, Debug)]
struct Job {
    kind: RunKind,
    id: u64,
    started_ns: u64,
    /// The block executing or last executed.
    last: Option<BlockEntry>,
    /// That block as the machine runs it (`as_executed`).
    last_block: Option<Block>,
    /// Blocks started.
    started_blocks: u64,
    /// Where the run stood when the operator first moved an axis by hand while it was stopped.
    return_to: Option<Axes>,
}

/// What [`Machine::run`] runs until.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Until {
    /// The machine is idle (RUN = 0 and nothing moving, a feed hold at rest, an e-stop).
    Idle,
    /// Machine time reaches this, ns.
    Time(u64),
    /// A block with this sequence number starts executing, or the machine is idle.
    BlockStart(u32),
    /// Machine time reaches this, ns, or the machine waits at a channel sync point
    /// ([`Reached::Sync`]), or it is idle ([`Reached::Idle`], e.g. its run ended): the
    /// multi-channel kernel's step (docs/pulse-core.md, "Channels").
    SyncPoint(u64),
}

/// Why [`Machine::run`] returned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reached {
    /// The machine is idle.
    Idle,
    /// The machine time asked for.
    Time,
    /// The block asked for has started.
    BlockStart,
    /// B1 is empty and the translator is still working (virtual time only): call again once it
    /// has caught up; the clock has not moved past the tick that wanted the block.
    Starved,
    /// Standing still mid-block at feed override 0: nothing will happen until it is raised.
    Stalled,
    /// The machine-time limit passed without reaching the condition.
    Limit,
    /// The caller's interrupt (a stop signal) ended the wait early.
    Interrupted,
    /// The machine waits at a channel sync point ([`Machine::sync_point`]).
    Sync,
}

/// One completed block, for tests that check where every block ended.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BlockEnd {
    /// The run it belongs to.
    pub run: u64,
    /// The block's sequence number (N).
    pub seq: u32,
    /// Its source line.
    pub stmt: u32,
    /// Where the machine was when it started, pulses.
    pub start: Axes,
    /// The programmed end point, pulses.
    pub end: Axes,
    /// Where the machine was when it completed, pulses.
    pub pos: Axes,
    /// The tool-tip Z then, pulses: axis Z less the set length of the tool in the spindle.
    pub tip: i64,
    /// The same by the length the block was planned with: a length revised while the block
    /// ran applies from the next block, so this one finishes the Z it was given.
    pub tip_planned: i64,
}

/// A block as the machine runs it when the tool in the spindle is `shift` pulses longer than
/// the block was translated for and Z is at `z_now` (docs/pulse-core.md, "Tool length revised
/// during a run"): a block whose Z follows the tool (`Block::tool_z`) and moves Z goes to its Z
/// moved by the difference; one that does not move Z stays at the Z the machine is at, so X Y
/// never turn into a slant. Other blocks are unchanged. `delta` is left to the caller.
pub fn as_executed(b: &mut Block, shift: i64, z_now: i64) {
    if !b.tool_z {
        return;
    }
    if b.delta[2] == 0 {
        b.end[2] = z_now;
        b.delta[2] = 0;
    } else {
        b.end[2] += shift;
    }
}

/// The simulated machine: axes, relay logic, RUN, the run and the operator state.
#[derive(Clone, Debug)]
pub struct Machine {
    settings: MachineSettings,
    accel: f64,
    now: u64,
    next_tick: u64,
    run: u8,
    hold: bool,
    estop: bool,
    /// The run an E-STOP abandoned and the source line of the block it was in (0: none), until
    /// RESET.
    estop_at: Option<(RunKind, u32)>,
    alarm: Option<String>,
    notice: Option<String>,
    single_block: bool,
    /// The block just completed carried M00, or M01 (a G-code source emits M01 only with
    /// OPTIONAL STOP on): the run stops after it as after a single block; START continues.
    program_stop: bool,
    feed_override: u32,
    pending_override: Option<u32>,
    /// Rapid override, percent: 0 (F0), 25, 50, 100.
    rapid_override: u32,
    /// Spindle override, percent: 50–120.
    spindle_override: u32,
    dry_run: bool,
    machine_lock: bool,
    z_neglect: bool,
    /// A tap's blocks are running (from its first block's start to its last one's end): the
    /// feed and spindle overrides are held at 100 % (docs/pulse-core.md, "Tapping").
    in_tap: bool,
    /// STOP during a tap: the hold takes effect when the tap's last block ends.
    hold_after_tap: bool,
    /// A thread block that goes on in the next (`Tap::Part`, a taper into the groove) ended
    /// at this encoder phase, at this time: the next thread block starts from it, not from an
    /// index.
    thread_phase: Option<(f64, u64)>,
    current: Option<Current>,
    job: Option<Job>,
    runs: u64,
    last_end: Option<RunEnd>,
    just_completed: bool,
    blocks_done: u64,
    out: PulseOut,
    selected_t: Option<u32>,
    tool: Option<u32>,
    tool_len: f64,
    spindle: i64,
    /// The spindle: its actual speed and encoder (docs/pulse-core.md, "The spindle").
    sp: Spindle,
    /// The way the spindle is commanded to turn: 1 forward (M3), -1 reverse (M4), 0 stopped.
    spindle_dir: i8,
    /// G96 in force: the spindle's target follows X.
    css: Option<Css>,
    /// M19: the spindle stands oriented at this angle, degrees (until M3, M4 or M5).
    orient: Option<f64>,
    /// Coolant: mist (M7) and flood (M8) on; M9, M2, M30, RESET and E-STOP turn both off.
    coolant: (bool, bool),
    s_rpm: u32,
    program_end: bool,
    magazine: Option<Magazine>,
    /// The tool data the loaded run's blocks were translated with.
    run_magazine: Option<Magazine>,
    jog: Option<Jog>,
    increments: VecDeque<(usize, i64)>,
    /// The return to where the run stopped: the move in progress and the targets after it.
    ret: Option<Jog>,
    ret_queue: VecDeque<Axes>,
    /// Virtual time: an empty B1 stops [`Machine::run`] instead of letting the tick pass.
    starve_stops: bool,
    starved: bool,
    started_seq: Option<u32>,
    /// The block start looked for ([`Machine::look_for_block`]): its sequence number, and the
    /// NCBR tick it first started at since (None: not yet).
    looked_for: Option<(u32, Option<u64>)>,
    /// The blocks whose start a channel marks ([`Machine::mark_starts`]), by sequence number,
    /// sorted.
    marked: Vec<u32>,
    /// Time the block in progress completed inside the last PGEN call.
    finished_at: Option<u64>,
    /// The NCBR tick a chuck point's spindle signal came on at inside the last PGEN call (the
    /// machine arrived at the sync point then).
    signal_at: Option<u64>,
    audit: Option<Vec<BlockEnd>>,
    /// Told the status at every change of state inside [`Machine::run`] (virtual time).
    watch: Option<report::Watch>,
    events: Option<EventSink>,
    last_state: Option<report::StateKey>,
    /// When `/nc/state` was last sent (a ramping spindle is sampled, not sent every tick).
    last_state_t: u64,
    op_mode: String,
    data_mode: String,
    commands: u64,
    /// The answer of the probe, M66 or clocks block just ended, for the source at the next
    /// NCBR.
    probe_answer: Option<Answer>,
    /// Machine time the cycle-start lamp has been lit (a run going, not held) before
    /// `lamp_since`, ns (Fanuc's #3002 counts it).
    lamp_ns: u64,
    /// When the cycle-start lamp was last lit, while it is.
    lamp_since: Option<u64>,
    /// The simulated inputs M66 reads.
    inputs: Signals,
    /// The outputs M62–M65, M67 and M68 set.
    outputs: Signals,
    /// One channel of a multi-channel kernel: a block with a sync point waits for the kernel
    /// to release it; a machine alone refuses such a block (it has no other channel).
    channel: bool,
    /// The kernel's chuck interlock: while set, a cutting block (a feed move) is refused
    /// with this reason (the chuck is open or the spindle empty).
    cut_interlock: Option<String>,
    /// What the kernel reports besides motion (a channel only; [`Machine::take_marks`]).
    marks: Vec<Mark>,
    /// A recording channel's next position sample and pulse batch flush, ns.
    next_sample: u64,
}

/// A channel of a kernel records its position, and sends its pulse batches, at most this
/// often while it moves (and whenever a run call returns): docs/recording.md, "Lathe
/// recordings" (every 10 ms). The centre's machine records at every NCBR tick (5 ms).
pub const CHANNEL_SAMPLE_NS: u64 = 10_000_000;

/// What a channel's machine did that its kernel reports as an event (docs/pulse-core.md,
/// "Channels"): kept only on a channel ([`Machine::set_channel`]), taken by the kernel.
#[derive(Clone, Debug, PartialEq)]
pub enum Mark {
    /// A cutting block (a feed move, arc or thread pass) started at `t`.
    Cut {
        /// Machine time, ns.
        t: u64,
        /// Source line.
        line: u32,
    },
    /// A thread pass starts at encoder index `index` (a whole number of revolutions), which
    /// the encoder reaches at `t`; `encoder` is the count at its first step.
    Thread {
        /// Machine time the encoder reaches the index, ns.
        t: u64,
        /// Source line.
        line: u32,
        /// The index count the pass is anchored to.
        index: u64,
        /// The encoder count at its first step.
        encoder: u64,
    },
    /// A block of [`Machine::mark_starts`] started at `t`.
    Start {
        /// Machine time, ns.
        t: u64,
        /// Its sequence number.
        seq: u32,
    },
    /// A block was refused: the machine is in alarm.
    Alarm {
        /// Machine time, ns.
        t: u64,
        /// Source line (0: none).
        line: u32,
        /// The alarm as the machine shows it.
        msg: String,
    },
}

impl Machine {
    /// A machine at rest at machine zero, time 0, no tool in the spindle.
    pub fn new(settings: MachineSettings) -> Machine {
        let accel = accel_pulses_ns2(settings.accel_mm_s2, settings.pulse_mm);
        let sp = Spindle::new(&settings);
        Machine {
            sp,
            spindle_dir: 0,
            css: None,
            settings,
            accel,
            now: 0,
            next_tick: 0,
            run: 0,
            hold: false,
            estop: false,
            estop_at: None,
            alarm: None,
            notice: None,
            single_block: false,
            program_stop: false,
            feed_override: 100,
            pending_override: None,
            rapid_override: 100,
            spindle_override: 100,
            dry_run: false,
            machine_lock: false,
            z_neglect: false,
            in_tap: false,
            hold_after_tap: false,
            thread_phase: None,
            current: None,
            job: None,
            runs: 0,
            last_end: None,
            just_completed: false,
            blocks_done: 0,
            out: PulseOut::default(),
            selected_t: None,
            tool: None,
            tool_len: 0.0,
            spindle: 0,
            orient: None,
            coolant: (false, false),
            s_rpm: 0,
            program_end: false,
            magazine: None,
            run_magazine: None,
            jog: None,
            increments: VecDeque::new(),
            ret: None,
            ret_queue: VecDeque::new(),
            starve_stops: false,
            starved: false,
            started_seq: None,
            looked_for: None,
            marked: Vec::new(),
            finished_at: None,
            signal_at: None,
            audit: None,
            watch: None,
            events: None,
            last_state: None,
            last_state_t: 0,
            op_mode: "AUTO".into(),
            data_mode: "SEARCH".into(),
            commands: 0,
            probe_answer: None,
            lamp_ns: 0,
            lamp_since: None,
            inputs: Signals::default(),
            outputs: Signals::default(),
            channel: false,
            cut_interlock: None,
            marks: Vec::new(),
            next_sample: 0,
        }
    }

    /// Makes this machine one channel of a multi-channel kernel (see the field `channel`).
    pub fn set_channel(&mut self, on: bool) {
        self.channel = on;
    }

    /// The kernel's chuck interlock: `Some(reason)` refuses every cutting block from now on.
    pub fn set_cut_interlock(&mut self, why: Option<String>) {
        self.cut_interlock = why;
    }

    /// What happened since the last call that the kernel reports (cuts started, thread
    /// passes at their index, refused blocks), in the order it happened; nothing unless the
    /// machine is a channel.
    pub fn take_marks(&mut self) -> Vec<Mark> {
        std::mem::take(&mut self.marks)
    }

    /// A copy of the machine to look ahead with (a kernel's `wait block N`): the same state,
    /// recording and keeping nothing (no sink, captured pulses, audit, watch or marks), made
    /// without copying what it has kept.
    pub fn quiet_copy(&mut self) -> Machine {
        let quiet = self.out.quiet_copy();
        let out = std::mem::replace(&mut self.out, quiet);
        let audit = self.audit.take();
        let watch = self.watch.take();
        let events = self.events.take();
        let marks = std::mem::take(&mut self.marks);
        let copy = self.clone();
        (self.out, self.audit, self.watch, self.events, self.marks) =
            (out, audit, watch, events, marks);
        copy
    }

    /// Looks for the next start of block `seq` (its sequence number, the N of the listing)
    /// from now on; None stops looking. [`Machine::block_started_at`] then tells when it
    /// started (a kernel's `wait block N`, which cannot stop one channel alone mid-step).
    pub fn look_for_block(&mut self, seq: Option<u32>) {
        self.looked_for = seq.map(|s| (s, None));
    }

    /// Marks the start of each block of `seqs` (sequence numbers) with [`Mark::Start`], every
    /// time one starts: the blocks a console says a program's message at (a kernel's
    /// `KernelEvent::BlockStart`, with its machine time).
    pub fn mark_starts(&mut self, mut seqs: Vec<u32>) {
        seqs.sort_unstable();
        seqs.dedup();
        self.marked = seqs;
    }

    /// The NCBR tick the block looked for first started at, if it has since it was asked.
    pub fn block_started_at(&self) -> Option<u64> {
        self.looked_for.and_then(|l| l.1)
    }

    /// The sync point the machine waits at, if it waits at one.
    pub fn sync_point(&self) -> Option<crate::block::Sync> {
        self.current
            .as_ref()
            .filter(|c| c.phase == Phase::Sync)
            .and_then(|c| c.block.sync)
    }

    /// Releases the sync point the machine waits at: the block goes on at the current time
    /// (its auxiliary functions, then its end). False if it waits at none.
    pub fn release_sync(&mut self) -> bool {
        let now = self.now;
        match &mut self.current {
            Some(c) if c.phase == Phase::Sync => {
                c.phase = Phase::PreAux;
                c.until = now.saturating_add(c.until);
                true
            }
            _ => false,
        }
    }

    /// The kernel's sync table refuses the sync point the machine waits at (an M10 with no
    /// supplier, an M11 with no receiver): alarm, the run ends before the block.
    pub fn refuse_sync(&mut self, why: String) {
        if self.sync_point().is_some() {
            if let Some(c) = self.current.take() {
                self.refuse(&c.entry, Some(&c.block), why);
            }
        }
    }

    /// Whether a feed hold is in force.
    pub fn is_held(&self) -> bool {
        self.hold
    }

    /// Whether an emergency stop is in force.
    pub fn is_estop(&self) -> bool {
        self.estop
    }

    /// The alarm in force.
    pub fn alarm(&self) -> Option<&str> {
        self.alarm.as_deref()
    }

    /// The latest run's end.
    pub fn last_end(&self) -> Option<&RunEnd> {
        self.last_end.as_ref()
    }

    /// The simulated inputs.
    pub fn inputs(&self) -> &Signals {
        &self.inputs
    }

    /// An output of block `b` (M62–M65, M67, M68) at time `t`: those with the motion
    /// (`synced`) when the block's motion starts, the others when the block is read into the
    /// NC table. Each is recorded on `/nc/io`.
    fn apply_output(&mut self, b: &Block, t: u64, synced: bool) {
        let (digital, index, value) = match b.io {
            Some(crate::block::Io::Digital {
                index,
                on,
                synced: s,
            }) if s == synced => (true, index, f64::from(u8::from(on))),
            Some(crate::block::Io::Analog {
                index,
                value,
                synced: s,
            }) if s == synced => (false, index, value),
            _ => return,
        };
        self.outputs.set(digital, index, value);
        if let Some(s) = &self.events {
            send_ev(
                s,
                &self.out.lossless,
                Event::Io {
                    t_ns: t,
                    seq: b.seq,
                    stmt: b.stmt,
                    digital,
                    index,
                    value,
                    synced,
                    input: false,
                },
            );
        }
    }

    /// A simulated input set by the operator or a script: recorded on `/nc/io` (`"dir":"in"`)
    /// when it changes, charged to the block executing (0 if none).
    pub(super) fn set_input(&mut self, digital: bool, index: u8, value: f64) {
        let before = self.inputs;
        self.inputs.set(digital, index, value);
        let changed = if digital {
            before.digital != self.inputs.digital
        } else {
            before.analog[usize::from(index)].to_bits()
                != self.inputs.analog[usize::from(index)].to_bits()
        };
        if let (true, Some(s)) = (changed, &self.events) {
            let (seq, stmt) = self
                .current
                .as_ref()
                .map_or((0, 0), |c| (c.block.seq, c.block.stmt));
            send_ev(
                s,
                &self.out.lossless,
                Event::Io {
                    t_ns: self.now,
                    seq,
                    stmt,
                    digital,
                    index,
                    value: self.inputs.get(digital, index),
                    synced: false,
                    input: true,
                },
            );
        }
    }

    /// The settings in force.
    pub fn settings(&self) -> &MachineSettings {
        &self.settings
    }

    /// Records events to `sink` (blocks, positions, pulses, state) and/or captures every pulse
    /// for `take_pulses`.
    pub fn set_recording(&mut self, sink: Option<EventSink>, capture_pulses: bool) {
        self.out.set_log(sink.clone(), capture_pulses);
        self.events = sink;
        // The first `/nc/state` goes with the first command or tick, so that the front end's
        // modes (`set_panel_modes`) are in it, not the defaults.
        self.last_state = None;
    }

    /// Whether the pulses are captured for `take_pulses`.
    pub fn captures(&self) -> bool {
        self.out.captures()
    }

    /// Whether block ends are logged for `take_audit`.
    pub fn audits(&self) -> bool {
        self.audit.is_some()
    }

    /// Captures the pulses for `take_pulses` (off: stops and forgets them), the recording
    /// kept as it is.
    pub fn set_capture(&mut self, on: bool) {
        self.out.set_log(self.events.clone(), on);
    }

    /// Lossless recording: wait for room in the recorder's queue rather than drop an event.
    /// Only for virtual time, where machine time does not follow the wall clock.
    pub fn set_lossless_recording(&mut self, on: bool) {
        self.out.lossless.set(on);
    }

    /// Virtual time: an empty B1 with the translator still working makes [`Machine::run`]
    /// return [`Reached::Starved`] without advancing the clock (real time lets the tick pass).
    pub fn set_starve_stops(&mut self, on: bool) {
        self.starve_stops = on;
    }

    /// Keeps a log of every block end (programmed end and actual position) for `take_audit`.
    pub fn set_audit(&mut self, on: bool) {
        self.audit = if on { Some(Vec::new()) } else { None };
    }

    /// Calls `w` with the status at every change of state (RUN, hold, e-stop, alarm, notice,
    /// the block executing, tool, spindle, overrides, the end of a run) found while the machine
    /// runs, between its ticks, so that nothing that happens inside one advance is merged into
    /// the state after it (the MTConnect adapter, docs/mtconnect.md). None stops it.
    pub fn set_watch(&mut self, w: Option<crate::pulse_core::Watcher>) {
        self.watch = w.map(|f| report::Watch::new(Some(f)));
    }

    /// The same watch with no watcher: every changed status is kept, in order, for
    /// [`Machine::take_watched`] (a kernel's channel, the kernel merging its channels' changes
    /// in time order). Off forgets them.
    pub fn keep_watch(&mut self, on: bool) {
        self.watch = on.then(|| report::Watch::new(None));
    }

    /// Checks the state now, between runs (after a command): a change is told, or kept.
    pub fn watch_now(&mut self) {
        self.watch_check();
    }

    /// The statuses kept since the last call (with [`Machine::keep_watch`] on).
    pub fn take_watched(&mut self) -> Vec<crate::pulse_core::Status> {
        self.watch
            .as_mut()
            .map(report::Watch::take)
            .unwrap_or_default()
    }

    /// The block ends logged since the last call (with the audit on).
    pub fn take_audit(&mut self) -> Vec<BlockEnd> {
        self.audit.as_mut().map(std::mem::take).unwrap_or_default()
    }

    /// The pulses captured since the last call (with `capture_pulses` on).
    pub fn take_pulses(&mut self) -> Vec<PulseRec> {
        self.out.take_capture()
    }

    /// The tool data used for the set length of the tool in the spindle. With no run loaded it
    /// is also what the next run's blocks are translated with; during a run (a revision in a
    /// feed hold) the difference moves the Z of the blocks started from then on.
    pub fn set_magazine(&mut self, m: Magazine) {
        if self.job.is_none() {
            self.run_magazine = Some(m.clone());
        }
        if let Some(c) = &mut self.current {
            c.len_planned.get_or_insert(self.tool_len);
        }
        self.magazine = Some(m);
        self.tool_len = self.set_length_of(self.tool);
    }

    /// The length the Z axis carries for tool `t` (set length plus wear), by the tool data in
    /// force now.
    fn set_length_of(&self, t: Option<u32>) -> f64 {
        Self::length_in(self.magazine.as_ref(), t)
    }

    fn length_in(m: Option<&Magazine>, t: Option<u32>) -> f64 {
        t.and_then(|t| m?.tools.get(t))
            .map(|r| r.length())
            .unwrap_or(0.0)
    }

    /// How much longer (pulses) the tool in the spindle is now than the run's blocks were
    /// translated for: the Z of every block started from now on is moved by it, so a length
    /// revised during a feed hold applies from the next block (docs/pulse-core.md).
    pub(super) fn length_shift(&self) -> i64 {
        let now = self.set_length_of(self.tool);
        let then = Self::length_in(self.run_magazine.as_ref(), self.tool);
        self.settings.to_pulses(now) - self.settings.to_pulses(then)
    }

    /// The operation and data-processing mode names recorded in `/nc/state`.
    pub fn set_panel_modes(&mut self, op_mode: &str, data_mode: &str) {
        self.op_mode = op_mode.to_string();
        self.data_mode = data_mode.to_string();
        self.send_state();
    }

    /// The jog feed, mm/min (at most the rapid rate): of the jogs, increments and returns
    /// started from now on. Not a finite positive number: ignored (the console refuses it).
    pub fn set_jog_feed(&mut self, mm_min: f64) {
        if mm_min.is_finite() && mm_min > 0.0 {
            self.settings.jog_mm_min = mm_min.min(self.settings.rapid_mm_min);
        }
    }

    /// The spindle and coolant as a machine before this one's clock left them (a lathe
    /// channel's new cycle: docs/lathe-gcode.md "What a channel keeps"): turning `dir` (1
    /// forward, -1 reverse, 0 stopped) at `s_rpm` programmed (G97) or under `css`, actually at
    /// `actual_rpm` (signed; it goes on from there, no ramp from rest), coolant mist and
    /// flood. Before the first block only; false (nothing changed) after.
    pub fn preset_spindle(
        &mut self,
        dir: i8,
        s_rpm: u32,
        css: Option<crate::block::Css>,
        actual_rpm: f64,
        coolant: (bool, bool),
    ) -> bool {
        if self.run != 0 || self.current.is_some() {
            return false;
        }
        self.coolant = coolant;
        self.s_rpm = s_rpm;
        self.spindle_dir = dir.signum();
        self.spindle = i64::from(dir.signum()) * i64::from(s_rpm);
        self.css = if dir == 0 { None } else { css };
        // From its actual speed towards its target: a spindle still coasting down after M5
        // goes on coasting down.
        self.sp.preset(self.now, actual_rpm);
        self.spindle_sync(self.now);
        true
    }

    /// Sets the axis positions (pulses) with the machine at rest and no run loaded; refused
    /// otherwise.
    pub fn set_position(&mut self, pos: impl Into<Axes>) -> bool {
        let pos = pos.into();
        if self.current.is_some() || self.jog.is_some() || self.job.is_some() {
            return false;
        }
        self.out.pos = pos;
        self.out.shift = Axes::default();
        true
    }

    /// Sets the machine's clock to `t` (rounded up to a whole NCBR tick) before anything has
    /// run on it (refused, false, once a run, a block or a jog has begun): a kernel made for a
    /// console's next cycle goes on from the console's machine time, so that one recording
    /// has one time base.
    pub fn set_clock(&mut self, t: u64) -> bool {
        if self.current.is_some() || self.jog.is_some() || self.job.is_some() || self.runs > 0 {
            return false;
        }
        let t = t.div_ceil(self.period()) * self.period();
        self.now = t;
        self.next_tick = t;
        true
    }

    /// Machine time, ns.
    pub fn now(&self) -> u64 {
        self.now
    }

    /// Program positions, pulses (the axes' own, but for what MACHINE LOCK held back).
    pub fn pos(&self) -> Axes {
        self.out.pos
    }

    /// Axis positions, pulses: where the axes really are.
    pub fn machine_pos(&self) -> Axes {
        self.out.machine_pos()
    }

    /// The machine's state for a program source to start from: with no run loaded, where the
    /// axes are (a new run brings the program position back to them, `begin_run`).
    pub fn machine_state(&self) -> MachineState {
        MachineState {
            pos: if self.job.is_some() {
                self.out.pos
            } else {
                self.out.machine_pos()
            },
            tool: self.tool,
            spindle: self.spindle,
            mist: self.coolant.0,
            flood: self.coolant.1,
        }
    }

    /// RUN flag.
    pub fn run_flag(&self) -> u8 {
        self.run
    }

    /// Blocks completed in this run.
    pub fn blocks_done(&self) -> u64 {
        self.blocks_done
    }

    /// Whether a START of `kind` now would begin a new run (rather than resume one or be
    /// refused): the caller must then have loaded the new run's blocks.
    pub fn start_begins_run(&self, _kind: RunKind) -> bool {
        self.job.is_none()
            && !self.estop
            && self.alarm.is_none()
            && self.jog.is_none()
            && self.increments.is_empty()
    }

    /// A manual move moves or is queued (a CONTINUOUS jog, STEP or handwheel increments), and
    /// no E-STOP stopped it.
    pub fn moves_by_hand(&self) -> bool {
        !self.estop && (self.jog.is_some() || !self.increments.is_empty())
    }

    /// Nothing will happen until a command: no motion, nothing pending, and RUN = 0 (or a feed
    /// hold at rest, or an emergency stop).
    pub fn is_idle(&self) -> bool {
        if self.estop {
            return true;
        }
        if self.jog.is_some() || !self.increments.is_empty() {
            return false;
        }
        if let Some(r) = &self.ret {
            if !(r.motion.is_held() && r.motion.at_rest()) {
                return false;
            }
        }
        if self.run == 0 {
            return self.current.is_none();
        }
        if self.hold {
            return match &self.current {
                None => true,
                Some(c) => c.phase == Phase::Move && c.motion.as_ref().is_some_and(|m| m.at_rest()),
            };
        }
        false
    }

    fn returning(&self) -> bool {
        self.ret.is_some() || !self.ret_queue.is_empty()
    }

    /// Standing still mid-block at feed override 0 (time passes but nothing moves).
    pub fn is_stalled(&self) -> bool {
        self.feed_override == 0
            && self.pending_override.is_none()
            && !self.hold
            && self.current.as_ref().is_some_and(|c| {
                c.phase == Phase::Move && c.motion.as_ref().is_some_and(|m| m.at_rest())
            })
    }

    /// Whether NCBR would read a block at the next tick.
    pub fn wants_block(&self) -> bool {
        self.run != 0
            && !self.hold
            && !self.estop
            && self.current.is_none()
            && !self.returning()
            && (!self.just_completed || !self.stops_after_block())
    }

    /// Whether the run stops after the block just completed: SINGLE BLOCK, or a program stop.
    /// SINGLE BLOCK does not stop inside a thread pass of several blocks (a block that goes
    /// on, `Tap::Part`, has left its phase for the next): the pass ends first, as a Fanuc's
    /// single block waits for the end of consecutive threading blocks.
    fn stops_after_block(&self) -> bool {
        (self.single_block && self.thread_phase.is_none()) || self.program_stop
    }

    /// Runs whole NCBR ticks (and the PGEN work inside them) until machine time `until`.
    pub fn advance_to(&mut self, until: u64, src: &mut dyn BlockSource) {
        while self.now < until {
            if self.run(src, Until::Time(until), u64::MAX) != Reached::Starved {
                return;
            }
        }
    }

    /// Runs exactly one NCBR tick from the current (tick-aligned) time.
    pub fn tick(&mut self, src: &mut dyn BlockSource) {
        self.advance_to(self.next_tick_end(), src);
    }

    /// Where the NCBR tick under way, or the next one from now, ends.
    pub fn next_tick_end(&self) -> u64 {
        if self.now >= self.next_tick {
            self.now + self.period()
        } else {
            self.next_tick
        }
    }

    /// Runs until the machine is idle (or `max_ns` of machine time has passed, or it stalls at
    /// override 0).
    pub fn run_until_idle(&mut self, src: &mut dyn BlockSource, max_ns: u64) {
        self.run(src, Until::Idle, max_ns);
    }

    fn period(&self) -> u64 {
        self.settings.ncbr_period_ns.max(1)
    }

    /// Runs the machine until `until`, or until `limit_ns` of machine time has passed. Every
    /// pulse made is in the recording when it returns in virtual time, and in real time once
    /// the axes are at rest. While they move in real time (a run is one slice of one NCBR
    /// tick, the Citizen's 100 µs) the batches fill on, and go out at the tick's end (every
    /// `CHANNEL_SAMPLE_NS` for a channel), at a block's end, at 4096 pulses and at a stop:
    /// a batch per slice made real-time recordings 3 to 14 times the size of the same run
    /// in virtual time.
    pub fn run(&mut self, src: &mut dyn BlockSource, until: Until, limit_ns: u64) -> Reached {
        let r = self.run_inner(src, until, limit_ns);
        if self.out.lossless.get() || !self.axes_moving() {
            self.out.flush();
        }
        r
    }

    /// Sends every pulse batch still filling to the recording (the core's thread ends).
    pub fn flush_recording(&mut self) {
        self.out.flush();
    }

    /// Whether an axis moves: a block's motion, a jog or a return, not at rest.
    fn axes_moving(&self) -> bool {
        self.current
            .as_ref()
            .and_then(|c| c.motion.as_ref())
            .is_some_and(|m| !m.at_rest())
            || self.jog.as_ref().is_some_and(|j| !j.motion.at_rest())
            || self.ret.as_ref().is_some_and(|j| !j.motion.at_rest())
    }

    fn run_inner(&mut self, src: &mut dyn BlockSource, until: Until, limit_ns: u64) -> Reached {
        let p = self.period();
        let t_end = match until {
            Until::Time(t) | Until::SyncPoint(t) => t,
            _ => self.now.saturating_add(limit_ns),
        };
        let sync_stops = matches!(until, Until::SyncPoint(_));
        let waits_for_rest = !matches!(until, Until::Time(_) | Until::SyncPoint(_));
        loop {
            if sync_stops {
                if self.sync_point().is_some() {
                    return Reached::Sync;
                }
                if self.is_idle() {
                    return Reached::Idle;
                }
            }
            if waits_for_rest {
                if self.is_idle() {
                    return Reached::Idle;
                }
                if self.is_stalled() {
                    return Reached::Stalled;
                }
            }
            if self.now >= t_end {
                return if waits_for_rest {
                    Reached::Limit
                } else {
                    Reached::Time
                };
            }
            if self.now >= self.next_tick {
                self.started_seq = None;
                self.ncbr(src);
                self.lamp();
                if std::mem::take(&mut self.starved) {
                    return Reached::Starved;
                }
                self.next_tick = self.now + p;
                if let Until::BlockStart(seq) = until {
                    if self.started_seq == Some(seq) {
                        return Reached::BlockStart;
                    }
                }
                if sync_stops && self.sync_point().is_some() {
                    // Its arrival is a change of state, told at the tick it arrived.
                    self.watch_check();
                    return Reached::Sync;
                }
            }
            let whole_block = self.events.is_none()
                && self.pending_override.is_none()
                && self.current.is_some()
                && self.jog.is_none()
                && self.increments.is_empty()
                && !self.returning()
                && !self.spindle_needs_ticks();
            if whole_block {
                self.finished_at = None;
                self.signal_at = None;
                self.pgen(t_end);
                // The block completed: the tick it completed in ends. The motion came to rest
                // (feed hold, override 0): the tick it stopped in ends, after which nothing
                // happens until a command. Otherwise it is still going at `t_end`.
                let resting = self
                    .current
                    .as_ref()
                    .and_then(|c| c.motion.as_ref())
                    .filter(|m| m.at_rest())
                    .map(|m| m.last_t());
                // Arrived at a chuck point: at the tick its spindle's signal came on.
                self.now = match (self.signal_at.take(), self.finished_at.take(), resting) {
                    (Some(t), _, _) => t,
                    (None, Some(t), _) => ((t / p + 1) * p).min(t_end),
                    (None, None, Some(t)) => {
                        let rest = ((t / p + 1) * p).min(t_end);
                        if rest > self.now {
                            rest
                        } else {
                            t_end
                        }
                    }
                    (None, None, None) => t_end,
                };
                self.next_tick = self.now.div_ceil(p) * p;
            } else {
                let end = t_end.min(self.next_tick);
                self.pgen(end);
                self.now = end;
            }
            if self.now >= self.next_tick {
                self.tick_end();
            }
            self.watch_check();
            if self.now == self.next_tick {
                if let Some(t) = self.quiet_ticks_end(t_end) {
                    // The ticks up to `t` would each have changed nothing (see there).
                    self.now = t;
                    self.next_tick = t;
                    self.started_seq = None;
                }
            }
        }
    }

    fn tick_end(&mut self) {
        if self.channel && self.events.is_some() {
            // A channel's tick is short (the Citizen's 100 µs): its positions and pulse
            // batches are recorded every CHANNEL_SAMPLE_NS, its state on every change.
            if self.now < self.next_sample {
                self.send_state();
                return;
            }
            self.next_sample = self.now.saturating_add(CHANNEL_SAMPLE_NS);
        }
        self.out.flush();
        if self.events.is_none() {
            return;
        }
        if self.axes_moving() {
            self.send_position();
        }
        self.send_state();
    }

    /// NCBR: override, RUN, DEN and the next block.
    fn ncbr(&mut self, src: &mut dyn BlockSource) {
        if let Some(a) = self.probe_answer.take() {
            src.answer(a);
        }
        if let Some(p) = self.pending_override.take() {
            self.feed_override = p;
            let feed = self
                .current
                .as_ref()
                .map(|c| &c.block)
                .filter(|b| b.motion != Kind::Rapid)
                .cloned();
            if let Some(b) = feed {
                let v = self.feed_speed(&b, self.now);
                if let Some(c) = self.current.as_mut() {
                    if c.per_rev_v.is_some() {
                        c.per_rev_v = Some(v);
                    }
                    if let Some(m) = c.motion.as_mut() {
                        m.set_target(v);
                    }
                }
            }
        }
        // The spindle's target follows X under G96; a feed per revolution follows its speed.
        self.spindle_sync(self.now);
        let per_rev = self
            .current
            .as_ref()
            .filter(|c| c.per_rev_v.is_some() && c.motion.is_some())
            .map(|c| self.feed_speed(&c.block, self.now));
        if let (Some(v), Some(c)) = (per_rev, self.current.as_mut()) {
            if c.per_rev_v != Some(v) {
                c.per_rev_v = Some(v);
                if let Some(m) = c.motion.as_mut() {
                    m.set_target(v);
                }
            }
        }
        if !self.wants_block() {
            if self.run != 0
                && self.just_completed
                && self.stops_after_block()
                && self.current.is_none()
            {
                self.run = 0;
                self.just_completed = false;
            }
            return;
        }
        match src.fetch() {
            Fetch::Block(e) => self.start_block(e),
            Fetch::Pending => {
                if self.starve_stops {
                    self.starved = true;
                }
            }
            Fetch::End => self.end_run(EndCause::ProgramEnd),
            Fetch::Error(error) => {
                let nothing_moved = self.job.as_ref().is_none_or(|j| j.started_blocks == 0);
                self.end_run(EndCause::Error {
                    error,
                    nothing_moved,
                });
            }
        }
    }

    /// Path speed for a programmed feed, after override, capped at the rapid rate. DRY RUN
    /// replaces the programmed feed by the jog feed; the feed override scales either
    /// (docs/pulse-core.md, "Overrides and switches").
    /// During a tap the feed is geared to the spindle: neither DRY RUN nor the override acts.
    /// A feed per revolution (G95) is mm/rev × the spindle's actual speed at `t`.
    fn feed_speed(&self, b: &Block, t: u64) -> f64 {
        let feed = match b.feed_mode {
            FeedMode::PerMin => b.feed,
            FeedMode::PerRev => b.feed * self.sp.rpm_at(t).abs(),
        };
        let (feed, pct) = if self.in_tap {
            (feed, 100)
        } else if self.dry_run {
            (self.settings.jog_mm_min, self.feed_override)
        } else {
            (feed, self.feed_override)
        };
        // An arc moves each axis of its plane in turn as fast as the path: it is held to the
        // lowest of the linear axes' own rates (a line is held axis by axis: `Drive::linear`).
        let top = match b.motion {
            Kind::ArcCw | Kind::ArcCcw => (self.settings.axis_rate[..3].iter())
                .fold(self.settings.rapid_mm_min, |m, &r| m.min(r)),
            _ => self.settings.rapid_mm_min,
        };
        let f = (feed * pct as f64 / 100.0).min(top);
        speed_pulses_ns(f.max(0.0), self.settings.pulse_mm)
    }

    /// The acceleration of an arc, pulses/ns²: the lowest of the linear axes' (an arc moves
    /// each axis of its plane in turn; a straight move is held axis by axis instead).
    fn arc_accel(&self) -> f64 {
        let s = &self.settings;
        let lowest = (s.axis_accel[..3].iter()).fold(s.accel_mm_s2, |m, &a| m.min(a));
        accel_pulses_ns2(lowest, s.pulse_mm)
    }

    /// The full path speed of a rapid of `delta`, mm/min: the rapid rate, held so that no axis
    /// moves faster than its own (`settings.axis_rate`); the rapid override is a share of it,
    /// so 50 % halves every axis's speed, as a Fanuc's override scales each axis's rapid.
    pub(super) fn rapid_top(&self, delta: &crate::block::Axes) -> f64 {
        let s = &self.settings;
        let (cap, _) = super::motion::axis_limits(delta, &s.axis_rate, &s.axis_accel);
        s.rapid_mm_min.min(cap)
    }

    /// Path speed of a rapid, jog or return whose full speed is `full` mm/min, after the rapid
    /// override: its percentage of `full`, or at F0 the F0 rate (never faster than `full`).
    pub(super) fn rapid_speed(&self, full: f64) -> f64 {
        let f = match self.rapid_override {
            0 => self.settings.rapid_f0_mm_min.min(full),
            p => full * f64::from(p.min(100)) / 100.0,
        };
        speed_pulses_ns(f.max(0.0), self.settings.pulse_mm)
    }

    /// The spindle rpm the spindle turns at: programmed times the spindle override.
    /// During a tap the override is held at 100 %: the feed is geared to the programmed speed.
    fn spindle_actual(&self) -> i64 {
        if self.in_tap {
            return self.spindle;
        }
        self.spindle * i64::from(self.spindle_override) / 100
    }

    /// Sets the target speed of the motions in force after an override or DRY RUN change:
    /// the block's (its feed, or a rapid), a jog's and a return's.
    pub(super) fn retarget(&mut self) {
        let v = self.current.as_ref().map(|c| &c.block).map(|b| {
            if b.motion == Kind::Rapid {
                self.rapid_speed(self.rapid_top(&b.delta))
            } else {
                self.feed_speed(b, self.now)
            }
        });
        if let (Some(v), Some(m)) = (v, self.current.as_mut().and_then(|c| c.motion.as_mut())) {
            m.set_target(v);
        }
        let (jog, ret) = (self.jog.as_ref(), self.ret.as_ref());
        let full = |m: &Jog| self.rapid_speed(self.settings.jog_mm_min.min(m.top));
        let (j, r) = (jog.map(full), ret.map(full));
        if let (Some(m), Some(v)) = (self.jog.as_mut(), j) {
            m.motion.set_target(v);
        }
        if let (Some(m), Some(v)) = (self.ret.as_mut(), r) {
            m.motion.set_target(v);
        }
    }

    /// A block the core will not run: alarm (RESET needed), the run ends before it.
    fn refuse(&mut self, e: &BlockEntry, b: Option<&Block>, why: String) {
        let line = e.stmt.line;
        let seq = b.map(|b| format!("N{} ", b.seq)).unwrap_or_default();
        self.alarm = Some(format!("line {line}: {seq}{why}"));
        if self.channel {
            self.marks.push(Mark::Alarm {
                t: self.now,
                line,
                msg: format!("{seq}{why}"),
            });
        }
        if let Some(j) = &mut self.job {
            j.last = Some(e.clone());
        }
        self.end_run(EndCause::Alarm);
    }

    /// The cycle-start lamp (Fanuc's STL: a run going, neither held nor stopped) as it is
    /// now: the time it was lit is counted up to now when it goes out (#3002). Called after
    /// whatever may change it (a command, NCBR, a run's end); the time counted is to the tick.
    pub(super) fn lamp(&mut self) {
        let lit = self.run != 0 && !self.hold && !self.estop;
        match (self.lamp_since, lit) {
            (Some(t), false) => {
                self.lamp_ns += self.now.saturating_sub(t);
                self.lamp_since = None;
            }
            (None, true) => self.lamp_since = Some(self.now),
            _ => {}
        }
    }

    /// The time the cycle-start lamp has been lit up to machine time `t`, ns.
    fn lamp_time(&self, t: u64) -> u64 {
        self.lamp_ns + self.lamp_since.map_or(0, |s| t.saturating_sub(s))
    }

    /// Ends the loaded run: RUN = 0, nothing held, the end recorded for the display.
    fn end_run(&mut self, cause: EndCause) {
        self.run = 0;
        self.in_tap = false;
        self.spindle_sync(self.now);
        self.hold_after_tap = false;
        self.thread_phase = None;
        self.probe_answer = None;
        self.hold = false;
        self.just_completed = false;
        self.ret = None;
        self.ret_queue.clear();
        self.program_end = cause == EndCause::ProgramEnd;
        if let Some(j) = self.job.take() {
            self.last_end = Some(RunEnd {
                id: j.id,
                kind: j.kind,
                blocks: self.blocks_done,
                machine_ns: self.now.saturating_sub(j.started_ns),
                lamp_ns: self.lamp_time(self.now),
                cause,
            });
        }
        self.lamp();
    }

    /// Starts a new run of `kind` (its blocks come from the source the caller passes).
    fn begin_run(&mut self, kind: RunKind) {
        self.runs += 1;
        self.job = Some(Job {
            kind,
            id: self.runs,
            started_ns: self.now,
            last: None,
            last_block: None,
            started_blocks: 0,
            return_to: None,
        });
        self.blocks_done = 0;
        self.out.count = Axes::default();
        self.out.unshift();
        self.program_end = false;
        self.just_completed = false;
        self.run_magazine = self.magazine.clone();
        self.tool_len = self.set_length_of(self.tool);
        self.run = kind.flag();
    }

    /// Reads a block into the NC table: checks from where the machine is, auxiliary
    /// functions, then the motion. The block's amounts are taken as its absolute end point less
    /// the actual position, so no shift can accumulate.
    fn start_block(&mut self, e: BlockEntry) {
        let Some(mut b) = e.stmt.blocks.get(e.index).cloned() else {
            self.refuse(&e, None, "no such block".into());
            return;
        };
        let pos = self.out.pos;
        let shift = self.length_shift();
        as_executed(&mut b, shift, pos[2]);
        if self.channel && matches!(b.motion, Kind::Aux | Kind::Dwell) {
            // A channel runs its program once per work from where the last cycle ended: a
            // block without motion stands where the machine is.
            b.end = pos;
        }
        let start = b.start();
        if matches!(b.motion, Kind::ArcCw | Kind::ArcCcw) && start != pos {
            let s = start;
            let why = format!(
                "the arc starts at X{:.3} Y{:.3} Z{:.3}, the machine is at X{:.3} Y{:.3} Z{:.3}",
                self.settings.to_mm(s[0]),
                self.settings.to_mm(s[1]),
                self.settings.to_mm(s[2]),
                self.settings.to_mm(pos[0]),
                self.settings.to_mm(pos[1]),
                self.settings.to_mm(pos[2]),
            );
            self.refuse(&e, Some(&b), why);
            return;
        }
        let probe = match b.probe {
            Some(g) if b.motion == Kind::Linear => Some(self.probe_stop(&mut b, pos, g)),
            _ => None,
        };
        let wait = match b.io {
            Some(crate::block::Io::Wait {
                digital,
                index,
                mode,
                timeout,
            }) => Some(InputWait {
                digital,
                index,
                mode,
                timeout_ns: if mode == 0 {
                    0
                } else {
                    (timeout.max(0.0) * 1e9).min(u64::MAX as f64 / 4.0) as u64
                },
                // A rise (fall) is armed by the input low (high) at the start.
                armed: match mode {
                    1 => self.inputs.get(digital, index) == 0.0,
                    2 => self.inputs.get(digital, index) != 0.0,
                    _ => false,
                },
                value: None,
            }),
            _ => None,
        };
        b.delta = Axes::from_fn(|a| b.end[a] - pos[a]);
        if let Err(why) = check_block(&self.settings, pos, &b) {
            self.refuse(&e, Some(&b), why);
            return;
        }
        if b.sync.is_some() && !self.channel {
            let why = "a channel sync point (M10, M11 or a waiting M code) needs another channel: this machine has one".into();
            self.refuse(&e, Some(&b), why);
            return;
        }
        let cut =
            matches!(b.motion, Kind::Linear | Kind::ArcCw | Kind::ArcCcw) && b.delta != [0; 3];
        if let (true, Some(why)) = (cut, &self.cut_interlock) {
            let why = format!("chuck interlock: {why}");
            self.refuse(&e, Some(&b), why);
            return;
        }
        let geared = b.thread.is_some() || (cut && b.feed_mode == FeedMode::PerRev);
        if geared && self.spindle_dir == 0 && !matches!(b.m, Some(3) | Some(4)) {
            // As Fanuc's G95: no feed without the spindle turning; refused before any pulse.
            let why = if b.thread.is_some() {
                "a thread pass with the spindle stopped (M3 or M4 first)"
            } else {
                "feed per revolution (G95) with the spindle stopped (M3 or M4 first)"
            };
            self.refuse(&e, Some(&b), why.into());
            return;
        }
        if cut && self.channel {
            self.marks.push(Mark::Cut {
                t: self.now,
                line: e.stmt.line,
            });
        }
        if let Some(s) = &self.events {
            send_ev(
                s,
                &self.out.lossless,
                Event::Block {
                    t_ns: self.now,
                    seq: b.seq,
                    stmt: b.stmt,
                    text: crate::block::iso_line(&b, &self.settings),
                },
            );
        }
        self.apply_output(&b, self.now, false);
        let mut pre = 0;
        if b.m == Some(6) {
            pre += self.settings.tool_change_ns;
        }
        let spindle_change = matches!(b.m, Some(3) | Some(4))
            || (b.s.is_some() && self.spindle != 0 && !matches!(b.m, Some(5) | Some(30)));
        if spindle_change {
            pre += self.settings.spindle_ns;
        }
        self.just_completed = false;
        // A thread pass is geared to the spindle as a tap is (overrides at 100 %, the hold
        // deferred to its end).
        self.in_tap = b.tap != crate::block::Tap::No || b.thread.is_some();
        self.spindle_sync(self.now);
        self.started_seq = Some(b.seq);
        if self.channel && self.marked.binary_search(&b.seq).is_ok() {
            self.marks.push(Mark::Start {
                t: self.now,
                seq: b.seq,
            });
        }
        if let Some((seq, at @ None)) = &mut self.looked_for {
            if *seq == b.seq {
                *at = Some(self.now);
            }
        }
        if let Some(j) = &mut self.job {
            j.last = Some(e.clone());
            j.last_block = Some(b.clone());
            j.started_blocks += 1;
        }
        let sync = b.sync.is_some();
        let signal = self.chuck_signal_at(&b);
        self.current = Some(Current {
            entry: e,
            block: b,
            phase: match (sync, signal) {
                (true, Some(_)) => Phase::Spindle { pre },
                (true, None) => Phase::Sync,
                (false, _) => Phase::PreAux,
            },
            until: match (sync, signal) {
                (true, Some(t)) => t,
                (true, None) => pre,
                (false, _) => self.now + pre,
            },
            motion: None,
            len_planned: None,
            probe,
            wait,
            pre_done: false,
            per_rev_v: None,
        });
    }

    /// A probe block (G38.x ×10 in `g`) from `pos`: where its stylus (a ball of the spindle
    /// tool's radius on its tip, the gauge line less its length) first meets the workpiece of
    /// the settings (G38.2/3) or leaves it (G38.4/5) along the straight move becomes the
    /// block's end, to the nearest pulse; already so at the start, nothing moves. Whether it
    /// trips, and whether at the start (docs/pulse-core.md, "Probing").
    fn probe_stop(&self, b: &mut Block, pos: Axes, g: u16) -> (bool, bool) {
        let st = &self.settings;
        let len = self.tool_len;
        let radius = self
            .tool
            .and_then(|t| self.magazine.as_ref()?.tools.get(t))
            .map_or(0.0, |r| r.cutting_diameter() / 2.0);
        let tip = |p: Axes| [st.to_mm(p[0]), st.to_mm(p[1]), st.to_mm(p[2]) - len];
        let (a, e) = (tip(pos), tip(b.end));
        match st.workpiece.probe(a, e, radius, g <= 383) {
            Touch::AtStart => {
                b.end = pos;
                b.motion = Kind::Aux;
                (true, true)
            }
            Touch::At(t) => {
                let p = along(a, e, t);
                b.end = Axes::with_rotary(
                    [
                        st.to_pulses(p[0]),
                        st.to_pulses(p[1]),
                        st.to_pulses(p[2] + len),
                    ],
                    b.end.rotary(),
                );
                (true, false)
            }
            Touch::Never => (false, false),
        }
    }

    /// PGEN up to `end`: the block's phases, then any manual move or return.
    fn pgen(&mut self, end: u64) {
        while let Some(c) = &mut self.current {
            match c.phase {
                Phase::Sync => break,
                Phase::Spindle { pre } => {
                    // At the chuck point once the spindle gives its signal, at a tick.
                    if c.until > end {
                        break;
                    }
                    self.signal_at = Some(c.until);
                    c.phase = Phase::Sync;
                    c.until = pre;
                    break;
                }
                Phase::PreAux => {
                    if c.until >= end {
                        break;
                    }
                    let t0 = c.until;
                    let b = c.block.clone();
                    if !std::mem::replace(&mut c.pre_done, true) {
                        self.pre_effects(&b, t0);
                    }
                    // A cut starts only with the spindle at speed (a spindle without a ramp
                    // always is; a stopped one is not waited for).
                    let cut = matches!(b.motion, Kind::Linear | Kind::ArcCw | Kind::ArcCcw)
                        && b.delta != [0; 3];
                    if let Some(r) = self.sp.ready_at(t0).filter(|&r| cut && r > t0) {
                        if let Some(c) = &mut self.current {
                            c.until = r;
                        }
                        continue;
                    }
                    self.apply_output(&b, t0, true);
                    // A thread block after one that goes on (`Tap::Part`) keeps its groove if
                    // it follows at once (the next tick); after a stop between them (SINGLE
                    // BLOCK) it is a new pass, from an index.
                    let period = self.settings.ncbr_period_ns;
                    let goes_on = self
                        .thread_phase
                        .take()
                        .filter(|&(_, t)| b.thread.is_some() && t0.saturating_sub(t) <= 2 * period);
                    let motion = match b.motion {
                        Kind::Rapid => Some(Drive::linear(
                            &self.settings,
                            b.delta,
                            self.rapid_speed(self.rapid_top(&b.delta)),
                            self.accel,
                            t0,
                        )),
                        Kind::Linear => Some(match (b.thread, self.rigid_tap_pitch(&b)) {
                            (Some(lead), _) => {
                                let anchor = goes_on
                                    .map_or(Anchor::Index, |(phase, t)| Anchor::After { phase, t });
                                Drive::thread(&self.settings, b.delta, lead, &self.sp, t0, anchor)
                            }
                            (None, Some(pitch)) => Drive::thread(
                                &self.settings,
                                b.delta,
                                pitch,
                                &self.sp,
                                t0,
                                Anchor::Here,
                            ),
                            (None, None) => Drive::linear(
                                &self.settings,
                                b.delta,
                                self.feed_speed(&b, t0),
                                self.accel,
                                t0,
                            ),
                        }),
                        Kind::ArcCw | Kind::ArcCcw => arc_stepper(&b).ok().map(|st| {
                            Drive::arc(
                                &self.settings,
                                &b,
                                st,
                                self.feed_speed(&b, t0),
                                self.arc_accel(),
                                t0,
                            )
                        }),
                        Kind::Dwell | Kind::Aux => None,
                    };
                    let per_rev_v = (b.feed_mode == FeedMode::PerRev
                        && matches!(b.motion, Kind::Linear | Kind::ArcCw | Kind::ArcCcw)
                        && b.thread.is_none())
                    .then(|| self.feed_speed(&b, t0));
                    let Some(c) = &mut self.current else { break };
                    c.per_rev_v = per_rev_v;
                    c.phase = Phase::Move;
                    c.until = t0
                        + if b.motion == Kind::Dwell {
                            b.dwell_ns
                        } else {
                            c.wait.map_or(0, |w| w.timeout_ns)
                        };
                    c.motion = motion.map(|mut m| {
                        m.set_hold(self.hold);
                        m
                    });
                    let line = c.entry.stmt.line;
                    let mark = match c.motion.as_mut().and_then(Drive::as_thread) {
                        Some(th) if self.channel && b.thread.is_some() && !th.continued() => {
                            let (t, encoder) = th.index_and_first_count();
                            Some(Mark::Thread {
                                t,
                                line,
                                index: th.anchor().abs() as u64,
                                encoder,
                            })
                        }
                        _ => None,
                    };
                    self.marks.extend(mark);
                }
                Phase::Move => {
                    if let Some(m) = &mut c.motion {
                        match m.run(end, &mut self.out) {
                            Progress::Done => {
                                c.until = c.until.max(m.last_t());
                                if c.block.thread.is_some()
                                    && c.block.tap == crate::block::Tap::Part
                                {
                                    self.thread_phase =
                                        m.as_thread().map(|th| (th.end_phase(), th.last_t()));
                                }
                            }
                            Progress::Pending | Progress::AtRest => break,
                        }
                    } else {
                        let inputs = self.inputs;
                        let now = self.now;
                        if let Some(w) = c.wait.as_mut().filter(|w| w.value.is_none()) {
                            if w.look(&inputs) {
                                // The wait is over now (not before the block's start).
                                let t0 = c.until.saturating_sub(w.timeout_ns);
                                c.until = c.until.min(now.max(t0));
                            }
                        }
                        if c.until >= end {
                            break;
                        }
                    }
                    let b = &c.block;
                    // M5, M30 and M19 stop a turning spindle (M19 then orients it).
                    let stops = matches!(b.m, Some(5) | Some(30))
                        || matches!(b.io, Some(crate::block::Io::Orient { .. }));
                    let post = if stops && self.spindle != 0 {
                        self.settings.spindle_ns
                    } else {
                        0
                    };
                    c.until += post;
                    c.phase = Phase::PostAux;
                    c.motion = None;
                }
                Phase::PostAux => {
                    if c.until >= end {
                        break;
                    }
                    let t = c.until;
                    if let Some(c) = self.current.take() {
                        self.finish_block(t, c);
                    }
                }
            }
        }
        if let Some(j) = &mut self.jog {
            if j.deadline.is_some_and(|d| d < end) {
                // The jog deadman: no keep-alive from the front end in time.
                j.deadline = None;
                j.motion.set_hold(true);
            }
            let p = j.motion.run(end, &mut self.out);
            if p == Progress::Done || (p == Progress::AtRest && j.release) {
                let t = j.motion.last_t().max(self.now);
                self.jog = None;
                self.out.flush();
                self.send_position();
                self.next_increment(t);
            }
        }
        if let Some(j) = &mut self.ret {
            if j.motion.run(end, &mut self.out) == Progress::Done {
                let t = j.motion.last_t().max(self.now);
                self.ret = None;
                self.next_return(t);
            }
        }
    }

    fn pre_effects(&mut self, b: &Block, t0: u64) {
        self.css = b.css;
        if let Some(t) = b.t {
            self.selected_t = Some(t);
            if self.settings.tool_turret {
                // A turret indexes at the T word: no M6, no tool length (the lathe's offsets
                // are in its reader's path).
                self.tool = Some(t);
            }
        }
        if let Some(s) = b.s {
            self.s_rpm = s;
        }
        match b.m {
            Some(7) => self.coolant.0 = true,
            Some(8) => self.coolant.1 = true,
            Some(9) | Some(2) | Some(30) => self.coolant = (false, false),
            _ => {}
        }
        match b.m {
            Some(6) => {
                self.tool = self.selected_t;
                self.tool_len = self.set_length_of(self.tool);
            }
            Some(3) => {
                self.spindle = i64::from(self.s_rpm);
                self.spindle_dir = 1;
                self.orient = None;
            }
            Some(4) => {
                self.spindle = -i64::from(self.s_rpm);
                self.spindle_dir = -1;
                self.orient = None;
            }
            _ => {
                if b.s.is_some() && self.spindle != 0 {
                    self.spindle = self.spindle.signum() * i64::from(self.s_rpm);
                }
            }
        }
        self.spindle_sync(t0);
    }

    /// The spindle's target now, signed rpm: stopped 0; G97 the programmed speed after the
    /// spindle override (held at 100 % in a tap or thread pass); G96 the rpm that gives the
    /// surface speed at the radius X (the distance of axis X from 0, docs/pulse-core.md "The
    /// spindle"), under its limit, after the override; never above the machine's maximum.
    fn spindle_target(&self) -> f64 {
        let max = self.settings.spindle_max_rpm;
        let rpm = match (self.spindle_dir, self.css) {
            (0, _) => return 0.0,
            (d, Some(c)) => {
                let r_mm = self.settings.to_mm(self.out.pos[0]).abs();
                let pct = if self.in_tap {
                    100
                } else {
                    self.spindle_override
                };
                f64::from(d) * css_rpm(c.m_per_min, c.limit_rpm.min(max), r_mm) * f64::from(pct)
                    / 100.0
            }
            (_, None) => self.spindle_actual() as f64,
        };
        // Not `clamp`: a maximum that is not a number or negative must not panic.
        rpm.min(max).max(-max)
    }

    /// Gives the spindle its target at time `t` (a thread pass in progress follows it).
    fn spindle_sync(&mut self, t: u64) {
        let tg = self.spindle_target();
        if tg != self.sp.target() {
            self.sp.set_target(t, tg);
            let sp = &self.sp;
            if let Some(th) = self
                .current
                .as_mut()
                .and_then(|c| c.motion.as_mut())
                .and_then(|m| m.as_thread())
            {
                th.set_spindle(sp);
            }
        }
    }

    /// At a tick boundary, with the block kept on the ticks by its live spindle
    /// (`spindle_needs_ticks`): the end of the whole ticks from now (up to `t_end`) in which
    /// nothing can happen, if there is at least one. On the Citizen these are most ticks of a
    /// G96 facing cut, where X moves one pulse every few ticks, and the ticks of a wait for
    /// the spindle at speed. Such a tick's work changes nothing when
    /// - its NCBR part does nothing: nothing recorded, watched, pending (override, answer),
    ///   no manual move; the spindle's target is the one the tick would set (`spindle_sync`),
    ///   and stays so as long as no pulse moves X; a feed per revolution in motion is the one
    ///   the tick would compute, with the spindle at its target for good (`Spindle::steady_at`);
    /// - and its PGEN part takes no step: the block's auxiliary functions end at or after the
    ///   tick's end (`PreAux`), or its DDA motion's next step, found by the last PGEN call
    ///   (`Drive::pending_step_at`), falls at or after the tick's end.
    ///
    /// Nothing then changes from tick to tick but time, so each of those ticks would find the
    /// same, and the tick in which the step (or the end of the auxiliary functions) falls runs
    /// as before, from the same state.
    fn quiet_ticks_end(&self, t_end: u64) -> Option<u64> {
        let calm = self.events.is_none()
            && self.watch.is_none()
            && self.pending_override.is_none()
            && self.probe_answer.is_none()
            && self.jog.is_none()
            && self.increments.is_empty()
            && !self.returning();
        if !calm {
            return None;
        }
        let c = self.current.as_ref()?;
        // A tick ending at h takes no step while h <= `quiet`.
        let quiet = match (c.phase, &c.motion) {
            (Phase::PreAux, _) => c.until,
            (Phase::Move, Some(m)) => {
                // PGEN takes the step when its time t < h (as f64, exact below 2^53 ns):
                // for a whole h that is h <= floor(t).
                let t = m.pending_step_at()?;
                if t.is_nan() || t < 0.0 {
                    return None;
                }
                t.floor() as u64 // saturates for +inf: no step ever
            }
            _ => return None,
        };
        let p = self.period();
        let ticks = quiet.min(t_end).checked_sub(self.now)? / p;
        if ticks == 0 || !self.spindle_needs_ticks() || self.spindle_target() != self.sp.target() {
            return None;
        }
        if let (Some(v), Some(_)) = (c.per_rev_v, &c.motion) {
            if !self.sp.steady_at(self.now) || self.feed_speed(&c.block, self.now) != v {
                return None;
            }
        }
        Some(self.now + ticks * p)
    }

    /// A tap's feed on a spindle with a ramp is geared to its encoder (rigid tapping): the
    /// pitch, mm/rev, is the block's feed over the programmed speed. None for any other block,
    /// and on a spindle without a ramp, which is always at the programmed speed (the centre's
    /// taps run as they always did).
    fn rigid_tap_pitch(&self, b: &Block) -> Option<f64> {
        let geared = b.tap != crate::block::Tap::No
            && b.motion == Kind::Linear
            && b.feed_mode == FeedMode::PerMin
            && self.sp.ramps()
            && self.spindle != 0
            && b.feed > 0.0;
        geared.then(|| b.feed / self.spindle.unsigned_abs() as f64)
    }

    /// The spindle as commanded: signed rpm (M3 +, M4 -; under G96 the target at X now), 0
    /// when M5, M30 or M19 stopped it (it may still be coasting down).
    pub fn spindle_commanded(&self) -> f64 {
        if self.spindle_dir == 0 {
            0.0
        } else {
            self.sp.target()
        }
    }

    /// When a chuck point (M10, M11) block `b` is reached if not now: the first NCBR tick at
    /// which the spindle gives the signal its command asks for, zero speed if it is commanded
    /// stopped (`|rpm| >= 1` is still turning: the end of its coast-down), speed arrival if
    /// commanded turning (`Spindle::ready_at`), as a real control's chuck waits for them. None
    /// for any other block, or with the signal on now. The sync table then decides on the
    /// commanded speeds (docs/pulse-core.md, "Chuck and spindle").
    fn chuck_signal_at(&self, b: &Block) -> Option<u64> {
        use crate::block::Sync;
        if !matches!(b.sync, Some(Sync::ChuckClose) | Some(Sync::ChuckOpen)) {
            return None;
        }
        let now = self.now;
        let t = if self.spindle_dir == 0 {
            if self.sp.rpm_at(now).abs() >= 1.0 {
                self.sp.stops_at().unwrap_or(now)
            } else {
                now
            }
        } else {
            self.sp.ready_at(now).unwrap_or(now)
        };
        let p = self.period();
        (t > now).then(|| t.div_ceil(p) * p)
    }

    /// The spindle: its actual speed, encoder and index (docs/pulse-core.md, "The spindle").
    pub fn spindle(&self) -> &Spindle {
        &self.sp
    }

    /// Whether the spindle needs the NCBR ticks: G96 (its target follows X) or a ramp (a feed
    /// per revolution follows its speed), with it turning. Else blocks may run whole.
    fn spindle_live(&self) -> bool {
        self.spindle_dir != 0 && (self.css.is_some() || self.sp.ramps())
    }

    /// Whether the NCBR ticks until the current block ends could change anything: a live
    /// spindle (above) makes each tick look at its target and at the feed per revolution, but
    /// once neither can change before the block ends, those ticks change nothing but time and
    /// the block may run whole (as with the spindle stopped, or on the centre). That is:
    /// - the spindle's target is the one the tick would give it (`spindle_sync` sets none),
    ///   and stays so: under G97 it depends on nothing a block in motion changes; under G96
    ///   on X, so the rest of the block must not move X (a line or rapid with no X amount, or
    ///   no motion at all);
    /// - a feed per revolution in motion is the one the tick would compute, and the spindle is
    ///   at its target for good (`Spindle::steady_at`: `rpm_at` gives the target from then
    ///   on), so every later tick computes the very same speed and does not retarget;
    /// - the block is past its auxiliary functions (`PreAux` changes the spindle);
    /// - no watcher (it would see the state at every tick) and no answer for the source.
    ///
    /// A thread pass is timed by the spindle's closed form, which only a new target changes.
    fn spindle_needs_ticks(&self) -> bool {
        if !self.spindle_live() {
            return false;
        }
        if self.watch.is_some() || self.probe_answer.is_some() {
            return true;
        }
        let Some(c) = &self.current else {
            return true;
        };
        if c.phase == Phase::PreAux {
            return true;
        }
        if self.css.is_some() {
            let moves_x = c.motion.is_some()
                && (!matches!(c.block.motion, Kind::Linear | Kind::Rapid) || c.block.delta[0] != 0);
            if moves_x {
                return true;
            }
        }
        if self.spindle_target() != self.sp.target() {
            return true;
        }
        if let (Some(v), Some(_)) = (c.per_rev_v, &c.motion) {
            if !self.sp.steady_at(self.now) || self.feed_speed(&c.block, self.now) != v {
                return true;
            }
        }
        false
    }

    /// The spindle speed the status shows, signed rpm: the actual one; a spindle without a
    /// ramp under G97 is at the programmed speed after the override at once.
    pub(super) fn spindle_status(&self) -> i64 {
        if self.sp.ramps() || self.css.is_some() {
            self.sp.rpm_at(self.now).round() as i64
        } else {
            self.spindle_actual()
        }
    }

    fn finish_block(&mut self, t: u64, c: Current) {
        let m = c.block.m;
        let pass_end = c.block.thread.is_some() && c.block.tap == crate::block::Tap::No;
        if c.block.tap == crate::block::Tap::End || pass_end {
            // The tap is out of the hole with the spindle forward: a STOP given during it
            // holds now.
            self.in_tap = false;
            if std::mem::take(&mut self.hold_after_tap) && self.run != 0 {
                self.hold = true;
                self.notice = None;
            }
        }
        if matches!(m, Some(5) | Some(30)) {
            self.spindle = 0;
            self.spindle_dir = 0;
            self.orient = None;
        }
        if let Some(crate::block::Io::Orient { angle, .. }) = c.block.io {
            // M19: stopped, then oriented at once (no spindle encoder: docs/pulse-core.md).
            self.spindle = 0;
            self.spindle_dir = 0;
            self.orient = Some(angle);
        }
        self.spindle_sync(t);
        self.blocks_done += 1;
        self.just_completed = true;
        self.program_stop = matches!(m, Some(0) | Some(1));
        self.finished_at = Some(t);
        self.out.flush();
        let pos = self.out.pos;
        let run = self.job.as_ref().map_or(0, |j| j.id);
        if let Some(a) = &mut self.audit {
            a.push(BlockEnd {
                run,
                seq: c.block.seq,
                stmt: c.block.stmt,
                start: c.block.start(),
                end: c.block.end,
                pos,
                tip: pos[2] - self.settings.to_pulses(self.tool_len),
                tip_planned: pos[2]
                    - self
                        .settings
                        .to_pulses(c.len_planned.unwrap_or(self.tool_len)),
            });
        }
        if let Some(s) = &self.events {
            send_ev(
                s,
                &self.out.lossless,
                Event::Position {
                    t_ns: t,
                    pulses: pos,
                    held: self.out.shift,
                    speed_mm_min: 0.0,
                },
            );
        }
        if let Some(w) = c.wait {
            self.probe_answer = Some(Answer::Input(w.value));
        }
        if c.block.clocks {
            self.probe_answer = Some(Answer::Clocks {
                machine_ns: t,
                cycle_ns: self.lamp_time(t),
            });
        }
        if let Some((tripped, at_start)) = c.probe {
            self.probe_answer = Some(Answer::Probe {
                at: pos,
                tripped,
                at_start,
            });
            if let Some(s) = &self.events {
                send_ev(
                    s,
                    &self.out.lossless,
                    Event::Probe {
                        t_ns: t,
                        seq: c.block.seq,
                        stmt: c.block.stmt,
                        pulses: pos,
                        tripped,
                        at_start,
                    },
                );
            }
        }
        if pos != c.block.end {
            // The in-position check: a block must end on its programmed point.
            let e = c.entry.clone();
            let why = format!(
                "position error: ended at X{:.3} Y{:.3} Z{:.3}, programmed X{:.3} Y{:.3} Z{:.3}",
                self.settings.to_mm(pos[0]),
                self.settings.to_mm(pos[1]),
                self.settings.to_mm(pos[2]),
                self.settings.to_mm(c.block.end[0]),
                self.settings.to_mm(c.block.end[1]),
                self.settings.to_mm(c.block.end[2]),
            ) + &(3..crate::block::MAX_AXES)
                .filter(|&a| pos[a] != c.block.end[a])
                .map(|a| {
                    format!(
                        "; {} at {:.3}, programmed {:.3}",
                        axis_name(a),
                        self.settings.to_mm(pos[a]),
                        self.settings.to_mm(c.block.end[a])
                    )
                })
                .collect::<String>();
            self.refuse(&e, Some(&c.block), why);
            return;
        }
        if m == Some(30) {
            self.end_run(EndCause::ProgramEnd);
        }
    }
}
