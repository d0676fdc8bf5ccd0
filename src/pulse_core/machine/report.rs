//! What the machine tells the outside: the status snapshot and the recorded events.

use super::{send_ev, Machine, Phase};
use crate::pulse_core::{RunInfo, Status};
use crate::record::{Event, Switches};

/// How often the state of a spindle whose speed changes every tick is sampled, ns.
const STATE_SAMPLE_NS: u64 = 10_000_000;

/// What `/nc/state` last said: a new message only when it changes.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct StateKey {
    run: u8,
    feed_override: u32,
    tool: u32,
    spindle: i64,
    op_mode: String,
    data_mode: String,
    switches: Switches,
}

/// What the watcher was last told: it is told again only when this changes.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct WatchKey {
    run: u8,
    hold: bool,
    estop: bool,
    alarm: Option<String>,
    notice: Option<String>,
    block: Option<u32>,
    in_block: bool,
    moving: bool,
    job: Option<u64>,
    last_end: Option<u64>,
    program_end: bool,
    tool: Option<u32>,
    spindle: i64,
    overrides: [u32; 3],
    single_block: bool,
}

/// The watcher and what it was last told: a watcher called at once (the single machine), or
/// none, the statuses kept for the owner to take in order (a kernel's channel: the kernel
/// merges its channels' changes in time order, docs/pulse-core.md "Channels").
#[derive(Clone)]
pub(super) struct Watch {
    f: Option<crate::pulse_core::Watcher>,
    kept: Vec<Status>,
    last: Option<WatchKey>,
}

impl Watch {
    pub(super) fn new(f: Option<crate::pulse_core::Watcher>) -> Watch {
        Watch {
            f,
            kept: Vec::new(),
            last: None,
        }
    }

    /// The statuses kept since the last call (a kept watch).
    pub(super) fn take(&mut self) -> Vec<Status> {
        std::mem::take(&mut self.kept)
    }
}

impl std::fmt::Debug for Watch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Watch").field("last", &self.last).finish()
    }
}

impl Machine {
    fn watch_key(&self) -> WatchKey {
        WatchKey {
            run: self.run,
            hold: self.hold,
            estop: self.estop,
            alarm: self.alarm.clone(),
            notice: self.notice.clone(),
            block: self.current.as_ref().map(|c| c.block.seq).or_else(|| {
                self.job
                    .as_ref()
                    .and_then(|j| j.last_block.as_ref())
                    .map(|b| b.seq)
            }),
            in_block: self.current.is_some(),
            moving: self
                .current
                .as_ref()
                .and_then(|c| c.motion.as_ref())
                .is_some_and(|m| !m.at_rest()),
            job: self.job.as_ref().map(|j| j.id),
            last_end: self.last_end.as_ref().map(|e| e.id),
            program_end: self.program_end,
            tool: self.tool,
            spindle: self.spindle_status(),
            overrides: [
                self.pending_override.unwrap_or(self.feed_override),
                self.rapid_override,
                self.spindle_override,
            ],
            single_block: self.single_block,
        }
    }

    /// Tells the watcher the status if the state changed since it was last told.
    pub(super) fn watch_check(&mut self) {
        if self.watch.is_none() {
            return;
        }
        let key = self.watch_key();
        if self.watch.as_ref().and_then(|w| w.last.as_ref()) == Some(&key) {
            return;
        }
        let st = self.status();
        if let Some(w) = &mut self.watch {
            w.last = Some(key);
            match &w.f {
                Some(f) => f(&[crate::pulse_core::ChannelStatus {
                    status: st,
                    sync: None,
                }]),
                None => w.kept.push(st),
            }
        }
    }

    pub(super) fn send_position(&self) {
        if let Some(s) = &self.events {
            send_ev(
                s,
                &self.out.lossless,
                Event::Position {
                    t_ns: self.now,
                    pulses: self.out.pos,
                    held: self.out.shift,
                    speed_mm_min: self.speed_mm_min(),
                },
            );
        }
    }
    /// The switch positions recorded in `/nc/state`.
    fn switches(&self) -> Switches {
        Switches {
            rapid_override: self.rapid_override,
            spindle_override: self.spindle_override,
            dry_run: self.dry_run,
            machine_lock: self.machine_lock,
            z_neglect: self.z_neglect,
            override_locked: self.in_tap,
        }
    }

    pub(super) fn send_state(&mut self) {
        let Some(s) = &self.events else { return };
        let key = StateKey {
            run: self.run,
            feed_override: self.feed_override,
            tool: self.tool.unwrap_or(0),
            spindle: self.spindle_status(),
            op_mode: self.op_mode.clone(),
            data_mode: self.data_mode.clone(),
            switches: self.switches(),
        };
        if self.last_state.as_ref() == Some(&key) {
            return;
        }
        // A spindle ramping or following G96 changes its speed every tick: its state is
        // sampled every 10 ms of machine time, and sent at once when it reaches its commanded
        // speed or stops, or when anything else changes.
        if let Some(last) = &self.last_state {
            let only_spindle = StateKey {
                spindle: last.spindle,
                ..key.clone()
            } == *last;
            let settled = key.spindle == 0 || key.spindle == self.spindle_actual();
            if only_spindle
                && !settled
                && self.now < self.last_state_t.saturating_add(STATE_SAMPLE_NS)
            {
                return;
            }
        }
        self.last_state_t = self.now;
        send_ev(
            s,
            &self.out.lossless,
            Event::State {
                t_ns: self.now,
                run: key.run,
                op_mode: key.op_mode.clone(),
                data_mode: key.data_mode.clone(),
                feed_override: key.feed_override,
                tool: key.tool,
                spindle: key.spindle,
                switches: key.switches,
            },
        );
        self.last_state = Some(key);
    }
    /// The commanded path speed of the motion in force (a block's, a jog's or a return's),
    /// mm/min; 0 with none.
    fn speed_mm_min(&self) -> f64 {
        self.current
            .as_ref()
            .and_then(|c| c.motion.as_ref())
            .or(self.jog.as_ref().map(|j| &j.motion))
            .or(self.ret.as_ref().map(|j| &j.motion))
            .map_or(0.0, |m| m.speed_mm_min(self.settings.pulse_mm))
    }

    /// A snapshot for the display.
    pub fn status(&self) -> Status {
        let motion = self
            .current
            .as_ref()
            .and_then(|c| c.motion.as_ref())
            .or(self.jog.as_ref().map(|j| &j.motion))
            .or(self.ret.as_ref().map(|j| &j.motion));
        Status {
            stalled: self.is_stalled(),
            run: self.run,
            hold: self.hold,
            estop: self.estop,
            estop_at: self.estop_at,
            alarm: self.alarm.clone(),
            pos: self.out.pos,
            machine_pos: self.out.machine_pos(),
            job: self.job.as_ref().map(|j| RunInfo {
                kind: j.kind,
                id: j.id,
                started_ns: j.started_ns,
                return_to: j.return_to,
                returning: self.ret.is_some() || !self.ret_queue.is_empty(),
            }),
            executing: self
                .current
                .as_ref()
                .map(|c| c.entry.clone())
                .or_else(|| self.job.as_ref().and_then(|j| j.last.clone())),
            executed: self
                .current
                .as_ref()
                .map(|c| c.block.clone())
                .or_else(|| self.job.as_ref().and_then(|j| j.last_block.clone())),
            length_shift: if self.job.is_some() {
                self.length_shift()
            } else {
                0
            },
            in_block: self.current.is_some(),
            last_end: self.last_end.clone(),
            runs: self.runs,
            blocks_done: self.blocks_done,
            pulses: self.out.count,
            tool: self.tool,
            changing_tool: self
                .current
                .as_ref()
                .filter(|c| c.phase == Phase::PreAux && c.block.m == Some(6))
                .and_then(|c| c.block.t.or(self.selected_t)),
            tool_set_length: self.tool_len,
            spindle: self.spindle_status(),
            spindle_programmed: self.spindle,
            spindle_dir: self.spindle_dir,
            feed_override: self.pending_override.unwrap_or(self.feed_override),
            switches: self.switches(),
            hold_after_tap: self.hold_after_tap,
            machine_ns: self.now,
            moving: motion.is_some_and(|m| !m.at_rest()),
            returning: self.ret.is_some() || !self.ret_queue.is_empty(),
            program_end: self.program_end,
            idle: self.is_idle(),
            notice: self.notice.clone(),
            single_block: self.single_block,
            speed_mm_min: self.speed_mm_min(),
            inputs: self.inputs,
            outputs: self.outputs,
            orient: self.orient,
            coolant: self.coolant,
            commands_applied: self.commands,
        }
    }
}
