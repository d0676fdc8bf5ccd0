//! OFS, the work offsets G54 to G59.3 (docs/panel.md "Pages", docs/gcode.md "At the console"):
//! the rows after the last T code. Down from the last T code goes on to G54; the cursor
//! stands on X, Y or Z, or a rotary axis the machine has (degrees). A value typed then INPUT
//! sets the cell, +INPUT adds to it. From any row, `G55 X100 Y-20.5` INPUT sets the axes it
//! names (+INPUT adds to them). G92, when in force, is shown under them (set by MDI `G92`,
//! cancelled by `G92.1`).
//!
//! A change is one journaled record of the stores (as G10 in a program makes). It is taken
//! with no run loaded, or with the run at rest; a G-code run reads the offsets at its START,
//! so a change applies from the next new run.

use super::super::display::{message_lines, split_line, Page as Frame};
use super::Console;
use crate::block::{FIRST_ROTARY, MAX_AXES};
use crate::gcode::state::SYSTEM_NAMES;
use crate::settings::AXIS_NAMES;

/// The machine's axes, as the table's columns: X Y Z, then its rotary axes.
pub(super) fn axes(c: &Console) -> Vec<usize> {
    c.cfg.settings.axis_list().collect()
}

/// The work offset system a line names (`G54` to `G59`, `G59.1` to `G59.3`, any case), and
/// the rest of the line.
pub(crate) fn system_of(line: &str) -> Option<(usize, &str)> {
    let l = line.trim_start();
    let upper = l.get(..5).map(|h| h.to_ascii_uppercase());
    if let Some(cs) = upper
        .as_deref()
        .and_then(|h| SYSTEM_NAMES[6..].iter().position(|n| *n == h))
    {
        return Some((6 + cs, &l[5..]));
    }
    let head = l.get(..3)?;
    let n = head
        .strip_prefix(['G', 'g'])
        .and_then(|n| n.parse::<usize>().ok())?;
    (54..=59).contains(&n).then(|| (n - 54, &l[3..]))
}

/// A number typed for an offset of axis `a`: mm, a rotary axis's degrees.
fn number(text: &str, a: usize) -> Result<f64, String> {
    let unit = if a >= FIRST_ROTARY { "degrees" } else { "mm" };
    text.trim()
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite() && v.abs() <= 100_000.0)
        .ok_or_else(|| {
            format!(
                "'{}' is not an offset in {unit} (at most 100000)",
                text.trim()
            )
        })
}

/// The axis values of `X.. Y.. Z..` (each at most once; the letters of `axes`, the machine's),
/// by axis: the work offset line of every console (the centre's OFS page, a lathe's).
pub(crate) fn axis_words(text: &str, axes: &[usize]) -> Result<[Option<f64>; MAX_AXES], String> {
    let mut out = [None; MAX_AXES];
    let t = text.trim().to_ascii_uppercase();
    if t.is_empty() {
        let example: Vec<String> = axes
            .iter()
            .map(|&a| format!("{}..", AXIS_NAMES[a]))
            .collect();
        return Err(format!("name the axes: G54 {}", example.join(" ")));
    }
    let mut rest = t.as_str();
    while let Some(c) = rest.chars().next() {
        let Some(a) = axes.iter().copied().find(|&a| AXIS_NAMES[a] == c) else {
            let names: Vec<String> = axes.iter().map(|&a| AXIS_NAMES[a].to_string()).collect();
            let (last, first) = names.split_last().expect("X Y Z at least");
            return Err(format!(
                "'{c}' is not an axis ({} or {last})",
                first.join(", ")
            ));
        };
        let after = &rest[1..];
        let end = after
            .find(|ch: char| ch.is_ascii_alphabetic())
            .unwrap_or(after.len());
        if out[a].is_some() {
            return Err(format!("{} is given twice", AXIS_NAMES[a]));
        }
        let text = after[..end].replace(' ', "");
        if text.is_empty() {
            return Err(format!(
                "{}: a number after it ({}-150.)",
                AXIS_NAMES[a], AXIS_NAMES[a]
            ));
        }
        out[a] = Some(number(&text, a)?);
        rest = after[end..].trim_start();
    }
    Ok(out)
}

/// Whether the offsets (or page `page`'s values) may change now: no run loaded, or the run
/// at rest; if not, the message says why.
pub(super) fn at_rest(c: &Console, page: &str) -> Result<(), String> {
    let st = &c.status;
    let at_rest = st.job.is_none() || (st.idle && (st.hold || st.run == 0));
    if !at_rest || st.moving {
        return Err(format!("{page} refused: the machine is moving; STOP first"));
    }
    Ok(())
}

/// Sets (or adds to, with `add`) the axes given of work offset `system`: what it did, or why
/// it is refused (nothing changed).
pub(super) fn set(
    c: &mut Console,
    system: usize,
    vals: [Option<f64>; MAX_AXES],
    add: bool,
) -> Result<String, String> {
    at_rest(c, "OFS")?;
    let mut o = c.mem.system_offset_all(system);
    for a in 0..MAX_AXES {
        if let Some(v) = vals[a] {
            o[a] = if add { o[a] + v } else { v };
            o[a] = (o[a] * 1000.0).round() / 1000.0;
        }
    }
    let axes = axes(c);
    // X Y Z, and the rotary axes up to the machine's last (one it has not keeps its value).
    let n = axes.last().map_or(3, |&a| a + 1);
    c.mem
        .set_work_offset(system, &o[..n])
        .map_err(|e| format!("OFS refused: {e}"))?;
    let when = if c.status.job.is_some() {
        ": from the next run"
    } else {
        ""
    };
    c.pages.ofs.0 = c.mem.magazine().tcodes.capacity() + 1 + system as u32;
    let words: String = axes
        .iter()
        .map(|&a| format!(" {}{:.3}", AXIS_NAMES[a], o[a]))
        .collect();
    Ok(format!("{}{words}{when}", SYSTEM_NAMES[system]))
}

/// `G5n X.. Y.. Z..` INPUT (or +INPUT).
pub(super) fn enter_line(
    c: &mut Console,
    system: usize,
    rest: &str,
    add: bool,
) -> Result<String, String> {
    let v = axis_words(rest, &axes(c)).map_err(|e| format!("OFS refused: {e}"))?;
    set(c, system, v, add)
}

/// A value INPUT (or +INPUT) on the cell under the cursor, row `system`, axis `axis`.
pub(super) fn enter_cell(
    c: &mut Console,
    system: usize,
    axis: usize,
    text: &str,
    add: bool,
) -> Result<String, String> {
    let axes = axes(c);
    let a = axes[axis.min(axes.len() - 1)];
    let v = number(text, a).map_err(|e| format!("OFS refused: {e}"))?;
    let mut vals = [None; MAX_AXES];
    vals[a] = Some(v);
    set(c, system, vals, add)
}

/// The work offsets table, the cursor on row `system`, axis `axis`.
pub(super) fn compose(
    c: &Console,
    rows: usize,
    cols: usize,
    system: usize,
    axis: usize,
) -> Vec<String> {
    let mut p = Frame::new(
        rows,
        cols,
        split_line("OFS WORK", "G55 X10 / Enter INPUT  Tab +INPUT", cols),
    );
    p.bottom = message_lines(c, cols, (rows / 4).max(1));
    p.bottom.push(format!("> {}_", c.shell.front.entry));
    let all = axes(c);
    // X Y Z keep the 11 columns they had; more axes take 10 each, and those that do not fit
    // the display (a 40-column plasma shows three) scroll with the cursor, as the rows do.
    let w = if all.len() > 3 { 10 } else { 11 };
    let shown = (cols.saturating_sub(6) / w).clamp(1, all.len());
    let axis = axis.min(all.len() - 1);
    let from = (axis + 1).saturating_sub(shown);
    let axes = &all[from..from + shown];
    let axis = axis - from;
    let mut table = Vec::new();
    for (i, name) in SYSTEM_NAMES.iter().enumerate() {
        let o = c.mem.system_offset_all(i);
        let mut line = format!("{name:<6}");
        for (k, &a) in axes.iter().enumerate() {
            let v = format!("{:.3}", o[a]);
            line.push_str(&if i == system && k == axis {
                format!("{:>w$}", format!(">{v}"))
            } else {
                format!("{v:>w$}")
            });
        }
        table.push(line);
    }
    // G92 in force (shown, not set here: MDI G92 / G92.1 set it).
    let g92 = c.interp.g92_all();
    if all.iter().any(|&a| g92[a] != 0.0) {
        let mut line = format!("{:<6}", "G92");
        for &a in axes {
            line.push_str(&format!("{:>w$}", format!("{:.3}", g92[a])));
        }
        table.push(line);
    }
    // The rows that fit under the axes' heading, the cursor's among them (and G92 under
    // the last system's).
    let fit = p.body_rows().saturating_sub(1).max(1);
    let last = if system + 1 == SYSTEM_NAMES.len() {
        table.len()
    } else {
        system + 1
    };
    let first = last.saturating_sub(fit);
    let heading: String = axes
        .iter()
        .map(|&a| format!("{:>w$}", AXIS_NAMES[a]))
        .collect();
    p.body.push(format!("{:<6}{heading}", ""));
    p.body.extend(table.into_iter().skip(first));
    p.lines()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offset_lines_read_or_say_why() {
        assert_eq!(system_of("g55 X1"), Some((1, " X1")));
        assert_eq!(system_of("G60 X1"), None);
        assert_eq!(system_of("g59.2 Z1"), Some((7, " Z1")));
        assert_eq!(system_of("G59 Z1"), Some((5, " Z1")));
        assert_eq!(system_of("X1"), None);
        let xyz = [0, 1, 2];
        assert_eq!(
            axis_words(" X100 Y-20.5", &xyz).unwrap(),
            [Some(100.0), Some(-20.5), None, None, None, None]
        );
        assert_eq!(
            axis_words("z 3", &xyz).unwrap(),
            [None, None, Some(3.0), None, None, None]
        );
        assert!(axis_words("X1 X2", &xyz).unwrap_err().contains("twice"));
        assert_eq!(
            axis_words("A1", &xyz).unwrap_err(),
            "'A' is not an axis (X, Y or Z)"
        );
        assert!(axis_words("Xabc", &xyz).is_err());
        assert_eq!(
            axis_words("Z Y1", &xyz).unwrap_err(),
            "Z: a number after it (Z-150.)"
        );
        assert!(axis_words("X1e9", &xyz).is_err());
        assert!(axis_words("", &xyz).is_err());
        // A machine with C: its offset in degrees.
        assert_eq!(
            axis_words("c-90 X1", &[0, 1, 2, 5]).unwrap(),
            [Some(1.0), None, None, None, None, Some(-90.0)]
        );
        assert_eq!(
            axis_words("B1", &[0, 1, 2, 5]).unwrap_err(),
            "'B' is not an axis (X, Y, Z or C)"
        );
    }
}
