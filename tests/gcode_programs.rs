//! The G-code samples in `programs/` and the program source's interface for the console
//! (docs/gcode.md): Table B in G-code machines the same ten holes as `programs/tableb.ap`, every
//! sample runs on the pulse core and ends each block exactly where it was programmed, and
//! SEARCH, MDI, the switches and G10 behave as documented.

use novanc::block::{Block, MachineState, Motion, Statement};
use novanc::gcode::{is_gcode, GcodeSource, Switches, WorkOffsets};
use novanc::pulse_core::{Command, Machine, RunKind, VecSource};
use novanc::settings::MachineSettings;
use novanc::tooldata::sample_magazine;
use novanc::translator::translate_all;
use std::collections::BTreeMap;

fn read(name: &str) -> String {
    std::fs::read_to_string(format!("{}/programs/{name}", env!("CARGO_MANIFEST_DIR")))
        .expect("sample program")
}

fn gcode(src: &str, state: MachineState, sw: Switches) -> GcodeSource {
    GcodeSource::new(
        src.into(),
        sample_magazine(),
        MachineSettings::default(),
        state,
        WorkOffsets::default(),
        sw,
    )
}

fn all(src: &str) -> Vec<Statement> {
    gcode(src, MachineState::at([0, 0, 0]), Switches::default())
        .collect::<Result<Vec<_>, _>>()
        .unwrap_or_else(|e| panic!("{e}"))
}

/// (T code, X, Y) of every hole with the deepest tool-tip Z a feed reached there, pulses.
fn holes(blocks: &[Block]) -> BTreeMap<(u32, i64, i64), i64> {
    let mag = sample_magazine();
    let st = MachineSettings::default();
    let mut tool = 0;
    let mut set = 0;
    let mut out = BTreeMap::new();
    for b in blocks {
        if b.m == Some(6) {
            tool = b.t.unwrap_or(0);
            set = mag
                .tools
                .get(tool)
                .map_or(0, |r| st.to_pulses(r.set_length));
        }
        if b.motion == Motion::Linear && b.delta[0] == 0 && b.delta[1] == 0 && b.delta[2] < 0 {
            let tip = b.end[2] - set;
            let e = out.entry((tool, b.end[0], b.end[1])).or_insert(tip);
            *e = (*e).min(tip);
        }
    }
    out
}

#[test]
fn table_b_in_g_code_machines_the_same_ten_holes() {
    let st = MachineSettings::default();
    let ap = translate_all(&read("tableb.ap"), &sample_magazine(), &st, [0, 0, 0])
        .unwrap_or_else(|e| panic!("{e}"));
    let ap_blocks: Vec<Block> = ap.iter().flat_map(|s| s.blocks.clone()).collect();
    let ngc = all(&read("tableb.ngc"));
    let ngc_blocks: Vec<Block> = ngc.iter().flat_map(|s| s.blocks.clone()).collect();
    let (a, g) = (holes(&ap_blocks), holes(&ngc_blocks));
    assert_eq!(
        a.len(),
        19,
        "bore 1, drill 6 + tap 6, drill 3 + tap 3: {a:?}"
    );
    assert_eq!(a, g, "the same tools at the same holes to the same depths");
    let positions: std::collections::BTreeSet<(i64, i64)> = g.keys().map(|k| (k.1, k.2)).collect();
    assert_eq!(positions.len(), 10, "ten holes");
    // G81, G84, G85 and a work offset are what it is written with.
    let text = read("tableb.ngc");
    for w in ["G81", "G84", "G85", "G10 L2 P1"] {
        assert!(text.contains(w), "{w}");
    }
}

#[test]
fn every_sample_runs_on_the_pulse_core_and_ends_each_block_exactly() {
    for name in ["tableb.ngc", "pocket.ngc", "helix.ngc", "subprogram.ngc"] {
        let stmts = all(&read(name));
        let n: usize = stmts.iter().map(|s| s.blocks.len()).sum();
        let mut m = Machine::new(MachineSettings::default());
        m.set_magazine(sample_magazine());
        m.set_audit(true);
        let mut src = VecSource::from_statements(stmts.into_iter().map(Ok));
        m.command(Command::Start(RunKind::Auto));
        m.run_until_idle(&mut src, 3_600_000_000_000);
        assert_eq!(m.status().alarm, None, "{name}");
        let audit = m.take_audit();
        assert_eq!(audit.len(), n, "{name}: every block ran");
        for e in &audit {
            assert_eq!(e.pos, e.end, "{name}: block N{} ended off its point", e.seq);
        }
    }
}

#[test]
fn the_samples_use_what_they_say() {
    let pocket = all(&read("pocket.ngc"));
    let arcs = pocket
        .iter()
        .flat_map(|s| &s.blocks)
        .filter(|b| matches!(b.motion, Motion::ArcCw | Motion::ArcCcw))
        .count();
    assert!(arcs >= 4, "the pocket's corners are arcs under G41");
    let helix = all(&read("helix.ngc"));
    let helices = helix
        .iter()
        .flat_map(|s| &s.blocks)
        .filter(|b| b.center.is_some() && b.delta[b.plane.axes()[2]] != 0)
        .count();
    assert!(helices >= 4, "{helices} helical blocks");
    let sub = all(&read("subprogram.ngc"));
    let dwells = sub
        .iter()
        .flat_map(|s| &s.blocks)
        .filter(|b| b.motion == Motion::Dwell)
        .count();
    assert_eq!(dwells, 12, "4 holes × 3 rows from M98 repeats");
}

#[test]
fn the_language_is_chosen_by_name_or_first_line() {
    assert!(is_gcode("part.NGC", ""));
    assert!(is_gcode("part.nc", "DA1 = (0, 0, 0)"));
    assert!(is_gcode("part.iso", ""));
    assert!(is_gcode("prog", "\n%\nG0 X1\n"));
    assert!(is_gcode("prog", "O1234 (x)\nG0 X1\n"));
    assert!(!is_gcode("tableb.ap", &read("tableb.ap")));
    assert!(!is_gcode("prog", "ORIGIN = 1"));
}

#[test]
fn g10_changes_are_reported_for_the_caller_to_keep() {
    let src = "G10 L2 P2 X10 Y20 Z-30\nG0 X0 Y0 Z0\nG10 L20 P1 X-5\nM30\n";
    let mut g = gcode(src, MachineState::at([100_000, 0, 0]), Switches::default());
    let _ = g.next();
    let c = g.take_offset_changes();
    assert_eq!(c.len(), 1);
    assert_eq!((c[0].system, c[0].offset), (1, [10.0, 20.0, -30.0]));
    for r in g.by_ref() {
        r.unwrap_or_else(|e| panic!("{e}"));
    }
    let c = g.take_offset_changes();
    // G0 X0 Y0 Z0 under G54 (zero) puts the machine at X0; L20 X-5 makes that read X-5.
    assert_eq!((c[0].system, c[0].offset), (0, [5.0, 0.0, 0.0]));
    assert_eq!(g.offsets().0[1], [10.0, 20.0, -30.0]);
}

#[test]
fn block_delete_and_optional_stop_follow_their_switches() {
    let src = "G0 X1 Y1 Z0\n/G0 X50\nM1\nM30\n";
    let count = |sw: Switches| {
        let stmts: Vec<Statement> = gcode(src, MachineState::at([0, 0, 0]), sw)
            .collect::<Result<_, _>>()
            .unwrap_or_else(|e| panic!("{e}"));
        let b: Vec<&Block> = stmts.iter().flat_map(|s| &s.blocks).collect();
        (
            b.iter().any(|b| b.end[0] == 50_000),
            b.iter().any(|b| b.m == Some(1)),
        )
    };
    assert_eq!(count(Switches::default()), (true, false));
    let on = Switches {
        block_delete: true,
        optional_stop: true,
    };
    assert_eq!(count(on), (false, true));
}

#[test]
fn search_restores_z_first_then_tool_spindle_x_y_and_z() {
    let src = "G10 L2 P1 X100 Y100 Z-300\nT2 M6\nG43 H2\nS800 M3\nG0 X10 Y10 Z5\nG1 X20 F100\nG1 X30\nM30\n";
    // The machine stands somewhere else, low, with another tool and the spindle stopped.
    let state = MachineState {
        tool: Some(4),
        ..MachineState::at([500_000, 400_000, -400_000])
    };
    let stmts: Vec<Statement> = gcode(src, state, Switches::default())
        .resume_at(7)
        .collect::<Result<_, _>>()
        .unwrap_or_else(|e| panic!("{e}"));
    let restore = &stmts[0];
    assert_eq!(restore.text, "(SEARCH: restore for line 7)");
    let b = &restore.blocks;
    assert_eq!(
        b[0].end,
        [500_000, 400_000, 0],
        "Z up to machine zero first"
    );
    assert_eq!((b[1].t, b[1].m), (Some(2), Some(6)));
    assert_eq!((b[2].s, b[2].m), (Some(800), Some(3)));
    // Line 6 left the tool at X20 Y10 Z5 in G54 with tool 2's 150 mm: machine X120 Y110 Z-145.
    assert_eq!(b[3].end, [120_000, 110_000, 0]);
    assert_eq!(b[4].end, [120_000, 110_000, -145_000]);
    assert!(b.iter().all(|b| b.seq == 0));
    assert_eq!(stmts[1].line, 7);
    assert_eq!(stmts[1].blocks[0].end, [130_000, 110_000, -145_000]);
    assert_eq!(stmts[1].blocks[0].start(), [120_000, 110_000, -145_000]);
}

#[test]
fn mdi_needs_no_end_and_starts_from_the_machine() {
    let g = gcode(
        "G91 G0 X5",
        MachineState::at([10_000, 0, 0]),
        Switches::default(),
    )
    .mdi();
    let stmts: Vec<Statement> = g
        .collect::<Result<_, _>>()
        .unwrap_or_else(|e| panic!("{e}"));
    let b: Vec<&Block> = stmts.iter().flat_map(|s| &s.blocks).collect();
    assert_eq!(b.len(), 1);
    assert_eq!(b[0].end, [15_000, 0, 0]);
}

/// SEARCH restores the coolant the lines before left, from the machine's: M7 and M8 to turn
/// on, M9 first when one is on that should not be (after the spindle, before X and Y).
#[test]
fn search_restores_the_coolant_from_the_machines() {
    let src = "G10 L2 P1 X100 Y100 Z-300\nS800 M3 M8\nG0 X10 Y10 Z5\nM7\nG1 X20 F100\nM9\nG1 X30\nM8\nG1 X40\nM30\n";
    for (line, mist, flood, want) in [
        (5, false, false, vec![3, 7, 8]),
        (7, false, true, vec![3, 9]),
        (9, true, true, vec![3, 9, 8]),
        (9, false, true, vec![3]),
    ] {
        let state = MachineState {
            mist,
            flood,
            ..MachineState::at([0, 0, 0])
        };
        let stmts: Vec<Statement> = gcode(src, state, Switches::default())
            .resume_at(line)
            .collect::<Result<_, _>>()
            .unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(stmts[0].text, format!("(SEARCH: restore for line {line})"));
        let m: Vec<u8> = stmts[0].blocks.iter().filter_map(|b| b.m).collect();
        assert_eq!(m, want, "line {line}, machine mist {mist} flood {flood}");
    }
}
