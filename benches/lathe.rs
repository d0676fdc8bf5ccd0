//! Lathe benchmark (issues 13 and 22): the Citizen on the one kernel (`pulse_core::Kernel`).
//!
//! In process: the Citizen's own programs (`programs/citizen`) to 100 parts, and the
//! three-channel 5-part sample (`novanc::lathe::testkit`), best of 3: wall time, axis pulses per
//! second, machine time. Then what the user runs: the whole `novanc run --machine citizen
//! programs/citizen` process (reading the three programs, the run, the summary), to 5 parts and
//! to 100 parts with and without a recording, best of 3. Last, an idle Citizen console in real
//! time, as at a terminal (ticked every 20 ms): the process's CPU over 3 s, percent of a core
//! (stop 43: its kernel thread woke for every 100 µs tick and used about 20 %).
//!
//! The lockstep lathe simulator this bench also timed was deleted in issue 22; its last
//! figures are in the README ("Figures", the Citizen lathe).
//!
//! Run with `cargo bench --bench lathe`.

use novanc::block::Statement;
use novanc::lathe::desc::LatheDesc;
use novanc::lathe::testkit::{citizen_like, citizen_programs, kernel, pt, sample_programs};
use novanc::pulse_core::Outcome;
use std::time::Instant;

/// The whole `novanc run --machine citizen` process to `parts`: (wall s, axis pulses, machine s).
fn whole(parts: u32, record: bool) -> Result<(f64, u64, f64), String> {
    let rec = std::env::temp_dir().join(format!("novanc-lathe-bench-{}.mcap", std::process::id()));
    let mut args = vec![
        "run".to_string(),
        "--machine".into(),
        "citizen".into(),
        concat!(env!("CARGO_MANIFEST_DIR"), "/programs/citizen").into(),
        "--parts".into(),
        parts.to_string(),
    ];
    if record {
        args.push("--record".into());
        args.push(rec.display().to_string());
    }
    let t0 = Instant::now();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_novanc"))
        .args(&args)
        .output()
        .map_err(|e| format!("novanc: {e}"))?;
    let wall = t0.elapsed().as_secs_f64();
    let _ = std::fs::remove_file(&rec);
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    if !out.status.success() || !text.contains(&format!("parts: {parts}\n")) {
        return Err(format!(
            "novanc run: {text}{}",
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    let mut pulses = 0;
    let mut machine = 0.0;
    for l in text.lines() {
        if let Some(m) = l.strip_prefix("machine time: ") {
            machine = m.trim_end_matches(" s").parse().unwrap_or(0.0);
        }
        if let Some(i) = l.find("pulses X ") {
            let mut w = l[i + 9..]
                .split(|c: char| !c.is_ascii_digit())
                .filter(|s| !s.is_empty());
            pulses += w.next().and_then(|s| s.parse::<u64>().ok()).unwrap_or(0);
            pulses += w.next().and_then(|s| s.parse::<u64>().ok()).unwrap_or(0);
        }
    }
    Ok((wall, pulses, machine))
}

/// The fastest of `n` runs (by their first figure, the wall time); a failed run ends the bench.
fn best_of<T: Copy>(
    n: usize,
    mut f: impl FnMut() -> Result<T, String>,
    wall: impl Fn(&T) -> f64,
) -> T {
    let mut best: Option<T> = None;
    for _ in 0..n {
        match f() {
            Ok(r) => {
                if best.as_ref().is_none_or(|b| wall(&r) < wall(b)) {
                    best = Some(r);
                }
            }
            Err(e) => {
                eprintln!("lathe bench: {e}");
                std::process::exit(1);
            }
        }
    }
    match best {
        Some(b) => b,
        None => std::process::exit(1),
    }
}

/// `programs` on `desc` to `parts` in process on the kernel, every tool at `at` (None: its
/// home): (wall s, axis pulses, machine ns).
fn on_kernel(
    desc: &LatheDesc,
    progs: &[Vec<Statement>],
    parts: u32,
    at: Option<[i64; 2]>,
) -> Result<(f64, u64, u64), String> {
    let progs = progs.to_vec();
    let t0 = Instant::now();
    let mut k = kernel(desc, progs, parts, at)?;
    k.start(None)?;
    let o = k.run_until_idle(u64::MAX / 4);
    let wall = t0.elapsed().as_secs_f64();
    if o != (Outcome::Finished { parts }) {
        return Err(format!("the kernel's run ended {o:?}"));
    }
    let pulses: u64 = (0..desc.channels.len())
        .filter_map(|ch| k.channel(ch))
        .map(|v| v.total_pulses.iter().sum::<u64>())
        .sum();
    Ok((wall, pulses, k.now()))
}

/// The CPU time the process has used, s (user and system).
fn cpu_s() -> f64 {
    // SAFETY: getrusage writes the struct it is given and nothing else.
    let mut u: libc::rusage = unsafe { std::mem::zeroed() };
    unsafe { libc::getrusage(libc::RUSAGE_SELF, &mut u) };
    let t = |v: libc::timeval| v.tv_sec as f64 + v.tv_usec as f64 * 1e-6;
    t(u.ru_utime) + t(u.ru_stime)
}

/// An idle Citizen console in real time, ticked every 20 ms as the terminal does, for `secs`:
/// the process's CPU, percent of one core.
fn idle_console(secs: f64) -> Result<f64, String> {
    let dir = std::env::temp_dir().join(format!("novanc-bench-idle-{}", std::process::id()));
    let clock = novanc::pulse_core::ClockMode::RealTime;
    let (mut c, _) = novanc::lathe::console::LatheConsole::open_on(
        LatheDesc::citizen(),
        &dir,
        (20, 60),
        None,
        clock,
    )?;
    // Past the opening's own work.
    std::thread::sleep(std::time::Duration::from_millis(300));
    let (t0, cpu0) = (Instant::now(), cpu_s());
    while t0.elapsed().as_secs_f64() < secs {
        std::thread::sleep(std::time::Duration::from_millis(20));
        c.tick(20_000_000);
        let _ = c.frame_text();
    }
    let pct = (cpu_s() - cpu0) / t0.elapsed().as_secs_f64() * 100.0;
    drop(c);
    let _ = std::fs::remove_dir_all(&dir);
    Ok(pct)
}

fn main() {
    let desc = LatheDesc::citizen();
    let progs = citizen_programs(&desc).unwrap_or_else(|e| {
        eprintln!("lathe bench: {e}");
        std::process::exit(1)
    });
    let sample = citizen_like(3);
    let sample_progs = sample_programs();
    for (name, d, p, parts, at) in [
        ("the Citizen, 100 parts", &desc, &progs, 100, None),
        (
            "the 3-channel sample, 5 parts",
            &sample,
            &sample_progs,
            5,
            Some(pt(20.0, 5.0)),
        ),
    ] {
        let (wall, pulses, machine) = best_of(3, || on_kernel(d, p, parts, at), |r| r.0);
        println!(
            "{name} in process on the kernel: {:.1} ms wall, {pulses} axis pulses ({:.1} M pulses/s), machine time {:.3} s ({:.0}x real time)",
            wall * 1e3,
            pulses as f64 / wall / 1e6,
            machine as f64 * 1e-9,
            machine as f64 * 1e-9 / wall
        );
    }
    for (parts, record) in [(5, false), (100, false), (100, true)] {
        let (wall, pulses, machine) = best_of(3, || whole(parts, record), |r| r.0);
        println!(
            "whole `novanc run --machine citizen`, {parts} parts{}: {:.1} ms wall, {} axis pulses ({:.1} M pulses/s), machine time {:.3} s ({:.0}x real time)",
            if record { ", recorded" } else { "" },
            wall * 1e3,
            pulses,
            pulses as f64 / wall / 1e6,
            machine,
            machine / wall
        );
    }
    match idle_console(3.0) {
        Ok(p) => {
            println!("an idle Citizen console in real time, ticked every 20 ms: {p:.1} % of a core")
        }
        Err(e) => eprintln!("lathe bench: idle console: {e}"),
    }
}
