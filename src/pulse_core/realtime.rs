//! Real time: the step queue between the pulse core and the wall clock.
//!
//! The pulse core generates each NCBR slice up to one tick ahead of the wall clock. What it
//! generated is a queue: its recorded events are held here and released only when the wall
//! clock reaches their machine time. An EMERGENCY STOP arriving at wall time w (machine time
//! m_w) must stop the pulses at m_w, not at the end of what was queued, so the machine is
//! rolled back: a snapshot is kept before each slice (with the blocks that slice read from B1
//! and the operator messages applied since), the snapshot of the slice holding m_w is
//! restored, advanced to exactly m_w (deterministic, so the same pulses), the messages since are
//! applied again, and the e-stop is applied there; queued events after m_w are dropped. No
//! pulse after m_w is counted or recorded.

use super::block_buffer::BlockBuffer;
use super::machine::Machine;
use super::source::{BlockSource, Fetch};
use super::Command;
use crate::block::Axes;
use crate::record::{Event, EventSink};
use crate::tooldata::Magazine;
use std::collections::VecDeque;
use std::sync::mpsc::{sync_channel, Receiver};
use std::time::{Duration, Instant};

/// The machine-side effect of a message to the pulse core (replayed after a rollback).
#[derive(Clone, Debug)]
pub enum Op {
    /// An operator command.
    Cmd(Command),
    /// New tool data.
    Magazine(Box<Magazine>),
    /// Panel mode names.
    Modes(String, String),
    /// Axis positions set.
    Position(Axes),
    /// The jog feed, mm/min.
    JogFeed(f64),
}

/// Applies an operation to the machine.
pub fn apply(m: &mut Machine, op: &Op) {
    match op {
        Op::Cmd(c) => m.command(c.clone()),
        Op::Magazine(mg) => m.set_magazine((**mg).clone()),
        Op::Modes(o, d) => m.set_panel_modes(o, d),
        Op::Position(p) => {
            m.set_position(*p);
        }
        Op::JogFeed(f) => m.set_jog_feed(*f),
    }
}

/// The machine before one slice, what that slice read from B1, and the messages since.
struct Snap {
    start: u64,
    machine: Machine,
    fetched: Vec<Fetch>,
    ops: Vec<Op>,
}

/// Reads B1 and logs what it read.
struct Logging<'a> {
    b1: &'a BlockBuffer,
    log: Option<&'a mut Vec<Fetch>>,
}

impl BlockSource for Logging<'_> {
    fn fetch(&mut self) -> Fetch {
        let mut src = self.b1;
        let f = src.fetch();
        if let Some(l) = &mut self.log {
            l.push(f.clone());
        }
        f
    }

    fn answer(&mut self, a: super::block_buffer::Answer) {
        let mut src = self.b1;
        src.answer(a);
    }
}

/// Gives back what a slice read.
struct Replay(VecDeque<Fetch>);

impl BlockSource for Replay {
    fn fetch(&mut self) -> Fetch {
        self.0.pop_front().unwrap_or(Fetch::Pending)
    }
}

/// Machine time of an event, and of the last pulse of a batch.
fn times(ev: &Event) -> (u64, u64) {
    match ev {
        Event::Block { t_ns, .. }
        | Event::Position { t_ns, .. }
        | Event::State { t_ns, .. }
        | Event::Display { t_ns, .. }
        | Event::PanelEvent { t_ns, .. }
        | Event::Probe { t_ns, .. }
        | Event::Io { t_ns, .. }
        | Event::Log { t_ns, .. }
        | Event::Lathe { t_ns, .. } => (*t_ns, *t_ns),
        Event::OnChannel { ev, .. } => times(ev),
        Event::Pulses { t_ns, .. } => (
            t_ns.first().copied().unwrap_or(0),
            t_ns.last().copied().unwrap_or(0),
        ),
    }
}

/// The real-time step queue.
pub struct StepQueue {
    wall0: Instant,
    t0: u64,
    snaps: VecDeque<Snap>,
    internal: EventSink,
    rx: Receiver<Event>,
    pending: VecDeque<Event>,
    out: Option<EventSink>,
}

impl StepQueue {
    /// Takes over the machine's recording (events now go through the queue to `out`), with
    /// machine time `m.now()` at the wall clock's now.
    pub fn new(m: &mut Machine, out: Option<EventSink>) -> StepQueue {
        let (tx, rx) = sync_channel(1 << 16);
        let internal = EventSink::new(tx);
        if out.is_some() {
            m.set_recording(Some(internal.clone()), false);
            m.set_lossless_recording(false);
        }
        StepQueue {
            wall0: Instant::now(),
            t0: m.now(),
            snaps: VecDeque::new(),
            internal,
            rx,
            pending: VecDeque::new(),
            out,
        }
    }

    /// The machine time the wall clock is at.
    pub fn machine_now(&self) -> u64 {
        self.t0 + self.wall0.elapsed().as_nanos() as u64
    }

    /// The wall-clock instant of machine time `t`.
    pub fn wall_of(&self, t: u64) -> Instant {
        self.wall0 + Duration::from_nanos(t.saturating_sub(self.t0))
    }

    /// Generates the next NCBR slice, keeping a snapshot for an e-stop rollback.
    pub fn slice(&mut self, m: &mut Machine, b1: &BlockBuffer) {
        self.snaps.push_back(Snap {
            start: m.now(),
            machine: m.clone(),
            fetched: Vec::new(),
            ops: Vec::new(),
        });
        while self.snaps.len() > 3 {
            self.snaps.pop_front();
        }
        let log = self.snaps.back_mut().map(|s| &mut s.fetched);
        m.tick(&mut Logging { b1, log });
        self.collect();
    }

    /// Records a message applied to the machine, for replay after a rollback.
    pub fn applied(&mut self, op: Op) {
        for s in &mut self.snaps {
            s.ops.push(op.clone());
        }
        self.collect();
    }

    /// EMERGENCY STOP at the wall clock's machine time: pulses stop there.
    pub fn estop(&mut self, m: &mut Machine) {
        let mw = self.machine_now();
        self.collect();
        if mw < m.now() {
            if let Some(s) = self.snaps.iter().rev().find(|s| s.start <= mw) {
                let mut r = s.machine.clone();
                r.set_recording(None, false);
                r.advance_to(mw, &mut Replay(s.fetched.iter().cloned().collect()));
                if self.out.is_some() {
                    r.set_recording(Some(self.internal.clone()), false);
                }
                for op in &s.ops {
                    apply(&mut r, op);
                }
                *m = r;
                self.drop_from(mw);
            }
        }
        m.command(Command::EStop);
        self.snaps.clear();
        self.collect();
    }

    /// Drops queued events at or after machine time `t`.
    fn drop_from(&mut self, t: u64) {
        self.pending.retain_mut(|ev| match ev {
            Event::Pulses { t_ns, .. } => {
                t_ns.retain(|&x| x < t);
                !t_ns.is_empty()
            }
            _ => times(ev).0 < t,
        });
    }

    fn collect(&mut self) {
        while let Ok(ev) = self.rx.try_recv() {
            self.pending.push_back(ev);
        }
    }

    /// Releases to the recording every queued event the wall clock has reached.
    pub fn release(&mut self) {
        self.collect();
        let Some(out) = &self.out else {
            self.pending.clear();
            return;
        };
        if self.internal.is_incomplete() {
            out.mark_incomplete();
        }
        let now = self.machine_now();
        while let Some(ev) = self.pending.front_mut() {
            let (first, last) = times(ev);
            if last <= now {
                if let Some(ev) = self.pending.pop_front() {
                    out.send(ev);
                }
            } else if first <= now {
                if let Event::Pulses { axis, dir, t_ns } = ev {
                    let k = t_ns.partition_point(|&x| x <= now);
                    let due: Vec<u64> = t_ns.drain(..k).collect();
                    out.send(Event::Pulses {
                        axis: *axis,
                        dir: *dir,
                        t_ns: due,
                    });
                }
                break;
            } else {
                break;
            }
        }
    }

    /// Releases everything queued (the core is stopping).
    pub fn release_all(&mut self) {
        self.collect();
        if let Some(out) = &self.out {
            if self.internal.is_incomplete() {
                out.mark_incomplete();
            }
            for ev in self.pending.drain(..) {
                out.send(ev);
            }
        }
    }
}
