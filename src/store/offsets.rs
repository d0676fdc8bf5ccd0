//! The work offsets G54 to G59 in the stores (docs/stores.md "Work offsets"): set from the OFS
//! page or by a G-code program's G10, journaled like the tool file, and in the snapshot.

use super::record::Record;
use super::{serr, to_store, StoreError, Stores};
use crate::gcode::WorkOffsets;

/// Millimetres as the stores keep them: whole nanometres (1e-6 mm); refused when not finite.
pub fn mm_to_nm(v: f64) -> Result<i64, String> {
    let nm = (v * 1e6).round();
    if !nm.is_finite() || nm.abs() > super::state::OFFSET_LIMIT_NM as f64 {
        return Err(format!(
            "work offset {v} mm is not a number within {} mm",
            super::state::OFFSET_LIMIT_NM / 1_000_000
        ));
    }
    Ok(nm as i64)
}

/// The offsets in millimetres.
pub fn offsets_mm(nm: &[[i64; 3]; 6]) -> WorkOffsets {
    let mut w = WorkOffsets::default();
    for (o, n) in w.0.iter_mut().zip(nm) {
        for a in 0..3 {
            o[a] = n[a] as f64 / 1e6;
        }
    }
    w
}

impl Stores {
    /// The work offsets G54 to G59, machine mm.
    pub fn work_offsets(&self) -> WorkOffsets {
        offsets_mm(&self.state.offsets)
    }

    /// Sets work offset `system` (0 = G54 … 5 = G59) to `mm`, journaled before it returns Ok;
    /// a value that is not a finite number within 100 m changes nothing.
    pub fn set_work_offset(&mut self, system: usize, mm: [f64; 3]) -> Result<(), StoreError> {
        if system > 5 {
            return Err(serr(format!(
                "work offset system {} is not G54 to G59",
                54 + system
            )));
        }
        let nm = [mm_to_nm(mm[0]), mm_to_nm(mm[1]), mm_to_nm(mm[2])];
        let nm = match nm {
            [Ok(x), Ok(y), Ok(z)] => [x, y, z],
            [Err(e), ..] | [_, Err(e), _] | [.., Err(e)] => return Err(serr(e)),
        };
        self.commit(Record::WorkOffset { system, nm }, None)
            .map(|_| ())
            .map_err(to_store)
    }
}
