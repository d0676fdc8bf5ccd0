//! One lockstep tick (docs/lathe-sim.md "The tick"): each channel in order 0, 1, 2, … updates
//! its spindle and encoder, then runs its program steps: instant steps (spindle, tool, a queue
//! point that is free) go on within the tick, a motion or dwell takes the tick. The queue points
//! (receive, delivery, waiting M codes) and the checks before a block live here.

use super::motion::{arc, Move, Path, ThreadMove};
use super::{ChState, Event, Exec, Lathe, Run, WaitOn};
use crate::lathe::ops::{Feed, Op, SpeedMode, SpindleDir};

/// Steps one channel may run within one tick (instant steps); a program of nothing but
/// instant steps cannot spin a tick forever.
const MAX_STEPS_PER_TICK: usize = 64;

/// Whether a step handler lets the channel go on within this tick.
pub(super) enum Flow {
    /// Go on with the next step within this tick.
    Next,
    /// The channel is done for this tick.
    Yield,
}

/// The operation's name in events.
fn op_name(op: &Op) -> &'static str {
    match op {
        Op::Rapid { .. } => "rapid",
        Op::Line { .. } => "line",
        Op::Arc { .. } => "arc",
        Op::Thread { .. } => "thread",
        Op::Dwell { .. } => "dwell",
        Op::Spindle { .. } => "spindle",
        Op::Tool { .. } => "tool",
        Op::Wait { .. } => "wait",
        Op::ChuckClose => "chuck close",
        Op::ChuckOpen => "chuck open",
        Op::Stop { .. } => "stop",
        Op::End { .. } => "end",
    }
}

impl Lathe {
    /// One lockstep tick of `desc.tick_ns` for every channel.
    pub fn tick(&mut self) {
        self.busy = false;
        self.t += self.desc.tick_ns;
        self.ticks += 1;
        let dt = self.desc.tick_ns as f64 * 1e-9;
        for i in 0..self.chans.len() {
            self.spindle(i, dt);
            self.chans[i].waits = None;
            for _ in 0..MAX_STEPS_PER_TICK {
                if self.chans[i].run != Run::Active {
                    break;
                }
                if let Flow::Yield = self.advance(i, dt) {
                    break;
                }
            }
            self.after(i);
        }
    }

    /// The spindle speed the channel's command asks for now, rpm (G96: from the tip's X).
    fn target_rpm(&self, i: usize) -> f64 {
        let c = &self.chans[i];
        let d = &self.desc.channels[i];
        if c.run != Run::Active || c.sp.dir == SpindleDir::Stop {
            return 0.0;
        }
        let rpm = match c.sp.mode {
            SpeedMode::Rpm(s) => s,
            SpeedMode::Css {
                m_per_min,
                limit_rpm,
            } => {
                let r_mm = c.pos[0].unsigned_abs() as f64 * self.desc.pulse_mm;
                let css = if r_mm > 1e-9 {
                    1000.0 * m_per_min / (std::f64::consts::TAU * r_mm)
                } else {
                    f64::INFINITY
                };
                css.min(limit_rpm)
            }
        };
        rpm.min(d.max_rpm).max(0.0)
    }

    /// True when the spindle turns at its commanded speed (within 1 %, at least 1 rpm).
    fn at_speed(&self, i: usize) -> bool {
        let target = self.target_rpm(i);
        target > 0.0 && (self.chans[i].sp.rpm - target).abs() <= (0.01 * target).max(1.0)
    }

    /// Ramps the spindle towards its target at `spindle_accel` and turns the encoder.
    fn spindle(&mut self, i: usize, dt: f64) {
        let target = self.target_rpm(i);
        let d = &self.desc.channels[i];
        let step = d.spindle_accel.max(0.0) * dt;
        let lines = f64::from(d.encoder);
        let c = &mut self.chans[i];
        if matches!(c.run, Run::Fault(_) | Run::Estop) {
            c.sp.rpm = 0.0;
        }
        let old = c.sp.rpm;
        c.sp.rpm = if old < target {
            (old + step).min(target)
        } else {
            (old - step).max(target)
        };
        if c.sp.rpm != old {
            self.busy = true;
        }
        c.sp.frac += c.sp.rpm / 60.0 * lines * dt;
        let whole = c.sp.frac.floor();
        c.sp.enc += whole as u64;
        c.sp.frac -= whole;
    }

    /// Ends the current step and goes to the next.
    pub(super) fn finish(&mut self, i: usize) {
        let c = &mut self.chans[i];
        c.pc += 1;
        c.exec = Exec::Fresh;
        self.busy = true;
    }

    /// Raises an alarm on channel `i` before its current step: nothing moves.
    pub(super) fn alarm(&mut self, i: usize, msg: String) -> Flow {
        let c = &mut self.chans[i];
        c.exec = Exec::Fresh;
        c.run = Run::Alarm(msg.clone());
        c.speed = 0.0;
        self.busy = true;
        if self.record {
            let line = c.prog.steps.get(c.pc).map_or(0, |s| s.line);
            self.events.push(Event::Alarm {
                ch: i,
                t: self.t,
                line,
                msg,
            });
        }
        Flow::Yield
    }

    /// Runs the current step of channel `i` for this tick.
    fn advance(&mut self, i: usize, dt: f64) -> Flow {
        let exec = std::mem::replace(&mut self.chans[i].exec, Exec::Fresh);
        let held = self.chans[i].held;
        match exec {
            Exec::Fresh if held => Flow::Yield,
            Exec::Fresh => self.begin(i),
            Exec::Move { mv, feed } => self.run_move(i, mv, feed, dt),
            Exec::Thread(th) => self.run_thread(i, th),
            Exec::Dwell(ns) => {
                if held {
                    self.chans[i].exec = Exec::Dwell(ns);
                    return Flow::Yield;
                }
                self.busy = true;
                if ns <= self.desc.tick_ns {
                    self.finish(i);
                } else {
                    self.chans[i].exec = Exec::Dwell(ns - self.desc.tick_ns);
                }
                Flow::Yield
            }
            Exec::RecvOffer if held => {
                self.chans[i].exec = Exec::RecvOffer;
                Flow::Yield
            }
            Exec::RecvOffer => self.recv_offer(i),
            Exec::RecvRelease { from, work } => {
                if self.chans[from].work == Some(work) {
                    self.chans[i].waits = Some(WaitOn::Channel(from));
                    self.chans[i].exec = Exec::RecvRelease { from, work };
                    return Flow::Yield;
                }
                self.finish(i);
                Flow::Next
            }
            Exec::Deliver if held => {
                self.chans[i].exec = Exec::Deliver;
                Flow::Yield
            }
            Exec::Deliver => self.deliver(i),
            Exec::Wait { m, with, n } => {
                for c in 0..self.chans.len() {
                    if with & (1 << c) != 0 && self.chans[c].arrived(m) < n {
                        self.chans[i].waits = Some(WaitOn::Channel(c));
                        self.chans[i].exec = Exec::Wait { m, with, n };
                        return Flow::Yield;
                    }
                }
                if held {
                    self.chans[i].exec = Exec::Wait { m, with, n };
                    return Flow::Yield;
                }
                self.finish(i);
                Flow::Next
            }
        }
    }

    /// Begins the step at the program counter: the checks before any pulse, then its work.
    fn begin(&mut self, i: usize) -> Flow {
        let c = &self.chans[i];
        let Some(step) = c.prog.steps.get(c.pc) else {
            // Ran off the end without M02/M30: the channel has finished.
            self.chans[i].run = Run::Done;
            self.busy = true;
            return Flow::Yield;
        };
        let (line, op) = (step.line, step.op.clone());
        self.busy = true;
        self.chans[i].stats.blocks += 1;
        if self.record {
            self.events.push(Event::Block {
                ch: i,
                t: self.t,
                line,
                op: op_name(&op),
            });
        }
        if op.cuts() {
            if let Some(msg) = self.check_cut(i, &op) {
                return self.alarm(i, msg);
            }
        }
        let pos = self.chans[i].pos;
        match op {
            Op::Rapid { end } => self.begin_move(i, Path::Line { start: pos, end }, None),
            Op::Line { end, feed } => {
                self.begin_move(i, Path::Line { start: pos, end }, Some(feed))
            }
            Op::Arc {
                end,
                centre,
                ccw,
                feed,
            } => match arc(pos, end, centre, ccw, 3.0) {
                Ok(path) => self.begin_move(i, path, Some(feed)),
                Err(msg) => self.alarm(i, msg),
            },
            Op::Thread { end, lead } => {
                if let Some(msg) = self.check_travel(i, &[pos, end]) {
                    return self.alarm(i, msg);
                }
                if lead.is_nan() || lead <= 0.0 {
                    return self.alarm(i, format!("thread: lead {lead} mm is not positive"));
                }
                self.cut_started(i, line);
                let major = (end[0] - pos[0]).abs().max((end[1] - pos[1]).abs()) as f64;
                self.chans[i].exec = Exec::Thread(ThreadMove {
                    start: pos,
                    end,
                    major,
                    lead: lead / self.desc.pulse_mm,
                    done: 0,
                    anchor: None,
                    synced: false,
                    started: false,
                });
                Flow::Next
            }
            Op::Dwell { ns } => {
                self.chans[i].exec = Exec::Dwell(ns);
                Flow::Next
            }
            Op::Spindle { dir, mode } => {
                let sp = &mut self.chans[i].sp;
                sp.dir = dir;
                sp.mode = mode;
                self.finish(i);
                Flow::Next
            }
            Op::Tool { tool } => {
                if tool != 0 && self.desc.channels[i].tool(tool).is_none() {
                    return self.alarm(i, format!("T{tool}: no such tool on the tool post"));
                }
                self.chans[i].tool = tool;
                self.finish(i);
                Flow::Next
            }
            Op::Wait { m, with } => {
                let c = &mut self.chans[i];
                let n = match c.arrivals.iter_mut().find(|a| a.0 == m) {
                    Some(a) => {
                        a.1 += 1;
                        a.1
                    }
                    None => {
                        c.arrivals.push((m, 1));
                        1
                    }
                };
                c.exec = Exec::Wait { m, with, n };
                Flow::Next
            }
            Op::ChuckClose => {
                if self.chans[i].work.is_none() {
                    self.chans[i].exec = Exec::RecvOffer;
                } else {
                    self.chans[i].closed = true;
                    self.finish(i);
                }
                Flow::Next
            }
            Op::ChuckOpen => {
                if self.chans[i].work.is_some() {
                    self.chans[i].exec = Exec::Deliver;
                } else {
                    self.chans[i].closed = false;
                    self.finish(i);
                }
                Flow::Next
            }
            Op::Stop { optional } => {
                self.finish(i);
                if !optional || self.optional_stop {
                    let why = if optional { "M01" } else { "M00" };
                    self.chans[i].run = Run::Stopped(why.to_string());
                    return Flow::Yield;
                }
                Flow::Next
            }
            Op::End { .. } => {
                let target = self.target;
                let c = &mut self.chans[i];
                c.parts += 1;
                let count = c.parts;
                if count >= target {
                    c.run = Run::Done;
                } else {
                    c.pc = 0;
                    c.exec = Exec::Fresh;
                    c.cycle_cut = None;
                    c.cycle_arrivals = c.arrivals.clone();
                }
                if self.record {
                    self.events.push(Event::Part {
                        ch: i,
                        t: self.t,
                        count,
                    });
                }
                Flow::Yield
            }
        }
    }

    /// The checks before a cutting block: a work in the spindle, the spindle turning.
    fn check_cut(&mut self, i: usize, op: &Op) -> Option<String> {
        let c = &self.chans[i];
        if c.work.is_none() {
            self.empty_cut_alarms += 1;
            return Some(format!(
                "{}: a machining block on an empty spindle (no work in CH{})",
                op_name(op),
                i + 1
            ));
        }
        if c.sp.dir == SpindleDir::Stop {
            return Some(format!("{}: the spindle is stopped", op_name(op)));
        }
        if let Op::Line { feed, .. } | Op::Arc { feed, .. } = op {
            let (Feed::PerMin(f) | Feed::PerRev(f)) = *feed;
            if !f.is_finite() || f <= 0.0 {
                return Some(format!("{}: feed {f} is not positive", op_name(op)));
            }
        }
        None
    }

    /// A travel alarm if any of `pts` is outside the channel's travel.
    fn check_travel(&self, i: usize, pts: &[[i64; 2]]) -> Option<String> {
        let axes = &self.desc.channels[i].axes;
        for p in pts {
            for (k, name) in ["X", "Z"].iter().enumerate() {
                let lo = self.desc.pulses(axes[k].travel[0]);
                let hi = self.desc.pulses(axes[k].travel[1]);
                if p[k] < lo || p[k] > hi {
                    return Some(format!(
                        "travel: {name} {:.3} mm is outside {:.3} to {:.3} mm",
                        p[k] as f64 * self.desc.pulse_mm,
                        axes[k].travel[0],
                        axes[k].travel[1]
                    ));
                }
            }
        }
        None
    }

    /// Records a cutting block's start and which work it machines.
    fn cut_started(&mut self, i: usize, line: u32) {
        let c = &mut self.chans[i];
        let work = c.work;
        if let Some(w) = work {
            if c.cycle_cut != Some(w) {
                c.cycle_cut = Some(w);
                let idx = (w as usize).saturating_sub(1);
                if self.machined.len() <= idx {
                    self.machined.resize(idx + 1, Vec::new());
                }
                let row = &mut self.machined[idx];
                if row.len() < self.chans.len() {
                    row.resize(self.chans.len(), 0);
                }
                row[i] += 1;
            }
        }
        if self.record {
            self.events.push(Event::CutStart {
                ch: i,
                t: self.t,
                line,
                work,
            });
        }
    }

    /// Begins a path move after the travel check.
    fn begin_move(&mut self, i: usize, path: Path, feed: Option<Feed>) -> Flow {
        let start = self.chans[i].pos;
        if let Some(msg) = self.check_travel(i, &path.extremes(start)) {
            return self.alarm(i, msg);
        }
        if feed.is_some() {
            let line = self.chans[i]
                .prog
                .steps
                .get(self.chans[i].pc)
                .map_or(0, |s| s.line);
            self.cut_started(i, line);
        }
        let mv = Move::new(path, start, &self.desc.channels[i].axes, &self.desc);
        self.chans[i].exec = Exec::Move { mv, feed };
        Flow::Next
    }

    /// One tick of a path move.
    fn run_move(&mut self, i: usize, mut mv: Move, feed: Option<Feed>, dt: f64) -> Flow {
        let held = self.chans[i].held;
        if feed.is_some() && !held && mv.v == 0.0 && !self.at_speed(i) {
            // A feed move starts (or resumes) only with the spindle at speed.
            self.chans[i].waits = Some(WaitOn::Spindle);
            self.chans[i].exec = Exec::Move { mv, feed };
            return Flow::Yield;
        }
        let per_s = 1.0 / (60.0 * self.desc.pulse_mm);
        let vmax = if held {
            0.0
        } else {
            let ovr = f64::from(self.feed_override) / 100.0;
            match feed {
                None => f64::INFINITY,
                Some(Feed::PerMin(f)) => f * per_s * ovr,
                Some(Feed::PerRev(f)) => f * self.chans[i].sp.rpm * per_s * ovr,
            }
        };
        let moving = mv.v > 0.0;
        let c = &mut self.chans[i];
        let old = c.pos;
        let (p, done) = mv.step(vmax, dt);
        c.stats.pulses[0] += (p[0] - old[0]).unsigned_abs();
        c.stats.pulses[1] += (p[1] - old[1]).unsigned_abs();
        c.pos = p;
        c.speed = mv.v * self.desc.pulse_mm * 60.0;
        if moving || mv.v > 0.0 || done {
            self.busy = true;
        }
        if done {
            c.speed = 0.0;
            self.sample(i);
            self.finish(i);
        } else {
            self.chans[i].exec = Exec::Move { mv, feed };
        }
        Flow::Yield
    }

    /// One tick of a thread pass: synchronise to the index, then follow the encoder.
    fn run_thread(&mut self, i: usize, mut th: ThreadMove) -> Flow {
        let lines = self.desc.channels[i].encoder;
        let held = self.chans[i].held;
        let Some(anchor) = th.anchor else {
            // A pass not yet (re)synchronised holds at a feed hold, and waits for the speed.
            if held {
                self.chans[i].exec = Exec::Thread(th);
                return Flow::Yield;
            }
            if !self.at_speed(i) {
                self.chans[i].waits = Some(WaitOn::Spindle);
                self.chans[i].exec = Exec::Thread(th);
                return Flow::Yield;
            }
            th.anchor = Some(th.next_anchor(self.chans[i].sp.enc, lines));
            self.busy = true;
            return self.run_thread(i, th);
        };
        let enc = self.chans[i].sp.enc;
        if held && !th.synced {
            // A feed hold before the pass moves: it waits, and synchronises afresh after.
            th.anchor = None;
            self.chans[i].exec = Exec::Thread(th);
            return Flow::Yield;
        }
        self.busy = true;
        if enc < anchor + th.done {
            self.chans[i].waits = Some(WaitOn::Index);
            self.chans[i].exec = Exec::Thread(th);
            return Flow::Yield;
        }
        if !th.synced {
            th.synced = true;
            if self.record {
                let line = self.chans[i]
                    .prog
                    .steps
                    .get(self.chans[i].pc)
                    .map_or(0, |s| s.line);
                self.events.push(Event::ThreadPass {
                    ch: i,
                    t: self.t,
                    line,
                    index: anchor,
                    encoder: enc,
                    resumed: th.started,
                });
            }
            th.started = true;
        }
        th.done = enc - anchor;
        let (p, fin) = th.at(th.done, lines);
        let c = &mut self.chans[i];
        let old = c.pos;
        c.stats.pulses[0] += (p[0] - old[0]).unsigned_abs();
        c.stats.pulses[1] += (p[1] - old[1]).unsigned_abs();
        c.pos = p;
        c.speed = th.lead * self.desc.pulse_mm * c.sp.rpm;
        if fin {
            c.speed = 0.0;
            self.sample(i);
            self.finish(i);
        } else {
            self.chans[i].exec = Exec::Thread(th);
        }
        Flow::Yield
    }

    /// Records a position sample of channel `i` now.
    fn sample(&mut self, i: usize) {
        let c = &mut self.chans[i];
        c.last_sample = (self.t, c.pos, c.sp.rpm);
        if self.record {
            self.events.push(Event::Sample {
                ch: i,
                t: self.t,
                pos: c.pos,
                rpm: c.sp.rpm,
                speed: c.speed,
            });
        }
    }

    /// After a channel's tick: its state change and its periodic sample.
    fn after(&mut self, i: usize) {
        let c = &self.chans[i];
        let now = (c.state(), c.waits);
        // A thread waiting on the index or a cut on the spindle is still RUN: no event.
        let now = match now {
            (ChState::Run, _) => (ChState::Run, None),
            other => other,
        };
        if now != c.last_state {
            self.chans[i].last_state = now;
            if self.record {
                self.events.push(Event::State {
                    ch: i,
                    t: self.t,
                    state: now.0,
                    waits_on: now.1,
                });
            }
        }
        let c = &self.chans[i];
        if self.record
            && self.sample_ns > 0
            && self.t - c.last_sample.0 >= self.sample_ns
            && (c.pos != c.last_sample.1 || c.sp.rpm != c.last_sample.2)
        {
            self.sample(i);
        }
    }
}
