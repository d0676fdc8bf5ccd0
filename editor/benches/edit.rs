//! Editor benchmark (issue 2): a 1,000,000-line program (about 30 MB) built with a seeded PRNG;
//! times L, M, K, D, I, C and Y at random positions (median and p99), S throughput in MB/s, and
//! the memory held by the buffer against the text size. Prints the figures.
//!
//! Run: `cargo bench -p novanc-editor --bench edit`

use novanc_editor::{Buffer, ExecOptions};
use std::hint::black_box;
use std::time::{Duration, Instant};

/// splitmix64.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

const LINES: usize = 1_000_000;
const SAMPLES: usize = 1_000;

/// A part program of `LINES` blocks like `N123456 G01 Y78.901` (about 30 bytes).
fn program(rng: &mut Rng) -> String {
    let mut s = String::with_capacity(LINES * 32);
    for n in 1..=LINES {
        let g = ["G00", "G01", "G02", "G03"][rng.below(4)];
        let x = rng.below(1_000_000) as f64 / 1000.0 - 500.0;
        let y = rng.below(1_000_000) as f64 / 1000.0 - 500.0;
        s.push_str(&format!("N{n} {g} X{x:.3} Y{y:.3}\n"));
    }
    s
}

/// Median and p99 of some durations, in microseconds.
fn stats(mut d: Vec<Duration>) -> (f64, f64) {
    d.sort();
    let us = |x: Duration| x.as_secs_f64() * 1e6;
    (
        us(d[d.len() / 2]),
        us(d[(d.len() * 99 / 100).min(d.len() - 1)]),
    )
}

/// Times `line` at SAMPLES random pointer positions.
fn time(buf: &mut Buffer, rng: &mut Rng, name: &str, line: &str, opts: &ExecOptions) {
    let mut d = Vec::with_capacity(SAMPLES);
    for _ in 0..SAMPLES {
        let at = rng.below(buf.len() + 1);
        buf.set_pointer(at);
        let t = Instant::now();
        let r = buf.execute(line, opts);
        d.push(t.elapsed());
        black_box(&r);
    }
    let (med, p99) = stats(d);
    println!("{name:<16} median {med:>9.1} µs   p99 {p99:>9.1} µs");
}

fn main() {
    let mut rng = Rng(0x0E_D170_5EED);
    let text = program(&mut rng);
    let mb = text.len() as f64 / 1e6;
    let t = Instant::now();
    let mut buf = Buffer::from_text(&text);
    println!(
        "buffer: {LINES} lines, {:.1} MB, loaded in {:.0} ms",
        mb,
        t.elapsed().as_secs_f64() * 1e3
    );
    let opts = ExecOptions {
        y_max_lines: Some(20),
        validator: None,
    };
    println!("per command at {SAMPLES} random pointer positions:");
    time(&mut buf, &mut rng, "L  (3L)", "3L", &opts);
    time(&mut buf, &mut rng, "L  (-3L)", "-3L", &opts);
    time(&mut buf, &mut rng, "M  (-5M)", "-5M", &opts);
    time(&mut buf, &mut rng, "K  (K)", "K", &opts);
    time(&mut buf, &mut rng, "K  (-2K)", "-2K", &opts);
    time(&mut buf, &mut rng, "D  (-1D)", "-1D", &opts);
    time(&mut buf, &mut rng, "I  (IN0 G00*)", "IN0 G00*", &opts);
    time(&mut buf, &mut rng, "C  (CG0$G9)", "CG0$G9", &opts);
    time(&mut buf, &mut rng, "Y  (20Y)", "20Y", &opts);
    let mut d = Vec::with_capacity(SAMPLES);
    for _ in 0..SAMPLES {
        buf.set_pointer(rng.below(buf.len() + 1));
        let t = Instant::now();
        black_box(buf.view(24, 80));
        d.push(t.elapsed());
    }
    let (med, p99) = stats(d);
    println!(
        "{:<16} median {med:>9.1} µs   p99 {p99:>9.1} µs",
        "view() 24x80"
    );

    // S throughput: search from the start for text that is not there, then for the last block.
    let size = buf.len() as f64 / 1e6;
    for (what, line) in [
        ("S absent", "SX9999.999 Y9999"),
        ("S last block", "SN1000000 "),
        ("S one char", "S#"),
    ] {
        let mut best = f64::MAX;
        for _ in 0..5 {
            buf.set_pointer(0);
            let t = Instant::now();
            black_box(buf.execute(line, &opts).is_ok());
            best = best.min(t.elapsed().as_secs_f64());
        }
        println!(
            "{what:<16} {:>7.0} MB/s  ({:.1} ms over {size:.1} MB)",
            size / best,
            best * 1e3
        );
    }

    let held = buf.heap_bytes();
    let text_len = buf.text().len();
    println!(
        "memory: {:.1} MB held for {:.1} MB of text = {:.3}x (after the edits above)",
        held as f64 / 1e6,
        text_len as f64 / 1e6,
        held as f64 / text_len as f64
    );
    let fresh = Buffer::from_text(&text);
    println!(
        "memory: {:.3}x for a freshly loaded buffer",
        fresh.heap_bytes() as f64 / text.len() as f64
    );
}
