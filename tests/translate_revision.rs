//! A tool-data revision changes the Z moves and not the part program: with tool 106's set
//! length changed in the tool file, only the Z values of the 106 blocks move, by exactly the
//! difference (docs/language.md "Coordinates and heights").

use novanc::settings::MachineSettings;
use novanc::tooldata::{parse_tape, parse_tcodes, Magazine, SAMPLE_TAPE, SAMPLE_TCODES};
use novanc::translator::{iso_line, translate_all, Statement};

const TABLEB: &str = include_str!("../programs/tableb.ap");

fn magazine(tape: &str) -> Magazine {
    let tape = parse_tape(tape, "tools.tt").unwrap();
    let tc = parse_tcodes(SAMPLE_TCODES, "magazine.tc", 24).unwrap();
    Magazine::load(tc, &tape)
}

fn translate(tape: &str) -> Vec<Statement> {
    translate_all(
        TABLEB,
        &magazine(tape),
        &MachineSettings::default(),
        [0, 0, 0],
    )
    .unwrap()
}

#[test]
fn revising_the_set_length_of_106_moves_only_its_z_values() {
    // 00106 DR 6.2 150.0 ... becomes set length 162.345: +12.345 mm = +12345 pulses.
    let mut found = false;
    let revised: String = SAMPLE_TAPE
        .lines()
        .map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            if f.first() == Some(&"00106") {
                assert_eq!(f[3], "150.0", "the sample set length of 106");
                found = true;
                format!("00106 DR 6.2 162.345 {} {} {} {}\n", f[4], f[5], f[6], f[7])
            } else {
                format!("{l}\n")
            }
        })
        .collect();
    assert!(found);
    let (a, b) = (translate(SAMPLE_TAPE), translate(&revised));
    let st = MachineSettings::default();
    assert_eq!(a.len(), b.len());
    let mut moved = 0;
    for (sa, sb) in a.iter().zip(&b) {
        assert_eq!(sa.blocks.len(), sb.blocks.len(), "line {}", sa.line);
        for (x, y) in sa.blocks.iter().zip(&sb.blocks) {
            assert_eq!(
                (x.end[0], x.end[1]),
                (y.end[0], y.end[1]),
                "X Y never change"
            );
            assert_eq!((x.motion, x.s, x.t, x.m), (y.motion, y.s, y.t, y.m));
            // Line 5 is DRL, 106. Its Z ends carry the set length, except the tool change's
            // rapid to machine zero Z0, which is an axis position.
            if sa.line == 5 && x.end[2] != 0 {
                assert_eq!(y.end[2] - x.end[2], 12_345, "{}", iso_line(x, &st));
                moved += 1;
            } else {
                assert_eq!(
                    iso_line(x, &st),
                    iso_line(y, &st),
                    "a block of line {} changed",
                    sa.line
                );
            }
        }
    }
    // Hole 1: Za, Zb, Zc. Holes 2 to 6: X Y at Zc, Zb, Zc. 3 + 5 x 3 = 18 blocks whose Z end
    // is a tool-tip height; the Z0, T02 M06, X Y at Z0 and S1200 M03 blocks stay as they were.
    assert_eq!(moved, 3 + 5 * 3);
}
