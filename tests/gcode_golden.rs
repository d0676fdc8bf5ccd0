//! novanc's G-code reading against the moves LinuxCNC 2.9's rs274 made of the same programs,
//! kept as golden listings in `tests/golden/gcode/` by `tools/compare_rs274.py --golden`
//! (docs/gcode.md "Agreement with LinuxCNC"): every move's kind and machine end point and
//! every arc's centre and direction, in the same order, to 0.001 mm (wider only where rs274
//! printed inches with 4 decimals); where rs274 refused a program, novanc refuses it. CI needs
//! no LinuxCNC.

use novanc::block::{Motion, Plane};
use novanc::gcode::{translate_all, WorkOffsets};
use novanc::settings::MachineSettings;
use novanc::tooldata::sample_magazine;
use std::path::Path;

/// One move: kind ('R', 'F', 'A'), arc direction and plane, numbers (end, then centre).
#[derive(Debug, PartialEq)]
struct Move {
    kind: char,
    ccw: bool,
    plane: String,
    nums: Vec<f64>,
}

fn novanc_moves(src: &str) -> Result<Vec<Move>, String> {
    let st = MachineSettings::default();
    let stmts = translate_all(
        src,
        &sample_magazine(),
        &st,
        [0, 0, 0],
        WorkOffsets::default(),
    )
    .map_err(|e| e.to_string())?;
    let mut out = Vec::new();
    for b in stmts.iter().flat_map(|s| &s.blocks) {
        let mm = |p: i64| st.to_mm(p);
        let end: Vec<f64> = b.end.iter().map(|&p| mm(p)).collect();
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
    Ok(out)
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

#[test]
fn every_golden_program_agrees_with_rs274() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden/gcode");
    let mut names: Vec<_> = std::fs::read_dir(&dir)
        .expect("tests/golden/gcode")
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "ngc"))
        .collect();
    names.sort();
    assert!(names.len() >= 50, "only {} golden programs", names.len());
    let (mut programs, mut moves, mut refused) = (0, 0, 0);
    for prog in &names {
        let src = std::fs::read_to_string(prog).expect("program");
        let exp = std::fs::read_to_string(prog.with_extension("expect")).expect("its .expect");
        let name = prog.file_name().and_then(|n| n.to_str()).unwrap_or("?");
        let got = novanc_moves(&src);
        match expected(&exp) {
            Err(why) => {
                assert!(
                    got.is_err(),
                    "{name}: rs274 refuses ({why}), novanc accepts"
                );
                refused += 1;
            }
            Ok(want) => {
                let got = got.unwrap_or_else(|e| panic!("{name}: novanc refuses: {e}"));
                assert_eq!(got.len(), want.len(), "{name}: number of moves");
                for (i, (g, (w, tol))) in got.iter().zip(&want).enumerate() {
                    assert_eq!(
                        (g.kind, g.ccw, &g.plane),
                        (w.kind, w.ccw, &w.plane),
                        "{name}: move {}",
                        i + 1
                    );
                    for (a, b) in g.nums.iter().zip(&w.nums) {
                        assert!(
                            (a - b).abs() <= *tol + 1e-9,
                            "{name}: move {}: novanc {:?}, rs274 {:?}",
                            i + 1,
                            g.nums,
                            w.nums
                        );
                    }
                }
                moves += want.len();
            }
        }
        programs += 1;
    }
    println!("{programs} programs ({refused} refused by both), {moves} moves agree with rs274");
}
