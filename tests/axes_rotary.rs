//! The rotary A axis (issue 22, "N axes"): a 4-axis program runs on `--machine centre4`, its A
//! pulses in the recording equal its A counter, its A moves are LinuxCNC's (rs274 for an
//! unwrapped A; the WRAPPED_ROTARY rule worked out independently here, since the standalone
//! rs274 reads no axis configuration), and A is refused with its place where it cannot act.

mod common;

use common::novanc;

use common::{python_check, temp_dir};
use std::path::Path;
use std::process::Command;

fn repo(p: &str) -> String {
    format!("{}/{p}", env!("CARGO_MANIFEST_DIR"))
}

/// The A words of a program as G90/G91 and values (degrees), in order: the test's own reading,
/// independent of novanc's reader (the program has one A word a line, no expressions).
fn a_words(text: &str) -> Vec<(bool, f64)> {
    let mut incremental = false;
    let mut out = Vec::new();
    for line in text.lines() {
        let code = line.split('(').next().unwrap_or("");
        for w in code.split_whitespace() {
            match w {
                "G90" => incremental = false,
                "G91" => incremental = true,
                _ => {}
            }
            if let Some(v) = w.strip_prefix('A') {
                out.push((incremental, v.parse::<f64>().expect("an A number")));
            }
        }
    }
    out
}

/// LinuxCNC 2.9's A positions for `words` from 0: G91 adds; G90 on a wrapped axis goes to the
/// nearest position ≡ |v| (mod 360) in the direction of v's sign (interp_find.cc
/// `unwrap_rotary`); on an unwrapped axis to v.
fn linuxcnc_a(words: &[(bool, f64)], wrapped: bool) -> Vec<f64> {
    let mut a: f64 = 0.0;
    let mut out = Vec::new();
    for &(inc, v) in words {
        a = if inc {
            a + v
        } else if wrapped {
            let mut r = (a / 360.0).floor() * 360.0 + v.abs();
            if v.is_sign_negative() && r > a {
                r -= 360.0;
            }
            if !v.is_sign_negative() && r < a {
                r += 360.0;
            }
            r
        } else {
            v
        };
        out.push(a);
    }
    out
}

/// The number after `key` on the line of `text` that starts with `line`.
fn field(text: &str, line: &str, key: &str) -> Option<f64> {
    let l = text.lines().find(|l| l.starts_with(line))?;
    let mut it = l.split_whitespace();
    it.find(|w| *w == key)?;
    it.next()?.parse().ok()
}

#[test]
fn the_wrapped_4_axis_program_runs_records_and_its_a_pulses_equal_its_counter() {
    let prog = repo("programs/wrap4.ngc");
    let text = std::fs::read_to_string(&prog).unwrap();
    let ends = linuxcnc_a(&a_words(&text), true);
    let mut travel = 0.0;
    let mut from = 0.0;
    for &e in &ends {
        travel += (e - from).abs();
        from = e;
    }
    let want_pulses = (travel / 0.001).round() as u64;
    let dir = temp_dir("axes-wrap4");
    let rec = dir.join("wrap4.mcap");
    let out = novanc(&[
        "run",
        &prog,
        "--machine",
        "centre4",
        "--record",
        rec.to_str().unwrap(),
    ]);
    let so = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(
        out.status.success(),
        "{so}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // The A counter: every degree the LinuxCNC rule turns, in 0.001° pulses.
    assert_eq!(field(&so, "pulses:", "A"), Some(want_pulses as f64), "{so}");
    assert_eq!(
        want_pulses, 1_170_000,
        "two turns of groove and five quarter turns"
    );
    let last = *ends.last().unwrap();
    assert_eq!(field(&so, "final position:", "A"), Some(last), "{so}");
    assert!(so.contains("recording complete: yes"), "{so}");
    // The recording: /nc/pulses of A add up to the counter (Python's mcap reader).
    if let Some((ok, check)) = python_check(&rec, &["--expect-complete"]) {
        assert!(ok, "{check}");
        let pulses = field(&check, "pulses", "A");
        assert_eq!(pulses, Some(want_pulses as f64), "{check}");
    }
    // A 3-axis machine refuses the program at its first A word, with its place.
    let out = novanc(&["run", &prog]);
    let se = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        se.contains("wrap4.ngc:9:14: unknown word A (novanc has the axes X, Y and Z)"),
        "{se}"
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// `novanc translate` of `text` on the machine `desc`: the A of every block that turns it.
fn listed_a(dir: &Path, text: &str, desc: &str) -> Result<Vec<f64>, String> {
    let prog = dir.join("a.ngc");
    std::fs::write(&prog, text).unwrap();
    let out = novanc(&["translate", prog.to_str().unwrap(), "--machine", desc]);
    if !out.status.success() {
        return Err(String::from_utf8_lossy(&out.stderr).to_string());
    }
    Ok(String::from_utf8_lossy(&out.stdout)
        .lines()
        .flat_map(|l| {
            l.split_whitespace()
                .filter_map(|w| w.strip_prefix('A')?.parse().ok())
        })
        .collect())
}

const UNWRAPPED: &str = "machine table\nkind mill\npulse 0.001\nx travel 0 1000 rapid 12000 accel 1000\ny travel 0 800 rapid 12000 accel 1000\nz travel -600 0 rapid 12000 accel 1000\na rotary travel -720 720 rapid 12000 accel 1000\n";

const MOVES: &str = "G21 G90 G94\nG0 X10 Y10 Z-10\nG0 A90\nG1 X20 A180 F600\nG91 G1 A-45 F3600\nG1 X5 A400\nG90 G0 A-10\nA20\nG1 X30 Y20 A0\nG91 A-30\nG90\nM2\n";

#[test]
fn a_moves_agree_with_rs274_on_an_unwrapped_axis_and_with_linuxcnc_s_rule_on_a_wrapped_one() {
    let dir = temp_dir("axes-rs274");
    let desc = dir.join("table.machine");
    std::fs::write(&desc, UNWRAPPED).unwrap();
    let got = listed_a(&dir, MOVES, desc.to_str().unwrap()).unwrap();
    let words = a_words(MOVES);
    // Unwrapped: what rs274 makes (its default configuration has an unwrapped A), if it is
    // installed; the rule otherwise.
    let want: Vec<f64> = match rs274_turns(&dir.join("a.ngc"), &dir, &[3]) {
        Some(v) => v.into_iter().map(|p| p[0]).collect(),
        _ => {
            eprintln!("rs274 not installed: the unwrapped A checked against the rule");
            let mut v = linuxcnc_a(&words, false);
            v.dedup();
            v
        }
    };
    assert_eq!(got, want, "unwrapped A: novanc against rs274");
    let mut rule = linuxcnc_a(&words, false);
    rule.dedup();
    assert_eq!(want, rule, "rs274 against the rule");
    // Wrapped (centre4): G90 A-10 turns back to 10, A20 forward, A0 forward to 360.
    let got = listed_a(&dir, MOVES.replace("A400", "A40").as_str(), "centre4").unwrap();
    let mut want = linuxcnc_a(&a_words(&MOVES.replace("A400", "A40")), true);
    want.dedup();
    assert_eq!(got, want);
    assert_eq!(want, [90.0, 180.0, 135.0, 175.0, 10.0, 20.0, 360.0, 330.0]);
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn a_is_refused_with_its_place_where_it_cannot_act() {
    let dir = temp_dir("axes-refused");
    let e = listed_a(&dir, "G0 X10 A10\n", "centre").unwrap_err();
    assert!(
        e.contains("1:8: unknown word A (novanc has the axes X, Y and Z)"),
        "{e}"
    );
    for (text, want) in [
        (
            "G90 G0 A360\n",
            "1:8: A360: a wrapped rotary axis takes an absolute position within ±360",
        ),
        (
            "G17 G2 X10 Y0 I5 J0 A10 F100\n",
            "1:21: A moves with G00 or G01 only",
        ),
        (
            "G92.1 A10\n",
            "1:7: A with no motion in force (G80): give G00, G01, G02, G03 or a cycle",
        ),
        ("G0 X1\nG4 P1 A10\n", "2:7: A cannot be given with G4"),
        (
            "G10 L1 P1 Z10 A10\n",
            "1:15: G10 L1 sets a tool's data: A is not one of its words",
        ),
        (
            "G92 A400\n",
            "1:5: G92 A400: a wrapped rotary axis takes a position within ±360",
        ),
        (
            "G0 X10 B10\n",
            "1:8: unknown word B (novanc has the axes X, Y, Z and A)",
        ),
        (
            "G81 X10 Y10 Z-5 R1 A10 F100\n",
            "1:20: A moves with G00 or G01 only",
        ),
        (
            "G91 G0 A1000000000000\n",
            "1:8: A1000000000000: out of all range",
        ),
        ("G80 A10\n", "1:1: G80 cancels the motion mode"),
    ] {
        let e = listed_a(&dir, text, "centre4").unwrap_err();
        assert!(e.contains(want), "{text}: {e}");
    }
    // A is run by the DDA only: refused at its place by the reader (the kernel's own check
    // behind it), before any pulse and before the line's modes take effect.
    let prog = dir.join("ep.ngc");
    std::fs::write(&prog, "G0 X10 A10\nM2\n").unwrap();
    let out = novanc(&[
        "run",
        prog.to_str().unwrap(),
        "--machine",
        "centre4",
        "--interpolator",
        "error-proportional",
    ]);
    let se = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        se.contains("ep.ngc:1:8: A is run by the DDA interpolator only (this machine runs the error-proportional one)"),
        "{se}"
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// A console on `centre4` in virtual time, on a state directory of its own named `name`.
fn centre4_console(name: &str) -> novanc::console::Console {
    let mut cfg = novanc::console::ConsoleConfig::new(temp_dir(name));
    cfg.clock = novanc::pulse_core::ClockMode::Virtual;
    cfg.settings = match novanc::lathe::desc::load("centre4") {
        Ok(novanc::lathe::desc::MachineDesc::Mill(s)) => s,
        other => panic!("centre4 is a mill: {other:?}"),
    };
    novanc::console::Console::open(cfg).unwrap().0
}

#[test]
fn pos_shows_a_on_a_machine_with_a_and_mdi_turns_it() {
    use novanc::panel_model::{OpMode, PanelEvent};
    let mut c = centre4_console("axes-pos");
    c.handle(PanelEvent::Op(OpMode::Mdi));
    common::type_line(&mut c, "G0 X10 A90");
    c.handle(PanelEvent::Start);
    c.handle(PanelEvent::Wait);
    assert_eq!(c.status().pos, [10_000, 0, 0, 90_000], "{}", c.frame_text());
    assert_eq!(c.status().pulses[3], 90_000);
    common::keys(&mut c, &["Ctrl+P"]);
    let f = c.frame_text();
    let a = f
        .lines()
        .find(|l| l.starts_with('A'))
        .unwrap_or_else(|| panic!("no A row:\n{f}"));
    assert_eq!(
        a.split_whitespace().collect::<Vec<_>>(),
        ["A", "90.000", "90.000", "90.000", "0.000"],
        "{f}"
    );
}

/// A trunnion table, B tilting and C turning without wrap (the travels rs274's standalone
/// configuration leaves free), beside the centre's X Y Z.
const TRUNNION: &str = "machine trunnion\nkind mill\npulse 0.001\nx travel 0 1000 rapid 12000 accel 1000\ny travel 0 800 rapid 12000 accel 1000\nz travel -600 0 rapid 12000 accel 1000\nb rotary travel -120 120 rapid 9000 accel 800\nc rotary travel -720 720 rapid 9000 accel 800\n";

/// Five axes at once, G91 turns, an inverse-time move of C with X, and G53 bringing the table
/// back (with no offsets set, G53 moves them as G00 does).
const FIVE: &str = "G21 G90 G94\nG0 X100 Y100 Z-50\nG0 B-30 C45\nG1 X120 Y110 Z-60 B-35 C90 F600\nG91 G1 C-120 F3600\nG1 X5 B10 C10\nG90 G93 G1 X130 C180 F2\nG94 G0 Z-10\nG53 G0 B0 C0\nM2\n";

/// (B, C) after each line that gives either, from `text` read here (one B and one C word at
/// most a line, no expressions): G91 adds, G90 goes to the word (unwrapped axes).
fn bc_rule(text: &str) -> Vec<[f64; 2]> {
    let (mut inc, mut at, mut out) = (false, [0.0; 2], Vec::new());
    for line in text.lines() {
        let mut moved = false;
        for w in line.split_whitespace() {
            match w {
                "G90" => inc = false,
                "G91" => inc = true,
                _ => {}
            }
            for (i, l) in ['B', 'C'].into_iter().enumerate() {
                if let Some(v) = w.strip_prefix(l).and_then(|v| v.parse::<f64>().ok()) {
                    at[i] = if inc { at[i] + v } else { v };
                    moved = true;
                }
            }
        }
        if moved {
            out.push(at);
        }
    }
    out
}

/// (B, C) after each block of a listing that turns either (a block prints the axes it moves).
fn listed_bc(listing: &str) -> Vec<[f64; 2]> {
    let (mut at, mut got) = ([0.0; 2], Vec::new());
    for l in listing.lines() {
        let mut moved = false;
        for w in l.split_whitespace() {
            for (i, c) in ['B', 'C'].into_iter().enumerate() {
                if let Some(v) = w.strip_prefix(c).and_then(|v| v.parse().ok()) {
                    at[i] = v;
                    moved = true;
                }
            }
        }
        if moved {
            got.push(at);
        }
    }
    got
}

/// The positions of `axes` (3 A, 4 B, 5 C) after each of rs274's straight moves that changes
/// them, where rs274 is installed and reads `prog` (its default configuration has A, B and C
/// unwrapped); None otherwise.
fn rs274_turns(prog: &Path, dir: &Path, axes: &[usize]) -> Option<Vec<Vec<f64>>> {
    let o = Command::new("rs274")
        .arg("-g")
        .arg(prog)
        .env("HOME", dir)
        .output()
        .ok()
        .filter(|o| o.status.success())?;
    let (mut last, mut v) = (vec![0.0; axes.len()], Vec::new());
    for l in String::from_utf8_lossy(&o.stdout).lines() {
        let Some(args) = l.split("STRAIGHT_").nth(1) else {
            continue;
        };
        let nums: Vec<f64> = args
            .split(['(', ')', ','])
            .filter_map(|w| w.trim().parse().ok())
            .collect();
        let at: Option<Vec<f64>> = axes.iter().map(|&a| nums.get(a).copied()).collect();
        if let Some(at) = at.filter(|at| *at != last) {
            last = at.clone();
            v.push(at);
        }
    }
    Some(v)
}

/// (B, C) after each of rs274's straight moves that turns either ([`rs274_turns`]).
fn rs274_bc(prog: &Path, dir: &Path) -> Option<Vec<[f64; 2]>> {
    let v = rs274_turns(prog, dir, &[4, 5])?;
    Some(v.into_iter().map(|p| [p[0], p[1]]).collect())
}

#[test]
fn b_and_c_turn_as_linuxcnc_turns_them_and_record_their_pulses() {
    let dir = temp_dir("axes-bc");
    // The listing: B and C on the blocks that turn them.
    let (listing, prog) = translate_on_trunnion(&dir, "five", FIVE);
    let desc = trunnion(&dir);
    let (prog_s, desc_s) = (prog.to_str().unwrap(), desc.to_str().unwrap());
    let got = listed_bc(&listing);
    let want = bc_rule(FIVE);
    assert_eq!(
        want,
        [
            [-30.0, 45.0],
            [-35.0, 90.0],
            [-35.0, -30.0],
            [-25.0, -20.0],
            [-25.0, 180.0],
            [0.0, 0.0]
        ]
    );
    assert_eq!(got, want, "{listing}");
    // rs274 itself, where it is installed (its default configuration has B and C unwrapped).
    if let Some(v) = rs274_bc(&prog, &dir) {
        assert_eq!(v, want, "rs274 against the rule");
    }
    // The run: each counter is every degree its axis turned, in 0.001° pulses, and the
    // recording's /nc/pulses of B and C add up to them.
    let turned = |i: usize| {
        let mut from = 0.0;
        let mut sum = 0.0;
        for p in &want {
            sum += (p[i] - from).abs();
            from = p[i];
        }
        (sum / 0.001_f64).round()
    };
    let rec = dir.join("five.mcap");
    let out = novanc(&[
        "run",
        prog_s,
        "--machine",
        desc_s,
        "--record",
        rec.to_str().unwrap(),
    ]);
    let so = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(
        out.status.success(),
        "{so}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(field(&so, "pulses:", "B"), Some(turned(0)), "{so}");
    assert_eq!(field(&so, "pulses:", "C"), Some(turned(1)), "{so}");
    assert_eq!((turned(0), turned(1)), (70_000.0, 600_000.0));
    assert_eq!(field(&so, "final position:", "C"), Some(0.0), "{so}");
    assert!(!so.contains(" A "), "no A on this machine: {so}");
    if let Some((ok, check)) = python_check(&rec, &["--expect-complete"]) {
        assert!(ok, "{check}");
        assert_eq!(field(&check, "pulses", "B"), Some(turned(0)), "{check}");
        assert_eq!(field(&check, "pulses", "C"), Some(turned(1)), "{check}");
    }
    // Beyond B's travel, refused at its place before anything moves.
    std::fs::write(&prog, "G0 B-150\nM2\n").unwrap();
    let out = novanc(&["translate", prog_s, "--machine", desc_s]);
    let se = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        se.contains("five.ngc:1:4: B-150.000 (machine) is beyond the B travel"),
        "{se}"
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// The trunnion's description ([`TRUNNION`]) written to `dir/trunnion.machine`: its path.
fn trunnion(dir: &Path) -> std::path::PathBuf {
    let desc = dir.join("trunnion.machine");
    std::fs::write(&desc, TRUNNION).unwrap();
    desc
}

/// `novanc translate` of `text` (written to `dir/NAME.ngc`) on the trunnion: its listing,
/// having succeeded, and the program's path.
fn translate_on_trunnion(dir: &Path, name: &str, text: &str) -> (String, std::path::PathBuf) {
    let desc = trunnion(dir);
    let prog = dir.join(format!("{name}.ngc"));
    std::fs::write(&prog, text).unwrap();
    let out = novanc(&[
        "translate",
        prog.to_str().unwrap(),
        "--machine",
        desc.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    (String::from_utf8_lossy(&out.stdout).to_string(), prog)
}

/// G28 and G30 bring the rotary axes home as LinuxCNC does: through the intermediate point
/// of their words, the named ones (or, with no axis word, every one) to #5164–#5166 or
/// #5184–#5186, which G28.1 sets. Before stop 53 a bare G28 left B and C where they stood,
/// and `G28 C10` was refused.
#[test]
fn g28_and_g30_bring_b_and_c_home_as_linuxcnc_does() {
    let dir = temp_dir("axes-home");
    let text = "G21 G90\nG0 X10 B30 C45\nG28\nG0 X20 B20 C20\nG91 G28 C10 X5\nG90 G0 C50\nG30 B0\nG0 B15 C25\nG28.1\nG0 B0 C0\nG28\nM2\n";
    let (listing, prog) = translate_on_trunnion(&dir, "home", text);
    let got = listed_bc(&listing);
    // Worked out by LinuxCNC's rule (interp_convert.cc convert_home): G91 G28 C10 passes C
    // at 30 and sends C alone home; G30 B0's end is where it passes (#5185 is 0); the last
    // G28 goes to the B 15, C 25 that G28.1 kept.
    let want = [
        [30.0, 45.0],
        [0.0, 0.0],
        [20.0, 20.0],
        [20.0, 30.0],
        [20.0, 0.0],
        [20.0, 50.0],
        [0.0, 50.0],
        [15.0, 25.0],
        [0.0, 0.0],
        [15.0, 25.0],
    ];
    assert_eq!(got, want, "{listing}");
    if let Some(v) = rs274_bc(&prog, &dir) {
        assert_eq!(v, want, "rs274 against the rule");
    }
    let _ = std::fs::remove_dir_all(dir);
}

/// `novanc script --machine MACHINE...` of `text` (a script file in `dir`) on the state
/// directory `dir/state`: what it printed, having succeeded.
fn script_run(dir: &Path, machine: &[&str], state: &str, text: &str) -> String {
    let script = dir.join(format!("{state}.script"));
    std::fs::write(&script, text).unwrap();
    let state = dir.join(state);
    let mut args = vec!["script", "--machine"];
    args.extend_from_slice(machine);
    args.extend(["--state", state.to_str().unwrap(), script.to_str().unwrap()]);
    let out = novanc(&args);
    let so = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(
        out.status.success(),
        "{so}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    so
}

/// The words of the first line of a shown display (`text`, a script's output) that starts
/// with `r`: a POS row (`C`, then WORK, REL, MACH, TO GO) or an OFS WORK row (`G54` ...).
fn display_row(text: &str, r: &str) -> Vec<String> {
    text.lines()
        .map(|l| l.trim_start_matches('|'))
        .find(|l| l.starts_with(r))
        .unwrap_or_else(|| panic!("no {r} row:\n{text}"))
        .split_whitespace()
        .map(str::to_string)
        .collect()
}

/// The console on `--machine FILE` (the terminal's, the window's and `novanc script`'s one
/// argument path) has the description's rotary axes: MDI turns them and POS shows a row each.
/// Until stop 53 the console took the description's travel but not its axes, so a console on
/// `--machine centre4` refused `A` as an unknown word.
#[test]
fn the_console_on_a_described_machine_has_its_rotary_axes() {
    let dir = temp_dir("axes-console");
    let desc = trunnion(&dir);
    let script = "op MDI\ntype G0 X10 B30 C-45\neob\nstart\nwait\nkey Ctrl+P\nshow\n";
    for (machine, rows) in [
        (desc.to_str().unwrap(), &["B", "C"][..]),
        ("centre4", &["A"][..]),
    ] {
        let text = if machine == "centre4" {
            script.replace("B30 C-45", "A30")
        } else {
            script.to_string()
        };
        let so = script_run(&dir, &[machine], &format!("state-{}", rows[0]), &text);
        for r in rows {
            let want = if *r == "C" { "-45.000" } else { "30.000" };
            assert_eq!(display_row(&so, r)[3], want, "{machine} {r} MACH:\n{so}");
        }
    }
    let _ = std::fs::remove_dir_all(dir);
}

/// MACHINE LOCK holds every axis back, the rotary ones too: the program position turns, the
/// table does not. Until stop 53 the lock was X Y Z only and a locked run turned A (found by
/// the operator sequences on a trunnion).
#[test]
fn machine_lock_holds_the_rotary_axes_too() {
    use novanc::panel_model::{OpMode, PanelEvent};
    let mut c = centre4_console("axes-lock");
    c.handle(PanelEvent::MachineLock(true));
    c.handle(PanelEvent::Op(OpMode::Mdi));
    common::type_line(&mut c, "G0 X10 A90");
    c.handle(PanelEvent::Start);
    c.handle(PanelEvent::Wait);
    let st = c.status();
    assert_eq!(st.pos, [10_000, 0, 0, 90_000], "{}", c.frame_text());
    assert_eq!(st.machine_pos, [0, 0, 0], "{}", c.frame_text());
    assert_eq!(st.pulses[3], 0, "no A pulse under MACHINE LOCK");
}

/// The rotary axes are turned by hand (stop 53; before, only X Y Z could be): the handwheel's
/// axis selector (Alt+a, `wheel AXIS 0`) goes round the machine's axes, HANDLE and STEP turn
/// B within its travel, and a CONTINUOUS jog turns the wrapped C without end. An axis the
/// machine has not is refused.
#[test]
fn the_handwheel_and_the_jogs_turn_the_rotary_axes() {
    let dir = temp_dir("axes-jog");
    let desc = dir.join("trunnion.machine");
    // C wrapped here (the trunnion of the other tests has it within travel).
    std::fs::write(
        &desc,
        TRUNNION.replace("c rotary travel -720 720", "c rotary wrap"),
    )
    .unwrap();
    let so = script_run(
        &dir,
        &[desc.to_str().unwrap()],
        "state",
        "key Alt+a\nshow\nkey Alt+a\nkey Alt+a\nkey Alt+a\nshow\n\
         op HANDLE\nwheelscale 1000\nwheel B -3\nwait\nop STEP\njog B+\nwait\n\
         jog B+\nwait\nop HANDLE\nwheel B -200\nwait\nshow\n\
         op CONTINUOUS\njog C-\nwait ms 2000\njogrelease\nwait\nwheel A 0\nshow\nkey Ctrl+P\nshow\n",
    );
    let frames: Vec<&str> = so.split("--- display").skip(1).collect();
    assert_eq!(frames.len(), 5, "{so}");
    assert!(frames[0].contains("handwheel on Y"), "{}", frames[0]);
    // X Y Z B C: three more turns of the selector reach C.
    assert!(frames[1].contains("handwheel on C"), "{}", frames[1]);
    // B past its travel (-1 - 200 degrees) is refused, and B stays at -1.
    assert!(frames[2].contains("outside travel"), "{}", frames[2]);
    assert!(
        frames[3].contains("this machine has no A axis"),
        "{}",
        frames[3]
    );
    let row = |l: &str| {
        frames[4]
            .lines()
            .find(|r| r.starts_with(l))
            .and_then(|r| r.split_whitespace().nth(3))
            .map(|v| v.parse::<f64>().unwrap())
    };
    assert_eq!(row("B"), Some(-1.0), "{}", frames[4]);
    // 2 s at the jog feed, 1000 degrees a minute, less the ramps: about 33 degrees back
    // past 0 (a wrapped axis has no limit to stop at).
    let c = row("C").unwrap();
    assert!((-34.0..-30.0).contains(&c), "C {c}: {}", frames[4]);
    let _ = std::fs::remove_dir_all(dir);
}

/// On the error-proportional interpolator (whose registers are X Y Z) a rotary axis turned by
/// hand is not brought home by a bare G28 behind the operator's back: the line is refused at
/// its place before anything moves, as a rotary word is.
#[test]
fn a_bare_g28_does_not_turn_a_rotary_axis_on_the_error_proportional_interpolator() {
    let dir = temp_dir("axes-ep-home");
    let so = script_run(
        &dir,
        &["centre4", "--interpolator", "error-proportional"],
        "state",
        "op HANDLE\nwheelscale 1000\nwheel A 5\nwait\nop MDI\ntype G28\neob\nstart\nwait\nkey Ctrl+P\nshow\n",
    );
    assert!(so.contains("the rotary axes go home"), "{so}");
    let a = so.lines().find(|l| l.starts_with('A')).unwrap_or_default();
    assert_eq!(a.split_whitespace().nth(3), Some("5.000"), "{so}");
    let _ = std::fs::remove_dir_all(dir);
}

/// The rotary axes' work offsets (stop 54; before, every one of these lines was refused):
/// G10 L2 and L20 set a system's B and C, G92, G52 and G92.1–.3 their G92 offset, G53 turns to
/// a machine position whatever the offsets, and #5424, #5425 and #<_c> read the program
/// position. The machine positions are worked out here by LinuxCNC's rule (a program position
/// plus the system's offset plus G92's: interp_convert.cc `convert_setup`,
/// `convert_axis_offsets`); rs274, where installed, prints the program positions.
const OFFSETS: &str = "G21 G90 G94\nG10 L2 P1 B10 C30\nG54 G0 X100 Y100 Z-50 B0 C0\nG1 B20 C-45 F600\nG10 L20 P1 C90\nG0 C100\nG92 B0\nG0 B5 X#5425\nG91 G0 B-10 C10\nG90 G53 G0 B0 C0\nG52 C10\nG0 B0 C0 X[#5424+100]\nG92.1\nG0 B0 C0\nG92 C20\nG92.2\nG0 C5\nG92.3\nG0 C5\nG55 G0 B0 C0\nG54 G0 B5 C5 Y[#<_c>+200]\nM2\n";

#[test]
fn rotary_work_offsets_and_g92_turn_b_and_c_as_linuxcnc_does() {
    let dir = temp_dir("axes-offsets");
    let (listing, prog) = translate_on_trunnion(&dir, "offsets", OFFSETS);
    // Each turn's program (B, C) and the offsets then in force (system + G92): G54 B10 C30;
    // L20 makes C read 90 at machine -15 (G54 C -105); G92 B0 at program B 20 (G92 B 20);
    // G53 to machine 0; G52 C10; G92.1; G92 C20 at program C 0 (G92 C -20), suspended by
    // G92.2 and back by G92.3; G55 (no offset) and G54 again.
    let turns: [([f64; 2], [f64; 2]); 11] = [
        ([0.0, 0.0], [10.0, 30.0]),
        ([20.0, -45.0], [10.0, 30.0]),
        ([20.0, 100.0], [10.0, -105.0]),
        ([5.0, 100.0], [30.0, -105.0]),
        ([-5.0, 110.0], [30.0, -105.0]),
        ([-30.0, 105.0], [30.0, -105.0]),
        ([0.0, 0.0], [30.0, -95.0]),
        ([0.0, 0.0], [10.0, -105.0]),
        ([0.0, 5.0], [10.0, -105.0]),
        ([0.0, 5.0], [10.0, -125.0]),
        ([0.0, 0.0], [0.0, -20.0]),
    ];
    let mut want: Vec<[f64; 2]> = turns
        .iter()
        .map(|(p, o)| [p[0] + o[0], p[1] + o[1]])
        .collect();
    want.push([15.0, -120.0]);
    assert_eq!(listed_bc(&listing), want, "{listing}");
    // The parameters read the program position: X = #5425 (C 100), X = #5424 + 100 (B -30),
    // Y = #<_c> + 200 (C 0 in G55, read before the line's G54 takes effect).
    assert!(listing.contains("N4 G00 B35.000\n"), "{listing}");
    assert!(listing.contains("X70.000 B30.000 C-95.000"), "{listing}");
    assert!(listing.contains("Y200.000 B15.000 C-120.000"), "{listing}");
    if let Some(v) = rs274_bc(&prog, &dir) {
        // (rs274's first turn is from 0, 0 to 0, 0: not a change.)
        let mut program: Vec<[f64; 2]> = turns.iter().skip(1).map(|(p, _)| *p).collect();
        program.dedup();
        program.push([5.0, 5.0]);
        let mut v = v;
        v.dedup();
        assert_eq!(v, program, "rs274's program positions");
    }
    let _ = std::fs::remove_dir_all(dir);
}

/// At the console the rotary offsets are the operator's too: OFS WORK has a column for each
/// rotary axis (`G54 C30` INPUT sets it, journaled as one record), POS's WORK shows the
/// program position, and a restart keeps the offset a program's G10 L20 set.
#[test]
fn the_console_shows_and_keeps_the_rotary_work_offsets() {
    let dir = temp_dir("axes-ofs-console");
    let desc = trunnion(&dir);
    let d = desc.to_str().unwrap();
    let wide = [d, "--cols", "80", "--rows", "30"];
    let so = script_run(
        &dir,
        &wide,
        "state",
        "key Ctrl+O\nkey End\ntype G54 C30 B-5\nshow\n\
         op MDI\ntype G54 G0 B0 C15\neob\nstart\nwait\nkey Ctrl+P\nshow\nkey Ctrl+P\n\
         type G10 L20 P1 C90\neob\nstart\nwait\n",
    );
    let frames: Vec<&str> = so.split("--- display").skip(1).collect();
    assert_eq!(frames.len(), 2, "{so}");
    assert!(
        frames[0].contains("G54 X0.000 Y0.000 Z0.000 B-5.000 C30.000"),
        "{}",
        frames[0]
    );
    let row = display_row;
    // A POS row's WORK and MACH.
    let work_mach = |frame: &str, axis: &str, want: (&str, &str)| {
        let r = row(frame, axis);
        assert_eq!((r[1].as_str(), r[3].as_str()), want, "{frame}");
    };
    // WORK, REL, MACH: C at 15 in G54 stands at machine 45.
    work_mach(frames[1], "C", ("15.000", "45.000"));
    work_mach(frames[1], "B", ("0.000", "-5.000"));
    // A new console on the same state: G54's C is what G10 L20 made it (45 - 90 = -45).
    let so = script_run(
        &dir,
        &wide,
        "state",
        "key Ctrl+P\nshow\nkey Ctrl+O\nkey End\nshow\n",
    );
    let frames: Vec<&str> = so.split("--- display").skip(1).collect();
    work_mach(frames[0], "C", ("90.000", "45.000"));
    let g54 = row(frames[1], "G54");
    assert_eq!(
        g54.last().map(String::as_str),
        Some("-45.000"),
        "{}",
        frames[1]
    );
    assert!(
        frames[1].contains("B         C"),
        "the rotary columns' heading:\n{}",
        frames[1]
    );
    // On a 40-column display three columns fit: they scroll with the cursor to C.
    let so = script_run(
        &dir,
        &[d],
        "state",
        "key Ctrl+O\nkey End\nkey Right\nkey Right\nkey Right\nkey Right\nshow\n",
    );
    let g54 = row(&so, "G54");
    assert_eq!(g54[1..], ["0.000", "-5.000", ">-45.000"], "{so}");
    let _ = std::fs::remove_dir_all(dir);
}

/// The rotary axes' jog keys (stop 54; before, only HANDLE, scripts and the window's wheel
/// could turn them): Alt+a selects the handwheel's axis, and Alt+, / Alt+. jog it in STEP (one
/// increment) and CONTINUOUS (a tap, one increment), as the arrows jog X and Y; in HANDLE they
/// stay the wheel's detents.
#[test]
fn alt_comma_and_period_jog_the_selected_rotary_axis() {
    let dir = temp_dir("axes-jog-keys");
    let desc = trunnion(&dir);
    let so = script_run(
        &dir,
        &[desc.to_str().unwrap()],
        "state",
        "key Alt+a\nkey Alt+a\nkey Alt+a\nkey Alt+a\nop STEP\nwheelscale 1000\n\
         key Alt+.\nwait\nkey Alt+.\nwait\nop CONTINUOUS\nkey Alt+,\nwait\n\
         op HANDLE\nkey Alt+.\nwait\nshow\nkey Alt+a\nkey Alt+.\nwait\nkey Ctrl+P\nshow\n",
    );
    // A detent on C is said in degrees.
    assert!(so.contains("HANDLE C+ 1.000 deg (x1000)"), "{so}");
    let pos = so.rsplit("--- display").next().unwrap_or_default();
    let row = |r: &str| display_row(pos, r);
    // C: +1 +1 in STEP, -1 in CONTINUOUS, +1 in HANDLE; then the selector goes round to X,
    // and a detent of the wheel in HANDLE moves X by its increment.
    assert_eq!(row("C")[3], "2.000", "{so}");
    assert_eq!(row("B")[3], "0.000", "{so}");
    assert_eq!(row("X")[3], "1.000", "{so}");
    // The manual pages say the handwheel's axis in its unit: with B selected, a STEP beyond
    // B's travel is refused in degrees, and the hints name both units (the arrows jog X Y Z).
    let so = script_run(
        &dir,
        &[desc.to_str().unwrap()],
        "limit",
        "op MDI\ntype G0 B119.95\neob\nstart\nwait\nkey Alt+a\nkey Alt+a\nkey Alt+a\n\
         op STEP\nwheelscale 100\nkey Alt+.\nwait\nshow\nop CONTINUOUS\nshow\n",
    );
    for want in [
        "STEP refused: B would go to 120.050 deg,",
        "0.100 mm/deg (x100) per jog key",
        "tap 0.100 mm/deg, hold jogs",
    ] {
        assert!(so.contains(want), "{want:?} not in\n{so}");
    }
    let _ = std::fs::remove_dir_all(dir);
}

/// Time of a move of `d` at most `v` per second, accelerating at `a` per second².
fn trapezoid(d: f64, v: f64, a: f64) -> f64 {
    if d * a > v * v {
        d / v + v / a
    } else {
        2.0 * (d / a).sqrt()
    }
}

/// The machine time `novanc run` gives for program `text` on description `desc`, s.
fn machine_time(dir: &Path, desc: &Path, text: &str) -> f64 {
    let prog = dir.join("move.ngc");
    std::fs::write(&prog, text).unwrap();
    let out = novanc(&[
        "run",
        prog.to_str().unwrap(),
        "--machine",
        desc.to_str().unwrap(),
    ]);
    let so = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(out.status.success(), "{text}: {so}");
    so.lines()
        .find_map(|l| l.strip_prefix("machine time: "))
        .and_then(|l| l.trim_end_matches(" s").parse().ok())
        .unwrap_or_else(|| panic!("{text}: {so}"))
}

/// A rotary axis turns no faster than its own rate, and accelerates no harder than its own
/// acceleration, on a move with X Y Z too (stop 54). Before, its rate only joined the path's
/// rate along X Y Z: `G0 X10 B90` turned the trunnion's B (9,000°/min) at 23,000°/min, `G1 X1
/// C360 F1000` turned C at 227,000°/min, and every X Y Z rapid was slowed to 9,000 mm/min. The
/// machine time of each move is worked out here as a trapezoid (or triangle) of the slowest
/// axis's own rate and acceleration.
#[test]
fn a_rotary_axis_turns_within_its_own_rate_and_x_y_z_keep_theirs() {
    let dir = temp_dir("axes-rates");
    let desc = trunnion(&dir);
    // X Y Z: 12,000 mm/min and 1,000 mm/s²; B and C: 9,000°/min and 800°/s².
    for (line, want) in [
        ("G0 X100", trapezoid(100.0, 200.0, 1000.0)),
        ("G0 X10 B90", trapezoid(90.0, 150.0, 800.0)),
        ("G0 B90", trapezoid(90.0, 150.0, 800.0)),
        ("G1 X1 C360 F1000", trapezoid(360.0, 150.0, 800.0)),
        ("G1 X100 C10 F600", trapezoid(100.0, 10.0, 1000.0)),
    ] {
        let t = machine_time(&dir, &desc, &format!("G21 G90\n{line}\nM2\n"));
        // Within two 5 ms ticks and the pulses' own timing.
        assert!(
            (t - want).abs() < 0.02,
            "{line}: {t} s, the rule {want:.3} s"
        );
    }
    // The console on the same description keeps the same rates (until stop 54 it copied the
    // description's fields one by one and missed these: its B turned in 0.2 s).
    let so = script_run(
        &dir,
        &[desc.to_str().unwrap()],
        "state",
        "op MDI\ntype G0 X10 B90\nstart\nwait\nshow\n",
    );
    assert!(so.contains("program end: 1 blocks in 0.8 s"), "{so}");
    let _ = std::fs::remove_dir_all(dir);
}

/// Stop 58: X, Y and Z keep their own rates and accelerations, by the rule the rotary axes
/// follow (a move is held so that no axis moves faster or accelerates harder than its own;
/// LinuxCNC's rule). Before, X Y Z kept one rate and one acceleration, the lowest of the
/// three: on this machine every rapid went at Z's 6,000 mm/min and 500 mm/s².
#[test]
fn x_y_and_z_each_move_at_their_own_rate() {
    let dir = temp_dir("axes-xyz-rates");
    let desc = dir.join("vmc.machine");
    std::fs::write(
        &desc,
        "machine vmc\nkind mill\npulse 0.001\n\
         x travel 0 1000 rapid 30000 accel 2000\n\
         y travel 0 800 rapid 20000 accel 1000\n\
         z travel -600 0 rapid 6000 accel 500\n",
    )
    .unwrap();
    let diagonal = (300.0f64 * 300.0 + 60.0 * 60.0).sqrt();
    for (line, want) in [
        ("G0 X300", trapezoid(300.0, 500.0, 2000.0)),
        ("G0 Y200", trapezoid(200.0, 20000.0 / 60.0, 1000.0)),
        ("G0 Z-60", trapezoid(60.0, 100.0, 500.0)),
        // Both: X at 30,000 × 300 / L and Z at 6,000 × 60 / L are at their own rates at once,
        // and neither accelerates harder than its own (2,000 × L / 300 and 500 × L / 60 are
        // both above the path's 2,000).
        ("G0 X300 Z-60", trapezoid(diagonal, 500.0, 2000.0)),
        // A feed past an axis's rate is held to it too.
        ("G1 Z-60 F20000", trapezoid(60.0, 100.0, 500.0)),
        // An arc is held to the lowest rate and acceleration of the three, Z's.
        (
            "G2 X100 Y0 I50 J0 F20000",
            trapezoid(50.0 * std::f64::consts::PI, 100.0, 500.0),
        ),
    ] {
        let t = machine_time(&dir, &desc, &format!("G21 G90 G17\n{line}\nM2\n"));
        assert!(
            (t - want).abs() < 0.02,
            "{line}: {t} s, the rule {want:.3} s"
        );
    }
    let _ = std::fs::remove_dir_all(dir);
}
