//! The lathe G-code reader never panics (docs/lathe-gcode.md "Bounds"): seeded random bytes,
//! runs of fragments and line-by-line lathe words, each refused with a place in the program or
//! read.

use novanc::lathe::desc::LatheDesc;
use novanc::lathe::gcode::{read_program, read_program_in, Parts, ReadOptions};
use novanc::pulse_core::testkit::Rng;
use novanc::settings::Dialect;

#[path = "common/gcode_fragments.rs"]
#[allow(dead_code)]
mod gcode_fragments;

fn desc() -> LatheDesc {
    let mut d = LatheDesc::citizen();
    for c in &mut d.channels {
        c.axes[0].travel = [-1.0, 100.0];
        c.axes[1].travel = [-200.0, 200.0];
    }
    d
}

#[test]
fn random_bytes_and_fragments_never_panic() {
    let frags = [
        "G0", "G1", "G2", "G3", "G4", "G7", "G8", "G18", "G20", "G21", "G33", "G40", "G41", "G42",
        "G70", "G71", "G76", "G90", "G91", "G94", "G95", "G96", "G97", "M0", "M1", "M2", "M3",
        "M4", "M5", "M10", "M11", "M100", "M130", "M30", "T0101", "T2", "T0303", "X", "Z", "U",
        "W", "I", "K", "R", "P", "Q", "F", "S", "D", "J", "H", "E", "L", "N1", "N2", "N3", "-",
        ".", "1", "2.5", "0", "10", "-3", "40", "0.8", "#1=", "[", "]", "(", ")", "/", "%", "\n",
        " ", "*", "#", "\u{e9}", "1e9", "G50", "G92", "G98", "G99",
    ];
    let words = [
        "G0 X",
        "G1 X",
        "G1 Z",
        "G2 X",
        "G3 Z",
        "G33 Z",
        "G76 P1 J0.1 K0.6 I-0.5 Z",
        "G71 U",
        "G71 P1 Q2 F",
        "G71 P1 Q2 F1 D",
        "G70 P1 Q",
        "G4 P",
        "G41 X",
        "G42 X",
        "G40 X",
        "G7 X",
        "G8 X",
        "G91 U",
        "W",
        "X",
        "Z",
        "R",
        "I",
        "K",
        "F",
        "S",
        "D",
        "M100 P",
        "M1",
        "M10 M",
        "G95 F",
        "G96 S",
        "G97 S",
        "G20 X",
        "G1 X",
        "G1 Z",
        "G0 Z",
        "X",
        "Z",
        // Fanuc's G code system A and two-block G76 (read so on channel 1 in Fanuc's dialect).
        "G76 P021060 Q150 R",
        "G76 X18. Z-20. P920 Q",
        "G90 X",
        "G92 Z-10. F",
        "G94 Z",
        "G50 S",
        "G99 F",
    ];
    let values = [
        "1", "5", "-2", "20", "0.5", "-10", "12", "0", "0.8", "101", "3", "-0.4",
    ];
    // Channel 1 reads Fanuc's G code system A when a program is read in Fanuc's dialect.
    let mut d = desc();
    d.channels[0].system_a = true;
    let mut rng = Rng::new(0x5eed_1a7e_u64);
    let mut good = 0;
    let mut deep = 0;
    let start = std::time::Instant::now();
    let mut errors = 0;
    for round in 0..10_000 {
        let mut text = String::new();
        if round % 5 == 0 {
            for _ in 0..(rng.next_u64() % 200) {
                text.push((rng.next_u64() % 128) as u8 as char);
            }
        } else if round % 5 == 1 {
            for _ in 0..(rng.next_u64() % 60) {
                text.push_str(rng.pick::<&str>(&frags));
                if rng.next_u64().is_multiple_of(3) {
                    text.push_str(rng.pick::<&str>(&["1", "5", "-2", "20", "0.5"]));
                }
            }
        } else {
            // Line by line, word by word: deep enough to reach moves, compensation, cycles.
            text.push_str(rng.pick::<&str>(&[
                "T0101 M3 S800 F100\n",
                "T0202 M4 G96 S100 F0.1 G95\n",
                "",
            ]));
            text.push_str(rng.pick::<&str>(&["G0 X40 Z5\n", "G0 X20 Z2\n", ""]));
            for _ in 0..(1 + rng.next_u64() % 14) {
                if rng.next_u64().is_multiple_of(6) {
                    text.push_str(rng.pick::<&str>(&["N1 ", "N2 ", "N3 ", "/"]));
                }
                for _ in 0..(1 + rng.next_u64() % 3) {
                    text.push_str(rng.pick::<&str>(&words));
                    text.push_str(rng.pick::<&str>(&values));
                    text.push(' ');
                }
                text.push('\n');
            }
        }
        let opts = ReadOptions {
            block_delete: round % 2 == 0,
            optional_stop: round % 3 == 0,
            // A part counter on some rounds (Fanuc's #3901/#3902 read, else refused).
            parts: (round % 4 == 0).then(|| Parts::new(&[1, 2, 3], 5)),
        };
        let ch = if round % 50 == 7 {
            3
        } else {
            (rng.next_u64() % 3) as usize
        };
        // The same text in Fanuc's dialect, with a macro word before it (the fuzz families
        // include the dialect): read or refused with its place, never a panic.
        let macro_word = [
            "",
            "#1 = 2\nWHILE [#1 GT 0] DO1\n#1 = #1 - 1\nEND1\n",
            "GOTO 1\n",
            "G65 P1 A1.\n",
            "IF [#0 EQ #1] GOTO 2\n",
        ][round % 5];
        // After the random lines, the machine state they leave is read and moved to (the
        // lathe's system variables, docs/lathe-gcode.md), in both dialects.
        let sysvars = [
            ("", ""),
            (
                "#1 = #5001 + #5002 + #4001 + #4120 + #2001 + #2901 + #10001 + #4109\nG0 X[#5001 - 1.] Z[#5002 - 1.]\n",
                "#1 = [#5420 + #5422 + #5400 + #5401 + #<_x> + #<_z> + #<_feed> + #<_line>]\nG0 X[#5420 * 2 - 1] Z[#<_z> - 1]\n",
            ),
            (
                "#1 = #3901 + #3902 + #4007 + #2301 + #2005 (print, #5001 #2001 #4120)\n#4001 = 1\n",
                "(print, #5420 #<_x> #<_motion_mode> #<_ccomp>)\n#5420 = 1\n",
            ),
        ][round % 3];
        let fanuc = format!("{macro_word}{text}{}", sysvars.0);
        let linuxcnc = format!("{text}{}", sysvars.1);
        for (program, dialect) in [(&fanuc, Dialect::Fanuc), (&linuxcnc, Dialect::LinuxCnc)] {
            let r = read_program_in(program, &d, ch, &opts, Some(dialect));
            if let Err(e) = r {
                let lines = program.lines().count().max(1) as u32;
                assert!(e.line >= 1 && e.line <= lines + 1, "{e} for {program:?}");
                assert!(!e.message.is_empty());
            }
        }
        match read_program(&text, &d, ch, &opts) {
            Ok(p) => {
                good += 1;
                assert!(p.iter().all(|s| s.line >= 1));
            }
            Err(e) => {
                errors += 1;
                if e.line > 3 {
                    deep += 1;
                }
                let lines = text.lines().count().max(1) as u32;
                assert!(e.line >= 1 && e.line <= lines + 1, "{e} for {text:?}");
                assert!(!e.message.is_empty());
            }
        }
    }
    eprintln!("fuzz: {errors} refused ({deep} past line 3), {good} read");
    assert!(
        good + deep > 800,
        "too few programs got past their first lines: {good} + {deep}"
    );
    assert!(
        errors > 100,
        "the fuzz found too few errors to be reading anything: {errors}"
    );
    assert!(start.elapsed().as_secs() < 5, "{:?}", start.elapsed());
}

/// Issue 20 (docs/limits.md): lathe lines with values at every edge (309 digits, 1e308,
/// denormals, negative zero, 1e17, 1e-12, dwells and feeds past the limits, leads and pitches
/// of nothing). No panic, no program slow to read, every error at a real line, and what is read
/// keeps the limits: dwells at most `MAX_DWELL_S`, feeds per minute at least `MIN_FEED`.
#[test]
fn extreme_values_never_panic_or_pass_a_limit() {
    use novanc::block::{FeedMode, Motion};
    use novanc::limits::{MAX_DWELL_S, MIN_FEED};
    let nums = gcode_fragments::extreme_numbers();
    let d = desc();
    let mut rng = Rng::new(0x2020_1ea7_u64);
    let (mut read, mut refused) = (0, 0);
    let start = std::time::Instant::now();
    for _ in 0..2000 {
        let mut text = String::from("T0101 M3 S1000 F100\nG0 X40 Z5\n");
        let lines = 1 + rng.next_u64() % 8;
        for _ in 0..lines {
            let kind = rng.next_u64() % 11;
            let mut n = || nums[(rng.next_u64() % nums.len() as u64) as usize].clone();
            let line = match kind {
                0 => format!("G0 X{} Z{}", n(), n()),
                1 => format!("G1 X{} Z{} F{}", n(), n(), n()),
                2 => format!("G95 G1 Z{} F{}", n(), n()),
                3 => format!("G4 P{}", n()),
                4 => format!("G33 Z{} K{}", n(), n()),
                5 => format!(
                    "G76 P{} Z{} I{} J{} K{} R{} H{}",
                    n(),
                    n(),
                    n(),
                    n(),
                    n(),
                    n(),
                    n()
                ),
                6 => format!("G96 S{} D{} M3", n(), n()),
                7 => format!("G97 S{} M3", n()),
                8 => format!("G2 X{} Z{} R{} F{}", n(), n(), n(), n()),
                9 => format!("#1={} G1 Z[#1] F[#1]", n()),
                _ => "G94".to_string(),
            };
            text.push_str(&line);
            text.push('\n');
        }
        let t = std::time::Instant::now();
        match read_program(&text, &d, 0, &ReadOptions::default()) {
            Ok(p) => {
                read += 1;
                for b in p.iter().flat_map(|s| &s.blocks) {
                    match (b.motion, b.feed_mode) {
                        (Motion::Dwell, _) => {
                            assert!(b.dwell_ns as f64 <= MAX_DWELL_S * 1e9, "{text}")
                        }
                        (Motion::Linear | Motion::ArcCw | Motion::ArcCcw, FeedMode::PerMin) => {
                            assert!(b.feed.is_finite() && b.feed >= MIN_FEED, "{text}")
                        }
                        _ => {}
                    }
                }
            }
            Err(e) => {
                refused += 1;
                let lines = text.lines().count() as u32;
                assert!(
                    e.line >= 1 && e.line <= lines && e.col >= 1,
                    "{e} for {text:?}"
                );
                assert!(e.to_string().len() < 300, "{e}");
            }
        }
        assert!(t.elapsed().as_secs() < 2, "{:?} for {text:?}", t.elapsed());
    }
    eprintln!(
        "lathe extremes: {read} read, {refused} refused in {:?}",
        start.elapsed()
    );
    assert!(read > 20 && refused > 200, "{read} read, {refused} refused");
}
