//! The Fanuc dialect (docs/gcode.md "Fanuc dialect"): Custom Macro B programs of our own, each
//! with its moves worked out here by hand (trigonometry on the macro's arguments, not the
//! reader), and their listings kept as golden files in `tests/golden/fanuc/` (`novanc
//! translate --dialect fanuc`; `UPDATE_GOLDEN=1` rewrites them). The LinuxCNC dialect still
//! refuses the Fanuc words.

mod common;

use common::{gcode_source, gcode_source_in};
use novanc::block::Motion;
use novanc::panel_model::{DataMode, OpMode, PanelEvent as E};
use novanc::settings::Dialect::{self, Fanuc, LinuxCnc};
use std::path::{Path, PathBuf};

fn golden(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/golden/fanuc")
        .join(name)
}

fn program(name: &str) -> String {
    std::fs::read_to_string(golden(name)).unwrap()
}

/// The moves of `src` read in `dialect`: kind ('R' rapid, 'F' feed) and machine end, mm; or
/// the error.
fn moves(src: &str, dialect: Dialect) -> Result<Vec<(char, [f64; 3])>, String> {
    let mut out = Vec::new();
    for s in gcode_source_in(src, dialect) {
        let s = s.map_err(|e| e.to_string())?;
        for b in &s.blocks {
            let kind = match b.motion {
                Motion::Rapid => 'R',
                Motion::Linear => 'F',
                _ => continue,
            };
            out.push((kind, b.end.xyz().map(|p| p as f64 / 1000.0)));
        }
    }
    Ok(out)
}

/// Whether two move lists agree to the pulse.
fn assert_moves(got: &[(char, [f64; 3])], want: &[(char, [f64; 3])]) {
    assert_eq!(got.len(), want.len(), "{got:?}\nwant {want:?}");
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        let close = g.1.iter().zip(&w.1).all(|(a, b)| (a - b).abs() <= 0.0011);
        assert!(g.0 == w.0 && close, "move {i}: {g:?}, want {w:?}");
    }
}

/// `novanc translate --dialect fanuc` of a golden program, compared with (or, with
/// `UPDATE_GOLDEN=1`, written to) its listing `NAME.iso`; the exit code.
fn check_listing(name: &str) -> i32 {
    let out = common::novanc_command()
        .args(["translate", "--dialect", "fanuc"])
        // Relative to the project folder (where `novanc_command` runs), so the listing names no
        // checkout's path.
        .arg(format!("tests/golden/fanuc/{name}.nc"))
        .output()
        .unwrap();
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let p = golden(&format!("{name}.iso"));
    if std::env::var_os("UPDATE_GOLDEN").is_some() {
        std::fs::write(&p, &text).unwrap();
    }
    let want = std::fs::read_to_string(&p)
        .unwrap_or_else(|e| panic!("{}: {e} (UPDATE_GOLDEN=1 writes it)", p.display()));
    assert_eq!(text, want, "the listing of {name}.nc changed");
    out.status.code().unwrap_or(-1)
}

/// Work Z0 of the programs here: `G10 L2 P1 Z-300.`.
const WZ: f64 = -300.0;

/// The moves of the bolt circle macro O9010 from the height `z`: for each hole, a rapid over
/// it, the feed down to `depth`, a rapid up to Z2.
#[allow(clippy::too_many_arguments)]
fn bolt_circle(
    out: &mut Vec<(char, [f64; 3])>,
    z: &mut f64,
    centre: [f64; 2],
    r: f64,
    start: f64,
    step: f64,
    holes: u32,
    depth: f64,
) {
    for k in 0..holes {
        let a = (start + f64::from(k) * step).to_radians();
        let (x, y) = (centre[0] + r * a.cos(), centre[1] + r * a.sin());
        out.push(('R', [x, y, *z]));
        out.push(('F', [x, y, WZ + depth]));
        *z = WZ + 2.0;
        out.push(('R', [x, y, *z]));
    }
}

#[test]
fn a_bolt_circle_by_g65_with_arguments_and_a_while_loop() {
    let src = program("bolt.nc");
    let mut want = vec![('R', [0.0, 0.0, WZ + 10.0])];
    let mut z = WZ + 10.0;
    bolt_circle(&mut want, &mut z, [100.0, 50.0], 40.0, 15.0, 60.0, 6, -5.0);
    // X200000 Y100000 without a point: least increments, 200 and 100 mm; A not given: null,
    // so the circle starts at 0 degrees.
    bolt_circle(&mut want, &mut z, [200.0, 100.0], 20.0, 0.0, 120.0, 3, -2.0);
    let last = want.last().map(|m| m.1).unwrap();
    want.push(('R', [last[0], last[1], WZ + 10.0]));
    assert_moves(&moves(&src, Fanuc).unwrap(), &want);
    assert_eq!(check_listing("bolt"), 0);
}

#[test]
fn a_part_family_is_chosen_by_if_and_goto() {
    let src = program("family.nc");
    for (part, side) in [(1, 30.0), (2, 50.0)] {
        let text = src.replace("#100=2", &format!("#100={part}"));
        let z = WZ + 5.0;
        let c = WZ - 1.0;
        let want = [
            ('R', [0.0, 0.0, z]),
            ('F', [0.0, 0.0, c]),
            ('F', [side, 0.0, c]),
            ('F', [side, side, c]),
            ('F', [0.0, side, c]),
            ('F', [0.0, 0.0, c]),
            ('R', [0.0, 0.0, z]),
        ];
        assert_moves(&moves(&text, Fanuc).unwrap(), &want);
    }
    // No such part: the alarm of line 6, and nothing moves.
    let text = src.replace("#100=2", "#100=3");
    assert_eq!(
        moves(&text, Fanuc).unwrap_err(),
        "6:1: MACRO ALARM 3002: NO SUCH PART (#3000 = 2)"
    );
    assert_eq!(check_listing("family"), 0);
}

#[test]
fn a_missing_argument_raises_the_3000_alarm_and_nothing_moves() {
    let src = program("missing.nc");
    let mut blocks = 0;
    let mut err = None;
    for s in gcode_source_in(&src, Fanuc) {
        match s {
            Ok(s) => blocks += s.blocks.len(),
            Err(e) => err = Some(e),
        }
    }
    let e = err.expect("the alarm");
    assert_eq!((e.line, e.col), (6, 21), "{e}");
    assert_eq!(e.message, "MACRO ALARM 3001: X MISSING (#3000 = 1)");
    assert_eq!(blocks, 0, "nothing moves before or after the alarm");
    // With X the macro runs, and its locals are the caller's again after M99.
    let given = src.replace("G65 P9020 Y5.", "#24=7. G65 P9020 X3. Y5.\nG00 X#24");
    assert_moves(
        &moves(&given, Fanuc).unwrap(),
        &[('R', [3.0, 5.0, 0.0]), ('R', [7.0, 5.0, 0.0])],
    );
    assert_eq!(check_listing("missing"), 1);
}

#[test]
fn a_row_of_holes_is_drilled_by_a_g66_modal_call() {
    let src = program("row.nc");
    // O9100 drills where the move left the tool: the feed to Z-6 and the rapid up to R2 after
    // each of the four moves in G66; not after M08 (no move), nor in the macro, nor after G67.
    let mut want = vec![('R', [0.0, 0.0, WZ + 10.0])];
    let mut z = WZ + 10.0;
    for x in [10.0, 25.0, 40.0, 55.0] {
        want.push(('R', [x, 20.0, z]));
        want.push(('F', [x, 20.0, WZ - 6.0]));
        z = WZ + 2.0;
        want.push(('R', [x, 20.0, z]));
    }
    want.push(('R', [55.0, 20.0, WZ + 10.0]));
    want.push(('R', [0.0, 0.0, WZ + 10.0]));
    assert_moves(&moves(&src, Fanuc).unwrap(), &want);
    assert_eq!(check_listing("row"), 0);
    // L0 gives no calls; without G67, M30 ends the modal call with its program.
    let l0 = src.replace("G66 P9100 R2.", "G66 P9100 L0 R2.");
    assert_eq!(moves(&l0, Fanuc).unwrap().len(), 6);
    // The macro's arguments are given at G66: a missing one is the macro's alarm, at the
    // macro's line, after the first move.
    let e = gcode_source_in(&src.replace(" Z-6. F120.", " F120."), Fanuc)
        .find_map(|s| s.err())
        .unwrap();
    assert_eq!(
        e.to_string(),
        "18:21: MACRO ALARM 3001: Z MISSING (#3000 = 1)"
    );
}

#[test]
fn g66_and_g67_are_refused_with_their_place_where_novanc_differs_or_the_block_is_wrong() {
    let cases = [
        (
            "O1\nG66 P9100 Z1.\nG66 P9200\nM30\n",
            "3:1: G66 while the modal call G66 P9100 of line 2 is in force: G67 first (novanc keeps one modal call)",
        ),
        (
            "O1\nG66 P9100 L2\nM30\n",
            "2:1: G66 L2: novanc calls a modal macro once after each move (L1, or L0 for none)",
        ),
        ("O1\nG66 X1.\nM30\n", "2:1: G66 needs P, the macro's program number"),
        (
            "O1\nG66 P9100 G01 X1.\nM30\n",
            "2:11: G66 stands alone on its block: no other G code with it",
        ),
        ("O1\nG67 X1.\nM30\n", "2:5: G67 stands alone on its block"),
        (
            "O1\nG66 P9100\nG0 X1.\nM30\n",
            "3:1: G66 P9100: macro O9100 is not in the program (searched forward from the call) nor a file 9100.ngc in the subroutine path (the modal call of line 2)",
        ),
    ];
    for (src, want) in cases {
        assert_eq!(moves(src, Fanuc).unwrap_err(), want, "{src}");
    }
    // LinuxCNC's dialect has no G66 or G67, as before.
    for g in ["G66 P9100", "G67"] {
        let e = moves(&format!("{g}\nM30\n"), LinuxCnc).unwrap_err();
        assert!(e.contains(&g[..3]), "{e}");
    }
}

#[test]
fn the_msg_page_shows_a_3000_alarm_with_its_number() {
    let d = common::temp_dir("fanuc-msg");
    let mut c = common::reopen_in(&d.join("state"), Fanuc);
    read_and_run(&mut c, &golden("missing.nc"));
    assert!(c.view().lamps.alarm, "{}", c.frame_text());
    common::keys(&mut c, &["Ctrl+e"]);
    assert!(
        common::shows(
            &c,
            "ALARM 3:1: in O9020.NGC line 2:21: MACRO ALARM 3001: X MISSING (#3000 = 1)"
        ),
        "{}",
        c.frame_text()
    );
}

#[test]
fn stop_3006_stops_with_its_message_and_start_goes_on() {
    let mut g = gcode_source_in("O1\n#3006=1 (LOAD THE PART)\nG0 X1.\nM30\n", Fanuc);
    let stmts: Vec<_> = g.by_ref().collect::<Result<_, _>>().unwrap();
    let stop = stmts.iter().find(|s| s.line == 2).expect("the #3006 line");
    let ms: Vec<_> = stop.blocks.iter().map(|b| b.m).collect();
    assert_eq!(ms, vec![Some(0)], "a stop, as M00");
    let after = stmts.iter().find(|s| s.line == 3).expect("the line after");
    assert_eq!(
        after.blocks[0].end[0], 1000,
        "the run goes on after the stop"
    );
    let events = g.take_events();
    assert!(
        events.iter().any(|e| matches!(e, novanc::gcode::Event::Message { kind: "MSG", text } if text == "#3006 STOP 1: LOAD THE PART")),
        "{events:?}"
    );
    assert_eq!(
        moves("O1\n#3006=1 (STOP) G0 X1.\nM30\n", Fanuc).unwrap_err(),
        "2:1: #3006 stands on a block of its own (no words with it)"
    );
}

#[test]
fn a_runaway_loop_is_refused_at_the_line_that_passes_the_limit() {
    // Lines executed: 1, 2, then 3 and 4 in turn: the 1001st is line 3 (in the DO2 loop,
    // lines 2 to 5 in turn from the second: the 1001st is line 2 + 999 mod 4 = 5).
    for (src, line) in [
        ("O1\n#1=0\nN10 #1=#1+1\nGOTO 10\nM30\n", 3),
        ("O1\n#1=0\nWHILE [1] DO1\nEND1\nM30\n", 3),
        ("O1\nDO2\nG0 X1.\nG0 X2.\nEND2\nM30\n", 5),
    ] {
        let e = gcode_source_in(src, Fanuc)
            .line_limit(1000)
            .find_map(|s| s.err())
            .expect("refused");
        assert_eq!(e.line, line, "{src}: {e}");
        assert!(e.message.contains("more than 1000 lines"), "{e}");
    }
}

#[test]
fn loops_nest_as_fanuc_s_and_a_mismatch_is_refused_with_its_place() {
    let cases = [
        (
            "O1\nWHILE [1] DO1\nWHILE [1] DO2\nEND1\nEND2\nM30\n",
            "4:1: END1 where the loop DO2 of line 3 is still open: loops may nest, not cross",
        ),
        (
            "O1\nWHILE [1] DO1\nWHILE [1] DO1\nEND1\nEND1\nM30\n",
            "3:1: DO1 inside the loop DO1 of line 2: nested loops need different numbers",
        ),
        (
            "O1\nWHILE [0] DO1\nG0 X1.\nM30\n",
            "2:1: WHILE [...] DO1: no END1 after it in this program",
        ),
        ("O1\nEND2\nM30\n", "2:1: END2 without a DO2 before it"),
        (
            "O1\nDO4\nEND4\nM30\n",
            "2:3: DO4: the loop number is 1 to 3",
        ),
        (
            "O1\nGOTO 55\nM30\n",
            "2:1: GOTO 55: no block N55 in this program (searched forward, then from its start)",
        ),
    ];
    for (src, want) in cases {
        assert_eq!(moves(src, Fanuc).unwrap_err(), want, "{src}");
    }
    // Three deep, with a GOTO out of the inner two, then counted passes.
    let src = "O1\n#1=0\n#4=0\nWHILE [#1 LT 2] DO1\n#2=0\nWHILE [1] DO2\nDO3\n#4=#4+1\n\
               IF [#4 GE 100] GOTO 20\nGOTO 10\nEND3\nEND2\nN10 #2=#2+1\nN20 #1=#1+1\nEND1\n\
               G0 X#1 Y#4\nM30\n";
    assert_moves(&moves(src, Fanuc).unwrap(), &[('R', [2.0, 2.0, 0.0])]);
}

#[test]
fn null_and_the_decimal_point_follow_fanuc() {
    let src = "O1\nG10 L2 P1 X100. Y100. Z-100.\n#1=#0\n#2=#1+1.\n#3=[#0 EQ #0]\n#4=[#0 EQ 0]\n#5=[#0 NE 0]\n#6=[#0 GE 0]\n\
               G0 X#2 Y#3 Z#1\nG0 X#4 Y#5 Z-#6\nG0 X10 Y10. Z[-10]\nG20\nG0 X10\nG21\nG0 X-5 Y#0\n\
               G0 X[FIX[-1.5]] Y[FUP[-1.2]]\nG0 X[ATAN[-1]/[-1]] Y[BIN[BCD[25]]]\nG0 X[ATAN[-1,1]] Y[ATAN[1,-1]]\nM30\n";
    let inch = 10.0 * 0.0001 * 25.4;
    // In work coordinates (G54 at 100, 100, -100); the first move's Z stays at machine 0.
    let want = [
        // Null + 1 is 1; #0 EQ #0 is true; a word with a null value is absent.
        ('R', [1.0, 1.0, 100.0]),
        ('R', [0.0, 1.0, -1.0]),
        // X10 is 10 least increments (0.001 mm, or 0.0001 inch under the G20 of a line
        // before); Y10. and Z[-10] are millimetres.
        ('R', [0.01, 10.0, -10.0]),
        ('R', [inch, 10.0, -10.0]),
        ('R', [-0.005, 10.0, -10.0]),
        // FIX[-1.5] is -1, FUP[-1.2] is -2; ATAN answers 0 to 360; BIN undoes BCD.
        ('R', [-1.0, -2.0, -10.0]),
        ('R', [225.0, 25.0, -10.0]),
        // Fanuc 30i's ATAN[y,x] is ATAN[y]/[x].
        ('R', [315.0, 135.0, -10.0]),
    ]
    .map(|(k, p)| (k, [p[0] + 100.0, p[1] + 100.0, p[2] - 100.0]));
    assert_moves(&moves(src, Fanuc).unwrap(), &want);
    assert_eq!(
        moves("O1\nG0 X[ATAN[1]]\nM30\n", Fanuc).unwrap_err(),
        "2:13: ATAN is written ATAN[y]/[x] or ATAN[y,x]"
    );
    assert_eq!(
        moves("O1\n#0=1\nM30\n", Fanuc).unwrap_err(),
        "2:1: #0 is null: it cannot be set"
    );
}

/// A Fanuc tape's program numbers: `%O1200` (leader and number on one line) and ISO's `:`
/// for O, a subprogram numbered so found by M98 (stop 57; refused before). LinuxCNC's dialect
/// refuses both.
#[test]
fn a_tape_s_program_number_may_follow_its_percent_or_be_written_with_a_colon() {
    let plain = "%\nO1200\nG0 X10. Y10.\nM98 P200\nM30\nO200\nG0 X20.\nM99\n%\n";
    let iso = "%O1200 (A FLANGE)\nG0 X10. Y10.\nM98 P200\nM30\n:200\nG0 X20.\nM99\n%\n";
    let want = moves(plain, Fanuc).unwrap();
    assert_eq!(want.len(), 2);
    assert_moves(&moves(iso, Fanuc).unwrap(), &want);
    assert!(moves(iso, LinuxCnc)
        .unwrap_err()
        .starts_with("1:1: a word letter was expected, not '%'"));
    assert!(moves("%\n:200\nM30\n%\n", LinuxCnc)
        .unwrap_err()
        .starts_with("2:1: a word letter was expected, not ':'"));
}

#[test]
fn the_linuxcnc_dialect_refuses_the_fanuc_words_as_before() {
    assert_eq!(
        moves(&program("family.nc"), LinuxCnc).unwrap_err(),
        "4:1: IF is Fanuc Custom Macro B, not LinuxCNC's language: write loops and tests as O-words (o100 while [...], o100 if [...])"
    );
    let e = gcode_source("G65 P9010 X1\nM30\n")
        .find_map(|s| s.err())
        .unwrap();
    assert!(e.to_string().contains("G65"), "{e}");
    assert!(
        moves("#1=#0\nM30\n", LinuxCnc)
            .unwrap_err()
            .contains("parameter number 0"),
        "#0 is not a parameter in LinuxCNC"
    );
    // M29 (rigid tapping) is Fanuc's; in its dialect it needs S.
    assert!(
        moves("S300\nM29\nM30\n", LinuxCnc)
            .unwrap_err()
            .contains("unknown or unsupported code M29"),
        "M29 is not LinuxCNC's"
    );
    assert_eq!(
        moves("M29\nM30\n", Fanuc).unwrap_err(),
        "1:1: M29 (rigid tapping) needs S, the tap's rpm: M29 S500"
    );
    // A number without a decimal point is millimetres in LinuxCNC's dialect.
    assert_moves(
        &moves("G0 X10\nM30\n", LinuxCnc).unwrap(),
        &[('R', [10.0, 0.0, 0.0])],
    );
}

#[test]
fn the_dialect_is_chosen_by_the_command_line_and_the_machine_description() {
    let bad = common::novanc_command()
        .args(["translate", "--dialect", "heidenhain"])
        .arg(golden("family.nc"))
        .output()
        .unwrap();
    assert_eq!(bad.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&bad.stderr).contains("dialect 'heidenhain': fanuc or linuxcnc")
    );
    let d = common::temp_dir("fanuc-desc");
    let centre = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("machines/centre.machine"),
    )
    .unwrap();
    let desc = d.join("fanuc.machine");
    std::fs::write(&desc, format!("{centre}dialect fanuc\n")).unwrap();
    let out = common::novanc_command()
        .args(["translate", "--machine"])
        .arg(&desc)
        .arg(golden("family.nc"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let want = std::fs::read_to_string(golden("family.iso")).unwrap();
    assert_eq!(String::from_utf8_lossy(&out.stdout), want);
    // The command line says last.
    let out = common::novanc_command()
        .args(["translate", "--dialect=linuxcnc", "--machine"])
        .arg(&desc)
        .arg(golden("family.nc"))
        .output()
        .unwrap();
    assert!(String::from_utf8_lossy(&out.stderr).contains("IF is Fanuc Custom Macro B"));
    use novanc::lathe::desc::{parse, MachineDesc};
    assert!(
        matches!(parse(&format!("{centre}dialect fanuc\n")), Ok(MachineDesc::Mill(s)) if s.dialect == Fanuc)
    );
    assert!(matches!(parse(&centre), Ok(MachineDesc::Mill(s)) if s.dialect == LinuxCnc));
    assert!(parse(&format!("{centre}dialect fanuc\ndialect fanuc\n"))
        .unwrap_err()
        .contains("the dialect is given twice"));
}

/// PROGRAM READ of `path` and an AUTO run to its end.
fn read_and_run(c: &mut novanc::console::Console, path: &Path) {
    c.handle(E::Op(OpMode::Data));
    c.handle(E::Data(DataMode::Read));
    c.handle(E::Tape(path.to_path_buf()));
    c.handle(E::Start);
    c.handle(E::Wait);
    c.handle(E::Op(OpMode::Auto));
    c.handle(E::Start);
    c.handle(E::Wait);
}

#[test]
fn common_variable_500_counts_across_a_restart() {
    let d = common::temp_dir("fanuc-500");
    let prog = d.join("COUNT.NC");
    std::fs::write(
        &prog,
        "O4000 (PARTS DONE IN #500)\nIF [#500 EQ #0] THEN #500=0\n#500=#500+1\n\
         #100=#100+1\nG00 X#500 Y#100\nM30\n",
    )
    .unwrap();
    let state = d.join("state");
    for run in 1..=2 {
        let mut c = common::reopen_in(&state, Fanuc);
        read_and_run(&mut c, &prog);
        assert!(!c.view().lamps.alarm, "{}", c.frame_text());
        // #500 counts the runs; #100 is vacant again after each power-on.
        assert_eq!(
            c.status().pos,
            [common::p(f64::from(run)), common::p(1.0), 0],
            "run {run}:\n{}",
            c.frame_text()
        );
        assert_eq!(c.interp_state().params[500], f64::from(run));
    }
}

#[test]
fn a_dnc_file_s_programs_are_stored_one_by_one_and_called_by_number() {
    let d = common::temp_dir("fanuc-dnc");
    let prog = d.join("SHOP.NC");
    let text =
        "%\nO1000 (MAIN)\nG21 G90 G54 G10 L2 P1 X0 Y0 Z0\nG65 P9010 X5. Y6.\nM98 P9020\nM30\n\
                O9010 (MACRO)\nG00 X#24 Y#25\nM99\nO9020 (SUB)\nG00 Z-2.\nM99\n%\n";
    std::fs::write(&prog, text).unwrap();
    let state = d.join("state");
    let mut c = common::reopen_in(&state, Fanuc);
    read_and_run(&mut c, &prog);
    assert!(!c.view().lamps.alarm, "{}", c.frame_text());
    assert_eq!(c.program_name(), "O1000.NGC");
    // O1000 alone is the current program: the macro and the subprogram are found in program
    // memory by number, not by searching on in its text.
    assert!(!c.program_text().contains("O9010"), "{}", c.program_text());
    assert_eq!(
        c.status().pos,
        [common::p(5.0), common::p(6.0), common::p(-2.0)]
    );
    // Kept across a restart; read again, the numbers are in use: refused, nothing stored.
    drop(c);
    let mut c = common::reopen_in(&state, Fanuc);
    c.handle(E::Op(OpMode::Data));
    c.handle(E::Data(DataMode::Read));
    c.handle(E::Tape(prog.clone()));
    c.handle(E::Start);
    c.handle(E::Wait);
    assert!(
        common::shows(
            &c,
            "SHOP.NC:2: program number O1000 already in use (program O1000.NGC); nothing stored"
        ),
        "{}",
        c.frame_text()
    );
    assert_eq!(c.program_name(), "O1000.NGC");
    // In LinuxCNC's dialect the file is one program, as before.
    let mut c = common::reopen_in(&d.join("state2"), LinuxCnc);
    c.handle(E::Op(OpMode::Data));
    c.handle(E::Data(DataMode::Read));
    c.handle(E::Tape(prog));
    c.handle(E::Start);
    c.handle(E::Wait);
    assert_eq!(c.program_name(), "SHOP.NC");
    assert!(c.program_text().contains("O9010"));
}

/// An AUTO run of the current program from X0 Y0 (a move read the same in both dialects).
fn run_current(c: &mut novanc::console::Console) {
    common::mdi(c, "G00 X0. Y0.");
    c.handle(E::Op(OpMode::Auto));
    c.handle(E::Start);
    c.handle(E::Wait);
    assert!(!c.view().lamps.alarm, "{}", c.frame_text());
}

/// Whether the PROG page says each of `texts`; the mode's display is shown again after.
fn prog_page_shows(c: &mut novanc::console::Console, texts: &[&str]) {
    common::keys(c, &["Ctrl+d"]);
    for t in texts {
        assert!(common::shows(c, t), "{t}:\n{}", c.frame_text());
    }
    common::keys(c, &["Ctrl+d"]);
}

#[test]
fn a_program_is_read_in_the_dialect_it_was_stored_in_after_the_machine_changes_its_own() {
    let d = common::temp_dir("fanuc-kept");
    let state = d.join("state");
    // Fanuc's: IF/GOTO (refused by LinuxCNC), X500 in least increments (0.5 mm).
    let fanuc = d.join("FAM.NC");
    std::fs::write(
        &fanuc,
        "O1000\n#1=2\nIF [#1 EQ 2] GOTO 10\nG00 X99.\nN10 G00 X500 Y6.\nM30\n",
    )
    .unwrap();
    // LinuxCNC's: X10 is 10 mm (Fanuc's would be 0.010 mm); Z#100, left vacant by a Fanuc run
    // reads 0 (LinuxCNC has no null).
    let linuxcnc = d.join("LC.NGC");
    std::fs::write(&linuxcnc, "G21 G90\nG00 X10 Y[2*3] Z#100\nM30\n").unwrap();
    let at = |c: &novanc::console::Console| c.status().pos;
    let mut c = common::reopen_in(&state, Fanuc);
    read_and_run(&mut c, &fanuc);
    assert_eq!(
        at(&c),
        [common::p(0.5), common::p(6.0), 0],
        "{}",
        c.frame_text()
    );
    drop(c);
    // The machine switched to LinuxCNC's dialect: FAM.NC is still read as Fanuc's.
    let mut c = common::reopen_in(&state, LinuxCnc);
    prog_page_shows(&mut c, &["PROG  FAM.NC FANUC", "*FAM.NC       FAN"]);
    run_current(&mut c);
    assert_eq!(
        at(&c),
        [common::p(0.5), common::p(6.0), 0],
        "{}",
        c.frame_text()
    );
    read_and_run(&mut c, &linuxcnc);
    assert_eq!(
        at(&c),
        [common::p(10.0), common::p(6.0), 0],
        "{}",
        c.frame_text()
    );
    drop(c);
    // And the reverse, after a restart (FAM.NC's dialect now read from the snapshot, LC.NGC's
    // from the journal).
    let mut c = common::reopen_in(&state, Fanuc);
    prog_page_shows(
        &mut c,
        &[
            "PROG  LC.NGC LINUXCNC",
            "FAM.NC       FAN",
            "*LC.NGC       ISO",
        ],
    );
    run_current(&mut c);
    assert_eq!(
        at(&c),
        [common::p(10.0), common::p(6.0), 0],
        "{}",
        c.frame_text()
    );
    // MDI is read in the machine's dialect.
    common::mdi(&mut c, "G00 X2000");
    assert_eq!(at(&c)[0], common::p(2.0), "{}", c.frame_text());
    drop(c);
    let mut c = common::reopen_in(&state, Fanuc);
    prog_page_shows(&mut c, &["FAM.NC       FAN", "*LC.NGC       ISO"]);
}

#[test]
fn a_store_written_before_programs_kept_their_dialect_reads_them_in_the_machine_s() {
    let d = common::temp_dir("fanuc-old-store");
    let state = d.join("state");
    {
        // A store told no dialect writes the records of before (`read NAME`, `program NAME
        // POINTER`), byte for byte.
        let (mut s, _) = novanc::store::Stores::open(&state, 24).unwrap();
        s.program_read("OLD.NGC", "G00 X10 Y6.\nM30\n").unwrap();
        assert_eq!(s.program_dialect("OLD.NGC"), None);
    }
    let journal = std::fs::read(state.join("journal.log")).unwrap();
    assert!(
        journal.windows(13).any(|w| w == b"read OLD.NGC\n"),
        "{}",
        String::from_utf8_lossy(&journal)
    );
    for (dialect, x, shown) in [
        (Fanuc, 0.010, "*OLD.NGC      FAN"),
        (LinuxCnc, 10.0, "*OLD.NGC      ISO"),
        (Fanuc, 0.010, "*OLD.NGC      FAN"),
    ] {
        let mut c = common::reopen_in(&state, dialect);
        prog_page_shows(&mut c, &[shown]);
        run_current(&mut c);
        assert_eq!(c.status().pos, [common::p(x), common::p(6.0), 0]);
    }
}

#[test]
fn reset_clears_the_common_variables_or_keeps_them_by_the_machine_s_setting() {
    let d = common::temp_dir("fanuc-ccv");
    let prog = d.join("COMMON.NC");
    std::fs::write(&prog, "O1\n#100=5.\n#199=#100+1\nG00 X1.\nM30\n").unwrap();
    for (keep, want) in [(false, None), (true, Some([5.0, 6.0]))] {
        let state = d.join(format!("state-{keep}"));
        let mut c = common::reopen_with(&state, |s| {
            s.dialect = Fanuc;
            s.fanuc.keep_common = keep;
        });
        read_and_run(&mut c, &prog);
        assert!(!c.view().lamps.alarm, "{}", c.frame_text());
        assert_eq!(c.interp_state().params[100], 5.0);
        c.handle(E::Reset);
        let now = [100, 199].map(|n| c.interp_state().params[n]);
        match want {
            Some(v) => assert_eq!(now, v, "common keep"),
            None => assert!(now.iter().all(|v| v.is_nan()), "common clear: {now:?}"),
        }
        // Power-off clears them either way (Fanuc's #100-#199 are not kept).
        drop(c);
        let c = common::reopen_with(&state, |s| {
            s.dialect = Fanuc;
            s.fanuc.keep_common = keep;
        });
        assert!(c.interp_state().params[100].is_nan());
    }
}

#[test]
fn the_fanuc_settings_are_lines_of_the_machine_description() {
    use novanc::lathe::desc::{parse, MachineDesc};
    let centre = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("machines/centre.machine"),
    )
    .unwrap();
    let fanuc = |extra: &str| match parse(&format!("{centre}{extra}")) {
        Ok(MachineDesc::Mill(s)) => Ok(s.fanuc),
        Ok(_) => Err("not a mill".to_string()),
        Err(e) => Err(e),
    };
    let set = |keep_common, calculator| novanc::settings::FanucSettings {
        keep_common,
        calculator,
        ..Default::default()
    };
    assert_eq!(fanuc(""), Ok(set(false, false)));
    assert_eq!(
        fanuc("common keep\ndecimal calculator\n"),
        Ok(set(true, true))
    );
    assert_eq!(
        fanuc("common clear\ndecimal increments\n"),
        Ok(set(false, false))
    );
    let lines = centre.lines().count();
    for (extra, e) in [
        (
            "common keep\ncommon clear\n",
            format!("{}: common is given twice", lines + 2),
        ),
        (
            "decimal point\n",
            format!(
                "{}: decimal takes calculator or increments (the Fanuc dialect's setting)",
                lines + 1
            ),
        ),
        (
            "common\n",
            format!(
                "{}: common takes keep or clear (the Fanuc dialect's setting)",
                lines + 1
            ),
        ),
    ] {
        assert_eq!(fanuc(extra), Err(e));
    }
    let citizen = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("machines/citizen.machine"),
    )
    .unwrap();
    // A lathe's channels take `common` (tests/lathe_state.rs) and `decimal`
    // (tests/lathe_real.rs), each in a channel (here the last) or machine-wide.
    match parse(&format!("{citizen}decimal calculator\n")) {
        Ok(novanc::lathe::desc::MachineDesc::Lathe(d)) => {
            let c: Vec<_> = d.channels.iter().map(|c| c.calculator).collect();
            assert_eq!(c, [None, None, Some(true)]);
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn calculator_type_input_reads_a_number_without_a_point_in_millimetres() {
    let calculator = novanc::settings::MachineSettings {
        dialect: Fanuc,
        fanuc: novanc::settings::FanucSettings {
            calculator: true,
            ..Default::default()
        },
        ..Default::default()
    };
    let src = "O1\nG21 G90\nG00 X10 Y20. Z-3\nG65 P9 X10 Y5.\nG04 X2\nG04 P1500\nM30\n\
               O9\n#100=#24\n#101=ADP[#24]\n#102=#25\nM99\n";
    let run = |settings: novanc::settings::MachineSettings| {
        let (mut ends, mut dwells) = (Vec::new(), Vec::new());
        let mut src = common::gcode_source_with(src, settings);
        for s in src.by_ref() {
            for b in &s.unwrap().blocks {
                match b.motion {
                    Motion::Dwell => dwells.push(b.dwell_ns as f64 / 1e9),
                    _ => ends.push(b.end.xyz().map(|p| p as f64 / 1000.0)),
                }
            }
        }
        let st = src.state().clone();
        (ends, dwells, [100, 101, 102].map(|n| st.params[n]))
    };
    let (ends, dwells, vars) = run(calculator.clone());
    assert_eq!(ends.last(), Some(&[10.0, 20.0, -3.0]));
    // G04 X2 is 2 s (seconds as written), P stays milliseconds; an argument is as written.
    assert_eq!(dwells, [2.0, 1.5]);
    assert_eq!(vars, [10.0, 10.0, 5.0]);
    // The default: least increments.
    let increments = novanc::settings::MachineSettings {
        fanuc: Default::default(),
        ..calculator
    };
    let (ends, dwells, vars) = run(increments);
    assert_eq!(ends.last(), Some(&[0.01, 20.0, -0.003]));
    assert_eq!(dwells, [0.002, 1.5]);
    assert_eq!(vars, [0.01, 10.0, 5.0]);
}

#[test]
fn a_macro_is_found_as_a_file_of_its_number_in_the_subroutine_path() {
    let d = common::temp_dir("fanuc-subs");
    std::fs::write(
        d.join("9030.ngc"),
        "O9030 (FROM A FILE)\nG00 X#24 Y#25\nIF [#26 NE #0] GOTO 10\nG00 Z-1.\nM99\nN10 G00 Z#26\nM99\n",
    )
    .unwrap();
    let src = "O1\nG65 P9030 X5. Y6.\nG65 P9030 X7. Y8. Z-3.\nM30\n";
    let mut got = Vec::new();
    for s in gcode_source_in(src, Fanuc).subroutines(Box::new(novanc::gcode::SubPath(vec![d]))) {
        for b in s
            .unwrap()
            .blocks
            .iter()
            .filter(|b| b.motion == Motion::Rapid)
        {
            got.push(('R', b.end.xyz().map(|p| p as f64 / 1000.0)));
        }
    }
    // GOTO 10 searches the macro's own lines: forward from the IF, in its file.
    assert_moves(
        &got,
        &[
            ('R', [5.0, 6.0, 0.0]),
            ('R', [5.0, 6.0, -1.0]),
            ('R', [7.0, 8.0, -1.0]),
            ('R', [7.0, 8.0, -3.0]),
        ],
    );
    // L is bounded as M98's is.
    let max = novanc::gcode::MAX_REPEATS;
    assert_eq!(
        moves(&format!("O1\nG65 P9030 L{} X1.\nM30\n", max + 1), Fanuc).unwrap_err(),
        format!("2:11: G65 L: a whole number 0 to {max}")
    );
    // Not there: refused at the call.
    assert_eq!(
        moves("O1\nG65 P9031 X1.\nM30\n", Fanuc).unwrap_err(),
        "2:1: G65 P9031: macro O9031 is not in the program (searched forward from the call) nor a file 9031.ngc in the subroutine path"
    );
}

#[test]
fn a_probing_macro_skips_by_g31_against_the_workpiece() {
    // The centre's stock (docs/gcode.md "Probing"): X 300 to 700, Y 200 to 600, top Z -450;
    // no tool, so the skip point is the gauge line. G54 is machine zero until the program
    // moves it onto the corner it found.
    let src = program("probe.nc");
    let (top, face) = (-450.0, 300.0);
    let want = [
        ('R', [500.0, 400.0, -400.0]),
        // G31 to Z-480 skips at the top; the block goes to its end point, the machine stops
        // it, and reading goes on from the skip point.
        ('F', [500.0, 400.0, -480.0]),
        ('R', [500.0, 400.0, top + 10.0]),
        ('R', [280.0, 400.0, top + 10.0]),
        ('R', [280.0, 400.0, top - 10.0]),
        // G91 X40 from X280: skips at the X- face.
        ('F', [320.0, 400.0, top - 10.0]),
        ('R', [face - 5.0, 400.0, top - 10.0]),
        ('R', [face - 5.0, 400.0, top + 10.0]),
        // #5221/#5223 moved G54 onto the corner at once (Fanuc): X10 Y10 is machine 310, 10.
        ('R', [face + 10.0, 10.0, top + 10.0]),
        // Above the stock nothing skips: no alarm, the move ends at its end point (the
        // macro's IF checks #5061 = -50 there).
        ('F', [face - 50.0, 10.0, top + 10.0]),
        ('R', [face, 0.0, top + 10.0]),
    ];
    assert_moves(&moves(&src, Fanuc).unwrap(), &want);
    assert_eq!(check_listing("probe"), 0);
    // G31 is one-shot: the motion mode stays G00 after it (an X word alone rapids).
    assert_moves(
        &moves(
            "O1\nG00 X500. Y400. Z-400.\nG31 Z-480. F100.\nX510.\nM30\n",
            Fanuc,
        )
        .unwrap(),
        &[
            ('R', [500.0, 400.0, -400.0]),
            ('F', [500.0, 400.0, -480.0]),
            ('R', [510.0, 400.0, -450.0]),
        ],
    );
    // LinuxCNC's dialect has no G31.
    assert!(moves("G31 Z-480 F100\nM30\n", LinuxCnc)
        .unwrap_err()
        .contains("G31"));
}

/// The dwells of `src` read in the Fanuc dialect, seconds; or the error.
fn dwells(src: &str) -> Result<Vec<f64>, String> {
    dwells_in(src, Fanuc)
}

/// The dwells of `src` read in `dialect`, seconds; or the error.
fn dwells_in(src: &str, dialect: Dialect) -> Result<Vec<f64>, String> {
    let mut out = Vec::new();
    for s in gcode_source_in(src, dialect) {
        let s = s.map_err(|e| e.to_string())?;
        for b in s.blocks.iter().filter(|b| b.motion == Motion::Dwell) {
            out.push(b.dwell_ns as f64 / 1e9);
        }
    }
    Ok(out)
}

#[test]
fn g04_dwells_as_fanuc_s_x_u_in_seconds_p_in_milliseconds() {
    assert_eq!(
        dwells("O1\nG04 X1.5\nG04 U2.\nG04 P1500\nG04 X2500\nG20\nG04 X2500\nG01 X1. F10.\nG04 X3.\nM30\n")
            .unwrap(),
        // X without a point: 0.001 s increments, in inches too; X on G04 never moves.
        [1.5, 2.0, 1.5, 2.5, 2.5, 3.0]
    );
    for (src, e) in [
        ("G04 P1.5", "2:5: G04 P1.5: P is in milliseconds and takes no decimal point (P1500 is 1.5 s; X1.5 gives seconds; a Haas's P with a point is seconds: `g04 p point seconds` in its description)"),
        ("#1=1.5\nG04 P#1", "3:5: G04 P1.5: P is a whole number of milliseconds"),
        ("G04 X1. P10", "2:9: G04 takes one dwell: X or U in seconds, or P in milliseconds"),
        ("G04", "2:1: G04 needs its dwell: X or U in seconds (X1.5), or P in milliseconds (P1500)"),
    ] {
        assert_eq!(dwells(&format!("O1\n{src}\nM30\n")).unwrap_err(), e);
    }
}

/// A Haas reads G04's P written with a point as seconds (`G04 P10.` ten seconds, `P10` ten
/// milliseconds): the description's `g04 p point seconds` says so (stop 57); a mill's line is
/// the machine's, a lathe's the channel's or every channel's. Without it P with a point stays
/// refused, as Fanuc refuses it, and the line refuses what it does not know.
#[test]
fn a_haas_description_reads_g04_p_with_a_point_as_seconds() {
    use novanc::lathe::desc::{parse, MachineDesc};
    let mill = |extra: &str| match parse(&format!(
        "machine haas\nkind mill\npulse 0.001\nx travel 0 1000 rapid 12000 accel 1000\n\
         y travel 0 800 rapid 12000 accel 1000\nz travel -600 0 rapid 12000 accel 1000\n\
         dialect fanuc\n{extra}"
    )) {
        Ok(MachineDesc::Mill(s)) => s,
        Ok(_) => panic!("not a mill"),
        Err(e) => panic!("{e}"),
    };
    let dwells = |src: &str, st: novanc::settings::MachineSettings| -> Result<Vec<f64>, String> {
        let mut out = Vec::new();
        for s in common::gcode_source_with(src, st) {
            let s = s.map_err(|e| e.to_string())?;
            for b in s.blocks.iter().filter(|b| b.motion == Motion::Dwell) {
                out.push(b.dwell_ns as f64 / 1e9);
            }
        }
        Ok(out)
    };
    let src = "O1\nG04 P1.5\nG04 P10.\nG04 P10\nG04 X2.\nM30\n";
    assert_eq!(
        dwells(src, mill("g04 p point seconds\n")).unwrap(),
        [1.5, 10.0, 0.01, 2.0]
    );
    assert!(dwells(src, mill("g04 p point refuse\n"))
        .unwrap_err()
        .starts_with("2:5: G04 P1.5: P is in milliseconds"));
    assert!(dwells(src, mill("")).is_err());
    for (line, want) in [
        (
            "g04 p point minutes",
            "g04 takes p point seconds or p point refuse",
        ),
        (
            "g04 p point seconds\ng04 p point seconds",
            "g04 is given twice",
        ),
    ] {
        let text = format!(
            "machine haas\nkind mill\npulse 0.001\nx travel 0 1000 rapid 12000 accel 1000\n\
             y travel 0 800 rapid 12000 accel 1000\nz travel -600 0 rapid 12000 accel 1000\n{line}\n"
        );
        let e = parse(&text).err().unwrap_or_default();
        assert!(e.contains(want), "{line}: {e}");
    }
}

#[test]
fn a_canned_cycle_s_dwell_p_is_in_milliseconds_in_fanuc_s_dialect_seconds_in_linuxcnc_s() {
    let cycles = |p82: &str, p89: &str| {
        format!(
            "G21 G90 G00 Z-5.\nG99 G82 X10. Y10. Z-12. R-6. P{p82} F100.\nX20.\nG80\n\
             G89 X30. Z-12. R-6. P{p89} F100.\nG80\nM30\n"
        )
    };
    // The second G82 hole repeats the cycle with its P.
    assert_eq!(dwells(&cycles("1500", "250")).unwrap(), [1.5, 1.5, 0.25]);
    assert_eq!(
        dwells_in(&cycles("1.5", "0.25"), LinuxCnc).unwrap(),
        [1.5, 1.5, 0.25]
    );
    for (src, e) in [
        ("G82 X0. Y0. Z-9. R-6. P1.5 F100.", "2:23: G82 P1.5: P is a whole number of milliseconds in the Fanuc dialect (P1500 is 1.5 s)"),
        ("G89 X0. Y0. Z-9. R-6. F100.", "2:1: G89 needs P, the dwell at the bottom in milliseconds"),
        // A point where Fanuc 0i allows none (alarm PS0007): on the cycle's line, and on a
        // line that repeats the cycle in force.
        ("G82 X0. Y0. Z-9. R-6. P1500. F100.", "2:23: G82 P1500.: P is a whole number of milliseconds written without a decimal point in the Fanuc dialect (P1500 is 1.5 s; a Fanuc 0i raises alarm PS0007, illegal use of decimal point)"),
        ("G89 X0. Y0. Z-9. R-6. P250 F100.\nX10. P0.", "3:6: G89 P0.: P is a whole number of milliseconds written without a decimal point in the Fanuc dialect (P1500 is 1.5 s; a Fanuc 0i raises alarm PS0007, illegal use of decimal point)"),
    ] {
        assert_eq!(dwells(&format!("G21 G90 G00 Z-5.\n{src}\nM30\n")).unwrap_err(), e);
    }
    // Another P on a line in a cycle keeps its own rules (G04's), and LinuxCNC's P is seconds
    // with a point.
    assert_eq!(
        dwells("G21 G90 G00 Z-5.\nG82 X0. Y0. Z-9. R-6. P1500 F100.\nG04 X2.\nG80\nM30\n").unwrap(),
        [1.5, 2.0]
    );
    assert_eq!(
        dwells_in(
            "G21 G90 G00 Z-5.\nG82 X0. Y0. Z-9. R-6. P2. F100.\nM30\n",
            LinuxCnc
        )
        .unwrap(),
        [2.0]
    );
}

/// The values of variables `ns` after `src` ran in the Fanuc dialect with 7 parts machined of
/// 10 required; or the error.
fn values(src: &str, ns: &[usize]) -> Result<Vec<f64>, String> {
    let mut g = gcode_source_in(src, Fanuc).part_counter(7, 10);
    for s in g.by_ref() {
        s.map_err(|e| e.to_string())?;
    }
    Ok(ns.iter().map(|&n| g.state().params[n]).collect())
}

#[test]
fn system_variables_give_positions_modes_offsets_and_parts() {
    let mag = novanc::tooldata::sample_magazine();
    let t2 = mag.tools.get(2).unwrap().clone();
    let src = "O1234\nG21 G90 G10 L2 P2 X10. Y20. Z-300.\nG55 G43 H2 G00 X1. Y2. Z3.\n\
               G01 X5. F300. S1200 M03 T7\n\
               #101=#5001 #102=#5002 #103=#5003 #104=#5021 #105=#5023 #106=#5043\n\
               #107=#4001 #108=#4003 #109=#4014 #110=#4109 #111=#4113 #112=#4115\n\
               #113=#4119 #114=#4120 #115=#4008 #116=#4111 #117=#4201 #118=#4006\n\
               #119=#11002 #120=#2202 #121=#13002 #122=#10002 #123=#3901 #124=#3902\n\
               #10002=0.05\n#125=#10002 #126=#11002\nM30\n";
    let got = values(src, &(101..=126).collect::<Vec<_>>()).unwrap();
    let l = t2.set_length;
    let want = [
        // Block end: work coordinates, the tool length not included.
        5.0,
        2.0,
        3.0,
        // Machine: G55's zero and the tool length included.
        15.0,
        -297.0 + l,
        // Work position with the tool length included.
        3.0 + l,
        // G01, G90, G55, F300, M03, O1234, S1200, T7, G43, H2; #4201 as #4001; G21.
        1.0,
        90.0,
        55.0,
        300.0,
        3.0,
        1234.0,
        1200.0,
        7.0,
        43.0,
        2.0,
        1.0,
        21.0,
        // Offset 2 (T code 2): length geometry in #11002 and #2202, radius in #13002, wear.
        l,
        l,
        t2.diameter / 2.0,
        t2.wear_length,
        7.0,
        10.0,
        // Length wear written and read back; the geometry unchanged.
        0.05,
        l,
    ];
    for (i, (g, w)) in got.iter().zip(&want).enumerate() {
        assert!((g - w).abs() < 1e-9, "#{}: {g}, want {w}", 101 + i);
    }
    // A written wear is in the tool data the next G43 takes, and said as an event.
    let mut g = gcode_source_in(
        "O1\nG10 L2 P1 Z-300.\nG43 H2 G00 Z0.\n#10002=1.\nG43 H2 G00 Z0.\nM30\n",
        Fanuc,
    );
    let zs: Vec<i64> = g
        .by_ref()
        .flat_map(|s| s.unwrap().blocks)
        .map(|b| b.end.xyz()[2])
        .collect();
    assert_eq!(zs.last().unwrap() - zs.first().unwrap(), 1000, "{zs:?}");
    assert!(g.take_events().iter().any(|e| matches!(e,
        novanc::gcode::Event::ToolOffsets { t: 2, wear_length, .. } if *wear_length == 1.0)));
    // A work offset written for the system in force acts at once (Fanuc), journaled as G10.
    assert_moves(
        &moves(
            "O1\nG10 L2 P1 X10.\nG00 X0\n#5221=20.\nG00 X0\nM30\n",
            Fanuc,
        )
        .unwrap(),
        &[('R', [10.0, 0.0, 0.0]), ('R', [20.0, 0.0, 0.0])],
    );
    // The LinuxCNC dialect reads its own parameters there, and has no #10001.
    assert_eq!(
        moves("G10 L2 P1 X10.\n#1=#5021\nG0 X#1\nM30\n", LinuxCnc).unwrap(),
        [('R', [10.0, 0.0, 0.0])]
    );
    assert_eq!(
        moves("#1=#10001\nM30\n", LinuxCnc).unwrap_err(),
        "1:4: parameter number 10001 is not 1 to 5602"
    );
}

#[test]
fn system_variables_novanc_lacks_are_refused_with_their_reason() {
    for (line, e) in [
        // No machine runs the program here (`values` reads it as `novanc translate` does).
        ("#1=#3001", "2:4: #3001 (the millisecond clock): the clocks are the machine's, and no machine runs the program here (novanc translate, the window's plot, the lines before a SEARCH point)"),
        ("#3002=0", "2:1: #3002 (the hour clock): the clocks are the machine's, and no machine runs the program here (novanc translate, the window's plot, the lines before a SEARCH point)"),
        ("#5081=1", "#5081 (the tool length offset) is read-only"),
        ("#1=#5084", "#5084 (the tool length offset of axis 4): this machine has the axes X, Y, Z"),
        ("#3901=0", "#3901: the part counter is set on the POS page (PARTS n, TARGET n), not by a program"),
        ("#4001=1", "#4001 (modal information) is read-only"),
        ("#5041=1", "#5041 (the work position) is read-only"),
        ("#1=#4012", "#4012: novanc keeps no such modal information (it has #4001 #4002 #4003 #4005 #4006 #4007 #4008 #4009 #4010 #4014 #4015 #4107 #4109 #4111 #4113 #4114 #4115 #4119 #4120)"),
        ("#1=#5004", "#5004 (the block end position of axis 4): this machine has the axes X, Y, Z"),
        ("#1=#9999", "#9999: novanc has no such variable (the Fanuc dialect reads #1 to #5602, and the tool offsets #10001 to #13999)"),
        ("#1=#10024", "#10024 (length wear of offset 24): T code 24 has no tool data in the tool file"),
        ("#12001=20.", "#12001 (radius wear): 20 mm is beyond the largest wear (10 mm either way)"),
        ("#13001=#0", "#13001 (radius geometry): a tool offset cannot be null"),
        ("G41 D1 G01 X50. F100.\n#1=#5001", "#5001 (the block end position) cannot be read with cutter radius compensation on"),
    ] {
        let src = format!("O1\n{line}\nM30\n");
        let got = values(&src, &[]).unwrap_err();
        assert!(got.ends_with(e), "{line}: {got}");
    }
    // Without a console there is no part counter.
    assert!(moves("O1\n#1=#3901\nM30\n", Fanuc).unwrap_err().ends_with(
        "#3901 (parts machined): there is no part counter here (the console's POS page keeps one)"
    ));
}

#[test]
fn a_tool_offset_written_by_a_program_is_journaled_and_the_part_counter_read() {
    let d = common::temp_dir("fanuc-offsets");
    let prog = d.join("WEAR.NC");
    std::fs::write(
        &prog,
        "O5000 (WEAR OF OFFSET 1 UP 0.01 A PART)\n#101=#3901\n#10001=#10001+0.01\nM30\n",
    )
    .unwrap();
    let state = d.join("state");
    let before = novanc::tooldata::sample_magazine()
        .tools
        .get(1)
        .unwrap()
        .wear_length;
    for run in 1..=2 {
        let mut c = common::reopen_in(&state, Fanuc);
        read_and_run(&mut c, &prog);
        assert!(!c.view().lamps.alarm, "{}", c.frame_text());
        // The parts machined before this run.
        assert_eq!(c.interp_state().params[101], f64::from(run - 1));
        let wear = c.magazine().tools.get(1).unwrap().wear_length;
        assert!(
            (wear - before - 0.01 * f64::from(run)).abs() < 1e-9,
            "run {run}: {wear}"
        );
    }
    let c = common::reopen_in(&state, Fanuc);
    let wear = c.magazine().tools.get(1).unwrap().wear_length;
    assert!(
        (wear - before - 0.02).abs() < 1e-9,
        "after a restart: {wear}"
    );
}

#[test]
fn adp_reads_an_argument_given_without_a_point_as_if_with_one() {
    // X10 is 0.010 mm as an argument (least increments), X10. is 10 mm: ADP gives 10 for
    // both; F is never in increments; a null argument stays null. M98 shares the locals.
    let src = "O1\nG65 P9 X10 Y10. F200 A5\nG65 P9 L0 X7\nM30\n\
               O9\nG0 X[ADP[#24]] Y[ADP[#25]] Z-[ADP[#9]/100]\nM98 P8\nM99\n\
               O8\nG0 X[ADP[#1]] Y#24 Z[ADP[#26] - 1]\nM99\n";
    assert_moves(
        &moves(src, Fanuc).unwrap(),
        &[('R', [10.0, 10.0, -2.0]), ('R', [5.0, 0.01, -1.0])],
    );
    // A G66 modal call's arguments too: Z5 is 0.005 mm as an argument, ADP gives 5.
    let g66 = "O1\nG66 P9 Z5\nG0 X1.\nG67\nM30\nO9\nG0 Z-[ADP[#26]]\nM99\n";
    let m = moves(g66, Fanuc).unwrap();
    assert_eq!(m.last().map(|x| x.1[2]), Some(-5.0), "{m:?}");
    assert_eq!(
        moves("O1\nG0 X[ADP[#100]]\nM30\n", Fanuc).unwrap_err(),
        "2:10: ADP takes a local variable: ADP[#1] to ADP[#33]"
    );
}

/// The final machine position `novanc run` printed, mm.
fn final_position(stdout: &str) -> [f64; 3] {
    let line = stdout
        .lines()
        .find_map(|l| l.strip_prefix("final position: "))
        .unwrap_or_else(|| panic!("no final position: {stdout}"));
    let v: Vec<f64> = line
        .split_whitespace()
        .filter_map(|w| w.parse().ok())
        .collect();
    [v[0], v[1], v[2]]
}

/// Fanuc's clocks in a run (`novanc run`, virtual time): a line that reads or sets #3001 or
/// #3002 waits until the pulse core has executed every block before it, and reads the core's
/// machine time. A dwell of 2 s reads 2000 ms and one of 36 s 0.01 h, each up to two NCBR
/// ticks (5 ms) more: the clocks block is reached at a tick, the machine waits for the reader
/// until the next, and the block after a dwell starts at the tick after its end. A WHILE on
/// #3001 waits one second of machine time (the line is read again, a new wait, each time
/// round). `novanc translate` refuses them with the reason.
#[test]
fn the_clocks_are_the_machine_s_when_it_has_reached_the_line() {
    let prog = "O1\n#3001=0\nG04 X2.\n#100=#3001\nG00 X[#100/100]\n\
                #3002=0\nG04 X36.\n#101=#3002\nG00 Y[#101*10000]\n\
                #3001=0\nWHILE [#3001 LT 1000] DO1\nEND1\nG00 Z[-#3001/100]\nM30\n";
    let (code, out, err, _) = common::novanc_on(&["run", "--dialect", "fanuc"], "t.nc", prog, &[]);
    assert_eq!(code, Some(0), "{err}");
    let [x, y, z] = final_position(&out);
    assert!((20.0..=20.1).contains(&x), "#100 = {} ms", x * 100.0);
    assert!((100.0..=100.03).contains(&y), "#101 = {} h", y / 10000.0);
    assert!(
        (-10.1..=-10.0).contains(&z),
        "#3001 after the loop: {} ms",
        -z * 100.0
    );
    let (code, _, err, _) =
        common::novanc_on(&["translate", "--dialect", "fanuc"], "t.nc", prog, &[]);
    assert_eq!(code, Some(1));
    assert!(err.contains("t.nc:2:1: #3001 (the millisecond clock): the clocks are the machine's, and no machine runs the program here"), "{err}");
}

/// #3001 counts all the time since power-on, #3002 only while the cycle-start lamp is lit (a
/// run going, not held); what a program set them to stays for the next run (they are the
/// machine's). At the console in virtual time: both set to 0 by MDI, 5 s idle, then a 10 s
/// feed move held for 3 s halfway: #3001 reads 18 s, #3002 10 s (and the few ticks each MDI
/// run lights the lamp).
#[test]
fn the_hour_clock_counts_only_while_a_run_goes() {
    let mut c = common::reopen_in(&common::temp_dir("fanuc-clocks"), Fanuc);
    common::mdi(&mut c, "#3001=0 #3002=0");
    c.handle(E::WaitMs(5000));
    c.handle(E::Op(OpMode::Mdi));
    common::type_line(&mut c, "G01 X100. F600.");
    c.handle(E::Start);
    c.handle(E::WaitMs(5000));
    c.handle(E::Stop);
    c.handle(E::WaitMs(3000));
    c.handle(E::Start);
    c.handle(E::Wait);
    common::mdi(&mut c, "#100=#3001 #101=#3002");
    assert!(!c.view().lamps.alarm, "{}", c.frame_text());
    let p = &c.interp_state().params;
    let (ms, h) = (p[100], p[101]);
    assert!((18_000.0..=18_100.0).contains(&ms), "#3001 = {ms}");
    assert!(
        (10_000.0..=10_100.0).contains(&(h * 3.6e6)),
        "#3002 = {h} h"
    );
}

/// #5081–#5083: the tool length offset in force along X, Y, Z, in program units (0 after G49).
#[test]
fn the_tool_length_offset_in_force_is_read_per_axis() {
    let mag = novanc::tooldata::sample_magazine();
    let l = mag.tools.get(2).unwrap().set_length;
    let got = values(
        "O1\nG43 H2\n#101=#5081 #102=#5082 #103=#5083\nG20\n#104=#5083\nG21 G49\n#105=#5083\nM30\n",
        &[101, 102, 103, 104, 105],
    )
    .unwrap();
    let want = [0.0, 0.0, l, l / 25.4, 0.0];
    for (i, (g, w)) in got.iter().zip(&want).enumerate() {
        assert!((g - w).abs() < 1e-9, "#{}: {g}, want {w}", 101 + i);
    }
}

/// RESET while reading waits for the machine's clocks: SINGLE BLOCK stops the run after the
/// rapid before the clock line (the translator has handed on the clocks block and waits);
/// RESET abandons the run and its wait, and the next run goes through to its end.
#[test]
fn reset_during_a_clock_wait_abandons_the_run_without_a_hang() {
    let mut c = common::reopen_in(&common::temp_dir("fanuc-clock-reset"), Fanuc);
    c.core().set_audit(true);
    let f = common::temp_dir("fanuc-clock-reset-prog").join("CLOCK.NC");
    std::fs::write(&f, "O1\nG00 X10.\n#100=#3001\nG00 Y[#100/1000]\nM30\n").unwrap();
    common::read_program(&mut c, f);
    common::one_block_reset_then_run(&mut c);
    assert!(!c.view().lamps.alarm, "{}", c.frame_text());
    assert!(c.interp_state().params[100] > 0.0);
}

// The second set (issue 24's "held-out set ... run the same way"): thirteen programs in the
// styles of shop programs and Fanuc's manuals, each with its moves worked out here by hand
// from the program's own numbers, and its listing kept in `tests/golden/fanuc/`.

/// The moves of `name` (a golden program) read in the Fanuc dialect, checked against `want`
/// (work coordinates of G54 at X0 Y0 Z`WZ`, each shifted to machine coordinates here), and its
/// listing against the golden one; the listing's exit code.
fn check_program(name: &str, want: &[(char, [f64; 3])]) -> i32 {
    let want: Vec<_> = want
        .iter()
        .map(|&(k, p)| (k, [p[0], p[1], p[2] + WZ]))
        .collect();
    assert_moves(
        &moves(&program(&format!("{name}.nc")), Fanuc).unwrap(),
        &want,
    );
    check_listing(name)
}

/// A rapid and a feed in work coordinates (G54 Z0 at `WZ`).
fn r(x: f64, y: f64, z: f64) -> (char, [f64; 3]) {
    ('R', [x, y, z])
}
fn f(x: f64, y: f64, z: f64) -> (char, [f64; 3]) {
    ('F', [x, y, z])
}

#[test]
fn held_a_bolt_hole_circle_macro_takes_its_defaults_from_null_arguments() {
    // O9010: I radius, J depth, H holes; A first angle (0), B step (360/H), C R plane (2.),
    // K feed (100.), X Y the centre (the position now). A hole: over it at the height the tool
    // is at, down to C, feed to J, up to C.
    let mut want = vec![r(150.0, 120.0, 20.0)];
    let mut z = 20.0;
    let mut circle =
        |want: &mut Vec<_>, c: [f64; 2], rad: f64, a0: f64, step: f64, n: u32, j: f64, rp: f64| {
            for k in 0..n {
                let a = (a0 + f64::from(k) * step).to_radians();
                let (x, y) = (c[0] + rad * a.cos(), c[1] + rad * a.sin());
                want.push(r(x, y, z));
                if z != rp {
                    want.push(r(x, y, rp));
                }
                want.push(f(x, y, j));
                want.push(r(x, y, rp));
                z = rp;
            }
        };
    circle(&mut want, [150.0, 120.0], 50.0, 90.0, 72.0, 5, -8.0, 3.0);
    want.push(r(400.0, 300.0, 3.0));
    circle(&mut want, [400.0, 300.0], 25.0, 0.0, 30.0, 4, -4.0, 2.0);
    want.push(r(425.0 - 25.0, 300.0 + 25.0, 20.0));
    assert_eq!(check_program("boltmac", &want), 0);
    // Without I: the macro's alarm 3001 at its line.
    let e = moves(&program("boltmac.nc").replace("I50. ", ""), Fanuc).unwrap_err();
    assert_eq!(e, "16:20: MACRO ALARM 3001: I RADIUS MISSING (#3000 = 1)");
}

#[test]
fn held_a_grid_of_holes_by_nested_while_loops() {
    let mut want = vec![r(0.0, 0.0, 10.0)];
    for row in 0..3 {
        for col in 0..4 {
            let (x, y) = (20.0 + 15.0 * f64::from(col), 30.0 + 10.0 * f64::from(row));
            want.push(r(x, y, if row + col == 0 { 10.0 } else { 1.0 }));
            if row + col == 0 {
                want.push(r(x, y, 1.0));
            }
            want.push(f(x, y, -3.0));
            want.push(r(x, y, 1.0));
        }
    }
    want.push(r(65.0, 50.0, 10.0));
    assert_eq!(check_program("grid", &want), 0);
}

#[test]
fn held_a_g66_modal_call_after_incremental_moves_keeps_the_caller_s_modes() {
    let mut want = vec![r(50.0, 50.0, 10.0)];
    let mut z = 10.0;
    for (x, y) in [(70.0, 50.0), (70.0, 70.0), (50.0, 70.0)] {
        // The move in G91, then the macro: spot to Z-2, a square of side 2 (G91), up to R5.
        want.push(r(x, y, z));
        want.push(f(x, y, -2.0));
        want.extend([
            f(x + 2.0, y, -2.0),
            f(x + 2.0, y + 2.0, -2.0),
            f(x, y + 2.0, -2.0),
            f(x, y, -2.0),
        ]);
        z = 5.0;
        want.push(r(x, y, z));
    }
    want.extend([r(50.0, 70.0, 10.0), r(0.0, 0.0, 10.0)]);
    assert_eq!(check_program("spot", &want), 0);
}

#[test]
fn held_a_part_family_by_a_computed_goto() {
    let src = program("family2.nc");
    for (part, len, depth) in [(1, 40.0, -1.0), (2, 60.0, -2.0), (3, 80.0, -3.0)] {
        let text = src.replace("#1=2 ", &format!("#1={part} "));
        let want = [
            r(10.0, 10.0, 5.0),
            f(10.0, 10.0, depth),
            f(10.0 + len, 10.0, depth),
            r(10.0 + len, 10.0, 5.0),
        ]
        .map(|(k, p)| (k, [p[0], p[1], p[2] + WZ]));
        assert_moves(&moves(&text, Fanuc).unwrap(), &want);
    }
    for bad in ["4", "0", "1.5"] {
        let text = src.replace("#1=2 ", &format!("#1={bad} "));
        assert_eq!(
            moves(&text, Fanuc).unwrap_err(),
            "10:5: MACRO ALARM 3009: PART NUMBER 1 TO 3 (#3000 = 9)",
            "part {bad}"
        );
    }
    assert_eq!(check_listing("family2"), 0);
}

#[test]
fn held_digits_engraved_by_subprograms_repeated_by_l_and_by_p_s_upper_digits() {
    // Each digit is drawn in G91 from where the last one ended, 8 mm on; the cut is at Z-0.2.
    let mut want = vec![r(10.0, 10.0, 2.0)];
    let mut x = 10.0;
    let cut = 2.0 - 2.2;
    let one = |want: &mut Vec<_>, x: &mut f64| {
        let c = *x + 3.0;
        want.extend([
            r(c, 10.0, 2.0),
            f(c, 10.0, cut),
            f(c, 20.0, cut),
            r(c, 20.0, 2.0),
            r(c, 10.0, 2.0),
        ]);
        *x += 8.0;
        want.push(r(*x, 10.0, 2.0));
    };
    for _ in 0..3 {
        one(&mut want, &mut x);
    }
    for _ in 0..2 {
        want.extend([
            f(x, 10.0, cut),
            f(x, 20.0, cut),
            f(x + 6.0, 20.0, cut),
            f(x + 6.0, 10.0, cut),
            f(x, 10.0, cut),
            r(x, 10.0, 2.0),
        ]);
        x += 8.0;
        want.push(r(x, 10.0, 2.0));
    }
    // M98 P21001: O1001 twice (Fanuc 0i: P's digits above the four of the number).
    for _ in 0..2 {
        one(&mut want, &mut x);
    }
    want.push(r(x, 10.0, 10.0));
    assert_eq!(check_program("engrave", &want), 0);
}

#[test]
fn held_a_part_counter_and_tool_life_count_by_3901_3902_and_500() {
    let src = program("counter.nc");
    let run = |src: &str, done: u64, target: u64| {
        let mut g = gcode_source_in(src, Fanuc).part_counter(done, target);
        let mut out = Vec::new();
        for s in g.by_ref() {
            for b in s.map_err(|e| e.to_string())?.blocks {
                out.push(b.end.xyz().map(|p| p as f64 / 1000.0));
            }
        }
        Ok::<_, String>((out, g.state().params[500]))
    };
    // 7 of 10 made, #500 vacant: it counts 1; the part is cut at X70 Y1.
    let (ends, kept) = run(&src, 7, 10).unwrap();
    assert_eq!(ends[0], [70.0, 1.0, WZ + 5.0]);
    assert_eq!(ends[1], [70.0, 1.0, WZ - 1.0]);
    assert_eq!(kept, 1.0);
    // No target (0): not checked.
    assert_eq!(run(&src, 12, 0).unwrap().1, 1.0);
    // The count reached, and the tool's life over after 25 parts: the alarms.
    assert_eq!(
        run(&src, 10, 10).unwrap_err(),
        "5:26: MACRO ALARM 3010: PART COUNT REACHED (#3000 = 10)"
    );
    let worn = src.replace("N10 IF", "#500=25\nN10 IF");
    assert_eq!(
        run(&worn, 1, 10).unwrap_err(),
        "9:22: MACRO ALARM 3011: TOOL 1 LIFE OVER (#3000 = 11)"
    );
    // novanc translate has no part counter: refused at the variable.
    assert_eq!(check_listing("counter"), 1);
}

#[test]
fn held_a_bad_argument_raises_its_alarm_after_the_moves_before_it() {
    let src = program("badarg.nc");
    let mut ends = Vec::new();
    let mut err = None;
    for s in gcode_source_in(&src, Fanuc) {
        match s {
            Ok(s) => ends.extend(s.blocks.iter().map(|b| b.end.xyz())),
            Err(e) => err = Some(e.to_string()),
        }
    }
    // The first call (R5.) moves; the second (R-5.) stops at its alarm, nothing after it.
    assert_eq!(
        ends.iter()
            .map(|p| p.map(|v| v as f64 / 1000.0))
            .collect::<Vec<_>>(),
        [[10.0, 10.0, WZ + 5.0], [15.0, 15.0, WZ + 5.0]]
    );
    assert_eq!(
        err.unwrap(),
        "11:20: MACRO ALARM 3002: R MUST BE ABOVE 0 (#3000 = 2)"
    );
    for (call, want) in [
        (
            "R5. H4.5",
            "12:27: MACRO ALARM 3003: H MUST BE WHOLE (#3000 = 3)",
        ),
        ("R5. H0", "13:36: MACRO ALARM 3004: H 1 TO 9 (#3000 = 4)"),
        ("H3", "10:21: MACRO ALARM 3001: R MISSING (#3000 = 1)"),
    ] {
        let text = src.replace("R-5. H4", call);
        assert_eq!(moves(&text, Fanuc).unwrap_err(), want, "{call}");
    }
    assert_eq!(check_listing("badarg"), 1);
}

#[test]
fn held_a_3006_stop_between_the_two_sides_of_a_part() {
    let src = program("turnover.nc");
    let want = [
        r(0.0, 0.0, 5.0),
        f(0.0, 0.0, -1.0),
        f(50.0, 0.0, -1.0),
        r(50.0, 0.0, 50.0),
        r(0.0, 150.0, 50.0),
        r(0.0, 0.0, 5.0),
        f(0.0, 0.0, -1.0),
        f(0.0, 50.0, -1.0),
        r(0.0, 50.0, 50.0),
    ];
    assert_eq!(check_program("turnover", &want), 0);
    let mut g = gcode_source_in(&src, Fanuc);
    let stop: Vec<_> = g
        .by_ref()
        .map(|s| s.unwrap())
        .filter(|s| s.line == 9)
        .flat_map(|s| s.blocks)
        .map(|b| b.m)
        .collect();
    assert_eq!(stop, [Some(0)]);
    assert!(g.take_events().iter().any(|e| matches!(e,
        novanc::gcode::Event::Message { text, .. } if text == "#3006 STOP 1: TURN THE PART OVER")));
}

#[test]
fn held_a_probing_macro_measures_the_stock_s_width_by_two_g31_skips() {
    // The stock is Y 200 to 600 (docs/gcode.md "Probing"); G54 is machine zero (Z too), so
    // these are machine coordinates. Each G31 block ends where it was written; reading goes
    // on from the skip point (#5062).
    let src = program("width.nc");
    let want = [
        ('R', [500.0, 650.0, -400.0]),
        ('R', [500.0, 650.0, -460.0]),
        ('F', [500.0, 550.0, -460.0]),
        ('R', [500.0, 650.0, -460.0]),
        ('R', [500.0, 650.0, -400.0]),
        ('R', [500.0, 150.0, -400.0]),
        ('R', [500.0, 150.0, -460.0]),
        ('F', [500.0, 250.0, -460.0]),
        ('R', [500.0, 150.0, -460.0]),
        ('R', [500.0, 150.0, -400.0]),
        // G54 Y0 moved onto the middle, (600 + 200) / 2.
        ('R', [500.0, 400.0, -400.0]),
    ];
    assert_moves(&moves(&src, Fanuc).unwrap(), &want);
    assert_eq!(check_listing("width"), 0);
    // Started where nothing is to touch: the macro's own alarm.
    let e = moves(&src.replace("X500. Y650.", "X900. Y650."), Fanuc).unwrap_err();
    assert_eq!(e, "8:25: MACRO ALARM 3001: NO Y+ FACE (#3000 = 1)");
}

#[test]
fn held_a_macro_reads_the_modal_information_and_puts_the_modes_back() {
    // G55 is 100 mm over G54 in X and Y: the zigzag in G55 G91 goes on from where the tool is.
    let want = [
        r(10.0, 10.0, 5.0),
        f(20.0, 10.0, 5.0),
        f(23.0, 13.0, 5.0),
        f(26.0, 10.0, 5.0),
        r(20.0, 10.0, 5.0),
        // After the macro: G01, G90, G54 and F300 again, so X30. feeds in G54.
        f(30.0, 10.0, 5.0),
        r(30.0, 10.0, 10.0),
    ];
    assert_eq!(check_program("modes", &want), 0);
    let feeds: Vec<_> = gcode_source_in(&program("modes.nc"), Fanuc)
        .flat_map(|s| s.unwrap().blocks)
        .filter(|b| b.motion == Motion::Linear)
        .map(|b| b.feed)
        .collect();
    assert_eq!(feeds, [300.0, 50.0, 50.0, 300.0]);
}

#[test]
fn held_fanuc_s_functions_and_numbers_with_and_without_a_point() {
    // G54 at X100 Y100. ROUND[2.5] 3, FIX[7.9] 7, FUP[7.1] 8; ATAN[1.]/[1.] 45, SQRT[16.] 4,
    // ABS[-3.5] 3.5; BIN[BCD[37]] 37, BCD[12] 18 (0x12), 17 MOD 5 2; #10=10 is 10 mm, while
    // Y10 is 0.010 mm and X1000 1 mm; AND, OR and XOR bit by bit: 10 AND 6 = 2, 10 XOR 3 = 9.
    let want = [
        ('R', [103.0, 107.0, WZ + 8.0]),
        ('R', [145.0, 104.0, WZ + 3.5]),
        ('R', [137.0, 118.0, WZ + 2.0]),
        ('R', [110.0, 100.01, WZ + 10.0]),
        ('R', [101.0, 110.0, WZ - 0.005]),
        ('R', [112.5, 100.5, WZ - 0.5]),
        ('R', [102.0, 101.0, WZ + 9.0]),
    ];
    assert_moves(&moves(&program("arith.nc"), Fanuc).unwrap(), &want);
    assert_eq!(check_listing("arith"), 0);
    assert_eq!(
        moves("O1\n#1=2.5 AND 1\nM30\n", Fanuc).unwrap_err(),
        "2:8: 2.5 AND 1: in the Fanuc dialect AND, OR and XOR work bit by bit on whole numbers 0 or above"
    );
    // LinuxCNC's AND stays logical.
    assert_moves(
        &moves("#1=[10 AND 6]\nG0 X#1\nM30\n", LinuxCnc).unwrap(),
        &[('R', [1.0, 0.0, 0.0])],
    );
}

#[test]
fn held_a_dnc_file_s_programs_call_each_other() {
    // O1000 calls O2000 twice (L2); each steps 30 in X and calls O9200 (G65, D2.), which pecks
    // by M98 P3000 twice from Z2. (a second G00 Z2. where the tool is makes no block).
    let mut want = vec![r(0.0, 0.0, 10.0)];
    for (i, x) in [30.0, 60.0].into_iter().enumerate() {
        want.push(r(x, 0.0, if i == 0 { 10.0 } else { 2.0 }));
        if i == 0 {
            want.push(r(x, 0.0, 2.0));
        }
        want.extend([f(x, 0.0, 1.0), f(x, 0.0, 0.0), r(x, 0.0, 2.0)]);
    }
    want.push(r(60.0, 0.0, 10.0));
    assert_eq!(check_program("dnc", &want), 0);
}

#[test]
fn held_a_tape_with_n_numbers_comments_block_delete_and_eob() {
    // Block delete off: the / blocks run.
    let want = [
        r(10.0, 10.0, 5.0),
        f(10.0, 10.0, -1.0),
        r(20.0, 10.0, -1.0),
        r(30.0, 10.0, -1.0),
        r(30.0, 20.0, -1.0),
    ];
    assert_eq!(check_program("tape", &want), 0);
    // Block delete on: they do not.
    let on = novanc::gcode::GcodeSource::new(
        program("tape.nc").into(),
        novanc::tooldata::sample_magazine(),
        novanc::settings::MachineSettings {
            dialect: Fanuc,
            ..Default::default()
        },
        novanc::block::MachineState::at([0, 0, 0]),
        novanc::gcode::WorkOffsets::default(),
        novanc::gcode::Switches {
            block_delete: true,
            ..Default::default()
        },
    );
    let ends: Vec<_> = on
        .flat_map(|s| s.unwrap().blocks)
        .filter(|b| b.motion == Motion::Rapid)
        .map(|b| b.end.xyz().map(|p| p as f64 / 1000.0))
        .collect();
    assert_eq!(
        ends,
        [
            [10.0, 10.0, WZ + 5.0],
            [20.0, 10.0, WZ + 5.0],
            [20.0, 20.0, WZ + 5.0]
        ]
    );
    // ';' ends a block: a second block after it on the line is refused, not dropped.
    assert_eq!(
        moves("O1\nG00 X1.;G00 X2.;\nM30;\n", Fanuc).unwrap_err(),
        "2:9: a block after ';' on the same line: ';' ends a block in the Fanuc dialect (EOB); put the next block on a line of its own"
    );
    // LinuxCNC's ';' is a comment to the end of the line, as before.
    assert_eq!(moves("G00 X1.;G00 X2.\nM30\n", LinuxCnc).unwrap().len(), 1);
}

#[test]
fn translate_and_run_with_state_read_a_stored_program_in_the_dialect_it_was_stored_in() {
    let d = common::temp_dir("fanuc-state-cli");
    let state = d.join("state");
    {
        let (mut s, _) = novanc::store::Stores::open(&state, 24).unwrap();
        // Stored before programs kept their dialect: none recorded.
        s.program_read("OLD.NGC", "G00 X10 Y6.\nM30\n").unwrap();
        s.set_dialect(Fanuc);
        s.program_read("FAMILY.NGC", &program("family.nc")).unwrap();
        s.set_dialect(LinuxCnc);
        s.program_read("ISO.NGC", "G00 X10 Y6.\nM30\n").unwrap();
    }
    let novanc = |args: &[&str]| {
        common::novanc_command()
            .args(args)
            .arg("--state")
            .arg(&state)
            .output()
            .unwrap()
    };
    let stdout = |o: &std::process::Output| String::from_utf8_lossy(&o.stdout).into_owned();
    // The Fanuc program is read in the Fanuc dialect whatever the command line says, as START
    // reads it.
    for dialect in [&[][..], &["--dialect", "linuxcnc"]] {
        let out = novanc(&[&["translate", "family.ngc"], dialect].concat());
        assert_eq!(out.status.code(), Some(0), "{out:?}");
        assert_eq!(stdout(&out), program("family.iso"));
        let out = novanc(&[&["run", "FAMILY.NGC"], dialect].concat());
        assert_eq!(out.status.code(), Some(0), "{out:?}");
    }
    // A program stored in LinuxCNC's dialect: X10 is 10 mm, even with --dialect fanuc.
    let out = novanc(&["translate", "ISO.NGC", "--dialect", "fanuc"]);
    assert!(stdout(&out).contains("G00 X10.000 Y6.000"), "{out:?}");
    // Without a recorded dialect, and for a file, the command line's (or the default).
    for (args, x) in [
        (
            &["translate", "OLD.NGC", "--dialect", "fanuc"][..],
            "X0.010",
        ),
        (&["translate", "OLD.NGC"][..], "X10.000"),
    ] {
        let out = novanc(args);
        assert!(stdout(&out).contains(x), "{args:?}: {out:?}");
    }
    let file = d.join("FILE.NC");
    std::fs::write(&file, "G00 X10 Y6.\nM30\n").unwrap();
    let out = novanc(&["translate", file.to_str().unwrap(), "--dialect", "fanuc"]);
    assert!(stdout(&out).contains("X0.010"), "{out:?}");
}

#[test]
fn the_hour_clock_is_kept_across_a_restart() {
    let state = common::temp_dir("fanuc-3002-kept").join("state");
    let mut seen = Vec::new();
    for _ in 0..3 {
        let mut c = common::reopen_in(&state, Fanuc);
        // 3.6 s with the lamp lit: 0.001 h a console session.
        common::mdi(&mut c, "G04 X3.6");
        common::mdi(&mut c, "#100=#3002");
        assert!(!c.view().lamps.alarm, "{}", c.frame_text());
        seen.push(c.interp_state().params[100] * 3.6e6);
    }
    // Each session counts on from what the last one kept (to the tick of each MDI line).
    for (i, ms) in seen.iter().enumerate() {
        let low = 3600.0 * (i + 1) as f64;
        assert!((low..low + 100.0).contains(ms), "{seen:?}");
    }
    // A program's setting is kept too: #3002=100. reads 100 h after a restart.
    let mut c = common::reopen_in(&state, Fanuc);
    common::mdi(&mut c, "#3002=100.");
    drop(c);
    let mut c = common::reopen_in(&state, Fanuc);
    common::mdi(&mut c, "#100=#3002");
    let h = c.interp_state().params[100];
    assert!((100.0..100.0 + 100.0 / 3.6e6).contains(&h), "{h}");
    drop(c);
    // In LinuxCNC's dialect #3002 is a parameter of its own, and not the clock kept.
    let mut c = common::reopen_in(&state, LinuxCnc);
    common::mdi(&mut c, "#100=#3002");
    assert_eq!(c.interp_state().params[100], 0.0);
}

/// What Fanuc CAM posts put around the cut (stop 48): the look-ahead switches G05.1 Q1 / Q0
/// (AI contour control), G05 P10000 / P0 (high-precision contour control) and G08 P1 / P0
/// (AI advanced preview) are read and move nothing (every block here ends at rest on its
/// programmed end); before, `G05.1 Q1` was taken for LinuxCNC's quadratic spline and refused
/// (`this motion needs at least one of X, Y and Z`), and G08 for the lathe's radius mode. A
/// value that is no such switch is refused at its word. LinuxCNC's G5.1 spline (with X Y I J)
/// stays readable in the dialect.
#[test]
fn the_look_ahead_switches_of_fanuc_posts_are_read() {
    let on = "G21 G90\nG05.1 Q1\nG08 P1\nG05 P10000\nG0 X10. Y10.\nG1 X20. F500.\nG05.1 Q0\nG08 P0\nG05 P0\nM30\n";
    assert_moves(
        &moves(on, Fanuc).unwrap(),
        &[('R', [10.0, 10.0, 0.0]), ('F', [20.0, 10.0, 0.0])],
    );
    // Fanuc 30i posts: nano smoothing, and AI contour control's precision level.
    assert!(moves("G05.1 Q2\nG05.1 Q1 R5\nG05.1 Q0\nM30\n", Fanuc).is_ok());
    assert_eq!(
        moves("G05.1 Q4\nM30\n", Fanuc).unwrap_err(),
        "1:7: G5.1 switches Fanuc's look-ahead with Q1 (AI contour control), Q2 (nano smoothing), Q3 (smooth tolerance control) or Q0 (off)"
    );
    assert_eq!(
        moves("G05.1 Q1 R11\nM30\n", Fanuc).unwrap_err(),
        "1:10: G5.1 R: AI contour control's precision level is a whole number 1 to 10"
    );
    assert_eq!(
        moves("G08 P2\nM30\n", Fanuc).unwrap_err(),
        "1:5: G8 switches Fanuc's look-ahead with P1 (on) or P0 (off)"
    );
    // LinuxCNC's quadratic spline, in either dialect.
    let spline = "G21 G90 G17\nG0 X0 Y0\nG5.1 X20. Y0 I10. J10. F500.\nM30\n";
    assert!(moves(spline, Fanuc).unwrap().len() > 2);
    assert!(moves("G05.1 Q1\nM30\n", LinuxCnc).is_err());
}

/// A Fanuc's G84 under G98 feeds out to R only, then rapids up to the initial level (its
/// manual's cycle); LinuxCNC's feeds out all the way to the clear level. Since stop 48 each
/// dialect does its own; before, the Fanuc dialect fed the tap out at its feed to the initial
/// level.
#[test]
fn a_fanuc_tap_feeds_out_to_r_then_rapids_to_the_initial_level() {
    let prog = "G21 G90 G17\nS300 M3\nG0 X10. Y10. Z-50.\nG98 G84 Z-110. R-98. F375.\nG80\nM30\n";
    let fanuc = moves(prog, Fanuc).unwrap();
    assert_moves(
        &fanuc,
        &[
            ('R', [10.0, 10.0, -50.0]),
            ('R', [10.0, 10.0, -98.0]),
            ('F', [10.0, 10.0, -110.0]),
            ('F', [10.0, 10.0, -98.0]),
            ('R', [10.0, 10.0, -50.0]),
        ],
    );
    let linuxcnc = moves(&prog.replace('.', ""), LinuxCnc).unwrap();
    assert_eq!(linuxcnc.last().unwrap(), &('F', [10.0, 10.0, -50.0]));
}

/// Fanuc's G10 L10–L13 set the tool offsets of memory C (stop 48): L10 the length geometry,
/// L11 its wear, L12 the radius geometry, L13 its wear, to R, or by R under G91. Before, the
/// dialect read them as LinuxCNC's L10/L11, whose R is a radius: `G10 L10 P2 R100.` made
/// T2 200 mm across and left its length.
#[test]
fn g10_l10_to_l13_set_fanuc_tool_offsets() {
    let mut g = gcode_source_in(
        "O1\nG10 L2 P1 Z-400.\nG10 L10 P2 R100.\nG10 L11 P2 R0.5\nG91 G10 L11 P2 R0.25\nG90\nG10 L12 P2 R4.\nG10 L13 P2 R-0.05\nG43 H2 G00 Z0.\nM30\n",
        Fanuc,
    );
    let zs: Vec<i64> = g
        .by_ref()
        .flat_map(|s| s.unwrap().blocks)
        .map(|b| b.end.xyz()[2])
        .collect();
    // The gauge line at program Z0: the work offset plus the length, geometry and wear.
    assert_eq!(zs.last(), Some(&(-400_000 + 100_750)), "{zs:?}");
    let last = g.take_events().into_iter().rev().find_map(|e| match e {
        novanc::gcode::Event::ToolOffsets {
            t: 2,
            length,
            diameter,
            wear_length,
            wear_diameter,
        } => Some((length, diameter, wear_length, wear_diameter)),
        _ => None,
    });
    assert_eq!(last, Some((100.0, 8.0, 0.75, -0.1)));
    assert_eq!(
        moves("G10 L12 P2 X1.\nM30\n", Fanuc).unwrap_err(),
        "1:12: G10 L12: X is not a word of a Fanuc tool offset (P the offset, R its value)"
    );
    assert_eq!(
        moves("G10 L10 P2\nM30\n", Fanuc).unwrap_err(),
        "1:1: G10 L10 needs R, the offset's value"
    );
}

/// Fanuc's codes that mean something else in LinuxCNC's language are read as Fanuc's or
/// refused with Fanuc's meaning (stop 48): G10 L20 (Fanuc's additional work systems, not
/// LinuxCNC's system from the current point, which would have moved G54), G10 L2 P0 and
/// #5201– (the external work offset), G53 (at rapid whatever the motion in force); G09 (exact
/// stop for one block) is read, every block ending at rest here anyway.
#[test]
fn fanuc_codes_that_linuxcnc_means_otherwise_keep_fanuc_s_meaning() {
    assert_eq!(
        moves("G10 L20 P1 X100. Y50. Z-200.\nM30\n", Fanuc).unwrap_err(),
        "1:5: G10 L20 sets Fanuc's additional work systems (G54.1 P1–P48): novanc has G54–G59.3, set with G10 L2 P1–P9"
    );
    assert_moves(
        &moves("G21 G90\nG09 G01 X10. F100.\nM30\n", Fanuc).unwrap(),
        &[('F', [10.0, 0.0, 0.0])],
    );
    // The external work offset (G10 L2 P0, #5201–#5206) shifts every system on a Fanuc;
    // LinuxCNC's P0 is the system in force, which it would have set instead.
    assert!(moves("G10 L2 P0 Z-0.5\nM30\n", Fanuc)
        .unwrap_err()
        .contains("G10 L2 P0: Fanuc's external work offset"));
    assert!(moves("#5203=-0.5\nM30\n", Fanuc)
        .unwrap_err()
        .contains("#5203: Fanuc's external work offset"));
    // G53 positions at rapid whatever the motion in force, and leaves it (one shot): after
    // G01 the retract is a rapid and the next X a feed; after G80 it is read.
    let g53 =
        "G21 G90\nG10 L2 P1 Z-450.\nG0 Z-10.\nG1 X10. F100.\nG53 Z0.\nX20.\nG80\nG53 Z0.\nM30\n";
    assert_moves(
        &moves(g53, Fanuc).unwrap(),
        &[
            ('R', [0.0, 0.0, -460.0]),
            ('F', [10.0, 0.0, -460.0]),
            ('R', [10.0, 0.0, 0.0]),
            ('F', [20.0, 0.0, 0.0]),
        ],
    );
    // Fanuc's own codes novanc does not read say what they are.
    for (code, what) in [
        ("G62", "automatic corner override"),
        ("G63", "tapping mode"),
        ("G37 Z0.", "tool length measurement"),
        ("G12 I10.", "circle cutting"),
        ("G16", "polar coordinate command"),
    ] {
        let e = moves(&format!("{code}\nM30\n"), Fanuc).unwrap_err();
        assert!(e.contains(what), "{code}: {e}");
    }
    // LinuxCNC's own reading is unchanged in its dialect: G53 takes the G01 in force.
    assert_eq!(
        moves(&g53.replace('.', "").replace("G80\nG53 Z0\n", ""), LinuxCnc).unwrap()[2].0,
        'F'
    );
    assert!(moves("G10 L2 P0 Z-0.5\nM30\n", LinuxCnc).is_ok());
    assert!(moves("G10 L20 P1 X0\nM30\n", LinuxCnc).is_ok());
    assert!(moves("G09 G01 X10 F100\nM30\n", LinuxCnc).is_err());
}

/// Fanuc's coordinate rotation (stop 48): G68 X Y R turns the program's points about X Y by
/// R degrees, moves, arcs and incremental moves alike, until G69; M30 and RESET end it.
/// Before, G68 was refused. Refused: under G91, without R, outside G17, with compensation on.
#[test]
fn g68_rotates_the_program_about_its_centre_until_g69() {
    let prog = "G21 G90 G17\nG10 L2 P1 X300. Y300.\nG0 X0 Y0\nG68 X0 Y0 R90.\nG1 X10. F500.\nG2 X20. Y10. R10.\nG91 G1 Y5.\nG90\nG69\nG1 X10. Y0\nM30\n";
    let got = moves(prog, Fanuc).unwrap();
    // (The arc, program X20 Y10 turned to X-10 Y20, is not listed; G91 Y5 goes on from its
    // end, turned: X-5.)
    assert_moves(
        &got,
        &[
            ('R', [300.0, 300.0, 0.0]),
            ('F', [300.0, 310.0, 0.0]),
            ('F', [285.0, 320.0, 0.0]),
            ('F', [310.0, 300.0, 0.0]),
        ],
    );
    // The centre defaults to where the tool stands.
    assert_moves(
        &moves(
            "G21 G90\nG10 L2 P1 X300. Y300.\nG0 X10. Y0\nG68 R180.\nG1 X20. F500.\nM30\n",
            Fanuc,
        )
        .unwrap(),
        &[('R', [310.0, 300.0, 0.0]), ('F', [300.0, 300.0, 0.0])],
    );
    for (src, why) in [
        ("G91 G68 X0 Y0 R45.\n", "G68 under G91"),
        ("G68 X0 Y0\n", "G68 needs R"),
        ("G18\nG68 X0 Y0 R45.\n", "G68 turns the XY plane only"),
        (
            "G41 D1\nG68 X0 Y0 R45.\n",
            "with cutter radius compensation on",
        ),
    ] {
        let e = moves(&format!("G21 G90 G17\n{src}M30\n"), Fanuc).unwrap_err();
        assert!(e.contains(why), "{src}: {e}");
    }
    assert!(moves("G68 X0 Y0 R45\nM30\n", LinuxCnc).is_err());
}

/// Fanuc's G76 fine boring (stop 48; before, refused as the lathe's threading): bore, dwell
/// P (ms), the spindle oriented (M19), the tool shifted off the wall by Q along +X, out at
/// rapid, shifted back, the spindle restarted; per hole, Q sticky like a peck. The spindle
/// must turn; Q is needed; G17 only.
#[test]
fn fanuc_g76_fine_boring_orients_and_shifts_off_the_wall_before_it_retracts() {
    let prog = "G21 G90 G17\nG10 L2 P1 X300. Y300.\nS500 M3\nG0 X10. Y10. Z-40.\nG98 G76 Z-70. R-48. Q0.5 P500 F100.\nG80\nM30\n";
    assert_moves(
        &moves(prog, Fanuc).unwrap(),
        &[
            ('R', [310.0, 310.0, -40.0]),
            ('R', [310.0, 310.0, -48.0]),
            ('F', [310.0, 310.0, -70.0]),
            ('R', [310.5, 310.0, -70.0]),
            ('R', [310.5, 310.0, -40.0]),
            ('R', [310.0, 310.0, -40.0]),
        ],
    );
    let blocks: Vec<_> = gcode_source_in(prog, Fanuc)
        .flat_map(|s| s.unwrap().blocks)
        .collect();
    let orient = blocks
        .iter()
        .position(|b| matches!(b.io, Some(novanc::block::Io::Orient { .. })));
    let shift = blocks.iter().position(|b| b.end.xyz()[0] == 310_500);
    assert!(
        orient.is_some() && orient < shift,
        "oriented before the shift"
    );
    let restart = blocks.iter().rposition(|b| b.m == Some(3));
    assert!(restart > shift, "the spindle restarted after the shift");
    for (src, why) in [
        (
            "M5\nG76 Z-70. R-48. Q0.5 F100.\n",
            "G76 needs the spindle turning",
        ),
        ("S500 M3\nG76 Z-70. R-48. F100.\n", "G76 needs Q, the shift"),
        ("S500 M3\nG18 G76 Z-70. R-48. Q1. F100.\n", "G17 only"),
        (
            "S500 M3\nG68 X0 Y0 R30.\nG76 Z-70. R-48. Q1. F100.\n",
            "G76 in a rotated coordinate system",
        ),
    ] {
        let e = moves(
            &format!("G21 G90 G17\nG10 L2 P1 X300. Y300.\n{src}M30\n"),
            Fanuc,
        )
        .unwrap_err();
        assert!(e.contains(why), "{src}: {e}");
    }
}

/// Fanuc 0i's K on a canned cycle is the number of repeats (stop 48), read as written without
/// a decimal point (`K3` is 3 holes, not 0.003 mm): under G91 a row of holes. Before, K was
/// refused there (`K word with no G2, G3 ... to use it`). K and L together are refused.
#[test]
fn fanuc_k_repeats_a_canned_cycle() {
    let prog = "G21 G90 G17\nG10 L2 P1 X300. Y300. Z-400.\nG0 X0 Y0 Z10.\nG91 G99 G81 X20. Z-5. R-8. K3 F100.\nG80 G90\nM30\n";
    let bottoms: Vec<[f64; 3]> = moves(prog, Fanuc)
        .unwrap()
        .into_iter()
        .filter(|(k, _)| *k == 'F')
        .map(|(_, p)| p)
        .collect();
    assert_eq!(bottoms.len(), 3, "{bottoms:?}");
    for (i, b) in bottoms.iter().enumerate() {
        assert!(
            (b[0] - (320.0 + 20.0 * i as f64)).abs() < 1e-6,
            "{bottoms:?}"
        );
        assert!((b[2] - (-403.0)).abs() < 1e-6, "{bottoms:?}");
    }
    assert_eq!(
        moves("G21 G90\nG81 X0 Z-5. R2. K2 L2 F100.\nM30\n", Fanuc).unwrap_err(),
        "2:20: G81: K and L both give the number of repeats: give one"
    );
    // LinuxCNC's K is no repeat count.
    assert!(moves("G21 G90\nG81 X0 Z-5 R2 K2 F100\nM30\n", LinuxCnc).is_err());
}
