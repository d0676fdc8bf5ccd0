//! The pulse core thread around [`Machine`]: operator commands in, status snapshots out.
//!
//! - Virtual time: ticks run as fast as possible. The machine clock stops while the machine is
//!   idle, stalled at override 0, or waiting for the translator to put a block in B1, so the
//!   same program always gives the same pulse times.
//! - Real time: slice k (the NCBR tick starting at machine time t_k) is generated when the wall
//!   clock reaches t_k − one NCBR period, so pulses are at most one tick ahead of the wall
//!   clock, like a step queue. A slice finished after its own start time t_k means the queue
//!   ran dry; each slice's lateness (finish − t_k, negative = ahead) is kept in [`RtStats`].
//!
//! The snapshot is republished after every NCBR tick (5 ms of machine time by default, which
//! includes every block start) and after every command.

use super::block_buffer::{MakeStatements, B1};
use super::machine::Machine;
use super::realtime::{apply, Op, StepQueue};
use super::{ClockMode, Command, Status};
use crate::record::EventSink;
use crate::settings::MachineSettings;
use crate::tooldata::Magazine;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError, Sender};
use std::sync::{Arc, Condvar, Mutex};
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
}

enum Msg {
    Cmd(Command),
    Load(MakeStatements),
    Magazine(Box<Magazine>),
    Modes(String, String),
    Position([i64; 3]),
    Shutdown,
}

struct Shared {
    status: Mutex<Status>,
    changed: Condvar,
    rt: Mutex<RtStats>,
}

/// The handle to the pulse core thread.
pub struct PulseCore {
    tx: Sender<Msg>,
    shared: Arc<Shared>,
    b1: Arc<B1>,
    sent: AtomicU64,
    settings: MachineSettings,
    thread: Option<JoinHandle<()>>,
}

impl PulseCore {
    /// Starts the pulse core thread.
    pub fn spawn(
        settings: MachineSettings,
        clock: ClockMode,
        sink: Option<EventSink>,
    ) -> PulseCore {
        let (tx, rx) = mpsc::channel();
        let mut machine = Machine::new(settings.clone());
        let mut rt_sink = None;
        if clock == ClockMode::RealTime {
            rt_sink = sink;
        } else if sink.is_some() {
            machine.set_recording(sink, false);
            machine.set_lossless_recording(true);
        }
        let shared = Arc::new(Shared {
            status: Mutex::new(machine.status()),
            changed: Condvar::new(),
            rt: Mutex::new(RtStats::default()),
        });
        let b1 = B1::new(settings.b1_capacity);
        let (sh, b) = (shared.clone(), b1.clone());
        let thread = std::thread::Builder::new()
            .name("pulse-core".into())
            .spawn(move || {
                let mut r = Runner::new(machine, sh, b, rx);
                if clock == ClockMode::RealTime {
                    r.rt = Some(StepQueue::new(&mut r.m, rt_sink));
                }
                r.run(clock)
            })
            .ok();
        PulseCore {
            tx,
            shared,
            b1,
            sent: AtomicU64::new(0),
            settings,
            thread,
        }
    }

    fn send(&self, m: Msg) {
        self.sent.fetch_add(1, Ordering::SeqCst);
        let _ = self.tx.send(m);
    }

    /// Loads a program: a translator thread fills B1 from these statements, concurrently
    /// with execution, waiting when B1 is full. Replaces any loaded program.
    pub fn load(
        &self,
        statements: Box<
            dyn Iterator<
                    Item = Result<crate::translator::Statement, crate::translator::TranslateError>,
                > + Send,
        >,
    ) {
        self.send(Msg::Load(Box::new(move || statements)));
    }

    /// Loads a part program: the translator is made and run on the translator thread (so it
    /// need not be `Send`), filling B1 concurrently with execution. Replaces any loaded program.
    pub fn load_program(&self, source: &str, magazine: Magazine, start: [i64; 3]) {
        let source = source.to_string();
        let settings = self.settings.clone();
        self.send(Msg::Load(Box::new(move || {
            Box::new(crate::translator::Translator::new(
                &source, magazine, settings, start,
            ))
        })));
    }

    /// Sends an operator command.
    pub fn command(&self, c: Command) {
        self.send(Msg::Cmd(c));
    }

    /// The latest status snapshot.
    pub fn status(&self) -> Status {
        lock(&self.shared.status).clone()
    }

    /// The settings the core runs with.
    pub fn settings(&self) -> &MachineSettings {
        &self.settings
    }

    /// The tool data the set length of the tool in the spindle is taken from (at M06).
    pub fn set_magazine(&self, m: Magazine) {
        self.send(Msg::Magazine(Box::new(m)));
    }

    /// The operation and data-processing mode names recorded in `/nc/state`.
    pub fn set_panel_modes(&self, op_mode: &str, data_mode: &str) {
        self.send(Msg::Modes(op_mode.into(), data_mode.into()));
    }

    /// Sets the axis positions (pulses); ignored unless the machine is at rest.
    pub fn set_position(&self, pos: [i64; 3]) {
        self.send(Msg::Position(pos));
    }

    /// Whether the pulse core thread is still running.
    pub fn is_running(&self) -> bool {
        self.thread.as_ref().is_some_and(|t| !t.is_finished())
    }

    /// Blocks now waiting in B1.
    pub fn b1_len(&self) -> usize {
        self.b1.len()
    }

    /// Real-time pacing figures so far (empty in virtual time).
    pub fn realtime_stats(&self) -> RtStats {
        lock(&self.shared.rt).clone()
    }

    /// Waits until every message sent so far has been applied and the machine is idle
    /// (RUN = 0, or a feed hold at rest, or an e-stop; no motion, nothing pending). Returns
    /// the status then, or `None` on timeout.
    pub fn wait_idle(&self, timeout: Duration) -> Option<Status> {
        let target = self.sent.load(Ordering::SeqCst);
        let deadline = Instant::now() + timeout;
        let mut st = lock(&self.shared.status);
        loop {
            if st.commands_applied >= target && st.idle {
                return Some(st.clone());
            }
            let now = Instant::now();
            if now >= deadline || self.thread.as_ref().is_none_or(|t| t.is_finished()) {
                return None;
            }
            st = self
                .shared
                .changed
                .wait_timeout(st, deadline - now)
                .map(|r| r.0)
                .unwrap_or_else(|p| p.into_inner().0);
        }
    }
}

impl Drop for PulseCore {
    fn drop(&mut self) {
        let _ = self.tx.send(Msg::Shutdown);
        self.b1.clear();
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

/// The state of the pulse core thread.
struct Runner {
    m: Machine,
    shared: Arc<Shared>,
    b1: Arc<B1>,
    rx: Receiver<Msg>,
    applied: u64,
    quit: bool,
    /// The step queue, in real time.
    rt: Option<StepQueue>,
}

impl Runner {
    fn new(m: Machine, shared: Arc<Shared>, b1: Arc<B1>, rx: Receiver<Msg>) -> Runner {
        Runner {
            m,
            shared,
            b1,
            rx,
            applied: 0,
            quit: false,
            rt: None,
        }
    }

    fn handle(&mut self, msg: Msg) {
        let op = match msg {
            Msg::Cmd(c) => {
                if c == Command::Reset {
                    self.b1.clear();
                }
                Op::Cmd(c)
            }
            Msg::Load(it) => {
                self.b1.load(it);
                Op::NewRun
            }
            Msg::Magazine(mg) => Op::Magazine(mg),
            Msg::Modes(o, d) => Op::Modes(o, d),
            Msg::Position(p) => Op::Position(p),
            Msg::Shutdown => {
                self.quit = true;
                self.applied += 1;
                return;
            }
        };
        match &mut self.rt {
            Some(rt) if matches!(op, Op::Cmd(Command::EStop)) => rt.estop(&mut self.m),
            Some(rt) => {
                apply(&mut self.m, &op);
                rt.applied(op);
            }
            None => apply(&mut self.m, &op),
        }
        self.applied += 1;
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

    fn publish(&self) {
        let mut st = self.m.status();
        st.commands_applied = self.applied;
        *lock(&self.shared.status) = st;
        self.shared.changed.notify_all();
    }

    fn wait_msg(&mut self, timeout: Duration) -> bool {
        match self.rx.recv_timeout(timeout) {
            Ok(msg) => {
                self.handle(msg);
                self.drain()
            }
            Err(RecvTimeoutError::Timeout) => true,
            Err(RecvTimeoutError::Disconnected) => false,
        }
    }

    fn run(mut self, clock: ClockMode) {
        match clock {
            ClockMode::Virtual => self.run_virtual(),
            ClockMode::RealTime => self.run_realtime(),
        }
        if let Some(rt) = &mut self.rt {
            rt.release_all();
        }
        self.publish();
    }

    fn run_virtual(&mut self) {
        while self.drain() {
            if self.m.is_idle() || self.m.is_stalled() {
                self.publish();
                if !self.wait_msg(Duration::from_millis(100)) {
                    return;
                }
                continue;
            }
            if self.m.wants_block() && !self.b1.ready() {
                self.publish();
                self.b1.wait_ready(Duration::from_millis(20));
                continue;
            }
            let b1 = self.b1.clone();
            self.m.tick(&mut &*b1);
            self.publish();
        }
    }

    fn run_realtime(&mut self) {
        let period = self.m.settings().ncbr_period_ns.max(1);
        while self.drain() {
            let Some(rt) = &mut self.rt else { return };
            rt.release();
            let slice_start = rt.wall_of(self.m.now());
            let gen_at = slice_start
                .checked_sub(Duration::from_nanos(period))
                .unwrap_or(slice_start);
            let now = Instant::now();
            if now < gen_at {
                // wake at least every millisecond to release queued events on time
                let nap = (gen_at - now).min(Duration::from_millis(1));
                if !self.wait_msg(nap) {
                    return;
                }
                continue;
            }
            let moving = !self.m.is_idle();
            rt.slice(&mut self.m, &self.b1);
            let done = Instant::now();
            if moving {
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
            self.publish();
        }
    }
}
