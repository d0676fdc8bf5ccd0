//! `--mtconnect ADDR:PORT` and `--mtconnect-wait SECONDS` (docs/mtconnect.md): taken out of a
//! subcommand's arguments, and the adapter fed from a console.

use crate::console::Console;
use crate::lathe::console::events::Mode as LatheMode;
use crate::lathe::console::{Cycle, LatheConsole};
use crate::mtconnect::items::lathe_mode;
use crate::mtconnect::{Adapter, Key, Modes, PathKeys};
use crate::pulse_core::{ChannelView, ClockMode, EndCause, PulseCore, Status};
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

/// Takes `--mtconnect V` / `--mtconnect=V` and `--mtconnect-wait S` out of `argv`.
pub fn take(argv: &[String]) -> Result<(MtcOpts, Vec<String>), String> {
    let mut o = MtcOpts::default();
    let (taken, rest) = super::args::take_values(argv, &["--mtconnect", "--mtconnect-wait"])?;
    for (name, v) in taken {
        if name == "--mtconnect" {
            o.addr = Some(crate::mtconnect::parse_addr(&v)?);
        } else {
            o.wait = Some(crate::mtconnect::parse_wait(&v)?);
        }
    }
    if o.wait.is_some() && o.addr.is_none() {
        return Err("--mtconnect-wait needs --mtconnect".into());
    }
    Ok((o, rest))
}

/// An adapter fed from a console: counts parts, builds the modes, publishes. Shared with the
/// pulse core's watcher in virtual time, which publishes every change of state inside a
/// `wait` (or a headless run) with the modes last published.
pub struct Feed {
    state: Arc<Mutex<FeedState>>,
}

struct FeedState {
    adapter: Adapter,
    partcount: u64,
    last_run_end: Option<u64>,
    modes: Option<Modes>,
    /// Virtual time: the wall time of machine time 0 (a change is stamped with it plus its
    /// machine time). None in real time: stamped with the wall clock.
    epoch: Option<SystemTime>,
    last_ts: SystemTime,
}

impl FeedState {
    /// Publishes `s` with `modes` (None: the modes last published; nothing before any).
    fn publish(&mut self, s: &Status, modes: Option<Modes>) {
        if let Some(m) = modes {
            self.modes = Some(m);
        }
        if let Some(e) = &s.last_end {
            if self.last_run_end != Some(e.id) {
                self.last_run_end = Some(e.id);
                if e.cause == EndCause::ProgramEnd && s.program_end {
                    self.partcount += 1;
                }
            }
        }
        let partcount = self.partcount;
        let Some(modes) = self.modes.as_mut() else {
            return;
        };
        modes.partcount = partcount;
        let ts = Self::stamp(self.epoch, &mut self.last_ts, s.machine_ns);
        self.adapter.publish_mill(s, modes, ts);
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
            core.set_watch(Some(Arc::new(move |s: &Status| {
                lock(&st).publish(s, None);
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
            last_run_end: None,
            modes: None,
            epoch,
            last_ts: std::time::UNIX_EPOCH,
        }));
        Ok(Some(Feed { state }))
    }

    /// Publishes the lathe console's state: the controller's items once, and each channel as
    /// a path (`p1_exec`, `p2_exec`, ...), stamped with the console's machine time.
    pub fn publish_lathe(&mut self, c: &LatheConsole) {
        let v = c.view();
        let snap = c.cycle().map_or(&[][..], |cy| cy.channels());
        let paths: Vec<LathePath> = v
            .channels
            .iter()
            .enumerate()
            .map(|(i, ch)| LathePath {
                status: snap.get(i).map(|s| &s.status),
                sync: snap.get(i).and_then(|s| s.sync.as_ref()),
                pos: ch.pos,
                program: ch.program.clone(),
                parts: u64::from(ch.parts),
            })
            .collect();
        let msg = Some(c.message()).filter(|m| !m.is_empty());
        let items = lathe_items(
            lathe_mode(c.mode()),
            &paths,
            c.desc().pulse_mm,
            c.feed_override(),
            msg,
        );
        lock(&self.state).send(items, c.machine_ns());
    }

    /// Publishes a headless lathe cycle (`novanc run --machine`): AUTO, each channel a path
    /// running `programs[i]`, stamped with the cycle's machine time.
    pub fn publish_cycle(&mut self, cy: &Cycle, programs: &[String], pulse_mm: f64) {
        let paths: Vec<LathePath> = cy
            .channels()
            .iter()
            .enumerate()
            .map(|(i, s)| LathePath {
                status: Some(&s.status),
                sync: s.sync.as_ref(),
                pos: [s.status.pos[0], s.status.pos[2]],
                program: programs.get(i).cloned().unwrap_or_default(),
                parts: u64::from(cy.totals(i).2),
            })
            .collect();
        let items = lathe_items(lathe_mode(LatheMode::Auto), &paths, pulse_mm, 100, None);
        lock(&self.state).send(items, cy.now_ns());
    }

    /// Publishes the console's state, then waits for an agent if `--mtconnect-wait` asks
    /// (the agent's first lines are then the state before the first event).
    pub fn start_and_wait(&mut self, c: &Console, o: &MtcOpts) -> Result<(), String> {
        self.publish(c);
        self.wait(o)
    }

    /// Publishes the console's state now.
    pub fn publish(&mut self, c: &Console) {
        let modes = Modes {
            mode: crate::mtconnect::items::controller_mode(c.view().op_mode),
            program: c.program_name(),
            partcount: 0,
            wpo: Some(crate::mtconnect::items::wpo_table(&c.work_offsets().0)),
            program_alarm: c.program_alarm().map(|a| a.error.to_string()),
            pulse_mm: c.settings().pulse_mm,
            work_origin: c.work_origin(),
            tooloffsets: Some(crate::mtconnect::items::tool_table(&tool_offsets(
                &c.magazine(),
            ))),
            waiting: false,
            fault: None,
        };
        self.publish_status(c.status(), modes);
    }

    /// Publishes a status snapshot with the modes given (their partcount is the feed's own).
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
    /// Its machine's status (None with no cycle loaded: idle at `pos`).
    status: Option<&'a Status>,
    /// Its place in the sync table.
    sync: Option<&'a ChannelView>,
    /// The tool post, pulses [X, Z].
    pos: [i64; 2],
    program: String,
    parts: u64,
}

/// The lathe's items: the controller's once (E-STOP is machine-wide), then each channel as
/// path `pN_` with the mill's mapping ([`crate::mtconnect::items::path_items`]); a channel
/// with no cycle loaded stands idle at its tool post with the console's feed override.
fn lathe_items(
    mode: &'static str,
    paths: &[LathePath],
    pulse_mm: f64,
    feed_override: u32,
    message: Option<&str>,
) -> Vec<(Key, String)> {
    let idle: Vec<Status> = paths
        .iter()
        .map(|p| Status {
            pos: [p.pos[0], 0, p.pos[1]].into(),
            feed_override,
            ..Status::default()
        })
        .collect();
    let statuses: Vec<&Status> = paths
        .iter()
        .zip(&idle)
        .map(|(p, i)| p.status.unwrap_or(i))
        .collect();
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
            work_origin: [0.0; 3],
            tooloffsets: None,
            waiting: p.sync.is_some_and(|v| v.waits_on.is_some()),
            fault: p.sync.and_then(|v| v.fault.clone()),
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
