//! Recorder benchmark (prints; `cargo bench --bench record`).
//!
//! 1. The JSON encoder alone on `/nc/pulses` batches of 1,000, 2,000 and 4,000 pulses.
//! 2. The MCAP writer on one thread (encode + MCAP + file): pulses/s and MB/s written.
//! 3. The recorder thread behind its queue, paced at rising pulse rates for a few seconds each
//!    with a small queue (so a backlog cannot hide in it): the highest rate with no drop and a
//!    prompt finish is the maximum sustained rate. Then the default queue at 10 M pulses/s.
//! 4. What the Foxglove topics cost (issue 25): `novanc run programs/tableb.ap --record X`,
//!    runs alternated with and without them (`NOVANC_FOXGLOVE_SCENE=off`), with and without
//!    the pulses: the process's wall clock and CPU time (user + system), best and median.
//!    `cargo bench --bench record -- foxglove` runs this stage alone.
//!
//! Pulse times look like a real run: 11-digit ns values (a minute into the run), ~100 ns apart.

use novanc::record::json::encode_event;
use novanc::record::{Event, RecordWriter, Recorder};
use novanc::settings::MachineSettings;
use std::hint::black_box;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// Pulse batches starting a minute into the run; batch `i` of axis `i % 3`.
fn batch(i: u64, n: u64) -> Event {
    let t0 = 60_000_000_000 + i * n * 100;
    Event::Pulses {
        axis: (i % 3) as u8,
        dir: if i.is_multiple_of(2) { 1 } else { -1 },
        t_ns: (0..n).map(|k| t0 + k * 100 + (k * 7919) % 37).collect(),
    }
}

/// CPU time of the calling thread, seconds (user + system, so the file writes count).
fn thread_cpu_s() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime only writes the timespec we pass, which lives on our stack.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    if rc != 0 {
        return f64::NAN;
    }
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

/// CPU seconds (user + system) used so far by this process's thread named `recorder`.
fn recorder_thread_cpu_s() -> Option<f64> {
    // SAFETY: sysconf has no memory effects.
    let ticks = unsafe { libc::sysconf(libc::_SC_CLK_TCK) } as f64;
    for task in std::fs::read_dir("/proc/self/task").ok()?.flatten() {
        let comm = std::fs::read_to_string(task.path().join("comm")).unwrap_or_default();
        if comm.trim() != "recorder" {
            continue;
        }
        let stat = std::fs::read_to_string(task.path().join("stat")).ok()?;
        // Fields after the ")" that closes the command name: state is field 3; utime 14, stime 15.
        let rest = &stat[stat.rfind(')')? + 2..];
        let f: Vec<&str> = rest.split_whitespace().collect();
        let utime: f64 = f.get(11)?.parse().ok()?;
        let stime: f64 = f.get(12)?.parse().ok()?;
        return Some((utime + stime) / ticks);
    }
    None
}

fn temp(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("novanc-bench-{name}-{}.mcap", std::process::id()))
}

fn encoder(n: u64) {
    let events: Vec<Event> = (0..64).map(|i| batch(i, n)).collect();
    let mut out = Vec::with_capacity(1 << 20);
    let mut bytes = 0u64;
    let mut pulses = 0u64;
    let start = Instant::now();
    let cpu0 = thread_cpu_s();
    let mut rounds = 0u64;
    while start.elapsed() < Duration::from_millis(700) {
        for ev in &events {
            out.clear();
            black_box(encode_event(&mut out, black_box(ev), 0.001));
            bytes += out.len() as u64;
            pulses += n;
        }
        rounds += 1;
    }
    let s = start.elapsed().as_secs_f64();
    let cpu = thread_cpu_s() - cpu0;
    println!(
        "encoder   batch {n:>5}: {:>7.1} M pulses/s  {:>7.1} MB/s JSON  {:.1} bytes/pulse  \
         | per CPU second: {:>7.1} M pulses, {:>6.1} ns/pulse  ({rounds} rounds)",
        pulses as f64 / s / 1e6,
        bytes as f64 / s / 1e6,
        bytes as f64 / pulses as f64,
        pulses as f64 / cpu / 1e6,
        cpu * 1e9 / pulses as f64
    );
}

fn writer_alone(n: u64, total_pulses: u64) {
    let path = temp("writer");
    let events: Vec<Event> = (0..64).map(|i| batch(i, n)).collect();
    let Ok(mut w) = RecordWriter::create(&path, &MachineSettings::default()) else {
        println!("writer: cannot create {}", path.display());
        return;
    };
    let start = Instant::now();
    let cpu0 = thread_cpu_s();
    let mut pulses = 0u64;
    let mut i = 0usize;
    while pulses < total_pulses {
        w.write(&events[i % events.len()]);
        pulses += n;
        i += 1;
    }
    let out = w.finish(false, 0);
    let s = start.elapsed().as_secs_f64();
    let cpu = thread_cpu_s() - cpu0;
    let _ = std::fs::remove_file(&path);
    if let Some(e) = out.disk_error {
        println!("writer: {e}");
        return;
    }
    println!(
        "writer    batch {n:>5}: {:>7.1} M pulses/s  {:>7.1} MB/s to the file  \
         | per CPU second: {:>7.1} M pulses, {:>6.1} MB  ({} pulses, {:.0} MB, {:.2} s)",
        pulses as f64 / s / 1e6,
        out.bytes as f64 / s / 1e6,
        pulses as f64 / cpu / 1e6,
        out.bytes as f64 / cpu / 1e6,
        pulses,
        out.bytes as f64 / 1e6,
        s
    );
}

/// Paces a producer at `rate` pulses/s for `secs` through a recorder with a queue of `queue`
/// events. Returns (dropped events, seconds finish took, recorded pulses, MB written, recorder
/// thread CPU seconds until the producer stopped).
fn paced(rate: f64, secs: f64, n: u64, queue: usize) -> Option<(u64, f64, u64, f64, f64)> {
    let path = temp("paced");
    let rec = Recorder::start_with_capacity(&path, &MachineSettings::default(), queue).ok()?;
    let sink = rec.sink();
    let per_batch = Duration::from_secs_f64(n as f64 / rate);
    let batches = (rate * secs / n as f64) as u64;
    let start = Instant::now();
    for i in 0..batches {
        let ev = batch(i, n);
        let due = start + per_batch * i as u32;
        while Instant::now() < due {
            std::hint::spin_loop();
        }
        sink.send(ev);
    }
    let cpu = recorder_thread_cpu_s().unwrap_or(f64::NAN);
    let fin = Instant::now();
    let summary = rec.finish().ok()?;
    let finish_s = fin.elapsed().as_secs_f64();
    let _ = std::fs::remove_file(&path);
    Some((
        summary.dropped,
        finish_s,
        summary.pulses,
        summary.bytes as f64 / 1e6,
        cpu,
    ))
}

/// (wall, CPU) seconds of one `novanc run` of Table B recorded to a file; the CPU time is
/// the child's user + system.
fn tableb_run(scene: bool, pulses: bool) -> Option<(f64, f64)> {
    let path = temp("tableb");
    let prog = concat!(env!("CARGO_MANIFEST_DIR"), "/programs/tableb.ap");
    let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_novanc"));
    cmd.args(["run", prog, "--record"]).arg(&path);
    if !pulses {
        cmd.args(["--pulses", "off"]);
    }
    if scene {
        cmd.env_remove(novanc::record::writer::SCENE_ENV);
    } else {
        cmd.env(novanc::record::writer::SCENE_ENV, "off");
    }
    let children_cpu = || {
        // SAFETY: getrusage only writes the struct we pass, which lives on our stack.
        let mut u: libc::rusage = unsafe { std::mem::zeroed() };
        unsafe { libc::getrusage(libc::RUSAGE_CHILDREN, &mut u) };
        let tv = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
        tv(u.ru_utime) + tv(u.ru_stime)
    };
    let cpu0 = children_cpu();
    let start = Instant::now();
    let out = cmd.output().ok()?;
    let wall = start.elapsed().as_secs_f64();
    let _ = std::fs::remove_file(&path);
    out.status.success().then(|| (wall, children_cpu() - cpu0))
}

/// Stage 4: the Foxglove topics' cost on Table B's recorded run.
fn foxglove_cost(runs: usize) {
    let ms = |v: &mut Vec<f64>, best: bool| {
        v.sort_by(f64::total_cmp);
        1e3 * if best { v[0] } else { v[v.len() / 2] }
    };
    for pulses in [true, false] {
        let (mut with, mut without) = (Vec::new(), Vec::new());
        for i in 0..runs {
            for scene in [i % 2 == 0, i % 2 != 0] {
                let Some(r) = tableb_run(scene, pulses) else {
                    println!("foxglove: novanc run failed");
                    return;
                };
                if scene {
                    with.push(r)
                } else {
                    without.push(r)
                }
            }
        }
        for (k, what) in [(0, "wall"), (1, "CPU")] {
            let mut a: Vec<f64> = without
                .iter()
                .map(|r| if k == 0 { r.0 } else { r.1 })
                .collect();
            let mut b: Vec<f64> = with
                .iter()
                .map(|r| if k == 0 { r.0 } else { r.1 })
                .collect();
            let (ab, am, bb, bm) = (
                ms(&mut a, true),
                ms(&mut a, false),
                ms(&mut b, true),
                ms(&mut b, false),
            );
            println!(
                "foxglove  Table B, pulses {}: {what:>4} without best {ab:>6.0} median {am:>6.0} ms, \
                 with best {bb:>6.0} median {bm:>6.0} ms: best {:+.1} %, median {:+.1} % ({runs} runs each)",
                if pulses { "on " } else { "off" },
                (bb / ab - 1.0) * 100.0,
                (bm / am - 1.0) * 100.0
            );
        }
    }
}

fn main() {
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    println!(
        "recorder benchmark: {} CPUs, load average {}",
        std::thread::available_parallelism().map_or(0, |n| n.get()),
        load.split_whitespace()
            .take(3)
            .collect::<Vec<_>>()
            .join(" ")
    );
    // `cargo bench --bench record -- foxglove`: stage 4 alone.
    if std::env::args().any(|a| a == "foxglove") {
        foxglove_cost(15);
        return;
    }
    for n in [1_000, 2_000, 4_000] {
        encoder(n);
    }
    for n in [1_000, 4_000] {
        writer_alone(n, 100_000_000);
    }

    let n = 2_000;
    let queue = 1_024;
    let secs = 2.0;
    println!(
        "recorder thread, paced producer, batches of {n}, queue {queue} events \
         ({:.1} M pulses), {secs} s per rate:",
        (queue as u64 * n) as f64 / 1e6
    );
    let mut best = 0.0;
    for rate_m in [5.0, 10.0, 20.0, 40.0, 80.0, 160.0] {
        let Some((dropped, finish_s, pulses, mb, cpu)) = paced(rate_m * 1e6, secs, n, queue) else {
            println!("  cannot start the recorder");
            return;
        };
        let kept = dropped == 0 && finish_s < 0.25;
        println!(
            "  {rate_m:>5.0} M pulses/s: {:>9} pulses recorded, {:>6} events dropped, \
             finish {:>6.3} s, {:>6.1} MB/s, recorder thread {:>3.0} % of a CPU  {}",
            pulses,
            dropped,
            finish_s,
            mb / secs,
            cpu / secs * 100.0,
            if kept { "kept up" } else { "FELL BEHIND" }
        );
        if kept {
            best = rate_m;
        } else {
            break;
        }
    }
    println!("maximum sustained rate without drops: >= {best:.0} M pulses/s");

    let default_queue = novanc::record::DEFAULT_QUEUE_EVENTS;
    println!("recorder thread, default queue ({default_queue} events), 3 s per rate:");
    for rate_m in [10.0, 20.0, 40.0] {
        if let Some((dropped, finish_s, pulses, mb, cpu)) =
            paced(rate_m * 1e6, 3.0, n, default_queue)
        {
            println!(
                "  {rate_m:>5.0} M pulses/s: {pulses:>9} pulses recorded, {dropped:>6} events dropped, \
                 finish {finish_s:>6.3} s, {:>6.1} MB/s, recorder thread {:>3.0} % of a CPU",
                mb / 3.0,
                cpu / 3.0 * 100.0
            );
        }
    }
    foxglove_cost(15);
}
