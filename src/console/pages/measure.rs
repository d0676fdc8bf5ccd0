//! OFS MEASURE: a work offset set so that the current position reads a typed value (Fanuc's
//! MEASURE soft key on the work offset screen, LinuxCNC's touch-off, G10 L20), and a tool's
//! length set by touching its tip to a known height (Fanuc's tool length measurement, LinuxCNC's
//! tool touch-off, G10 L10) (docs/panel.md, "Pages").
//!
//! - On a work offset row, `MEASURE X0 Y0` INPUT sets that system's zero so that the work
//!   position of X and Y reads 0 here: zero = machine position − G92 − value, and for Z also
//!   less the length in force of the tool in the spindle (the tip is what reads the value).
//!   `MEASURE G55 X0` names the system from any row.
//! - On a tool row, `MEASURE Z50` INPUT with that tool in the spindle, its tip touching a
//!   surface 50 mm high in the work system in force: the set length becomes what makes the tip
//!   read Z50 there (length = machine Z − zero − G92 − 50 − length wear; the wear stays).
//!
//! Both go through the same checks as a typed value (the machine at rest, the tool file's
//! validator), so each is one journaled revision and a refusal changes nothing.

use super::Console;

/// `MEASURE …` INPUT on the OFS page; `rest` follows the word.
pub(super) fn enter(c: &mut Console, rest: &str) -> Result<String, String> {
    let s = c.cfg.settings.clone();
    let cap = c.mem.magazine().tcodes.capacity();
    let (t, _) = c.pages.ofs;
    let (system, words) = match super::workofs::system_of(rest) {
        Some((cs, w)) => (Some(cs), w),
        None if t > cap => (Some((t - cap - 1) as usize), rest),
        None => (None, rest),
    };
    let axes = super::workofs::axes(c);
    let vals = super::workofs::axis_words(words, &axes)
        .map_err(|e| format!("OFS MEASURE refused: {e}"))?;
    if c.status.moving {
        return Err("OFS MEASURE refused: the machine is moving; STOP first".into());
    }
    let (len, _) = super::pos::length_in_force(c);
    let g92 = c.interp.g92_all();
    match system {
        Some(cs) => {
            // Where the tip (a rotary axis: the table) stands reads the value given.
            let mut zero = [None; crate::block::MAX_AXES];
            for a in axes {
                if let Some(v) = vals[a] {
                    let tip = s.to_mm(c.status.pos[a]) - if a == 2 { len } else { 0.0 };
                    zero[a] = Some(tip - g92[a] - v);
                }
            }
            super::workofs::set(c, cs, zero, false)
        }
        None => {
            let (Some(z), true) = (vals[2], vals.iter().filter(|v| v.is_some()).count() == 1)
            else {
                return Err(
                    "OFS MEASURE refused: a tool row measures its length in Z (MEASURE Z50); a work offset is measured on its row or by name (MEASURE G54 X0)".into(),
                );
            };
            if c.status.tool != Some(t) {
                let inside = c
                    .status
                    .tool
                    .map_or("no tool".to_string(), |s| format!("T{s:02}"));
                return Err(format!(
                    "OFS MEASURE refused: T{t:02} is not in the spindle ({inside} is); change to it and touch its tip"
                ));
            }
            let cs = c.interp.modal.cs;
            let zero = if c.status.job.is_some() {
                c.interp.origin[2]
            } else {
                c.mem.system_offset(cs)[2]
            };
            let wear = c.mem.magazine().tools.get(t).map_or(0.0, |r| r.wear_length);
            let set = s.to_mm(c.status.pos[2]) - zero - g92[2] - z - wear;
            c.pages.ofs.1 = super::ofs::LENGTH;
            super::ofs::enter(c, &format!("{set:.3}"), false)
        }
    }
}
