//! The fuzz command of issue 15 (README, *Limits*): generated part programs (by grammar and by
//! mutation of `programs/*.ap`), G-code programs (the same two ways, from `programs/*.ngc`),
//! tool tapes, T-code tables, editor command lines (on a buffer and on the stores), panel
//! scripts run on a console, damaged state directories, lathe programs (by grammar and by
//! mutation of the Citizen's and the lathe golden programs), and machine descriptions (by
//! lines and by mutation of `machines/*.machine`), each case checked for no panic, no
//! case slower than 5 s, no heap growth over 256 MB, the messages and limits of
//! docs/language.md and docs/gcode.md, and no store changed by a refused input.
//!
//! ```text
//! cargo test --release --test fuzz -- --ignored --nocapture     # 600 s; NOVANC_FUZZ_SECS=N for N s
//! NOVANC_FUZZ_SEED=0x1234 ...                                   # start from this base seed
//! NOVANC_FUZZ_REPLAY=family:0xSEED cargo test --release --test fuzz replay -- --nocapture
//! ```
//!
//! CI runs `fuzz_briefly`, a 3-second budget from a fixed seed (`NOVANC_FUZZ_BRIEF_SECS`).
//! Each finding becomes a regression test (`tests/translate_limits.rs`, `tests/bad_input.rs`).
//!
//! To add a family, write a function
//! `fn(&mut Rng, &Ctx) -> Result<(), String>` that generates one case from the generator, calls
//! `note` with its input and checks it, and add it to `FAMILIES`.

mod console;
#[path = "../common/counting.rs"]
mod counting;
mod desc;
mod editor;
mod gcode;
mod harness;
mod lathe;
mod programs;
mod rng;
mod tooldata;

use harness::{Ctx, Family};
use std::time::Duration;

#[global_allocator]
static ALLOC: harness::Counting = harness::Counting;

/// Every family; each gets an equal share of the time.
const FAMILIES: &[Family] = &[
    Family {
        name: "program-grammar",
        case: programs::grammar_case,
    },
    Family {
        name: "program-mutation",
        case: programs::mutation_case,
    },
    Family {
        name: "tape",
        case: tooldata::tape_case,
    },
    Family {
        name: "tcode-table",
        case: tooldata::tcode_case,
    },
    Family {
        name: "editor",
        case: editor::editor_case,
    },
    Family {
        name: "stores",
        case: editor::stores_case,
    },
    Family {
        name: "panel-script",
        case: console::script_case,
    },
    Family {
        name: "state-damage",
        case: console::damage_case,
    },
    Family {
        name: "gcode-program",
        case: gcode::gcode_case,
    },
    Family {
        name: "gcode-extremes",
        case: gcode::extremes_case,
    },
    Family {
        name: "lathe-program",
        case: lathe::lathe_case,
    },
    Family {
        name: "machine-description",
        case: desc::description_case,
    },
];

fn ctx() -> Ctx {
    let root = env!("CARGO_MANIFEST_DIR");
    let read = |ext: &str| {
        let mut v: Vec<String> = std::fs::read_dir(format!("{root}/programs"))
            .expect("programs/")
            .filter_map(|e| e.ok())
            .filter(|e| e.path().extension().is_some_and(|x| x == ext))
            .filter_map(|e| std::fs::read_to_string(e.path()).ok())
            .collect();
        v.sort();
        v
    };
    let programs = read("ap");
    let gcode = read("ngc");
    // The lathe's: the Citizen's channel programs and our lathe golden programs.
    let mut lathe = Vec::new();
    for dir in ["programs/citizen", "tests/golden/lathe_rs274"] {
        for e in std::fs::read_dir(format!("{root}/{dir}"))
            .expect(dir)
            .flatten()
        {
            if e.path().extension().is_some_and(|x| x == "ngc") {
                lathe.extend(std::fs::read_to_string(e.path()).ok());
            }
        }
    }
    lathe.sort();
    assert!(lathe.len() >= 8, "the lathe programs");
    assert!(programs.len() >= 3, "the sample programs");
    static N: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let n = N.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let tmp = std::env::temp_dir().join(format!("novanc-fuzz-{}-{n}", std::process::id()));
    std::fs::create_dir_all(&tmp).expect("a scratch directory");
    assert!(gcode.len() >= 3, "the sample G-code programs");
    // The machine descriptions: the shipped ones and the remap machine of the golden tests.
    let mut descriptions: Vec<String> = std::fs::read_dir(format!("{root}/machines"))
        .expect("machines/")
        .flatten()
        .filter(|e| e.path().extension().is_some_and(|x| x == "machine"))
        .filter_map(|e| std::fs::read_to_string(e.path()).ok())
        .collect();
    descriptions
        .extend(std::fs::read_to_string(format!("{root}/tests/golden/remap/remap.machine")).ok());
    descriptions.sort();
    assert!(descriptions.len() >= 4, "the machine descriptions");
    Ctx {
        programs,
        gcode,
        lathe,
        descriptions,
        tape: std::fs::read_to_string(format!("{root}/tooldata/tools.tt")).expect("tools.tt"),
        tcodes: std::fs::read_to_string(format!("{root}/tooldata/magazine.tc"))
            .expect("magazine.tc"),
        tmp,
    }
}

fn env_u64(name: &str) -> Option<u64> {
    let v = std::env::var(name).ok()?;
    let v = v.trim();
    match v.strip_prefix("0x") {
        Some(h) => u64::from_str_radix(h, 16).ok(),
        None => v.parse().ok(),
    }
}

fn fuzz(secs: u64, base: u64) {
    let c = ctx();
    let report = harness::run(FAMILIES, &c, Duration::from_secs(secs), base);
    let _ = std::fs::remove_dir_all(&c.tmp);
    println!("{}", report.text());
    assert!(report.failures.is_empty(), "{}", report.text());
}

/// The short budget CI runs (a few seconds, from a fixed seed).
#[test]
fn fuzz_briefly() {
    let secs = env_u64("NOVANC_FUZZ_BRIEF_SECS").unwrap_or(3);
    fuzz(secs, env_u64("NOVANC_FUZZ_SEED").unwrap_or(1));
}

/// The long run: `NOVANC_FUZZ_SECS` (default 600), from `NOVANC_FUZZ_SEED` or the clock.
#[test]
#[ignore]
fn fuzz_long() {
    let secs = env_u64("NOVANC_FUZZ_SECS").unwrap_or(600);
    let seed = env_u64("NOVANC_FUZZ_SEED").unwrap_or_else(|| {
        std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(1, |d| d.as_nanos() as u64)
    });
    println!("fuzz: base seed {seed:#x} (NOVANC_FUZZ_SEED={seed:#x} runs these cases again)");
    fuzz(secs, seed);
}

/// Replays one case: `NOVANC_FUZZ_REPLAY=family:0xSEED` (does nothing without it).
#[test]
fn replay() {
    let Ok(spec) = std::env::var("NOVANC_FUZZ_REPLAY") else {
        return;
    };
    let (name, seed) = spec.split_once(':').expect("family:seed");
    let seed = match seed.strip_prefix("0x") {
        Some(h) => u64::from_str_radix(h, 16).expect("a hex seed"),
        None => seed.parse().expect("a seed"),
    };
    let c = ctx();
    let out = harness::replay(FAMILIES, &c, name, seed).expect("a family name");
    let _ = std::fs::remove_dir_all(&c.tmp);
    println!("{out}");
    assert!(out.ends_with(": ok"), "{out}");
}

/// The samples the mutations start from translate whole, so that mutations reach every part
/// of the translator.
#[test]
fn the_sample_programs_translate() {
    let m = novanc::tooldata::sample_magazine();
    let c = ctx();
    let _ = std::fs::remove_dir_all(&c.tmp);
    for p in c.programs {
        let r: Result<Vec<_>, _> =
            novanc::translator::Translator::new(&p, m.clone(), Default::default(), [0, 0, 0])
                .collect();
        let stmts = r.unwrap_or_else(|e| panic!("{e} in\n{p}"));
        assert!(stmts.iter().map(|s| s.blocks.len()).sum::<usize>() > 50);
    }
}
