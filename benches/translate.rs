//! Translation throughput: a generated program of 100,000 statements (origins, points,
//! patterns, macros, and DRL, TAP, REM, BOR and MIL cycles) through the translator, and the
//! printing of its blocks as ISO lines. Prints statements/s and blocks/s.
//!
//! Run: `cargo bench --bench translate`.

use novanc::settings::MachineSettings;
use novanc::tooldata::sample_magazine;
use novanc::translator::{iso_program, Statement, Translator};
use std::time::Instant;

/// Ten statements per unit: 5 definitions and 5 cycles.
fn program(units: usize) -> String {
    let mut s = String::with_capacity(units * 400);
    for k in 1..=units {
        let (a, b, c) = (3 * k - 2, 3 * k - 1, 3 * k);
        s += &format!(
            "DA{k} = ({}, {}, -400)\n\
             P{a} = (50, 50)\n\
             P{b} = P{a}(20, 10, -2)\n\
             PAT{k} = DA{k}, NH8, P{a}, R30, SA0, IA45\n\
             DRL, 106/DP10/PAT{k}\n\
             TAP, 208/DP8/PAT{k}\n\
             MAC{k} = DA{k}, P{a}, P{b}, (P{b}(-10,25)=P{c})\n\
             REM, 301/DP6/MAC{k}\n\
             BOR, 603/DP5, SDP2/DA{k}, P{a}\n\
             MIL, 402/DP2, LFT/DA{k}, P{a}, P{b}, P{c}, P{a}\n",
            300 + (k % 20) * 10,
            200 + (k % 15) * 10
        );
    }
    s
}

fn main() {
    let settings = MachineSettings::default();
    let magazine = sample_magazine();
    let src = program(10_000);
    let mut best = f64::MAX;
    let mut result: Vec<Statement> = Vec::new();
    for _ in 0..5 {
        let t = Instant::now();
        let stmts: Result<Vec<Statement>, _> =
            Translator::new(&src, magazine.clone(), settings.clone(), [0, 0, 0]).collect();
        let dt = t.elapsed().as_secs_f64();
        match stmts {
            Ok(s) => result = s,
            Err(e) => {
                eprintln!("the generated program does not translate: {e}");
                std::process::exit(1);
            }
        }
        best = best.min(dt);
    }
    let n_stmts = result.len();
    let n_blocks: usize = result.iter().map(|s| s.blocks.len()).sum();
    println!(
        "translate: {n_stmts} statements, {n_blocks} blocks, best of 5: {:.1} ms",
        best * 1e3
    );
    println!("  statements/s: {:.0}", n_stmts as f64 / best);
    println!("  blocks/s:     {:.0}", n_blocks as f64 / best);
    let t = Instant::now();
    let text = iso_program(&result, &settings);
    let dt = t.elapsed().as_secs_f64();
    println!(
        "print ISO: {} lines, {} bytes in {:.1} ms ({:.0} lines/s)",
        n_blocks + 2,
        text.len(),
        dt * 1e3,
        (n_blocks + 2) as f64 / dt
    );
}
