//! Pulse core benchmarks that print (issue 4): axis pulses per second in virtual time on a long
//! 3-axis contour with recording off and on, and real-time pacing at 200,000 pulses/s; and
//! (issue 12) the same contour with both interpolators: pulses/s, machine time, the largest
//! deviation from the programmed path, and the whole `novanc run` process on it.
//!
//! Run with `cargo bench --bench pulses` (`-- interp` for the interpolator comparison only).

use novanc::pulse_core::testkit::{polyline, Rng};
use novanc::pulse_core::{ClockMode, Command, Machine, MakeRun, PulseCore, RunKind, VecSource};
use novanc::record::{Event, EventSink, Recorder};
use novanc::settings::{Interpolator, MachineSettings};
use novanc::translator::Statement;
use std::time::{Duration, Instant};

const MID: [i64; 3] = [500_000, 400_000, -300_000];

/// A long 3-axis contour: `n` blocks zigzagging about the middle of the travel, 10–30 mm out
/// in X and Y and 3–10 mm in Z from it (so about 20–60 mm and 6–20 mm per block).
fn contour(n: usize, feed: f64) -> Vec<novanc::block::Block> {
    polyline(&contour_points(n), feed)
}

fn contour_points(n: usize) -> Vec<[i64; 3]> {
    let mut rng = Rng::new(42);
    let mut pts = vec![MID];
    for i in 0..n {
        let s = if i % 2 == 0 { 1 } else { -1 };
        pts.push([
            MID[0] + s * rng.range(10_000, 30_000),
            MID[1] - s * rng.range(10_000, 30_000),
            MID[2] + s * rng.range(3_000, 10_000),
        ]);
    }
    pts
}

/// The same contour as an ISO program for `novanc run` (1 µm pulses, machine coordinates):
/// a rapid to its start, then the `n` feed blocks.
fn contour_program(n: usize, feed: f64) -> std::path::PathBuf {
    let mm = |p: i64| format!("{:.3}", p as f64 / 1000.0);
    let pts = contour_points(n);
    let mut text = String::from("%\nG21 G90 G17\n");
    text += &format!(
        "G00 X{} Y{} Z{}\n",
        mm(pts[0][0]),
        mm(pts[0][1]),
        mm(pts[0][2])
    );
    for (i, p) in pts[1..].iter().enumerate() {
        text += &format!("G01 X{} Y{} Z{}", mm(p[0]), mm(p[1]), mm(p[2]));
        if i == 0 {
            text += &format!(" F{feed}");
        }
        text += "\n";
    }
    text += "M30\n%\n";
    let path = std::env::temp_dir().join(format!("novanc-contour-{}.ngc", std::process::id()));
    std::fs::write(&path, text).expect("write the contour program");
    path
}

/// A program source of one statement.
fn once(stmt: Statement) -> MakeRun {
    Box::new(move |_| Box::new(std::iter::once(Ok(stmt))))
}

fn total(m: &Machine) -> u64 {
    m.status().pulses.iter().sum()
}

fn virtual_off(blocks: &[novanc::block::Block]) -> (u64, f64, f64) {
    virtual_off_with(blocks, MachineSettings::default())
}

/// CPU time of this thread, seconds (the machine is shared: wall time counts other builds).
fn thread_cpu() -> f64 {
    // SAFETY: a zeroed timespec is valid and clock_gettime fills it.
    let mut ts: libc::timespec = unsafe { std::mem::zeroed() };
    // SAFETY: valid pointer to our own timespec.
    unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

fn virtual_off_with(blocks: &[novanc::block::Block], s: MachineSettings) -> (u64, f64, f64) {
    let mut m = Machine::new(s);
    m.set_position(MID);
    let mut src = VecSource::from_blocks(blocks.to_vec());
    m.command(Command::Start(RunKind::Auto));
    let t = Instant::now();
    m.run_until_idle(&mut src, u64::MAX / 4);
    let st = m.status();
    assert!(
        st.alarm.is_none() && st.blocks_done == blocks.len() as u64,
        "{:?}",
        st.alarm
    );
    (total(&m), t.elapsed().as_secs_f64(), m.now() as f64 * 1e-9)
}

/// Recording on, the core's side only: every event into a channel drained by a thread.
fn virtual_sink(blocks: &[novanc::block::Block]) -> (u64, f64, u64, bool) {
    let (tx, rx) = std::sync::mpsc::sync_channel::<Event>(1 << 16);
    let drain = std::thread::spawn(move || {
        let mut n = 0u64;
        for ev in rx {
            if let Event::Pulses { t_ns, .. } = ev {
                n += t_ns.len() as u64;
            }
        }
        n
    });
    let sink = EventSink::new(tx);
    let mut m = Machine::new(MachineSettings::default());
    m.set_position(MID);
    m.set_recording(Some(sink.clone()), false);
    m.set_lossless_recording(true);
    let mut src = VecSource::from_blocks(blocks.to_vec());
    m.command(Command::Start(RunKind::Auto));
    let t = Instant::now();
    m.run_until_idle(&mut src, u64::MAX / 4);
    let secs = t.elapsed().as_secs_f64();
    let n = total(&m);
    let incomplete = sink.is_incomplete();
    drop(m);
    drop(sink);
    let recorded = drain.join().unwrap_or(0);
    (n, secs, recorded, incomplete)
}

/// Recording on, end to end: the pulse core thread and the MCAP recorder writing a file.
fn virtual_mcap(blocks: &[novanc::block::Block]) -> (u64, f64, String) {
    let s = MachineSettings::default();
    let path = std::env::temp_dir().join(format!("novanc-bench-{}.mcap", std::process::id()));
    let rec = match Recorder::start(&path, &s) {
        Ok(r) => r,
        Err(e) => return (0, 0.0, e),
    };
    let core = PulseCore::spawn(s, ClockMode::Virtual, Some(rec.sink()));
    core.set_position(MID);
    let stmt = Statement {
        line: 1,
        text: "contour".into(),
        blocks: blocks.to_vec(),
    };
    let t = Instant::now();
    core.start(RunKind::Auto, Some(once(stmt)));
    let st = core.wait_idle(Duration::from_secs(600));
    drop(core);
    let line = match rec.finish() {
        Ok(sum) => sum.to_string(),
        Err(e) => e,
    };
    let secs = t.elapsed().as_secs_f64();
    let _ = std::fs::remove_file(&path);
    (st.map_or(0, |s| s.pulses.iter().sum()), secs, line)
}

fn realtime(seconds: f64) {
    let s = MachineSettings::default();
    let core = PulseCore::spawn(s.clone(), ClockMode::RealTime, None);
    let start = [0, 400_000, -300_000];
    core.set_position(start);
    // 12 m/min on X = 200,000 pulses/s at 1 µm
    let len = (200_000.0 * seconds) as i64;
    let b = novanc::pulse_core::testkit::block(
        1,
        novanc::block::Motion::Rapid,
        start,
        [len, 0, 0],
        0.0,
    );
    let stmt = Statement {
        line: 1,
        text: "GD".into(),
        blocks: vec![b],
    };
    let t = Instant::now();
    core.start(RunKind::Auto, Some(once(stmt)));
    let st = core.wait_idle(Duration::from_secs(600));
    let wall = t.elapsed().as_secs_f64();
    let rt = core.realtime_stats();
    let late_at: Vec<usize> = rt
        .lateness_ns
        .iter()
        .enumerate()
        .filter(|(_, &x)| x > 0)
        .map(|(i, _)| i)
        .take(10)
        .collect();
    let mut l = rt.lateness_ns.clone();
    l.sort_unstable();
    let q = |f: f64| {
        l.get(((l.len() as f64 - 1.0) * f) as usize)
            .copied()
            .unwrap_or(0)
    };
    println!(
        "real time, X at 12 m/min (200,000 pulses/s), {} pulses in {:.3} s wall ({:.3} s machine):",
        st.as_ref().map_or(0, |s| s.pulses[0]),
        wall,
        st.as_ref().map_or(0.0, |s| s.machine_ns as f64 * 1e-9)
    );
    println!(
        "  slice lateness vs wall clock (negative = generated ahead): median {:.3} ms, p99 {:.3} ms, max {:.3} ms over {} slices",
        q(0.5) as f64 * 1e-6,
        q(0.99) as f64 * 1e-6,
        l.last().copied().unwrap_or(0) as f64 * 1e-6,
        l.len()
    );
    println!(
        "  queue ran dry: {} ({} slices finished after their start time; first late slices: {:?})",
        if rt.dry > 0 { "yes" } else { "no" },
        rt.dry,
        late_at
    );
}

/// Distance of `p` from the segment `a`–`b`, pulses.
fn off_segment(p: [i64; 3], a: [i64; 3], b: [i64; 3]) -> f64 {
    let d: Vec<f64> = (0..3).map(|i| (b[i] - a[i]) as f64).collect();
    let v: Vec<f64> = (0..3).map(|i| (p[i] - a[i]) as f64).collect();
    let dd: f64 = d.iter().map(|x| x * x).sum();
    let k = if dd > 0.0 {
        (v.iter().zip(&d).map(|(x, y)| x * y).sum::<f64>() / dd).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (0..3)
        .map(|i| (v[i] - k * d[i]).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// The largest distance of the tool (after all the pulses of each instant) from the block it
/// is executing, over `blocks`, pulses.
fn deviation(blocks: &[novanc::block::Block], s: MachineSettings) -> f64 {
    let mut m = Machine::new(s);
    m.set_position(MID);
    m.set_recording(None, true);
    let mut src = VecSource::from_blocks(blocks.to_vec());
    m.command(Command::Start(RunKind::Auto));
    m.run_until_idle(&mut src, u64::MAX / 4);
    let pulses = m.take_pulses();
    let (mut pos, mut i, mut worst, mut k) = (MID, 0usize, 0.0f64, 0usize);
    while k < pulses.len() && i < blocks.len() {
        let t = pulses[k].t_ns;
        while k < pulses.len() && pulses[k].t_ns == t {
            pos[pulses[k].axis as usize] += pulses[k].dir as i64;
            k += 1;
        }
        let b = &blocks[i];
        worst = worst.max(off_segment(pos, b.start().xyz(), b.end.xyz()));
        if pos == b.end {
            i += 1;
        }
    }
    worst
}

/// `novanc run --interpolator I` on the program: wall seconds, and its summary.
fn whole_run(path: &std::path::Path, interp: &str) -> (f64, String) {
    let t = Instant::now();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_novanc"))
        .arg("run")
        .arg(path)
        .arg("--interpolator")
        .arg(interp)
        .output();
    let secs = t.elapsed().as_secs_f64();
    match out {
        Ok(o) => (secs, String::from_utf8_lossy(&o.stdout).into_owned()),
        Err(e) => (secs, e.to_string()),
    }
}

/// `novanc run`'s summary: the axis pulses in all, and its machine time line.
fn run_summary(out: &str) -> (u64, &str) {
    let pulses = out
        .lines()
        .find(|l| l.starts_with("pulses:"))
        .map(|l| {
            l.split_whitespace()
                .filter_map(|w| w.parse::<u64>().ok())
                .sum()
        })
        .unwrap_or(0);
    let mt = out
        .lines()
        .find(|l| l.starts_with("machine time:"))
        .unwrap_or("machine time: ?");
    (pulses, mt)
}

/// Both interpolators on the same contour (issue 12).
fn interpolators(blocks: &[novanc::block::Block]) {
    println!("interpolators on the 3000-block contour at F10000 (virtual time, recording off):");
    for interp in [Interpolator::Dda, Interpolator::ErrorProportional] {
        let s = MachineSettings {
            interpolator: interp,
            ..MachineSettings::default()
        };
        let (mut best, mut n, mut ms, mut best_cpu) = (0.0f64, 0, 0.0, 0.0f64);
        for _ in 0..3 {
            let c0 = thread_cpu();
            let (p, secs, m) = virtual_off_with(blocks, s.clone());
            best_cpu = best_cpu.max(p as f64 / (thread_cpu() - c0));
            best = best.max(p as f64 / secs);
            n = p;
            ms = m;
        }
        let dev = deviation(&blocks[..100], s.clone());
        println!(
            "  {:<18} {:>6.1} M axis pulses/s (best of 3; {:.1} M per CPU second), {} pulses, {:.0} s of machine time; largest deviation from the path {:.3} pulses (first 100 blocks)",
            interp.name(),
            best / 1e6,
            best_cpu / 1e6,
            n,
            ms,
            dev
        );
    }
    // The whole process on the same contour (an ISO program; the rapid to its start adds
    // pulses and machine time), then on the sample programs.
    let prog = contour_program(3000, 10_000.0);
    for interp in ["dda", "error-proportional"] {
        let (mut best, mut out) = (f64::MAX, String::new());
        for _ in 0..3 {
            let (secs, o) = whole_run(&prog, interp);
            if secs < best {
                (best, out) = (secs, o);
            }
        }
        let (pulses, mt) = run_summary(&out);
        println!(
            "  whole `novanc run contour.ngc --interpolator {interp}` process (the same contour, best of 3): {best:.2} s wall, {pulses} axis pulses ({:.1} M/s), {mt}",
            pulses as f64 / best / 1e6
        );
    }
    let _ = std::fs::remove_file(&prog);
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("programs");
    for prog in ["tableb.ap", "bracket.ap", "geometry.ap"] {
        for interp in ["dda", "error-proportional"] {
            let (secs, out) = whole_run(&dir.join(prog), interp);
            let (pulses, mt) = run_summary(&out);
            println!(
                "  whole `novanc run {prog} --interpolator {interp}` process: {secs:.2} s wall, {pulses} axis pulses ({:.1} M/s), {mt}",
                pulses as f64 / secs / 1e6
            );
        }
    }
}

fn main() {
    let blocks = contour(3000, 10_000.0);
    let only_interp = std::env::args().any(|a| a == "interp");
    interpolators(&blocks);
    if only_interp {
        return;
    }
    println!("pulse core benchmarks (virtual time, 3000-block 3-axis contour at F10000)");
    let mut best = 0.0f64;
    let mut n = 0;
    let mut machine_s = 0.0;
    for _ in 0..3 {
        let (p, secs, ms) = virtual_off(&blocks);
        best = best.max(p as f64 / secs);
        n = p;
        machine_s = ms;
    }
    println!(
        "recording off: {:.1} M axis pulses/s ({} pulses, {:.0} s of machine time; best of 3)",
        best / 1e6,
        n,
        machine_s
    );
    let (p, secs, recorded, inc) = virtual_sink(&blocks);
    println!(
        "recording on, core side (every pulse into the event queue, drained by a thread): {:.1} M axis pulses/s ({} recorded of {}, incomplete: {inc})",
        p as f64 / secs / 1e6,
        recorded,
        p
    );
    let (p, secs, line) = virtual_mcap(&blocks[..500]);
    println!(
        "recording on, end to end (pulse core thread + MCAP recorder to a file, lossless; first 500 blocks): {:.1} M axis pulses/s",
        p as f64 / secs / 1e6
    );
    println!("  {line}");
    realtime(3.0);
}
