//! Bounded work (docs/language.md, *Limits*): adversarial inputs of at most 1 MiB (one huge
//! line, lines at the length limit, deep parentheses, many and deep macros, huge numbers, many
//! points and patterns) go through what `novanc translate` does (`cli::translate::iso_text`),
//! each timed and with its peak heap measured by a counting allocator. The bounds asserted are
//! generous (the test profile is barely optimised); the figures are printed, e.g.
//! `cargo test --release --test translate_1mb -- --nocapture`.

use novanc::cli::translate::iso_text;
use novanc::settings::MachineSettings;
use novanc::tooldata::sample_magazine;
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// Counts the bytes allocated now and the peak since the last reset.
struct Counting;

static NOW: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

fn grew(n: usize) {
    let now = NOW.fetch_add(n, Ordering::Relaxed) + n;
    PEAK.fetch_max(now, Ordering::Relaxed);
}

// SAFETY: every call is passed to `System` unchanged; only counters are kept beside it.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(l) };
        if !p.is_null() {
            grew(l.size());
        }
        p
    }

    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        unsafe { System.dealloc(p, l) };
        NOW.fetch_sub(l.size(), Ordering::Relaxed);
    }

    unsafe fn realloc(&self, p: *mut u8, l: Layout, new: usize) -> *mut u8 {
        let q = unsafe { System.realloc(p, l, new) };
        if !q.is_null() {
            if new >= l.size() {
                grew(new - l.size());
            } else {
                NOW.fetch_sub(l.size() - new, Ordering::Relaxed);
            }
        }
        q
    }
}

#[global_allocator]
static ALLOC: Counting = Counting;

const MIB: usize = 1 << 20;
const HEAD: &str = "DA1 = (200, 0, -450)\nP1 = (150, 130)\n";

/// Lines from `line(n)` for n = 1, 2, ... while the text stays within 1 MiB, then `tail`.
fn fill(head: &str, mut line: impl FnMut(usize) -> String, tail: &str) -> String {
    let mut s = String::from(head);
    for n in 1.. {
        let l = line(n);
        if s.len() + l.len() + tail.len() > MIB {
            break;
        }
        s.push_str(&l);
    }
    s.push_str(tail);
    s
}

/// The adversarial inputs: (name, text).
fn inputs() -> Vec<(&'static str, String)> {
    let mut v = Vec::new();
    v.push((
        "one 1 MiB line",
        format!("GO, {}, 0, 0\n", "9".repeat(MIB - 20)),
    ));
    let desigs = |n: usize| {
        let mut l = String::from("DRL, 106/DP1/DA1");
        while l.len() < 9_990 - 4 {
            l.push_str(if n.is_multiple_of(2) { ", P1" } else { ", P2" });
        }
        l + "\n"
    };
    v.push((
        "lines of 10,000 characters of designations",
        fill(&format!("{HEAD}P2 = (160, 140)\n"), desigs, ""),
    ));
    v.push((
        "deep parentheses",
        fill(
            "",
            |_| format!("P1 = {}1{}\n", "(".repeat(4_000), ")".repeat(4_000)),
            "",
        ),
    ));
    let mut doubling = format!("{HEAD}MAC1 = DA1, P1, P1\n");
    for n in 2..=16 {
        doubling.push_str(&format!("MAC{n} = MAC{}, MAC{}\n", n - 1, n - 1));
    }
    let mut chain = doubling.clone();
    let mut last = 16;
    while chain.len() + 40 < MIB {
        last += 1;
        chain.push_str(&format!("MAC{last} = MAC{}\n", last - 1));
    }
    chain.push_str(&format!("DRL, 106/DP1/MAC{last}\n"));
    v.push((
        "doubling macros, then a chain of macros, then one use",
        chain,
    ));
    v.push((
        "doubling macros to the limit, never used",
        fill(&doubling, |n| format!("MAC{} = MAC16, P1\n", 16 + n), ""),
    ));
    v.push((
        "huge numbers",
        fill(
            "DA1 = (999999999.999, -999999999.999, 999999999.999)\n",
            |n| {
                let s = if n.is_multiple_of(2) { "" } else { "-" };
                format!(
                    "DA{} = DA{n}, ({s}999999999.999, {s}999999999.999, {s}999999999.999)\n",
                    n + 1
                )
            },
            "GO, DA2, 0, 0, 0\n",
        ),
    ));
    let mut points = String::from(HEAD);
    for n in 1..=20_000 {
        points.push_str(&format!(
            "P{} = ({}, {}, -{})\n",
            n + 1,
            n % 300,
            n % 250,
            n % 7
        ));
    }
    v.push((
        "many points, milled in lines of 10,000 characters",
        fill(
            &points,
            |n| {
                let mut l = String::from("MIL, 402/DP1/DA1");
                let mut k = n * 7;
                while l.len() < 9_980 {
                    l.push_str(&format!(", P{}", k % 20_000 + 2));
                    k += 1;
                }
                l + "\n"
            },
            "",
        ),
    ));
    v.push((
        "many 10,000-hole patterns, ten used",
        fill(
            HEAD,
            |n| format!("PAT{n} = DA1, NH10000, P1, R50\n"),
            "DRL, 106/DP1/PAT1, PAT2, PAT3, PAT4, PAT5, PAT6, PAT7, PAT8, PAT9, PAT10\n",
        ),
    ));
    v.push((
        "bad characters everywhere",
        fill("", |n| format!("P{n} = (1, 2) \u{0}\u{feff}\n"), ""),
    ));
    v
}

#[test]
fn no_input_of_1_mib_takes_long_or_much_memory() {
    let settings = MachineSettings::default();
    let magazine = sample_magazine();
    println!(
        "{:<55} {:>9} {:>10} {:>10} {:>11}",
        "input (≤ 1 MiB)", "bytes", "time", "peak heap", "ISO lines"
    );
    for (name, src) in inputs() {
        assert!(src.len() <= MIB, "{name}: {} bytes", src.len());
        let base = NOW.load(Ordering::Relaxed);
        PEAK.store(base, Ordering::Relaxed);
        let t = Instant::now();
        let r = iso_text(
            "p.ap",
            &src,
            magazine.clone(),
            &settings,
            Default::default(),
        );
        let took = t.elapsed();
        let peak = PEAK.load(Ordering::Relaxed) - base;
        let lines = match &r {
            Ok(t) => t.lines().count().to_string(),
            Err(e) => format!("error {}:{}", e.line, e.col),
        };
        if let Err(e) = &r {
            assert!(e.to_string().len() < 400, "{name}: a long message: {e}");
        }
        println!(
            "{name:<55} {:>9} {:>8.3} s {:>7.1} MB {lines:>11}",
            src.len(),
            took.as_secs_f64(),
            peak as f64 / 1e6
        );
        drop(r);
        assert!(took < Duration::from_secs(10), "{name}: {took:?}");
        assert!(peak < 256 << 20, "{name}: peak heap {peak} bytes");
    }
}
