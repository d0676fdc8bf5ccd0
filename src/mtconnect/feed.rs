//! The adapter fed from a console (docs/mtconnect.md): every front end's (the terminal, the
//! window, `novanc script` and `novanc run`), so it lives here, beside the adapter, and not in
//! the command line, which only reads its options (`cli::mtconnect::take`).

use super::{Adapter, Key, Modes, PathKeys};
use crate::console::Console;
use crate::lathe::console::{Cycle, LatheConsole};
use crate::pulse_core::{
    ChannelStatus, ChannelView, ClockMode, EndCause, PulseCore, RunKind, Status, Watcher,
};
use crate::tooldata::Magazine;
use std::net::SocketAddr;
use std::sync::{Arc, Mutex};
use std::time::{Duration, SystemTime};

/// The adapter options of a command line.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MtcOpts {
    /// Where to listen.
    pub addr: Option<SocketAddr>,
    /// How long to wait for an agent before the first event.
    pub wait: Option<Duration>,
}

/// An adapter fed from a console: counts parts, builds the modes, publishes. Shared with the
/// pulse core's watcher in virtual time, which publishes every change of state inside a
/// `wait` (or a headless run) with the modes last published.
pub struct Feed {
    state: Arc<Mutex<FeedState>>,
}

struct FeedState {
    adapter: Adapter,
    /// Runs that reached their program's end since the adapter started (`novanc run`'s
    /// `partcount`, which has no console).
    partcount: u64,
    /// The console's part counter as it last published it (what its POS page shows), and the
    /// AUTO program ends counted here since that it has not counted yet (the watcher sees an
    /// end inside an advance before the console does): the console's `partcount` is their
    /// sum, so it rises with the end and never falls back when the console catches up.
    console_parts: Option<(u64, Vec<u64>)>,
    last_run_end: Option<u64>,
    modes: Option<Modes>,
    /// Virtual time: the wall time of machine time 0 (a change is stamped with it plus its
    /// machine time). None in real time: stamped with the wall clock.
    epoch: Option<SystemTime>,
    last_ts: SystemTime,
    /// A lathe's batch besides its channels' states, as last published from the console or
    /// the headless run: the kernel's watcher publishes with it.
    lathe: Option<LatheCtx>,
}

/// What a lathe's batch says besides its channels' states.
#[derive(Clone, Debug)]
struct LatheCtx {
    mode: &'static str,
    /// Per channel: its program's name and its parts (the console's counter: an MDI run
    /// counts none).
    programs: Vec<String>,
    parts: Vec<u64>,
    /// The parts are the sync table's (AUTO).
    auto_parts: bool,
    pulse_mm: f64,
    message: Option<String>,
}

impl LatheCtx {
    /// The items of the lathe with its channels `chans` (the kernel's, loaded or not), each
    /// channel a path.
    fn items(&self, chans: &[ChannelStatus]) -> Vec<(Key, String)> {
        let paths: Vec<LathePath> = self
            .programs
            .iter()
            .zip(chans)
            .enumerate()
            .map(|(i, (program, c))| {
                let sync = c.sync.as_ref();
                let parts = self.parts.get(i).copied().unwrap_or(0);
                LathePath {
                    status: &c.status,
                    sync,
                    program: program.clone(),
                    parts: match sync {
                        Some(v) if self.auto_parts => u64::from(v.parts),
                        _ => parts,
                    },
                }
            })
            .collect();
        lathe_items(self.mode, &paths, self.pulse_mm, self.message.as_deref())
    }
}

impl FeedState {
    /// Publishes `s` with `modes` (None: the modes last published; nothing before any).
    fn publish(&mut self, s: &Status, modes: Option<Modes>) {
        if let Some(m) = modes {
            self.modes = Some(m);
        }
        if let Some(e) = &s.last_end {
            if self.last_run_end.is_none_or(|seen| e.id > seen) {
                self.last_run_end = Some(e.id);
                if e.cause == EndCause::ProgramEnd && s.program_end {
                    self.partcount += 1;
                    if let (Some((_, ahead)), RunKind::Auto) = (&mut self.console_parts, e.kind) {
                        ahead.push(e.id);
                    }
                }
            }
        }
        let partcount = match &self.console_parts {
            Some((parts, ahead)) => parts + ahead.len() as u64,
            None => self.partcount,
        };
        let Some(modes) = self.modes.as_mut() else {
            return;
        };
        modes.partcount = partcount;
        let ts = Self::stamp(self.epoch, &mut self.last_ts, s.machine_ns);
        self.adapter.publish_mill(s, modes, ts);
    }

    /// Publishes a lathe's channels with `ctx` (None: as last published), stamped with
    /// machine time `machine_ns`.
    fn publish_lathe(&mut self, chans: &[ChannelStatus], ctx: Option<LatheCtx>, machine_ns: u64) {
        if let Some(c) = ctx {
            self.lathe = Some(c);
        }
        let Some(items) = self.lathe.as_ref().map(|c| c.items(chans)) else {
            return;
        };
        self.send(items, machine_ns);
    }

    /// Sends `items`, stamped ([`FeedState::stamp`]).
    fn send(&mut self, items: Vec<(Key, String)>, machine_ns: u64) {
        let ts = Self::stamp(self.epoch, &mut self.last_ts, machine_ns);
        self.adapter.publish(items, ts);
    }

    /// The time of a batch: machine time `machine_ns` in virtual time, the wall clock in real
    /// time, never before the last batch.
    fn stamp(epoch: Option<SystemTime>, last_ts: &mut SystemTime, machine_ns: u64) -> SystemTime {
        let ts = match epoch {
            Some(t0) => t0 + Duration::from_nanos(machine_ns),
            None => SystemTime::now(),
        }
        .max(*last_ts);
        *last_ts = ts;
        ts
    }
}

fn lock(m: &Mutex<FeedState>) -> std::sync::MutexGuard<'_, FeedState> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

impl Feed {
    /// Starts the adapter (announcing its address on stderr as `who: mtconnect: listening on
    /// ADDR`); None with no `--mtconnect`. In virtual time, `core` is watched: every change of
    /// state inside an advance is published, stamped with its machine time.
    pub fn start(o: &MtcOpts, who: &str, core: &PulseCore) -> Result<Option<Feed>, String> {
        let virt = core.clock() == ClockMode::Virtual;
        let Some(feed) = Feed::start_on(o, who, virt, core.status().machine_ns)? else {
            return Ok(None);
        };
        if virt {
            let st = feed.state.clone();
            core.set_watch(Some(Arc::new(move |s: &[ChannelStatus]| {
                if let Some(c) = s.first() {
                    lock(&st).publish(&c.status, None);
                }
            })));
        }
        Ok(Some(feed))
    }

    /// Starts the adapter with no core to watch (the lathe, whose cycles each have their own):
    /// in virtual time (`virt`) a batch is stamped with the wall time now plus its machine
    /// time since `machine_ns`, in real time with the wall clock. None with no `--mtconnect`.
    pub fn start_on(
        o: &MtcOpts,
        who: &str,
        virt: bool,
        machine_ns: u64,
    ) -> Result<Option<Feed>, String> {
        let Some(addr) = o.addr else { return Ok(None) };
        let adapter = Adapter::start(addr)?;
        eprintln!("{who}: mtconnect: listening on {}", adapter.local_addr());
        let now = SystemTime::now();
        let epoch = virt.then(|| now - Duration::from_nanos(machine_ns));
        let state = Arc::new(Mutex::new(FeedState {
            adapter,
            partcount: 0,
            console_parts: None,
            last_run_end: None,
            modes: None,
            epoch,
            last_ts: std::time::UNIX_EPOCH,
            lathe: None,
        }));
        Ok(Some(Feed { state }))
    }

    /// Publishes the lathe console's state: the controller's items once, and each channel as
    /// a path (`p1_exec`, `p2_exec`, ...), stamped with the console's machine time.
    pub fn publish_lathe(&mut self, c: &LatheConsole) {
        let v = c.view();
        let ctx = LatheCtx {
            mode: super::items::controller_mode(c.mode()),
            programs: v.channels.iter().map(|ch| ch.program.clone()).collect(),
            parts: v.channels.iter().map(|ch| u64::from(ch.parts)).collect(),
            auto_parts: !c.cycle().mdi,
            pulse_mm: c.desc().pulse_mm,
            message: Some(c.message_line()).filter(|m| !m.is_empty()),
        };
        let snap = c.cycle().channels();
        lock(&self.state).publish_lathe(snap, Some(ctx), c.machine_ns());
    }

    /// Publishes a headless lathe cycle (`novanc run --machine`): AUTO, each channel a path
    /// running `programs[i]`, stamped with the cycle's machine time.
    pub fn publish_cycle(&mut self, cy: &Cycle, programs: &[String], pulse_mm: f64) {
        let n = cy.channels().len();
        let ctx = LatheCtx {
            mode: super::items::controller_mode(crate::panel_model::OpMode::Auto),
            programs: (0..n)
                .map(|i| programs.get(i).cloned().unwrap_or_default())
                .collect(),
            parts: vec![0; n],
            auto_parts: true,
            pulse_mm,
            message: None,
        };
        lock(&self.state).publish_lathe(cy.channels(), Some(ctx), cy.now_ns());
    }

    /// The watcher of a lathe's kernel (virtual time): every change of a channel's state is
    /// published as it happens, stamped with its machine time, with what the console or the
    /// run last published besides the channels (mode, programs, message).
    pub fn lathe_watcher(&self) -> Watcher {
        let st = self.state.clone();
        Arc::new(move |chans: &[ChannelStatus]| {
            let t = chans.first().map_or(0, |c| c.status.machine_ns);
            lock(&st).publish_lathe(chans, None, t);
        })
    }

    /// Publishes the console's state now.
    pub fn publish(&mut self, c: &Console) {
        let modes = Modes {
            mode: crate::mtconnect::items::controller_mode(c.view().op_mode),
            program: c.program_name(),
            partcount: 0,
            wpo: Some(crate::mtconnect::items::wpo_table(
                &std::array::from_fn(|cs| c.system_offset_all(cs)),
                &c.settings().axis_list().collect::<Vec<_>>(),
            )),
            program_alarm: c.program_alarm().map(|a| a.error.to_string()),
            pulse_mm: c.settings().pulse_mm,
            work_origin: c.work_origin(),
            rotary_mask: c.settings().rotary_mask(),
            tooloffsets: Some(crate::mtconnect::items::tool_table(&tool_offsets(
                &c.magazine(),
            ))),
            waiting: false,
            fault: None,
            message: Some(c.message_line()).filter(|m| !m.is_empty()),
        };
        let (parts, seen) = c.part_count();
        {
            let mut st = lock(&self.state);
            // The ends the console has counted are in its counter; one it counted that the
            // feed never saw (real time: no watcher) must not be counted again.
            let ahead = match st.console_parts.take() {
                Some((_, mut v)) => {
                    v.retain(|&id| id > seen);
                    v
                }
                None => Vec::new(),
            };
            st.console_parts = Some((parts, ahead));
            if seen > 0 && st.last_run_end.is_none_or(|id| id < seen) {
                st.last_run_end = Some(seen);
            }
        }
        self.publish_status(c.status(), modes);
    }

    /// Publishes a status snapshot with the modes given (their partcount is the feed's own:
    /// the console's counter once a console has published, else the runs that ended).
    pub fn publish_status(&mut self, s: &Status, modes: Modes) {
        lock(&self.state).publish(s, Some(modes));
    }

    /// Waits for an agent if `--mtconnect-wait` asks (publish the state first: an agent's
    /// first lines are the state before the first event).
    pub fn wait(&self, o: &MtcOpts) -> Result<(), String> {
        if let Some(w) = o.wait {
            // Before the first event: the machine is not running, the watcher is silent.
            if !lock(&self.state).adapter.wait_for_agent(w) {
                return Err(format!(
                    "mtconnect: no agent connected within {} s",
                    w.as_secs_f64()
                ));
            }
        }
        Ok(())
    }
}

/// One lathe channel as the adapter sees it.
struct LathePath<'a> {
    /// Its machine's status.
    status: &'a Status,
    /// Its place in the sync table.
    sync: Option<&'a ChannelView>,
    program: String,
    parts: u64,
}

/// The lathe's items: the controller's once (E-STOP is machine-wide), then each channel as
/// path `pN_` with the mill's mapping ([`crate::mtconnect::items::path_items`]), each from
/// its machine in the kernel (the lathe console's kernel runs from its opening: before stop
/// 42 a channel with no cycle loaded was published as an idle status made up from the
/// console's memory).
fn lathe_items(
    mode: &'static str,
    paths: &[LathePath],
    pulse_mm: f64,
    message: Option<&str>,
) -> Vec<(Key, String)> {
    let statuses: Vec<&Status> = paths.iter().map(|p| p.status).collect();
    let estop = statuses.iter().find(|s| s.estop);
    let mut v = crate::mtconnect::items::controller_items(
        estop.is_some(),
        estop.and_then(|s| s.alarm.as_deref()),
        message,
    );
    for (i, (p, s)) in paths.iter().zip(&statuses).enumerate() {
        let m = Modes {
            mode,
            program: p.program.clone(),
            partcount: p.parts,
            wpo: None,
            program_alarm: None,
            pulse_mm,
            work_origin: [0.0; crate::block::MAX_AXES],
            rotary_mask: 0,
            tooloffsets: None,
            waiting: p.sync.is_some_and(|v| v.waits_on.is_some()),
            fault: p.sync.and_then(|v| v.fault.clone()),
            message: None,
        };
        v.extend(crate::mtconnect::items::path_items(
            s,
            &m,
            &PathKeys::lathe(i + 1),
        ));
    }
    v
}

/// The tool file as the `tooloffsets` table: by T code, set length, radius (half the diameter),
/// length wear, radius wear.
pub fn tool_offsets(m: &Magazine) -> Vec<(u32, [f64; 4])> {
    m.tools
        .iter()
        .map(|(t, r)| {
            (
                t,
                [
                    r.set_length,
                    r.diameter / 2.0,
                    r.wear_length,
                    r.wear_diameter / 2.0,
                ],
            )
        })
        .collect()
}
