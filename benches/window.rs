//! Window benchmark (issue 6): the frame time of `novanc --window` under Xvfb with the software
//! renderer (Mesa llvmpipe) while Table B runs in AUTO in real time, and the pulse rate the
//! pulse core keeps meanwhile, compared with the same console run for the same wall time with
//! no window. Prints its figures; needs Xvfb (skips with a message without it).
//!
//! Two programs: Table B, and a generated 60,000-block milling program (a heavy backplot).
//! Then the Citizen lathe's window (stop 51): its cycle started, and again after 60 s of
//! machine time (every channel's trail and programmed path drawn), against the same console
//! with no window in real time.
//!
//! `cargo bench --features window --bench window` (frames: NOVANC_BENCH_FRAMES, default 600).

use novanc::cli::console_opts::config_from_args;
use novanc::console::Console;
use novanc::panel_model::PanelEvent;
use novanc::pulse_core::ClockMode;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

// The window tests' Xvfb helper (the bench uses only `start_xvfb`).
#[path = "../tests/common/xvfb.rs"]
mod xvfb;

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("novanc_bench_window_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    let _ = std::fs::create_dir_all(&d);
    d
}

/// The value after `key` in the window's `bench-frames` line.
fn field(line: &str, key: &str) -> Option<f64> {
    let w: Vec<&str> = line.split_whitespace().collect();
    let i = w.windows(2).position(|p| p[0] == key)?;
    w.get(i + 1)?.trim_start_matches('(').parse().ok()
}

/// The same console with no window: the same panel events (a `wait` waits for the machine),
/// then ticked at 60 Hz for `wall`. Returns (machine seconds, pulses).
fn headless(state: &Path, events: &[PanelEvent], wall: Duration) -> Result<(f64, u64), String> {
    let args = vec!["--state".to_string(), state.display().to_string()];
    let (cfg, _) = config_from_args(&args)?;
    let (mut c, _) = Console::open(cfg)?;
    for ev in events {
        match ev {
            PanelEvent::Wait => c.wait_idle(),
            e => c.handle(e.clone()),
        }
    }
    let t0 = Instant::now();
    let m0 = c.view().machine_ns;
    let (mut pulses, mut last) = (0u64, 0u64);
    while t0.elapsed() < wall {
        std::thread::sleep(Duration::from_millis(16));
        c.tick();
        let now: u64 = c.status().pulses.iter().sum();
        pulses += if now >= last { now - last } else { now };
        last = now;
    }
    let machine = (c.view().machine_ns - m0) as f64 / 1e9;
    let _ = c.finish();
    Ok((machine, pulses))
}

/// A milling program of about 60,000 blocks: 300 passes round a 200-point contour.
fn big_program() -> String {
    let mut s = String::from("DA1 = (100, 100, -450)\n");
    for i in 1..=200 {
        let a = i as f64 * std::f64::consts::TAU / 200.0;
        s += &format!(
            "P{i} = ({:.3}, {:.3})\n",
            200.0 + 150.0 * a.cos(),
            200.0 + 150.0 * a.sin()
        );
    }
    let pts: Vec<String> = (1..=200).map(|i| format!("P{i}")).collect();
    for k in 0..300 {
        s += &format!("MIL, 402/DP{}/DA1, {}\n", 1 + k % 5, pts.join(", "));
    }
    s
}

/// The Citizen's console with no window in real time: `events` (a `start`; a `wait ms` is let
/// pass in real time), then ticked at 60 Hz for `wall`. Returns (machine seconds, pulses).
fn headless_lathe(
    state: &Path,
    events: &[PanelEvent],
    wall: Duration,
) -> Result<(f64, u64), String> {
    use novanc::lathe::console::LatheConsole;
    use novanc::lathe::desc::LatheDesc;
    let desc = LatheDesc::citizen();
    let n = desc.channels.len();
    let (mut c, _) = LatheConsole::open_on(desc, state, (12, 40), None, ClockMode::RealTime)?;
    for ev in events {
        match ev {
            PanelEvent::WaitMs(ms) => std::thread::sleep(Duration::from_millis(*ms)),
            e => c.handle(e.clone()),
        }
    }
    let pulses = |c: &LatheConsole| -> u64 {
        (0..n)
            .map(|ch| c.cycle().totals(ch).1.iter().sum::<u64>())
            .sum()
    };
    c.tick(0);
    let (t0, m0, p0) = (Instant::now(), c.machine_ns(), pulses(&c));
    while t0.elapsed() < wall {
        std::thread::sleep(Duration::from_millis(16));
        c.tick(16_000_000);
    }
    let machine = (c.machine_ns() - m0) as f64 / 1e9;
    let p = pulses(&c) - p0;
    let _ = c.close(None);
    Ok((machine, p))
}

/// How a scenario's console runs with no window: the centre's or the lathe's.
type Headless = fn(&Path, &[PanelEvent], Duration) -> Result<(f64, u64), String>;

/// Runs one scenario: the window, then the console without it for the same wall time.
fn scenario(title: &str, display: &str, script: &str, frames: u64) {
    scenario_on(title, display, &[], script, frames, headless)
}

/// [`scenario`] on the machine `machine` names (`--machine ...`; none: the centre).
fn scenario_on(
    title: &str,
    display: &str,
    machine: &[&str],
    script: &str,
    frames: u64,
    headless: Headless,
) {
    let dir = scratch(title.split_whitespace().next().unwrap_or("x"));
    let path = dir.join("script.txt");
    if std::fs::write(&path, script).is_err() {
        println!("window bench: cannot write {}", path.display());
        return;
    }
    let out = Command::new(env!("CARGO_BIN_EXE_novanc"))
        .args(["--window", "--size", "1400x860"])
        .args(machine)
        .arg("--state")
        .arg(dir.join("state"))
        .arg("--script")
        .arg(&path)
        .args(["--bench-frames", &frames.to_string()])
        .env("DISPLAY", display)
        .env_remove("WAYLAND_DISPLAY")
        .env("LIBGL_ALWAYS_SOFTWARE", "1")
        .env("WINIT_X11_SCALE_FACTOR", "1")
        .output();
    let out = match out {
        Ok(o) => o,
        Err(e) => {
            println!("window bench: cannot run novanc: {e}");
            return;
        }
    };
    let text = String::from_utf8_lossy(&out.stdout);
    let Some(line) = text.lines().find(|l| l.starts_with("bench-frames")) else {
        println!(
            "window bench: no figures from the window (exit {:?}): {}",
            out.status.code(),
            String::from_utf8_lossy(&out.stderr)
        );
        return;
    };
    println!("{title}\n  window (Xvfb, llvmpipe, 1400x860):\n    {line}");
    let wall = field(line, "wall").unwrap_or(10.0);
    let win_pulses = field(line, "pulses").unwrap_or(0.0);
    let events = match PanelEvent::parse_script(script) {
        Ok(e) => e,
        Err(e) => {
            println!("window bench: bad script: {e}");
            return;
        }
    };
    match headless(
        &dir.join("state-nowin"),
        &events,
        Duration::from_secs_f64(wall),
    ) {
        Ok((machine, pulses)) => {
            println!(
                "  no window (same events, same {wall:.2} s of wall time):\n    machine {machine:.2} s (machine/wall {:.3}); pulses {pulses} ({:.0} pulses/s)",
                machine / wall,
                pulses as f64 / wall
            );
            if pulses > 0 {
                println!(
                    "  pulse rate with the window / without: {:.3}",
                    win_pulses / pulses as f64
                );
            }
        }
        Err(e) => println!("  no-window run failed: {e}"),
    }
}

fn main() {
    let frames: u64 = std::env::var("NOVANC_BENCH_FRAMES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(600);
    let x = match xvfb::start_xvfb() {
        Ok(x) => x,
        Err(why) => {
            println!("window bench: SKIPPED, {why}");
            return;
        }
    };
    scenario(
        "Table B in AUTO, real time",
        &x.display,
        "op AUTO\nstart\n",
        frames,
    );
    let dir = scratch("bigprog");
    let prog = dir.join("big.ap");
    if std::fs::write(&prog, big_program()).is_err() {
        println!("window bench: cannot write {}", prog.display());
        return;
    }
    let script = format!(
        "op DATA\ndata READ\ntape {}\nstart\nwait\nop AUTO\nstart\n",
        prog.display()
    );
    scenario(
        "A 60,000-block milling program (300 passes of a 200-point contour) in AUTO, real time",
        &x.display,
        &script,
        frames,
    );
    let citizen = ["--machine", "citizen"];
    scenario_on(
        "The Citizen lathe, its cycle started (the window: virtual time at the wall clock's pace)",
        &x.display,
        &citizen,
        "start\n",
        frames,
        headless_lathe,
    );
    scenario_on(
        "The Citizen lathe after 60 s of machine time (every trail and programmed path drawn)",
        &x.display,
        &citizen,
        "start\nwait ms 60000\n",
        frames,
        headless_lathe,
    );
}
