//! novanc's G-code reading against the moves LinuxCNC 2.9's rs274 made of the same programs,
//! kept as golden listings in `tests/golden/gcode/` by `tools/compare_rs274.py --golden`
//! (docs/gcode.md "Agreement with LinuxCNC"): every move's kind and machine end point and
//! every arc's centre and direction, in the same order, to 0.001 mm (wider only where rs274
//! printed inches with 4 decimals); where rs274 refused a program, novanc refuses it. CI needs
//! no LinuxCNC.
//!
//! rs274 prints a spline (G5, G5.1, G5.2 … G5.3) without its points: a listing line `S n`.
//! It matches a run of novanc's feed moves (the chords, one at least per spline) that ends
//! where novanc's next move agrees with the listing's next one, as the comparison tool matches
//! them; an arc after it must start on its own circle there. The curves themselves are checked
//! by the unit tests of `src/gcode/spline`.

use novanc::block::{MachineState, Motion, Plane, Statement};
use novanc::gcode::{GcodeSource, SubPath, Switches, WorkOffsets};
use novanc::lathe::desc::{load, LatheDesc, MachineDesc};
use novanc::lathe::gcode::{read_program, ReadOptions};
use novanc::settings::{MachineSettings, Remap};
use novanc::tooldata::sample_magazine;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// One move: kind ('R', 'F', 'A'), arc direction and plane, numbers (end, then centre).
#[derive(Debug, PartialEq)]
struct Move {
    kind: char,
    ccw: bool,
    plane: String,
    nums: Vec<f64>,
}

/// novanc's moves of program `src` on the machine `st`, finding subroutine files in `subs`.
fn novanc_moves(src: &str, st: &MachineSettings, subs: &[PathBuf]) -> Result<Vec<Move>, String> {
    let stmts: Vec<_> = GcodeSource::new(
        src.into(),
        sample_magazine(),
        st.clone(),
        MachineState::at([0, 0, 0]),
        WorkOffsets::default(),
        Switches::default(),
    )
    .subroutines(Box::new(SubPath(subs.to_vec())))
    .collect::<Result<_, _>>()
    .map_err(|e| e.to_string())?;
    Ok(moves_of(&stmts, st))
}

/// The moves of a lathe's channel 1 program `src` (the lathe reader, from the top of both
/// travels), X a radius.
fn lathe_moves(src: &str, desc: &LatheDesc) -> Result<Vec<Move>, String> {
    let opts = ReadOptions::default();
    let stmts = read_program(src, desc, 0, &opts).map_err(|e| e.to_string())?;
    let st = MachineSettings::lathe_channel(desc, 0).expect("a channel");
    Ok(moves_of(&stmts, &st))
}

/// The moves of `stmts` in machine mm.
fn moves_of(stmts: &[Statement], st: &MachineSettings) -> Vec<Move> {
    let mut out = Vec::new();
    for b in stmts.iter().flat_map(|s| &s.blocks) {
        let mm = |p: i64| st.to_mm(p);
        let end: Vec<f64> = b.end.xyz().iter().map(|&p| mm(p)).collect();
        match b.motion {
            Motion::Rapid | Motion::Linear => out.push(Move {
                kind: if b.motion == Motion::Rapid { 'R' } else { 'F' },
                ccw: false,
                plane: String::new(),
                nums: end,
            }),
            Motion::ArcCw | Motion::ArcCcw => {
                let s = b.start();
                let c = b.centre3().unwrap_or([0; 3]);
                let mut nums = end;
                nums.extend((0..3).map(|i| mm(s[i] + c[i])));
                out.push(Move {
                    kind: 'A',
                    ccw: b.motion == Motion::ArcCcw,
                    plane: match b.plane {
                        Plane::XY => "XY",
                        Plane::XZ => "XZ",
                        Plane::YZ => "YZ",
                    }
                    .to_string(),
                    nums,
                });
            }
            Motion::Dwell | Motion::Aux => {}
        }
    }
    out
}

/// (expected moves with their tolerances) or the refusal rs274 gave.
fn expected(text: &str) -> Result<Vec<(Move, f64)>, String> {
    if let Some(e) = text.strip_prefix("ERROR ") {
        return Err(e.trim().to_string());
    }
    let mut out = Vec::new();
    for line in text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
    {
        let f: Vec<&str> = line.split_whitespace().collect();
        let num = |s: &str| s.parse::<f64>().expect("a number in the listing");
        let tol = num(f[f.len() - 1]);
        let m = if f[0].starts_with('A') {
            Move {
                kind: 'A',
                ccw: f[0] == "A1",
                plane: f[1].to_string(),
                nums: f[2..f.len() - 1].iter().map(|s| num(s)).collect(),
            }
        } else {
            Move {
                kind: f[0].chars().next().unwrap_or('?'),
                ccw: false,
                plane: String::new(),
                nums: f[1..f.len() - 1].iter().map(|s| num(s)).collect(),
            }
        };
        out.push((m, tol));
    }
    Ok(out)
}

/// Whether novanc's move `g` is the listing's move `w` within `tol`.
fn agrees(g: &Move, w: &Move, tol: f64) -> bool {
    (g.kind, g.ccw, &g.plane) == (w.kind, w.ccw, &w.plane)
        && g.nums.len() == w.nums.len()
        && g.nums
            .iter()
            .zip(&w.nums)
            .all(|(a, b)| (a - b).abs() <= tol + 1e-9)
}

/// Where a move ends.
fn end_of(m: &Move) -> &[f64] {
    &m.nums[..3]
}

/// Whether arc `w` (a listing move) starts on its own circle at `start`.
fn on_circle(start: &[f64], w: &Move) -> bool {
    let (u, v) = match w.plane.as_str() {
        "XY" => (0, 1),
        "XZ" => (2, 0),
        _ => (1, 2),
    };
    let (e, c) = (&w.nums[..3], &w.nums[3..6]);
    let r0 = (start[u] - c[u]).hypot(start[v] - c[v]);
    let r1 = (e[u] - c[u]).hypot(e[v] - c[v]);
    (r0 - r1).abs() <= 0.03
}

/// Compares novanc's moves from `got[j]` with the listing's from `want[i]`: the first
/// difference, if any. A run of splines tries each run of feed moves that could end it;
/// `failed` remembers the places already found to fail.
fn walk(
    got: &[Move],
    want: &[(Move, f64)],
    mut i: usize,
    mut j: usize,
    failed: &mut HashMap<(usize, usize), String>,
) -> Result<(), String> {
    while i < want.len() {
        if want[i].0.kind == 'S' {
            if let Some(e) = failed.get(&(i, j)) {
                return Err(e.clone());
            }
            let c = want[i..].iter().take_while(|w| w.0.kind == 'S').count();
            let m = got[j..]
                .iter()
                .take_while(|g| g.kind == 'F' || g.kind == 'A')
                .count();
            let mut runs = Vec::new();
            if m >= c {
                match want.get(i + c) {
                    None => runs.push((m, 0)),
                    Some((next, tol)) => {
                        runs.extend(
                            (c..=m)
                                .filter(|&n| got.get(j + n).is_some_and(|g| agrees(g, next, *tol)))
                                .map(|n| (n, 0)),
                        );
                        let end = end_of(&got[j + m - 1]);
                        if next.kind != 'A'
                            && end_of(next)
                                .iter()
                                .zip(end)
                                .all(|(a, b)| (a - b).abs() <= *tol)
                        {
                            runs.push((m, 1));
                        }
                    }
                }
            }
            let mut err = format!(
                "move {}: no run of novanc's {m} feed moves ends the listing's {c} spline(s)",
                j + 1
            );
            for (n, skip) in runs {
                if let Some((next, _)) = want.get(i + c + skip) {
                    if next.kind == 'A' && !on_circle(end_of(&got[j + n - 1]), next) {
                        err = format!(
                            "move {}: a spline ends off the next arc's circle",
                            j + n + 1
                        );
                        continue;
                    }
                }
                match walk(got, want, i + c + skip, j + n, failed) {
                    Ok(()) => return Ok(()),
                    Err(e) => err = e,
                }
            }
            failed.insert((i, j), err.clone());
            return Err(err);
        }
        let Some(g) = got.get(j) else { break };
        let (w, tol) = &want[i];
        if !agrees(g, w, *tol) {
            return Err(format!(
                "move {}: novanc {:?} {:?}, rs274 {:?} {:?}",
                j + 1,
                g.kind,
                g.nums,
                w.kind,
                w.nums
            ));
        }
        i += 1;
        j += 1;
    }
    if i < want.len() || j < got.len() {
        return Err(format!(
            "rs274 has {} moves, novanc {} (they part after novanc's move {j})",
            want.len(),
            got.len()
        ));
    }
    Ok(())
}

#[test]
fn every_golden_program_agrees_with_rs274() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden/gcode");
    let st = MachineSettings::default();
    let programs = agree_with_rs274(&dir, &[], |src| novanc_moves(src, &st, &[]));
    assert!(programs >= 50, "only {programs} golden programs");
}

/// The lathe reader against rs274 in lathe mode (`tools/compare_rs274.py --machine
/// lathe.machine --golden`; docs/lathe-gcode.md "Agreement with LinuxCNC"): our own programs
/// of nose-radius compensation in three tip positions (entries into inside corners), arcs as
/// entry moves (a tip 9 tool: rs274 turns the entry arc of a tool with another tip into a
/// full circle, docs/lathe-gcode.md), G41.1/G42.1 with D and L, I K arcs LinuxCNC reads as
/// spirals, G76 with Q and E/L taper ends, G33 tapers, G53, G91,
/// G20, tool offsets, G92 shifts (a G76 at a shifted zero), the work offsets G54–G59 (G10 L2
/// and L20, P0, under a G92 shift, in diameter and radius mode; stop 57), and an entry move
/// too short, refused by both. rs274 was given the lathe's start, G18 G21 G7 and the tools
/// with LinuxCNC's orientation numbers.
#[test]
fn the_lathe_golden_programs_agree_with_rs274() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden/lathe_rs274");
    let desc = match load(&dir.join("lathe.machine").to_string_lossy()) {
        Ok(MachineDesc::Lathe(d)) => d,
        other => panic!("lathe.machine: {other:?}"),
    };
    assert_eq!(
        agree_with_rs274(&dir, &[], |src| lathe_moves(src, &desc)),
        11
    );
}

/// M6 remapped to `o<toolchange>` by the machine description `remap.machine` (docs/gcode.md
/// "Remapping M6 and other M codes"), its subroutine file beside the programs: the moves rs274
/// made with `REMAP=M6 modalgroup=6 ngc=toolchange` (the changer's moves, the built-in M6
/// inside it, the rest of the M6 line after it), and the same refusals (an abort in the
/// subroutine, a subroutine that calls itself without end). M31 and M33 remapped in modal
/// group 10 (`REMAP=M31 modalgroup=10 ngc=chip_on`, a Haas's chip conveyor): the steps of
/// their line before them run first, its dwell and motion after their subroutine (stop 55).
#[test]
fn remapped_m6_agrees_with_rs274() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden/remap");
    let st = match load(&dir.join("remap.machine").to_string_lossy()) {
        Ok(MachineDesc::Mill(s)) => s,
        other => panic!("remap.machine: {other:?}"),
    };
    assert_eq!(st.remap_m6.as_deref(), Some("toolchange"));
    let relay = Remap {
        argspec: "Pq".into(),
        ..Remap::new(59, "relay")
    };
    assert_eq!(
        st.remap_m,
        [Remap::new(31, "chip_on"), Remap::new(33, "chip_off"), relay]
    );
    let names: Vec<String> = (st.remap_m6.iter())
        .chain(st.remap_m.iter().map(|r| &r.ngc))
        .map(|n| format!("{n}.ngc"))
        .collect();
    let subs = [dir.clone()];
    let programs = agree_with_rs274(&dir, &names, |src| novanc_moves(src, &st, &subs));
    assert_eq!(programs, 7);
}

/// Checks every program `NAME.ngc` of `dir` (but `sub_files`, subroutines) against its
/// `NAME.expect`, reading it with `read`; returns how many there were.
fn agree_with_rs274(
    dir: &Path,
    sub_files: &[String],
    read: impl Fn(&str) -> Result<Vec<Move>, String>,
) -> usize {
    let mut names: Vec<_> = std::fs::read_dir(dir)
        .expect("the golden folder")
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "ngc"))
        .filter(|p| {
            let name = p.file_name().and_then(|n| n.to_str()).unwrap_or_default();
            !sub_files.iter().any(|s| s == name)
        })
        .collect();
    names.sort();
    let (mut programs, mut moves, mut refused) = (0, 0, 0);
    let mut failures = Vec::new();
    for prog in &names {
        let src = std::fs::read_to_string(prog).expect("program");
        let exp = std::fs::read_to_string(prog.with_extension("expect")).expect("its .expect");
        let name = prog.file_name().and_then(|n| n.to_str()).unwrap_or("?");
        let got = read(&src);
        match expected(&exp) {
            Err(why) => {
                if got.is_ok() {
                    failures.push(format!("{name}: rs274 refuses ({why}), novanc accepts"));
                }
                refused += 1;
            }
            Ok(want) => match got {
                Err(e) => failures.push(format!("{name}: novanc refuses: {e}")),
                Ok(got) => match walk(&got, &want, 0, 0, &mut HashMap::new()) {
                    Ok(()) => moves += want.len(),
                    Err(e) => failures.push(format!("{name}: {e}")),
                },
            },
        }
        programs += 1;
    }
    println!("{programs} programs ({refused} refused by both), {moves} moves agree with rs274");
    assert!(
        failures.is_empty(),
        "{} of {programs} programs differ:\n{}",
        failures.len(),
        failures.join("\n")
    );
    programs
}

/// The remapped M6's subroutine reads the tool selected and the tool in the spindle
/// (`#<selected_tool>`, `#<tool_in_spindle>`, as LinuxCNC's change_prolog gives them); an
/// error inside it names the calling line and its own; one that calls itself is refused.
#[test]
fn a_remapped_m6_gives_its_subroutine_the_tools_and_names_both_lines() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden/remap");
    let st = MachineSettings {
        remap_m6: Some("change".into()),
        ..MachineSettings::default()
    };
    let sub = "o<change> sub\n(debug, sel=#<selected_tool> in=#<tool_in_spindle> level=#<_remap_level>)\nM6\no<change> endsub\n";
    let src = format!("{sub}G21 G90\nT4 M6\nT2 M6\nM2\n");
    let mut g = GcodeSource::new(
        src.as_str().into(),
        sample_magazine(),
        st.clone(),
        MachineState::at([0, 0, 0]),
        WorkOffsets::default(),
        Switches::default(),
    );
    assert!(g.by_ref().all(|s| s.is_ok()));
    let said: Vec<String> = g
        .take_events()
        .into_iter()
        .filter_map(|e| match e {
            novanc::gcode::Event::Message { text, .. } => Some(text),
            _ => None,
        })
        .collect();
    assert_eq!(
        said,
        [
            " sel=4.000000 in=0.000000 level=1.000000",
            " sel=2.000000 in=4.000000 level=1.000000"
        ]
    );
    let toolchange = std::fs::read_to_string(dir.join("toolchange.ngc")).unwrap();
    for (program, want) in [
        (
            "remap_m6_sub_error.ngc",
            "5:1: in toolchange.ngc line 4:3: (ABORT) the changer refuses tool 4",
        ),
        (
            "remap_m6_recursion.ngc",
            "5:1: in toolchange.ngc line 7:3: o<toolchange> call: calls nested more than",
        ),
    ] {
        let src = std::fs::read_to_string(dir.join(program)).unwrap();
        let st = MachineSettings {
            remap_m6: Some("toolchange".into()),
            ..MachineSettings::default()
        };
        let e = novanc_moves(&src, &st, std::slice::from_ref(&dir)).unwrap_err();
        assert!(e.starts_with(want), "{program}: {e}");
        // Without the remap, M6 is the built-in change and the program runs.
        assert!(novanc_moves(&src, &MachineSettings::default(), &[]).is_ok());
        assert!(toolchange.contains("o<toolchange> sub"));
    }
}

/// A remapped M code of modal group 10 (stop 55): read only on a machine whose description
/// remaps it, refused with its reason elsewhere; a missing subroutine is an error of the code;
/// inside its own subroutine it has no built-in meaning and is refused; in LinuxCNC's
/// M100–M199 a remap takes the place of the configuration's user program; two on one line
/// are two codes of group 10.
#[test]
fn a_remapped_machine_m_code_calls_its_subroutine_or_says_why_not() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden/remap");
    let remapped = |codes: &[(u32, &str)]| MachineSettings {
        remap_m: codes.iter().map(|(m, n)| Remap::new(*m, n)).collect(),
        ..MachineSettings::default()
    };
    let haas = remapped(&[(31, "chip_on"), (33, "chip_off"), (101, "chip_on")]);
    let subs = [dir.clone()];
    let run = |src: &str, st: &MachineSettings| novanc_moves(src, st, &subs);
    assert!(run("G21 M31\nM33\nM101\nM2\n", &haas).is_ok());
    for (src, st, want) in [
        (
            "G21\nM31\nM2\n",
            MachineSettings::default(),
            "2:1: unknown or unsupported code M31",
        ),
        (
            "G21\nM101\nM2\n",
            MachineSettings::default(),
            "2:1: M101: M100–M199 run the user programs",
        ),
        (
            "G21\nM31 M33\nM2\n",
            haas.clone(),
            "2:5: M33 and M31 are in the same modal group",
        ),
        (
            "G21\nG0 X1 M31\nM2\n",
            remapped(&[(31, "conveyor")]),
            "2:7: M31 (remapped to o<conveyor> by the machine description): subroutine o<conveyor> not found",
        ),
        (
            "o<again> sub\nM31\no<again> endsub\nG21\nM31\nM2\n",
            remapped(&[(31, "again")]),
            "2:1: M31 inside a remap subroutine",
        ),
    ] {
        let e = run(src, &st).unwrap_err();
        assert!(e.contains(want), "{src:?}: {e}");
    }
}
