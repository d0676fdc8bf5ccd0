//! Recording: events from the pulse core and the console go to a recorder thread that writes
//! an MCAP file (docs/recording.md). The sender side never blocks: if the recorder falls behind, events are
//! dropped, the recording is marked incomplete, and the operator is told.
//!
//! `topic` names the topics and their schemas, `json` encodes the messages, `writer` lays them
//! out as MCAP, `file` keeps the file a readable MCAP at every moment, `recorder` runs the
//! thread.

pub mod file;
pub mod foxglove;
pub mod info;
pub mod json;
pub mod recorder;
pub mod testkit;
pub mod topic;
pub mod writer;

pub use info::{ChannelInfo, RecordingInfo};
pub use recorder::{interrupt_all, interrupted, RecordSummary, Recorder, DEFAULT_QUEUE_EVENTS};
pub use topic::{Topic, ALL_TOPICS, TOPICS};
pub use writer::{RecordWriter, WriterOutcome};

use crate::block::Axes;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc::{SyncSender, TrySendError};
use std::sync::Arc;

/// The positions of the override and switch selectors recorded in `/nc/state`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Switches {
    /// Rapid override, percent (0 = F0).
    pub rapid_override: u32,
    /// Spindle override, percent.
    pub spindle_override: u32,
    /// DRY RUN.
    pub dry_run: bool,
    /// MACHINE LOCK.
    pub machine_lock: bool,
    /// Z NEGLECT.
    pub z_neglect: bool,
    /// A tap is in progress: the feed and spindle overrides are held at 100 % whatever their
    /// switches say (issue 23; docs/pulse-core.md, "Tapping").
    pub override_locked: bool,
}

impl Default for Switches {
    fn default() -> Switches {
        Switches {
            rapid_override: 100,
            spindle_override: 100,
            dry_run: false,
            machine_lock: false,
            z_neglect: false,
            override_locked: false,
        }
    }
}

/// One thing to record. Every time is machine time in ns since the run started.
#[derive(Clone, Debug, PartialEq)]
pub enum Event {
    /// `/nc/block`: a block starts executing.
    Block {
        /// Machine time, ns.
        t_ns: u64,
        /// Block sequence number.
        seq: u32,
        /// Source statement line, 1-based.
        stmt: u32,
        /// The block's ISO line.
        text: String,
    },
    /// `/nc/position`: axis positions in pulses (mm derived from the pulse length).
    Position {
        /// Machine time, ns.
        t_ns: u64,
        /// Program positions X, Y, Z (A), pulses (`x`, `y`, `z`, `a` in the file).
        pulses: Axes,
        /// What MACHINE LOCK or Z NEGLECT held back of each: the axis counters (`pulses` in
        /// the file) stand at `pulses - held` (docs/pulse-core.md, "Machine lock").
        held: Axes,
        /// The commanded path speed, mm/min (what the interpolator is making: the KT ramp's
        /// speed, or f_r·|E|/(E_m + L) in the error-proportional tail); 0 at rest.
        speed_mm_min: f64,
    },
    /// `/nc/pulses`: a batch of pulses of one axis in one direction.
    Pulses {
        /// Axis 0 = X, 1 = Y, 2 = Z.
        axis: u8,
        /// +1 or -1.
        dir: i8,
        /// Pulse times, ns, ascending.
        t_ns: Vec<u64>,
    },
    /// `/nc/state`: RUN, modes, override, tool, spindle.
    State {
        /// Machine time, ns.
        t_ns: u64,
        /// RUN flag: 0 stopped, 1 AUTO, 2 MDI.
        run: u8,
        /// Operation mode selector position name.
        op_mode: String,
        /// Data-processing mode selector position name.
        data_mode: String,
        /// Feed override, percent.
        feed_override: u32,
        /// T code in the spindle, 0 for none.
        tool: u32,
        /// Spindle speed, rpm, signed (negative = reverse), 0 stopped: programmed times the
        /// spindle override.
        spindle: i64,
        /// Rapid and spindle overrides, DRY RUN, MACHINE LOCK and Z NEGLECT.
        switches: Switches,
    },
    /// `/panel/display`: the display frame changed.
    Display {
        /// Machine time, ns.
        t_ns: u64,
        /// The display lines.
        lines: Vec<String>,
    },
    /// `/panel/event`: an operator action.
    PanelEvent {
        /// Machine time, ns.
        t_ns: u64,
        /// The action as a panel-script line.
        event: String,
    },
    /// `/nc/probe`: a probe block ended.
    Probe {
        /// Machine time, ns.
        t_ns: u64,
        /// Block sequence number.
        seq: u32,
        /// Source statement line, 1-based.
        stmt: u32,
        /// Where the machine stopped, pulse counters X, Y, Z.
        pulses: Axes,
        /// The probe found what it sought.
        tripped: bool,
        /// It was so at the start: nothing moved.
        at_start: bool,
    },
    /// `/nc/io`: an output set by a block (M62–M65, M67, M68), or a simulated input the
    /// operator or a script set (`input`).
    Io {
        /// Machine time, ns.
        t_ns: u64,
        /// Block sequence number.
        seq: u32,
        /// Source statement line, 1-based.
        stmt: u32,
        /// Digital (M62–M65) or analog (M67, M68).
        digital: bool,
        /// Output 0–63.
        index: u8,
        /// The value: a digital output 1 on, 0 off.
        value: f64,
        /// With the motion (M62, M63, M67) or at once.
        synced: bool,
        /// An input (`"dir":"in"`), not an output (no `dir`).
        input: bool,
    },
    /// `/foxglove/log`: an operator or program message, or an alarm (`foxglove.Log`).
    Log {
        /// Machine time, ns.
        t_ns: u64,
        /// `foxglove.Log` level: `foxglove::level::INFO`, `WARNING` or `ERROR`.
        level: u8,
        /// Who says it: `console`, `program`, `pulse core`, `novanc run`.
        name: String,
        /// The text, as the operator sees it.
        message: String,
        /// The program it is about (empty when none).
        file: String,
        /// Its source line, 1-based (0 when none).
        line: u32,
    },
    /// `/lathe/event`: what a lathe channel does besides moving (docs/recording.md, "Lathe
    /// recordings"): a supply, transfer, cut, thread pass, part, wait, fault, alarm, done.
    Lathe {
        /// Machine time, ns.
        t_ns: u64,
        /// The channel, 1-based.
        channel: u16,
        /// The event's word (`supply`, `transfer`, `thread`, `cut`, `part`, `wait`, `fault`,
        /// `alarm`, `reset`, `done`).
        event: &'static str,
        /// The work it concerns, if any.
        work: Option<u32>,
        /// Its number, if any (the receiving channel, the encoder index, the count, the line).
        value: Option<i64>,
        /// The event in words.
        text: String,
    },
    /// Any other event, sent by one channel of a kernel ([`EventSink::for_channel`]): written
    /// on its own topic with `"channel"` (1-based) first.
    OnChannel {
        /// The channel, 1-based.
        channel: u16,
        /// The event.
        ev: Box<Event>,
    },
}

impl Event {
    /// The event itself, without the channel it was sent on.
    pub fn inner(&self) -> &Event {
        match self {
            Event::OnChannel { ev, .. } => ev.inner(),
            ev => ev,
        }
    }

    /// The channel (1-based) a kernel's channel sent it on; None for a single machine's.
    pub fn channel(&self) -> Option<u16> {
        match self {
            Event::OnChannel { channel, .. } => Some(*channel),
            _ => None,
        }
    }
}

/// The non-blocking sending side of a recording. Cloneable; shared by every producer.
#[derive(Clone, Debug)]
pub struct EventSink {
    tx: SyncSender<Event>,
    incomplete: Arc<AtomicBool>,
    dropped: Arc<AtomicU64>,
    /// The pulse core sends `/nc/pulses` (off: `--pulses off`).
    pulses: bool,
    /// Every event sent is tagged with this channel, 1-based (None: a single machine's sink,
    /// whose messages carry no channel).
    channel: Option<u16>,
}

impl EventSink {
    /// Wraps the sender of a bounded channel whose receiver is the recorder thread.
    pub fn new(tx: SyncSender<Event>) -> EventSink {
        EventSink {
            tx,
            incomplete: Arc::new(AtomicBool::new(false)),
            dropped: Arc::new(AtomicU64::new(0)),
            pulses: true,
            channel: None,
        }
    }

    /// The same recording for channel `ch` (0-based) of a kernel: every event sent through
    /// it is written with `"channel": ch + 1` (docs/recording.md, "Lathe recordings").
    pub fn for_channel(&self, ch: usize) -> EventSink {
        let mut s = self.clone();
        s.channel = Some(u16::try_from(ch + 1).unwrap_or(u16::MAX));
        s
    }

    /// The event as this sink sends it (tagged with its channel, if it has one).
    fn tag(&self, ev: Event) -> Event {
        match self.channel {
            Some(channel) => Event::OnChannel {
                channel,
                ev: Box::new(ev),
            },
            None => ev,
        }
    }

    /// An event handed back untagged (so that a retry does not tag it twice).
    fn untag(&self, ev: Event) -> Event {
        match (self.channel, ev) {
            (Some(_), Event::OnChannel { ev, .. }) => *ev,
            (_, ev) => ev,
        }
    }

    /// The same sink with `/nc/pulses` left out (`--pulses off`): the pulse core sends no
    /// pulse batch to it; everything else is recorded.
    pub fn with_pulses(mut self, on: bool) -> EventSink {
        self.pulses = on;
        self
    }

    /// Whether the pulse core sends its pulses to this sink.
    pub fn records_pulses(&self) -> bool {
        self.pulses
    }

    /// Sends an event without ever blocking; on a full queue or a gone recorder the event is
    /// dropped and the recording marked incomplete.
    pub fn send(&self, ev: Event) {
        match self.tx.try_send(self.tag(ev)) {
            Ok(()) => {}
            Err(TrySendError::Full(_)) | Err(TrySendError::Disconnected(_)) => {
                self.incomplete.store(true, Ordering::Relaxed);
                self.dropped.fetch_add(1, Ordering::Relaxed);
            }
        }
    }

    /// Sends an event without ever blocking, but hands it back when the queue is full instead
    /// of dropping it, so that a producer with no real-time duty (the pulse core in virtual
    /// time) can let the recorder catch up and retry. A gone recorder drops it as `send` does.
    pub fn try_send(&self, ev: Event) -> Result<(), Event> {
        match self.tx.try_send(self.tag(ev)) {
            Ok(()) => Ok(()),
            Err(TrySendError::Full(ev)) => Err(self.untag(ev)),
            Err(TrySendError::Disconnected(_)) => {
                self.incomplete.store(true, Ordering::Relaxed);
                self.dropped.fetch_add(1, Ordering::Relaxed);
                Ok(())
            }
        }
    }

    /// Marks the recording incomplete (for example after a disk error in the recorder).
    pub fn mark_incomplete(&self) {
        self.incomplete.store(true, Ordering::Relaxed);
    }

    /// Whether any event has been lost.
    pub fn is_incomplete(&self) -> bool {
        self.incomplete.load(Ordering::Relaxed)
    }

    /// How many events were dropped.
    pub fn dropped(&self) -> u64 {
        self.dropped.load(Ordering::Relaxed)
    }

    /// The sink's shared incomplete/dropped flags without its sender, so that the recorder
    /// thread can mark the recording incomplete without holding the channel open.
    pub fn flags(&self) -> SinkFlags {
        SinkFlags {
            incomplete: Arc::clone(&self.incomplete),
            dropped: Arc::clone(&self.dropped),
        }
    }
}

/// The incomplete flag and dropped-event count shared by every clone of one `EventSink`.
#[derive(Clone, Debug)]
pub struct SinkFlags {
    incomplete: Arc<AtomicBool>,
    dropped: Arc<AtomicU64>,
}

impl SinkFlags {
    /// Marks the recording incomplete (every clone of the sink sees it).
    pub fn mark_incomplete(&self) {
        self.incomplete.store(true, Ordering::Relaxed);
    }

    /// Whether any event has been lost.
    pub fn is_incomplete(&self) -> bool {
        self.incomplete.load(Ordering::Relaxed)
    }

    /// How many events the sink dropped.
    pub fn dropped(&self) -> u64 {
        self.dropped.load(Ordering::Relaxed)
    }
}
