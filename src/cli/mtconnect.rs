//! `--mtconnect ADDR:PORT` and `--mtconnect-wait SECONDS` (docs/mtconnect.md): taken out of a
//! subcommand's arguments, and the adapter fed from a console.

use crate::console::Console;
use crate::mtconnect::{Adapter, Modes};
use crate::pulse_core::{ClockMode, EndCause, PulseCore, Status};
use crate::tooldata::Magazine;
use std::net::SocketAddr;
use std::sync::{Arc, Mutex};
use std::time::{Duration, SystemTime};

/// The adapter options of a command line.
#[derive(Clone, Debug, Default)]
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
        let ts = match self.epoch {
            Some(t0) => t0 + Duration::from_nanos(s.machine_ns),
            None => SystemTime::now(),
        }
        .max(self.last_ts);
        self.last_ts = ts;
        self.adapter.publish(crate::mtconnect::items(s, modes), ts);
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
        let Some(addr) = o.addr else { return Ok(None) };
        let adapter = Adapter::start(addr)?;
        eprintln!("{who}: mtconnect: listening on {}", adapter.local_addr());
        let now = SystemTime::now();
        let virt = core.clock() == ClockMode::Virtual;
        let epoch = virt.then(|| now - Duration::from_nanos(core.status().machine_ns));
        let state = Arc::new(Mutex::new(FeedState {
            adapter,
            partcount: 0,
            last_run_end: None,
            modes: None,
            epoch,
            last_ts: std::time::UNIX_EPOCH,
        }));
        if virt {
            let st = state.clone();
            core.set_watch(Some(Arc::new(move |s: &Status| {
                lock(&st).publish(s, None);
            })));
        }
        Ok(Some(Feed { state }))
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
            op: c.view().op_mode,
            program: c.program_name(),
            partcount: 0,
            wpo: crate::mtconnect::items::wpo_table(&c.work_offsets().0),
            program_alarm: c.program_alarm().map(|a| a.error.to_string()),
            pulse_mm: c.settings().pulse_mm,
            work_origin: c.work_origin(),
            tooloffsets: crate::mtconnect::items::tool_table(&tool_offsets(&c.magazine())),
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
