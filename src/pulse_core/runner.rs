//! The pulse core thread around the [`Kernel`]: operator commands in, status snapshots out.
//!
//! - Virtual time is stepped: machine time passes only inside [`PulseCore::advance`] (the
//!   script's `wait`, `wait ms`, `wait block`, and `novanc run`), as fast as the machine can
//!   compute, and stands still while the translator is behind. Whatever the thread scheduling,
//!   the same commands give the same pulses at the same machine times.
//! - Real time: slice k (the NCBR tick starting at machine time t_k) is generated when the wall
//!   clock reaches t_k − one NCBR period, so pulses are at most one tick ahead of the wall
//!   clock, like a step queue. A slice finished after its own start time t_k means the queue
//!   ran dry; each slice's lateness (finish − t_k, negative = ahead) is kept in [`RtStats`].
//!
//! - One kernel, N channels: the thread runs a [`Kernel`], one loop, one clock. The
//!   machining centre's ([`PulseCore::spawn`]) is a streaming kernel
//!   ([`Kernel::streaming`]): one channel, channel 0, that reads B1 as the translator thread
//!   fills it; a lathe's ([`PulseCore::spawn_kernel`]) has one [`Machine`] per channel and the
//!   sync table. Commands are addressed to a channel or to all
//!   ([`PulseCore::channel_command`]); E-STOP is machine-wide and acts from this thread,
//!   whatever the caller does next. Each channel's [`Status`] and its place in the sync table
//!   are published ([`PulseCore::channels`]). In real time every kernel runs through the step
//!   queue (`realtime.rs`: what it made recorded on the wall clock, an E-STOP rolled back to
//!   the wall clock's instant).
//!
//! Every call that sends a message waits until the thread has applied it, so the snapshot a
//! caller reads afterwards already shows its effect. The snapshot is republished after every
//! message, after a real-time slice at most every 2 ms, and at most every 20 ms of wall time
//! during a long virtual advance; a waiting caller is woken only when one waits.

use super::block_buffer::{BlockBuffer, MakeRun};
use super::kernel::{ChannelView, Kernel, KernelEvent, Outcome};
use super::machine::{BlockEnd, Machine, Reached};
use super::pulse_out::PulseRec;
use super::realtime::{apply, Op, StepQueue};
use super::{ClockMode, Command, RunKind, Status};
use crate::block::Axes;
use crate::record::EventSink;
use crate::settings::MachineSettings;
use crate::tooldata::Magazine;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError, Sender};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// Real-time pacing figures: lateness of each slice against the wall clock.
#[derive(Clone, Debug, Default)]
pub struct RtStats {
    /// Lateness of each slice, ns: finish time − the slice's start on the wall clock
    /// (negative = generated ahead, as intended). The first 1,000,000 slices are kept.
    pub lateness_ns: Vec<i64>,
    /// Slices that finished after their start time (the queue ran dry).
    pub dry: u64,
    /// Slices generated (moving or not).
    pub slices: u64,
    /// Snapshots published in real time (after a message, or after a slice at most every
    /// 2 ms of wall time: every slice of the centre's 5 ms).
    pub published: u64,
}

/// What a virtual-time advance runs until.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Wait {
    Idle(u64),
    For(u64),
    /// Block `.1` (its sequence number) of channel `.0` starts (the centre's one is channel
    /// 0), at most `.2` ns.
    Block(usize, u32, u64),
}

/// A look at the kernel run in its thread ([`PulseCore::inspect_kernel`]).
type KernelLook = Box<dyn FnOnce(&Kernel) + Send>;
/// A change made to the kernel in its thread, between two ticks ([`PulseCore::edit_kernel`]).
type KernelEdit = Box<dyn FnOnce(&mut Kernel) -> Result<(), String> + Send>;

enum Msg {
    Cmd(Command),
    /// A command to channel `.0` of a kernel (None: every channel).
    Chan(Option<usize>, Command),
    /// A fault injected into a kernel's channel.
    Fault(usize, String),
    /// A kernel's part target.
    Target(u32),
    /// A kernel channel's program from its next run on.
    Program(
        usize,
        Vec<crate::block::Statement>,
        mpsc::Sender<Result<Option<u32>, String>>,
    ),
    /// A look at the kernel from its thread, between two ticks.
    Inspect(KernelLook),
    /// A change to the kernel from its thread, between two ticks.
    Edit(KernelEdit),
    Capture(bool),
    Start(RunKind, Option<MakeRun>),
    Magazine(Box<Magazine>),
    Modes(String, String),
    Position(Axes),
    Advance(Wait),
    Audit(bool),
    Watch(Option<super::Watcher>),
    Interrupt(fn() -> bool),
    Shutdown,
}

struct Shared {
    status: Mutex<Status>,
    changed: Condvar,
    waiters: AtomicUsize,
    reached: Mutex<Option<Reached>>,
    audit: Mutex<Vec<BlockEnd>>,
    rt: Mutex<RtStats>,
    /// Every channel's published state (one for the centre's streaming kernel).
    channels: Mutex<Vec<ChannelStatus>>,
    /// The refusal of the latest channel command (None: it acted).
    refusal: Mutex<Option<String>>,
    /// The machine time the latest E-STOP was applied at, by the thread.
    estop_at: Mutex<Option<u64>>,
    /// Captured pulses per channel (with the capture on).
    pulses: Mutex<Vec<Vec<PulseRec>>>,
    /// The kernel's events not yet taken by the front end.
    events: Mutex<Vec<KernelEvent>>,
}

impl Shared {
    /// The shared state of a new core: its first status and every channel's (one pulse log
    /// per channel).
    fn new(status: Status, channels: Vec<ChannelStatus>) -> Arc<Shared> {
        let n = channels.len();
        Arc::new(Shared {
            status: Mutex::new(status),
            changed: Condvar::new(),
            waiters: AtomicUsize::new(0),
            reached: Mutex::new(None),
            audit: Mutex::new(Vec::new()),
            rt: Mutex::new(RtStats::default()),
            channels: Mutex::new(channels),
            refusal: Mutex::new(None),
            estop_at: Mutex::new(None),
            pulses: Mutex::new(vec![Vec::new(); n]),
            events: Mutex::new(Vec::new()),
        })
    }
}

/// One channel's published state.
#[derive(Clone, Debug)]
pub struct ChannelStatus {
    /// Its machine's status (RUN, hold, alarm, block, position, ...).
    pub status: Status,
    /// Its place in the kernel's sync table: the sync point it waits at and on what, its work
    /// and chuck, its parts (None for the centre's streaming kernel, which has no table).
    pub sync: Option<ChannelView>,
}

/// The handle to the pulse core thread.
pub struct PulseCore {
    tx: Sender<Msg>,
    shared: Arc<Shared>,
    buffer: Arc<BlockBuffer>,
    sent: AtomicU64,
    settings: MachineSettings,
    clock: ClockMode,
    thread: Option<JoinHandle<()>>,
}

/// A virtual-time advance runs this much machine time between looks at the interrupt.
const SLICE_NS: u64 = 10_000_000_000;

/// Longest a new run's START waits in real time for its source to fill the block buffer.
const PRIMING: Duration = Duration::from_millis(40);

/// Longest a caller waits for the thread to apply a message before giving up on it.
const APPLY_PATIENCE: Duration = Duration::from_secs(60);

impl PulseCore {
    /// Starts the pulse core thread: the machining centre's kernel, one channel streaming B1
    /// from the translator thread ([`Kernel::streaming`]). `sink`: the recording, the
    /// machine's own (no channel tag).
    pub fn spawn(
        settings: MachineSettings,
        clock: ClockMode,
        sink: Option<EventSink>,
    ) -> PulseCore {
        let mut machine = Machine::new(settings.clone());
        // Virtual time stands still while the translator is behind.
        machine.set_starve_stops(clock == ClockMode::Virtual);
        let buffer = BlockBuffer::new(settings.b1_capacity);
        let kernel = Kernel::streaming(machine, buffer.clone());
        PulseCore::launch(kernel, buffer, clock, sink)
    }

    /// Starts the pulse core thread running `kernel`'s N channels on its clock (each channel's
    /// program is the kernel's; B1 stays empty). In real time, machine time 0 of the kernel's
    /// clock is now on the wall clock, and each NCBR tick of every channel is generated at
    /// most one tick ahead of it. `sink`: the recording. Every channel's machine writes its
    /// blocks, positions, pulses and states to it, each message carrying its channel
    /// ([`EventSink::for_channel`]), and the kernel's events go to `/lathe/event`; in virtual
    /// time nothing is dropped (the thread waits for the recorder), in real time the kernel
    /// never waits (the step queue releases what it made on the wall clock; a full queue
    /// drops and marks the recording incomplete).
    pub fn spawn_kernel(kernel: Kernel, clock: ClockMode, sink: Option<EventSink>) -> PulseCore {
        let buffer = BlockBuffer::new(kernel.first().settings().b1_capacity);
        PulseCore::launch(kernel, buffer, clock, sink)
    }

    /// The thread around `kernel` (`buffer`: its B1, a streaming kernel's), recording to
    /// `sink`: directly in virtual time, through the step queue in real time.
    fn launch(
        mut kernel: Kernel,
        buffer: Arc<BlockBuffer>,
        clock: ClockMode,
        sink: Option<EventSink>,
    ) -> PulseCore {
        let (tx, rx) = mpsc::channel();
        let virtual_time = clock == ClockMode::Virtual;
        if virtual_time && sink.is_some() {
            kernel.set_recording(sink.clone(), true);
        }
        let settings = kernel.first().settings().clone();
        let (mut st, mut chans) = states(&kernel);
        // No message of this core is applied yet: the channels' machines count the commands
        // the kernel was given before it was spawned, which a caller's wait must not take for
        // its own (it would return before its message is applied).
        st.commands_applied = 0;
        for c in &mut chans {
            c.status.commands_applied = 0;
        }
        let shared = Shared::new(st, chans);
        let (sh, b) = (shared.clone(), buffer.clone());
        let thread = std::thread::Builder::new()
            .name("pulse-core".into())
            .spawn(move || {
                let mut k = Box::new(kernel);
                let rt = (!virtual_time).then(|| StepQueue::new(&mut k, sink.clone()));
                let r = Runner {
                    shared: sh,
                    buffer: b,
                    rx,
                    applied: 0,
                    quit: false,
                    rt,
                    interrupt: None,
                    last_work: vec![None; k.channels()],
                    k,
                    sink,
                    lossless: std::cell::Cell::new(virtual_time),
                    published: Instant::now(),
                };
                r.run(clock)
            })
            .ok();
        PulseCore {
            tx,
            shared,
            buffer,
            sent: AtomicU64::new(0),
            settings,
            clock,
            thread,
        }
    }

    fn send(&self, m: Msg) -> u64 {
        let n = self.sent.fetch_add(1, Ordering::SeqCst) + 1;
        let _ = self.tx.send(m);
        n
    }

    /// Sends a message and waits until the thread has applied it; the status then.
    fn send_sync(&self, m: Msg) -> Status {
        let n = self.send(m);
        self.wait_until(|st| st.commands_applied >= n, Some(APPLY_PATIENCE))
            .unwrap_or_else(|| self.status())
    }

    /// Waits until `done` holds for the published status (or the thread has ended, or
    /// `patience` has passed).
    fn wait_until(
        &self,
        done: impl Fn(&Status) -> bool,
        patience: Option<Duration>,
    ) -> Option<Status> {
        let deadline = patience.map(|p| Instant::now() + p);
        let mut st = lock(&self.shared.status);
        loop {
            if done(&st) {
                return Some(st.clone());
            }
            let now = Instant::now();
            if deadline.is_some_and(|d| now >= d)
                || self.thread.as_ref().is_none_or(|t| t.is_finished())
            {
                return None;
            }
            let nap = deadline.map_or(Duration::from_millis(100), |d| {
                (d - now).min(Duration::from_millis(100))
            });
            self.shared.waiters.fetch_add(1, Ordering::SeqCst);
            st = self
                .shared
                .changed
                .wait_timeout(st, nap)
                .map(|r| r.0)
                .unwrap_or_else(|p| p.into_inner().0);
            self.shared.waiters.fetch_sub(1, Ordering::SeqCst);
        }
    }

    /// START: resumes a run of `kind` that is held or stopped between single blocks; with no
    /// run loaded, starts a new one, whose blocks `make` gives from the machine's actual state
    /// (on the translator thread, filling B1 concurrently with execution). A START that cannot
    /// act says why in the status's notice. Returns the status after it.
    pub fn start(&self, kind: RunKind, make: Option<MakeRun>) -> Status {
        self.send_sync(Msg::Start(kind, make))
    }

    /// Sends an operator command; returns the status once it is applied.
    pub fn command(&self, c: Command) -> Status {
        self.send_sync(Msg::Cmd(c))
    }

    /// Sends an operator command to channel `ch` (None: every channel) and waits until it is
    /// applied; its refusal, if any. START, STOP (feed hold), RESET and the rest act on the
    /// channels named; E-STOP acts on every channel, whatever `ch`. The centre's streaming
    /// kernel has one channel, 0.
    pub fn channel_command(&self, ch: Option<usize>, c: Command) -> Result<(), String> {
        self.send_sync(Msg::Chan(ch, c));
        lock(&self.shared.refusal).clone().map_or(Ok(()), Err)
    }

    /// Sends the command as [`PulseCore::channel_command`] and returns at once, without
    /// waiting for the thread or reading anything (what a frozen front end does).
    pub fn post(&self, ch: Option<usize>, c: Command) {
        self.send(Msg::Chan(ch, c));
    }

    /// Injects a fault (tool breakage) into channel `ch` of a kernel: a feed hold that only
    /// RESET then START end. Refused by the centre's streaming kernel.
    pub fn fault(&self, ch: usize, reason: &str) -> Result<(), String> {
        self.send_sync(Msg::Fault(ch, reason.into()));
        lock(&self.shared.refusal).clone().map_or(Ok(()), Err)
    }

    /// Every channel's latest published state.
    pub fn channels(&self) -> Vec<ChannelStatus> {
        lock(&self.shared.channels).clone()
    }

    /// Runs `f` on the kernel in its thread, between two ticks, and returns what it gives:
    /// for what the published state does not carry (the sync table's history, for tests and
    /// audits).
    pub fn inspect_kernel<R: Send + 'static>(
        &self,
        f: impl FnOnce(&Kernel) -> R + Send + 'static,
    ) -> Option<R> {
        let (tx, rx) = mpsc::channel();
        self.send_sync(Msg::Inspect(Box::new(move |k| {
            let _ = tx.send(f(k));
        })));
        rx.recv_timeout(APPLY_PATIENCE).ok()
    }

    /// Channel `ch` of a kernel runs `prog`, its program read again with revised tools, from
    /// its next tool call in the part under way, else from its next part
    /// (`Kernel::replace_program`): the line of that tool call, if in this part.
    pub fn replace_program(
        &self,
        ch: usize,
        prog: Vec<crate::block::Statement>,
    ) -> Result<Option<u32>, String> {
        let (tx, rx) = mpsc::channel();
        self.send_sync(Msg::Program(ch, prog, tx));
        rx.recv_timeout(APPLY_PATIENCE)
            .unwrap_or_else(|_| Err("the pulse core did not answer".into()))
    }

    /// Changes the kernel in its thread, between two NCBR ticks, as one step: no tick runs
    /// inside `f` (a new cycle's programs loaded with `Kernel::load`, with what goes with
    /// them). `f`'s refusal, or that the core runs no kernel.
    pub fn edit_kernel(
        &self,
        f: impl FnOnce(&mut Kernel) -> Result<(), String> + Send + 'static,
    ) -> Result<(), String> {
        self.send_sync(Msg::Edit(Box::new(f)));
        lock(&self.shared.refusal).take().map_or(Ok(()), Err)
    }

    /// Sets a kernel's part target (refused below the works already supplied, or once a
    /// channel has finished).
    pub fn set_target(&self, n: u32) -> Result<(), String> {
        self.send_sync(Msg::Target(n));
        lock(&self.shared.refusal).take().map_or(Ok(()), Err)
    }

    /// The kernel's events (transfers, thread passes, parts, waits, faults, alarms) since the
    /// last call, in time order; none for the centre's streaming kernel.
    pub fn take_events(&self) -> Vec<KernelEvent> {
        std::mem::take(&mut *lock(&self.shared.events))
    }

    /// The machine time the latest E-STOP was applied at by the thread (None: none yet).
    pub fn estop_at(&self) -> Option<u64> {
        *lock(&self.shared.estop_at)
    }

    /// Captures every channel's pulses from now on (off: stops and forgets them). Only a
    /// lathe's channels: the centre's pulses go to its recording.
    pub fn set_pulse_capture(&self, on: bool) {
        self.send_sync(Msg::Capture(on));
    }

    /// The pulses channel `ch` output since the last call (with the capture on).
    pub fn take_pulses(&self, ch: usize) -> Vec<PulseRec> {
        lock(&self.shared.pulses)
            .get_mut(ch)
            .map(std::mem::take)
            .unwrap_or_default()
    }

    /// The latest status snapshot.
    pub fn status(&self) -> Status {
        lock(&self.shared.status).clone()
    }

    /// The settings the core runs with.
    pub fn settings(&self) -> &MachineSettings {
        &self.settings
    }

    /// The clock the core runs on.
    pub fn clock(&self) -> ClockMode {
        self.clock
    }

    /// The tool data the set length of the tool in the spindle is taken from.
    pub fn set_magazine(&self, m: Magazine) {
        self.send_sync(Msg::Magazine(Box::new(m)));
    }

    /// The operation and data-processing mode names recorded in `/nc/state`.
    pub fn set_panel_modes(&self, op_mode: &str, data_mode: &str) {
        self.send(Msg::Modes(op_mode.into(), data_mode.into()));
    }

    /// Sets the axis positions (pulses); ignored unless the machine is at rest with no run.
    pub fn set_position(&self, pos: impl Into<Axes>) {
        let pos = pos.into();
        self.send_sync(Msg::Position(pos));
    }

    /// The jog feed, mm/min: of the jogs, the increments and the return after a manual
    /// intervention from now on (the panel's jog feed and rapid jog selection).
    pub fn set_jog_feed(&self, mm_min: f64) {
        self.command(Command::JogFeed(mm_min));
    }

    /// Keeps a log of every block end (programmed end and actual position), for tests.
    pub fn set_audit(&self, on: bool) {
        self.send_sync(Msg::Audit(on));
    }

    /// Virtual time: `w` is told every channel's state at every change of state while the
    /// machine runs (every block, hold, stop and alarm inside one `wait`; with a kernel, every
    /// channel's, and every arrival, wait and release at a sync point, merged in machine-time
    /// order: [`Kernel::set_watch`]), on the pulse core thread; None stops it. Ignored in real
    /// time, where the caller's own snapshots (at display rate) are the record.
    pub fn set_watch(&self, w: Option<super::Watcher>) {
        if self.clock == ClockMode::RealTime {
            return;
        }
        self.send_sync(Msg::Watch(w));
    }

    /// A virtual-time advance asks `f` between slices of machine time and ends early
    /// ([`Reached::Interrupted`]) when it returns true (a stop signal).
    pub fn set_interrupt(&self, f: fn() -> bool) {
        self.send_sync(Msg::Interrupt(f));
    }

    /// The block ends logged since the last call (with the audit on).
    pub fn take_audit(&self) -> Vec<BlockEnd> {
        std::mem::take(&mut *lock(&self.shared.audit))
    }

    /// Whether the pulse core thread is still running.
    pub fn is_running(&self) -> bool {
        self.thread.as_ref().is_some_and(|t| !t.is_finished())
    }

    /// Blocks now waiting in B1.
    pub fn b1_len(&self) -> usize {
        self.buffer.len()
    }

    /// Real-time pacing figures so far (empty in virtual time).
    pub fn realtime_stats(&self) -> RtStats {
        lock(&self.shared.rt).clone()
    }

    /// Virtual time: lets the machine run until it is idle (`limit_ns` of machine time at
    /// most), `for_ns` of machine time, or block `seq` starts. Real time: waits on the wall
    /// clock for the same. Returns why it stopped and the status then.
    fn advance(&self, w: Wait) -> (Reached, Status) {
        if self.clock == ClockMode::Virtual {
            let st = self.send_sync(Msg::Advance(w));
            let r = lock(&self.shared.reached).take().unwrap_or(Reached::Limit);
            return (r, st);
        }
        let start = self.status().machine_ns;
        let n = self.sent.load(Ordering::SeqCst);
        let applied = move |st: &Status| st.commands_applied >= n;
        let r = match w {
            Wait::Idle(limit) => self.wait_until(
                |st| applied(st) && (st.idle || st.machine_ns >= start.saturating_add(limit)),
                None,
            ),
            Wait::For(ns) => self.wait_until(|st| st.machine_ns >= start.saturating_add(ns), None),
            Wait::Block(_, _, limit) => self.wait_until(
                |st| {
                    applied(st)
                        && (st.idle
                            || st.machine_ns >= start.saturating_add(limit)
                            || self.at_block(w, st))
                },
                None,
            ),
        };
        let st = r.unwrap_or_else(|| self.status());
        let reached = if st.idle {
            Reached::Idle
        } else {
            match w {
                Wait::For(_) => Reached::Time,
                Wait::Block(..) if self.at_block(w, &st) => Reached::BlockStart,
                _ => Reached::Limit,
            }
        };
        (reached, st)
    }

    /// Real time: whether the block `w` waits for executes, as last published (`st`: the
    /// core's status, which is channel 0's; another channel of a kernel is looked at in its
    /// own).
    fn at_block(&self, w: Wait, st: &Status) -> bool {
        let Wait::Block(ch, seq, _) = w else {
            return false;
        };
        let chans = (ch > 0).then(|| lock(&self.shared.channels));
        let Some(c) = chans
            .as_ref()
            .map_or(Some(st), |c| c.get(ch).map(|c| &c.status))
        else {
            return false;
        };
        c.in_block && c.executing.as_ref().and_then(|e| e.block()).map(|b| b.seq) == Some(seq)
    }

    /// Runs (or waits) until the machine is idle: RUN = 0, or a feed hold at rest, or an
    /// e-stop; no motion, nothing pending. At most `limit_ns` of machine time.
    pub fn run_until_idle(&self, limit_ns: u64) -> (Reached, Status) {
        self.advance(Wait::Idle(limit_ns))
    }

    /// Lets `ns` of machine time pass.
    pub fn run_for(&self, ns: u64) -> (Reached, Status) {
        self.advance(Wait::For(ns))
    }

    /// Runs until block `seq` (its N number) of channel `ch` starts executing (the single
    /// machine is channel 0; a kernel's in virtual time: every channel at the end of the NCBR
    /// tick it started in, `Kernel::run_until`), or the machine is idle; at most `limit_ns` of
    /// machine time.
    pub fn run_until_block(&self, ch: usize, seq: u32, limit_ns: u64) -> (Reached, Status) {
        self.advance(Wait::Block(ch, seq, limit_ns))
    }

    /// Waits until the machine is idle (see [`PulseCore::run_until_idle`]); `None` if it is not
    /// within `timeout` of wall time (real time) or of machine time (virtual time).
    pub fn wait_idle(&self, timeout: Duration) -> Option<Status> {
        let (r, st) = self.run_until_idle(timeout.as_nanos().min(u64::MAX as u128) as u64);
        (r == Reached::Idle).then_some(st)
    }
}

impl Drop for PulseCore {
    fn drop(&mut self) {
        let _ = self.tx.send(Msg::Shutdown);
        self.buffer.clear();
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// The core's status and every channel's: the core's is channel 0's at the kernel's time,
/// idle only when no channel progresses.
fn states(k: &Kernel) -> (Status, Vec<ChannelStatus>) {
    let chans: Vec<ChannelStatus> = (0..k.channels())
        .filter_map(|i| {
            Some(ChannelStatus {
                status: k.machine(i)?.status(),
                sync: k.channel(i),
            })
        })
        .collect();
    let mut st = chans
        .first()
        .map_or_else(|| k.first().status(), |c| c.status.clone());
    st.machine_ns = k.now();
    st.idle = !k.progressing();
    (st, chans)
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

/// The state of the pulse core thread.
struct Runner {
    /// The kernel: the centre's one streaming channel, or a lathe's N.
    k: Box<Kernel>,
    shared: Arc<Shared>,
    buffer: Arc<BlockBuffer>,
    rx: Receiver<Msg>,
    applied: u64,
    quit: bool,
    /// The step queue, in real time.
    rt: Option<StepQueue>,
    /// Asked between slices of a virtual-time advance: true ends it (a stop signal).
    interrupt: Option<fn() -> bool>,
    /// The recording: the kernel's events go to it (`/lathe/event`), the machines hold their
    /// own sinks.
    sink: Option<EventSink>,
    /// The work of each channel's latest cut (a thread pass's work).
    last_work: Vec<Option<u32>>,
    /// `/lathe/event` waits for the recorder (virtual time).
    lossless: std::cell::Cell<bool>,
    /// When the snapshot was last published.
    published: Instant,
}

/// A kernel in real time publishes its snapshot at most this often (and at once after a
/// message): its NCBR tick (100 µs on the Citizen) would otherwise publish 10,000 a second.
const KERNEL_PUBLISH: Duration = Duration::from_millis(2);

/// A kernel in real time with no channel progressing (nothing moves, runs, or waits to go on)
/// runs this much machine time in one step, ahead of the wall clock, and sleeps until the next:
/// the Citizen's 100 µs NCBR tick, one wake-up at a time, cost a fifth of a core with the
/// console standing idle (stop 43, measured per thread). A message wakes the thread at once:
/// a command that sets something going is taken at the kernel's time, at most one step after
/// it was given, and from then on every tick is generated on time again. E-STOP and STOP have
/// nothing to stop at rest.
const KERNEL_IDLE_STEP: Duration = Duration::from_millis(10);

impl Runner {
    fn handle(&mut self, msg: Msg) {
        match msg {
            Msg::Cmd(c) => {
                let _ = self.channel_command(None, c);
            }
            Msg::Chan(ch, c) => {
                let r = self.channel_command(ch, c);
                *lock(&self.shared.refusal) = r.err();
            }
            Msg::Start(kind, make) if self.k.streams() => self.start(kind, make),
            Msg::Start(kind, _) => {
                let _ = self.channel_command(None, Command::Start(kind));
            }
            Msg::Fault(ch, why) => {
                let r = self.apply_op(Op::Fault(ch, why));
                *lock(&self.shared.refusal) = r.err();
            }
            Msg::Target(n) => {
                let r = self.apply_op(Op::Target(n));
                *lock(&self.shared.refusal) = r.err();
            }
            Msg::Inspect(f) => f(&self.k),
            Msg::Edit(f) => {
                let r = f(&mut self.k);
                self.barrier();
                *lock(&self.shared.refusal) = r.err();
            }
            Msg::Program(ch, prog, tx) => {
                let _ = tx.send(self.k.replace_program(ch, prog));
                self.barrier();
            }
            Msg::Capture(on) => {
                for i in 0..self.k.channels() {
                    if let Some(m) = self.k.machine_mut(i) {
                        m.set_capture(on);
                    }
                }
                if !on {
                    lock(&self.shared.pulses).iter_mut().for_each(Vec::clear);
                }
            }
            Msg::Magazine(mg) => {
                let _ = self.apply_op(Op::Magazine(mg));
            }
            Msg::Modes(o, d) => {
                let _ = self.apply_op(Op::Modes(o, d));
            }
            Msg::Position(p) => {
                let _ = self.apply_op(Op::Position(p));
            }
            Msg::Audit(on) => self.k.first_mut().set_audit(on),
            // Real time publishes at display rate; the watcher is for virtual time
            // (`PulseCore::set_watch` sends none in real time).
            Msg::Watch(w) => self.k.set_watch(w),
            Msg::Interrupt(f) => self.interrupt = Some(f),
            Msg::Advance(w) => {
                let r = self.advance(w);
                *lock(&self.shared.reached) = Some(r);
            }
            Msg::Shutdown => self.quit = true,
        }
        self.applied += 1;
    }

    /// START of the centre's machine (a streaming kernel): resumes a run, or begins a new one
    /// whose blocks `make` gives from the machine's actual state.
    fn start(&mut self, kind: RunKind, make: Option<MakeRun>) {
        let op = Op::Cmd(Command::Start(kind));
        let m = self.k.first_mut();
        if !m.start_begins_run(kind) {
            let _ = self.apply_op(op);
            return;
        }
        match make {
            Some(make) => self.buffer.load(make, m.machine_state()),
            None => self.buffer.clear(),
        }
        // Priming: the run takes no block before the buffer is full or the source is done, so
        // an error found by then refuses the whole run. Real time waits at most PRIMING so a
        // slow source cannot hold up the core; the machine then waits at its first block
        // instead.
        let patience = self.rt.is_some().then_some(PRIMING);
        self.buffer.wait_primed(patience);
        let _ = self.apply_op(op);
        if let Some(e) = self.buffer.take_early_error() {
            self.k.first_mut().refuse_run(e);
        }
    }

    /// A command addressed to channel `ch` (None: all). E-STOP is machine-wide whatever the
    /// channel named, and stops the pulses at the wall clock's instant in real time (the step
    /// queue). The centre's streaming kernel has one channel, 0, told the centre's commands
    /// (RESET abandons B1; a START that begins a run needs its source: `start`); a lathe's are
    /// told by the kernel's rules (`Kernel::command_to`).
    fn channel_command(&mut self, ch: Option<usize>, c: Command) -> Result<(), String> {
        if c == Command::EStop {
            self.buffer.clear();
            let at = match &mut self.rt {
                Some(rt) => rt.estop(&mut self.k),
                None => {
                    self.k.estop();
                    self.k.now()
                }
            };
            *lock(&self.shared.estop_at) = Some(at);
            // What the machines made past that instant was never output.
            for l in lock(&self.shared.pulses).iter_mut() {
                l.retain(|p| p.t_ns <= at);
            }
            return Ok(());
        }
        if !self.k.streams() {
            return self.apply_op(Op::Chan(ch, c));
        }
        if let Some(i) = ch.filter(|&i| i > 0) {
            return Err(format!("CH{}: the machine has 1 channel", i + 1));
        }
        match c {
            Command::Start(kind) => self.start(kind, None),
            c => {
                if matches!(c, Command::Reset | Command::Abandon) {
                    self.buffer.clear();
                }
                let _ = self.apply_op(Op::Cmd(c));
            }
        }
        Ok(())
    }

    /// Applies `op` to the kernel (`realtime::apply`), logged in the step queue for a
    /// rollback in real time. Its refusal.
    fn apply_op(&mut self, op: Op) -> Result<(), String> {
        let r = apply(&mut self.k, &op);
        if let Some(rt) = &mut self.rt {
            rt.applied(op);
        }
        r
    }

    /// A change the step queue cannot replay (a cycle loaded, a program read again).
    fn barrier(&mut self) {
        if let Some(rt) = &mut self.rt {
            rt.barrier();
        }
    }

    /// Moves the kernel's events, the captured pulses and the audit to the shared logs.
    fn drain_pulses(&mut self) {
        let k = &mut self.k;
        let a = k.first_mut().take_audit();
        if !a.is_empty() {
            lock(&self.shared.audit).extend(a);
        }
        let ev = k.take_events();
        // A lathe's events: the centre's machine records its own, and says its alarms on the
        // console.
        if !ev.is_empty() && !k.streams() {
            let sink = self.rt.as_ref().map_or(self.sink.as_ref(), StepQueue::sink);
            if let Some(s) = sink {
                for e in &ev {
                    let ch = e.channel();
                    let work = match e {
                        KernelEvent::CutStart { work, .. } => {
                            if let Some(w) = self.last_work.get_mut(ch) {
                                *w = *work;
                            }
                            *work
                        }
                        _ => self.last_work.get(ch).copied().flatten(),
                    };
                    if let Some(r) = e.record(work) {
                        super::pulse_out::emit(s, r, &self.lossless);
                    }
                }
            }
            lock(&self.shared.events).extend(ev);
        }
        let mut log = lock(&self.shared.pulses);
        for i in 0..k.channels() {
            if let (Some(m), Some(l)) = (k.machine_mut(i), log.get_mut(i)) {
                if m.captures() {
                    l.extend(m.take_pulses());
                }
            }
        }
    }

    /// Virtual time: runs the kernel until the wait is over, a slice of machine time at a
    /// time so that a stop signal is seen between slices (a script's wait ends on it); a
    /// streaming kernel waits for its translator when B1 runs dry.
    fn advance(&mut self, w: Wait) -> Reached {
        let interrupt = self.interrupt;
        let (limit, block) = match w {
            Wait::For(ns) => (ns, None),
            Wait::Idle(limit) => (limit, None),
            Wait::Block(ch, seq, limit) => (limit, Some((ch, seq))),
        };
        let end = self.k.now().saturating_add(limit);
        let mut shown = Instant::now();
        let r = loop {
            let k = &mut self.k;
            let slice = end.saturating_sub(k.now()).min(SLICE_NS);
            let out = match w {
                Wait::For(_) => k.run_to(k.now().saturating_add(slice)),
                _ => k.run_until(slice, block),
            };
            match out {
                Outcome::TimeLimit if k.now() >= end => {
                    break if matches!(w, Wait::For(_)) {
                        Reached::Time
                    } else {
                        Reached::Limit
                    };
                }
                Outcome::TimeLimit => {}
                Outcome::Starved => self.buffer.wait_ready(Duration::from_millis(20)),
                Outcome::BlockStart { .. } => break Reached::BlockStart,
                Outcome::Stalled => break Reached::Stalled,
                _ => break Reached::Idle,
            }
            if interrupt.is_some_and(|f| f()) {
                break Reached::Interrupted;
            }
            if shown.elapsed() > Duration::from_millis(20) {
                self.publish();
                shown = Instant::now();
            }
        };
        self.drain_pulses();
        r
    }

    fn drain(&mut self) -> bool {
        let mut any = false;
        while let Ok(msg) = self.rx.try_recv() {
            self.handle(msg);
            any = true;
        }
        if any {
            self.publish();
        }
        !self.quit
    }

    fn publish(&mut self) {
        self.published = Instant::now();
        if self.rt.is_some() {
            lock(&self.shared.rt).published += 1;
        }
        self.drain_pulses();
        let (mut st, mut chans) = states(&self.k);
        st.commands_applied = self.applied;
        for c in &mut chans {
            c.status.commands_applied = self.applied;
        }
        *lock(&self.shared.channels) = chans;
        *lock(&self.shared.status) = st;
        if self.shared.waiters.load(Ordering::SeqCst) > 0 {
            self.shared.changed.notify_all();
        }
    }

    fn run(mut self, clock: ClockMode) {
        match clock {
            ClockMode::Virtual => self.run_virtual(),
            ClockMode::RealTime => self.run_realtime(),
        }
        // Every pulse made is in the recording when the thread ends (in real time a moving
        // axis's batch fills across slices).
        for i in 0..self.k.channels() {
            if let Some(m) = self.k.machine_mut(i) {
                m.flush_recording();
            }
        }
        self.drain_pulses();
        if let Some(rt) = &mut self.rt {
            rt.release_all();
        }
        self.publish();
    }

    fn run_virtual(&mut self) {
        while let Ok(msg) = self.rx.recv() {
            self.handle(msg);
            self.publish();
            if !self.drain() {
                return;
            }
        }
    }

    fn wait_msg(&mut self, timeout: Duration) -> bool {
        match self.rx.recv_timeout(timeout) {
            Ok(msg) => {
                self.handle(msg);
                self.publish();
                self.drain()
            }
            Err(RecvTimeoutError::Timeout) => true,
            Err(RecvTimeoutError::Disconnected) => false,
        }
    }

    /// Real time: each NCBR slice of the kernel is generated when the wall clock is one tick
    /// short of its start, through the step queue (which releases what it made on the wall
    /// clock and rolls an E-STOP back to its instant). A lathe at rest runs whole
    /// `KERNEL_IDLE_STEP`s and sleeps between: no tick has anything to be on time for.
    fn run_realtime(&mut self) {
        let period = self.k.first().settings().ncbr_period_ns.max(1);
        let idle_ticks = (KERNEL_IDLE_STEP.as_nanos() as u64 / period).max(1);
        loop {
            if !self.drain() {
                return;
            }
            let Some(rt) = &mut self.rt else {
                return;
            };
            rt.release();
            let slice_start = rt.wall_of(self.k.now());
            let gen_at = slice_start
                .checked_sub(Duration::from_nanos(period))
                .unwrap_or(slice_start);
            let now = Instant::now();
            // Asked once a tick: a nap goes round the loop again, so it still holds below.
            let idle = !self.k.progressing();
            let at_rest = idle && !self.k.streams();
            if now < gen_at {
                // wake at least every millisecond to release queued events on time
                let most = match at_rest {
                    true => KERNEL_IDLE_STEP,
                    false => Duration::from_millis(1),
                };
                let nap = (gen_at - now).min(most);
                if !self.wait_msg(nap) {
                    return;
                }
                continue;
            }
            // One NCBR tick of every channel; an E-STOP read by `drain` before the next one
            // acts at its instant, in the same tick on every channel. At rest, a whole idle
            // step of ticks in one call (each channel's machine runs them as in virtual time).
            rt.slice(&mut self.k, if at_rest { idle_ticks } else { 1 });
            self.drain_pulses();
            let done = Instant::now();
            lock(&self.shared.rt).slices += 1;
            if !idle {
                let late = if done >= slice_start {
                    (done - slice_start).as_nanos() as i64
                } else {
                    -((slice_start - done).as_nanos() as i64)
                };
                let mut st = lock(&self.shared.rt);
                if late > 0 {
                    st.dry += 1;
                }
                if st.lateness_ns.len() < 1_000_000 {
                    st.lateness_ns.push(late);
                }
            }
            if done - self.published >= KERNEL_PUBLISH {
                self.publish();
            }
        }
    }
}
