//! The block buffer (the patent's B1, lines 283–357 and claims 1–2): bounded, between the
//! translator thread and the pulse core.
//!
//! The translator thread pushes blocks and waits while the buffer is full; the pulse core takes
//! them. Each lock is held only for a queue operation (no allocation, no translation inside).
//! A thread is woken only when the other side is known to be waiting, so a run that never
//! waits makes no wake-up calls at all. A generation number lets RESET and a new run abandon a
//! translator thread that is still running.
//!
//! **Priming.** A new run takes no block until the buffer is full or the translator has
//! finished. If the translator finished with an error by then, the run is refused before its
//! first block, so nothing moves; a program longer than the buffer is checked as it runs,
//! at most one buffer ahead of the machine (`docs/pulse-core.md`).
//!
//! **The machine's answers.** A source that must know what the machine did before it reads on
//! (a probe's trip point: LinuxCNC's queue busters) waits on [`MachineLink::wait_answer`]
//! from the translator thread; the core gives the answer with [`BlockSource::answer`] when the
//! block is done. A translator waiting so counts as primed (else a short buffer would never
//! fill), and RESET or a new run ends the wait.

use super::source::{BlockSource, Fetch};
use super::BlockEntry;
use crate::block::Axes;
use crate::block::{MachineState, Statement, TranslateError};
use std::collections::VecDeque;
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::Duration;

/// The statements a program source yields (made and used on the translator thread, so it need
/// not be `Send`).
pub type StatementIter = Box<dyn Iterator<Item = Result<Statement, TranslateError>>>;

/// Makes a run's program source on the translator thread, from the machine's actual state at
/// the START that begins the run.
pub type MakeRun = Box<dyn FnOnce(MachineState) -> StatementIter + Send>;

#[derive(Debug)]
struct State {
    q: VecDeque<BlockEntry>,
    /// The translator's last word: `Some(None)` = end, `Some(Some(e))` = error.
    done: Option<Option<TranslateError>>,
    gen: u64,
    /// The run may take blocks (the buffer has been full, or the translator is done).
    primed: bool,
    /// Blocks taken in this generation.
    taken: u64,
    translator_waits: bool,
    core_waits: bool,
    /// The machine's answers not yet read by the translator, in order.
    answers: VecDeque<Answer>,
}

/// What the machine answers a source that waits on it (docs/pulse-core.md, "The machine's
/// answers").
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Answer {
    /// A probe block ended: where the machine stopped (pulses), whether the probe found what
    /// it sought, whether it had already at the start (nothing moved).
    Probe {
        /// The machine's position, pulses.
        at: Axes,
        /// The probe tripped (or for G38.4/G38.5 came free).
        tripped: bool,
        /// It was so at the start of the move.
        at_start: bool,
    },
    /// An M66 block ended: the input's value (digital 0 or 1), `None` when its wait timed
    /// out.
    Input(Option<f64>),
    /// A clocks block ended (`Block::clocks`): the machine time then, and how long the
    /// cycle-start lamp had been lit by then (Fanuc's #3001 and #3002), ns.
    Clocks {
        /// Machine time, ns.
        machine_ns: u64,
        /// Machine time with the cycle-start lamp lit (a run going, not held), ns.
        cycle_ns: u64,
    },
}

thread_local! {
    /// The run a translator thread makes statements for: its buffer and generation.
    static LINK: std::cell::RefCell<Option<MachineLink>> = const { std::cell::RefCell::new(None) };
}

/// The translator thread's line to the machine of its run.
#[derive(Clone, Debug)]
pub struct MachineLink {
    buf: Arc<BlockBuffer>,
    gen: u64,
}

impl MachineLink {
    /// The link of the run this (translator) thread makes statements for; `None` on any other
    /// thread.
    pub fn here() -> Option<MachineLink> {
        LINK.with(|l| l.borrow().clone())
    }

    /// Waits for the machine's next answer (every block pushed before it is released to the
    /// core meanwhile); an error if the run is abandoned (RESET, a new run) first.
    pub fn wait_answer(&self) -> Result<Answer, String> {
        let b = &self.buf;
        let mut s = b.lock();
        loop {
            if s.gen != self.gen {
                return Err("the run was abandoned while reading waited for the machine".into());
            }
            if let Some(a) = s.answers.pop_front() {
                return Ok(a);
            }
            // Waiting on the machine: the blocks so far must run for it to answer.
            s.primed = true;
            if s.core_waits {
                b.not_empty.notify_all();
            }
            s.translator_waits = true;
            s = b
                .not_full
                .wait_timeout(s, Duration::from_millis(50))
                .map(|r| r.0)
                .unwrap_or_else(|p| p.into_inner().0);
            s.translator_waits = false;
        }
    }
}

/// The shared buffer.
#[derive(Debug)]
pub struct BlockBuffer {
    state: Mutex<State>,
    not_full: Condvar,
    not_empty: Condvar,
    cap: usize,
}

impl BlockBuffer {
    /// An empty buffer of `cap` blocks with nothing loaded.
    pub fn new(cap: usize) -> Arc<BlockBuffer> {
        Arc::new(BlockBuffer {
            state: Mutex::new(State {
                q: VecDeque::with_capacity(cap.clamp(1, 1 << 16)),
                done: Some(None),
                gen: 0,
                primed: true,
                taken: 0,
                translator_waits: false,
                core_waits: false,
                answers: VecDeque::new(),
            }),
            not_full: Condvar::new(),
            not_empty: Condvar::new(),
            cap: cap.max(1),
        })
    }

    fn lock(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Empties the buffer and abandons any translator thread (RESET).
    pub fn clear(&self) {
        let mut s = self.lock();
        s.q.clear();
        s.answers.clear();
        s.done = Some(None);
        s.primed = true;
        s.gen += 1;
        drop(s);
        self.not_full.notify_all();
        self.not_empty.notify_all();
    }

    /// Empties the buffer and starts a translator thread filling it from the source `make`
    /// gives for the machine state `state`.
    pub fn load(self: &Arc<BlockBuffer>, make: MakeRun, state: MachineState) {
        let gen = {
            let mut s = self.lock();
            s.q.clear();
            s.answers.clear();
            s.done = None;
            s.primed = false;
            s.taken = 0;
            s.gen += 1;
            s.gen
        };
        self.not_full.notify_all();
        let buf = self.clone();
        let link = MachineLink {
            buf: self.clone(),
            gen,
        };
        let spawned = std::thread::Builder::new()
            .name("translator".into())
            .spawn(move || {
                LINK.with(|l| *l.borrow_mut() = Some(link));
                let run = std::panic::AssertUnwindSafe(|| buf.translate(gen, make(state)));
                if std::panic::catch_unwind(run).is_err() {
                    buf.finish(
                        gen,
                        Some(TranslateError {
                            line: 0,
                            col: 0,
                            message: "internal error in the translator; the run is stopped".into(),
                        }),
                    );
                }
            });
        if spawned.is_err() {
            self.finish(
                gen,
                Some(TranslateError {
                    line: 1,
                    col: 1,
                    message: "could not start the translator".into(),
                }),
            );
        }
    }

    /// The translator thread: statements to blocks, waiting while the buffer is full.
    fn translate(&self, gen: u64, stmts: StatementIter) {
        lower_priority();
        for r in stmts {
            match r {
                Ok(stmt) => {
                    let stmt = Arc::new(stmt);
                    for index in 0..stmt.blocks.len() {
                        let e = BlockEntry {
                            stmt: stmt.clone(),
                            index,
                        };
                        if !self.push(gen, e) {
                            return;
                        }
                    }
                }
                Err(e) => {
                    self.finish(gen, Some(e));
                    return;
                }
            }
        }
        self.finish(gen, None);
    }

    fn push(&self, gen: u64, e: BlockEntry) -> bool {
        let mut s = self.lock();
        while s.gen == gen && s.q.len() >= self.cap {
            s.primed = true;
            if s.core_waits {
                self.not_empty.notify_all();
            }
            s.translator_waits = true;
            s = self.not_full.wait(s).unwrap_or_else(|p| p.into_inner());
            s.translator_waits = false;
        }
        if s.gen != gen {
            return false;
        }
        s.q.push_back(e);
        if s.q.len() >= self.cap {
            s.primed = true;
        }
        if s.core_waits && s.primed {
            self.not_empty.notify_all();
        }
        true
    }

    fn finish(&self, gen: u64, err: Option<TranslateError>) {
        let mut s = self.lock();
        if s.gen == gen {
            s.done = Some(err);
            s.primed = true;
        }
        let wake = s.core_waits;
        drop(s);
        if wake {
            self.not_empty.notify_all();
        }
    }

    /// Whether a fetch now would not be `Pending`.
    pub fn ready(&self) -> bool {
        let s = self.lock();
        s.primed && (!s.q.is_empty() || s.done.is_some())
    }

    /// Waits up to `timeout` for a block or the translator's last word.
    /// A wake-up for something else (or a spurious one) waits on until the deadline.
    pub fn wait_ready(&self, timeout: Duration) {
        let deadline = std::time::Instant::now() + timeout;
        let mut s = self.lock();
        while !(s.primed && (!s.q.is_empty() || s.done.is_some())) {
            let now = std::time::Instant::now();
            if now >= deadline {
                break;
            }
            s.core_waits = true;
            s = self
                .not_empty
                .wait_timeout(s, deadline - now)
                .map(|r| r.0)
                .unwrap_or_else(|p| p.into_inner().0);
            s.core_waits = false;
        }
    }

    /// Waits until a new run may take blocks (the buffer full, or the translator done), at most
    /// `patience` (for ever with `None`).
    pub fn wait_primed(&self, patience: Option<Duration>) {
        let deadline = patience.map(|p| std::time::Instant::now() + p);
        let mut s = self.lock();
        while !s.primed {
            let nap = match deadline {
                Some(d) => {
                    let now = std::time::Instant::now();
                    if now >= d {
                        return;
                    }
                    (d - now).min(Duration::from_millis(50))
                }
                None => Duration::from_millis(50),
            };
            s.core_waits = true;
            s = self
                .not_empty
                .wait_timeout(s, nap)
                .map(|r| r.0)
                .unwrap_or_else(|p| p.into_inner().0);
            s.core_waits = false;
        }
    }

    /// The source's error, if it failed before the run took its first block (the run is then
    /// refused as a whole: nothing moves).
    pub fn take_early_error(&self) -> Option<TranslateError> {
        let mut s = self.lock();
        if s.primed && s.taken == 0 && matches!(s.done, Some(Some(_))) {
            s.q.clear();
            if let Some(Some(e)) = s.done.replace(None) {
                return Some(e);
            }
        }
        None
    }

    /// Blocks in the buffer now.
    pub fn len(&self) -> usize {
        self.lock().q.len()
    }

    /// Whether the buffer holds no block now.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// The pulse core reads the buffer through this.
impl BlockSource for &BlockBuffer {
    fn answer(&mut self, a: Answer) {
        let mut s = self.lock();
        s.answers.push_back(a);
        let wake = s.translator_waits;
        drop(s);
        if wake {
            self.not_full.notify_all();
        }
    }

    fn fetch(&mut self) -> Fetch {
        let mut s = self.lock();
        if !s.primed {
            return Fetch::Pending;
        }
        // A source that failed before the run took its first block: refuse the whole run.
        if s.taken == 0 && matches!(s.done, Some(Some(_))) {
            s.q.clear();
        }
        if let Some(e) = s.q.pop_front() {
            s.taken += 1;
            let wake = s.translator_waits;
            drop(s);
            if wake {
                self.not_full.notify_all();
            }
            return Fetch::Block(e);
        }
        match s.done.take() {
            None => Fetch::Pending,
            Some(None) => {
                s.done = Some(None);
                Fetch::End
            }
            Some(Some(e)) => {
                s.done = Some(None);
                Fetch::Error(e)
            }
        }
    }
}

/// The NC side has priority: the translator thread runs at a lower scheduling priority.
fn lower_priority() {
    #[cfg(target_os = "linux")]
    // SAFETY: setpriority on the calling thread's own id; no memory is passed.
    unsafe {
        let tid = libc::syscall(libc::SYS_gettid) as libc::id_t;
        let _ = libc::setpriority(libc::PRIO_PROCESS, tid, 10);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::block::Block;

    fn stmts(n: u32) -> MakeRun {
        Box::new(move |_| {
            Box::new((1..=n).map(|i| {
                Ok(Statement {
                    line: i,
                    text: String::new(),
                    blocks: vec![Block::aux(i, i, [0; 3])],
                })
            }))
        })
    }

    fn wait_len(b: &BlockBuffer, n: usize) {
        for _ in 0..500 {
            if b.len() == n {
                return;
            }
            std::thread::sleep(Duration::from_millis(2));
        }
    }

    #[test]
    fn the_translator_waits_while_the_buffer_is_full_and_blocks_come_in_order() {
        let b = BlockBuffer::new(3);
        b.load(stmts(10), MachineState::default());
        wait_len(&b, 3);
        std::thread::sleep(Duration::from_millis(20));
        assert_eq!(b.len(), 3, "never more than the capacity");
        let mut seen = vec![];
        let mut src = &*b;
        loop {
            match src.fetch() {
                Fetch::Block(e) => seen.push(e.stmt.line),
                Fetch::Pending => b.wait_ready(Duration::from_millis(50)),
                Fetch::End => break,
                Fetch::Error(e) => panic!("{e}"),
            }
        }
        assert_eq!(seen, (1..=10).collect::<Vec<_>>());
    }

    #[test]
    fn clear_abandons_the_translator() {
        let b = BlockBuffer::new(2);
        b.load(stmts(100), MachineState::default());
        wait_len(&b, 2);
        b.clear();
        std::thread::sleep(Duration::from_millis(20));
        assert_eq!(b.len(), 0);
        assert!(matches!((&*b).fetch(), Fetch::End));
    }

    #[test]
    fn a_panicking_translator_stops_the_run_with_an_error() {
        let b = BlockBuffer::new(2);
        b.load(
            Box::new(|_| {
                Box::new((0..1).map(|_| -> Result<Statement, TranslateError> { panic!("bug") }))
            }),
            MachineState::default(),
        );
        // The panic's message and backtrace take seconds on a loaded machine (7.7 s seen with
        // CI's RUST_BACKTRACE): wait for the buffer to be ready, up to a minute.
        let until = std::time::Instant::now() + Duration::from_secs(60);
        while !b.ready() && std::time::Instant::now() < until {
            b.wait_ready(Duration::from_millis(100));
        }
        assert!(matches!((&*b).fetch(), Fetch::Error(_)));
    }

    #[test]
    fn an_error_before_the_first_block_is_taken_refuses_the_whole_run() {
        let b = BlockBuffer::new(8);
        b.load(
            Box::new(|_| {
                Box::new((1..=3).map(|i| {
                    if i < 3 {
                        Ok(Statement {
                            line: i,
                            text: String::new(),
                            blocks: vec![Block::aux(i, i, [0; 3])],
                        })
                    } else {
                        Err(TranslateError {
                            line: 3,
                            col: 1,
                            message: "bad".into(),
                        })
                    }
                }))
            }),
            MachineState::default(),
        );
        for _ in 0..100 {
            if b.ready() {
                break;
            }
            b.wait_ready(Duration::from_millis(50));
        }
        assert!(matches!((&*b).fetch(), Fetch::Error(e) if e.line == 3));
    }

    #[test]
    fn a_new_run_waits_until_the_buffer_is_primed() {
        let b = BlockBuffer::new(4);
        let (tx, rx) = std::sync::mpsc::channel::<()>();
        b.load(
            Box::new(move |_| {
                Box::new((1..=10).map(move |i| {
                    if i == 3 {
                        let _ = rx.recv();
                    }
                    Ok(Statement {
                        line: i,
                        text: String::new(),
                        blocks: vec![Block::aux(i, i, [0; 3])],
                    })
                }))
            }),
            MachineState::default(),
        );
        wait_len(&b, 2);
        assert!(
            matches!((&*b).fetch(), Fetch::Pending),
            "2 of 4: not primed"
        );
        tx.send(()).unwrap();
        wait_len(&b, 4);
        assert!(matches!((&*b).fetch(), Fetch::Block(_)));
    }
}
