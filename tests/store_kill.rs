//! Crash safety: a child process edits the stores and prints `ack K` after each acknowledged
//! change; the parent kills it with SIGKILL at a random moment, reopens the stores and checks
//! that every acknowledged change is there (and nothing that was never attempted).
//!
//! The child is this same test binary, run with `CHILD_DIR` set, executing `child_session`.

use novanc::store::{Stores, Target};
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const CHILD_DIR: &str = "NOVANC_KILL_TEST_DIR";
const CHILD_FROM: &str = "NOVANC_KILL_TEST_FROM";
const CHILD_LIMIT: &str = "NOVANC_KILL_TEST_LIMIT";

/// splitmix64: the seeded PRNG of this test.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
}

/// Kinds of change, by `k % KINDS`: 0, 1 a program line; 2 an MDI line; 3 a T-code setting;
/// 4 a tool-file revision of T02's speed.
const KINDS: u64 = 5;

/// The change number `k` makes.
fn apply(s: &mut Stores, k: u64) -> Result<(), String> {
    match k % KINDS {
        0 | 1 => s
            .edit(Target::Program, &format!("IE{k}*"), None)
            .map(|_| ())
            .map_err(|e| e.to_string()),
        2 => s
            .edit(Target::Mdi, &format!("IM{k}*"), None)
            .map(|_| ())
            .map_err(|e| e.to_string()),
        3 => s.set_tcode(21, Some(10_000 + k as u32)),
        _ => s
            .edit(
                Target::ToolFile,
                &format!("-99LLKIT02 00106 DR 6.2 150 40 {k} 120 3*"),
                None,
            )
            .map(|_| ())
            .map_err(|e| e.to_string()),
    }
}

/// The child: applies changes from `CHILD_FROM` on, printing `ack K` after each one.
#[test]
fn child_session() {
    let Some(dir) = std::env::var_os(CHILD_DIR) else {
        return; // run as a normal test: nothing to do
    };
    let num = |k: &str| {
        std::env::var(k)
            .ok()
            .and_then(|v| v.parse::<u64>().ok())
            .unwrap_or(0)
    };
    let (mut s, _) = Stores::open(Path::new(&dir), 24).unwrap();
    s.set_journal_limit(num(CHILD_LIMIT) as usize);
    let from = num(CHILD_FROM);
    let start = Instant::now();
    let mut out = std::io::stdout().lock();
    for k in from..from + 100_000 {
        if start.elapsed() > Duration::from_secs(20) {
            break; // the parent is gone
        }
        apply(&mut s, k).unwrap();
        writeln!(out, "\nack {k}").unwrap();
        out.flush().unwrap();
    }
}

/// What the reopened stores hold: the change numbers found, the T21 tool, T02's speed.
fn found(s: &Stores) -> (Vec<u64>, Vec<u64>, Option<u64>, Option<u64>) {
    let nums = |t: Target, p: char| -> Vec<u64> {
        s.buffer(t)
            .text()
            .lines()
            .filter_map(|l| l.strip_prefix(p)?.parse().ok())
            .collect()
    };
    (
        nums(Target::Program, 'E'),
        nums(Target::Mdi, 'M'),
        s.magazine().tcodes.tool_in(21).map(|n| n as u64 - 10_000),
        s.magazine().find(106).ok().map(|(_, r)| r.speed as u64),
    )
}

#[test]
fn kill_9_mid_session_loses_no_acknowledged_change() {
    let dir: PathBuf = Path::new(env!("CARGO_TARGET_TMPDIR")).join("store-kill");
    let _ = std::fs::remove_dir_all(&dir);
    {
        let (mut s, _) = Stores::open(&dir, 24).unwrap();
        s.new_program("KILL").unwrap();
    }
    let exe = std::env::current_exe().unwrap();
    let seed = std::env::var("NOVANC_KILL_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0x5EED_0002);
    let mut rng = Rng(seed);
    let mut torn = 0;
    let mut flights = 0;
    let mut next = 0u64;
    let mut total_acks = 0;
    for round in 0..8 {
        let limit = if round % 2 == 0 { 4096 } else { 5 };
        let mut child = Command::new(&exe)
            .args([
                "--exact",
                "child_session",
                "--nocapture",
                "--test-threads=1",
            ])
            .env(CHILD_DIR, &dir)
            .env(CHILD_FROM, next.to_string())
            .env(CHILD_LIMIT, limit.to_string())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
        let ack = |l: &str| l.strip_prefix("ack ").and_then(|n| n.parse::<u64>().ok());
        let want = 1 + rng.below(120);
        let mut acked = Vec::new();
        for l in lines.by_ref() {
            if let Some(k) = ack(&l.unwrap()) {
                acked.push(k);
                if acked.len() as u64 >= want {
                    break;
                }
            }
        }
        std::thread::sleep(Duration::from_micros(rng.below(3000)));
        child.kill().unwrap(); // SIGKILL
        for l in lines {
            if let Some(k) = l.ok().as_deref().and_then(ack) {
                acked.push(k);
            }
        }
        let _ = child.wait();
        assert!(
            !acked.is_empty(),
            "round {round}: the child acknowledged nothing"
        );
        let last = *acked.last().unwrap();
        assert_eq!(acked, (next..=last).collect::<Vec<_>>(), "round {round}");
        total_acks += acked.len();

        let (s, warnings) = Stores::open(&dir, 24).unwrap();
        torn += warnings.len();
        for w in &warnings {
            // A torn tail is allowed (the change being written when killed); nothing else.
            assert!(w.contains("journal record"), "round {round}: {w}");
        }
        let (prog, mdi, t21, speed) = found(&s);
        let upto = |n: u64, kinds: &[u64]| -> Vec<u64> {
            (next..=n)
                .filter(|k| kinds.contains(&(k % KINDS)))
                .collect()
        };
        let from = |v: &[u64]| -> Vec<u64> { v.iter().copied().filter(|&k| k >= next).collect() };
        // Every acknowledged change is there, in order; at most the one in flight beyond.
        let (p, m) = (from(&prog), from(&mdi));
        assert!(
            p == upto(last, &[0, 1]) || p == upto(last + 1, &[0, 1]),
            "round {round}: {p:?}"
        );
        assert!(
            m == upto(last, &[2]) || m == upto(last + 1, &[2]),
            "round {round}: {m:?}"
        );
        // For the settings that hold one value: the last acknowledged, or the one in flight.
        let latest = |n: u64, kind: u64| (0..=n).rev().find(|k| k % KINDS == kind);
        for (kind, got, initial) in [(3, t21, None), (4, speed, Some(1200))] {
            let acked = latest(last, kind).or(initial);
            let flight = latest(last + 1, kind).filter(|&k| k == last + 1);
            assert!(
                got == acked || (flight.is_some() && got == flight),
                "round {round}: kind {kind} holds {got:?}, last acknowledged {acked:?}"
            );
        }
        let in_flight = p.contains(&(last + 1))
            || m.contains(&(last + 1))
            || [t21, speed].contains(&Some(last + 1));
        flights += in_flight as usize;
        next = if in_flight { last + 2 } else { last + 1 };
    }
    eprintln!("kill test (seed {seed}): {total_acks} acknowledged changes over 8 kills, {torn} torn tails, {flights} kills between journal and ack");
}
