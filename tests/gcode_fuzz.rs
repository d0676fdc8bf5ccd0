//! Whatever text a file holds, reading it as G-code never panics and never runs unbounded:
//! every line either reads or gives `LINE:COL: reason` with a real line and column
//! (docs/gcode.md "Errors", "Limits"). Seeded random programs from valid fragments, mutated.

mod common;

use novanc::block::MachineState;
use novanc::gcode::{GcodeSource, Switches, WorkOffsets};
use novanc::pulse_core::testkit::Rng;
use novanc::settings::MachineSettings;
use novanc::tooldata::sample_magazine;

#[path = "common/gcode_fragments.rs"]
mod gcode_fragments;
use gcode_fragments::{extreme_program, FANUC_FRAGMENTS, FRAGMENTS};
use novanc::settings::Dialect;

fn program(rng: &mut Rng, extra: &[&str]) -> String {
    let mut s = String::new();
    let lines = rng.range(1, 40);
    for _ in 0..lines {
        let words = rng.range(0, 5);
        for _ in 0..words {
            let k = rng.range(0, (FRAGMENTS.len() + extra.len()) as i64 - 1) as usize;
            let f = FRAGMENTS
                .get(k)
                .unwrap_or_else(|| &extra[k - FRAGMENTS.len()]);
            s.push_str(f);
            s.push(' ');
        }
        if rng.range(0, 20) == 0 {
            // A random byte.
            s.push(char::from(rng.range(32, 126) as u8));
        }
        s.push('\n');
    }
    if rng.range(0, 2) == 0 {
        s.push_str("M30\nO100\nG91 G1 X1 F100\nM99\n");
    }
    s
}

#[test]
fn random_text_never_panics_and_errors_name_a_real_place() {
    fuzz(31, Dialect::LinuxCnc, &[]);
}

#[test]
fn the_fanuc_dialect_s_family_never_panics_and_errors_name_a_real_place() {
    fuzz(32, Dialect::Fanuc, FANUC_FRAGMENTS);
}

/// 3000 random programs of `FRAGMENTS` and `extra`, read in `dialect`.
fn fuzz(seed: u64, dialect: Dialect, extra: &[&str]) {
    let mut rng = Rng::new(seed);
    let (mut ok, mut refused) = (0, 0);
    for _ in 0..3000 {
        let src = program(&mut rng, extra);
        let n_lines = src.lines().count() as u32 + 1;
        let g = GcodeSource::new(
            src.clone().into(),
            sample_magazine(),
            MachineSettings {
                dialect,
                ..MachineSettings::default()
            },
            MachineState::at([500_000, 400_000, -300_000]),
            WorkOffsets::default(),
            Switches::default(),
        )
        .line_limit(100_000);
        let mut failed = false;
        for r in g {
            match r {
                Ok(st) => assert!(st.line >= 1 && st.line <= n_lines),
                Err(e) => {
                    assert!(e.line >= 1 && e.line <= n_lines, "{e} in\n{src}");
                    assert!(e.col >= 1, "{e}");
                    assert!(!e.message.is_empty());
                    failed = true;
                }
            }
        }
        if failed {
            refused += 1;
        } else {
            ok += 1;
        }
    }
    assert!(ok > 20 && refused > 20, "{ok} read, {refused} refused");
}

#[test]
fn deep_brackets_and_tiny_pecks_are_refused_not_run() {
    let src = format!("G0 X[{}1{}]\nM30\n", "[".repeat(4_000), "]".repeat(4_000));
    let e = common::gcode_source(&src)
        .find_map(|r| r.err())
        .map(|e| e.to_string());
    assert_eq!(
        e.as_deref(),
        Some("1:69: brackets, signs or # nested more than 64 deep")
    );
    let src = "G0 X10 Y10 Z0\nG83 X10 Y10 Z-50 R1 Q0.0001 F10\nM30\n";
    let e = common::gcode_source(src)
        .find_map(|r| r.err())
        .map(|e| e.to_string());
    assert_eq!(
        e.as_deref(),
        Some("2:21: G83: Q0.0001 would make more than 1000 pecks")
    );
}

/// Issue 20 (docs/limits.md): values at every edge (309 digits, 1e308, denormals, negative
/// zero, R 1e17, Q 1e-12, L 9999 and past it, dwells and feeds) in moves, arcs, compensation
/// and every canned cycle. No panic, no case slower than a few seconds (none runs unbounded),
/// every error at a real place, and what is made keeps the limits: no statement over
/// `MAX_BLOCKS` blocks, every feed finite and at least `MIN_FEED`, every dwell at most
/// `MAX_DWELL_S`, every point inside the travel.
#[test]
fn extreme_values_never_panic_hang_or_pass_a_limit() {
    use novanc::block::Motion;
    use novanc::limits::{MAX_BLOCKS, MAX_DWELL_S, MIN_FEED};
    let settings = MachineSettings::default();
    let mut rng = Rng::new(20);
    let (mut ok, mut refused, mut blocks) = (0, 0, 0usize);
    let start = std::time::Instant::now();
    for _ in 0..2000 {
        let src = extreme_program(|n| rng.range(0, n as i64 - 1) as usize);
        let n_lines = src.lines().count() as u32 + 1;
        let t = std::time::Instant::now();
        let mut failed = false;
        for r in GcodeSource::new(
            src.clone().into(),
            sample_magazine(),
            settings.clone(),
            MachineState::at([0, 0, 0]),
            WorkOffsets::default(),
            Switches::default(),
        ) {
            match r {
                Ok(st) => {
                    assert!(st.blocks.len() <= MAX_BLOCKS, "line {} in\n{src}", st.line);
                    blocks += st.blocks.len();
                    for b in &st.blocks {
                        assert!(settings.within_travel(b.end), "{b:?} in\n{src}");
                        if matches!(b.motion, Motion::Linear | Motion::ArcCw | Motion::ArcCcw) {
                            assert!(b.feed.is_finite() && b.feed >= MIN_FEED, "{b:?}\n{src}");
                        }
                        assert!(b.dwell_ns as f64 <= MAX_DWELL_S * 1e9, "{b:?}\n{src}");
                    }
                }
                Err(e) => {
                    assert!(
                        e.line >= 1 && e.line <= n_lines && e.col >= 1,
                        "{e} in\n{src}"
                    );
                    assert!(e.to_string().len() < 300, "{e}");
                    failed = true;
                }
            }
        }
        assert!(t.elapsed().as_secs() < 5, "{:?} for\n{src}", t.elapsed());
        if failed {
            refused += 1;
        } else {
            ok += 1;
        }
    }
    eprintln!(
        "extremes: {ok} read, {refused} refused, {blocks} blocks in {:?}",
        start.elapsed()
    );
    assert!(ok > 20 && refused > 100, "{ok} read, {refused} refused");
}
