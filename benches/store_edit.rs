//! What an acknowledged edit costs: the editor command line plus the journal append and its
//! fsync, which must finish before the display shows the edit as accepted. Also the raw
//! fdatasync latency of the disk and the start-up replay of a journal.
//!
//! `cargo bench --bench store_edit` (state in target/tmp, or `NOVANC_BENCH_DIR`).

use novanc::store::{Stores, Target};
use novanc_editor::{Buffer, ExecOptions};
use std::io::Write;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// Median, 99th percentile and maximum of some timings.
fn stats(mut v: Vec<Duration>) -> String {
    v.sort();
    let us = |d: Duration| d.as_secs_f64() * 1e6;
    let p = |q: f64| v[((v.len() - 1) as f64 * q) as usize];
    format!(
        "median {:8.1} us   p99 {:8.1} us   max {:8.1} us",
        us(p(0.5)),
        us(p(0.99)),
        us(v[v.len() - 1])
    )
}

fn main() {
    let base = std::env::var_os("NOVANC_BENCH_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_TARGET_TMPDIR")));
    let dir = base.join("bench-store");
    let _ = std::fs::remove_dir_all(&dir);
    let n = 1000;
    println!("store_edit: {n} edits, state in {}", dir.display());

    // The editor alone, on the same text.
    let mut b = Buffer::from_text(novanc::store::TABLEB);
    let mut t = Vec::with_capacity(n);
    for i in 0..n {
        let line = format!("IN{i}*");
        let s = Instant::now();
        let _ = b.execute(&line, &ExecOptions::default());
        t.push(s.elapsed());
    }
    println!("  editor only (no journal)       {}", stats(t));

    // Raw append + fdatasync of a record-sized write.
    std::fs::create_dir_all(&dir).unwrap();
    let mut f = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(dir.join("raw"))
        .unwrap();
    let mut t = Vec::with_capacity(n);
    for _ in 0..n {
        let s = Instant::now();
        f.write_all(b"@ 12 0123abcd\nedit P X\nIN1*\n").unwrap();
        f.sync_data().unwrap();
        t.push(s.elapsed());
    }
    println!("  raw append + fdatasync         {}", stats(t));
    let _ = std::fs::remove_file(dir.join("raw"));

    // Acknowledged edits through the stores.
    let (mut st, _) = Stores::open(&dir, 24).unwrap();
    let targets = [Target::Program, Target::Mdi, Target::ToolFile];
    for target in targets {
        let mut t = Vec::with_capacity(n);
        let start = Instant::now();
        for i in 0..n {
            let line = match target {
                // A revision of T02's speed, checked by the tool-file validator.
                Target::ToolFile if i % 2 == 0 => "-99LS00106$C1200.0$1300.0".to_string(),
                Target::ToolFile => "-99LS00106$C1300.0$1200.0".to_string(),
                _ => format!("IN{i}*"),
            };
            let s = Instant::now();
            st.edit(target, &line, None).unwrap();
            t.push(s.elapsed());
        }
        let rate = n as f64 / start.elapsed().as_secs_f64();
        println!(
            "  acknowledged edit, {:<9}     {}   ({rate:.0} edits/s)",
            format!("{target:?}"),
            stats(t)
        );
    }
    let mut t = Vec::new();
    for i in 0..200 {
        let s = Instant::now();
        st.set_tcode(21, Some(10_000 + i)).unwrap();
        t.push(s.elapsed());
    }
    println!("  T-CODE SETTING                 {}", stats(t));
    drop(st);

    // Start-up: snapshot read, journal replay (most of 3200 records) and compaction.
    let s = Instant::now();
    let (st, w) = Stores::open(&dir, 24).unwrap();
    println!(
        "  open with the journal replayed  {:8.1} ms ({} warnings)",
        s.elapsed().as_secs_f64() * 1e3,
        w.len()
    );
    drop(st);
    let s = Instant::now();
    let (mut st, _) = Stores::open(&dir, 24).unwrap();
    println!(
        "  open, nothing to replay          {:8.1} ms",
        s.elapsed().as_secs_f64() * 1e3
    );

    // A 1,000,000-line program (about 30 MB) in program memory.
    let big: String = (0..1_000_000)
        .map(|i| format!("N{i:07} G01 X{:03}.5 Y{:03}.25\n", i % 997, i % 613))
        .collect();
    let s = Instant::now();
    st.program_read("BIG", &big).unwrap();
    println!(
        "  PROGRAM READ of {:.1} MB (journal + compaction) {:8.1} ms",
        big.len() as f64 / 1e6,
        s.elapsed().as_secs_f64() * 1e3
    );
    let mut t = Vec::with_capacity(200);
    for i in 0..200u64 {
        let line = format!("{}LIN{i}*", (i * 7919) % 1_000_000);
        let s = Instant::now();
        st.edit(Target::Program, &format!("-9999999L{line}"), None)
            .unwrap();
        t.push(s.elapsed());
    }
    println!("  acknowledged edit, 30 MB program {}", stats(t));
    drop(st);
    let s = Instant::now();
    let (st, _) = Stores::open(&dir, 24).unwrap();
    println!(
        "  open with a 30 MB program, 200 edits replayed {:8.1} ms",
        s.elapsed().as_secs_f64() * 1e3
    );
    drop(st);
    let s = Instant::now();
    let (_st, _) = Stores::open(&dir, 24).unwrap();
    println!(
        "  open with a 30 MB program, nothing to replay  {:8.1} ms",
        s.elapsed().as_secs_f64() * 1e3
    );
    let _ = std::fs::remove_dir_all(&dir);
}
