//! The console's rules (docs/panel.md) through its public API: keys that are not valid change
//! nothing, DATA INPUT clears RUN, a translation error moves nothing, manual moves respect
//! the travel limits, edits survive a restart.

mod common;

use novanc::console::{Console, ConsoleConfig};
use novanc::panel_model::{Axis, DataMode, OpMode, PanelEvent as E};
use novanc::pulse_core::testkit::Rng;
use novanc::pulse_core::ClockMode;
use std::path::PathBuf;

fn open_in(dir: PathBuf) -> Console {
    let mut cfg = ConsoleConfig::new(dir);
    cfg.clock = ClockMode::Virtual;
    Console::open(cfg).unwrap().0
}

fn open(name: &str) -> Console {
    open_in(common::temp_dir(name))
}

/// The operator-visible state that bad keys must not touch.
fn snapshot(c: &Console) -> (String, String, [i64; 3], u8) {
    (
        c.program_text(),
        format!("{:?}", c.magazine()),
        c.status().pos.xyz(),
        c.status().run,
    )
}

#[test]
fn data_keys_outside_data_input_change_nothing_and_say_why() {
    let mut c = open("keys");
    for op in OpMode::ALL {
        // DATA INPUT edits; in MDI the data keys type the MDI buffer (docs/panel.md).
        if op == OpMode::Data || op == OpMode::Mdi {
            continue;
        }
        c.handle(E::Op(op));
        let before = snapshot(&c);
        for ev in [E::Type("2K".into()), E::Key('X'), E::Eob, E::Rubout] {
            c.handle(ev);
            c.wait_idle();
            assert_eq!(snapshot(&c), before, "in {op:?}");
            assert!(
                c.frame_text().contains("refused"),
                "in {op:?}:\n{}",
                c.frame_text()
            );
            assert!(c.view().entry.is_empty());
        }
    }
}

#[test]
fn start_jog_and_wheel_in_the_wrong_mode_change_nothing() {
    let mut c = open("wrongmode");
    c.handle(E::Op(OpMode::Data));
    let before = snapshot(&c);
    for ev in [
        E::Start,
        E::Wheel(Axis::X, 5),
        E::Jog(Axis::Y, 1),
        E::Override(155),
        E::WheelScale(7),
    ] {
        c.handle(ev.clone());
        c.wait_idle();
        assert_eq!(snapshot(&c), before, "{ev:?}");
    }
    assert_eq!(c.view().feed_override, 100);
    // The default increment: 0.1 mm (x100), refused x7 left it.
    assert_eq!(c.view().wheel.1, 100);
}

#[test]
fn switching_to_data_input_clears_run() {
    let mut c = open("clearrun");
    c.handle(E::Override(0));
    c.handle(E::Op(OpMode::Auto));
    c.handle(E::Start);
    // Override 0: RUN = 1, the machine waits.
    for _ in 0..200 {
        c.tick();
        if c.view().run == 1 {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    assert_eq!(c.view().run, 1);
    c.handle(E::Op(OpMode::Data));
    c.wait_idle();
    assert_eq!(c.view().run, 0);
    assert!(c.frame_text().contains("RUN cleared"), "{}", c.frame_text());
    // Editing is accepted now.
    c.handle(E::Data(DataMode::Revise));
    c.handle(E::Type("99LI; a comment*".into()));
    assert!(c.program_text().ends_with("; a comment\n"));
}

#[test]
fn a_translation_error_shows_its_line_and_nothing_moves() {
    let mut c = open("xlate");
    c.handle(E::Op(OpMode::Data));
    c.handle(E::Data(DataMode::Revise));
    c.handle(E::Type("99LIDRL, 999/DP5/DA1, P1*".into()));
    c.handle(E::Op(OpMode::Auto));
    c.handle(E::Start);
    c.wait_idle();
    let f = c.frame_text();
    assert!(f.contains("line 10:"), "{f}");
    assert!(c.view().lamps.alarm);
    assert_eq!(c.status().pos, [0, 0, 0]);
    assert_eq!(c.status().blocks_done, 0);
    // RESET clears the alarm.
    c.handle(E::Reset);
    assert!(!c.view().lamps.alarm);
}

#[test]
fn handwheel_and_step_move_within_the_travel_limits_only() {
    let mut c = open("manual");
    c.handle(E::Op(OpMode::Handle));
    c.handle(E::WheelScale(100));
    c.handle(E::Wheel(Axis::X, 10));
    c.wait_idle();
    assert_eq!(c.status().pos, [1000, 0, 0]);
    // X would go to -9 mm: below the travel limit, refused.
    c.handle(E::Wheel(Axis::X, -100));
    c.wait_idle();
    assert_eq!(c.status().pos, [1000, 0, 0]);
    assert!(
        c.frame_text().contains("outside travel"),
        "{}",
        c.frame_text()
    );
    c.handle(E::Op(OpMode::Step));
    c.handle(E::Jog(Axis::Y, 1));
    c.wait_idle();
    assert_eq!(c.status().pos, [1000, 100, 0]);
    // Z is at its upper limit (0): a step up is refused.
    c.handle(E::Jog(Axis::Z, 1));
    c.wait_idle();
    assert_eq!(c.status().pos, [1000, 100, 0]);
}

#[test]
fn emergency_stop_refuses_start_until_reset() {
    let mut c = open("estop");
    c.handle(E::Op(OpMode::Auto));
    c.handle(E::EStop);
    c.wait_idle();
    assert!(c.view().lamps.estop);
    // The program's header does not invite the START it would refuse (stop 47; it said
    // `TABLEB: press START` under the E-STOP alarm).
    let header = |c: &Console| c.frame_text().lines().next().unwrap_or("").to_string();
    assert!(
        header(&c).contains("RESET, then START"),
        "{}",
        c.frame_text()
    );
    c.handle(E::Start);
    c.wait_idle();
    assert_eq!(c.status().blocks_done, 0);
    assert!(
        c.frame_text().contains("EMERGENCY STOP"),
        "{}",
        c.frame_text()
    );
    c.handle(E::Reset);
    c.wait_idle();
    assert!(!c.view().lamps.estop);
    assert!(header(&c).contains("press START"), "{}", c.frame_text());
    c.handle(E::Start);
    c.wait_idle();
    assert!(c.status().blocks_done > 50, "{}", c.status().blocks_done);
}

#[test]
fn an_estop_during_a_run_says_the_line_it_stopped_in_until_reset() {
    let mut c = open("estop-line");
    c.handle(E::Op(OpMode::Auto));
    c.handle(E::Start);
    c.handle(E::WaitMs(8000));
    let line = c.status().executing.as_ref().map_or(0, |e| e.stmt.line);
    assert!(line > 1, "a block after the first runs: {line}");
    c.handle(E::EStop);
    c.wait_idle();
    let first = c.frame_text().lines().next().unwrap_or("").to_string();
    assert!(
        first.ends_with(&format!("E-STOP in line {line}: RESET first")),
        "{first}"
    );
    // The listing stands at that line, marked, as a lathe channel's does: the one line
    // marked is the program's line `line`.
    let text = c.program_text();
    let source = text.lines().nth(line as usize - 1).unwrap().to_string();
    let frame = c.frame_text();
    let marked: Vec<&str> = frame.lines().filter(|l| l.starts_with('>')).collect();
    assert_eq!(marked.len(), 1, "{frame}");
    assert!(source.starts_with(marked[0][1..].trim_end()), "{frame}");
    // An MDI page does not show the AUTO run's line.
    c.handle(E::Op(OpMode::Mdi));
    let first = c.frame_text().lines().next().unwrap_or("").to_string();
    assert!(first.ends_with("RESET, then START"), "{first}");
    c.handle(E::Op(OpMode::Auto));
    c.handle(E::Reset);
    c.wait_idle();
    let frame = c.frame_text();
    let first = frame.lines().next().unwrap_or("").to_string();
    assert!(first.ends_with(": press START"), "{first}");
    assert!(!frame.lines().any(|l| l.starts_with('>')), "{frame}");
}

#[test]
fn single_block_runs_one_block_per_start() {
    let mut c = open("single");
    c.handle(E::Op(OpMode::Single));
    for n in 1..=5u64 {
        c.handle(E::Start);
        c.wait_idle();
        assert_eq!(c.status().blocks_done, n);
        assert_eq!(c.view().run, 0);
    }
    // Turning to AUTO and START runs the rest.
    c.handle(E::Op(OpMode::Auto));
    c.handle(E::Start);
    c.wait_idle();
    assert!(c.status().program_end);
}

#[test]
fn accepted_edits_survive_a_restart() {
    let dir = common::temp_dir("persist");
    {
        let mut c = open_in(dir.clone());
        c.handle(E::Op(OpMode::Data));
        c.handle(E::Data(DataMode::Revise));
        c.handle(E::Type("99LIGO, 10, 10, -10*".into()));
        c.handle(E::Data(DataMode::TCode));
        c.handle(E::Type("T21=111".into()));
    }
    let c = open_in(dir);
    assert!(c.program_text().ends_with("GO, 10, 10, -10\n"));
    assert_eq!(c.magazine().tcodes.tool_in(21), Some(111));
}

#[test]
fn a_random_session_never_corrupts_the_display_or_edits_outside_data_input() {
    let mut c = open("random");
    let mut r = Rng::new(0x5eed);
    let words = [
        "2K", "I*", "-5D", "S$", "C$", "Y", "T5=", "0", "6", "Q", "%%", "", "9999999L",
    ];
    let rows = c.config().rows;
    let cols = c.config().cols;
    for _ in 0..1500 {
        let ev = match r.below(14) {
            0 => E::Op(OpMode::ALL[r.below(7)]),
            1 => E::Data(DataMode::ALL[r.below(7)]),
            2 | 3 => E::Type(words[r.below(words.len())].into()),
            4 => E::Key(char::from(32 + r.below(95) as u8)),
            5 => E::Eob,
            6 => E::Rubout,
            7 => E::Start,
            8 => E::Stop,
            9 => E::Reset,
            10 => E::Override((r.below(17) * 10) as u32),
            11 => E::Wheel(Axis::Z, r.below(5) as i32 - 2),
            12 => E::Jog(Axis::X, if r.below(2) == 0 { -1 } else { 1 }),
            _ => E::JogRelease,
        };
        let op = c.view().op_mode;
        let text = c.program_text();
        c.handle(ev.clone());
        if op != OpMode::Data && !matches!(ev, E::Op(_)) {
            assert_eq!(
                c.program_text(),
                text,
                "{ev:?} in {op:?} edited the program"
            );
        }
        let v = c.view();
        assert_eq!(v.display.len(), rows);
        assert!(v.display.iter().all(|l| l.chars().count() == cols));
        let s = c.settings().clone();
        for a in 0..3 {
            let (lo, hi) = s.travel_pulses(a);
            assert!(c.status().pos[a] >= lo && c.status().pos[a] <= hi);
        }
    }
    c.handle(E::Reset);
    c.wait_idle();
}

/// Z axis position after the first four blocks of Table B in single block (tool T01 changed,
/// rapid to the first hole, spindle on, rapid down): axis Z = tip Z + set length.
fn z_after_four_blocks(c: &mut Console) -> i64 {
    c.handle(E::Op(OpMode::Single));
    for _ in 0..4 {
        c.handle(E::Start);
        c.wait_idle();
    }
    assert_eq!(c.status().blocks_done, 4);
    c.status().pos[2]
}

#[test]
fn a_tool_revision_changes_the_next_run_not_the_program() {
    let mut plain = open("rev-a");
    let z0 = z_after_four_blocks(&mut plain);
    let mut c = open("rev-b");
    let program = c.program_text();
    c.handle(E::Op(OpMode::Data));
    c.handle(E::Data(DataMode::ToolRevise));
    // T01 is the boring bar 00610: set length 220 → 225.
    c.handle(E::Type("C220$225".into()));
    assert!(c.frame_text().contains("ok"), "{}", c.frame_text());
    let z1 = z_after_four_blocks(&mut c);
    assert_eq!(z1 - z0, 5000, "Z carries the set length");
    assert_eq!(c.program_text(), program);
}

#[test]
fn run_text_is_the_mdi_buffer_in_mdi_and_program_memory_otherwise() {
    let mut c = open("runtext");
    c.handle(E::Op(OpMode::Data));
    c.handle(E::Data(DataMode::Mdi));
    c.handle(E::Type("IGO, 100, 50, -20*".into()));
    assert_eq!(c.run_text(), c.program_text(), "DATA INPUT: program memory");
    assert!(c.program_text().starts_with("DA1 = (200, 0, -450)"));
    c.handle(E::Op(OpMode::Mdi));
    assert_eq!(c.run_text(), "GO, 100, 50, -20\n");
    c.handle(E::Op(OpMode::Auto));
    assert_eq!(c.run_text(), c.program_text());
}

/// The front of the console: the display program and the operator pages (which draw the
/// screens) and the key map. They read the model and act on it; the model names none of them
/// (issue 23: "the display depends on the model, the model on nothing of the display").
const FRONT: [&str; 3] = ["display", "pages", "keys"];

/// The console's own modules as `src/console/` holds them (`pages/` is one module).
fn console_modules() -> Vec<(String, String)> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src/console");
    let mut out = Vec::new();
    for (sub, module) in [("", None), ("pages", Some("pages"))] {
        let d = dir.join(sub);
        let mut names: Vec<_> = std::fs::read_dir(&d)
            .unwrap()
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "rs"))
            .collect();
        names.sort();
        for p in names {
            let stem = p.file_stem().unwrap().to_string_lossy().into_owned();
            let name = module.map(str::to_string).unwrap_or(stem);
            out.push((name, std::fs::read_to_string(&p).unwrap()));
        }
    }
    out
}

/// The first path segment of every item a `use` group or path names after `at` (`{a, b::c}`
/// gives a and b; `x::y` gives x).
fn named_after(text: &str, at: usize) -> Vec<String> {
    let rest = &text[at..];
    if let Some(group) = rest.strip_prefix('{') {
        let (mut depth, mut end) = (0, group.len());
        for (i, ch) in group.char_indices() {
            match ch {
                '{' => depth += 1,
                '}' if depth == 0 => {
                    end = i;
                    break;
                }
                '}' => depth -= 1,
                _ => {}
            }
        }
        return group[..end]
            .split(',')
            .filter_map(|item| {
                let head = item.trim().split("::").next()?.trim();
                (!head.is_empty() && !head.starts_with('{')).then(|| head.to_string())
            })
            .collect();
    }
    let ident: String = rest
        .chars()
        .take_while(|c| c.is_alphanumeric() || *c == '_')
        .collect();
    vec![ident]
}

/// The edges of the console's module graph: (module, module it names), each pair once, read
/// from the sources with their comments left out. `mod` is `src/console/mod.rs` (the
/// `Console` type and the items it declares).
fn console_edges() -> Vec<(String, String)> {
    let modules = console_modules();
    let known: std::collections::BTreeSet<String> =
        modules.iter().map(|(m, _)| m.clone()).collect();
    let mut edges = std::collections::BTreeSet::new();
    for (from, text) in &modules {
        let code: String = text
            .lines()
            .map(|l| l.split("//").next().unwrap_or(""))
            .collect::<Vec<_>>()
            .join("\n");
        // In pages/, `super::` is pages itself and `super::super::` the console; elsewhere
        // `super::` is the console. `crate::console::` is the console everywhere; mod.rs names
        // its modules bare.
        let prefixes: &[&str] = if from == "pages" {
            &["super::super::", "crate::console::"]
        } else if from == "mod" {
            &["crate::console::", ""]
        } else {
            &["super::", "crate::console::"]
        };
        for prefix in prefixes {
            let mut at = 0;
            while at < code.len() {
                let found = if prefix.is_empty() {
                    known
                        .iter()
                        .filter_map(|m| {
                            code[at..]
                                .find(&format!("{m}::"))
                                .map(|i| (at + i, m.len() + 2))
                        })
                        .min()
                } else {
                    code[at..].find(prefix).map(|i| (at + i, prefix.len()))
                };
                let Some((i, len)) = found else { break };
                let boundary = i == 0
                    || !code[..i]
                        .chars()
                        .next_back()
                        .is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':');
                if boundary {
                    let targets = if prefix.is_empty() {
                        vec![code[i..i + len - 2].to_string()]
                    } else {
                        named_after(&code, i + len)
                    };
                    for t in targets.into_iter().filter(|t| t != "self") {
                        let to = if known.contains(&t) && t != "mod" {
                            t
                        } else {
                            "mod".to_string()
                        };
                        if &to != from {
                            edges.insert((from.clone(), to));
                        }
                    }
                }
                at = i + len;
            }
        }
    }
    edges.into_iter().collect()
}

#[test]
fn the_console_model_names_nothing_of_the_display() {
    let edges = console_edges();
    let front = |m: &str| FRONT.contains(&m);
    let between = |a: bool, b: bool| {
        edges
            .iter()
            .filter(|(f, t)| f != "mod" && t != "mod" && front(f) == a && front(t) == b)
            .count()
    };
    println!(
        "console module graph: {} edges; model->model {}, front->model {}, front->front {}, model->front {}",
        edges.len(),
        between(false, false),
        between(true, false),
        between(true, true),
        between(false, true)
    );
    for (f, t) in &edges {
        println!("  {f} -> {t}");
    }
    let wrong: Vec<_> = edges
        .iter()
        .filter(|(f, t)| f != "mod" && !front(f) && front(t))
        .collect();
    assert!(
        wrong.is_empty(),
        "model modules that name the display, the pages or the key map: {wrong:?}"
    );
}

/// DESIGN.md: "Nothing below the command line imports from it." The terminal and the window
/// are front ends beside it, and take the MTConnect feed and the stop signals from their own
/// modules (`mtconnect::feed`, `signals`), not from `cli` (issue 22: the window imported the
/// command line). Read from the sources with their comments left out.
#[test]
fn nothing_outside_the_command_line_imports_it() {
    fn walk(dir: &std::path::Path, out: &mut Vec<std::path::PathBuf>) {
        for e in std::fs::read_dir(dir).unwrap().filter_map(|e| e.ok()) {
            let p = e.path();
            if p.is_dir() {
                walk(&p, out);
            } else if p.extension().is_some_and(|x| x == "rs") {
                out.push(p);
            }
        }
    }
    let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    walk(&src, &mut files);
    let mut bad = Vec::new();
    for p in files {
        let rel = p
            .strip_prefix(&src)
            .unwrap()
            .to_string_lossy()
            .replace('\\', "/");
        if rel.starts_with("cli/") || rel == "main.rs" {
            continue;
        }
        let text = std::fs::read_to_string(&p).unwrap();
        for (i, l) in text.lines().enumerate() {
            let code = l.split("//").next().unwrap_or("");
            if code.contains("crate::cli") || code.contains("novanc::cli") {
                bad.push(format!("src/{rel}:{}: {}", i + 1, l.trim()));
            }
        }
    }
    assert!(
        bad.is_empty(),
        "imports of the command line:\n{}",
        bad.join("\n")
    );
    assert!(
        files_named(&src, "cli").len() > 3,
        "the walk found the command line's own files"
    );
}

fn files_named(src: &std::path::Path, dir: &str) -> Vec<String> {
    std::fs::read_dir(src.join(dir))
        .map(|d| {
            d.filter_map(|e| e.ok().map(|e| e.file_name().to_string_lossy().into_owned()))
                .collect()
        })
        .unwrap_or_default()
}
