//! The lathe's programs read through the one G-code reader's flow and parameters
//! (docs/lathe-gcode.md "One reader, two dialects"): O-word subroutines, loops and named
//! parameters (LinuxCNC's dialect), Fanuc's macro calls, WHILE and IF/GOTO (a channel's
//! `dialect fanuc`), the bound on the lines a program executes, and the description's
//! `dialect` line per channel.

mod common;

use novanc::block::{Block, FeedMode, Motion, Statement};
use novanc::lathe::desc::{parse, LatheDesc, MachineDesc, CITIZEN};
use novanc::lathe::gcode::{read_program, read_program_in, Parts, ReadOptions};
use novanc::settings::Dialect;
use novanc::store::lathe::{Counter, LatheStore, Program};

/// The Citizen, its description's first channel given `line` (`dialect fanuc`).
fn citizen_with(line: &str) -> Result<LatheDesc, String> {
    let text = CITIZEN.replacen(
        "channel SYSTEM-1\n",
        &format!("channel SYSTEM-1\n{line}\n"),
        1,
    );
    match parse(&text)? {
        MachineDesc::Lathe(d) => Ok(d),
        MachineDesc::Mill(_) => Err("a mill".into()),
    }
}

fn read(text: &str, desc: &LatheDesc) -> Vec<Statement> {
    match read_program(text, desc, 0, &ReadOptions::default()) {
        Ok(p) => p,
        Err(e) => panic!("{e}\n{text}"),
    }
}

/// The blocks without their places in the program (sequence and line), which differ between
/// a program and its flat form.
fn unplaced(p: Vec<Statement>) -> Vec<Block> {
    p.into_iter()
        .flat_map(|s| s.blocks)
        .map(|b| Block {
            seq: 0,
            stmt: 0,
            ..b
        })
        .collect()
}

#[test]
fn an_oword_subroutine_a_loop_and_named_parameters_move_as_the_flat_program() {
    let desc = LatheDesc::citizen();
    let program = "\
o<groove> sub
  #<bottom> = #1
  G1 X#<bottom> F50
  G0 X30
o<groove> endsub
T0101 M3 S1000
G0 X30 Z-5
o<groove> call [20]
G0 Z-10
o<groove> call [18]
#<z> = -15
G0 Z#<z>
o100 repeat [2]
  #<z> = [#<z> - 2]
  G0 Z#<z>
o100 endrepeat
M30
";
    let flat = "\
T0101 M3 S1000
G0 X30 Z-5
G1 X20 F50
G0 X30
G0 Z-10
G1 X18 F50
G0 X30
G0 Z-15
G0 Z-17
G0 Z-19
M30
";
    let a = unplaced(read(program, &desc));
    let b = unplaced(read(flat, &desc));
    assert!(b.len() >= 10, "{b:?}");
    assert_eq!(a, b);
}

#[test]
fn a_runaway_loop_on_the_lathe_is_refused_at_its_line() {
    let desc = LatheDesc::citizen();
    // Three lines a turn: the 1,000,001st line executed is line 2.
    let e = read_program(
        "o1 while [1]\nG0 X20\no1 endwhile\nM30\n",
        &desc,
        0,
        &ReadOptions::default(),
    )
    .err()
    .map(|e| e.to_string());
    assert_eq!(
        e.as_deref(),
        Some("2:1: the program executes more than 1000000 lines, counting each line of a loop or subroutine each time it runs: refused")
    );
    // And in Fanuc's dialect: four lines a turn, the 1,000,001st is line 2 again.
    let e = read_program_in(
        "#1 = 0\nWHILE [#1 GE 0] DO1\n#1 = #1 + 1\nEND1\nM30\n",
        &desc,
        0,
        &ReadOptions::default(),
        Some(Dialect::Fanuc),
    )
    .err()
    .map(|e| e.to_string());
    assert!(
        e.as_deref()
            .is_some_and(|e| e.starts_with("2:1: the program executes more than 1000000 lines")),
        "{e:?}"
    );
}

/// A program's moves in brief, as the `.moves` golden listings write them by hand: R rapid, F
/// feed (" per rev" under G95/G99), T a thread pass with its lead; X a radius, Z, mm.
fn moves(p: &[Statement]) -> Vec<String> {
    p.iter()
        .flat_map(|s| &s.blocks)
        .filter_map(|b| {
            let (k, tail) = match (b.motion, b.thread) {
                (Motion::Rapid, _) => ('R', String::new()),
                (Motion::Linear, Some(lead)) => ('T', format!(" lead {lead:.3}")),
                (Motion::Linear, None) if b.feed_mode == FeedMode::PerRev => {
                    ('F', " per rev".to_string())
                }
                (Motion::Linear, None) => ('F', String::new()),
                _ => return None,
            };
            Some(format!(
                "{k} X{:.3} Z{:.3}{tail}",
                b.end[0] as f64 / 1000.0,
                b.end[2] as f64 / 1000.0
            ))
        })
        .collect()
}

/// The golden listing `tests/golden/lathe/NAME.moves` (its lines without the comments) and
/// the program `NAME.ngc` it was worked out for.
fn golden(name: &str) -> (String, Vec<String>) {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/golden/lathe");
    let program = std::fs::read_to_string(format!("{dir}/{name}.ngc")).unwrap_or_default();
    let want = std::fs::read_to_string(format!("{dir}/{name}.moves"))
        .unwrap_or_default()
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .map(str::to_string)
        .collect();
    (program, want)
}

#[test]
fn a_fanuc_macro_program_with_g65_while_and_if_goto_moves_as_worked_by_hand() {
    let (program, want) = golden("fanuc_macro");
    assert_eq!(want.len(), 13, "the hand-worked moves are missing");
    // The program's F50. is per minute, as the moves were worked out; a Fanuc channel powers
    // on in G95 unless its description says `feed per-minute`.
    let desc = match citizen_with("dialect fanuc\nfeed per-minute") {
        Ok(d) => d,
        Err(e) => panic!("{e}"),
    };
    assert_eq!(desc.channels[0].dialect, Some(Dialect::Fanuc));
    assert_eq!(moves(&read(&program, &desc)), want);
    // The same channel without the line reads LinuxCNC's dialect, which has no GOTO.
    let e = read_program(&program, &LatheDesc::citizen(), 0, &ReadOptions::default());
    assert!(e.is_err());
    // A call without its B: the macro's #3000 alarm, at its line, with its number.
    let no_b = program.replace(" B20.", "");
    let e = read_program(&no_b, &desc, 0, &ReadOptions::default())
        .err()
        .map(|e| e.to_string());
    assert_eq!(
        e.as_deref(),
        Some("18:1: MACRO ALARM 3001: NO BOTTOM DIAMETER (#3000 = 1)")
    );
}

#[test]
fn fanucs_two_block_g76_cuts_an_m20_thread_as_worked_by_hand() {
    let (program, want) = golden("fanuc_g76");
    assert_eq!(want.len(), 36, "the hand-worked moves are missing");
    let desc = match citizen_with("dialect fanuc") {
        Ok(d) => d,
        Err(e) => panic!("{e}"),
    };
    assert_eq!(moves(&read(&program, &desc)), want);
    // The same passes in G code system A: G76 is the same in both.
    let desc = match citizen_with("dialect fanuc\ngcode system A") {
        Ok(d) => d,
        Err(e) => panic!("{e}"),
    };
    assert_eq!(moves(&read(&program, &desc)), want);
}

/// G76's one-block form (Fanuc's Series 15 format, which a Haas writes: `G76 X Z K D F A`),
/// and M23/M24, the chamfer out of the thread on and off: each the same passes as the
/// two-block form that says the same.
#[test]
fn g76s_one_block_form_and_m24_cut_as_the_two_block_form_says() {
    let desc = match citizen_with("dialect fanuc") {
        Ok(d) => d,
        Err(e) => panic!("{e}"),
    };
    let run = |text: &str| {
        moves(&read(
            &format!("T0101\nG97 S800 M3\nG0 X24. Z5.\n{text}M30\n"),
            &desc,
        ))
    };
    let two = run("G76 P010060 Q150 R0.05\nG76 X18.16 Z-20. P920 Q350 F1.5\n");
    assert!(two.len() > 20, "{two:?}");
    // K the height and D the first cut as lengths, A the angle; the rest the first block's.
    let one = run("G76 P010060 Q150 R0.05\nG76 X18.16 Z-20. K0.92 D0.35 A60 F1.5\n");
    assert_eq!(one, two);
    // Without a first block: one finishing pass, no least cut, no allowance, the angle A's.
    assert_eq!(
        run("G76 X18.16 Z-20. K0.92 D0.35 A60 F1.5\n"),
        run("G76 P010060 Q0 R0\nG76 X18.16 Z-20. P920 Q350 F1.5\n")
    );
    // M24: the chamfer the first block asks (r = 10, one lead) is left out until M23.
    let chamfered = run("G76 P011060 Q150 R0.05\nG76 X18.16 Z-20. P920 Q350 F1.5\n");
    assert_ne!(chamfered, two);
    assert_eq!(
        run("M24\nG76 P011060 Q150 R0.05\nG76 X18.16 Z-20. P920 Q350 F1.5\n"),
        two
    );
    assert_eq!(
        run("M24\nM23\nG76 P011060 Q150 R0.05\nG76 X18.16 Z-20. P920 Q350 F1.5\n"),
        chamfered
    );
    // Refused at their place, each with why.
    let pre = "T0101\nG97 S800 M3\nG0 X24. Z5.\n";
    for (text, want) in [
        (
            "G76 X18.16 Z-20. K0.92 D0.35 Q90 F1.5\n",
            "4:30: G76 Q in the one-block form is the thread's start angle",
        ),
        (
            "G76 X18.16 Z-20. K0.92 D0.35 P2 F1.5\n",
            "4:30: G76 P2: the way of cutting",
        ),
        (
            "G76 X18.16 Z-20. K0.92 D0.35 A90 F1.5\n",
            "4:30: G76 A90: the tool's angle, whole degrees 0 to 80",
        ),
        (
            "G76 X18.16 Z-20. K0.92 D0.35 R0.1 F1.5\n",
            "4:30: G76 R beside K or D",
        ),
        (
            "G76 X18.16 Z-20. D0.35 F1.5\n",
            "4:1: G76 (one-block form) needs K",
        ),
    ] {
        let e = read_program(&format!("{pre}{text}"), &desc, 0, &ReadOptions::default())
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default();
        assert!(e.starts_with(want), "{text}: {e}");
    }
    let e = read_program("M24\n", &LatheDesc::citizen(), 0, &ReadOptions::default())
        .err()
        .map(|e| e.to_string());
    assert!(
        e.as_deref()
            .is_some_and(|e| e.starts_with("1:1: M24: the thread chamfer on and off")),
        "{e:?}"
    );
}

#[test]
fn a_system_a_program_turns_faces_and_threads_as_worked_by_hand() {
    let (program, want) = golden("fanuc_system_a");
    assert_eq!(want.len(), 32, "the hand-worked moves are missing");
    let desc = match citizen_with("dialect fanuc\ngcode system A") {
        Ok(d) => d,
        Err(e) => panic!("{e}"),
    };
    assert!(desc.channels[0].system_a);
    let p = read(&program, &desc);
    assert_eq!(moves(&p), want);
    // G50 S3000 is the limit G96 S150 runs under (every block under G96 carries it), as
    // LinuxCNC's D.
    let css: Vec<_> = p
        .iter()
        .flat_map(|s| &s.blocks)
        .filter_map(|b| b.css)
        .collect();
    assert!(!css.is_empty());
    assert!(
        css.iter()
            .all(|c| (c.m_per_min, c.limit_rpm) == (150.0, 3000.0)),
        "{css:?}"
    );
    // In system B (the default) the same program is refused at its first system A code.
    let b = match citizen_with("dialect fanuc") {
        Ok(d) => d,
        Err(e) => panic!("{e}"),
    };
    let e = read_program(&program, &b, 0, &ReadOptions::default())
        .err()
        .map(|e| e.to_string());
    assert!(
        e.as_deref()
            .is_some_and(|e| e.starts_with("3:4: ") && e.contains("G50")),
        "{e:?}"
    );
}

#[test]
fn system_a_g50_x_z_makes_where_the_tool_stands_that_point() {
    // F100. per minute (G98 at power-on, by the description).
    let desc = match citizen_with("dialect fanuc\ngcode system A\nfeed per-minute") {
        Ok(d) => d,
        Err(e) => panic!("{e}"),
    };
    // By hand (X a radius): the tool stands at X30 Z50 when G50 X100. Z100. makes that point
    // X100 (radius 50) Z100, so the program's zero lies at X30 - 50 = -20, Z50 - 100 = -50:
    // X60. Z90. is at -20 + 30 = 10, Z -50 + 90 = 40; U and W are increments as before; and
    // X100. Z100. is where G50 was given.
    let p = read(
        "G0 X60. Z50.\nG50 X100. Z100.\nG0 X60. Z90.\nG1 U-10. W-5. F100.\nG0 X100. Z100.\n",
        &desc,
    );
    assert_eq!(
        moves(&p),
        [
            "R X30.000 Z50.000",
            "R X10.000 Z40.000",
            "F X5.000 Z35.000",
            "R X30.000 Z50.000"
        ]
    );
    // G50 on its own line moves nothing and gives no block.
    assert!(p.iter().all(|s| s.line != 2));
}

#[test]
fn fanucs_g71_and_g70_read_q_as_a_sequence_number() {
    // Q is a length elsewhere in Fanuc's dialect (Q20 is 0.020 mm), but G71's and G70's Q
    // names the profile's last line, N20: the same blocks as LinuxCNC's dialect reads.
    let program = "T0101 M3 S1000\nG0 X40. Z2.\nG71 U1. R0.5\nG71 P10 Q20 U0.4 W0.1 F100.\nN10 G0 X20.\nG1 Z-10.\nN20 G1 X40. Z-20.\nG70 P10 Q20\nM30\n";
    let want = unplaced(read(program, &LatheDesc::citizen()));
    // Both powered on per minute, as LinuxCNC's dialect does (F100. per minute).
    for line in [
        "dialect fanuc\nfeed per-minute",
        "dialect fanuc\ngcode system A\nfeed per-minute",
    ] {
        let desc = match citizen_with(line) {
            Ok(d) => d,
            Err(e) => panic!("{e}"),
        };
        assert_eq!(unplaced(read(program, &desc)), want, "{line}");
    }
}

#[test]
fn gcode_system_a_is_a_fanuc_channels_line() {
    // System B is the default: no channel of the Citizen reads system A.
    assert!(LatheDesc::citizen().channels.iter().all(|c| !c.system_a));
    // LinuxCNC's lathe has system B only: system A without Fanuc's dialect is refused at
    // its line (the Citizen's channel 1 starts on line 13, its own line is 14).
    let e = citizen_with("gcode system A").err();
    assert_eq!(
        e.as_deref(),
        Some("14: gcode system A is Fanuc's G code system: give 'dialect fanuc' in this channel or before the channels (LinuxCNC's lathe reads system B only)")
    );
    assert!(citizen_with("dialect linuxcnc\ngcode system A").is_err());
    assert!(citizen_with("gcode system B").is_ok_and(|d| !d.channels[0].system_a));
    // The machine's dialect line counts for the channel.
    let text = CITIZEN.replacen(
        "channel SYSTEM-1\n",
        "dialect fanuc\nchannel SYSTEM-1\ngcode system a\n",
        1,
    );
    let Ok(MachineDesc::Lathe(d)) = parse(&text) else {
        panic!("{:?}", parse(&text));
    };
    assert_eq!(
        d.channels.iter().map(|c| c.system_a).collect::<Vec<_>>(),
        [true, false, false]
    );
    for (line, want) in [
        (
            "dialect fanuc\ngcode system A\ngcode system B",
            "16: the gcode system is given twice in this channel",
        ),
        (
            "gcode system C",
            "14: gcode takes system A or system B (Fanuc's lathe G code systems)",
        ),
        (
            "gcode A",
            "14: gcode takes system A or system B (Fanuc's lathe G code systems)",
        ),
    ] {
        assert_eq!(citizen_with(line).err().as_deref(), Some(want), "{line}");
    }
    let before = CITIZEN.replacen(
        "channel SYSTEM-1\n",
        "gcode system A\nchannel SYSTEM-1\n",
        1,
    );
    assert_eq!(
        parse(&before).err().as_deref(),
        Some("13: gcode system: a lathe channel's line (write 'channel NAME' first)")
    );
    // A program kept in LinuxCNC's dialect reads system B on a system A channel.
    let a = match citizen_with("dialect fanuc\ngcode system A") {
        Ok(d) => d,
        Err(e) => panic!("{e}"),
    };
    let p = read_program_in(
        "G91 G0 U-2\n",
        &a,
        0,
        &ReadOptions::default(),
        Some(Dialect::LinuxCnc),
    );
    assert!(p.is_ok(), "{p:?}");
}

#[test]
fn the_description_gives_each_channel_its_dialect() {
    // A line before the channels is the machine's; a channel's own line says last.
    let text = CITIZEN
        .replacen("channel SYSTEM-1\n", "dialect fanuc\nchannel SYSTEM-1\n", 1)
        .replacen(
            "channel SYSTEM-2\n",
            "channel SYSTEM-2\ndialect linuxcnc\n",
            1,
        );
    let Ok(MachineDesc::Lathe(d)) = parse(&text) else {
        panic!("{:?}", parse(&text));
    };
    let got: Vec<_> = d.channels.iter().map(|c| c.dialect).collect();
    assert_eq!(
        got,
        [
            Some(Dialect::Fanuc),
            Some(Dialect::LinuxCnc),
            Some(Dialect::Fanuc)
        ]
    );
    // Without a line, none is said (the console's --dialect, else LinuxCNC's).
    assert!(LatheDesc::citizen()
        .channels
        .iter()
        .all(|c| c.dialect.is_none()));
    let twice = CITIZEN.replacen(
        "channel SYSTEM-1\n",
        "channel SYSTEM-1\ndialect fanuc\ndialect fanuc\n",
        1,
    );
    assert_eq!(
        parse(&twice).err().as_deref(),
        Some("15: the dialect is given twice in this channel")
    );
}

#[test]
fn parameters_that_report_the_mills_state_are_refused_on_the_lathe() {
    let desc = LatheDesc::citizen();
    let e = |text: &str, d: Option<Dialect>| {
        read_program_in(text, &desc, 0, &ReadOptions::default(), d)
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default()
    };
    // What the lathe keeps is read (docs/lathe-gcode.md "System variables"); the rest is
    // the mill's: its G92 offsets, its Y, its machine position.
    assert!(e("G0 X#5211\n", None).starts_with("1:5: #5211: parameters from #5000"));
    assert!(e("#1 = #<_y>\n", None).contains("#<_y> reports the mill's interpreter state"));
    assert!(e("#1 = #5021\n", Some(Dialect::Fanuc))
        .starts_with("1:6: #5021: the lathe keeps no such system variable"));
    assert!(e("#2001 = 1\n", Some(Dialect::Fanuc)).starts_with("1:1: #2001"));
}

#[test]
fn fanucs_least_increment_follows_g20_and_g21() {
    // X and Z without a point: 0.001 mm under G21, 0.0001 inch under G20 (the lathe's G20
    // takes X on the diameter, so X10000 is a radius of 0.5 inch).
    let p = read_program_in(
        "G0 X20000 Z2000\nG20\nG0 X10000 Z1000\nG21\nG0 X30000\n",
        &LatheDesc::citizen(),
        0,
        &ReadOptions::default(),
        Some(Dialect::Fanuc),
    );
    let ends: Vec<[i64; 2]> = p
        .unwrap_or_else(|e| panic!("{e}"))
        .iter()
        .flat_map(|s| &s.blocks)
        .map(|b| [b.end[0], b.end[2]])
        .collect();
    assert_eq!(ends, [[10_000, 2_000], [12_700, 2_540], [15_000, 2_540]]);
}

#[test]
fn a_lathe_program_keeps_the_dialect_it_was_stored_in() {
    let state = common::temp_dir("lathe-reader-dialect");
    let desc = LatheDesc::citizen();
    let p = Program {
        name: "O1000.NGC".into(),
        text: "G65 P9100 A1.\nM30\n".into(),
        dialect: Some(Dialect::Fanuc),
    };
    match LatheStore::open(&state, &desc) {
        Ok(mut o) => o
            .store
            .save_program(0, &p)
            .unwrap_or_else(|e| panic!("{e}")),
        Err(e) => panic!("{e}"),
    }
    let o = LatheStore::open(&state, &desc).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(o.programs[0], p);
    // The samples (and programs stored before) say none: the channel's at each run.
    assert_eq!(o.programs[1].dialect, None);
}

#[test]
fn start_reads_a_stored_program_in_the_dialect_it_was_stored_in() {
    use novanc::lathe::console::LatheConsole;
    use novanc::panel_model::PanelEvent;
    let fanuc = "#1 = 0\nWHILE [#1 LT 2] DO1\nG0 X[30. - #1] Z2.\n#1 = #1 + 1\nEND1\nM30\n";
    // The same text stored without a dialect (before programs kept theirs) and with Fanuc's,
    // on the Citizen whose description says none: LinuxCNC's for the channel.
    for (dialect, starts) in [(None, false), (Some(Dialect::Fanuc), true)] {
        let state = common::temp_dir("lathe-reader-start-dialect");
        let desc = LatheDesc::citizen();
        let p = Program {
            name: "O1000.NGC".into(),
            text: fanuc.into(),
            dialect,
        };
        match LatheStore::open(&state, &desc) {
            Ok(mut o) => o
                .store
                .save_program(0, &p)
                .unwrap_or_else(|e| panic!("{e}")),
            Err(e) => panic!("{e}"),
        }
        let (mut c, _) =
            LatheConsole::open(desc, &state, 20, 160, None).unwrap_or_else(|e| panic!("{e}"));
        c.handle(PanelEvent::Start);
        let m = c.message().to_string();
        if starts {
            assert_eq!(m, "cycle start", "{dialect:?}");
        } else {
            assert!(m.starts_with("CH1 O1000.NGC:2:"), "{m}");
        }
        c.handle(PanelEvent::EStop);
    }
}

#[test]
fn dialect_on_the_command_line_is_the_default_of_the_channels_that_say_none() {
    use novanc::cli::args::{take_machine, Machine};
    let path = common::temp_path("lathe-reader-dialect.machine");
    let text = CITIZEN.replacen(
        "channel SYSTEM-2\n",
        "channel SYSTEM-2\ndialect linuxcnc\n",
        1,
    );
    std::fs::write(&path, text).unwrap_or_else(|e| panic!("{e}"));
    let argv: Vec<String> = [
        "--machine",
        path.to_str().unwrap_or(""),
        "--dialect",
        "fanuc",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    match take_machine(&argv) {
        Ok((Machine::Lathe(d), rest)) => {
            assert!(rest.is_empty());
            let got: Vec<_> = d.channels.iter().map(|c| c.dialect).collect();
            assert_eq!(
                got,
                [
                    Some(Dialect::Fanuc),
                    Some(Dialect::LinuxCnc),
                    Some(Dialect::Fanuc)
                ]
            );
        }
        other => panic!("{other:?}"),
    }
}

/// The Citizen with a tool 4 on channel 1's tool post whose offsets are X 0.02 (radius) and
/// Z -0.01, nose radius 0.5 mm, tip 2.
fn citizen_with_offsets() -> LatheDesc {
    citizen_with("tool 4 radius 0.5 tip 2 offset 0.02 -0.01").unwrap_or_else(|e| panic!("{e}"))
}

/// The end points, pulses [X radius, Z], of the moves a program makes on channel 1.
fn move_ends(text: &str, desc: &LatheDesc, dialect: Dialect) -> Vec<[i64; 2]> {
    match read_program_in(text, desc, 0, &ReadOptions::default(), Some(dialect)) {
        Ok(p) => p
            .iter()
            .flat_map(|s| &s.blocks)
            .filter(|b| matches!(b.motion, Motion::Rapid | Motion::Linear))
            .map(|b| [b.end[0], b.end[2]])
            .collect(),
        Err(e) => panic!("{e}\n{text}"),
    }
}

/// What a program's `(abort, ...)` says: the values it read, or the refusal before it.
fn said(text: &str, desc: &LatheDesc, dialect: Dialect) -> String {
    match read_program_in(text, desc, 0, &ReadOptions::default(), Some(dialect)) {
        Ok(_) => "read without a refusal".into(),
        Err(e) => e.to_string(),
    }
}

#[test]
fn a_fanuc_lathe_macro_moves_from_the_block_end_position_modes_and_tool_offsets() {
    // A gauging-style macro: it retracts from where the last block ended (#5001 X on the
    // diameter, #5002 Z), checks the modes it relies on (#4001, #4005, #4120; a wrong one
    // jumps over every move after it), adds the X wear (#2004, on the diameter), and reads
    // X on the radius after G8.
    let program = "\
O0001
T0404 M3 S1000
G0 X40. Z5.
G95 G1 X30. F0.2
#1 = #5001
#2 = #5002
IF [#4001 NE 1] GOTO 90
IF [#4005 NE 95] GOTO 90
IF [#4120 NE 404] GOTO 90
G0 Z[#5002 + 2.]
X[#1 + 10. + #2004]
G#4001 Z[#2 - 1.]
G8
G0 X[#5001 + 1.]
G7
G1 Z[#5002 + #2104 * 100.]
N90 M30
";
    // Worked by hand: the tool's offsets are added to every programmed point (X 0.020 mm on
    // the radius, Z -0.010 mm), pulses of 0.001 mm.
    // G0 X40 Z5: r 20 → 20.020; Z 5 → 4.990.  G1 X30: r 15.020.
    // #1 = 30, #2 = 5.  G0 Z7: 6.990.  X 30 + 10 + 0.04 = 40.04: r 20.02 → 20.040.
    // G0 (#4001 is 0 now) Z4: 3.990.  G8: #5001 = 20.02 (radius), X 21.02 → 21.040.
    // G7, G1 Z 4 + (-0.01 × 100) = 3: 2.990.
    assert_eq!(
        move_ends(program, &citizen_with_offsets(), Dialect::Fanuc),
        [
            [20_020, 4_990],
            [15_020, 4_990],
            [15_020, 6_990],
            [20_040, 6_990],
            [20_040, 3_990],
            [21_040, 3_990],
            [21_040, 2_990],
        ]
    );
}

#[test]
fn the_lathes_system_variables_read_the_tool_offsets_modes_and_positions() {
    let desc = citizen_with_offsets();
    // Fanuc 0i-TF's numbers, in inches after G20 (X on the diameter); #4005 is 95, the feed
    // per revolution a Fanuc channel powers on in.
    let fanuc = "\
T0404 M3 S1000
G0 X30. Z2.
G20
#1=#5001 #2=#5002 #3=#2004 #4=#2104 #5=#2904 #6=#2304 #7=#10004 #8=#11004 #9=#12004
#10=#13004 #11=#2704 #12=#2804 #13=#2204 #14=#4006 #15=#4002 #16=#4003 #17=#4007
#18=#4016 #19=#4120 #20=#4119 #21=#4201 #22=#4113 #23=#4109 #24=#4005
(abort, #1 #2 #3 #4 #5 #6 #7 #8 #9 #10 #11 #12 #13 #14 #15 #16 #17 #18 #19 #20 #21 #22 #23 #24)
";
    assert_eq!(
        said(fanuc, &desc, Dialect::Fanuc),
        "7:1: (ABORT) 1.181102 0.078740 0.001575 -0.000394 0.019685 2.000000 0.001575 \
         -0.000394 0.000000 2.000000 0.000000 0.000000 0.000000 20.000000 97.000000 \
         90.000000 40.000000 18.000000 404.000000 1000.000000 0.000000 3.000000 0.000000 \
         95.000000"
    );
    // LinuxCNC's parameters and named parameters: X on the radius (as LinuxCNC's); #5411 the
    // tool's orientation in LinuxCNC's numbering: tool 4's tip 2 is its Q3 (since stop 50).
    let linuxcnc = "\
T0404 M3 S1000
G0 X30 Z2
G1 F100 X20
#1=#5400 #2=#5401 #3=#5403 #4=#5410 #5=#5411 #6=#5420 #7=#5422 #8=#<_x> #9=#<_z>
#10=#<_metric> #11=#<_absolute> #12=#<_feed> #13=#<_rpm> #14=#<_current_tool>
#15=#<_motion_mode> #16=#<_plane> #17=#<_ccomp> #18=#<_units_per_rev>
#19=#<_lathe_diameter_mode> #20=#<_spindle_on>
(abort, #1 #2 #3 #4 #5 #6 #7 #8 #9 #10 #11 #12 #13 #14 #15 #16 #17 #18 #19 #20)
";
    assert_eq!(
        said(linuxcnc, &desc, Dialect::LinuxCnc),
        "8:1: (ABORT) 4.000000 0.020000 -0.010000 1.000000 3.000000 10.000000 2.000000 \
         10.000000 2.000000 1.000000 1.000000 100.000000 1000.000000 4.000000 10.000000 \
         180.000000 400.000000 0.000000 1.000000 1.000000"
    );
    // A message prints them as the line reads them, and `######` for what the lathe
    // refuses (the mill's machine position, its Y).
    assert_eq!(
        said(
            "G0 X30. Z2.\n(abort, #5001 #5002 #4001 #5021)\n",
            &desc,
            Dialect::Fanuc
        ),
        "2:1: (ABORT) 30.000000 2.000000 0.000000 ######"
    );
    assert_eq!(
        said(
            "G0 X30 Z2\n(abort, #5420 #<_x> #<_z> #<_y>)\n",
            &desc,
            Dialect::LinuxCnc
        ),
        "2:1: (ABORT) 15.000000 15.000000 2.000000 ######"
    );
    // What the one reader keeps itself, on both machines: the last N, a returned value, the
    // call level.
    let returned = "\
o<seven> sub
o<seven> return [7]
o<seven> endsub
N20 G0 X30 Z2
o<seven> call
#1 = [#<_value> + #<_value_returned> + #<_call_level> + #<_line>]
(abort, #1)
";
    assert_eq!(
        said(returned, &desc, Dialect::LinuxCnc),
        "7:1: (ABORT) 28.000000"
    );
}

#[test]
fn the_lathes_system_variables_are_refused_at_their_place() {
    let desc = citizen_with_offsets();
    let fanuc = |t: &str| said(t, &desc, Dialect::Fanuc);
    let cases = [
        ("#5001 = 1.\n", "1:1: #5001 (the block end position) is read-only"),
        ("G0 X1. Z1.\n#4001 = 1\n", "2:1: #4001 (modal information) is read-only"),
        ("#1 = 2 #2104 = 0.1\n", "1:8: #2104 (Z wear of offset 4): a lathe program cannot set a tool offset: the lathe reads its program whole at START"),
        ("#3901 = 5\n", "1:1: #3901: the part counter is set on the POS page"),
        ("#1 = #3901\n", "1:6: #3901 (parts machined): there is no part counter here"),
        ("G0 X#2005\n", "1:5: #2005 (X wear of offset 5): tool 5 is not on channel 1's tool post (it has 4, 1, 2, 3;"),
        ("#1 = #2401\n", "1:6: #2401: the lathe has no such tool offset variable"),
        ("#1 = #5003\n", "1:6: #5003: the lathe keeps no such system variable"),
        ("#5021 = 1.\n", "1:1: #5021: the lathe keeps no such system variable"),
        ("#1 = #4008\n", "1:6: #4008: novanc keeps no such modal information (it has #4001 #4002 #4003 #4005 #4006 #4007 #4010 #4011 #4014 #4016 #4109 #4113 #4114 #4115 #4119 #4120)"),
    ];
    for (text, want) in cases {
        let got = fanuc(text);
        assert!(got.starts_with(want), "{text}: {got}");
    }
    let linuxcnc = |t: &str| said(t, &desc, Dialect::LinuxCnc);
    let cases = [
        (
            "#5420 = 1\n",
            "1:1: #5420 reports the lathe's state: it is read-only",
        ),
        ("#<_x> = 1\n", "1:1: #<_x> is read-only"),
        (
            "T0404\nG0 X30 Z2\nG42 G1 X20 F100\nG1 Z#5422\n",
            "4:5: #5422 (the current position) cannot be read with nose-radius compensation on",
        ),
    ];
    for (text, want) in cases {
        let got = linuxcnc(text);
        assert!(got.starts_with(want), "{text}: {got}");
    }
}

#[test]
fn the_part_counter_is_read_per_channel_as_it_stood_at_start() {
    let text = "#1 = #3901\n#2 = #3902\n(abort, #1 #2)\n";
    let desc = LatheDesc::citizen();
    let opts = ReadOptions {
        parts: Some(Parts::new(&[3, 1, 0], 10)),
        ..Default::default()
    };
    let said = |ch: usize| match read_program_in(text, &desc, ch, &opts, Some(Dialect::Fanuc)) {
        Ok(_) => "read without a refusal".to_string(),
        Err(e) => e.to_string(),
    };
    assert_eq!(said(0), "3:1: (ABORT) 3.000000 10.000000");
    assert_eq!(said(1), "3:1: (ABORT) 1.000000 10.000000");
    // The console's START gives its counter (channel 1 has made 2 of 7).
    use novanc::lathe::console::LatheConsole;
    use novanc::panel_model::PanelEvent;
    let state = common::temp_dir("lathe-reader-part-counter");
    let p = Program {
        name: "O1000.NGC".into(),
        text: text.into(),
        dialect: Some(Dialect::Fanuc),
    };
    match LatheStore::open(&state, &desc) {
        Ok(mut o) => {
            let c = Counter {
                target: 7,
                counts: vec![2, 0, 0],
            };
            let r = o
                .store
                .save_program(0, &p)
                .and_then(|()| o.store.save_counter(&c));
            r.unwrap_or_else(|e| panic!("{e}"));
        }
        Err(e) => panic!("{e}"),
    }
    let (mut c, _) =
        LatheConsole::open(desc, &state, 20, 160, None).unwrap_or_else(|e| panic!("{e}"));
    c.handle(PanelEvent::Start);
    assert_eq!(c.message(), "CH1 O1000.NGC:3:1: (ABORT) 2.000000 7.000000");
}
#[test]
fn a_g70_profile_line_reads_the_block_end_position_too() {
    // The profile's lines are read by the one reader for the cycle (`Lines::read_line`):
    // N2 reads Z where N1 left it, 2, and goes to Z-3; G70 then returns to its start.
    let program = "\
T0101 M3 S1000
G0 X20. Z2.
G70 P1. Q2.
M30
N1 G1 X10. F100.
N2 G1 Z[#5002 - 5.]
";
    assert_eq!(
        move_ends(program, &LatheDesc::citizen(), Dialect::Fanuc),
        [
            [10_000, 2_000],
            [5_000, 2_000],
            [5_000, -3_000],
            [10_000, 2_000]
        ]
    );
}
