//! B1, the bounded block buffer between the translator thread and the pulse core.
//!
//! The translator thread pushes blocks and waits while B1 is full; the pulse core takes them.
//! Each lock is held only for a queue operation (no allocation, no translation inside), so the
//! translator never holds a lock the core waits on for longer than a push. A generation number
//! lets RESET and a new load abandon a translator thread that is still running.

use super::source::{BlockSource, Fetch};
use super::B1Entry;
use crate::translator::{Statement, TranslateError};
use std::collections::VecDeque;
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::time::Duration;

/// The statements a translator yields (made and used on the translator thread, so it need
/// not be `Send`).
pub type StatementIter = Box<dyn Iterator<Item = Result<Statement, TranslateError>>>;

/// Makes the translator on the translator thread.
pub type MakeStatements = Box<dyn FnOnce() -> StatementIter + Send>;

#[derive(Debug)]
struct State {
    q: VecDeque<B1Entry>,
    /// The translator's last word: `Some(None)` = end, `Some(Some(e))` = error.
    done: Option<Option<TranslateError>>,
    gen: u64,
}

/// The shared buffer.
#[derive(Debug)]
pub struct B1 {
    state: Mutex<State>,
    not_full: Condvar,
    not_empty: Condvar,
    cap: usize,
}

impl B1 {
    /// An empty B1 of `cap` blocks with nothing loaded.
    pub fn new(cap: usize) -> Arc<B1> {
        Arc::new(B1 {
            state: Mutex::new(State {
                q: VecDeque::with_capacity(cap.max(1)),
                done: Some(None),
                gen: 0,
            }),
            not_full: Condvar::new(),
            not_empty: Condvar::new(),
            cap: cap.max(1),
        })
    }

    fn lock(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Empties B1 and abandons any translator thread (RESET).
    pub fn clear(&self) {
        let mut s = self.lock();
        s.q.clear();
        s.done = Some(None);
        s.gen += 1;
        drop(s);
        self.not_full.notify_all();
        self.not_empty.notify_all();
    }

    /// Empties B1 and starts a translator thread filling it from the statements `make` gives.
    pub fn load(self: &Arc<B1>, make: MakeStatements) {
        let gen = {
            let mut s = self.lock();
            s.q.clear();
            s.done = None;
            s.gen += 1;
            s.gen
        };
        self.not_full.notify_all();
        let b1 = self.clone();
        let spawned = std::thread::Builder::new()
            .name("translator".into())
            .spawn(move || {
                let run = std::panic::AssertUnwindSafe(|| b1.translate(gen, make()));
                if std::panic::catch_unwind(run).is_err() {
                    b1.finish(
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
            let mut s = self.lock();
            if s.gen == gen {
                s.done = Some(Some(TranslateError {
                    line: 1,
                    col: 1,
                    message: "could not start the translator".into(),
                }));
            }
        }
    }

    /// The translator thread: statements to blocks in B1, waiting while B1 is full.
    fn translate(&self, gen: u64, stmts: StatementIter) {
        lower_priority();
        for r in stmts {
            match r {
                Ok(stmt) => {
                    let stmt = Arc::new(stmt);
                    for index in 0..stmt.blocks.len() {
                        let e = B1Entry {
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
            std::thread::yield_now();
        }
        self.finish(gen, None);
    }

    fn push(&self, gen: u64, e: B1Entry) -> bool {
        let mut s = self.lock();
        while s.gen == gen && s.q.len() >= self.cap {
            s = self.not_full.wait(s).unwrap_or_else(|p| p.into_inner());
        }
        if s.gen != gen {
            return false;
        }
        s.q.push_back(e);
        drop(s);
        self.not_empty.notify_all();
        true
    }

    fn finish(&self, gen: u64, err: Option<TranslateError>) {
        let mut s = self.lock();
        if s.gen == gen {
            s.done = Some(err);
        }
        drop(s);
        self.not_empty.notify_all();
    }

    /// Whether a fetch now would not be `Pending`.
    pub fn ready(&self) -> bool {
        let s = self.lock();
        !s.q.is_empty() || s.done.is_some()
    }

    /// Waits up to `timeout` for a block or the translator's last word.
    pub fn wait_ready(&self, timeout: Duration) {
        let s = self.lock();
        if s.q.is_empty() && s.done.is_none() {
            let _ = self.not_empty.wait_timeout(s, timeout);
        }
    }

    /// Blocks in B1 now.
    pub fn len(&self) -> usize {
        self.lock().q.len()
    }
}

/// The pulse core reads B1 through this.
impl BlockSource for &B1 {
    fn fetch(&mut self) -> Fetch {
        let mut s = self.lock();
        if let Some(e) = s.q.pop_front() {
            drop(s);
            self.not_full.notify_all();
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

    fn stmts(n: u32) -> MakeStatements {
        Box::new(move || {
            Box::new((1..=n).map(|i| {
                Ok(Statement {
                    line: i,
                    text: String::new(),
                    blocks: vec![Block::aux(i, i, [0; 3])],
                })
            }))
        })
    }

    fn wait_len(b1: &B1, n: usize) {
        for _ in 0..500 {
            if b1.len() == n {
                return;
            }
            std::thread::sleep(Duration::from_millis(2));
        }
    }

    #[test]
    fn the_translator_waits_while_b1_is_full_and_blocks_come_in_order() {
        let b1 = B1::new(3);
        b1.load(stmts(10));
        wait_len(&b1, 3);
        std::thread::sleep(Duration::from_millis(20));
        assert_eq!(b1.len(), 3, "never more than the capacity");
        let mut seen = vec![];
        let mut src = &*b1;
        loop {
            match src.fetch() {
                Fetch::Block(e) => seen.push(e.stmt.line),
                Fetch::Pending => b1.wait_ready(Duration::from_millis(50)),
                Fetch::End => break,
                Fetch::Error(e) => panic!("{e}"),
            }
        }
        assert_eq!(seen, (1..=10).collect::<Vec<_>>());
    }

    #[test]
    fn clear_abandons_the_translator() {
        let b1 = B1::new(2);
        b1.load(stmts(100));
        wait_len(&b1, 2);
        b1.clear();
        std::thread::sleep(Duration::from_millis(20));
        assert_eq!(b1.len(), 0);
        assert!(matches!((&*b1).fetch(), Fetch::End));
    }

    #[test]
    fn a_panicking_translator_stops_the_run_with_an_error() {
        let b1 = B1::new(2);
        b1.load(Box::new(|| {
            Box::new((0..1).map(|_| -> Result<Statement, TranslateError> { panic!("bug") }))
        }));
        b1.wait_ready(Duration::from_secs(5));
        assert!(matches!((&*b1).fetch(), Fetch::Error(_)));
    }
}
