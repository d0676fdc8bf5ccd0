//! Crash safety by command: a child process makes mixed changes to the stores and prints
//! `ack K` after each acknowledged one (`nak K` after a refused one); the parent kills it with
//! SIGKILL at a random moment, reopens the stores and compares them with a reference that made
//! the same changes without being killed. Every acknowledged change must be there, in order,
//! and nothing beyond the one in flight. The same harness drives both machines' stores:
//!
//! - the centre's (`Stores`): program edits, MDI, tool-file revisions, T-code settings,
//!   PROGRAM READ, TOOL DATA READ, SEARCH, new and deleted programs, work offsets, the
//!   G-code interpreter's parameters (G92, the system in force, G28 homes, rotations);
//! - the lathe's (`store::lathe::LatheStore`, as the lathe console uses it, on the same
//!   journal): program edits on each channel, tool revisions, the part counter's counts and
//!   target, with the journal compacted every 4096, 5 or 1 records in turn as the centre's;
//!
//! and `novanc edit FILE -c ... --write` racing itself: several editors of one file at once
//! (with and without a second hard link), killed at random; every edit whose process exited 0
//! must be in the file, and the file must be whole (every line one an editor wrote).
//!
//! The child is this same test binary, run with `NOVANC_KILL_TEST_DIR` set, executing
//! `child_session`. CI runs 50 kills of each; the 1,000-kill runs of the README are
//!
//! ```text
//! cargo test --release --test store_kill -- --ignored --nocapture
//! ```
//!
//! `NOVANC_KILLS=N` sets the number of kills of every test, `NOVANC_KILL_SEED=S` the seed.

mod common;

use novanc::lathe::desc::{LatheDesc, ToolDesc};
use novanc::pulse_core::testkit::Rng;
use novanc::store::lathe::{Counter, LatheStore, Program};
use novanc::store::{Stores, Target};
use novanc_editor::{Buffer, ExecOptions};
use std::collections::HashMap;
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const CHILD_DIR: &str = "NOVANC_KILL_TEST_DIR";
const CHILD_FROM: &str = "NOVANC_KILL_TEST_FROM";
const CHILD_LIMIT: &str = "NOVANC_KILL_TEST_LIMIT";
const CHILD_KIND: &str = "NOVANC_KILL_TEST_KIND";

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

/// Change number `k` to the centre's stores, the same in the child and in the reference: Ok
/// if acknowledged, Err with the message if refused (a refusal changes nothing).
fn centre_apply(s: &mut Stores, k: u64) -> Result<(), String> {
    let mut r = Rng::new(k.wrapping_mul(0x2545_F491_4F6C_DD1D) ^ 0x5EED);
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
                (5161 + r.below(3), v * 2.0),
                (5230 + 20 * r.below(9), (r.below(360) as f64) - 180.0),
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
            let system = r.below(9);
            let x = if r.below(10) == 0 {
                1e9
            } else {
                k as f64 * 0.001
            };
            s.set_work_offset(system, &[x, -(r.below(1000) as f64), 1.5])
                .map_err(|e| e.to_string())
        }
        // SEARCH, new and deleted programs.
        89..=93 => s
            .select_program(program[r.below(program.len())])
            .map_err(|e| e.to_string()),
        94..=96 => s
            .new_program(&format!("N{}", r.below(2)))
            .map_err(|e| e.to_string()),
        _ => s
            .delete_program(&format!("N{}", r.below(2)))
            .map_err(|e| e.to_string()),
    }
}

/// What the kill harness drives: one machine's stores, as its console uses them.
trait Subject: Sized {
    /// The name in the child's environment and in the test's directories.
    const KIND: &'static str;
    /// Most changes a child makes before it is killed (one fdatasync each, a journal record;
    /// a lathe's change carries a whole program or tool table, so it makes fewer).
    const MOST: u64;
    /// Opens (creating) the stores in `dir`, with the warnings of opening.
    fn open(dir: &Path) -> Result<(Self, Vec<String>), String>;
    /// Sets up the state the first change starts from (the same in the child's directory and
    /// the reference's).
    fn prepare(&mut self) {}
    /// The journal's compaction limit, where there is one.
    fn set_limit(&mut self, _records: usize) {}
    /// Change number `k`, the same in the child and in the reference: Ok if acknowledged,
    /// Err with the message if refused (a refusal changes nothing).
    fn apply(&mut self, k: u64) -> Result<(), String>;
    /// Everything the stores hold, hashed: equal states, equal digests.
    fn digest(&self) -> u64;
    /// Whether a warning at reopen is one a kill may cause (a torn last record).
    fn torn(w: &str) -> bool;
}

/// FNV-1a of a text.
fn fnv(text: &str) -> u64 {
    text.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}

impl Subject for Stores {
    const KIND: &'static str = "centre";
    const MOST: u64 = 120;

    fn open(dir: &Path) -> Result<(Self, Vec<String>), String> {
        Stores::open(dir, 24).map_err(|e| e.to_string())
    }

    fn prepare(&mut self) {
        self.new_program("KILL").unwrap();
    }

    fn set_limit(&mut self, records: usize) {
        self.set_journal_limit(records);
    }

    fn apply(&mut self, k: u64) -> Result<(), String> {
        centre_apply(self, k)
    }

    fn digest(&self) -> u64 {
        let s = self;
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
        text.push_str(&format!("{:?}", s.work_offsets()));
        text.push_str(&format!("{:?}", s.params()));
        fnv(&text)
    }

    fn torn(w: &str) -> bool {
        // A torn last record is allowed (the change being written when killed).
        w.contains("journal record")
    }
}

/// The lathe's stores as the lathe console holds them: what `LatheStore::open` gave, changed
/// in memory only once `LatheStore` has stored the change.
struct Lathe {
    store: LatheStore,
    programs: Vec<Program>,
    tools: Vec<Vec<ToolDesc>>,
    counter: Counter,
    /// Each channel's #500–#999 and work offsets (docs/lathe-gcode.md "What a channel keeps").
    params: Vec<std::collections::BTreeMap<usize, f64>>,
    /// Each channel's MDI buffer (the lines typed in MDI, not yet run).
    mdi: Vec<Vec<String>>,
    /// Each channel's editor pointer (characters from its program's start).
    pointers: Vec<usize>,
    /// Each channel's jog feed chosen on POS, mm/min, and rapid jog (stop 60).
    jogs: Vec<(Option<f64>, bool)>,
    /// Where each tool post stands, and which moves (the position memory, stop 61).
    posts: Option<Vec<novanc::store::lathe::Post>>,
}

impl Subject for Lathe {
    const KIND: &'static str = "lathe";
    const MOST: u64 = 20;

    fn open(dir: &Path) -> Result<(Self, Vec<String>), String> {
        let desc = LatheDesc::citizen();
        let o = LatheStore::open(dir, &desc)?;
        let tools = o
            .tools
            .into_iter()
            .zip(&desc.channels)
            .map(|(t, c)| t.unwrap_or_else(|| c.tools.clone()))
            .collect();
        let l = Lathe {
            store: o.store,
            programs: o.programs,
            tools,
            counter: o.counter,
            params: o
                .params
                .iter()
                .map(|p| p.iter().copied().collect())
                .collect(),
            mdi: o.mdi,
            pointers: o.pointers,
            jogs: o.jogs,
            posts: o.posts,
        };
        Ok((l, o.warnings))
    }

    fn apply(&mut self, k: u64) -> Result<(), String> {
        let mut r = Rng::new(k.wrapping_mul(0x2545_F491_4F6C_DD1D) ^ 0x1A7E);
        let ch = r.below(3);
        match r.below(100) {
            // DATA: an editor command line on the channel's program (insert or kill a line).
            0..=49 => {
                let at = r.below(12);
                let line = match r.below(3) {
                    0 => format!("-999999L{at}LK"),
                    _ => format!("-999999L{at}LIG1 X{k} (K{k})*"),
                };
                let mut buf = Buffer::from_text(&self.programs[ch].text);
                buf.execute(&line, &ExecOptions::default())
                    .map_err(|e| e.to_string())?;
                let p = Program {
                    name: self.programs[ch].name.clone(),
                    text: buf.text(),
                    dialect: None,
                };
                self.store.save_program(ch, &p)?;
                // A pointer past the new text's end stands at its end (as the stores do).
                let len = p.text.chars().count();
                self.pointers[ch] = self.pointers[ch].min(len);
                self.programs[ch] = p;
            }
            // OFS: a tool's offsets revised.
            55..=79 => {
                let mut tools = self.tools[ch].clone();
                let i = r.below(tools.len());
                tools[i].offset = [(k % 997) as f64 * 0.001, -((k % 89) as f64) * 0.01];
                self.store.save_tools(ch, &tools)?;
                self.tools[ch] = tools;
            }
            // DATA: a pointer move alone (nL), kept across a restart.
            50..=54 => {
                let at = r.below(self.programs[ch].text.chars().count() + 1);
                self.store.save_pointer(ch, at)?;
                self.pointers[ch] = at;
            }
            // MDI: a line typed into the channel's buffer, or the buffer run (cleared).
            80..=84 => {
                let mut lines = self.mdi[ch].clone();
                if lines.len() >= 60 || r.below(4) == 0 {
                    lines.clear();
                } else {
                    lines.push(format!("G0 X{} Z{}", k % 40, k % 17));
                }
                self.store.save_mdi(ch, &lines)?;
                self.mdi[ch] = lines;
            }
            // A START whose read changed a channel's #500–#999 (0: vacant again), or a work
            // offset's X or Z (revised at OFS or by a program's G10 L2; stop 57).
            85..=89 => {
                let n = match r.below(3) {
                    0 => novanc::lathe::gcode::work_params(r.below(6))[r.below(2)],
                    _ => 500 + r.below(500),
                };
                let v = if r.below(4) == 0 {
                    0.0
                } else {
                    k as f64 * 0.25
                };
                self.store.save_params(ch, &[(n, v)])?;
                if v == 0.0 {
                    self.params[ch].remove(&n);
                } else {
                    self.params[ch].insert(n, v);
                }
            }
            // POS: a channel's jog feed (`JOG 250.5`, `JOG RAPID`, `JOG`).
            95..=99 => {
                let (feed, rapid) = match (r.below(3), self.jogs[ch].0) {
                    (0, feed) => (feed, true),
                    (1, feed) => (feed, false),
                    _ => (Some(1.0 + (k % 4000) as f64 * 0.5), false),
                };
                self.store.save_jog(ch, feed, rapid)?;
                self.jogs[ch] = (feed, rapid);
            }
            // The position memory: a post set moving before a move, or all at rest where they
            // stand after one.
            90..=92 => {
                let mut posts = self.posts.clone().unwrap_or_else(|| {
                    vec![
                        novanc::store::lathe::Post {
                            moving: false,
                            pos: [35_000, 60_000],
                        };
                        3
                    ]
                });
                if r.below(2) == 0 {
                    posts[ch].moving = true;
                } else {
                    posts[ch].pos = [(k % 35_000) as i64, -((k % 60_000) as i64)];
                    posts.iter_mut().for_each(|p| p.moving = false);
                }
                self.store.save_posts(&posts)?;
                self.posts = Some(posts);
            }
            // The part counter: a channel counts a work, or a new target starts a batch.
            _ => {
                let mut c = self.counter.clone();
                if r.below(5) == 0 {
                    c.target = 1 + (k % 999) as u32;
                    c.counts.iter_mut().for_each(|n| *n = 0);
                } else {
                    c.counts[ch] += 1;
                }
                self.store.save_counter(&c)?;
                self.counter = c;
            }
        }
        Ok(())
    }

    fn digest(&self) -> u64 {
        fnv(&format!(
            "{:?}{:?}{:?}{:?}{:?}{:?}{:?}{:?}",
            self.programs,
            self.tools,
            self.counter,
            self.params,
            self.mdi,
            self.pointers,
            self.jogs,
            self.posts
        ))
    }

    fn set_limit(&mut self, records: usize) {
        self.store.set_journal_limit(records);
    }

    fn torn(w: &str) -> bool {
        // The one journal, as the centre's: a torn last record is the change in flight.
        w.contains("journal record")
    }
}

/// The child: applies changes from `CHILD_FROM` on, printing `ack K` or `nak K` after each.
#[test]
fn child_session() {
    match std::env::var(CHILD_KIND).as_deref() {
        Ok(Stores::KIND) => child::<Stores>(),
        Ok(Lathe::KIND) => child::<Lathe>(),
        _ => {} // run as a normal test: nothing to do
    }
}

fn child<S: Subject>() {
    let Some(dir) = std::env::var_os(CHILD_DIR) else {
        return;
    };
    let num = |k: &str| {
        std::env::var(k)
            .ok()
            .and_then(|v| v.parse::<u64>().ok())
            .unwrap_or(0)
    };
    let mut out = std::io::stdout().lock();
    let (mut s, _) = match S::open(Path::new(&dir)) {
        Ok(x) => x,
        Err(e) => {
            let _ = writeln!(out, "\nfail open {e}");
            return;
        }
    };
    s.set_limit(num(CHILD_LIMIT) as usize);
    let from = num(CHILD_FROM);
    let start = Instant::now();
    for k in from..from + 100_000 {
        if start.elapsed() > Duration::from_secs(20) {
            break; // the parent is gone
        }
        let line = match s.apply(k) {
            Ok(()) => format!("ack {k}"),
            Err(e) if e.contains("not saved") || e.contains("could not be stored") => {
                format!("fail {k} {e}")
            }
            Err(_) => format!("nak {k}"),
        };
        let _ = writeln!(out, "\n{line}");
        let _ = out.flush();
    }
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
struct Reference<S> {
    stores: S,
    done: u64,
    digests: HashMap<u64, u64>,
    acked: HashMap<u64, bool>,
}

impl<S: Subject> Reference<S> {
    /// Applies changes up to `k` (inclusive).
    fn advance(&mut self, k: u64) {
        while self.done <= k {
            let ok = self.stores.apply(self.done).is_ok();
            self.acked.insert(self.done, ok);
            self.digests.insert(self.done, self.stores.digest());
            self.done += 1;
        }
    }
}

/// Kills a child `kills` times and checks every reopen against the reference.
fn kill_run<S: Subject>(kills: usize, tag: &str) -> Tally {
    let base = Path::new(env!("CARGO_TARGET_TMPDIR"));
    let dir: PathBuf = base.join(format!("store-kill-{}-{tag}", S::KIND));
    let ref_dir: PathBuf = base.join(format!("store-kill-{}-{tag}-reference", S::KIND));
    for d in [&dir, &ref_dir] {
        let _ = std::fs::remove_dir_all(d);
        S::open(d).unwrap().0.prepare();
    }
    let (stores, _) = S::open(&ref_dir).unwrap();
    let mut reference = Reference {
        digests: HashMap::from([(u64::MAX, stores.digest())]),
        stores,
        done: 0,
        acked: HashMap::new(),
    };
    let exe = std::env::current_exe().unwrap();
    let seed = std::env::var("NOVANC_KILL_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0x5EED_0002);
    let mut rng = Rng::new(seed);
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
            .env(CHILD_KIND, S::KIND)
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
            _ => 1 + rng.below(S::MOST as usize) as u64,
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
        std::thread::sleep(Duration::from_micros(rng.below(3000) as u64));
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

        let (s, warnings) = match S::open(&dir) {
            Ok(x) => x,
            Err(e) => {
                eprintln!("round {round}: the stores do not open: {e}");
                t.load_failures += 1;
                break;
            }
        };
        for w in &warnings {
            assert!(S::torn(w), "round {round}: {w}");
            t.torn += 1;
        }
        let got = s.digest();
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

/// The number of kills of a test: `kills`, or `NOVANC_KILLS`.
fn kills_wanted(kills: usize) -> usize {
    std::env::var("NOVANC_KILLS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(kills)
}

/// Runs `kills` kills (or `NOVANC_KILLS`) of one machine's stores, prints the figures and
/// checks none was lost.
fn run_and_check<S: Subject>(kills: usize, tag: &str) {
    let _serial = common::serial();
    let kills = kills_wanted(kills);
    let start = Instant::now();
    let t = kill_run::<S>(kills, tag);
    eprintln!(
        "kill test ({}): {} kills ({} while opening) in {:.1} s: {} acknowledged changes ({} refused), {} lost, {} load failures; {} torn last records, {} changes in flight found saved",
        S::KIND,
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

/// What a kill run of `novanc edit --write` racing itself found.
#[derive(Debug, Default)]
struct EditTally {
    rounds: usize,
    kills: usize,
    /// Editors that exited 0.
    acknowledged: usize,
    /// Acknowledged edits not in the file.
    lost: usize,
    /// Editors that failed (exit code 1 or 2): none should.
    failed: usize,
    /// Files found torn as a kill left them (a rewrite in place cut short).
    torn_as_left: usize,
    /// Files torn after the next `novanc edit` of the file.
    torn: usize,
    /// Rewrites in place cut short by a kill and finished by a later editor (it says so).
    finished: usize,
    /// Killed editors whose edit was found in the file.
    in_flight: usize,
}

/// Whether `text` is whole: it ends with a newline and each of its lines is a different one
/// of `lines` (what the file started with and what the editors wrote), every one of `base` is
/// there. Otherwise why not.
fn whole(text: &str, lines: &std::collections::HashSet<String>, base: &str) -> Result<(), String> {
    if !text.is_empty() && !text.ends_with('\n') {
        return Err("its last line is cut short".into());
    }
    let mut seen = std::collections::HashSet::new();
    for (i, l) in text.lines().enumerate() {
        if !lines.contains(l) {
            return Err(format!("line {} {l:?} is no line an editor wrote", i + 1));
        }
        if !seen.insert(l) {
            return Err(format!("line {} {l:?} is there twice", i + 1));
        }
    }
    match base.lines().find(|l| !seen.contains(l)) {
        Some(l) => Err(format!("line {l:?} is missing")),
        None => Ok(()),
    }
}

/// Several `novanc edit FILE -c 'I...' --write` of one file at once (2 to 6), some killed at
/// random, until `kills` are; `hard`: the file has a second hard link (rewritten in place).
/// After each round the file is checked as the kills left it, then after one more
/// `novanc edit FILE` (which finishes a rewrite in place a kill cut short), for every
/// acknowledged edit and for whole lines.
fn edit_kill_run(kills: usize, hard: bool) -> EditTally {
    use std::os::unix::process::ExitStatusExt;
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!(
        "store-kill-edit-{}",
        if hard { "hard" } else { "one" }
    ));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    let file = d.join("f.ap");
    // 2,000 lines, 50 kB: a copy in place takes long enough for kills to land in it.
    let base: String = (0..2000)
        .map(|i| format!("B{i:04} G01 X{i}.5 Y-{i}.25 F300\n"))
        .collect();
    std::fs::write(&file, &base).unwrap();
    if hard {
        std::fs::hard_link(&file, d.join("g.ap")).unwrap();
    }
    let mut lines: std::collections::HashSet<String> = base.lines().map(String::from).collect();
    let mut acked: Vec<String> = Vec::new();
    let seed = std::env::var("NOVANC_KILL_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0x5EED_0002u64);
    let mut rng = Rng::new(seed ^ (hard as u64 + 1) << 40);
    let mut t = EditTally::default();
    let novanc = env!("CARGO_BIN_EXE_novanc");
    while t.kills < kills {
        t.rounds += 1;
        let round = t.rounds;
        let n = 2 + rng.below(5);
        let mut kids = Vec::new();
        for i in 0..n {
            let line = format!("E{round:05}-{i}");
            lines.insert(line.clone());
            let at = rng.below(2000);
            let child = Command::new(novanc)
                .arg("edit")
                .arg(&file)
                .arg("-c")
                .arg(format!("-999999L{at}LI{line}*"))
                .arg("--write")
                .stdout(Stdio::null())
                .stderr(Stdio::piped())
                .spawn()
                .unwrap();
            kids.push((child, line));
        }
        std::thread::sleep(Duration::from_micros(rng.below(8000) as u64));
        for (c, _) in kids.iter_mut() {
            if rng.below(2) == 0 {
                let _ = c.kill(); // SIGKILL
            }
        }
        let mut killed = Vec::new();
        let finished = |stderr: &[u8]| {
            String::from_utf8_lossy(stderr)
                .matches("was killed while rewriting")
                .count()
        };
        for (c, line) in kids {
            let o = c.wait_with_output().unwrap();
            t.finished += finished(&o.stderr);
            match (o.status.code(), o.status.signal()) {
                (Some(0), _) => {
                    t.acknowledged += 1;
                    acked.push(line);
                }
                (_, Some(9)) => {
                    t.kills += 1;
                    killed.push(line);
                }
                _ => {
                    eprintln!(
                        "round {round}: an editor failed: {:?} {}",
                        o.status,
                        String::from_utf8_lossy(&o.stderr)
                    );
                    t.failed += 1;
                }
            }
        }
        let text = std::fs::read_to_string(&file).unwrap_or_default();
        if whole(&text, &lines, &base).is_err() {
            t.torn_as_left += 1;
        }
        // The next edit of the file finishes what a kill cut short.
        let o = Command::new(novanc)
            .arg("edit")
            .arg(&file)
            .output()
            .unwrap();
        t.finished += finished(&o.stderr);
        if o.status.code() != Some(0) {
            eprintln!(
                "round {round}: the next edit fails: {}",
                String::from_utf8_lossy(&o.stderr)
            );
            t.failed += 1;
        }
        let text = std::fs::read_to_string(&file).unwrap_or_default();
        if let Err(why) = whole(&text, &lines, &base) {
            eprintln!("round {round}: the file is torn: {why}");
            t.torn += 1;
            break;
        }
        let have: std::collections::HashSet<&str> = text.lines().collect();
        let lost = acked.iter().filter(|l| !have.contains(l.as_str())).count();
        if lost > 0 {
            eprintln!("round {round}: {lost} acknowledged edits are not in the file");
            t.lost += lost;
            break;
        }
        t.in_flight += killed.iter().filter(|l| have.contains(l.as_str())).count();
        if hard {
            assert!(
                std::fs::read(d.join("g.ap")).unwrap() == text.as_bytes(),
                "round {round}: the second name sees another text"
            );
        }
        // What a finished rewrite kept aside (the torn text) is not needed by the test.
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            if e.file_name().to_string_lossy().contains(".bad-") {
                let _ = std::fs::remove_file(e.path());
            }
        }
        if round % 50 == 0 {
            std::fs::write(&file, &base).unwrap();
            acked.clear();
        }
    }
    t
}

/// Runs `kills` kills (or `NOVANC_KILLS`) of racing `novanc edit --write`, with one name and
/// with two hard links, prints the figures and checks no edit was lost and no file torn.
fn run_and_check_edit(kills: usize) {
    let _serial = common::serial();
    let kills = kills_wanted(kills);
    for hard in [false, true] {
        let start = Instant::now();
        let t = edit_kill_run(kills, hard);
        eprintln!(
            "kill test (novanc edit --write, {}): {} kills in {} rounds of 2 to 6 editors at once in {:.1} s: {} edits acknowledged, {} lost, {} failed; {} torn files; {} rewrites in place cut short by a kill and finished by the next editor ({} of them torn as the kill left them), {} killed edits found saved",
            if hard { "two hard links" } else { "one name" },
            t.kills,
            t.rounds,
            start.elapsed().as_secs_f64(),
            t.acknowledged,
            t.lost,
            t.failed,
            t.torn,
            t.finished,
            t.torn_as_left,
            t.in_flight
        );
        assert_eq!((t.lost, t.failed, t.torn), (0, 0, 0), "{t:?}");
        if !hard {
            assert_eq!(t.torn_as_left, 0, "a rename never tears: {t:?}");
        }
    }
}

#[test]
fn kill_9_during_mixed_edits_loses_no_acknowledged_change() {
    run_and_check::<Stores>(50, "ci");
}

#[test]
fn kill_9_of_the_lathe_stores_loses_no_acknowledged_change() {
    run_and_check::<Lathe>(50, "ci");
}

#[test]
fn kill_9_of_racing_edit_writes_loses_no_edit_and_tears_no_file() {
    run_and_check_edit(50);
}

/// The README's figures: `cargo test --release --test store_kill -- --ignored --nocapture`.
#[test]
#[ignore]
fn kill_9_a_thousand_times() {
    run_and_check::<Stores>(1000, "long");
}

/// `cargo test --release --test store_kill -- --ignored --nocapture`, as above.
#[test]
#[ignore]
fn kill_9_of_the_lathe_stores_a_thousand_times() {
    run_and_check::<Lathe>(1000, "long");
}

/// `cargo test --release --test store_kill -- --ignored --nocapture`, as above.
#[test]
#[ignore]
fn kill_9_of_racing_edit_writes_a_thousand_times() {
    run_and_check_edit(1000);
}
