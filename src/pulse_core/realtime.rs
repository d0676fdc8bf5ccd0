//! Real time: the step queue between the pulse core and the wall clock, every kernel's.
//!
//! The pulse core generates each NCBR slice up to one tick ahead of the wall clock. What it
//! generated is a queue: its recorded events are held here and released only when the wall
//! clock reaches their machine time. An EMERGENCY STOP arriving at wall time w (machine time
//! m_w) must stop the pulses at m_w, not at the end of what was queued, so the kernel is
//! rolled back: a quiet copy is kept before a slice (at most every `SNAP_EVERY_NS`, with the
//! blocks B1 handed the centre's channel since and the operator messages applied since), the
//! latest copy before m_w is restored, advanced to exactly m_w (deterministic, so the same
//! pulses), the messages since are applied again, and the e-stop is applied there; queued
//! events from m_w on are dropped. No pulse from m_w on is counted or recorded, on any channel.

use super::kernel::Kernel;
use super::source::Fetch;
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
    /// An operator command to the centre's machine (a streaming kernel's channel 0).
    Cmd(Command),
    /// An operator command to a channel of a kernel (None: every channel), by the kernel's
    /// rules (`Kernel::command_to`).
    Chan(Option<usize>, Command),
    /// A fault injected into a channel.
    Fault(usize, String),
    /// The part target.
    Target(u32),
    /// New tool data.
    Magazine(Box<Magazine>),
    /// Panel mode names (every channel's).
    Modes(String, String),
    /// Axis positions set.
    Position(Axes),
}

/// Applies an operation to the kernel: the centre's own to channel 0, the panel's mode names
/// to every channel. A command's refusal, if any.
pub fn apply(k: &mut Kernel, op: &Op) -> Result<(), String> {
    match op {
        Op::Cmd(c) => k.first_mut().command(c.clone()),
        Op::Chan(ch, c) => return k.command_to(*ch, c.clone()),
        Op::Fault(ch, why) => return k.fault(*ch, why),
        Op::Target(n) => return k.set_target(*n),
        Op::Magazine(mg) => k.first_mut().set_magazine((**mg).clone()),
        Op::Modes(o, d) => {
            for i in 0..k.channels() {
                if let Some(m) = k.machine_mut(i) {
                    m.set_panel_modes(o, d);
                }
            }
        }
        Op::Position(p) => {
            k.first_mut().set_position(*p);
        }
    }
    Ok(())
}

/// The kernel before one slice, what that slice read from B1, and the messages since.
struct Snap {
    start: u64,
    kernel: Kernel,
    fetched: Vec<Fetch>,
    ops: Vec<Op>,
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

/// A copy of the kernel is kept before a slice at most this often, in machine time (the
/// centre's 5 ms slices each have one; of the Citizen's 100 µs ticks, one in ten): an E-STOP is
/// rolled back to the latest copy before its instant and run forward from there. A copy a
/// tick cost the Citizen's real-time run about 15 % more CPU time.
const SNAP_EVERY_NS: u64 = 1_000_000;

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
    /// Takes over the kernel's recording (events now go through the queue to `out`: the
    /// centre's machine untagged, each channel of a lathe tagged with its channel), with
    /// machine time `k.now()` at the wall clock's now.
    pub fn new(k: &mut Kernel, out: Option<EventSink>) -> StepQueue {
        let (tx, rx) = sync_channel(1 << 16);
        let q = StepQueue {
            wall0: Instant::now(),
            t0: k.now(),
            snaps: VecDeque::new(),
            internal: EventSink::new(tx),
            rx,
            pending: VecDeque::new(),
            out,
        };
        q.record(k);
        k.log_stream(true);
        q
    }

    /// Every channel's machine records into the queue (with an output), keeping its capture.
    fn record(&self, k: &mut Kernel) {
        if self.out.is_some() {
            k.set_recording(Some(self.internal.clone()), false);
        }
    }

    /// Where what is recorded outside the machines (a kernel's events) goes: through the
    /// queue, when there is an output.
    pub fn sink(&self) -> Option<&EventSink> {
        self.out.as_ref().map(|_| &self.internal)
    }

    /// The machine time the wall clock is at.
    pub fn machine_now(&self) -> u64 {
        self.t0 + self.wall0.elapsed().as_nanos() as u64
    }

    /// The wall-clock instant of machine time `t`.
    pub fn wall_of(&self, t: u64) -> Instant {
        self.wall0 + Duration::from_nanos(t.saturating_sub(self.t0))
    }

    /// Generates the next NCBR slice of `ticks` ticks (more than one: a kernel at rest),
    /// keeping a copy of the kernel for an e-stop rollback.
    pub fn slice(&mut self, k: &mut Kernel, ticks: u64) {
        let now = k.now();
        if self
            .snaps
            .back()
            .is_none_or(|s| now.saturating_sub(s.start) >= SNAP_EVERY_NS)
        {
            self.snaps.push_back(Snap {
                start: now,
                kernel: k.quiet_copy(),
                fetched: Vec::new(),
                ops: Vec::new(),
            });
            while self.snaps.len() > 3 {
                self.snaps.pop_front();
            }
        }
        k.advance_to(k.slice_end(ticks));
        if let Some(s) = self.snaps.back_mut() {
            s.fetched.extend(k.take_stream_log());
        }
        self.collect();
    }

    /// Records a message applied to the kernel, for replay after a rollback.
    pub fn applied(&mut self, op: Op) {
        for s in &mut self.snaps {
            s.ops.push(op.clone());
        }
        self.collect();
    }

    /// A change that cannot be replayed (a new cycle loaded, a program read again, the
    /// capture or audit turned): no rollback reaches back before it, so an E-STOP in the
    /// slice under way acts at the kernel's time.
    pub fn barrier(&mut self) {
        self.snaps.clear();
        self.collect();
    }

    /// EMERGENCY STOP at the wall clock's machine time: pulses stop there. The kernel is
    /// rolled back to the copy kept before the slice holding that instant, run forward to
    /// it with what B1 handed out then and the messages since, and stopped there; what it
    /// made past that instant, and had queued, is dropped. The instant it stopped at.
    pub fn estop(&mut self, k: &mut Kernel) -> u64 {
        let mw = self.machine_now();
        if mw < k.now() {
            if let Some(s) = self.snaps.iter().rev().find(|s| s.start <= mw) {
                // Every pulse made so far goes to the queue (a lathe channel's batches fill
                // for 10 ms of machine time), to be cut at the instant below.
                for i in 0..k.channels() {
                    if let Some(m) = k.machine_mut(i) {
                        m.flush_recording();
                    }
                }
                let mut r = s.kernel.clone();
                let audits: Vec<bool> = (0..k.channels())
                    .map(|i| k.machine(i).is_some_and(|m| m.audits()))
                    .collect();
                r.replay_stream(s.fetched.clone());
                r.advance_to(mw);
                r.resume_stream();
                // What the copy made again up to the instant was already taken from the
                // kernel (events): it is forgotten, not told twice.
                r.take_events();
                for (i, audit) in audits.into_iter().enumerate() {
                    if let Some(m) = r.machine_mut(i) {
                        m.set_audit(audit);
                    }
                }
                for i in 0..k.channels() {
                    let on = k.machine(i).is_some_and(|m| m.captures());
                    if let Some(m) = r.machine_mut(i) {
                        m.set_capture(on);
                    }
                }
                self.record(&mut r);
                for op in &s.ops {
                    let _ = apply(&mut r, op);
                }
                *k = r;
                self.collect();
                self.drop_from(mw);
            }
        }
        k.estop();
        self.snaps.clear();
        self.collect();
        k.now()
    }

    /// Drops queued events at or after machine time `t`.
    fn drop_from(&mut self, t: u64) {
        /// Keeps what of `ev` happened before `t` (a channel's event looked into).
        fn keep(ev: &mut Event, t: u64) -> bool {
            match ev {
                Event::OnChannel { ev, .. } => keep(ev, t),
                Event::Pulses { t_ns, .. } => {
                    t_ns.retain(|&x| x < t);
                    !t_ns.is_empty()
                }
                _ => times(ev).0 < t,
            }
        }
        self.pending.retain_mut(|ev| keep(ev, t));
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
