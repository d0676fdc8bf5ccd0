//! The printed program is valid G-code that describes exactly the blocks' moves: a small,
//! independent G-code reader (modal G, absolute coordinates, incremental I J) reads it back and
//! checks every line against its block — end point, axis amounts, motion, F, S, T, M, dwell —
//! on Table B, a milling program and seeded random programs.

use novanc::block::{Block, Motion};
use novanc::pulse_core::testkit::Rng;
use novanc::settings::MachineSettings;
use novanc::tooldata::sample_magazine;
use novanc::translator::{iso_program, translate_all, Statement};

/// One word: letter and value.
fn words(line: &str) -> Vec<(char, f64)> {
    line.split_whitespace()
        .map(|w| {
            let mut c = w.chars();
            let letter = c.next().expect("a word");
            assert!(letter.is_ascii_uppercase(), "bad word {w} in {line}");
            let v: f64 = c
                .as_str()
                .parse()
                .unwrap_or_else(|_| panic!("bad number in {w}"));
            (letter, v)
        })
        .collect()
}

fn mm_to_pulses(v: f64) -> i64 {
    (v * 1000.0).round() as i64
}

/// Reads the program and checks it against the blocks; returns how many lines it read.
fn check(program: &str, stmts: &[Statement], start: [i64; 3]) -> usize {
    let blocks: Vec<&Block> = stmts.iter().flat_map(|s| &s.blocks).collect();
    let lines: Vec<&str> = program.lines().collect();
    assert_eq!(lines.first(), Some(&"G21 G90 G17 G94 G40 G49 G80"));
    // The program ends with the translator's end-of-program block `Nn M30`, or a bare `M30`
    // when the blocks end otherwise.
    let last = lines.last().copied().unwrap_or("");
    assert!(last.ends_with("M30"), "last line {last}");
    let body = if last == "M30" {
        &lines[1..lines.len() - 1]
    } else {
        &lines[1..]
    };
    assert_eq!(body.len(), blocks.len(), "one line per block");
    let mut pos = [
        start[0] as f64 / 1000.0,
        start[1] as f64 / 1000.0,
        start[2] as f64 / 1000.0,
    ];
    let mut modal_g = -1;
    for (line, b) in body.iter().zip(&blocks) {
        let ws = words(line);
        let get = |c: char| ws.iter().find(|w| w.0 == c).map(|w| w.1);
        let count = |c: char| ws.iter().filter(|w| w.0 == c).count();
        assert!(count('M') <= 1, "more than one M in {line}");
        assert!(count('G') <= 1, "more than one G in {line}");
        for (c, _) in &ws {
            assert!("NGXYZIJPFSTM".contains(*c), "unexpected word {c} in {line}");
        }
        assert_eq!(get('N'), Some(b.seq as f64), "{line}");
        let g = get('G').map(|g| g as i32);
        let has_axis = count('X') + count('Y') + count('Z') > 0;
        if let Some(g) = g {
            if g != 4 {
                modal_g = g;
            }
        }
        let start_pos = pos;
        let motion = match g {
            Some(4) => Motion::Dwell,
            _ if !has_axis => Motion::Aux,
            _ => match modal_g {
                0 => Motion::Rapid,
                1 => Motion::Linear,
                2 => Motion::ArcCw,
                3 => Motion::ArcCcw,
                other => panic!("axis words with no motion G (modal {other}) in {line}"),
            },
        };
        assert_eq!(motion, b.motion, "{line}");
        if motion != Motion::Dwell {
            for (i, c) in ['X', 'Y', 'Z'].into_iter().enumerate() {
                if let Some(v) = get(c) {
                    pos[i] = v;
                }
            }
        }
        let end = [
            mm_to_pulses(pos[0]),
            mm_to_pulses(pos[1]),
            mm_to_pulses(pos[2]),
        ];
        let from = [
            mm_to_pulses(start_pos[0]),
            mm_to_pulses(start_pos[1]),
            mm_to_pulses(start_pos[2]),
        ];
        assert_eq!(end, b.end, "end point of {line}");
        assert_eq!(
            [end[0] - from[0], end[1] - from[1], end[2] - from[2]],
            b.delta,
            "axis amounts of {line}"
        );
        match motion {
            Motion::ArcCw | Motion::ArcCcw => {
                let (i, j) = (get('I').expect("I"), get('J').expect("J"));
                assert_eq!(Some([mm_to_pulses(i), mm_to_pulses(j)]), b.center, "{line}");
                let (cx, cy) = (start_pos[0] + i, start_pos[1] + j);
                let r0 = (start_pos[0] - cx).hypot(start_pos[1] - cy);
                let r1 = (pos[0] - cx).hypot(pos[1] - cy);
                assert!((r0 - r1).abs() <= 0.002, "arc radii differ in {line}");
                assert!(r0 > 0.0005, "arc of no radius in {line}");
                assert_eq!(get('F'), Some(b.feed), "{line}");
            }
            Motion::Linear => assert_eq!(get('F'), Some(b.feed), "{line}"),
            Motion::Dwell => {
                let p = get('P').expect("P");
                assert_eq!((p * 1e9).round() as u64, b.dwell_ns, "{line}");
            }
            Motion::Rapid | Motion::Aux => assert_eq!(get('F'), None, "{line}"),
        }
        assert_eq!(get('S').map(|s| s as u32), b.s, "{line}");
        assert_eq!(get('T').map(|t| t as u32), b.t, "{line}");
        assert_eq!(get('M').map(|m| m as u8), b.m, "{line}");
    }
    body.len()
}

fn run(src: &str, start: [i64; 3]) -> Result<usize, String> {
    let st = MachineSettings::default();
    let stmts = translate_all(src, &sample_magazine(), &st, start).map_err(|e| e.to_string())?;
    let prog = iso_program(&stmts, &st);
    Ok(check(&prog, &stmts, start))
}

#[test]
fn table_b_reads_back_exactly() {
    let n = run(include_str!("../programs/tableb.ap"), [0, 0, 0]).unwrap();
    assert_eq!(n, 101, "98 cycle blocks and M05, G00 Z0, M30 at the end");
}

const MILLING: &str = "\
DA1 = (300, 200, -420)
P1 = (0, 0)
P2 = (60, 0)
P3 = (60, 40)
P4 = (0, 40)
P5 = (30, 20)
C1 = P5, R12.5
MIL, 402/DP4, LFT/DA1, P1, P2, P3, P4, P1
MIL, 402/DP4, RGT/DA1, P1, P2, P3, P4, P1
MIL, 404/DP2/DA1, P1, P3, (P3(-20,7)), C1
MIL, 404/DP3, LFT/DA1, C1
DRL, 106/DP20, DH6, DW0.5/DA1, P5, (P5(10,0)=P6)
REM, 301/DP15, DW1/DA1, P6
BOR, 603/DP10, SDP4/DA1, P5, P6
GO, DA1, 0, 0, 30
GD, 10, -5, 2
CL
";

#[test]
fn a_milling_program_reads_back_exactly() {
    let n = run(MILLING, [1000, 2000, -3000]).unwrap();
    assert!(n > 80, "{n} lines");
}

/// A length in [lo, hi) mm, to the micrometre.
fn mm(rng: &mut Rng, lo: f64, hi: f64) -> f64 {
    (rng.uniform(lo, hi) * 1000.0).round() / 1000.0
}

/// A random program of definitions, patterns, cycles, contours and positioning.
fn random_program(rng: &mut Rng) -> String {
    let drills = [101, 106, 105, 107, 109, 110, 104, 108];
    let taps = [208, 206, 209, 205];
    let mut s = String::new();
    let (mut p, mut pat) = (0, 0);
    let da_z = mm(rng, -450.0, -330.0);
    s += &format!(
        "DA1 = ({}, {}, {da_z})\n",
        mm(rng, 200.0, 700.0),
        mm(rng, 200.0, 500.0)
    );
    for _ in 0..12 {
        match rng.below(9) {
            0 | 1 => {
                p += 1;
                s += &format!(
                    "P{p} = ({}, {}, {})\n",
                    mm(rng, -100.0, 100.0),
                    mm(rng, -100.0, 100.0),
                    mm(rng, -10.0, 5.0)
                );
            }
            2 if p > 0 => {
                pat += 1;
                s += &format!(
                    "PAT{pat} = DA1, NH{}, P{}, R{}, SA{}, IA{}\n",
                    1 + rng.below(8),
                    1 + rng.below(p),
                    mm(rng, 5.0, 80.0),
                    mm(rng, 0.0, 90.0),
                    mm(rng, 10.0, 60.0)
                );
            }
            3 if pat > 0 => {
                let t = drills[rng.below(drills.len())];
                let dh = if rng.below(2) == 0 {
                    format!(", DH{}", mm(rng, 2.0, 8.0))
                } else {
                    String::new()
                };
                s += &format!(
                    "DRL, {t}/DP{}{dh}/PAT{}\n",
                    mm(rng, 1.0, 30.0),
                    1 + rng.below(pat)
                );
            }
            4 if p > 0 => {
                let t = taps[rng.below(taps.len())];
                s += &format!(
                    "TAP, {t}/DP{}/DA1, P{}\n",
                    mm(rng, 3.0, 20.0),
                    1 + rng.below(p)
                );
            }
            5 if p > 0 => {
                s += &format!(
                    "BOR, 603/DP{}, SDP2, DW0.25/DA1, P{}\n",
                    mm(rng, 3.0, 20.0),
                    1 + rng.below(p)
                )
            }
            6 if p > 0 => {
                // A regular polygon about a point, closed, milled inside or outside.
                let c = 1 + rng.below(p);
                let n = 3 + rng.below(5);
                let r = mm(rng, 15.0, 40.0);
                let mut names = Vec::new();
                for k in 0..n {
                    let a = (k as f64 * 360.0 / n as f64).to_radians();
                    p += 1;
                    s += &format!("P{p} = P{c}({:.3}, {:.3})\n", r * a.cos(), r * a.sin());
                    names.push(format!("P{p}"));
                }
                names.push(names[0].clone());
                let side = ["RGT, ", "LFT, ", ""][rng.below(3)];
                s += &format!(
                    "MIL, 402/{side}DP{}/DA1, {}\n",
                    mm(rng, 1.0, 5.0),
                    names.join(", ")
                );
            }
            7 => {
                s += &format!(
                    "GO, DA1, {}, {}, 60\n",
                    mm(rng, -50.0, 50.0),
                    mm(rng, -50.0, 50.0)
                )
            }
            _ => s += "CL\n",
        }
    }
    s
}

#[test]
fn random_programs_read_back_exactly() {
    let mut rng = Rng::new(0x5EED_0003);
    let mut ok = 0;
    for _ in 0..200 {
        let src = random_program(&mut rng);
        let start = [
            rng.below(1_000_000) as i64,
            rng.below(800_000) as i64,
            -(rng.below(100_000) as i64),
        ];
        match run(&src, start) {
            Ok(n) => ok += usize::from(n > 0),
            Err(e) => panic!("{e}\n{src}"),
        }
    }
    assert!(ok > 150, "only {ok} of 200 random programs made blocks");
}
