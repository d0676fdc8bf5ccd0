//! The lathe console's cycle: the channel programs read, the simulator running them, and what
//! it reports turned into the display's views and the recording's messages.

use super::view::ChanView;
use crate::lathe::desc::LatheDesc;
use crate::lathe::gcode::{read_program, ReadOptions};
use crate::lathe::ops::LatheProgram;
use crate::lathe::record::{LatheRecorder, StateMsg};
use crate::lathe::sim::{ChState, Event, Lathe};
use crate::store::lathe::Program;

/// Where each channel's tool post starts the first cycle: the top of its travel (X and Z at
/// their maxima), clear of any work, where the reader takes a program to start. Later cycles
/// start where the last one left it.
pub fn home(desc: &LatheDesc, ch: usize) -> [i64; 2] {
    crate::lathe::gcode::home(desc, ch)
}

/// A cycle (AUTO: every channel to the part target) or an MDI run of one channel.
pub struct Cycle {
    /// The machine.
    pub lathe: Lathe,
    /// True for an MDI run of channel `only`.
    pub mdi: bool,
    only: usize,
    started_ns: u64,
    /// Ticks owed: machine time given but less than a tick.
    rest_ns: u64,
    seq: Vec<u32>,
    message: Option<String>,
    /// The source lines of each channel's program, for the block messages.
    lines: Vec<Vec<String>>,
}

impl Cycle {
    /// Reads every channel's program (`texts`: name and text per channel) and makes the
    /// machine, each tool post where `pos` says. Any error names the channel, the program and
    /// the line, and nothing is made.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        desc: &LatheDesc,
        texts: &[(String, String)],
        opts: &ReadOptions,
        target: u32,
        mdi: bool,
        only: usize,
        pos: &[[i64; 2]],
        started_ns: u64,
    ) -> Result<Cycle, String> {
        let mut progs = Vec::new();
        for (ch, (name, text)) in texts.iter().enumerate() {
            if mdi && ch != only {
                continue;
            }
            let p = read_program(name, text, desc, ch, opts)
                .map_err(|e| format!("CH{} {name}:{e}", ch + 1))?;
            if !mdi && p.steps.is_empty() {
                return Err(format!("CH{} {name}: the program is empty", ch + 1));
            }
            progs.push(p);
        }
        let (d, chans): (LatheDesc, Vec<usize>) = if mdi {
            let mut d = desc.clone();
            d.channels = vec![desc.channels[only].clone()];
            d.supplier = 0;
            d.unloader = 0;
            d.transfers.clear();
            (d, vec![only])
        } else {
            (desc.clone(), (0..desc.channels.len()).collect())
        };
        let lines: Vec<Vec<String>> = progs
            .iter()
            .map(|p: &LatheProgram| p.lines.clone())
            .collect();
        let mut lathe = Lathe::new(d, progs, target)?;
        lathe.set_recording(true, 10_000_000);
        lathe.set_optional_stop(opts.optional_stop);
        for (i, &ch) in chans.iter().enumerate() {
            lathe.set_position(i, pos[ch])?;
        }
        lathe.start();
        Ok(Cycle {
            lathe,
            mdi,
            only,
            started_ns,
            rest_ns: 0,
            seq: vec![0; chans.len()],
            message: None,
            lines,
        })
    }

    /// The channel of the console that the machine's channel `i` is.
    fn console_ch(&self, i: usize) -> usize {
        if self.mdi {
            self.only
        } else {
            i
        }
    }

    /// The machine's channel that the console's channel `ch` is, if it runs in this cycle.
    fn machine_ch(&self, ch: usize) -> Option<usize> {
        match self.mdi {
            true if ch == self.only => Some(0),
            true => None,
            false => Some(ch),
        }
    }

    /// When the cycle began, in the console's machine time.
    pub fn started_ns(&self) -> u64 {
        self.started_ns
    }

    /// Every channel finished (AUTO), or the MDI program ran out.
    pub fn is_over(&self) -> bool {
        (0..self.lathe.channels()).all(|i| {
            self.lathe
                .channel(i)
                .is_some_and(|s| s.state == ChState::Done)
        })
    }

    /// Nothing moves or can move without the operator.
    pub fn at_rest(&mut self) -> bool {
        !self.lathe.busy
    }

    /// Advances the machine by `ns` (whole ticks; the remainder is carried).
    pub fn advance(&mut self, ns: u64) {
        let tick = self.lathe.desc.tick_ns.max(1);
        let total = self.rest_ns + ns;
        for _ in 0..total / tick {
            self.lathe.tick();
        }
        self.rest_ns = total % tick;
    }

    /// RESET of the console's channel `ch`: clears its fault or alarm; after an E-STOP, every
    /// channel's, each back at the start of its program (the run is abandoned). Returns the
    /// message.
    pub fn reset(&mut self, ch: usize) -> String {
        let estop = (0..self.lathe.channels()).any(|i| {
            self.lathe
                .channel(i)
                .is_some_and(|s| s.state == ChState::Estop)
        });
        if estop {
            for i in 0..self.lathe.channels() {
                let _ = self.lathe.reset(i);
            }
            return "RESET: E-STOP released; every channel back at its program start, START begins a new cycle".into();
        }
        let Some(i) = self.machine_ch(ch) else {
            return format!("RESET CH{}: it is not in this MDI run", ch + 1);
        };
        let before = self.lathe.channel(i).map(|s| s.state);
        match self.lathe.reset(i) {
            Ok(()) => match before {
                Some(ChState::Fault | ChState::Alarm) => {
                    format!(
                        "RESET CH{}: cleared; START resumes where it stopped",
                        ch + 1
                    )
                }
                _ => format!("RESET CH{}: nothing to clear", ch + 1),
            },
            Err(e) => e,
        }
    }

    /// A fault in the console's channel `ch`.
    pub fn fault(&mut self, ch: usize, why: &str) -> Result<(), String> {
        match self.machine_ch(ch) {
            Some(i) => self.lathe.fault(i, why),
            None => Err("it is not in this MDI run".into()),
        }
    }

    /// A message for the operator, once.
    pub fn take_message(&mut self) -> Option<String> {
        self.message.take()
    }

    /// Each channel's position now (for the next cycle to start from).
    pub fn positions(&self, out: &mut [[i64; 2]]) {
        for i in 0..self.lathe.channels() {
            if let Some(s) = self.lathe.channel(i) {
                out[self.console_ch(i)] = s.pos;
            }
        }
    }

    /// Each channel's work in the spindle now (`None` for a channel not in this run).
    pub fn works(&self, out: &mut [Option<u32>]) {
        out.iter_mut().for_each(|w| *w = None);
        for i in 0..self.lathe.channels() {
            if let Some(s) = self.lathe.channel(i) {
                out[self.console_ch(i)] = s.work;
            }
        }
    }

    /// Records what the machine reported (times offset by the cycle's start) and returns each
    /// console channel's part count.
    pub fn drain(&mut self, mut rec: Option<&mut LatheRecorder>, counts: &[u32]) -> Vec<u32> {
        let t0 = self.started_ns;
        let mut counts = counts.to_vec();
        for ev in self.lathe.drain_events() {
            match ev {
                Event::Block { ch, t, line, .. } => {
                    self.seq[ch] += 1;
                    let c = self.console_ch(ch);
                    let text = self
                        .lines
                        .get(ch)
                        .and_then(|l| l.get(line as usize - 1))
                        .map_or("", |s| s.trim());
                    if let Some(r) = rec.as_deref_mut() {
                        r.block(t0 + t, c, self.seq[ch], line, text);
                    }
                }
                Event::Sample {
                    ch,
                    t,
                    pos,
                    rpm,
                    speed,
                } => {
                    if let Some(r) = rec.as_deref_mut() {
                        r.position(t0 + t, self.console_ch(ch), pos, speed, rpm);
                    }
                }
                Event::State {
                    ch,
                    t,
                    state,
                    waits_on,
                } => {
                    let c = self.console_ch(ch);
                    let s = self.lathe.channel(ch);
                    if let Some(r) = rec.as_deref_mut() {
                        let st = state.to_string();
                        r.state(
                            t0 + t,
                            c,
                            &StateMsg {
                                run: u8::from(!matches!(state, ChState::Idle | ChState::Done)),
                                op_mode: if self.mdi { "MDI" } else { "AUTO" },
                                state: &st,
                                feed_override: 100,
                                tool: s.as_ref().map_or(0, |s| s.tool),
                                spindle: s.as_ref().map_or(0, |s| {
                                    let r = s.rpm.round() as i64;
                                    if s.dir == crate::lathe::ops::SpindleDir::Ccw {
                                        -r
                                    } else {
                                        r
                                    }
                                }),
                                parts: s.as_ref().map_or(0, |s| s.parts),
                            },
                        );
                        if let Some(w) = waits_on {
                            r.event(
                                t0 + t,
                                c,
                                "wait",
                                None,
                                None,
                                &format!("CH{} waits {w}", c + 1),
                            );
                        }
                        if state == ChState::Done {
                            r.event(
                                t0 + t,
                                c,
                                "done",
                                None,
                                None,
                                &format!("CH{} reached the part target", c + 1),
                            );
                        }
                    }
                }
                Event::Transfer {
                    t,
                    from,
                    to,
                    work,
                    both_closed,
                } => {
                    if let Some(r) = rec.as_deref_mut() {
                        let text = format!(
                            "W{work} {} -> {}{}",
                            from.map_or("BAR FEEDER".to_string(), |c| format!("CH{}", c + 1)),
                            to.map_or("UNLOADER".to_string(), |c| format!("CH{}", c + 1)),
                            match (from, both_closed) {
                                (None, _) => "",
                                (Some(_), true) => " (both chucks closed)",
                                (Some(_), false) => " (NOT INTERLOCKED)",
                            }
                        );
                        match from {
                            None => r.event(
                                t0 + t,
                                to.map_or(0, |c| self.console_ch(c)),
                                "supply",
                                Some(work),
                                None,
                                &text,
                            ),
                            Some(f) => r.event(
                                t0 + t,
                                self.console_ch(f),
                                "transfer",
                                Some(work),
                                Some(to.map_or(0, |c| self.console_ch(c) as i64 + 1)),
                                &text,
                            ),
                        }
                    }
                }
                Event::ThreadPass {
                    ch,
                    t,
                    line,
                    index,
                    encoder,
                    resumed,
                } => {
                    if let Some(r) = rec.as_deref_mut() {
                        let s = self.lathe.channel(ch);
                        let text = format!(
                            "line {line}: pass {} at index {index} (encoder {encoder} at the first Z pulse)",
                            if resumed { "resumed" } else { "starts" }
                        );
                        r.event(
                            t0 + t,
                            self.console_ch(ch),
                            "thread",
                            s.and_then(|s| s.work),
                            Some(index as i64),
                            &text,
                        );
                    }
                }
                Event::CutStart { ch, t, line, work } => {
                    if let Some(r) = rec.as_deref_mut() {
                        r.event(
                            t0 + t,
                            self.console_ch(ch),
                            "cut",
                            work,
                            None,
                            &format!("line {line}"),
                        );
                    }
                }
                Event::Part { ch, t, count } => {
                    let c = self.console_ch(ch);
                    if !self.mdi {
                        counts[c] = count;
                    }
                    if let Some(r) = rec.as_deref_mut() {
                        r.event(
                            t0 + t,
                            c,
                            "part",
                            None,
                            Some(i64::from(count)),
                            &format!("CH{} part {count}", c + 1),
                        );
                    }
                }
                Event::Fault { ch, t, reason } => {
                    let c = self.console_ch(ch);
                    if let Some(r) = rec.as_deref_mut() {
                        r.event(t0 + t, c, "fault", None, None, &reason);
                    }
                }
                Event::Alarm { ch, t, line, msg } => {
                    let c = self.console_ch(ch);
                    self.message = Some(format!("CH{} ALARM line {line}: {msg}", c + 1));
                    if let Some(r) = rec.as_deref_mut() {
                        r.event(t0 + t, c, "alarm", None, Some(i64::from(line)), &msg);
                    }
                }
            }
        }
        counts
    }

    /// Every console channel as the display shows it.
    pub fn views(
        &self,
        desc: &LatheDesc,
        programs: &[Program],
        pos: &[[i64; 2]],
        counts: &[u32],
    ) -> Vec<ChanView> {
        (0..desc.channels.len())
            .map(|ch| {
                let mut v = ChanView {
                    name: desc.channels[ch].name.clone(),
                    program: if self.mdi && ch == self.only {
                        "MDI".into()
                    } else {
                        programs[ch].name.clone()
                    },
                    state: "IDLE".into(),
                    pos: pos[ch],
                    parts: counts[ch],
                    ..Default::default()
                };
                if let Some(s) = self.machine_ch(ch).and_then(|i| self.lathe.channel(i)) {
                    let i = self.machine_ch(ch).unwrap_or(0);
                    v.state = s.state.to_string();
                    v.line = s.line;
                    v.text = self
                        .lines
                        .get(i)
                        .and_then(|l| l.get((s.line as usize).wrapping_sub(1)))
                        .cloned()
                        .unwrap_or_default();
                    v.waits = if s.state == ChState::Wait {
                        s.waits_on.map(|w| w.to_string()).unwrap_or_default()
                    } else {
                        String::new()
                    };
                    v.note = s.reason.clone().unwrap_or_default();
                    v.pos = s.pos;
                    v.rpm = if s.dir == crate::lathe::ops::SpindleDir::Ccw {
                        -s.rpm
                    } else {
                        s.rpm
                    };
                    v.tool = s.tool;
                    v.work = s.work;
                    v.chuck = s.chuck_closed;
                    if !self.mdi {
                        v.parts = s.parts;
                    }
                }
                v
            })
            .collect()
    }
}
