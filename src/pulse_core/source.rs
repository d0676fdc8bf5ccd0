//! Where NCBR reads blocks from: the block buffer B1 as seen by the pulse core.

use super::block_buffer::BlockBuffer;
use super::BlockEntry;
use crate::block::{Block, Statement, TranslateError};
use std::sync::Arc;

/// What NCBR finds when it reads the next block.
#[derive(Clone, Debug)]
pub enum Fetch {
    /// The next block.
    Block(BlockEntry),
    /// B1 is empty but the translator is still working.
    Pending,
    /// The program has been run to its end.
    End,
    /// The translator stopped at this error; every block before it has been read.
    Error(TranslateError),
}

/// The reading side of B1.
pub trait BlockSource {
    /// Takes the next block (or says why there is none).
    fn fetch(&mut self) -> Fetch;

    /// The machine's answer to a source waiting on it (a probe block done); sources that
    /// never wait drop it.
    fn answer(&mut self, _a: super::block_buffer::Answer) {}
}

/// An in-memory B1 filled up front (tests, benchmarks, `translate_all` results). It keeps
/// what it has handed out, so that [`VecSource::rewind`] can read the program again from its
/// first block: a channel of the multi-channel kernel runs its program once per work
/// (docs/pulse-core.md, "Channels").
#[derive(Clone, Debug, Default)]
pub struct VecSource {
    q: Vec<Fetch>,
    /// The next entry to hand out.
    at: usize,
}

impl VecSource {
    /// B1 holding every block of these statements, then the end (or the error).
    pub fn from_statements<I>(stmts: I) -> VecSource
    where
        I: IntoIterator<Item = Result<Statement, TranslateError>>,
    {
        let mut q = Vec::new();
        for r in stmts {
            match r {
                Ok(s) => {
                    let s = Arc::new(s);
                    for index in 0..s.blocks.len() {
                        q.push(Fetch::Block(BlockEntry {
                            stmt: s.clone(),
                            index,
                        }));
                    }
                }
                Err(e) => {
                    q.push(Fetch::Error(e));
                    return VecSource { q, at: 0 };
                }
            }
        }
        q.push(Fetch::End);
        VecSource { q, at: 0 }
    }

    /// B1 holding these blocks, each as its own statement (line = `block.stmt`).
    pub fn from_blocks(blocks: Vec<Block>) -> VecSource {
        VecSource::from_statements(blocks.into_iter().map(|b| {
            Ok(Statement {
                line: b.stmt,
                text: String::new(),
                blocks: vec![b],
            })
        }))
    }

    /// Blocks still in the buffer.
    pub fn len(&self) -> usize {
        self.q[self.at.min(self.q.len())..]
            .iter()
            .filter(|f| matches!(f, Fetch::Block(_)))
            .count()
    }

    /// Whether no block is left.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Every block it holds, from the first.
    pub fn blocks(&self) -> impl Iterator<Item = &crate::block::Block> {
        self.q.iter().filter_map(|f| match f {
            Fetch::Block(e) => e.stmt.blocks.get(e.index),
            _ => None,
        })
    }

    /// Back to the first block: the program is read again from its start.
    pub fn rewind(&mut self) {
        self.at = 0;
    }

    /// Takes `other`'s blocks from the first tool call (`t`) not yet handed out on, where
    /// `other` is this program read again (the same blocks in the same order, their end
    /// points moved by a revised tool offset), and where the block before the call ends at
    /// the same point in both (so that the machine stands where `other`'s next block starts
    /// from: not after a tool whose offset was revised). What is handed out from there is
    /// `other`'s. Returns the block of the call, or None (no such call, or the two are not the
    /// same program up to it: nothing changes).
    pub fn splice_at_next_tool_call(&mut self, other: &VecSource) -> Option<&Block> {
        fn block(f: &Fetch) -> Option<&Block> {
            match f {
                Fetch::Block(e) => e.stmt.blocks.get(e.index),
                _ => None,
            }
        }
        // The same program, block for block: the same numbers, tools and meeting points.
        let same = |a: Option<&Block>, b: Option<&Block>| match (a, b) {
            (Some(a), Some(b)) => (a.seq, a.stmt, a.t, a.sync) == (b.seq, b.stmt, b.t, b.sync),
            (None, None) => true,
            _ => false,
        };
        let n = self.q.len().min(other.q.len());
        let mut last_end = None;
        let mut k = None;
        for i in 0..n {
            let (a, b) = (block(&self.q[i]), block(&other.q[i]));
            if !same(a, b) {
                return None;
            }
            if i >= self.at
                && a.is_some_and(|a| a.t.is_some())
                && last_end.is_none_or(|(x, y)| x == y)
            {
                k = Some(i);
                break;
            }
            if let (Some(a), Some(b)) = (a, b) {
                last_end = Some((a.end, b.end));
            }
        }
        let k = k?;
        self.q.truncate(k);
        self.q.extend(other.q[k..].iter().cloned());
        block(&self.q[k])
    }
}

impl BlockSource for VecSource {
    fn fetch(&mut self) -> Fetch {
        match self.q.get(self.at) {
            None | Some(Fetch::End) => Fetch::End,
            Some(f) => {
                self.at += 1;
                f.clone()
            }
        }
    }
}

/// Where a kernel channel reads its blocks (docs/pulse-core.md, "Channels"): its program read
/// whole, run once per work (a lathe channel's), or B1 as the translator thread fills it (the
/// machining centre's one channel, whose program is translated while it runs). A copy of a
/// stream reads the same B1: the kernel never copies a streaming channel to look ahead with
/// (`Kernel::run_until` runs it alone), and the real-time step queue, which keeps copies to
/// roll an E-STOP back to, gives a copy what the stream handed out instead ([`Self::replay`]).
#[derive(Clone, Debug)]
pub enum ChannelSource {
    /// The program read whole, read again from its first block at each work.
    Program(VecSource),
    /// B1, filled by the translator thread from the machine's state at the START of each run;
    /// with a log, what it has handed out since the log was last taken.
    Stream(Arc<BlockBuffer>, Option<Vec<Fetch>>),
    /// What a stream handed out, read again (then `Pending`), before the stream goes on.
    Replay(std::collections::VecDeque<Fetch>, Arc<BlockBuffer>),
}

impl ChannelSource {
    /// Back to the start of the program: a program is read again from its first block; a
    /// stream is abandoned (the next run's START loads B1 again).
    pub fn rewind(&mut self) {
        match self {
            ChannelSource::Program(v) => v.rewind(),
            ChannelSource::Stream(b, _) | ChannelSource::Replay(_, b) => b.clear(),
        }
    }

    /// Whether it is B1, streamed (or read again).
    pub fn streams(&self) -> bool {
        !matches!(self, ChannelSource::Program(_))
    }

    /// A stream logs what it hands out from now on (off: forgets it).
    pub fn log(&mut self, on: bool) {
        if let ChannelSource::Stream(_, log) = self {
            *log = on.then(Vec::new);
        }
    }

    /// What a logging stream has handed out since the last call.
    pub fn take_log(&mut self) -> Vec<Fetch> {
        match self {
            ChannelSource::Stream(_, Some(log)) => std::mem::take(log),
            _ => Vec::new(),
        }
    }

    /// A stream hands out `fetched` again, then `Pending`, until [`Self::resume`].
    pub fn replay(&mut self, fetched: Vec<Fetch>) {
        if let ChannelSource::Stream(b, _) | ChannelSource::Replay(_, b) = self {
            *self = ChannelSource::Replay(fetched.into(), b.clone());
        }
    }

    /// A stream read again reads B1 again, logging.
    pub fn resume(&mut self) {
        if let ChannelSource::Replay(_, b) = self {
            *self = ChannelSource::Stream(b.clone(), Some(Vec::new()));
        }
    }
}

impl BlockSource for ChannelSource {
    fn fetch(&mut self) -> Fetch {
        match self {
            ChannelSource::Program(v) => v.fetch(),
            ChannelSource::Stream(b, log) => {
                let f = (&mut &**b).fetch();
                if let Some(l) = log {
                    l.push(f.clone());
                }
                f
            }
            ChannelSource::Replay(q, _) => q.pop_front().unwrap_or(Fetch::Pending),
        }
    }

    fn answer(&mut self, a: super::block_buffer::Answer) {
        match self {
            ChannelSource::Program(v) => v.answer(a),
            ChannelSource::Stream(b, _) => (&mut &**b).answer(a),
            // A block read again was answered the first time.
            ChannelSource::Replay(..) => {}
        }
    }
}
