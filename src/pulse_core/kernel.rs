//! The multi-channel kernel (docs/pulse-core.md, "Channels"): N channels, each a [`Machine`]
//! with its own settings, B1, run, hold, override, alarm and modal state, advanced on one NCBR
//! clock, and the [`SyncTable`] between them. E-STOP is machine-wide; START, STOP (feed hold),
//! RESET and a fault are per channel (or all channels).
//!
//! **Stepping.** Channels meet only at their sync points, so between two sync points a channel
//! runs alone, with the machine's whole-block fast-forward. [`Kernel::advance_to`] runs every
//! free channel to the time asked for or to its next sync point (the NCBR tick it reads the
//! block at), then takes the arrivals in time order: at each arrival time it counts the new
//! arrivals and lets the sync table release whom it can, at that time; a released channel runs
//! free again from there. When it returns every channel stands at the same machine time, so an
//! operator command (E-STOP) acts on all channels in the same tick. A kernel of one channel
//! without sync points is its machine alone: the same calls, the same pulses (tested).
//!
//! **Streaming.** The machining centre's kernel ([`Kernel::streaming`]) has one channel that
//! reads B1 as the translator thread fills it. Such a source can be neither copied (to look
//! ahead) nor read again (at the next work), so its channel runs alone, as its machine: the
//! clock stands still while the translator is behind ([`Outcome::Starved`]), and a wait for a
//! block stops at the tick it starts in.

use super::block_buffer::BlockBuffer;
use super::machine::{Machine, Mark, Reached, Until};
use super::runner::ChannelStatus;
use super::source::{ChannelSource, Fetch, VecSource};
use super::sync::{AtPoint, Decision, SyncTable, Transfer, WaitOn, WorkFlow};
use super::{Command, EndCause, RunKind, Status, Watcher};
use crate::block::{Statement, Sync};
use crate::record::EventSink;
use crate::settings::MachineSettings;
use std::sync::Arc;

/// Channels a kernel may have (the waiting M codes' channel mask is 8 bits).
pub const MAX_CHANNELS: usize = 8;

/// One channel: its machine, its program and where it stands with the sync table.
#[derive(Clone, Debug)]
struct Channel {
    m: Machine,
    src: ChannelSource,
    /// The NCBR tick it reached the sync point it waits at (None: at none).
    at_point: Option<u64>,
    /// Its arrival there is counted in the table.
    counted: bool,
    /// An injected fault (tool breakage): held until RESET.
    fault: Option<String>,
    /// The latest run end already taken into account (its id).
    seen_end: u64,
    /// Its part count reached the target.
    done: bool,
    /// When it finished.
    done_at: Option<u64>,
    /// Blocks and pulses of its runs before the current one (each part is a run).
    blocks_before: u64,
    pulses_before: [u64; 3],
    /// The run whose counts are in the totals.
    totalled_run: u64,
    /// What it was last reported waiting on at its sync point (a `Wait` event).
    waiting: Option<WaitOn>,
    /// Its program from its next run on (read again with revised tool offsets): taken at the
    /// next part or RESET, never inside a run.
    next_src: Option<VecSource>,
    /// What its runs are (recorded as `/nc/state`'s `run`): AUTO, or MDI for an MDI program.
    kind: RunKind,
}

impl Channel {
    fn new(m: Machine, src: ChannelSource) -> Channel {
        Channel {
            m,
            src,
            at_point: None,
            counted: false,
            fault: None,
            seen_end: 0,
            done: false,
            done_at: None,
            blocks_before: 0,
            pulses_before: [0; 3],
            totalled_run: 0,
            waiting: None,
            next_src: None,
            kind: RunKind::Auto,
        }
    }

    /// It can still move without the operator: a manual move moving or queued, or not
    /// finished, not waiting at a sync point and not idle (held at rest, stopped, faulted, in
    /// E-STOP or alarm are idle).
    fn progressing(&self) -> bool {
        // A channel done with its part target, or waiting at a sync point, may still move by
        // hand (a STEP after the cycle has finished): before stop 44 that move did not count,
        // so a wait for rest ended with it half done, and in real time the idle step ran it
        // up to 10 ms ahead of the wall clock.
        self.m.moves_by_hand() || (!self.done && self.at_point.is_none() && !self.m.is_idle())
    }

    /// Its program from the start: the one read again for it, if any, else the same.
    fn restart_program(&mut self) {
        match self.next_src.take() {
            Some(s) => self.src = ChannelSource::Program(s),
            None => self.src.rewind(),
        }
    }

    /// Its machine begins a new run (a new part, a START after RESET): the counts of the run
    /// that ends are added to the totals first.
    fn begin_run(&mut self) {
        let st = self.m.status();
        if (st.run == 0 || st.program_end) && st.runs != self.totalled_run {
            self.totalled_run = st.runs;
            self.blocks_before += st.blocks_done;
            for (a, p) in self.pulses_before.iter_mut().zip(st.pulses.xyz()) {
                *a += p;
            }
        }
        self.m.command(Command::Start(self.kind));
    }
}

/// A channel's state as the operator sees it.
#[derive(Clone, Debug, PartialEq)]
pub struct ChannelView {
    /// RUN flag of its machine (0: not running).
    pub run: u8,
    /// Feed hold in force.
    pub held: bool,
    /// The sync point it stands at, if any.
    pub at_sync: Option<Sync>,
    /// What it waits on there.
    pub waits_on: Option<WaitOn>,
    /// Its machine's alarm (E-STOP, a refused block).
    pub alarm: Option<String>,
    /// An injected fault.
    pub fault: Option<String>,
    /// Its part count reached the target.
    pub done: bool,
    /// It can still move without the operator (`Kernel::progressing`, the one rest
    /// predicate: the kernel's waits and idle step go by it, and a console's rest reads it
    /// here, beside the positions it shows).
    pub progressing: bool,
    /// The work its chuck holds, and whether the chuck is closed.
    pub work: Option<u32>,
    /// The chuck is closed.
    pub closed: bool,
    /// Parts counted.
    pub parts: u32,
    /// Axis positions, pulses.
    pub pos: [i64; 3],
    /// Pulses output per axis since its run began.
    pub pulses: [u64; 3],
    /// The source line of the block executing or last executed (0: none).
    pub line: u32,
    /// Blocks executed since the kernel began, over every run (part) of the channel.
    pub total_blocks: u64,
    /// Pulses output per axis since the kernel began, over every run.
    pub total_pulses: [u64; 3],
    /// When it reached the part target (machine time, ns).
    pub done_at: Option<u64>,
}

/// What a lathe channel does besides moving, as the kernel saw it happen: the console's
/// messages and the recording's `/lathe/event` (docs/recording.md "Lathe recordings").
/// Channels are 0-based; times are the kernel's machine time, ns.
#[derive(Clone, Debug, PartialEq)]
pub enum KernelEvent {
    /// A work passed from a chuck to another (`from` None = the bar feeder, `to` None = the
    /// unloader); `both_closed`: both chucks held it at the handover.
    Transfer {
        /// Machine time, ns.
        t: u64,
        /// Giving channel.
        from: Option<usize>,
        /// Receiving channel.
        to: Option<usize>,
        /// Work number.
        work: u32,
        /// Both chucks were closed on the work at the handover.
        both_closed: bool,
        /// The operator loaded it, or took it out (`loading manual`): `from` or `to` None is
        /// the operator, not the bar feeder or the unloader.
        by_hand: bool,
    },
    /// A thread pass started (or resumed) at an encoder index.
    ThreadPass {
        /// Channel.
        ch: usize,
        /// Machine time, ns.
        t: u64,
        /// Source line.
        line: u32,
        /// The index count the pass is anchored to.
        index: u64,
        /// The encoder count at its first pulse.
        encoder: u64,
        /// Resuming after a stop.
        resumed: bool,
    },
    /// A cutting block started with the work in the chuck.
    CutStart {
        /// Channel.
        ch: usize,
        /// Machine time, ns.
        t: u64,
        /// Source line.
        line: u32,
        /// The work.
        work: Option<u32>,
    },
    /// A channel reached a sync point and waits there.
    Wait {
        /// Channel.
        ch: usize,
        /// Machine time, ns.
        t: u64,
        /// What it waits on.
        on: WaitOn,
    },
    /// A channel counted a part at its program end.
    Part {
        /// Channel.
        ch: usize,
        /// Machine time, ns.
        t: u64,
        /// The channel's count.
        count: u32,
    },
    /// A channel reached the part target.
    Done {
        /// Channel.
        ch: usize,
        /// Machine time, ns.
        t: u64,
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
    /// An alarm stopped a channel.
    Alarm {
        /// Channel.
        ch: usize,
        /// Machine time, ns.
        t: u64,
        /// Source line (0: none).
        line: u32,
        /// Message.
        msg: String,
    },
    /// A block a console asked to be told of started (`Machine::mark_starts`: the blocks it
    /// says a program's message at). Not recorded: the console records what it says.
    BlockStart {
        /// Channel.
        ch: usize,
        /// Machine time, ns.
        t: u64,
        /// The block's sequence number.
        seq: u32,
    },
}

/// How [`Kernel::run_until_idle`] ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Outcome {
    /// Every channel finished; `parts` delivered to the unloader.
    Finished {
        /// Parts delivered.
        parts: u32,
    },
    /// A channel stands stopped (held, not started, between single blocks).
    Stopped,
    /// A channel is faulted (the first one).
    Fault {
        /// Channel.
        ch: usize,
        /// Reason.
        reason: String,
    },
    /// A channel is in alarm (the first one).
    Alarm {
        /// Channel.
        ch: usize,
        /// Message.
        msg: String,
    },
    /// Emergency stop.
    Estop,
    /// Every channel waits at a sync point or has finished.
    Deadlock {
        /// (channel, what it waits on) for every waiting channel.
        waits: Vec<(usize, Option<WaitOn>)>,
    },
    /// The machine time given passed first.
    TimeLimit,
    /// Feed override 0 holds the machine still for good ([`Kernel::stalled`]).
    Stalled,
    /// A streaming kernel's channel waits for its translator ([`Kernel::streaming`]): the
    /// clock stands at the tick that wanted the block.
    Starved,
    /// The block asked of [`Kernel::run_until`] started.
    BlockStart {
        /// Channel.
        ch: usize,
        /// The NCBR tick it started at, ns (the kernel stands at that tick's end).
        t: u64,
    },
}

/// N channels on one NCBR clock with a sync table.
#[derive(Clone, Debug)]
pub struct Kernel {
    chans: Vec<Channel>,
    table: SyncTable,
    now: u64,
    /// Events not yet taken ([`Kernel::take_events`]), in time order, none later than `now`.
    events: Vec<KernelEvent>,
    /// Events made but not yet released: channels run one after the other up to the same
    /// time, and a thread pass is known at its block's start but begins at the index, which
    /// may lie beyond `now`.
    pending: Vec<KernelEvent>,
    /// The watcher ([`Kernel::set_watch`]).
    watch: Option<Box<KernelWatch>>,
    /// The machine time [`Kernel::run_until`] runs between its looks at the channels, ns
    /// (0: a thousand NCBR periods): how late past the moment it waits for it may end.
    look_ns: u64,
}

/// What the sync table decides of a channel's view: a change of it is told to the watcher.
type SyncKey = (
    Option<Sync>,
    Option<WaitOn>,
    Option<String>,
    bool,
    Option<u32>,
    bool,
    u32,
);

fn sync_key(v: &ChannelView) -> SyncKey {
    (
        v.at_sync,
        v.waits_on,
        v.fault.clone(),
        v.done,
        v.work,
        v.closed,
        v.parts,
    )
}

/// One change a channel made, at a machine time.
#[derive(Clone, Debug)]
enum Change {
    /// Its machine's status changed (its machine's watch kept it).
    Status(Box<Status>),
    /// Its place in the sync table changed.
    Sync(Box<ChannelView>),
}

/// The kernel's watcher: every channel's state as last told, and the changes not yet told.
/// Channels run one after the other up to the same time, so their changes are gathered and
/// told in machine-time order once every channel stands at the kernel's time.
#[derive(Clone)]
struct KernelWatch {
    f: Watcher,
    told: Vec<ChannelStatus>,
    noted: Vec<Option<SyncKey>>,
    changes: Vec<(u64, usize, Change)>,
}

impl std::fmt::Debug for KernelWatch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("KernelWatch")
            .field("changes", &self.changes.len())
            .finish()
    }
}

impl KernelEvent {
    /// Its machine time, ns.
    pub fn t(&self) -> u64 {
        match self {
            KernelEvent::Transfer { t, .. }
            | KernelEvent::ThreadPass { t, .. }
            | KernelEvent::CutStart { t, .. }
            | KernelEvent::Wait { t, .. }
            | KernelEvent::Part { t, .. }
            | KernelEvent::Done { t, .. }
            | KernelEvent::Fault { t, .. }
            | KernelEvent::Alarm { t, .. }
            | KernelEvent::BlockStart { t, .. } => *t,
        }
    }

    /// The `/lathe/event` message of this event (docs/recording.md, "Lathe recordings"), None
    /// for a block start a console asked for (not recorded):
    /// the lathe console's words and texts. `work`: the work a thread pass cuts (the work of
    /// the channel's latest cut; the pass itself is one).
    pub fn record(&self, work: Option<u32>) -> Option<crate::record::Event> {
        let chan = |c: usize| u16::try_from(c + 1).unwrap_or(u16::MAX);
        let ev = |ch: usize, event, work, value, text| crate::record::Event::Lathe {
            t_ns: self.t(),
            channel: chan(ch),
            event,
            work,
            value,
            text,
        };
        Some(match self {
            KernelEvent::Transfer {
                from,
                to,
                work,
                both_closed,
                by_hand,
                ..
            } => {
                let (feeder, unloader) = if *by_hand {
                    ("OPERATOR", "OPERATOR")
                } else {
                    ("BAR FEEDER", "UNLOADER")
                };
                let text = format!(
                    "W{work} {} -> {}{}",
                    from.map_or(feeder.to_string(), |c| format!("CH{}", c + 1)),
                    to.map_or(unloader.to_string(), |c| format!("CH{}", c + 1)),
                    match (from, both_closed) {
                        (None, _) => "",
                        (Some(_), true) => " (both chucks closed)",
                        (Some(_), false) => " (NOT INTERLOCKED)",
                    }
                );
                match from {
                    None => ev(to.unwrap_or(0), "supply", Some(*work), None, text),
                    Some(f) => ev(
                        *f,
                        "transfer",
                        Some(*work),
                        Some(to.map_or(0, |c| c as i64 + 1)),
                        text,
                    ),
                }
            }
            KernelEvent::ThreadPass {
                ch,
                line,
                index,
                encoder,
                resumed,
                ..
            } => ev(
                *ch,
                "thread",
                work,
                Some(i64::try_from(*index).unwrap_or(i64::MAX)),
                format!(
                    "line {line}: pass {} at index {index} (encoder {encoder} at the first Z pulse)",
                    if *resumed { "resumed" } else { "starts" }
                ),
            ),
            KernelEvent::CutStart { ch, line, work, .. } => {
                ev(*ch, "cut", *work, None, format!("line {line}"))
            }
            KernelEvent::Wait { ch, on, .. } => {
                ev(*ch, "wait", None, None, format!("CH{} waits {on}", ch + 1))
            }
            KernelEvent::Part { ch, count, .. } => ev(
                *ch,
                "part",
                None,
                Some(i64::from(*count)),
                format!("CH{} part {count}", ch + 1),
            ),
            KernelEvent::Done { ch, .. } => ev(
                *ch,
                "done",
                None,
                None,
                format!("CH{} reached the part target", ch + 1),
            ),
            KernelEvent::Fault { ch, reason, .. } => ev(*ch, "fault", None, None, reason.clone()),
            KernelEvent::Alarm { ch, line, msg, .. } => {
                ev(*ch, "alarm", None, Some(i64::from(*line)), msg.clone())
            }
            // The console's own marks: what it says of them, it records.
            KernelEvent::BlockStart { .. } => return None,
        })
    }

    /// The channel it happened on (a transfer: the giving channel, or the receiving one
    /// from the bar feeder).
    pub fn channel(&self) -> usize {
        match self {
            KernelEvent::Transfer { from, to, .. } => from.or(*to).unwrap_or(0),
            KernelEvent::ThreadPass { ch, .. }
            | KernelEvent::CutStart { ch, .. }
            | KernelEvent::Wait { ch, .. }
            | KernelEvent::Part { ch, .. }
            | KernelEvent::Done { ch, .. }
            | KernelEvent::Fault { ch, .. }
            | KernelEvent::Alarm { ch, .. }
            | KernelEvent::BlockStart { ch, .. } => *ch,
        }
    }
}

impl Kernel {
    /// A kernel running `channels[i] = (settings, program)` on channel i, with the work flow
    /// (None: no chucks) and the part target. Refused: no channel or more than
    /// [`MAX_CHANNELS`], channels with different NCBR periods (one clock), a flow naming a
    /// channel the machine has not, a waiting M code that does not list its own channel or
    /// lists one the machine has not.
    pub fn new(
        channels: Vec<(MachineSettings, Vec<Statement>)>,
        flow: Option<WorkFlow>,
        target: u32,
    ) -> Result<Kernel, String> {
        let n = channels.len();
        if n == 0 || n > MAX_CHANNELS {
            return Err(format!(
                "the machine has {n} channels; 1 to {MAX_CHANNELS} are allowed"
            ));
        }
        let period = channels[0].0.ncbr_period_ns;
        if channels.iter().any(|c| c.0.ncbr_period_ns != period) {
            return Err("the channels have different NCBR periods: one clock runs them all".into());
        }
        check_programs(n, channels.iter().map(|c| &c.1), flow.as_ref())?;
        let table = SyncTable::new(n, flow, target);
        let chans = channels
            .into_iter()
            .enumerate()
            .map(|(i, (settings, prog))| {
                let mut m = Machine::new(settings);
                m.set_channel(true);
                m.set_cut_interlock(table.interlock(i));
                Channel::new(
                    m,
                    ChannelSource::Program(VecSource::from_statements(prog.into_iter().map(Ok))),
                )
            })
            .collect();
        Ok(Kernel::of(chans, table))
    }

    /// The machining centre's kernel: one channel, the machine `m`, reading B1 as the
    /// translator thread fills it (`buffer`), with no sync table and no part counter. Its
    /// source can be neither copied nor read again, so it runs alone as its machine
    /// ([`Kernel::run_until`], [`Kernel::run_to`]): time stands still while the translator
    /// is behind (with `Machine::set_starve_stops`), and a wait for a block stops at the tick
    /// the block starts in, as `Machine::run` does. It takes no program load, part target,
    /// fault or program replacement: its START loads B1 (`PulseCore::start`).
    pub fn streaming(m: Machine, buffer: Arc<BlockBuffer>) -> Kernel {
        let chans = vec![Channel::new(m, ChannelSource::Stream(buffer, None))];
        Kernel::of(chans, SyncTable::new(1, None, 0))
    }

    fn of(chans: Vec<Channel>, table: SyncTable) -> Kernel {
        Kernel {
            chans,
            table,
            now: 0,
            events: Vec::new(),
            pending: Vec::new(),
            watch: None,
            look_ns: 0,
        }
    }

    /// The one channel of a streaming kernel ([`Kernel::streaming`]), which runs alone.
    fn alone(&mut self) -> Option<&mut Channel> {
        match self.chans.as_mut_slice() {
            [c] if c.src.streams() => Some(c),
            _ => None,
        }
    }

    /// Whether the kernel is a streaming one ([`Kernel::streaming`]).
    pub fn streams(&self) -> bool {
        matches!(self.chans.as_slice(), [c] if c.src.streams())
    }

    /// Records every channel's machine to `sink` (None: no recording): a streaming kernel's
    /// one channel untagged, as the centre's recordings have it, each channel of a lathe
    /// tagged with its channel (`EventSink::for_channel`); every machine keeps its pulse
    /// capture. `lossless`: wait for the recorder (virtual time).
    pub fn set_recording(&mut self, sink: Option<EventSink>, lossless: bool) {
        let tagged = !self.streams();
        for (i, c) in self.chans.iter_mut().enumerate() {
            let s = match tagged {
                true => sink.as_ref().map(|s| s.for_channel(i)),
                false => sink.clone(),
            };
            let capture = c.m.captures();
            c.m.set_recording(s, capture);
            c.m.set_lossless_recording(lossless);
        }
    }

    /// A streaming kernel's channel logs what B1 hands it from now on (the real-time step
    /// queue's; off: forgets it).
    pub fn log_stream(&mut self, on: bool) {
        for c in &mut self.chans {
            c.src.log(on);
        }
    }

    /// What B1 has handed a streaming kernel's channel since the last call (with the log on).
    pub fn take_stream_log(&mut self) -> Vec<Fetch> {
        self.chans
            .first_mut()
            .map(|c| c.src.take_log())
            .unwrap_or_default()
    }

    /// A streaming kernel's channel reads `fetched` again, then nothing, until
    /// [`Kernel::resume_stream`] (a copy kept before a real-time slice, rolled forward to an
    /// E-STOP's instant).
    pub fn replay_stream(&mut self, fetched: Vec<Fetch>) {
        if let Some(c) = self.chans.first_mut() {
            c.src.replay(fetched);
        }
    }

    /// A streaming kernel's channel reads B1 again, logging.
    pub fn resume_stream(&mut self) {
        if let Some(c) = self.chans.first_mut() {
            c.src.resume();
        }
    }

    /// Where the next NCBR slice of `ticks` ticks ends: channel 0's next tick (every channel
    /// ticks with it) and `ticks` − 1 periods on.
    pub fn slice_end(&self, ticks: u64) -> u64 {
        let m = self.first();
        let period = m.settings().ncbr_period_ns.max(1);
        m.next_tick_end()
            .saturating_add(period.saturating_mul(ticks.max(1) - 1))
    }

    /// An operator command to channel `ch` (None: every channel): E-STOP machine-wide
    /// ([`Kernel::estop`]), START, STOP (feed hold) and RESET by their rules here, any other to
    /// the channels' machines. Its refusals.
    pub fn command_to(&mut self, ch: Option<usize>, c: Command) -> Result<(), String> {
        match c {
            Command::EStop => {
                self.estop();
                Ok(())
            }
            Command::Start(kind) => self.start_as(ch, kind),
            Command::Stop => self.stop(ch),
            Command::Reset => self.reset(ch),
            c => match ch {
                Some(i) => self.command(i, c),
                None => (0..self.chans.len()).try_for_each(|i| self.command(i, c.clone())),
            },
        }
    }

    /// The refusal of what a streaming kernel does not take: `what`.
    fn refuse_stream(&self, what: &str) -> Result<(), String> {
        match self.streams() {
            true => Err(format!(
                "no {what} here: the machine's one channel runs its program as the translator \
                 reads it (a lathe channel's program is read whole)"
            )),
            false => Ok(()),
        }
    }

    /// A new cycle's programs, one a channel, with its work flow (None: no chucks) and part
    /// target, on the kernel as it stands: each channel's machine keeps its axes, spindle,
    /// coolant, tool, overrides, switches and the one clock, as a real control keeps its
    /// machine when a program is loaded; the sync table, the part counts and the totals
    /// begin again. `starts[i]`: the block numbers whose starts channel i reports
    /// ([`KernelEvent::BlockStart`]). Refused, nothing changed, while a channel has a run
    /// loaded or moves, or for programs [`Kernel::new`] would refuse. Nothing starts: START
    /// does.
    pub fn load(
        &mut self,
        programs: Vec<Vec<Statement>>,
        flow: Option<WorkFlow>,
        target: u32,
        starts: Vec<Vec<u32>>,
    ) -> Result<(), String> {
        let n = self.chans.len();
        if programs.len() != n {
            return Err(format!(
                "{} programs for {n} channels: give one program per channel",
                programs.len()
            ));
        }
        self.refuse_stream("program load")?;
        check_programs(n, programs.iter(), flow.as_ref())?;
        for (i, c) in self.chans.iter().enumerate() {
            if !c.m.start_begins_run(c.kind) || !c.m.is_idle() || c.m.is_estop() {
                return Err(format!(
                    "CH{}: a run is loaded or the machine moves; a program is loaded at rest",
                    i + 1
                ));
            }
        }
        self.table = SyncTable::new(n, flow, target);
        let mut starts = starts.into_iter();
        for (i, (c, prog)) in self.chans.iter_mut().zip(programs).enumerate() {
            c.m.set_cut_interlock(self.table.interlock(i));
            c.m.mark_starts(starts.next().unwrap_or_default());
            c.src = ChannelSource::Program(VecSource::from_statements(prog.into_iter().map(Ok)));
            c.next_src = None;
            c.at_point = None;
            c.counted = false;
            c.fault = None;
            c.done = false;
            c.done_at = None;
            c.waiting = None;
            // The totals are the new cycle's: the run that ended before it is not counted.
            c.blocks_before = 0;
            c.pulses_before = [0; 3];
            c.totalled_run = c.m.status().runs;
        }
        self.note_sync(self.now, 0..n);
        Ok(())
    }

    /// Tells `w` every channel's state at every change of one of them (its machine's status:
    /// RUN, hold, alarm, the block, tool, spindle, overrides; or its place in the sync table:
    /// arrival, wait, release, chuck, work, part, fault), in machine-time order, each once
    /// every channel stands at the time asked of [`Kernel::advance_to`]; every status's
    /// `machine_ns` is the time of the change. None stops it (and the channels keep nothing).
    pub fn set_watch(&mut self, w: Option<Watcher>) {
        if let Some(c) = self.alone() {
            // Alone, its machine tells its changes as they come.
            c.m.set_watch(w);
            return;
        }
        for c in &mut self.chans {
            c.m.keep_watch(w.is_some());
        }
        self.watch = w.map(|f| {
            let told: Vec<ChannelStatus> = (0..self.chans.len())
                .map(|i| ChannelStatus {
                    status: self.chans[i].m.status(),
                    sync: self.channel(i),
                })
                .collect();
            Box::new(KernelWatch {
                f,
                noted: told.iter().map(|c| c.sync.as_ref().map(sync_key)).collect(),
                told,
                changes: Vec::new(),
            })
        });
    }

    /// With a watcher: notes a change of channels `chans`' places in the sync table, at `t`.
    fn note_sync(&mut self, t: u64, chans: std::ops::Range<usize>) {
        if self.watch.is_none() {
            return;
        }
        for i in chans {
            let Some(v) = self.channel(i) else { continue };
            let key = sync_key(&v);
            let Some(w) = self.watch.as_mut() else { return };
            if w.noted.get(i) != Some(&Some(key.clone())) {
                if let Some(n) = w.noted.get_mut(i) {
                    *n = Some(key);
                }
                w.changes.push((t, i, Change::Sync(Box::new(v))));
            }
        }
    }

    /// With a watcher: the commands given since the last advance (E-STOP, RESET, START, a
    /// fault, an override) changed what at the kernel's time.
    fn watch_commands(&mut self) {
        if self.watch.is_none() {
            return;
        }
        for c in &mut self.chans {
            c.m.watch_now();
        }
        self.note_sync(self.now, 0..self.chans.len());
    }

    /// With a watcher: tells it the changes made up to now, in time order (stable: a channel's
    /// changes at one time keep their order).
    fn tell_watch(&mut self) {
        let Some(w) = self.watch.as_mut() else {
            return;
        };
        for (i, c) in self.chans.iter_mut().enumerate() {
            for st in c.m.take_watched() {
                w.changes
                    .push((st.machine_ns, i, Change::Status(Box::new(st))));
            }
        }
        w.changes.sort_by_key(|c| c.0);
        for (t, i, change) in std::mem::take(&mut w.changes) {
            let Some(c) = w.told.get_mut(i) else { continue };
            match change {
                Change::Status(st) => c.status = *st,
                Change::Sync(v) => c.sync = Some(*v),
            }
            for c in &mut w.told {
                c.status.machine_ns = t;
            }
            (w.f)(&w.told);
        }
    }

    /// Machine time, ns (every channel stands at it between calls).
    pub fn now(&self) -> u64 {
        match self.streams() {
            true => self.first().now(),
            false => self.now,
        }
    }

    /// The events since the last call, in time order; every one at or before [`Kernel::now`]
    /// (a thread pass is reported once the encoder has reached its index).
    pub fn take_events(&mut self) -> Vec<KernelEvent> {
        std::mem::take(&mut self.events)
    }

    /// Releases the events made so far that are not later than `now`, in time order (stable:
    /// events of the same time keep the order they were made in).
    fn flush(&mut self) {
        if self.pending.is_empty() {
            return;
        }
        self.pending.sort_by_key(KernelEvent::t);
        let now = self.now;
        let later = self.pending.partition_point(|e| e.t() <= now);
        let rest = self.pending.split_off(later);
        self.events.append(&mut self.pending);
        self.pending = rest;
    }

    /// A thread pass not begun when channel `ch` (None: every channel) stopped its run
    /// (E-STOP, RESET) never happened: it is forgotten.
    fn forget_passes(&mut self, ch: Option<usize>) {
        let now = self.now;
        self.pending.retain(|e| {
            !matches!(e, KernelEvent::ThreadPass { ch: c, t, .. }
                if *t > now && ch.is_none_or(|ch| ch == *c))
        });
    }

    /// Channel `i`'s machine's marks since the last look become events: a cut notes the
    /// work in the table.
    fn note(&mut self, i: usize) {
        let marks = self.chans[i].m.take_marks();
        for mk in marks {
            let ev = match mk {
                Mark::Cut { t, line } => {
                    self.table.cut(i);
                    KernelEvent::CutStart {
                        ch: i,
                        t,
                        line,
                        work: self.table.work(i).0,
                    }
                }
                Mark::Thread {
                    t,
                    line,
                    index,
                    encoder,
                } => KernelEvent::ThreadPass {
                    ch: i,
                    t,
                    line,
                    index,
                    encoder,
                    resumed: false,
                },
                Mark::Start { t, seq } => KernelEvent::BlockStart { ch: i, t, seq },
                Mark::Alarm { t, line, msg } => KernelEvent::Alarm {
                    ch: i,
                    t,
                    line,
                    msg,
                },
            };
            self.pending.push(ev);
        }
    }

    /// The number of channels.
    pub fn channels(&self) -> usize {
        self.chans.len()
    }

    /// Channel `ch`'s machine.
    pub fn machine(&self, ch: usize) -> Option<&Machine> {
        self.chans.get(ch).map(|c| &c.m)
    }

    /// Channel 0's machine (every kernel has one): the machining centre's only one.
    pub fn first(&self) -> &Machine {
        &self.chans[0].m
    }

    /// Channel 0's machine, for what the kernel does not wrap: the centre's magazine, position,
    /// jog feed, audit and step queue.
    pub fn first_mut(&mut self) -> &mut Machine {
        &mut self.chans[0].m
    }

    /// Channel `ch`'s machine, for what the kernel does not wrap (overrides, switches,
    /// recording, the audit).
    pub fn machine_mut(&mut self, ch: usize) -> Option<&mut Machine> {
        self.chans.get_mut(ch).map(|c| &mut c.m)
    }

    /// The sync table.
    pub fn table(&self) -> &SyncTable {
        &self.table
    }

    /// Every handover so far.
    pub fn transfers(&self) -> &[Transfer] {
        self.table.transfers()
    }

    /// The time the last channel finished (None until every channel has).
    pub fn finished_at(&self) -> Option<u64> {
        self.chans
            .iter()
            .map(|c| c.done_at)
            .try_fold(0, |a, d| d.map(|d| a.max(d)))
    }

    /// Sets channel `ch`'s axis positions before it runs (refused with a run loaded).
    pub fn set_position(&mut self, ch: usize, pos: [i64; 3]) -> Result<(), String> {
        let c = self.chans.get_mut(ch).ok_or_else(|| no_channel(ch))?;
        if c.m.set_position(pos) {
            Ok(())
        } else {
            Err(format!("CH{}: a run is loaded", ch + 1))
        }
    }

    /// Sets the clock of every channel to `t` (a whole NCBR tick, rounded up) before anything
    /// has run: a kernel made for a console's next cycle goes on from its machine time.
    pub fn set_clock(&mut self, t: u64) -> Result<(), String> {
        if self.chans.iter_mut().all(|c| c.m.set_clock(t)) {
            self.now = self.chans.first().map_or(t, |c| c.m.now());
            Ok(())
        } else {
            Err("the clock is set before anything runs".into())
        }
    }

    /// Sets the part target (refused below the works already supplied).
    pub fn set_target(&mut self, n: u32) -> Result<(), String> {
        self.refuse_stream("part target")?;
        if n != self.table.target() && self.chans.iter().any(|c| c.done) {
            return Err(format!("target {n}: a channel has already finished"));
        }
        self.table.set_target(n)
    }

    /// The channels a command addresses: one, or all (None).
    fn select(&self, ch: Option<usize>) -> Result<std::ops::Range<usize>, String> {
        match ch {
            None => Ok(0..self.chans.len()),
            Some(c) if c < self.chans.len() => Ok(c..c + 1),
            Some(c) => Err(no_channel(c)),
        }
    }

    /// START of channel `ch` (None: every channel): begins its run from the start of its
    /// program, or resumes it (a feed hold, a stop). A faulted channel needs RESET first; a
    /// finished one stays finished. The refusals, if any, are returned.
    pub fn start(&mut self, ch: Option<usize>) -> Result<(), String> {
        self.start_as(ch, RunKind::Auto)
    }

    /// [`Kernel::start`], the runs begun being of `kind` (an MDI program's: MDI).
    pub fn start_as(&mut self, ch: Option<usize>, kind: RunKind) -> Result<(), String> {
        let mut refused = Vec::new();
        for i in self.select(ch)? {
            let c = &mut self.chans[i];
            c.kind = kind;
            if c.done {
                continue;
            }
            if let Some(f) = &c.fault {
                refused.push(format!(
                    "CH{} START refused: fault ({f}), press RESET",
                    i + 1
                ));
                continue;
            }
            if c.m.run_flag() != 0 && !c.m.is_held() {
                // Running (or waiting at a sync point): START has nothing to do.
                continue;
            }
            // Loading by hand: a cycle begins with a work in the chuck.
            let now = c.m.now();
            let before = self.table.transfers().len();
            self.table.load_by_hand(now);
            self.push_transfers(before);
            let c = &mut self.chans[i];
            c.m.set_cut_interlock(self.table.interlock(i));
            c.begin_run();
            if let Some(n) = c.m.status().notice {
                refused.push(format!("CH{} {n}", i + 1));
            }
        }
        if refused.is_empty() {
            Ok(())
        } else {
            Err(refused.join("; "))
        }
    }

    /// STOP (feed hold) of channel `ch` (None: every channel).
    pub fn stop(&mut self, ch: Option<usize>) -> Result<(), String> {
        for i in self.select(ch)? {
            self.chans[i].m.command(Command::Stop);
        }
        Ok(())
    }

    /// RESET of channel `ch` (None: every channel). A fault alone is cleared keeping the
    /// channel's place (it stands held; START goes on with the interrupted block, as the
    /// simulator did). Otherwise (an E-STOP, an alarm, or a channel running) the run is
    /// abandoned: the channel returns to the start of its program, its sync points counted
    /// as when its cycle began, keeping the work its chuck holds and its count; START then
    /// begins a new cycle there, and no interrupted block is resumed.
    pub fn reset(&mut self, ch: Option<usize>) -> Result<(), String> {
        for i in self.select(ch)? {
            let c = &mut self.chans[i];
            let fault_only = c.fault.is_some() && !c.m.is_estop() && c.m.alarm().is_none();
            c.fault = None;
            if fault_only {
                continue;
            }
            c.m.command(Command::Reset);
            c.restart_program();
            c.at_point = None;
            c.counted = false;
            c.waiting = None;
            self.table.reset(i);
            self.note(i);
            self.forget_passes(Some(i));
        }
        self.flush();
        Ok(())
    }

    /// E-STOP: every channel's run is abandoned now, in the same tick; RESET needed.
    pub fn estop(&mut self) {
        let now = self.now;
        for (i, c) in self.chans.iter_mut().enumerate() {
            let line = c.m.status().executing.map_or(0, |e| e.stmt.line);
            c.m.command(Command::EStop);
            c.at_point = None;
            c.counted = false;
            c.waiting = None;
            self.table.leave(i);
            let msg = c.m.alarm().unwrap_or("EMERGENCY STOP").to_string();
            self.pending.push(KernelEvent::Alarm {
                ch: i,
                t: now,
                line,
                msg,
            });
        }
        self.forget_passes(None);
        self.flush();
    }

    /// Injects a fault into channel `ch` (tool breakage): a feed hold that only RESET then
    /// START end. A finished channel cannot fault.
    pub fn fault(&mut self, ch: usize, reason: &str) -> Result<(), String> {
        self.refuse_stream("fault injection")?;
        let c = self.chans.get_mut(ch).ok_or_else(|| no_channel(ch))?;
        if c.done {
            return Err(format!("CH{} has finished", ch + 1));
        }
        c.fault = Some(reason.to_string());
        c.m.command(Command::Stop);
        self.pending.push(KernelEvent::Fault {
            ch,
            t: self.now,
            reason: reason.to_string(),
        });
        self.flush();
        Ok(())
    }

    /// Channel `ch` runs `prog`, the same program read again with its tools revised: from its
    /// next tool call not yet read in the part under way, as a real lathe takes a wear offset
    /// at the next T, and whole from its next part (or a RESET). Refused unless its waiting
    /// codes and chuck codes are those of the program it replaces, in the same order: the sync
    /// table was made for them. The line of the tool call it is taken at, if in this part.
    pub fn replace_program(
        &mut self,
        ch: usize,
        prog: Vec<Statement>,
    ) -> Result<Option<u32>, String> {
        self.refuse_stream("program replacement")?;
        let c = self.chans.get_mut(ch).ok_or_else(|| no_channel(ch))?;
        let ChannelSource::Program(src) = &mut c.src else {
            return Err(no_channel(ch));
        };
        let syncs =
            |src: &VecSource| -> Vec<Sync> { src.blocks().filter_map(|b| b.sync).collect() };
        let next = VecSource::from_statements(prog.into_iter().map(Ok));
        if syncs(&next) != syncs(src) {
            return Err(format!(
                "CH{}: the program read again has other waiting or chuck codes",
                ch + 1
            ));
        }
        // Inside the part: from the next tool call B1 has not yet read (every block before it
        // is the one read before; a block ahead of it, already read, keeps the old offsets).
        let at = src.splice_at_next_tool_call(&next).map(|b| b.stmt);
        c.next_src = Some(next);
        Ok(at)
    }

    /// Another operator command to channel `ch`'s machine (override, SINGLE BLOCK, ...).
    pub fn command(&mut self, ch: usize, cmd: Command) -> Result<(), String> {
        let c = self.chans.get_mut(ch).ok_or_else(|| no_channel(ch))?;
        c.m.command(cmd);
        Ok(())
    }

    /// Channel `ch`'s state (None for a streaming kernel's, which has no place in a sync
    /// table: its machine's status says it all).
    pub fn channel(&self, ch: usize) -> Option<ChannelView> {
        if self.streams() {
            return None;
        }
        let c = self.chans.get(ch)?;
        let st = c.m.status();
        let (work, closed) = self.table.work(ch);
        Some(ChannelView {
            run: st.run,
            held: st.hold,
            at_sync: c.m.sync_point(),
            waits_on: self.table.waits_on(ch).filter(|_| c.at_point.is_some()),
            alarm: st.alarm,
            fault: c.fault.clone(),
            done: c.done,
            progressing: c.progressing(),
            work,
            closed,
            parts: self.table.parts(ch),
            pos: st.pos.xyz(),
            pulses: st.pulses.xyz(),
            line: st.executing.map_or(0, |e| e.stmt.line),
            total_blocks: c.blocks_before + st.blocks_done,
            total_pulses: {
                let mut t = c.pulses_before;
                for (a, p) in t.iter_mut().zip(st.pulses.xyz()) {
                    *a += p;
                }
                t
            },
            done_at: c.done_at,
        })
    }

    /// Runs every channel to machine time `t` as [`Kernel::advance_to`] does: a streaming
    /// kernel's channel ([`Kernel::streaming`]) up to where its translator has read
    /// ([`Outcome::Starved`]: call again once B1 has blocks), else [`Outcome::TimeLimit`].
    pub fn run_to(&mut self, t: u64) -> Outcome {
        if let Some(c) = self.alone() {
            return match c.m.run(&mut c.src, Until::Time(t), 0) {
                Reached::Starved => Outcome::Starved,
                _ => Outcome::TimeLimit,
            };
        }
        self.advance_to(t);
        Outcome::TimeLimit
    }

    /// Runs every channel to machine time `t` (see the module comment).
    pub fn advance_to(&mut self, t: u64) {
        self.watch_commands();
        // Commands since the last call (START of a held channel) may free a waiting one.
        self.resolve_at(self.now);
        loop {
            for i in 0..self.chans.len() {
                self.free_run(i, t);
            }
            let next = self
                .chans
                .iter()
                .filter(|c| !c.counted)
                .filter_map(|c| c.at_point)
                .min();
            match next {
                Some(te) => self.resolve_at(te),
                None => break,
            }
        }
        for c in &mut self.chans {
            if c.m.now() < t {
                c.m.advance_to(t, &mut c.src);
            }
        }
        for i in 0..self.chans.len() {
            self.note(i);
        }
        self.now = self.now.max(t);
        self.flush();
        self.tell_watch();
    }

    /// Runs channel `i` alone until `t`, its next sync point, or its end (the part counter
    /// then begins its next cycle at once).
    fn free_run(&mut self, i: usize, t: u64) {
        loop {
            let c = &mut self.chans[i];
            if c.at_point.is_some() || c.m.now() >= t {
                return;
            }
            let r = c.m.run(&mut c.src, Until::SyncPoint(t), u64::MAX);
            self.note(i);
            let c = &mut self.chans[i];
            match r {
                Reached::Sync => {
                    c.at_point = Some(c.m.now());
                    c.counted = false;
                    return;
                }
                Reached::Idle => {
                    if !self.program_end(i) {
                        let c = &mut self.chans[i];
                        c.m.advance_to(t, &mut c.src);
                        return;
                    }
                }
                _ => return,
            }
        }
    }

    /// Channel `i`'s run ended: at its program's end the part counter counts the work and,
    /// short of the target, rewinds the program and begins the next cycle (true).
    fn program_end(&mut self, i: usize) -> bool {
        let c = &mut self.chans[i];
        let Some(e) = c.m.last_end() else {
            return false;
        };
        if e.id == c.seen_end {
            return false;
        }
        c.seen_end = e.id;
        if e.cause != EndCause::ProgramEnd || !self.table.has_flow() {
            return false;
        }
        let now = c.m.now();
        let before = self.table.transfers().len();
        let done = self.table.program_end(i, now);
        self.push_transfers(before);
        let c = &mut self.chans[i];
        c.m.set_cut_interlock(self.table.interlock(i));
        self.pending.push(KernelEvent::Part {
            ch: i,
            t: now,
            count: self.table.parts(i),
        });
        if done {
            let c = &mut self.chans[i];
            c.done = true;
            c.done_at = Some(now);
            self.pending.push(KernelEvent::Done { ch: i, t: now });
            self.note_sync(now, i..i + 1);
            return false;
        }
        self.note_sync(now, i..i + 1);
        let c = &mut self.chans[i];
        c.restart_program();
        c.begin_run();
        true
    }

    /// The table's transfers from the `before`-th on, as events.
    fn push_transfers(&mut self, before: usize) {
        let by_hand = self.table.manual();
        for tr in &self.table.transfers()[before..] {
            self.pending.push(KernelEvent::Transfer {
                t: tr.t,
                from: tr.from,
                to: tr.to,
                work: tr.work,
                both_closed: tr.both_closed,
                by_hand,
            });
        }
    }

    /// The arrivals at time `te` are counted, then the table releases whom it can, at `te`.
    fn resolve_at(&mut self, te: u64) {
        for i in 0..self.chans.len() {
            let c = &mut self.chans[i];
            if c.at_point == Some(te) && !c.counted {
                c.counted = true;
                if let Some(p) = c.m.sync_point() {
                    self.table.arrive(i, p);
                }
            }
        }
        let at: Vec<Option<AtPoint>> = self
            .chans
            .iter()
            .map(|c| {
                let p = c.m.sync_point()?;
                (c.counted && c.at_point.is_some_and(|a| a <= te)).then_some(AtPoint {
                    point: p,
                    can_go: !c.m.is_held() && c.fault.is_none(),
                    spindle: c.m.spindle_commanded(),
                })
            })
            .collect();
        if at.iter().all(Option::is_none) {
            return;
        }
        let before = self.table.transfers().len();
        let decided = self.table.resolve(te, &at);
        self.push_transfers(before);
        for (i, d) in decided {
            let c = &mut self.chans[i];
            if c.m.now() < te {
                c.m.advance_to(te, &mut c.src);
            }
            c.at_point = None;
            c.counted = false;
            c.waiting = None;
            match d {
                Decision::Release => {
                    c.m.release_sync();
                }
                Decision::Refuse(why) => c.m.refuse_sync(why),
            }
        }
        for (i, c) in self.chans.iter_mut().enumerate() {
            c.m.set_cut_interlock(self.table.interlock(i));
            let on = self.table.waits_on(i).filter(|_| c.at_point.is_some());
            if on.is_some() && on != c.waiting {
                if let Some(on) = on {
                    self.pending.push(KernelEvent::Wait { ch: i, t: te, on });
                }
            }
            c.waiting = on.or(c.waiting.filter(|_| c.at_point.is_some()));
        }
        self.note_sync(te, 0..self.chans.len());
    }

    /// Whether some channel can still move without the operator (not finished, not waiting
    /// at a sync point, not idle: held at rest, stopped, faulted, in E-STOP or alarm).
    pub fn progressing(&self) -> bool {
        self.chans.iter().any(Channel::progressing)
    }

    /// How much machine time [`Kernel::run_until`] runs between its looks at the channels
    /// (0: a thousand NCBR periods, `novanc run`'s, which reads the machine time of each
    /// event, not of the run's end). A console waiting for rest sets 10 ms: its wait ends at
    /// most that late, as it did when the console stepped the kernel itself.
    pub fn set_look_ns(&mut self, ns: u64) {
        self.look_ns = ns;
    }

    /// Feed override 0 holds the machine still for good: every channel that would go on
    /// stands mid-block in a feed move at override 0 (`Machine::is_stalled`), and one does.
    /// Nothing but the operator changes that, so a wait for rest would never end.
    pub fn stalled(&self) -> bool {
        let mut any = false;
        for c in &self.chans {
            if c.done || c.at_point.is_some() || c.m.is_idle() {
                continue;
            }
            if !c.m.is_stalled() {
                return false;
            }
            any = true;
        }
        any
    }

    /// Runs until every channel has finished or none can go on without the operator, or
    /// `max_ns` of machine time has passed.
    pub fn run_until_idle(&mut self, max_ns: u64) -> Outcome {
        self.run_until(max_ns, None)
    }

    /// [`Kernel::run_until_idle`], and with `block` = (channel, N) only until block N of that
    /// channel's program starts: N is the block's sequence number (`Block::seq`, the N of the
    /// listing, the centre's `wait block N`). It then returns [`Outcome::BlockStart`] with
    /// every channel at the end of the NCBR tick the block started in, so the block is the
    /// channel's executing one. Channels run one after the other up to the same time and
    /// cannot be taken back, so each step is first run on a quiet copy of the kernel
    /// (recording and keeping nothing, telling no watcher) that finds the tick; the kernel
    /// then runs to that tick's end, and finds the start itself.
    pub fn run_until(&mut self, max_ns: u64, block: Option<(usize, u32)>) -> Outcome {
        if let Some(c) = self.alone() {
            let until = block.map_or(Until::Idle, |(_, seq)| Until::BlockStart(seq));
            let r = c.m.run(&mut c.src, until, max_ns);
            let t = c.m.now();
            return match r {
                Reached::BlockStart => Outcome::BlockStart { ch: 0, t },
                Reached::Starved => Outcome::Starved,
                Reached::Stalled => Outcome::Stalled,
                Reached::Time | Reached::Limit => Outcome::TimeLimit,
                _ => self.outcome(),
            };
        }
        let t0 = self.now;
        let period = self
            .chans
            .first()
            .map_or(1, |c| c.m.settings().ncbr_period_ns.max(1));
        let step = match self.look_ns {
            0 => period.saturating_mul(1000),
            ns => ns.max(period),
        };
        let looked = block.and_then(|(ch, seq)| {
            let m = &mut self.chans.get_mut(ch)?.m;
            m.look_for_block(Some(seq));
            Some(ch)
        });
        let outcome = loop {
            let mut t = self.now.saturating_add(step).min(t0.saturating_add(max_ns));
            if let Some((ch, seq)) = block {
                if let Some(tb) = self.block_start_before(ch, seq, t) {
                    t = (tb / period).saturating_add(1).saturating_mul(period);
                }
            }
            self.advance_to(t);
            if let Some(ch) = looked {
                if let Some(t) = self.chans[ch].m.block_started_at() {
                    break Outcome::BlockStart { ch, t };
                }
            }
            if !self.progressing() {
                break self.outcome();
            }
            if self.stalled() {
                break Outcome::Stalled;
            }
            if self.now - t0 >= max_ns {
                break Outcome::TimeLimit;
            }
        };
        if let Some(ch) = looked {
            self.chans[ch].m.look_for_block(None);
        }
        outcome
    }

    /// When block `seq` of channel `ch` starts if every channel runs on to `t`, found on a
    /// quiet copy of the kernel (None: not before `t`).
    fn block_start_before(&mut self, ch: usize, seq: u32, t: u64) -> Option<u64> {
        let mut k = self.quiet_copy();
        k.chans.get_mut(ch)?.m.look_for_block(Some(seq));
        k.advance_to(t);
        k.chans[ch].m.block_started_at()
    }

    /// A copy of the kernel to look ahead with, or to roll back to (the real-time step
    /// queue's): the same state, every channel's machine a quiet copy (`Machine::quiet_copy`:
    /// no recording, capture, audit or marks), no events taken or watcher, the events not yet
    /// due kept.
    pub(super) fn quiet_copy(&mut self) -> Kernel {
        let chans = self
            .chans
            .iter_mut()
            .map(|c| {
                let quiet = c.m.quiet_copy();
                let m = std::mem::replace(&mut c.m, quiet);
                let copy = c.clone();
                c.m = m;
                copy
            })
            .collect();
        Kernel {
            chans,
            table: self.table.clone(),
            now: self.now,
            events: Vec::new(),
            pending: self.pending.clone(),
            watch: None,
            look_ns: self.look_ns,
        }
    }

    /// What the state means once no channel progresses.
    fn outcome(&self) -> Outcome {
        if self.chans.iter().all(|c| c.done) {
            return Outcome::Finished {
                parts: self.table.delivered(),
            };
        }
        if self.chans.iter().any(|c| c.m.is_estop()) {
            return Outcome::Estop;
        }
        for (ch, c) in self.chans.iter().enumerate() {
            if let Some(reason) = &c.fault {
                return Outcome::Fault {
                    ch,
                    reason: reason.clone(),
                };
            }
        }
        for (ch, c) in self.chans.iter().enumerate() {
            if let Some(msg) = c.m.alarm() {
                return Outcome::Alarm {
                    ch,
                    msg: msg.to_string(),
                };
            }
        }
        if self
            .chans
            .iter()
            .any(|c| !c.done && (c.m.is_held() || (c.at_point.is_none() && c.m.is_idle())))
        {
            return Outcome::Stopped;
        }
        Outcome::Deadlock {
            waits: self
                .chans
                .iter()
                .enumerate()
                .filter(|(_, c)| c.at_point.is_some())
                .map(|(i, _)| (i, self.table.waits_on(i)))
                .collect(),
        }
    }
}

/// The programs of a kernel of `n` channels and its work flow, checked: a flow naming a
/// channel the machine has not, a waiting M code that does not list its own channel or lists
/// one the machine has not, are refused.
fn check_programs<'a>(
    n: usize,
    programs: impl Iterator<Item = &'a Vec<Statement>>,
    flow: Option<&WorkFlow>,
) -> Result<(), String> {
    if let Some(f) = flow {
        f.check(n)?;
    }
    for (i, prog) in programs.enumerate() {
        for b in prog.iter().flat_map(|s| s.blocks.iter()) {
            if let Some(Sync::Wait { m, with }) = b.sync {
                if u32::from(with) >> n != 0 || with & (1 << i) == 0 {
                    return Err(format!(
                        "CH{} line {}: M{m} must list channel {} and only channels the machine has",
                        i + 1,
                        b.stmt,
                        i + 1
                    ));
                }
            }
        }
    }
    Ok(())
}

fn no_channel(ch: usize) -> String {
    format!("no channel {}", ch + 1)
}
