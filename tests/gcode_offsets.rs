//! Work offsets G54..G59 at the console (docs/gcode.md "At the console", docs/stores.md "Work
//! offsets"): G10 from MDI or a program keeps them in the stores across a restart, the OFS
//! page shows and sets them, POS shows work coordinates, and bad input changes nothing.

mod common;

use common::{keys, mdi, open, p, reopen, shows, type_line};
use novanc::panel_model::{DataMode, OpMode, PanelEvent as E};
use std::path::{Path, PathBuf};

fn repo(f: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(f)
}

#[test]
fn g10_in_mdi_sets_an_offset_that_survives_a_restart_and_g55_uses_it() {
    let mut c = open("ofs-g10");
    let dir = c.config().state_dir.clone();
    mdi(&mut c, "G10 L2 P2 X100 Y50 Z-300");
    assert!(shows(&c, "program end"), "{}", c.frame_text());
    assert_eq!(c.work_offsets().0[1], [100.0, 50.0, -300.0]);
    mdi(&mut c, "G55 G0 X1 Y2 Z3");
    assert_eq!(c.status().pos, [p(101.0), p(52.0), p(-297.0)]);
    // G10 L20: the offset that makes the current position the given work coordinates.
    mdi(&mut c, "G10 L20 P3 X0 Y0 Z0");
    assert_eq!(c.work_offsets().0[2], [101.0, 52.0, -297.0]);
    c.finish().unwrap();
    let c = reopen(&dir);
    assert_eq!(c.work_offsets().0[1], [100.0, 50.0, -300.0]);
    assert_eq!(c.work_offsets().0[2], [101.0, 52.0, -297.0]);
    // novanc run --state uses them.
    let prog = common::temp_dir("ofs-run").join("g55.ngc");
    std::fs::write(&prog, "G55 G0 X0 Y0 Z0\nM30\n").unwrap();
    c.finish().unwrap();
    let out = common::novanc_command()
        .args([
            "run",
            prog.to_str().unwrap(),
            "--state",
            dir.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    let s = String::from_utf8_lossy(&out.stdout);
    assert!(
        s.contains("final position: X 100.000 Y 50.000 Z -300.000 mm"),
        "{s}{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn a_program_run_keeps_its_g10_in_the_stores() {
    let mut c = open("ofs-tableb");
    c.handle(E::Op(OpMode::Data));
    c.handle(E::Data(DataMode::Read));
    c.handle(E::Tape(repo("programs/tableb.ngc")));
    c.handle(E::Start);
    c.handle(E::Wait);
    c.handle(E::Op(OpMode::Auto));
    c.handle(E::Start);
    c.handle(E::Wait);
    assert!(shows(&c, "program end"), "{}", c.frame_text());
    assert_eq!(c.work_offsets().0[0], [200.0, 0.0, -450.0]);
}

#[test]
fn a_refused_run_changes_no_offset() {
    let mut c = open("ofs-refused");
    // Two lines in the MDI buffer: a G10, then a feed move without F.
    c.handle(E::Op(OpMode::Data));
    c.handle(E::Data(DataMode::Mdi));
    type_line(&mut c, "IG10 L2 P1 X5*G1 X1*");
    c.handle(E::Op(OpMode::Mdi));
    c.handle(E::Start);
    c.handle(E::Wait);
    assert!(
        shows(&c, "START refused, nothing moved: line 2:"),
        "{}",
        c.frame_text()
    );
    assert_eq!(c.work_offsets().0[0], [0.0; 3]);
    for bad in ["G10 L2 P10 X1", "G10 L2 P1 X[1/0]"] {
        mdi(&mut c, bad);
        assert!(shows(&c, "START refused"), "{bad}: {}", c.frame_text());
        c.handle(E::Reset);
        assert_eq!(c.work_offsets().0, [[0.0; 3]; 6], "{bad}");
    }
}

#[test]
fn the_ofs_page_shows_and_sets_the_offsets_and_pos_shows_work_coordinates() {
    let mut c = open("ofs-page");
    keys(&mut c, &["Ctrl+o"]);
    type_line(&mut c, "G56 X10 Y-2.5 Z-100");
    assert_eq!(c.work_offsets().0[2], [10.0, -2.5, -100.0]);
    assert!(
        shows(&c, "G56 X10.000 Y-2.500 Z-100.000"),
        "{}",
        c.frame_text()
    );
    assert!(shows(&c, "OFS WORK"), "{}", c.frame_text());
    // +INPUT (Tab) adds.
    for ch in ["G", "5", "6", " ", "X", "1"] {
        keys(&mut c, &[ch]);
    }
    keys(&mut c, &["Tab"]);
    assert_eq!(c.work_offsets().0[2], [11.0, -2.5, -100.0]);
    // The cell under the cursor: the row after G56 is G57; Right moves to Y.
    keys(&mut c, &["Down", "Right", "7", "Enter"]);
    assert_eq!(c.work_offsets().0[3], [0.0, 7.0, 0.0], "{}", c.frame_text());
    keys(&mut c, &["2", "Tab"]);
    assert_eq!(c.work_offsets().0[3], [0.0, 9.0, 0.0]);
    // Bad values say why and change nothing.
    let before = c.work_offsets();
    for bad in ["abc", "1e9", "G54 Q1", "G54 X1 X2", "G54"] {
        type_line(&mut c, bad);
        assert!(shows(&c, "OFS refused"), "{bad}: {}", c.frame_text());
        assert_eq!(c.work_offsets(), before, "{bad}");
    }
    // Up from G54 goes back to the tool table.
    keys(&mut c, &["Up", "Up", "Up", "Up"]);
    assert!(!shows(&c, "OFS WORK"), "{}", c.frame_text());
    // POS: WORK is the tip less the G54 offset.
    type_line(&mut c, "G54 X100 Y0 Z-400");
    keys(&mut c, &["Ctrl+o"]);
    mdi(&mut c, "G53 G0 X150 Y20 Z-410");
    assert_eq!(c.status().pos, [p(150.0), p(20.0), p(-410.0)]);
    keys(&mut c, &["Ctrl+p"]);
    let f = c.frame_text();
    assert!(
        f.lines()
            .any(|l| l.starts_with("X   50.000  150.000  150.000")),
        "{f}"
    );
    assert!(f.lines().any(|l| l.starts_with("Z  -10.000")), "{f}");
}
