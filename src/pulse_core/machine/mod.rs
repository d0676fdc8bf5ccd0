//! The simulated machine as a pure, deterministic state machine: NCBR every NCBR period of
//! machine time, PGEN inside each tick, the relay logic for M, S and T, and the operator
//! commands. Tests drive it directly; the pulse core thread only wraps it.
//!
//! Timing of one NCBR tick at machine time t (period P, 5 ms by default):
//! 1. a new feed override takes effect (the target speed of the motion in force changes);
//! 2. if RUN ≠ 0, no feed hold, and the last block is complete (DEN and auxiliary function
//!    complete): in SINGLE BLOCK RUN is cleared; otherwise the next block is read from B1,
//!    checked against the travel limits, and started (its auxiliary functions first);
//! 3. PGEN distributes every pulse whose time falls in [t, t + P);
//! 4. pending pulse batches are flushed and, while moving, the position is recorded.
//!
//! A block that completes mid-tick leaves the machine at rest until the next tick reads the
//! following block (as the patent's NCBR does).

use super::motion::{accel_pulses_ns2, speed_pulses_ns, Motion, Progress};
use super::pulse_out::{PulseOut, PulseRec};
use super::source::{BlockSource, Fetch};
use super::B1Entry;
use crate::block::{Block, Motion as Kind};
use crate::record::{Event, EventSink};
use crate::settings::MachineSettings;
use crate::tooldata::Magazine;
use check::{arc_stepper, check_block};
use std::collections::VecDeque;

mod check;
mod commands;
mod jog;
mod report;

pub use check::axis_name;

/// Sends an event to the recording (lossless in virtual time, see `pulse_out::emit`).
fn send_ev(s: &EventSink, lossless: &std::cell::Cell<bool>, ev: Event) {
    super::pulse_out::emit(s, ev, lossless);
}

/// Where the executing block is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Phase {
    /// Auxiliary functions before the motion (T, M06, S, M03, M04), until `until`.
    PreAux,
    /// The motion (or the dwell, until `until`).
    Move,
    /// Auxiliary functions after the motion (M05, M30), until `until`.
    PostAux,
}

/// The block being executed.
#[derive(Clone, Debug)]
struct Current {
    entry: B1Entry,
    /// A copy of the entry's block.
    block: Block,
    phase: Phase,
    until: u64,
    motion: Option<Motion>,
}

/// A jog in progress (CONTINUOUS, STEP or HANDLE).
#[derive(Clone, Debug)]
struct Jog {
    motion: Motion,
    /// CONTINUOUS: stop and drop the rest once at rest.
    release: bool,
}

/// The simulated machine: axes, relay logic, RUN and the operator state.
#[derive(Clone, Debug)]
pub struct Machine {
    settings: MachineSettings,
    accel: f64,
    now: u64,
    next_tick: u64,
    run: u8,
    hold: bool,
    estop: bool,
    alarm: Option<String>,
    notice: Option<String>,
    single_block: bool,
    feed_override: u32,
    pending_override: Option<u32>,
    current: Option<Current>,
    last_entry: Option<B1Entry>,
    just_completed: bool,
    blocks_done: u64,
    out: PulseOut,
    selected_t: Option<u32>,
    tool: Option<u32>,
    tool_len: f64,
    spindle: i64,
    s_rpm: u32,
    program_end: bool,
    magazine: Option<Magazine>,
    jog: Option<Jog>,
    increments: VecDeque<(usize, i64)>,
    events: Option<EventSink>,
    last_state: Option<(u8, u32, u32, i64, String, String)>,
    op_mode: String,
    data_mode: String,
    commands: u64,
}

impl Machine {
    /// A machine at rest at machine zero, time 0.
    pub fn new(settings: MachineSettings) -> Machine {
        let accel = accel_pulses_ns2(settings.accel_mm_s2, settings.pulse_mm);
        Machine {
            settings,
            accel,
            now: 0,
            next_tick: 0,
            run: 0,
            hold: false,
            estop: false,
            alarm: None,
            notice: None,
            single_block: false,
            feed_override: 100,
            pending_override: None,
            current: None,
            last_entry: None,
            just_completed: false,
            blocks_done: 0,
            out: PulseOut::default(),
            selected_t: None,
            tool: None,
            tool_len: 0.0,
            spindle: 0,
            s_rpm: 0,
            program_end: false,
            magazine: None,
            jog: None,
            increments: VecDeque::new(),
            events: None,
            last_state: None,
            op_mode: "AUTO".into(),
            data_mode: "SEARCH".into(),
            commands: 0,
        }
    }

    /// The settings in force.
    pub fn settings(&self) -> &MachineSettings {
        &self.settings
    }

    /// Records events to `sink` (blocks, positions, pulses, state) and/or captures every pulse
    /// for `take_pulses`.
    pub fn set_recording(&mut self, sink: Option<EventSink>, capture_pulses: bool) {
        self.out.set_log(sink.clone(), capture_pulses);
        self.events = sink;
        self.last_state = None;
        self.send_state();
    }

    /// Lossless recording: wait for room in the recorder's queue rather than drop an event.
    /// Only for virtual time, where machine time does not follow the wall clock.
    pub fn set_lossless_recording(&mut self, on: bool) {
        self.out.lossless.set(on);
    }

    /// The pulses captured since the last call (with `capture_pulses` on).
    pub fn take_pulses(&mut self) -> Vec<PulseRec> {
        self.out.take_capture()
    }

    /// The tool data used for the set length of the tool in the spindle.
    pub fn set_magazine(&mut self, m: Magazine) {
        self.magazine = Some(m);
    }

    /// The operation and data-processing mode names recorded in `/nc/state`.
    pub fn set_panel_modes(&mut self, op_mode: &str, data_mode: &str) {
        self.op_mode = op_mode.to_string();
        self.data_mode = data_mode.to_string();
        self.send_state();
    }

    /// Sets the axis positions (pulses) with the machine at rest; refused while anything moves.
    pub fn set_position(&mut self, pos: [i64; 3]) -> bool {
        if self.current.is_some() || self.jog.is_some() {
            return false;
        }
        self.out.pos = pos;
        true
    }

    /// A new run: block and pulse counters to zero, program end cleared.
    pub fn new_run(&mut self) {
        self.blocks_done = 0;
        self.out.count = [0; 3];
        self.program_end = false;
        self.just_completed = false;
        self.last_entry = None;
    }

    /// Machine time, ns.
    pub fn now(&self) -> u64 {
        self.now
    }

    /// Axis positions, pulses.
    pub fn pos(&self) -> [i64; 3] {
        self.out.pos
    }

    /// RUN flag.
    pub fn run_flag(&self) -> u8 {
        self.run
    }

    /// Blocks completed in this run.
    pub fn blocks_done(&self) -> u64 {
        self.blocks_done
    }

    /// Nothing will happen until a command: no motion, nothing pending, and RUN = 0 (or a feed
    /// hold at rest, or an emergency stop).
    pub fn is_idle(&self) -> bool {
        if self.estop {
            return true;
        }
        if self.jog.is_some() || !self.increments.is_empty() {
            return false;
        }
        if self.run == 0 {
            return self.current.is_none();
        }
        if self.hold {
            return match &self.current {
                None => true,
                Some(c) => c.phase == Phase::Move && c.motion.as_ref().is_some_and(|m| m.at_rest()),
            };
        }
        false
    }

    /// Standing still mid-block at feed override 0 (time passes but nothing moves).
    pub fn is_stalled(&self) -> bool {
        self.feed_override == 0
            && self.pending_override.is_none()
            && self.current.as_ref().is_some_and(|c| {
                c.phase == Phase::Move && c.motion.as_ref().is_some_and(|m| m.at_rest())
            })
    }

    /// Whether NCBR would read a block at the next tick.
    pub fn wants_block(&self) -> bool {
        self.run != 0
            && !self.hold
            && !self.estop
            && self.current.is_none()
            && !(self.just_completed && self.single_block)
    }

    /// Runs whole NCBR ticks (and the PGEN work inside them) until machine time `until`.
    pub fn advance_to(&mut self, until: u64, src: &mut dyn BlockSource) {
        while self.now < until {
            if self.now >= self.next_tick {
                self.ncbr(src);
                self.next_tick = self.now + self.settings.ncbr_period_ns.max(1);
            }
            let end = until.min(self.next_tick);
            self.pgen(end);
            self.now = end;
            if self.now >= self.next_tick {
                self.tick_end();
            }
        }
    }

    /// Runs exactly one NCBR tick from the current (tick-aligned) time.
    pub fn tick(&mut self, src: &mut dyn BlockSource) {
        let t = if self.now >= self.next_tick {
            self.now + self.settings.ncbr_period_ns.max(1)
        } else {
            self.next_tick
        };
        self.advance_to(t, src);
    }

    /// Runs ticks until the machine is idle (or `max_ns` of machine time has passed).
    pub fn run_until_idle(&mut self, src: &mut dyn BlockSource, max_ns: u64) {
        let stop = self.now.saturating_add(max_ns);
        while !self.is_idle() && self.now < stop {
            self.tick(src);
        }
    }

    fn tick_end(&mut self) {
        self.out.flush();
        let moving = self
            .current
            .as_ref()
            .and_then(|c| c.motion.as_ref())
            .is_some_and(|m| !m.at_rest())
            || self.jog.as_ref().is_some_and(|j| !j.motion.at_rest());
        if moving {
            self.send_position();
        }
        self.send_state();
    }

    /// NCBR: override, RUN, DEN and the next block.
    fn ncbr(&mut self, src: &mut dyn BlockSource) {
        if let Some(p) = self.pending_override.take() {
            self.feed_override = p;
            let feed = self
                .current
                .as_ref()
                .map(|c| &c.block)
                .filter(|b| b.motion != Kind::Rapid)
                .map(|b| b.feed);
            if let Some(feed) = feed {
                let v = self.feed_speed(feed);
                if let Some(m) = self.current.as_mut().and_then(|c| c.motion.as_mut()) {
                    m.set_target(v);
                }
            }
        }
        if !self.wants_block() {
            if self.run != 0 && self.just_completed && self.single_block && self.current.is_none() {
                self.run = 0;
                self.just_completed = false;
            }
            return;
        }
        match src.fetch() {
            Fetch::Block(e) => self.start_block(e),
            Fetch::Pending => {}
            Fetch::End => {
                self.run = 0;
                self.program_end = true;
                self.just_completed = false;
            }
            Fetch::Error(e) => {
                self.run = 0;
                self.just_completed = false;
                self.alarm = Some(e.to_string());
            }
        }
    }

    /// Path speed for a programmed feed, after override, capped at the rapid rate.
    fn feed_speed(&self, feed: f64) -> f64 {
        let f = (feed * self.feed_override as f64 / 100.0).min(self.settings.rapid_mm_min);
        speed_pulses_ns(f.max(0.0), self.settings.pulse_mm)
    }

    fn refuse(&mut self, e: &B1Entry, b: Option<&Block>, why: String) {
        let line = e.stmt.line;
        let seq = b.map(|b| format!("N{} ", b.seq)).unwrap_or_default();
        self.alarm = Some(format!(
            "{line}: {seq}{why} (statement: {})",
            e.stmt.text.trim()
        ));
        self.run = 0;
        self.just_completed = false;
        self.last_entry = Some(e.clone());
    }

    /// Reads a block into the NC table: checks, auxiliary functions, then the motion.
    fn start_block(&mut self, e: B1Entry) {
        let Some(b) = e.stmt.blocks.get(e.index).cloned() else {
            self.refuse(&e, None, "no such block".into());
            return;
        };
        if let Err(why) = check_block(&self.settings, self.out.pos, &b) {
            self.refuse(&e, Some(&b), why);
            return;
        }
        if let Some(s) = &self.events {
            send_ev(
                s,
                &self.out.lossless,
                Event::Block {
                    t_ns: self.now,
                    seq: b.seq,
                    stmt: b.stmt,
                    text: crate::translator::iso_line(&b, &self.settings),
                },
            );
        }
        let mut pre = 0;
        if b.m == Some(6) {
            pre += self.settings.tool_change_ns;
        }
        let spindle_change = matches!(b.m, Some(3) | Some(4))
            || (b.s.is_some() && self.spindle != 0 && !matches!(b.m, Some(5) | Some(30)));
        if spindle_change {
            pre += self.settings.spindle_ns;
        }
        self.just_completed = false;
        self.last_entry = Some(e.clone());
        self.current = Some(Current {
            entry: e,
            block: b,
            phase: Phase::PreAux,
            until: self.now + pre,
            motion: None,
        });
    }

    /// PGEN up to `end`: the block's phases, then any jog.
    fn pgen(&mut self, end: u64) {
        while let Some(c) = &mut self.current {
            match c.phase {
                Phase::PreAux => {
                    if c.until >= end {
                        break;
                    }
                    let t0 = c.until;
                    let b = c.block.clone();
                    self.pre_effects(&b);
                    let motion = match b.motion {
                        Kind::Rapid => Some(Motion::linear(
                            b.delta,
                            speed_pulses_ns(self.settings.rapid_mm_min, self.settings.pulse_mm),
                            self.accel,
                            t0,
                        )),
                        Kind::Linear => Some(Motion::linear(
                            b.delta,
                            self.feed_speed(b.feed),
                            self.accel,
                            t0,
                        )),
                        Kind::ArcCw | Kind::ArcCcw => arc_stepper(&b)
                            .ok()
                            .map(|st| Motion::arc(st, self.feed_speed(b.feed), self.accel, t0)),
                        Kind::Dwell | Kind::Aux => None,
                    };
                    let Some(c) = &mut self.current else { break };
                    c.phase = Phase::Move;
                    c.until = t0
                        + if b.motion == Kind::Dwell {
                            b.dwell_ns
                        } else {
                            0
                        };
                    c.motion = motion.map(|mut m| {
                        m.set_hold(self.hold);
                        m
                    });
                }
                Phase::Move => {
                    if let Some(m) = &mut c.motion {
                        match m.run(end, &mut self.out) {
                            Progress::Done => {
                                c.until = c.until.max(m.last_t());
                            }
                            Progress::Pending | Progress::AtRest => break,
                        }
                    } else if c.until >= end {
                        break;
                    }
                    let b = &c.block;
                    let post = match b.m {
                        Some(5) | Some(30) if self.spindle != 0 => self.settings.spindle_ns,
                        _ => 0,
                    };
                    c.until += post;
                    c.phase = Phase::PostAux;
                    c.motion = None;
                }
                Phase::PostAux => {
                    if c.until >= end {
                        break;
                    }
                    let t = c.until;
                    let m = c.block.m;
                    self.current = None;
                    self.finish_block(t, m);
                }
            }
        }
        if let Some(j) = &mut self.jog {
            let p = j.motion.run(end, &mut self.out);
            if p == Progress::Done || (p == Progress::AtRest && j.release) {
                self.jog = None;
                self.out.flush();
                self.send_position();
                self.next_increment();
            }
        }
    }

    fn pre_effects(&mut self, b: &Block) {
        if let Some(t) = b.t {
            self.selected_t = Some(t);
        }
        if let Some(s) = b.s {
            self.s_rpm = s;
        }
        match b.m {
            Some(6) => {
                self.tool = self.selected_t;
                self.tool_len = self
                    .tool
                    .and_then(|t| self.magazine.as_ref()?.tools.get(t))
                    .map(|r| r.set_length)
                    .unwrap_or(0.0);
            }
            Some(3) => self.spindle = i64::from(self.s_rpm),
            Some(4) => self.spindle = -i64::from(self.s_rpm),
            _ => {
                if b.s.is_some() && self.spindle != 0 {
                    self.spindle = self.spindle.signum() * i64::from(self.s_rpm);
                }
            }
        }
    }

    fn finish_block(&mut self, t: u64, m: Option<u8>) {
        if matches!(m, Some(5) | Some(30)) {
            self.spindle = 0;
        }
        self.blocks_done += 1;
        self.just_completed = true;
        self.out.flush();
        if let Some(s) = &self.events {
            send_ev(
                s,
                &self.out.lossless,
                Event::Position {
                    t_ns: t,
                    pulses: self.out.pos,
                },
            );
        }
        if m == Some(30) {
            self.run = 0;
            self.program_end = true;
            self.just_completed = false;
        }
    }
}
