//! A lathe program's moves in brief, for the tests that work them out by hand
//! (`tests/lathe_shop_codes.rs`, `tests/lathe_drilling.rs`): R rapid, F feed, the block's end
//! (X a radius, Z), mm; with dwells, D and the dwell in ms.

use novanc::block::{Motion, Statement};
use novanc::lathe::desc::LatheDesc;
use novanc::lathe::gcode::{read_program, ReadOptions};

/// Channel 1's program `text` on `desc`, read as START reads it.
pub fn read(text: &str, desc: &LatheDesc) -> Result<Vec<Statement>, String> {
    read_program(text, desc, 0, &ReadOptions::default()).map_err(|e| e.to_string())
}

/// The moves of `p` (and its dwells, if `dwells`), in brief.
pub fn moves(p: &[Statement], dwells: bool) -> Vec<String> {
    p.iter()
        .flat_map(|s| &s.blocks)
        .filter_map(|b| {
            let k = match b.motion {
                Motion::Rapid => 'R',
                Motion::Linear => 'F',
                Motion::Dwell if dwells => return Some(format!("D {}", b.dwell_ns / 1_000_000)),
                _ => return None,
            };
            Some(format!(
                "{k} X{:.3} Z{:.3}",
                b.end[0] as f64 / 1000.0,
                b.end[2] as f64 / 1000.0
            ))
        })
        .collect()
}

/// The moves of `text` read on `desc`; a program that does not read fails the test.
pub fn ok(text: &str, desc: &LatheDesc, dwells: bool) -> Vec<String> {
    match read(text, desc) {
        Ok(p) => moves(&p, dwells),
        Err(e) => panic!("{e}\n{text}"),
    }
}
