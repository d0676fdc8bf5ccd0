//! The lockstep lathe channel simulator (docs/lathe-sim.md): one `LatheProgram` per channel of
//! a `LatheDesc`, all advanced by one tick of `desc.tick_ns` in one thread, so machine time is
//! virtual and deterministic (seed 004: three systems, receive / machining / delivery blocks,
//! queueing, part counter, faults, lines 136–142, 288–304, 330–378).
//!
//! - [`Lathe`]: the machine; operator commands, status, outcome and statistics.
//! - `types`: the public status, event, outcome and statistics types.
//! - `exec`: one tick: each channel's spindle and program steps, the checks before a block.
//! - `queue`: the queue points receive (M10) and delivery (M11); waiting M codes are in `exec`.
//! - `motion`: a block's motion (trapezoid along a line or arc; thread passes on the encoder).

mod exec;
mod motion;
mod queue;
pub mod testkit;
#[cfg(test)]
mod tests;
mod types;

use crate::lathe::desc::LatheDesc;
use crate::lathe::ops::{Feed, LatheProgram, Op, SpeedMode, SpindleDir};
use motion::{Move, ThreadMove};
pub use types::{ChState, ChannelStats, ChannelStatus, Event, Outcome, Stats, WaitOn};

/// How a channel runs (the operator's view, before queue points).
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Run {
    Idle,
    Active,
    Stopped(String),
    Fault(String),
    Alarm(String),
    Estop,
    Done,
}

/// What the current step is doing.
#[derive(Clone, Debug)]
pub(crate) enum Exec {
    /// Not begun.
    Fresh,
    /// A path move; `feed` None for a rapid (not a cut).
    Move { mv: Move, feed: Option<Feed> },
    /// A thread pass.
    Thread(ThreadMove),
    /// A dwell, ns left.
    Dwell(u64),
    /// A receive: waiting for an offer.
    RecvOffer,
    /// A receive: closed on `work`, waiting for channel `from` to let go.
    RecvRelease { from: usize, work: u32 },
    /// A delivery: waiting for the receiver to close.
    Deliver,
    /// A waiting M code: this channel's `n`-th arrival at `m`.
    Wait { m: u32, with: u8, n: u64 },
}

/// The spindle of a channel.
#[derive(Clone, Debug)]
pub(crate) struct Spindle {
    pub dir: SpindleDir,
    pub mode: SpeedMode,
    pub rpm: f64,
    pub enc: u64,
    pub frac: f64,
}

/// One channel's whole state.
#[derive(Clone, Debug)]
pub(crate) struct Chan {
    pub prog: LatheProgram,
    pub pc: usize,
    pub run: Run,
    pub held: bool,
    pub exec: Exec,
    pub pos: [i64; 2],
    pub sp: Spindle,
    pub tool: u32,
    pub work: Option<u32>,
    pub closed: bool,
    pub parts: u32,
    pub waits: Option<WaitOn>,
    /// Arrivals per waiting M code (m, count).
    pub arrivals: Vec<(u32, u64)>,
    /// The arrivals when the current cycle began (RESET after an E-STOP returns to them).
    pub cycle_arrivals: Vec<(u32, u64)>,
    /// The work this channel cut in its current cycle (for the machined-twice check).
    pub cycle_cut: Option<u32>,
    pub stats: ChannelStats,
    pub last_state: (ChState, Option<WaitOn>),
    pub last_sample: (u64, [i64; 2], f64),
    pub speed: f64,
}

impl Chan {
    /// Arrivals of this channel at waiting code `m`.
    pub(crate) fn arrived(&self, m: u32) -> u64 {
        self.arrivals.iter().find(|a| a.0 == m).map_or(0, |a| a.1)
    }

    /// The state the display shows.
    pub(crate) fn state(&self) -> ChState {
        match &self.run {
            Run::Idle => ChState::Idle,
            Run::Stopped(_) => ChState::Stop,
            Run::Fault(_) => ChState::Fault,
            Run::Alarm(_) => ChState::Alarm,
            Run::Estop => ChState::Estop,
            Run::Done => ChState::Done,
            Run::Active if self.held => ChState::Hold,
            Run::Active => match self.waits {
                Some(WaitOn::Channel(_)) | Some(WaitOn::BarFeeder) => ChState::Wait,
                _ => ChState::Run,
            },
        }
    }

    /// Stops the axes and the spindle at once (fault, E-STOP); the step keeps its place.
    pub(crate) fn stop_now(&mut self) {
        self.sp.rpm = 0.0;
        self.speed = 0.0;
        match &mut self.exec {
            Exec::Move { mv, .. } => mv.v = 0.0,
            Exec::Thread(th) => {
                th.anchor = None;
                th.synced = false;
            }
            _ => {}
        }
    }
}

/// The lathe: every channel, the bar feeder, the unloader and the work log.
#[derive(Clone, Debug)]
pub struct Lathe {
    pub(crate) desc: LatheDesc,
    pub(crate) chans: Vec<Chan>,
    pub(crate) t: u64,
    pub(crate) ticks: u64,
    pub(crate) target: u32,
    pub(crate) supplied: u32,
    pub(crate) delivered: u32,
    pub(crate) empty_cut_alarms: u32,
    /// Per work id (index id-1): how many cycles each channel machined it.
    pub(crate) machined: Vec<Vec<u32>>,
    pub(crate) events: Vec<Event>,
    pub(crate) record: bool,
    pub(crate) sample_ns: u64,
    pub(crate) optional_stop: bool,
    /// Feed override, percent of the programmed feed (not rapids, not threads).
    pub(crate) feed_override: u32,
    /// Set by a tick when anything changed or moved.
    pub(crate) busy: bool,
}

impl Lathe {
    /// A lathe running `programs[i]` on channel i of `desc`, to `target_parts` parts.
    /// Errors: a program count other than the channel count, or a description the simulator
    /// cannot run (no channels, zero tick or pulse, a channel number out of range).
    pub fn new(
        desc: LatheDesc,
        programs: Vec<LatheProgram>,
        target_parts: u32,
    ) -> Result<Lathe, String> {
        let n = desc.channels.len();
        if n == 0 || n > 8 {
            return Err(format!("the machine has {n} channels; 1 to 8 are allowed"));
        }
        if programs.len() != n {
            return Err(format!(
                "{} programs for {n} channels: give one program per channel",
                programs.len()
            ));
        }
        if desc.tick_ns == 0 || desc.pulse_mm.is_nan() || desc.pulse_mm <= 0.0 {
            return Err("the tick and the pulse size must be positive".to_string());
        }
        if desc.supplier >= n || desc.unloader >= n {
            return Err("the supplier or unloader channel is not a channel".to_string());
        }
        if desc
            .transfers
            .iter()
            .any(|t| t.0 >= n || t.1 >= n || t.0 == t.1)
        {
            return Err("a transfer names a channel the machine has not".to_string());
        }
        for (i, p) in programs.iter().enumerate() {
            for s in &p.steps {
                if let Op::Wait { m, with } = s.op {
                    if u32::from(with) >> n != 0 {
                        return Err(format!(
                            "{} line {}: M{m} waits with a channel the machine has not",
                            p.name, s.line
                        ));
                    }
                    if with & (1 << i) == 0 {
                        return Err(format!(
                            "{} line {}: M{m} must list its own channel {}",
                            p.name,
                            s.line,
                            i + 1
                        ));
                    }
                }
            }
        }
        let chans = programs
            .into_iter()
            .map(|prog| Chan {
                prog,
                pc: 0,
                run: Run::Idle,
                held: false,
                exec: Exec::Fresh,
                pos: [0, 0],
                sp: Spindle {
                    dir: SpindleDir::Stop,
                    mode: SpeedMode::Rpm(0.0),
                    rpm: 0.0,
                    enc: 0,
                    frac: 0.0,
                },
                tool: 0,
                work: None,
                closed: false,
                parts: 0,
                waits: None,
                arrivals: Vec::new(),
                cycle_arrivals: Vec::new(),
                cycle_cut: None,
                stats: ChannelStats::default(),
                last_state: (ChState::Idle, None),
                last_sample: (0, [0, 0], 0.0),
                speed: 0.0,
            })
            .collect();
        Ok(Lathe {
            desc,
            chans,
            t: 0,
            ticks: 0,
            target: target_parts,
            supplied: 0,
            delivered: 0,
            empty_cut_alarms: 0,
            machined: Vec::new(),
            events: Vec::new(),
            record: true,
            sample_ns: 1_000_000,
            optional_stop: false,
            feed_override: 100,
            busy: false,
        })
    }

    /// Sets every channel's starting tool tip position (default [0, 0]), before START.
    pub fn set_position(&mut self, ch: usize, pos: [i64; 2]) -> Result<(), String> {
        let c = self.chans.get_mut(ch).ok_or_else(|| no_channel(ch))?;
        if c.run != Run::Idle {
            return Err(format!(
                "CH{} has started: its position is the run's",
                ch + 1
            ));
        }
        c.pos = pos;
        Ok(())
    }

    /// Turns event recording on or off (on by default) and sets the sample period (ns; 0 =
    /// only at block ends).
    pub fn set_recording(&mut self, on: bool, sample_ns: u64) {
        self.record = on;
        self.sample_ns = sample_ns;
    }

    /// OPTIONAL STOP: whether M01 stops (off by default).
    pub fn set_optional_stop(&mut self, on: bool) {
        self.optional_stop = on;
    }

    /// FEED OVERRIDE, percent (0 to 200, default 100) of the programmed feed of Line and Arc
    /// blocks; rapids and thread passes (which follow the spindle) are not overridden.
    pub fn set_feed_override(&mut self, pct: u32) -> Result<(), String> {
        if pct > 200 {
            return Err(format!("feed override {pct} %: 0 to 200 %"));
        }
        self.feed_override = pct;
        Ok(())
    }

    /// Replaces channel `ch`'s program (an MDI buffer, an edited program) and puts it at its
    /// first step, IDLE, keeping its work, chuck, spindle command, position and count. Only
    /// between blocks of a channel that is idle, stopped or done.
    pub fn load(&mut self, ch: usize, prog: LatheProgram) -> Result<(), String> {
        let c = self.chans.get_mut(ch).ok_or_else(|| no_channel(ch))?;
        if !matches!(c.run, Run::Idle | Run::Stopped(_) | Run::Done) {
            return Err(format!("CH{} is {}: stop it first", ch + 1, c.state()));
        }
        if !matches!(c.exec, Exec::Fresh) {
            return Err(format!("CH{} is inside a block: finish it first", ch + 1));
        }
        for s in &prog.steps {
            if let Op::Wait { m, with } = s.op {
                if u32::from(with) >> self.chans.len() != 0 || with & (1 << ch) == 0 {
                    return Err(format!(
                        "line {}: M{m} must list channel {} and only channels the machine has",
                        s.line,
                        ch + 1
                    ));
                }
            }
        }
        let c = &mut self.chans[ch];
        c.prog = prog;
        c.pc = 0;
        c.run = Run::Idle;
        c.held = false;
        Ok(())
    }

    /// START of channel `ch` alone (MDI): begins or resumes it if idle or stopped, ends its
    /// hold.
    pub fn start_channel(&mut self, ch: usize) -> Result<(), String> {
        let c = self.chans.get_mut(ch).ok_or_else(|| no_channel(ch))?;
        c.held = false;
        if matches!(c.run, Run::Idle | Run::Stopped(_)) {
            c.run = Run::Active;
        }
        Ok(())
    }

    /// RESET of every channel (the machine's RESET after an E-STOP).
    pub fn reset_all(&mut self) {
        for ch in 0..self.chans.len() {
            let _ = self.reset(ch);
        }
    }

    /// True if any channel is in E-STOP.
    pub fn estopped(&self) -> bool {
        self.chans.iter().any(|c| c.run == Run::Estop)
    }

    /// The channels channel `ch` waits for now (see [`ChannelStatus::waits_for`]).
    fn waits_for(&self, ch: usize) -> Vec<usize> {
        let c = &self.chans[ch];
        match (&c.exec, c.waits) {
            (&Exec::Wait { m, with, n }, Some(WaitOn::Channel(_))) => (0..self.chans.len())
                .filter(|&o| with & (1 << o) != 0 && self.chans[o].arrived(m) < n)
                .collect(),
            (_, Some(WaitOn::Channel(o))) => vec![o],
            _ => Vec::new(),
        }
    }

    /// START: begins an idle run, resumes every stopped channel (M00, after RESET) and ends
    /// a feed hold. Faulted, alarmed and E-stopped channels need RESET first.
    pub fn start(&mut self) {
        for c in &mut self.chans {
            c.held = false;
            if matches!(c.run, Run::Idle | Run::Stopped(_)) {
                c.run = Run::Active;
            }
        }
    }

    /// FEED HOLD on every channel: moves slow to a stop on their path (a thread pass runs to
    /// its end first), no new block starts; START resumes.
    pub fn hold(&mut self) {
        for c in &mut self.chans {
            if c.run == Run::Active {
                c.held = true;
            }
        }
    }

    /// RESET of channel `ch`: clears a fault or an alarm, keeping the place in the program (the
    /// channel then stands stopped until START). After an E-STOP the run is abandoned: the
    /// channel returns to the start of its program with its spindle stopped, keeping the work
    /// its chuck holds, its position and its part count; START begins a new cycle there, no
    /// interrupted block is resumed (docs/lathe.md "E-STOP"). No effect on other states.
    pub fn reset(&mut self, ch: usize) -> Result<(), String> {
        let c = self.chans.get_mut(ch).ok_or_else(|| no_channel(ch))?;
        if c.run == Run::Estop {
            c.pc = 0;
            c.exec = Exec::Fresh;
            c.waits = None;
            c.arrivals = c.cycle_arrivals.clone();
            c.sp.dir = SpindleDir::Stop;
            c.stop_now();
            c.run = Run::Stopped("reset".to_string());
            c.held = false;
            return Ok(());
        }
        if matches!(c.run, Run::Fault(_) | Run::Alarm(_)) {
            c.run = Run::Stopped("reset".to_string());
            c.held = false;
        }
        Ok(())
    }

    /// E-STOP: every channel stops at once, axes and spindles, until RESET.
    pub fn estop(&mut self) {
        for c in &mut self.chans {
            if c.run != Run::Done {
                c.run = Run::Estop;
                c.held = false;
            }
            c.stop_now();
        }
    }

    /// Injects a fault into channel `ch` (tool breakage, failed supply): it stops at once,
    /// axes and spindle. A finished channel cannot fault.
    pub fn fault(&mut self, ch: usize, reason: &str) -> Result<(), String> {
        let t = self.t;
        let c = self.chans.get_mut(ch).ok_or_else(|| no_channel(ch))?;
        if c.run == Run::Done {
            return Err(format!("CH{} has finished", ch + 1));
        }
        c.run = Run::Fault(reason.to_string());
        c.held = false;
        c.stop_now();
        if self.record {
            self.events.push(Event::Fault {
                ch,
                t,
                reason: reason.to_string(),
            });
        }
        Ok(())
    }

    /// Sets the part target. Refused (nothing changes) below the works the bar feeder has
    /// already supplied, or once a channel has finished (raising it then would leave the
    /// others waiting on a finished channel).
    pub fn set_target(&mut self, n: u32) -> Result<(), String> {
        if n < self.supplied {
            return Err(format!(
                "target {n}: the bar feeder has already supplied {} works",
                self.supplied
            ));
        }
        if n != self.target && self.chans.iter().any(|c| c.run == Run::Done) {
            return Err(format!("target {n}: a channel has already finished"));
        }
        self.target = n;
        Ok(())
    }

    /// The part target.
    pub fn target(&self) -> u32 {
        self.target
    }

    /// The number of channels.
    pub fn channels(&self) -> usize {
        self.chans.len()
    }

    /// The machine description the lathe runs on.
    pub fn desc(&self) -> &LatheDesc {
        &self.desc
    }

    /// Channel `ch`'s program (its source lines for the display), if there is such a channel.
    pub fn program(&self, ch: usize) -> Option<&LatheProgram> {
        self.chans.get(ch).map(|c| &c.prog)
    }

    /// Channel `ch`'s status, or None if there is no such channel.
    pub fn channel(&self, ch: usize) -> Option<ChannelStatus> {
        let c = self.chans.get(ch)?;
        let reason = match &c.run {
            Run::Fault(r) | Run::Alarm(r) | Run::Stopped(r) => Some(r.clone()),
            _ => None,
        };
        Some(ChannelStatus {
            name: self.desc.channels[ch].name.clone(),
            state: c.state(),
            reason,
            step: c.pc,
            line: c.prog.steps.get(c.pc).map_or(0, |s| s.line),
            pos: c.pos,
            rpm: c.sp.rpm,
            encoder: c.sp.enc,
            work: c.work,
            chuck_closed: c.closed,
            parts: c.parts,
            waits_on: c.waits,
            waits_for: self.waits_for(ch),
            tool: c.tool,
            dir: c.sp.dir,
        })
    }

    /// The summary line: per channel its state, current line, whom it waits on and its count,
    /// e.g. `CH1 RUN N12 5/5 | CH2 WAIT N3 waits CH1 2/5`.
    pub fn summary(&self) -> String {
        let mut parts = Vec::new();
        for ch in 0..self.chans.len() {
            if let Some(s) = self.channel(ch) {
                let mut p = format!("CH{} {} N{}", ch + 1, s.state, s.line);
                if let (ChState::Wait, Some(w)) = (s.state, s.waits_on) {
                    p.push_str(&format!(" waits {w}"));
                }
                p.push_str(&format!(" {}/{}", s.parts, self.target));
                parts.push(p);
            }
        }
        parts.join(" | ")
    }

    /// Machine time, ns.
    pub fn machine_time_ns(&self) -> u64 {
        self.t
    }

    /// Takes the events recorded since the last call.
    pub fn drain_events(&mut self) -> Vec<Event> {
        std::mem::take(&mut self.events)
    }

    /// The run's statistics.
    pub fn stats(&self) -> Stats {
        Stats {
            delivered: self.delivered,
            supplied: self.supplied,
            machine_ns: self.t,
            ticks: self.ticks,
            empty_cut_alarms: self.empty_cut_alarms,
            channels: self
                .chans
                .iter()
                .map(|c| ChannelStats {
                    parts: c.parts,
                    ..c.stats.clone()
                })
                .collect(),
        }
    }

    /// How many cycles each channel machined work `id` (index = channel); empty if the work
    /// was never machined.
    pub fn machined(&self, id: u32) -> Vec<u32> {
        let i = (id as usize).wrapping_sub(1);
        self.machined.get(i).cloned().unwrap_or_default()
    }

    /// Where each work is: (work id, channel holding it), every chuck holding one.
    pub fn works(&self) -> Vec<(u32, usize)> {
        self.chans
            .iter()
            .enumerate()
            .filter_map(|(i, c)| c.work.map(|w| (w, i)))
            .collect()
    }

    /// Runs ticks until every channel has finished, or none can progress without the
    /// operator (a stop, hold, fault, alarm, E-STOP, or a deadlock), or `max_ns` of machine
    /// time has passed.
    pub fn run_until_idle(&mut self, max_ns: u64) -> Outcome {
        let t0 = self.t;
        loop {
            self.tick();
            if !self.busy {
                return self.outcome();
            }
            if self.t - t0 >= max_ns {
                return Outcome::TimeLimit;
            }
        }
    }

    /// What the machine's state means once no channel progresses.
    fn outcome(&self) -> Outcome {
        let runs: Vec<&Run> = self.chans.iter().map(|c| &c.run).collect();
        if runs.iter().all(|r| **r == Run::Done) {
            return Outcome::Finished {
                parts: self.delivered,
            };
        }
        if runs.iter().any(|r| **r == Run::Estop) {
            return Outcome::Estop;
        }
        for (ch, r) in runs.iter().enumerate() {
            if let Run::Fault(reason) = r {
                return Outcome::Fault {
                    ch,
                    reason: reason.clone(),
                };
            }
        }
        for (ch, r) in runs.iter().enumerate() {
            if let Run::Alarm(msg) = r {
                return Outcome::Alarm {
                    ch,
                    msg: msg.clone(),
                };
            }
        }
        if self.feed_override == 0
            || self
                .chans
                .iter()
                .any(|c| c.held || matches!(c.run, Run::Idle | Run::Stopped(_)))
        {
            return Outcome::Stopped;
        }
        let waits = self
            .chans
            .iter()
            .enumerate()
            .filter_map(|(i, c)| c.waits.map(|w| (i, w)))
            .collect();
        Outcome::Deadlock { waits }
    }
}

fn no_channel(ch: usize) -> String {
    format!("no channel {}", ch + 1)
}
