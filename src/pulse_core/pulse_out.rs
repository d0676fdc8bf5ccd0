//! The servo side of PGEN: the axis pulse counters, and the pulse log that batches pulse times
//! for the recording (`/nc/pulses`) or captures them for tests.
//!
//! With logging off the cost of a pulse is a counter update and one flag check.

use crate::block::Axes;
use crate::record::{Event, EventSink};
use std::cell::Cell;

/// Pulses of one (axis, direction) are sent when a batch reaches this many.
pub const BATCH: usize = 4096;

/// Longest a lossless sender waits for room in the recorder's queue before dropping an event.
const LOSSLESS_PATIENCE: std::time::Duration = std::time::Duration::from_secs(2);

/// Sends an event to the recording. Lossy (real time): never waits; a full queue drops it
/// and marks the recording incomplete. Lossless (virtual time, where no wall-clock duty
/// exists): waits for room, up to `LOSSLESS_PATIENCE`; a recorder that makes no room in that
/// time is taken as stuck: the event is dropped as a lossy send would, and `lossless` is
/// switched off for the rest of the run so that the machine is never held up again.
pub fn emit(sink: &EventSink, ev: Event, lossless: &Cell<bool>) {
    if !lossless.get() {
        sink.send(ev);
        return;
    }
    let mut ev = ev;
    let start = std::time::Instant::now();
    let mut spins = 0u32;
    loop {
        match sink.try_send(ev) {
            Ok(()) => return,
            Err(back) => ev = back,
        }
        if start.elapsed() > LOSSLESS_PATIENCE {
            lossless.set(false);
            sink.send(ev);
            return;
        }
        spins += 1;
        if spins < 16 {
            std::thread::yield_now();
        } else {
            std::thread::sleep(std::time::Duration::from_micros(50));
        }
    }
}

/// One captured pulse: axis (0 = X), direction (±1), machine time in ns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PulseRec {
    /// Axis 0 = X, 1 = Y, 2 = Z, 3 = A.
    pub axis: u8,
    /// +1 or −1.
    pub dir: i8,
    /// Machine time, ns.
    pub t_ns: u64,
}

/// The axis counters and the pulse log.
///
/// MACHINE LOCK and Z NEGLECT (docs/pulse-core.md, "Machine lock"): a pulse of a locked axis
/// moves the program position `pos` but is not output: no count, no log, and `shift` keeps
/// how far `pos` has left the axis, so the axis itself stands at `pos - shift`.
#[derive(Clone, Debug, Default)]
pub struct PulseOut {
    /// Program positions, pulses: where the interpolation stands (the axis positions, less
    /// `shift` on locked axes).
    pub pos: Axes,
    /// Pulses output per axis in this run.
    pub count: Axes<u64>,
    /// Axes whose pulses are held back (machine lock, Z neglect).
    lock: Axes<bool>,
    /// How far the program position has moved on locked axes since the last `unshift`.
    pub shift: Axes,
    /// Logging or a lock: every pulse goes through `slow_pulse`.
    slow: bool,
    log: bool,
    batches: [[Vec<u64>; 2]; crate::block::MAX_AXES],
    capture: Option<Vec<PulseRec>>,
    sink: Option<EventSink>,
    /// Wait for room in the recorder's queue rather than drop (virtual time).
    pub lossless: Cell<bool>,
}

impl PulseOut {
    /// Whether pulses are captured for tests.
    pub fn captures(&self) -> bool {
        self.capture.is_some()
    }

    /// Sets where logged pulses go.
    pub fn set_log(&mut self, sink: Option<EventSink>, capture: bool) {
        self.sink = sink.filter(|s| s.records_pulses());
        self.capture = if capture { Some(Vec::new()) } else { None };
        self.log = self.sink.is_some() || self.capture.is_some();
        self.slow = self.log || self.lock.iter().any(|&l| l);
    }

    /// Sets which axes are locked (their pulses are not output), from the next pulse.
    pub fn set_lock(&mut self, lock: impl Into<Axes<bool>>) {
        let lock = lock.into();
        self.lock = lock;
        self.slow = self.log || lock.iter().any(|&l| l);
    }

    /// The axis positions, pulses: the program position less what locked axes did not move.
    pub fn machine_pos(&self) -> Axes {
        Axes::from_fn(|a| self.pos[a] - self.shift[a])
    }

    /// Brings the program position back to the axes' (RESET, a new run).
    pub fn unshift(&mut self) {
        self.pos = self.machine_pos();
        self.shift = Axes::default();
    }

    /// A copy that outputs the same pulses and logs none (no sink, capture or batches): a
    /// machine's look-ahead copy, made without copying what the log holds.
    pub fn quiet_copy(&mut self) -> PulseOut {
        let sink = self.sink.take();
        let capture = self.capture.take();
        let batches = std::mem::take(&mut self.batches);
        let mut q = self.clone();
        (self.sink, self.capture, self.batches) = (sink, capture, batches);
        q.log = false;
        q.slow = q.lock.iter().any(|&l| l);
        q
    }

    /// Takes the captured pulses so far.
    pub fn take_capture(&mut self) -> Vec<PulseRec> {
        self.capture
            .as_mut()
            .map(std::mem::take)
            .unwrap_or_default()
    }

    /// One pulse at machine time `t` ns given as a float (truncated to whole ns, and only
    /// when the pulse is logged: a dry run never converts it).
    #[inline(always)]
    pub fn pulse_at(&mut self, axis: usize, dir: i8, t: f64) {
        self.pos[axis] += dir as i64;
        self.count[axis] += 1;
        if self.slow {
            self.slow_pulse(axis, dir, t as u64);
        }
    }

    /// One pulse at machine time `t` ns (the error-proportional interpolator's cycles are
    /// whole nanoseconds).
    #[inline(always)]
    pub fn pulse_at_ns(&mut self, axis: usize, dir: i8, t: u64) {
        self.pos[axis] += dir as i64;
        self.count[axis] += 1;
        if self.slow {
            self.slow_pulse(axis, dir, t);
        }
    }

    /// A pulse with logging on or a lock: a locked axis's pulse is taken back from the
    /// counter and kept in `shift`; any other is logged.
    #[inline]
    fn slow_pulse(&mut self, axis: usize, dir: i8, t: u64) {
        if self.lock[axis] {
            self.count[axis] -= 1;
            self.shift[axis] += dir as i64;
        } else if self.log {
            self.log_pulse(axis, dir, t);
        }
    }

    #[inline]
    fn log_pulse(&mut self, axis: usize, dir: i8, t: u64) {
        if let Some(c) = &mut self.capture {
            c.push(PulseRec {
                axis: axis as u8,
                dir,
                t_ns: t,
            });
        }
        if self.sink.is_some() {
            let d = usize::from(dir < 0);
            let b = &mut self.batches[axis][d];
            b.push(t);
            if b.len() >= BATCH {
                self.flush_one(axis, d);
            }
        }
    }

    fn flush_one(&mut self, axis: usize, d: usize) {
        let b = &mut self.batches[axis][d];
        if b.is_empty() {
            return;
        }
        let t_ns = std::mem::replace(b, Vec::with_capacity(BATCH));
        if let Some(s) = &self.sink {
            let ev = Event::Pulses {
                axis: axis as u8,
                dir: if d == 0 { 1 } else { -1 },
                t_ns,
            };
            emit(s, ev, &self.lossless);
        }
    }

    /// Sends every pending batch (at each NCBR tick and block end).
    pub fn flush(&mut self) {
        if self.sink.is_none() {
            return;
        }
        for a in 0..crate::block::MAX_AXES {
            for d in 0..2 {
                self.flush_one(a, d);
            }
        }
    }
}
