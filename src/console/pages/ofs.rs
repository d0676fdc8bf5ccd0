//! OFS: the tool file as a table (T code, tool, kind, diameter, set length, effective length,
//! speed, feed, depth, length wear, diameter wear). The arrows move the cursor by cell; a
//! value typed then INPUT (Enter) sets the cell, +INPUT (Tab) adds to it, as on a Fanuc.
//!
//! A change is one journaled revision of the tool file, through the same validator as TOOL
//! DATA REVISION: a refused value says why and changes nothing. It is accepted with no run
//! loaded, and during a run stopped at rest (a feed hold, or between single blocks): the
//! length (set length plus wear) then applies from the next block the tool moves in (the pulse
//! core moves its Z by the difference); the other values, the diameter wear among them, from
//! the next translation (the next run, SEARCH or MDI). The tool number is set in T-CODE
//! SETTING.

use super::super::display::{message_lines, split_line, Page as Frame, CUT};
use super::Console;
use crate::tooldata::{ToolKind, ToolRecord};
use novanc_panel::Key;

/// The columns, in order: heading and width-free name.
const COLUMNS: [&str; 11] = [
    "T", "TOOL", "KIND", "DIA", "LEN", "EFF", "SPEED", "FEED", "DEPTH", "WEAR L", "WEAR D",
];

/// The first column the cursor may stand on (the T code and tool number are set elsewhere).
const FIRST: usize = 2;

/// The set-length column, where the cursor starts.
pub const LENGTH: usize = 4;

/// Moves the cursor by cell.
pub(super) fn arrow(c: &mut Console, k: Key) {
    let cap = c.mem.magazine().tcodes.capacity().max(1);
    let last = cap + crate::gcode::state::SYSTEMS as u32;
    let last_axis = super::workofs::axes(c).len() - 1;
    let axis = &mut c.pages.ofs_axis;
    let (t, col) = &mut c.pages.ofs;
    match k {
        Key::Up => *t = t.saturating_sub(1).max(1),
        Key::Down => *t = (*t + 1).min(last),
        Key::PageUp => *t = t.saturating_sub(8).max(1),
        Key::PageDown => *t = (*t + 8).min(last),
        // Home: the first T code; End: the work offsets, G54 (the row after the last T code).
        Key::Home => *t = 1,
        Key::End => *t = cap + 1,
        Key::Left if *t > cap => *axis = axis.saturating_sub(1),
        Key::Right if *t > cap => *axis = (*axis + 1).min(last_axis),
        Key::Left => *col = col.saturating_sub(1).max(FIRST),
        Key::Right => *col = (*col + 1).min(COLUMNS.len() - 1),
        _ => {}
    }
}

/// A cell's value as shown.
fn cell(r: &ToolRecord, col: usize) -> String {
    match col {
        2 => r.kind.code().to_string(),
        3 => format!("{}", r.diameter),
        4 => format!("{:.3}", r.set_length),
        5 => format!("{}", r.effective_length),
        6 => format!("{}", r.speed),
        7 => format!("{}", r.feed),
        8 => format!("{}", r.depth),
        9 => format!("{:.3}", r.wear_length),
        10 => format!("{:.3}", r.wear_diameter),
        _ => String::new(),
    }
}

/// The record with the cell at `col` set to `text` (or `text` added to it).
fn revised(r: &ToolRecord, col: usize, text: &str, add: bool) -> Result<ToolRecord, String> {
    let mut n = r.clone();
    if col == 2 {
        if add {
            return Err("+INPUT adds to numbers; type the kind and INPUT".into());
        }
        n.kind = ToolKind::from_code(&text.trim().to_ascii_uppercase()).ok_or_else(|| {
            format!(
                "'{}' is not a tool kind (DR CD TP RM EM FM BB)",
                text.trim()
            )
        })?;
        return Ok(n);
    }
    let v: f64 = text
        .trim()
        .parse()
        .ok()
        .filter(|v: &f64| v.is_finite() && v.abs() <= 1e9)
        .ok_or_else(|| format!("'{}' is not a number", text.trim()))?;
    let field = match col {
        3 => &mut n.diameter,
        4 => &mut n.set_length,
        5 => &mut n.effective_length,
        6 => &mut n.speed,
        7 => &mut n.feed,
        8 => &mut n.depth,
        9 => &mut n.wear_length,
        10 => &mut n.wear_diameter,
        _ => return Err("that column is set in T-CODE SETTING".into()),
    };
    *field = if add { *field + v } else { v };
    // Three decimals at most, as the part-programming language writes numbers.
    *field = (*field * 1000.0).round() / 1000.0;
    Ok(n)
}

/// INPUT (or +INPUT with `add`) on the cell under the cursor: what it did, or why it is
/// refused (nothing changed).
pub(super) fn enter(c: &mut Console, line: &str, add: bool) -> Result<String, String> {
    let (t, col) = c.pages.ofs;
    if line.trim().is_empty() {
        return Err("OFS: type a value, then Enter (INPUT) or Tab (+INPUT)".into());
    }
    if let Some(rest) = line
        .trim_start()
        .get(..7)
        .filter(|w| w.eq_ignore_ascii_case("MEASURE"))
        .map(|_| &line.trim_start()[7..])
    {
        return super::measure::enter(c, rest);
    }
    if let Some((system, rest)) = super::workofs::system_of(line) {
        return super::workofs::enter_line(c, system, rest, add);
    }
    let cap = c.mem.magazine().tcodes.capacity();
    if t > cap {
        let axis = c.pages.ofs_axis;
        return super::workofs::enter_cell(c, (t - cap - 1) as usize, axis, line, add);
    }
    let st = &c.status;
    let at_rest = st.job.is_none() || (st.idle && (st.hold || st.run == 0));
    if !at_rest || st.moving {
        return Err(if st.hold {
            "OFS refused: the feed hold is still braking; INPUT again once it has stopped"
        } else {
            "OFS refused: the machine is moving; STOP first"
        }
        .into());
    }
    let m = c.mem.magazine();
    let (Some(tool), Some(rec)) = (m.tcodes.tool_in(t), m.tools.get(t)) else {
        return Err(format!(
            "OFS refused: T{t:02} holds no tool with data (TOOL DATA READ)"
        ));
    };
    let new = revised(rec, col, line, add).map_err(|e| format!("OFS refused: {e}"))?;
    let before = c.status.tool_set_length;
    c.mem
        .revise_tool(t, tool, &new)
        .map_err(|e| format!("OFS refused: {e}"))?;
    note_pending(c, t, before);
    let name = COLUMNS[col];
    let said = if c.status.job.is_some() {
        c.core.set_magazine(c.mem.magazine());
        if super::super::gcode_run::gcode_run_loaded(c) {
            // A G-code run took its lengths and radii when its lines were read (G43,
            // G41/G42), as LinuxCNC does (docs/gcode.md, "Tool length").
            format!(
                "T{t:02} {name} {}: from the next run; this G-code run keeps what its G43/G41/G42 read",
                cell(&new, col)
            )
        } else {
            format!("T{t:02} {name} {}: from the next block", cell(&new, col))
        }
    } else {
        format!("T{t:02} {name} {}", cell(&new, col))
    };
    // The program alarm is rechecked against the revised tool, and says so after this.
    c.shell.front.message = said;
    super::super::run::recheck_program_alarm(c);
    Ok(std::mem::take(&mut c.shell.front.message))
}

/// The OFS page: the T code and tool, then three value columns around the cursor.
pub(super) fn compose(c: &Console, rows: usize, cols: usize) -> Vec<String> {
    let m = c.mem.magazine();
    let (focus, col) = c.pages.ofs;
    let cap = m.tcodes.capacity();
    if focus > cap {
        let system = ((focus - cap - 1) as usize).min(crate::gcode::state::SYSTEMS - 1);
        return super::workofs::compose(c, rows, cols, system, c.pages.ofs_axis);
    }
    let mut p = Frame::new(
        rows,
        cols,
        split_line("OFS", "Enter INPUT  Tab +INPUT", cols),
    );
    p.bottom = message_lines(c, cols, (rows / 4).max(1));
    p.bottom.push(format!("> {}_", c.shell.front.entry));
    let shown = ((cols.saturating_sub(10)) / 9).clamp(1, COLUMNS.len() - FIRST);
    let first = col
        .saturating_sub(shown / 2)
        .clamp(FIRST, COLUMNS.len() - shown);
    let cols_shown = first..first + shown;
    let mut head = format!("{:<3} {:<5} ", "T", "TOOL");
    for k in cols_shown.clone() {
        head.push_str(&format!("{:>9}", COLUMNS[k]));
    }
    if first + shown < COLUMNS.len() {
        head.push(CUT);
    }
    p.body.push(head);
    let n = p.body_rows().saturating_sub(1);
    let cap = m.tcodes.capacity();
    let top = focus
        .saturating_sub(n as u32 / 2)
        .max(1)
        .min(cap.saturating_sub(n as u32).saturating_add(1).max(1));
    for t in (top..=cap).take(n) {
        let mut line = match m.tcodes.tool_in(t) {
            None => format!("T{t:02} -----"),
            Some(tool) => format!("T{t:02} {tool:05}"),
        };
        if let Some(r) = m.tools.get(t) {
            line.push(' ');
            for k in cols_shown.clone() {
                let v = cell(r, k);
                let here = t == focus && k == col;
                line.push_str(&if here {
                    format!(">{v:>8}")
                } else {
                    format!("{v:>9}")
                });
            }
        } else if t == focus {
            line.push_str(" <");
        }
        p.body.push(line);
    }
    p.lines()
}

/// Notes a length of the tool in the spindle revised while a run is loaded: it is not in force
/// until the next block (the next run for a G-code run), and POS marks it until then.
fn note_pending(c: &mut Console, t: u32, before: f64) {
    let st = &c.status;
    if st.job.is_none() || st.tool != Some(t) {
        return;
    }
    let revised = c.mem.magazine().tools.get(t).map_or(0.0, |r| r.length());
    let in_force = match &c.pages.pending_len {
        Some(p) if p.tool == t && p.blocks_done == st.blocks_done => p.in_force,
        _ => before,
    };
    c.pages.pending_len = (revised != in_force).then(|| super::PendingLength {
        tool: t,
        in_force,
        revised,
        blocks_done: st.blocks_done,
        gcode: super::super::gcode_run::gcode_run_loaded(c),
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cell_is_set_or_added_to() {
        let m = crate::tooldata::sample_magazine();
        let r = m.tools.get(2).unwrap();
        assert_eq!(revised(r, 4, "155", false).unwrap().set_length, 155.0);
        assert_eq!(revised(r, 4, "5", true).unwrap().set_length, 155.0);
        assert_eq!(revised(r, 9, "-0.05", true).unwrap().wear_length, -0.05);
        assert_eq!(revised(r, 2, "em", false).unwrap().kind, ToolKind::EndMill);
        assert!(revised(r, 4, "x", false).is_err());
        assert!(revised(r, 1, "5", false).is_err());
    }
}
