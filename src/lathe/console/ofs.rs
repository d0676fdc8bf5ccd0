//! The lathe console's OFS page (docs/lathe.md "Tool offsets"): a channel's tools as a table
//! with the centre's cursor (the arrows move it by cell; a value typed then INPUT, Enter, sets
//! the cell, +INPUT, Tab, adds to it, as on a Fanuc), and the revision line
//! `T1 X0.02 Z-0.01 R0.8 P3`. A cell's INPUT is the revision line of that one word, so both
//! are checked, stored and taken by one rule ([`revise`]). Under the tools, the channel's work
//! offsets G54 to G59 (docs/lathe-gcode.md "Work offsets"), X as a diameter and Z, revised by
//! `G55 X0 Z-150.` ([`revise_work`]) or a cell's INPUT alike.

use crate::console::pages::workofs::{axis_words, system_of};
use crate::lathe::desc::ToolDesc;
use crate::lathe::gcode::{WorkOffsets, MAX_WORK_OFFSET_MM};
use novanc_panel::Key;

/// The work offset rows under the tools: G54 to G59.
pub const WORK_ROWS: usize = 6;

/// The table's value columns in order, by the letter a revision gives them: nose radius, tip,
/// X offset as a diameter, Z offset.
pub const COLUMNS: [char; 4] = ['R', 'P', 'X', 'Z'];

/// Where the cursor starts: the X offset (what an operator sizes a diameter with).
pub const FIRST_COLUMN: usize = 2;

/// The OFS page of a channel in `room` lines: the heading, then one line per tool (number,
/// nose radius, tip, X offset as a diameter, Z offset) and one per work offset (G54 to G59, X
/// as a diameter, Z), as many as fit around the cursor's; the cell under `cursor` (row,
/// column) marked `>`, as the centre's OFS page marks it.
pub fn table(
    tools: &[ToolDesc],
    work: &WorkOffsets,
    cursor: (usize, usize),
    room: usize,
) -> Vec<String> {
    let (row, col) = clamp(tools, cursor);
    let sep = |i: usize, c: usize| if i == row && c == col { '>' } else { ' ' };
    let tool_rows = tools.iter().enumerate().map(|(i, t)| {
        format!(
            "T{:02}{}{:5.3}{}{}{} {:7.3}{}{:7.3}",
            t.number,
            sep(i, 0),
            t.radius,
            sep(i, 1),
            t.tip,
            sep(i, 2),
            t.offset[0] * 2.0,
            sep(i, 3),
            t.offset[1]
        )
    });
    let work_rows = work.iter().enumerate().map(|(k, [z, x])| {
        let i = tools.len() + k;
        format!(
            "G{}        {} {:7.3}{}{:7.3}",
            54 + k,
            sep(i, 2),
            x * 2.0,
            sep(i, 3),
            z
        )
    });
    let rows: Vec<String> = tool_rows.chain(work_rows).collect();
    // The cursor's row stays on the page.
    let shown = room.saturating_sub(1).max(1);
    let first = (row + 1).saturating_sub(shown);
    let mut out = vec!["T   R     P  X(DIA)   Z".to_string()];
    out.extend(rows.into_iter().skip(first).take(shown));
    out
}

/// The cursor inside the table of `tools` and the work offsets (a work row has X and Z only).
fn clamp(tools: &[ToolDesc], (row, col): (usize, usize)) -> (usize, usize) {
    let row = row.min(tools.len() + WORK_ROWS - 1);
    let col = col.min(COLUMNS.len() - 1);
    (row, if row >= tools.len() { col.max(2) } else { col })
}

/// The cursor moved by a cursor key: Up/Down a row, PgUp/PgDn eight, Home/End the first and
/// the last, Left/Right a column.
pub fn cursor_moved(tools: &[ToolDesc], cursor: (usize, usize), k: Key) -> (usize, usize) {
    let (row, col) = clamp(tools, cursor);
    let last = tools.len() + WORK_ROWS - 1;
    let moved = match k {
        Key::Up => (row.saturating_sub(1), col),
        Key::Down => ((row + 1).min(last), col),
        Key::PageUp => (row.saturating_sub(8), col),
        Key::PageDown => ((row + 8).min(last), col),
        Key::Home => (0, col),
        Key::End => (last, col),
        Key::Left => (row, col.saturating_sub(1)),
        Key::Right => (row, (col + 1).min(COLUMNS.len() - 1)),
        _ => (row, col),
    };
    clamp(tools, moved)
}

/// The work offset (0 for G54) whose row the cursor stands on, if it stands on one.
pub fn work_row(tools: &[ToolDesc], cursor: (usize, usize)) -> Option<usize> {
    clamp(tools, cursor).0.checked_sub(tools.len())
}

/// A measure typed on a work offset's row (Fanuc's MEASURE): `Z0` or `X50.`, the axis and
/// the value the tool in place is to read where it stands (X a diameter); None if `line` is
/// not one.
pub fn measure(line: &str) -> Option<Result<(char, f64), String>> {
    let t = line.trim();
    let letter = t.chars().next()?.to_ascii_uppercase();
    if !matches!(letter, 'X' | 'Z') {
        return None;
    }
    Some(value(t, letter).map(|v| (letter, v)))
}

/// The revision line of INPUT of `value` on the cell under `cursor` (+INPUT with `add`: the
/// value added to the cell's): `T1 X0.04`. Err: why it cannot be one.
pub fn cell_line(
    tools: &[ToolDesc],
    work: &WorkOffsets,
    cursor: (usize, usize),
    value: &str,
    add: bool,
) -> Result<String, String> {
    let (row, col) = clamp(tools, cursor);
    let letter = COLUMNS[col];
    let v: f64 = value
        .trim()
        .parse()
        .ok()
        .filter(|v: &f64| v.is_finite())
        .ok_or_else(|| format!("OFS: '{}' is not a number", value.trim()))?;
    if let Some([z, x]) = row.checked_sub(tools.len()).and_then(|k| work.get(k)) {
        let was = if letter == 'X' { x * 2.0 } else { *z };
        let now = if add { was + v } else { v };
        let now = (now * 1000.0).round() / 1000.0;
        return Ok(format!("G{} {letter}{now}", 54 + row - tools.len()));
    }
    let Some(t) = tools.get(row) else {
        return Err("OFS: the channel has no tools".into());
    };
    let was = match letter {
        'R' => t.radius,
        'P' if add => {
            return Err("OFS: P, the tip position, is set (INPUT), not added to".into());
        }
        'P' => 0.0,
        'X' => t.offset[0] * 2.0,
        _ => t.offset[1],
    };
    let now = if add { was + v } else { v };
    // Three decimals at most, as the centre's OFS page rounds.
    let now = (now * 1000.0).round() / 1000.0;
    Ok(format!("T{} {letter}{now}", t.number))
}

fn value(w: &str, letter: char) -> Result<f64, String> {
    match w[1..].parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(format!("{letter}: '{}' is not a number", &w[1..])),
    }
}

/// Applies a work offset's revision line (`G55 X0 Z-150.`, X a diameter) to `work`: returns
/// the new offsets and the one revised (0 for G54). The line is read as the centre's OFS page
/// reads one (`console::pages::workofs`), on the lathe's axes X and Z. Nothing is changed on
/// an error.
pub fn revise_work(work: &WorkOffsets, line: &str) -> Result<(WorkOffsets, usize), String> {
    let first = line.split_whitespace().next().unwrap_or("");
    let (k, rest) = match system_of(line) {
        Some((k, rest)) if k < WORK_ROWS => (k, rest),
        _ => {
            return Err(format!(
                "'{first}': the work offsets are G54 to G59 (G55 X0 Z-150.)"
            ))
        }
    };
    // X (axis 0) as a diameter, Z (axis 2).
    let v = axis_words(rest, &[0, 2])?;
    let mut out = *work;
    if let Some(x) = v[0] {
        out[k][1] = x / 2.0;
    }
    if let Some(z) = v[2] {
        out[k][0] = z;
    }
    if out[k].iter().any(|v| v.abs() > MAX_WORK_OFFSET_MM) {
        return Err(format!(
            "X, Z: a work offset is within ±{MAX_WORK_OFFSET_MM} mm (X ±{} as a diameter)",
            2.0 * MAX_WORK_OFFSET_MM
        ));
    }
    Ok((out, k))
}

/// Applies a revision line to `tools`: returns the new tools and the tool revised. Nothing is
/// changed on an error.
pub fn revise(tools: &[ToolDesc], line: &str) -> Result<(Vec<ToolDesc>, u32), String> {
    let words: Vec<&str> = line.split_whitespace().collect();
    let Some(first) = words.first() else {
        return Err("type T, then X Z R P".into());
    };
    let n = match first.strip_prefix('T').map(|s| s.parse::<u32>()) {
        Some(Ok(n)) => n,
        _ => {
            return Err(format!(
                "'{first}': a revision starts with the tool, T1 X0.02 Z-0.01 R0.8 P3"
            ))
        }
    };
    let Some(i) = tools.iter().position(|t| t.number == n) else {
        return Err(format!("T{n} is not on this tool post"));
    };
    let mut t = tools[i].clone();
    if words.len() == 1 {
        return Err(format!("T{n}: say what to revise (X Z R P)"));
    }
    for w in &words[1..] {
        let letter = w.chars().next().unwrap_or(' ');
        if w.len() < 2 {
            return Err(format!("'{w}': a letter and a number"));
        }
        match letter {
            'X' => t.offset[0] = value(w, 'X')? / 2.0,
            'Z' => t.offset[1] = value(w, 'Z')?,
            'R' => t.radius = value(w, 'R')?,
            'P' => {
                let v = value(w, 'P')?;
                if v.fract() != 0.0 || !(0.0..=9.0).contains(&v) {
                    return Err(format!("P{v}: tip positions are 0 to 9"));
                }
                t.tip = v as u8;
            }
            c => return Err(format!("'{c}': a tool takes X (diameter) Z R P")),
        }
    }
    if t.offset.iter().any(|v| v.abs() > 1000.0) {
        return Err("X, Z: offsets within ±1000 mm (X ±2000 as a diameter)".into());
    }
    if !(0.0..=10.0).contains(&t.radius) {
        return Err(format!("R{}: a nose radius is 0 to 10 mm", t.radius));
    }
    let mut out = tools.to_vec();
    out[i] = t;
    Ok((out, n))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tools() -> Vec<ToolDesc> {
        vec![ToolDesc {
            number: 1,
            radius: 0.8,
            tip: 3,
            offset: [0.0, 0.0],
        }]
    }

    #[test]
    fn a_revision_changes_only_what_it_names() {
        let (t, n) = revise(&tools(), "T1 X0.04 Z-0.01").unwrap();
        assert_eq!(n, 1);
        assert_eq!(
            t[0],
            ToolDesc {
                number: 1,
                radius: 0.8,
                tip: 3,
                offset: [0.02, -0.01]
            }
        );
        let (t, _) = revise(&t, "T1 R0.4 P2").unwrap();
        assert_eq!(
            (t[0].radius, t[0].tip, t[0].offset),
            (0.4, 2, [0.02, -0.01])
        );
        let w = [[0.0; 2]; 6];
        assert_eq!(table(&t, &w, (0, 0), 9)[1], "T01>0.400 2    0.040  -0.010");
        assert_eq!(table(&t, &w, (0, 2), 9)[1], "T01 0.400 2>   0.040  -0.010");
    }

    #[test]
    fn input_sets_the_cell_and_plus_input_adds_to_it() {
        let t = tools();
        let w = [[0.0; 2]; 6];
        assert_eq!(
            cell_line(&t, &w, (0, 2), "0.04", false).unwrap(),
            "T1 X0.04"
        );
        let (t, _) = revise(&t, "T1 X0.04").unwrap();
        // +INPUT: X as a diameter, -0.01 on it.
        assert_eq!(
            cell_line(&t, &w, (0, 2), "-0.01", true).unwrap(),
            "T1 X0.03"
        );
        assert_eq!(cell_line(&t, &w, (0, 3), "-0.2", true).unwrap(), "T1 Z-0.2");
        assert_eq!(cell_line(&t, &w, (0, 0), "0.4", false).unwrap(), "T1 R0.4");
        assert!(cell_line(&t, &w, (0, 1), "1", true).is_err());
        assert!(cell_line(&t, &w, (0, 2), "x", false).is_err());
        assert!(cell_line(&[], &w, (6, 2), "1", false).is_ok());
        assert_eq!(cursor_moved(&t, (0, 2), Key::Right), (0, 3));
        assert_eq!(cursor_moved(&t, (0, 3), Key::Right), (0, 3));
        // Down from the last tool: the work offsets, X and Z only.
        assert_eq!(cursor_moved(&t, (0, 0), Key::Down), (1, 2));
        assert_eq!(cursor_moved(&t, (1, 2), Key::Left), (1, 2));
        assert_eq!(cursor_moved(&t, (0, 2), Key::End), (6, 2));
        assert_eq!(cursor_moved(&t, (6, 2), Key::Down), (6, 2));
    }

    #[test]
    fn the_work_offsets_stand_under_the_tools_and_are_revised_alike() {
        let t = tools();
        let w = [[0.0; 2]; 6];
        // G55 is the second work row (row 2: one tool above).
        assert_eq!(
            cell_line(&t, &w, (2, 3), "-150", false).unwrap(),
            "G55 Z-150"
        );
        let (w, k) = revise_work(&w, "G55 Z-150").unwrap();
        assert_eq!((k, w[1]), (1, [-150.0, 0.0]));
        // +INPUT adds; X is a diameter.
        assert_eq!(
            cell_line(&t, &w, (2, 3), "0.5", true).unwrap(),
            "G55 Z-149.5"
        );
        let (w, _) = revise_work(&w, "g55 x4").unwrap();
        assert_eq!(w[1], [-150.0, 2.0]);
        let page = table(&t, &w, (2, 3), 9);
        assert_eq!(page[3], "G55            4.000>-150.000");
        assert_eq!(page.len(), 8);
        // Three lines of room: the heading and the cursor's row with the one before it.
        let page = table(&t, &w, (6, 2), 3);
        assert_eq!(page.len(), 3);
        assert!(
            page[2].starts_with("G59") && page[2].contains('>'),
            "{page:?}"
        );
        for (line, want) in [
            ("G60 X1", "the work offsets are G54 to G59"),
            ("G59.1 X1", "the work offsets are G54 to G59"),
            ("G54", "name the axes: G54 X.. Z.."),
            ("G54 R1", "'R' is not an axis (X or Z)"),
            ("G54 Y1", "'Y' is not an axis (X or Z)"),
            ("G54 Z1 Z2", "Z is given twice"),
            ("G54 Z20000", "within ±10000 mm"),
            ("G54 Zq", "Z: a number after it"),
            ("G54 Z1.2.3", "'1.2.3' is not an offset in mm"),
        ] {
            match revise_work(&w, line) {
                Err(e) => assert!(e.contains(want), "{line}: {e}"),
                Ok(r) => panic!("{line}: {r:?}"),
            }
        }
    }

    #[test]
    fn bad_revisions_say_why_and_change_nothing() {
        for (line, want) in [
            ("T7 X1", "T7 is not on this tool post"),
            ("X1", "a revision starts with the tool"),
            ("T1", "say what to revise"),
            ("T1 P12", "P12: tip positions are 0 to 9"),
            ("T1 R-1", "R-1: a nose radius"),
            ("T1 Xa", "X: 'a' is not a number"),
            ("T1 Q1", "'Q': a tool takes"),
            ("T1 Z5000", "offsets within"),
        ] {
            match revise(&tools(), line) {
                Err(e) => assert!(e.contains(want), "{line}: {e}"),
                Ok(t) => panic!("{line}: {t:?}"),
            }
        }
    }
}
