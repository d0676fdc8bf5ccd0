//! Crash safety by command: a child process makes mixed changes to the stores (program edits,
//! MDI, tool-file revisions, T-code settings, PROGRAM READ, TOOL DATA READ, SEARCH, new and
//! deleted programs, work offsets, the interpreter's parameters: G92, the system in force, G28
//! homes, rotations) and prints `ack K` after each acknowledged one (`nak K` after a refused
//! one); the parent kills it with SIGKILL at a random moment, reopens the stores and compares
//! them with a reference that made the same changes without being killed. Every acknowledged
//! change must be there, in order, and nothing beyond the one in flight.
//!
//! The child is this same test binary, run with `NOVANC_KILL_TEST_DIR` set, executing
//! `child_session`. CI runs 50 kills; the 1,000-kill run of the README is
//!
//! ```text
//! cargo test --release --test store_kill -- --ignored --nocapture
//! ```
//!
//! `NOVANC_KILLS=N` sets the number of kills of either test, `NOVANC_KILL_SEED=S` the seed.

use novanc::store::{Stores, Target};
use std::collections::HashMap;
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

/// A T-code table file: the sample's T01 to T20, and tools 90000.. in some of T21 to T24.
fn tcode_table(r: &mut Rng) -> String {
    let mut t = novanc::tooldata::sample_magazine().tcodes.to_text();
    for pocket in 21..=24 {
        if r.below(2) == 0 {
            t.push_str(&format!(
                "T{pocket} {}\n",
                90_000 + pocket * 10 + r.below(3)
            ));
        }
    }
    t
}

/// Change number `k`, the same in the child and in the reference: Ok if acknowledged, Err
/// with the message if refused (a refusal changes nothing).
fn apply(s: &mut Stores, k: u64) -> Result<(), String> {
    let mut r = Rng(k.wrapping_mul(0x2545_F491_4F6C_DD1D) ^ 0x5EED);
    let edit = |s: &mut Stores, t: Target, line: String| {
        s.edit(t, &line, None)
            .map(|_| ())
            .map_err(|e| e.to_string())
    };
    let program = ["KILL", "R0", "R1", "R2", "N0", "N1", "TABLEB"];
    match r.below(100) {
        // Program edits: insert or kill a line somewhere in the current program.
        0..=15 => {
            let at = r.below(8);
            edit(s, Target::Program, format!("-999999L{at}LIE{k}*"))
        }
        16..=27 => {
            let at = r.below(8);
            edit(s, Target::Program, format!("-999999L{at}LK"))
        }
        // MDI: insert a block, or empty the buffer.
        28..=39 => edit(s, Target::Mdi, format!("IM{k}*")),
        40..=42 => s.clear_mdi().map_err(|e| e.to_string()),
        // TOOL DATA REVISION: T02's speed.
        43..=52 => edit(
            s,
            Target::ToolFile,
            format!("-99LLKIT02 00106 DR 6.2 150 40 {} 120 3*", 100 + k % 5000),
        ),
        // T-CODE SETTING: by T code, by tool (a move with its data), from a table file.
        53..=60 => {
            let t = 21 + r.below(4) as u32;
            let tool = match r.below(4) {
                0 => None,
                _ => Some(90_000 + r.below(50) as u32),
            };
            s.set_tcode(t, tool)
        }
        61..=65 => s.move_tool(90_000 + r.below(50) as u32, 21 + r.below(4) as u32),
        66..=69 => s
            .tcode_read(&tcode_table(&mut r), "m.tc")
            .map_err(|e| e.to_string()),
        // PROGRAM READ, by name and from a file name.
        70..=74 => s
            .program_read(
                &format!("R{}", r.below(3)),
                &format!("P1 = ({k}, 2)\r\nDRL, 106/DP5/DA1, P1\r\n"),
            )
            .map_err(|e| e.to_string()),
        75..=77 => s
            .program_read_file(&format!("/tapes/r{}.ap", r.below(3)), &format!("R{k}\n"))
            .map(|_| ())
            .map_err(|e| e.to_string()),
        // TOOL DATA READ: new data for T02 and for some of the 90000 tools.
        78..=84 => {
            let mut tape = format!("00106 DR 6.{} 150 40 1200 120 3\n", k % 10);
            for n in 0..3 {
                tape.push_str(&format!(
                    "{} EM {}.0 100 30 800 90 5\n",
                    90_000 + r.below(50),
                    8 + n
                ));
            }
            s.tool_read(&tape, "t.tt")
                .map(|_| ())
                .map_err(|e| e.to_string())
        }
        // The interpreter's parameters as a G-code run sets them together (G92, the system
        // selected, a G28 home, a rotation): one refused in ten (not a kept parameter, or
        // beyond the limit).
        85..=86 => {
            let v = k as f64 * 0.001;
            let mut ps = vec![
                (5210, 1.0),
                (5211, v),
                (5212, -(r.below(1000) as f64)),
                (5220, (1 + r.below(9)) as f64),
                (5161 + r.below(3) as usize, v * 2.0),
                (
                    5230 + 20 * r.below(9) as usize,
                    (r.below(360) as f64) - 180.0,
                ),
            ];
            match r.below(20) {
                0 => ps.push((5400, 1.0)),
                1 => ps.push((5213, 1e13)),
                _ => {}
            }
            s.set_params(&ps).map_err(|e| e.to_string())
        }
        // Work offsets (OFS page, G10 L2): one refused in ten (beyond 100 m).
        87..=88 => {
            let system = r.below(9) as usize;
            let x = if r.below(10) == 0 {
                1e9
            } else {
                k as f64 * 0.001
            };
            s.set_work_offset(system, [x, -(r.below(1000) as f64), 1.5])
                .map_err(|e| e.to_string())
        }
        // SEARCH, new and deleted programs.
        89..=93 => s
            .select_program(program[r.below(program.len() as u64) as usize])
            .map_err(|e| e.to_string()),
        94..=96 => s
            .new_program(&format!("N{}", r.below(2)))
            .map_err(|e| e.to_string()),
        _ => s
            .delete_program(&format!("N{}", r.below(2)))
            .map_err(|e| e.to_string()),
    }
}

/// The child: applies changes from `CHILD_FROM` on, printing `ack K` or `nak K` after each.
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
    let mut out = std::io::stdout().lock();
    let (mut s, _) = match Stores::open(Path::new(&dir), 24) {
        Ok(x) => x,
        Err(e) => {
            let _ = writeln!(out, "\nfail open {e}");
            return;
        }
    };
    s.set_journal_limit(num(CHILD_LIMIT) as usize);
    let from = num(CHILD_FROM);
    let start = Instant::now();
    for k in from..from + 100_000 {
        if start.elapsed() > Duration::from_secs(20) {
            break; // the parent is gone
        }
        let line = match apply(&mut s, k) {
            Ok(()) => format!("ack {k}"),
            Err(e) if e.contains("not saved") => format!("fail {k} {e}"),
            Err(_) => format!("nak {k}"),
        };
        let _ = writeln!(out, "\n{line}");
        let _ = out.flush();
    }
}

/// Everything the stores hold, hashed (FNV-1a): equal states, equal digests.
fn digest(s: &Stores) -> u64 {
    let mut text = format!("current {}\n", s.current_program());
    for n in s.program_names() {
        text.push_str(&format!(
            "program {n}\n{}",
            s.program_text(&n).unwrap_or_default()
        ));
    }
    for t in [Target::Program, Target::Mdi, Target::ToolFile] {
        let b = s.buffer(t);
        text.push_str(&format!("{t:?} {}\n{}", b.pointer(), b.text()));
    }
    text.push_str(&format!("{:?}", s.magazine()));
    text.push_str(&format!("{:?}", s.params()));
    text.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}

/// What a kill run found.
#[derive(Debug, Default)]
struct Tally {
    kills: usize,
    acknowledged: usize,
    refused: usize,
    lost: usize,
    load_failures: usize,
    torn: usize,
    in_flight: usize,
    during_open: usize,
}

/// The reference: the same changes on stores that are never killed, with the digest after
/// each change and whether it was acknowledged.
struct Reference {
    stores: Stores,
    done: u64,
    digests: HashMap<u64, u64>,
    acked: HashMap<u64, bool>,
}

impl Reference {
    /// Applies changes up to `k` (inclusive).
    fn advance(&mut self, k: u64) {
        while self.done <= k {
            let ok = apply(&mut self.stores, self.done).is_ok();
            self.acked.insert(self.done, ok);
            self.digests.insert(self.done, digest(&self.stores));
            self.done += 1;
        }
    }
}

/// Kills a child `kills` times and checks every reopen against the reference.
fn kill_run(kills: usize, tag: &str) -> Tally {
    let base = Path::new(env!("CARGO_TARGET_TMPDIR"));
    let dir: PathBuf = base.join(format!("store-kill-{tag}"));
    let ref_dir: PathBuf = base.join(format!("store-kill-{tag}-reference"));
    for d in [&dir, &ref_dir] {
        let _ = std::fs::remove_dir_all(d);
        let (mut s, _) = Stores::open(d, 24).unwrap();
        s.new_program("KILL").unwrap();
    }
    let (stores, _) = Stores::open(&ref_dir, 24).unwrap();
    let mut reference = Reference {
        digests: HashMap::from([(u64::MAX, digest(&stores))]),
        stores,
        done: 0,
        acked: HashMap::new(),
    };
    let exe = std::env::current_exe().unwrap();
    let seed = std::env::var("NOVANC_KILL_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0x5EED_0002);
    let mut rng = Rng(seed);
    let mut t = Tally::default();
    let mut next = 0u64;
    for round in 0..kills {
        let limit = [4096, 5, 1][round % 3];
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
        // One kill in ten lands while the child opens the stores (replay, compaction).
        let want = match rng.below(10) {
            0 => 0,
            _ => 1 + rng.below(120),
        };
        let mut done: Vec<(u64, bool)> = Vec::new();
        let seen = |l: &str, done: &mut Vec<(u64, bool)>| {
            let mut f = l.splitn(3, ' ');
            match (f.next(), f.next().and_then(|n| n.parse::<u64>().ok())) {
                (Some("ack"), Some(k)) => done.push((k, true)),
                (Some("nak"), Some(k)) => done.push((k, false)),
                (Some("fail"), _) => panic!("round {round}: the child failed: {l}"),
                _ => {}
            }
        };
        if want > 0 {
            for l in lines.by_ref() {
                seen(&l.unwrap(), &mut done);
                if done.len() as u64 >= want {
                    break;
                }
            }
        }
        std::thread::sleep(Duration::from_micros(rng.below(3000)));
        child.kill().unwrap(); // SIGKILL
        for l in lines.map_while(Result::ok) {
            seen(&l, &mut done);
        }
        let _ = child.wait();
        t.kills += 1;
        t.during_open += done.is_empty() as usize;
        let ks: Vec<u64> = done.iter().map(|d| d.0).collect();
        let last = ks.last().copied().unwrap_or(next.wrapping_sub(1));
        assert_eq!(ks, (next..=last).collect::<Vec<_>>(), "round {round}");
        reference.advance(last.wrapping_add(1));
        for &(k, ok) in &done {
            assert_eq!(ok, reference.acked[&k], "round {round}: change {k}");
            t.acknowledged += ok as usize;
            t.refused += !ok as usize;
        }

        let (s, warnings) = match Stores::open(&dir, 24) {
            Ok(x) => x,
            Err(e) => {
                eprintln!("round {round}: the stores do not open: {e}");
                t.load_failures += 1;
                break;
            }
        };
        for w in &warnings {
            // A torn last record is allowed (the change being written when killed).
            assert!(w.contains("journal record"), "round {round}: {w}");
            t.torn += 1;
        }
        let got = digest(&s);
        drop(s);
        let d = |k: u64| reference.digests[&k];
        if got == d(last) {
            next = last.wrapping_add(1);
        } else if got == d(last.wrapping_add(1)) {
            t.in_flight += 1;
            next = last.wrapping_add(2);
        } else {
            // Lost: find how far back the reopened stores are (the changes from k on).
            let lost = match ks.iter().rev().find(|&&k| d(k.wrapping_sub(1)) == got) {
                Some(&k) => (k..=last).filter(|k| reference.acked[k]).count(),
                None => done.iter().filter(|d| d.1).count().max(1),
            };
            eprintln!("round {round}: {lost} acknowledged changes lost (changes {next}..={last})");
            t.lost += lost;
            break;
        }
        for e in std::fs::read_dir(&dir).unwrap().flatten() {
            if e.file_name().to_string_lossy().contains(".bad-") {
                let _ = std::fs::remove_file(e.path());
            }
        }
    }
    t
}

/// Runs `kills` kills (or `NOVANC_KILLS`), prints the figures and checks none was lost.
fn run_and_check(kills: usize, tag: &str) {
    let kills = std::env::var("NOVANC_KILLS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(kills);
    let start = Instant::now();
    let t = kill_run(kills, tag);
    eprintln!(
        "kill test: {} kills ({} while opening) in {:.1} s: {} acknowledged changes ({} refused), {} lost, {} load failures; {} torn last records, {} changes in flight found saved",
        t.kills,
        t.during_open,
        start.elapsed().as_secs_f64(),
        t.acknowledged,
        t.refused,
        t.lost,
        t.load_failures,
        t.torn,
        t.in_flight
    );
    assert_eq!(t.lost, 0, "{t:?}");
    assert_eq!(t.load_failures, 0, "{t:?}");
    assert_eq!(t.kills, kills, "{t:?}");
}

#[test]
fn kill_9_during_mixed_edits_loses_no_acknowledged_change() {
    run_and_check(50, "ci");
}

/// The README's figure: `cargo test --release --test store_kill -- --ignored --nocapture`.
#[test]
#[ignore]
fn kill_9_a_thousand_times() {
    run_and_check(1000, "long");
}
