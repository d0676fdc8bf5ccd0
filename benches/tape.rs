//! Tape reading speed (docs/tape.md, "Speed"): a generated program of about 100 MB punched in
//! ISO and in EIA, decoded in-process (`tape::read_image`, best of 5) and by a whole
//! `novanc tape read IMAGE` process with its text going to /dev/null (best of 3, the file in the
//! page cache). Target: 100 MB/s. Prints MB/s of image.
//!
//! Then PROGRAM READ of a 30 MB plain text file at the console (issue 23: a text file is read
//! at file speed; target under 1 s): in-process from START to the program stored (best of 3,
//! a fresh state directory each time), and a whole `novanc script` process that puts the file
//! in the reader, reads it and ends.
//! Run: `cargo bench --bench tape`.

use novanc::tape::{self, Code, PunchOptions, ReadOptions};
use std::process::{Command, Stdio};
use std::time::Instant;

/// Image size to aim for, bytes.
const TARGET_BYTES: usize = 100_000_000;

/// G-code-like blocks with a comment now and then (small letters: EIA case shifts).
fn program(bytes: usize) -> String {
    let mut s = String::with_capacity(bytes + 100);
    let mut n = 0u64;
    while s.len() < bytes {
        n += 1;
        let x = (n * 7919) % 400_000;
        let y = (n * 104_729) % 300_000;
        s += &format!(
            "N{n} G01 X{}.{:03} Y-{}.{:03} Z-{}.5 F{}",
            x / 1000,
            x % 1000,
            y / 1000,
            y % 1000,
            n % 40,
            100 + n % 900
        );
        if n.is_multiple_of(10) {
            s += " ; pass over the pocket";
        }
        s.push('\n');
    }
    s
}

fn mb(bytes: usize, secs: f64) -> f64 {
    bytes as f64 / secs / 1e6
}

fn main() {
    let cpus = std::thread::available_parallelism().map_or(0, |n| n.get());
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    let load: Vec<&str> = load.split_whitespace().take(3).collect();
    println!(
        "tape benchmark: {cpus} CPUs, load average {}",
        load.join(" ")
    );
    let text = program(TARGET_BYTES * 9 / 10);
    for code in [Code::Iso, Code::Eia] {
        let opts = PunchOptions {
            code,
            leader: 100,
            label: Some("BENCH".into()),
        };
        let t = Instant::now();
        let image = match tape::punch(&text, &opts) {
            Ok(i) => i,
            Err(e) => {
                eprintln!("cannot punch the generated program: {e}");
                std::process::exit(1);
            }
        };
        let punch_s = t.elapsed().as_secs_f64();
        // In-process, best of 5, block parity checked.
        let mut best = f64::MAX;
        let mut blocks = 0;
        for _ in 0..5 {
            let t = Instant::now();
            let r = tape::read_image(&image, ReadOptions { block_parity: true });
            let dt = t.elapsed().as_secs_f64();
            match r {
                Ok(tape) if tape.text.len() == text.len() => {
                    best = best.min(dt);
                    blocks = tape.blocks;
                }
                Ok(_) => {
                    eprintln!("the text read differs from the text punched");
                    std::process::exit(1);
                }
                Err(e) => {
                    eprintln!("{e}");
                    std::process::exit(1);
                }
            }
        }
        // Whole process: read the file, decode, write the text to /dev/null.
        let path = std::env::temp_dir().join(format!(
            "novanc-bench-{}.{}",
            std::process::id(),
            code.name()
        ));
        if let Err(e) = std::fs::write(&path, &image) {
            eprintln!("cannot write {}: {e}", path.display());
            std::process::exit(1);
        }
        let best_proc = best_process("novanc tape read", |_| {
            let mut c = Command::new(env!("CARGO_BIN_EXE_novanc"));
            c.args(["tape", "read"]).arg(&path);
            c
        });
        let _ = std::fs::remove_file(&path);
        println!(
            "{}: image {:.1} MB ({} frames, {blocks} blocks), text {:.1} MB; punch {:.0} MB/s; read in-process {:.0} MB/s ({:.3} s); `novanc tape read` process {:.0} MB/s ({:.3} s)",
            code.name(),
            image.len() as f64 / 1e6,
            image.len(),
            text.len() as f64 / 1e6,
            mb(image.len(), punch_s),
            mb(image.len(), best),
            best,
            mb(image.len(), best_proc),
            best_proc
        );
    }
    program_read(&program(30_000_000));
}

/// PROGRAM READ of a plain text file at the console, in-process and as a whole process.
fn program_read(text: &str) {
    use novanc::console::{Console, ConsoleConfig};
    use novanc::panel_model::PanelEvent as E;
    use novanc::panel_model::{DataMode, OpMode};
    use novanc::pulse_core::ClockMode;
    let base = std::env::temp_dir().join(format!("novanc-bench-read-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&base);
    std::fs::create_dir_all(&base).expect("temp dir");
    let path = base.join("CAM30MB.NGC");
    std::fs::write(&path, text).expect("write the program");
    let mut best = f64::MAX;
    for i in 0..3 {
        let mut cfg = ConsoleConfig::new(base.join(format!("state{i}")));
        cfg.clock = ClockMode::Virtual;
        let (mut c, _) = Console::open(cfg).expect("console");
        c.handle(E::Op(OpMode::Data));
        c.handle(E::Data(DataMode::Read));
        c.handle(E::Tape(path.clone()));
        let t = Instant::now();
        c.handle(E::Start);
        let dt = t.elapsed().as_secs_f64();
        if c.program_text().len() + 1 < text.len() {
            eprintln!(
                "PROGRAM READ stored {} of {} bytes",
                c.program_text().len(),
                text.len()
            );
            std::process::exit(1);
        }
        best = best.min(dt);
    }
    let script = base.join("read.script");
    std::fs::write(
        &script,
        format!("op DATA\ndata READ\ntape {}\nstart\nwait\n", path.display()),
    )
    .expect("write the script");
    let best_proc = best_process("novanc script", |i| {
        let mut c = Command::new(env!("CARGO_BIN_EXE_novanc"));
        c.arg("script")
            .arg(&script)
            .arg("--state")
            .arg(base.join(format!("proc{i}")));
        c
    });
    let _ = std::fs::remove_dir_all(&base);
    println!(
        "PROGRAM READ of a {:.1} MB text file ({} lines) at the console: in-process {:.3} s (START to stored); whole `novanc script` process {:.3} s (target under 1 s)",
        text.len() as f64 / 1e6,
        text.lines().count(),
        best,
        best_proc
    );
}

/// The best of three whole processes, seconds: `make(i)` builds the i-th command (output to
/// /dev/null); a failure ends the benchmark.
fn best_process(what: &str, make: impl Fn(usize) -> Command) -> f64 {
    let mut best = f64::MAX;
    for i in 0..3 {
        let t = Instant::now();
        let st = make(i).stdout(Stdio::null()).stderr(Stdio::null()).status();
        let dt = t.elapsed().as_secs_f64();
        match st {
            Ok(s) if s.success() => best = best.min(dt),
            other => {
                eprintln!("{what} failed: {other:?}");
                std::process::exit(1);
            }
        }
    }
    best
}
