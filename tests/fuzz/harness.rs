//! The loop that keeps looking: runs the families' cases, each family getting an equal share of
//! the time, until the budget is spent, each case under `catch_unwind` with its own seed, timed, with its peak heap counted;
//! a watchdog ends the process on a case that hangs. Failures are reported with the command
//! that replays them (`NOVANC_FUZZ_REPLAY=family:seed`).

use super::rng::{case_seed, Rng};
use std::fmt::Write as _;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// A case slower than this is a failure.
pub const SLOW: Duration = Duration::from_secs(5);

/// A case still running after this is a hang: the watchdog reports it and ends the process.
pub const HANG: Duration = Duration::from_secs(60);

/// A case whose heap grows by more than this is a failure.
pub const MEMORY: usize = 256 << 20;

/// What every case may use: the sample texts and a scratch directory.
pub struct Ctx {
    /// Sample part programs (Table B and the other programs in `programs/`).
    pub programs: Vec<String>,
    /// Sample G-code programs (`programs/*.ngc`).
    pub gcode: Vec<String>,
    /// Lathe programs (`programs/citizen/*.ngc`, `tests/golden/lathe_rs274/*.ngc`).
    pub lathe: Vec<String>,
    /// Machine descriptions (`machines/*.machine`, the remap machine of the golden tests).
    pub descriptions: Vec<String>,
    /// The sample tool tape.
    pub tape: String,
    /// The sample T-code table.
    pub tcodes: String,
    /// A directory of this run for files a case makes (removed by the case).
    pub tmp: PathBuf,
}

/// One family of generated inputs: makes a case from the generator and checks the code under
/// test with it. `Err` is a check that failed (a panic is caught by the harness).
pub struct Family {
    /// Its name, as `NOVANC_FUZZ_REPLAY` spells it.
    pub name: &'static str,
    /// Generates one case from the generator and checks it.
    pub case: fn(&mut Rng, &Ctx) -> Result<(), String>,
}

// ---- the input of the case running now, for a failure report and for the watchdog ----

static INPUT: Mutex<String> = Mutex::new(String::new());

/// Records the input of the case being run (the last call wins), so that a failure can show it.
pub fn note(what: &str, text: &str) {
    let mut s = INPUT.lock().unwrap_or_else(|p| p.into_inner());
    s.clear();
    let _ = write!(s, "{what}:\n{text}");
}

fn input() -> String {
    INPUT.lock().unwrap_or_else(|p| p.into_inner()).clone()
}

pub use super::counting::Counting;

// ---- panics ----

static PANIC: Mutex<Option<String>> = Mutex::new(None);

/// Keeps the message and place of a panic for the report instead of printing it; only a panic
/// inside a case is expected, and the report prints it with the case's seed.
fn quiet_panics() {
    std::panic::set_hook(Box::new(|info| {
        let msg = info
            .payload()
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| info.payload().downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "(no message)".to_string());
        let at = info
            .location()
            .map(|l| format!(" at {}:{}", l.file(), l.line()))
            .unwrap_or_default();
        *PANIC.lock().unwrap_or_else(|p| p.into_inner()) = Some(format!("{msg}{at}"));
    }));
}

// ---- the run ----

/// One failed case.
#[derive(Clone, Debug)]
pub struct Failure {
    /// The family.
    pub family: &'static str,
    /// The case's seed.
    pub seed: u64,
    /// What went wrong.
    pub what: String,
    /// Where the case's whole input was written.
    pub input_file: PathBuf,
}

/// Figures of one family.
#[derive(Clone, Debug, Default)]
pub struct Tally {
    /// Cases run.
    pub cases: u64,
    /// Time spent in them.
    pub time: Duration,
    /// The slowest case: (time, seed).
    pub slowest: (Duration, u64),
    /// The largest heap growth of a case, bytes.
    pub peak: usize,
}

/// What a run found.
pub struct Report {
    /// Per family, in the order given.
    pub tallies: Vec<(&'static str, Tally)>,
    /// The failures (at most 20 kept).
    pub failures: Vec<Failure>,
    /// Wall time of the run.
    pub elapsed: Duration,
    /// The base seed.
    pub base: u64,
}

impl Report {
    /// The figures as a table, and the failures with their replay commands.
    pub fn text(&self) -> String {
        let mut s = String::new();
        let total: u64 = self.tallies.iter().map(|t| t.1.cases).sum();
        let _ = writeln!(
            s,
            "fuzz: {total} cases in {:.1} s, base seed {:#x}",
            self.elapsed.as_secs_f64(),
            self.base
        );
        let _ = writeln!(
            s,
            "{:<18} {:>9} {:>10} {:>12} {:>20} {:>10}",
            "family", "cases", "time", "mean", "slowest (seed)", "peak heap"
        );
        for (name, t) in &self.tallies {
            let mean = t.time.as_secs_f64() * 1e3 / t.cases.max(1) as f64;
            let _ = writeln!(
                s,
                "{name:<18} {:>9} {:>8.1} s {:>9.3} ms {:>9.1} ms {:#018x} {:>7.1} MB",
                t.cases,
                t.time.as_secs_f64(),
                mean,
                t.slowest.0.as_secs_f64() * 1e3,
                t.slowest.1,
                t.peak as f64 / 1e6
            );
        }
        for f in &self.failures {
            let _ = writeln!(
                s,
                "FAILED {}:{:#x}: {}\n  input: {}\n  replay: NOVANC_FUZZ_REPLAY={}:{:#x} cargo test --release --test fuzz replay -- --nocapture",
                f.family,
                f.seed,
                f.what,
                f.input_file.display(),
                f.family,
                f.seed
            );
        }
        s
    }
}

/// Runs one case: Ok(time, heap growth) or the failure's description.
fn one(family: &Family, seed: u64, ctx: &Ctx) -> (Duration, usize, Option<String>) {
    note("(no input noted)", "");
    *PANIC.lock().unwrap_or_else(|p| p.into_inner()) = None;
    let mark = Counting::mark();
    let t = Instant::now();
    let r = catch_unwind(AssertUnwindSafe(|| (family.case)(&mut Rng::new(seed), ctx)));
    let took = t.elapsed();
    let peak = mark.peak();
    let what = match r {
        Ok(Ok(())) if took > SLOW => Some(format!("slow: {took:?} (limit {SLOW:?})")),
        Ok(Ok(())) if peak > MEMORY => Some(format!("memory: the heap grew by {peak} bytes")),
        Ok(Ok(())) => None,
        Ok(Err(e)) => Some(format!("check failed: {e}")),
        Err(_) => {
            let p = PANIC.lock().unwrap_or_else(|p| p.into_inner()).take();
            Some(format!("panic: {}", p.unwrap_or_default()))
        }
    };
    (took, peak, what)
}

fn save_input(ctx: &Ctx, family: &str, seed: u64) -> PathBuf {
    let p = std::env::temp_dir().join(format!("novanc-fuzz-{family}-{seed:#x}.txt"));
    let _ = std::fs::write(&p, input());
    let _ = &ctx.tmp;
    p
}

/// Runs the families for `budget` from base seed `base`, an equal share of time each.
pub fn run(families: &[Family], ctx: &Ctx, budget: Duration, base: u64) -> Report {
    quiet_panics();
    let current: Arc<Mutex<(usize, u64, Instant)>> = Arc::new(Mutex::new((0, 0, Instant::now())));
    let done = Arc::new(AtomicBool::new(false));
    let watchdog = {
        let (current, done) = (current.clone(), done.clone());
        let names: Vec<&'static str> = families.iter().map(|f| f.name).collect();
        std::thread::spawn(move || {
            while !done.load(Ordering::Relaxed) {
                std::thread::sleep(Duration::from_millis(200));
                let (f, seed, started) = *current.lock().unwrap_or_else(|p| p.into_inner());
                if started.elapsed() > HANG && !done.load(Ordering::Relaxed) {
                    let p = std::env::temp_dir()
                        .join(format!("novanc-fuzz-{}-{seed:#x}.txt", names[f]));
                    let _ = std::fs::write(&p, input());
                    eprintln!(
                        "FAILED {}:{seed:#x}: hangs (still running after {HANG:?}); input in {}\n  replay: NOVANC_FUZZ_REPLAY={}:{seed:#x} cargo test --release --test fuzz replay -- --nocapture",
                        names[f],
                        p.display(),
                        names[f]
                    );
                    std::process::exit(101);
                }
            }
        })
    };
    let start = Instant::now();
    let mut tallies: Vec<(&'static str, Tally)> = families
        .iter()
        .map(|f| (f.name, Tally::default()))
        .collect();
    let mut failures = Vec::new();
    let mut index = 0u64;
    while start.elapsed() < budget {
        // Each family gets an equal share of the time: the one that has had least goes next.
        let fi = (0..families.len())
            .min_by_key(|&i| tallies[i].1.time)
            .unwrap_or(0);
        let seed = case_seed(base, index);
        *current.lock().unwrap_or_else(|p| p.into_inner()) = (fi, seed, Instant::now());
        let (took, peak, what) = one(&families[fi], seed, ctx);
        let t = &mut tallies[fi].1;
        t.cases += 1;
        t.time += took;
        if took > t.slowest.0 {
            t.slowest = (took, seed);
        }
        t.peak = t.peak.max(peak);
        if let Some(what) = what {
            if failures.len() < 20 {
                failures.push(Failure {
                    family: families[fi].name,
                    seed,
                    what,
                    input_file: save_input(ctx, families[fi].name, seed),
                });
            }
        }
        index += 1;
    }
    done.store(true, Ordering::Relaxed);
    let _ = watchdog.join();
    let _ = std::panic::take_hook();
    Report {
        tallies,
        failures,
        elapsed: start.elapsed(),
        base,
    }
}

/// Runs one case again and prints its input and what happened (`NOVANC_FUZZ_REPLAY`).
pub fn replay(families: &[Family], ctx: &Ctx, name: &str, seed: u64) -> Option<String> {
    quiet_panics();
    let family = families.iter().find(|f| f.name == name)?;
    let (took, peak, what) = one(family, seed, ctx);
    let _ = std::panic::take_hook();
    Some(format!(
        "{}\n--- {name}:{seed:#x}: {took:?}, heap +{peak} bytes: {}",
        input(),
        what.unwrap_or_else(|| "ok".to_string())
    ))
}

/// A reader's refusal as every G-code family checks it: at a real place of a program of
/// `lines` lines, with a short message and no raw control character.
pub fn check_refusal(e: &novanc::block::TranslateError, lines: u32) -> Result<(), String> {
    let text = e.to_string();
    if e.line < 1 || e.line > lines || e.col < 1 {
        return Err(format!("the refusal names no real place: {text}"));
    }
    if e.message.trim().is_empty() || text.chars().count() > 300 {
        return Err(format!("the message is empty or long: {text}"));
    }
    if text.chars().any(|c| c.is_control()) {
        return Err(format!("a control character printed raw: {text:?}"));
    }
    Ok(())
}
