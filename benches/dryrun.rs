//! Dry runs as the operator runs them (issue "The core owns the run"), printed:
//! - the 30,000-hole drilling program (95 hours of machine time, 1.44 G axis pulses) and a
//!   dense contour, each in process (the pulse core and translator threads, no recording) and
//!   as the whole `novanc run` process, with axis pulses per second;
//! - START to the first pulse of a 1,000,000-statement program at the console, in real time;
//! - the peak memory (maximum resident set) of `novanc run` on that program.
//!
//! Run with `cargo bench --bench dryrun`. The programs are written to a temporary directory.

use novanc::console::{Console, ConsoleConfig, RunSource};
use novanc::panel_model::{OpMode, PanelEvent};
use novanc::pulse_core::{ClockMode, PulseCore, Reached, RunKind};
use novanc::settings::MachineSettings;
use novanc::tooldata::sample_magazine;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// 30,000 holes: 300 bolt circles of 100 holes, drilled 20 mm deep with the 6.2 drill.
fn holes() -> String {
    let mut s = String::from("DA1 = (0, 0, -450)\n");
    let mut k = 0;
    for gx in 0..20 {
        for gy in 0..15 {
            k += 1;
            let _ = writeln!(s, "P{k} = ({}, {})", 60 + gx * 45, 60 + gy * 45);
            let _ = writeln!(s, "PAT{k} = DA1, NH100, P{k}, R40");
            let _ = writeln!(s, "DRL, 106/DP20/PAT{k}");
        }
    }
    s
}

/// A dense contour: 1,000 milling statements of 200 points each, 0.5 mm to 3 mm apart, with
/// the 8 mm end mill.
fn contour() -> String {
    let mut s = String::from("DA1 = (100, 100, -450)\n");
    let mut seed: u64 = 7;
    let mut rnd = move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 33) as f64 / (1u64 << 31) as f64
    };
    for _ in 0..1000 {
        s.push_str("MIL, 402/DP2/DA1");
        let (mut x, mut y) = (100.0 + 50.0 * rnd(), 100.0 + 50.0 * rnd());
        for _ in 0..200 {
            x = (x + (rnd() - 0.5) * 4.0).clamp(10.0, 300.0);
            y = (y + (rnd() - 0.5) * 4.0).clamp(10.0, 300.0);
            let _ = write!(s, ", ({x:.3}, {y:.3})");
        }
        s.push('\n');
    }
    s
}

/// 1,000,000 statements: rapid positioning to and fro in X and Y (with a definition every
/// tenth line, so the tables grow too).
fn million() -> String {
    let mut s = String::with_capacity(30_000_000);
    for i in 0..1_000_000u32 {
        if i % 10 == 9 {
            let _ = writeln!(s, "P{i} = ({}, {})", i % 500, i % 300);
        } else {
            let d = i % 2;
            let _ = writeln!(s, "GO, {}, {}, -100", 400 + d, 300 + d);
        }
    }
    s
}

fn temp() -> PathBuf {
    let d = std::env::temp_dir().join(format!("novanc-dryrun-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&d);
    d
}

/// In process: the pulse core (virtual time, no recording) runs the program from machine zero.
fn in_process(text: &str) -> (f64, u64, f64) {
    let settings = MachineSettings::default();
    let core = PulseCore::spawn(settings.clone(), ClockMode::Virtual, None);
    let magazine = sample_magazine();
    core.set_magazine(magazine.clone());
    let src = RunSource::program("", text.into(), magazine, settings);
    let t = Instant::now();
    core.start(RunKind::Auto, Some(src.make_run()));
    let (r, st) = core.run_until_idle(u64::MAX);
    let secs = t.elapsed().as_secs_f64();
    assert_eq!(r, Reached::Idle);
    assert!(st.alarm.is_none() && st.program_end, "{:?}", st.last_end);
    (secs, st.pulses.iter().sum(), st.machine_ns as f64 * 1e-9)
}

/// The whole `novanc run` process: wall time and peak resident set (MB).
fn whole_process(path: &Path) -> (f64, f64, String) {
    let t = Instant::now();
    let mut child = match std::process::Command::new(env!("CARGO_BIN_EXE_novanc"))
        .arg("run")
        .arg(path)
        .stdout(std::process::Stdio::piped())
        .spawn()
    {
        Ok(c) => c,
        Err(e) => return (0.0, 0.0, e.to_string()),
    };
    let pid = child.id() as libc::pid_t;
    let mut status = 0;
    // SAFETY: a zeroed rusage is valid; wait4 fills it for our own child.
    let mut ru: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: waiting for our own child with valid pointers.
    unsafe { libc::wait4(pid, &mut status, 0, &mut ru) };
    let secs = t.elapsed().as_secs_f64();
    let mut out = String::new();
    if let Some(mut o) = child.stdout.take() {
        use std::io::Read;
        let _ = o.read_to_string(&mut out);
    }
    (secs, ru.ru_maxrss as f64 / 1024.0, out)
}

/// START to the first pulse at the console, in real time, on a program in memory; and how
/// long the START key itself took.
fn first_pulse(text: &str) -> (f64, f64) {
    let dir = temp().join("state");
    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::create_dir_all(&dir);
    // The program goes into memory as PROGRAM READ stores it, without the reader's real-time
    // speed (19 MB at 300 characters/s would take 18 hours).
    {
        let Ok((mut s, _)) = novanc::store::Stores::open(&dir, 24) else {
            return (f64::NAN, f64::NAN);
        };
        if s.program_read("BIG", text).is_err() {
            return (f64::NAN, f64::NAN);
        }
    }
    let cfg = ConsoleConfig::new(dir.clone());
    let Ok((mut c, _)) = Console::open(cfg) else {
        return (f64::NAN, f64::NAN);
    };
    assert_eq!(
        c.program_text().len(),
        text.len(),
        "the program is in memory"
    );
    c.handle(PanelEvent::Op(OpMode::Auto));
    let t = Instant::now();
    c.handle(PanelEvent::Start);
    let returned = t.elapsed().as_secs_f64();
    let mut first = None;
    while t.elapsed() < Duration::from_secs(10) {
        c.tick();
        if c.status().pulses.iter().sum::<u64>() > 0 {
            first = Some(t.elapsed().as_secs_f64());
            break;
        }
        std::thread::sleep(Duration::from_micros(200));
    }
    c.handle(PanelEvent::Reset);
    let _ = c.finish();
    let _ = std::fs::remove_dir_all(&dir);
    (first.unwrap_or(f64::NAN), returned)
}

fn report(name: &str, text: &str, path: &Path) {
    let _ = std::fs::write(path, text);
    let (secs, pulses, machine) = in_process(text);
    println!(
        "{name}: {:.1} M axis pulses in {machine:.0} s of machine time ({:.1} h)",
        pulses as f64 / 1e6,
        machine / 3600.0
    );
    println!(
        "  in process (translator + pulse core threads): {secs:.2} s, {:.1} M axis pulses/s",
        pulses as f64 / secs / 1e6
    );
    let (wall, rss, out) = whole_process(path);
    println!(
        "  whole `novanc run` process:                    {wall:.2} s, {:.1} M axis pulses/s, peak RSS {rss:.1} MB",
        pulses as f64 / wall / 1e6
    );
    let summary: Vec<&str> = out.lines().take(1).collect();
    println!("  ({})", summary.join(" "));
}

fn main() {
    let dir = temp();
    println!("dry runs (virtual time, recording off)");
    report("30,000 holes", &holes(), &dir.join("holes.ap"));
    report("dense contour", &contour(), &dir.join("contour.ap"));
    let big = million();
    let path = dir.join("million.ap");
    let _ = std::fs::write(&path, &big);
    let (wall, rss, out) = whole_process(&path);
    println!(
        "1,000,000 statements ({:.1} MB): whole `novanc run` {wall:.2} s, peak RSS {rss:.1} MB (target < 150 MB)",
        big.len() as f64 / 1e6
    );
    let summary: Vec<&str> = out.lines().take(1).collect();
    println!("  ({})", summary.join(" "));
    let (first, key) = first_pulse(&big);
    println!(
        "START to the first pulse at the console, real time, 1,000,000-statement program in memory: {:.1} ms (target 50 ms; the START key took {:.1} ms)",
        first * 1e3,
        key * 1e3
    );
    let _ = std::fs::remove_dir_all(&dir);
}
