//! The lathe G-code reader's blocks, kept as a golden listing (`tests/golden/lathe/blocks.txt`):
//! every block (its `Debug`) the reader makes of the Citizen's programs (`programs/citizen`),
//! of the testkit's three-channel sample, and of programs that use every word of the lathe
//! dialect (modes, spindle, G96, G95, threads, G76, G71/G70, nose-radius compensation on both
//! sides and changing side, waits, chuck, stops, block delete). Written from the blocks an
//! adapter made of the reader's own operations (`lathe/ops.rs`, `lathe/blocks.rs`) before issue
//! 22 made the reader emit the kernel's blocks itself: the reader's blocks are the adapter's,
//! byte for byte. The testkit's sample was then built of operations by hand; its G-code
//! (`testkit::SYSTEM1`…`SYSTEM3`, one block a line) reads into the same blocks.
//! `NOVANC_BLESS=1` rewrites the listing: only when a change of the blocks is meant.

use novanc::block::Statement;
use novanc::lathe::desc::LatheDesc;
use novanc::lathe::gcode::{read_program, ReadOptions};
use novanc::lathe::testkit;
use std::fmt::Write;

/// The Citizen with room to turn at negative Z (as the reader's unit tests have it).
fn wide_desc() -> LatheDesc {
    let mut d = LatheDesc::citizen();
    for c in &mut d.channels {
        c.axes[0].travel = [-1.0, 100.0];
        c.axes[1].travel = [-200.0, 200.0];
    }
    d
}

/// Programs read on channel 1 of [`wide_desc`]: each feature of the dialect at least once.
const PROGRAMS: &[(&str, &str)] = &[
    ("plain", "%\nO1000 (PART)\nN5 G18 G21 G90 T0101 ; tool 1\nM3 S1000\nG0 X20 Z2\nG1 Z-10 F100\nG2 X30 Z-15 R5\nM30\n%\n"),
    ("modes", "G0 X20 Z0\nG8 G0 X20\nG7 G0 X20\nG91 G0 X-4\nG8 G0 X-4\nU10 W-1\n"),
    ("arc", "G0 X20 Z0\nG1 F50\nG3 X30 Z-5 I0 K-5\nG20 G8 G0 X1 Z-1\n"),
    ("css", "M4 G96 S180 D2500\nG95 G0 X20 Z1\nG1 Z-5 F0.15\nG97 S800\nG1 Z-8\nM5\nG96 S100 M3\nG1 X30 F0.1\nM30\n"),
    ("offsets", "T0101\nG0 X20 Z0\nT0100\nG0 X20 Z0\nT1\nG0 Z1\n"),
    ("g33", "M3 S500\nG0 X20 Z5\nG33 Z-20 K1.5\nG33 X22 Z-30 K2\n"),
    ("g76", "M3 S500\nG8 G0 X10 Z5\nG76 P1.5 Z-20 I-0.5 J0.2 K0.6 H1 Q29.5\nG0 X10 Z5\nG76 P1 Z-10 I0.5 J0.2 K0.6 R2\n"),
    ("g71", "T0101 M3 S1000\nG0 X40 Z2\nG71 U2 R0.5\nG71 P10 Q20 U0.4 W0.1 F100\nN10 G0 X20\nG1 Z-10\nN20 G1 X40 Z-20\nG70 P10 Q20\nM30\n"),
    ("g71arc", "G0 X40 Z2\nG71 U3 R0\nG71 P1 Q3 F100\nN1 G0 X10\nN2 G1 Z0\nN3 G2 X40 Z-15 R15\nM30\n"),
    ("g71bore", "T0303 M3 S1000\nG0 X10 Z2\nG71 U1 R0\nG71 P1 Q2 F50\nN1 G41 G0 X20\nN2 G1 Z-5\nG40 G0 X10\nG70 P1 Q2\nM30\n"),
    ("waits", "M100 P12\nM101 P123\nM102\nM103 P1\n"),
    ("stops", "M10\n/M11\nM0\nM1\nG4 P1.5\nM2\nG0 X1\n"),
    ("held", "T0101 M3 S1000\nG0 X30 Z5\nG42 G0 X10 Z2\nG1 Z0 F100\nM10\nG1 X20 Z-10\nG40 G0 X40 Z5\nM30\n"),
    ("comp42", "T0101\nM3 S1000\nG0 X30 Z5\nG42 G0 X10 Z2\nG1 Z0 F100\nG1 X20 Z-10\nG2 X30 Z-15 R5\nG3 X40 Z-20 R5\nG1 Z-30\nG1 X50\nG40 G0 X60 Z-25\nM30\n"),
    ("comp41", "T0202\nM3 S1000\nG0 X30 Z5\nG41 G0 X10 Z2\nG1 Z0 F100\nG1 X20 Z-10\nG2 X30 Z-15 R5\nG3 X40 Z-20 R5\nG1 Z-30\nG1 X50\nG40 G0 X60 Z-25\nM30\n"),
    ("corner", "T0101 M3 S1000\nG0 X30 Z5\nG42 G0 X10 Z2\nG1 Z-10 F100\nG1 X9.996 Z-20\nG40 G0 X30\nM30\n"),
    ("side", "T0303 M3 S1000\nG8 G0 X30 Z5\nG42 G0 X10 Z2\nG1 Z-10 F100\nG41 G1 X20 Z-12\nG1 Z-20\nG40 G0 X30\nM30\n"),
    ("circle", "M3 S1000\nG0 X20 Z0\nG1 F100\nG2 X20 Z0 I5 K0\nG96 S120 D3000\nG95 G1 Z-5 F0.1\nG4 P0.25\nM30\n"),
];

/// Channel `ch`'s statements of program `text` on `desc`, each statement's text checked to
/// be its source line.
fn statements(name: &str, text: &str, desc: &LatheDesc, ch: usize) -> Vec<Statement> {
    let opts = ReadOptions {
        block_delete: name == "stops",
        optional_stop: name == "stops",
        parts: None,
    };
    let st = read_program(text, desc, ch, &opts)
        .unwrap_or_else(|e| panic!("{name} on channel {}: {e}", ch + 1));
    let lines: Vec<&str> = text.lines().collect();
    for s in &st {
        assert_eq!(
            Some(&s.text.as_str()),
            lines.get(s.line as usize - 1),
            "{name}"
        );
    }
    st
}

fn dump(out: &mut String, title: &str, st: &[Statement]) {
    let _ = writeln!(out, "== {title}");
    for s in st {
        let _ = writeln!(out, "L{}", s.line);
        for b in &s.blocks {
            let _ = writeln!(out, "  {b:?}");
        }
    }
}

#[test]
fn the_readers_blocks_are_the_golden_listings() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut out = String::new();
    let citizen = LatheDesc::citizen();
    for ch in 0..3 {
        let name = format!("system{}.ngc", ch + 1);
        let text = std::fs::read_to_string(root.join("programs/citizen").join(&name))
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        dump(
            &mut out,
            &format!("programs/citizen/{name} on the Citizen, channel {}", ch + 1),
            &statements(&name, &text, &citizen, ch),
        );
    }
    let like = testkit::citizen_like(3);
    for (ch, text) in [testkit::SYSTEM1, testkit::SYSTEM2, testkit::SYSTEM3]
        .iter()
        .enumerate()
    {
        dump(
            &mut out,
            &format!("testkit sample, channel {}", ch + 1),
            &statements("sample", text, &like, ch),
        );
    }
    let wide = wide_desc();
    for (name, text) in PROGRAMS {
        dump(&mut out, name, &statements(name, text, &wide, 0));
    }
    let path = root.join("tests/golden/lathe/blocks.txt");
    if std::env::var_os("NOVANC_BLESS").is_some() {
        std::fs::write(&path, &out).expect("write the listing");
    }
    let want = std::fs::read_to_string(&path).unwrap_or_default();
    if want != out {
        let at = want
            .lines()
            .zip(out.lines())
            .position(|(a, b)| a != b)
            .unwrap_or(want.lines().count().min(out.lines().count()));
        panic!(
            "the blocks differ from tests/golden/lathe/blocks.txt at line {}:\n  want {:?}\n  got  {:?}",
            at + 1,
            want.lines().nth(at),
            out.lines().nth(at)
        );
    }
}
