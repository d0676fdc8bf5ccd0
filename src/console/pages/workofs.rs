//! OFS, the work offsets G54 to G59.3 (docs/panel.md "Pages", docs/gcode.md "At the console"):
//! the rows after the last T code. Down from the last T code goes on to G54; the cursor
//! stands on X, Y or Z. A value typed then INPUT sets the cell, +INPUT adds to it. From any
//! row, `G55 X100 Y-20.5` INPUT sets the axes it names (+INPUT adds to them). G92, when in
//! force, is shown under them (set by MDI `G92`, cancelled by `G92.1`).
//!
//! A change is one journaled record of the stores (as G10 in a program makes). It is taken
//! with no run loaded, or with the run at rest; a G-code run reads the offsets at its START,
//! so a change applies from the next new run.

use super::super::display::{message_lines, split_line, Page as Frame};
use super::Console;
use crate::gcode::state::SYSTEM_NAMES;

/// The axes' headings.
const AXES: [&str; 3] = ["X", "Y", "Z"];

/// The work offset system a line names (`G54` to `G59`, `G59.1` to `G59.3`, any case), and
/// the rest of the line.
pub(super) fn system_of(line: &str) -> Option<(usize, &str)> {
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

/// A number typed for an offset, mm.
fn number(text: &str) -> Result<f64, String> {
    text.trim()
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite() && v.abs() <= 100_000.0)
        .ok_or_else(|| format!("'{}' is not an offset in mm (at most 100000)", text.trim()))
}

/// The axis values of `X.. Y.. Z..` (each at most once), by axis.
pub(super) fn axis_words(text: &str) -> Result<[Option<f64>; 3], String> {
    let mut out = [None; 3];
    let t = text.trim().to_ascii_uppercase();
    if t.is_empty() {
        return Err("name the axes: G54 X100 Y50 Z-450".into());
    }
    let mut rest = t.as_str();
    while let Some(c) = rest.chars().next() {
        let Some(a) = AXES.iter().position(|x| x.starts_with(c)) else {
            return Err(format!("'{c}' is not an axis (X, Y or Z)"));
        };
        let after = &rest[1..];
        let end = after
            .find(|ch: char| ch.is_ascii_alphabetic())
            .unwrap_or(after.len());
        if out[a].is_some() {
            return Err(format!("{} is given twice", AXES[a]));
        }
        out[a] = Some(number(&after[..end].replace(' ', ""))?);
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
    vals: [Option<f64>; 3],
    add: bool,
) -> Result<String, String> {
    at_rest(c, "OFS")?;
    let mut o = c.mem.system_offset(system);
    for a in 0..3 {
        if let Some(v) = vals[a] {
            o[a] = if add { o[a] + v } else { v };
            o[a] = (o[a] * 1000.0).round() / 1000.0;
        }
    }
    c.mem
        .set_work_offset(system, o)
        .map_err(|e| format!("OFS refused: {e}"))?;
    let when = if c.status.job.is_some() {
        ": from the next run"
    } else {
        ""
    };
    c.pages.ofs.0 = c.mem.magazine().tcodes.capacity() + 1 + system as u32;
    Ok(format!(
        "{} X{:.3} Y{:.3} Z{:.3}{when}",
        SYSTEM_NAMES[system], o[0], o[1], o[2]
    ))
}

/// `G5n X.. Y.. Z..` INPUT (or +INPUT).
pub(super) fn enter_line(
    c: &mut Console,
    system: usize,
    rest: &str,
    add: bool,
) -> Result<String, String> {
    let v = axis_words(rest).map_err(|e| format!("OFS refused: {e}"))?;
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
    let v = number(text).map_err(|e| format!("OFS refused: {e}"))?;
    let mut vals = [None; 3];
    vals[axis.min(2)] = Some(v);
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
    p.bottom.push(format!("> {}_", c.front.entry));
    let mut table = Vec::new();
    for (i, name) in SYSTEM_NAMES.iter().enumerate() {
        let o = c.mem.system_offset(i);
        let mut line = format!("{name:<6}");
        for (a, v) in o.iter().enumerate() {
            let v = format!("{v:.3}");
            line.push_str(&if i == system && a == axis {
                format!("{:>11}", format!(">{v}"))
            } else {
                format!("{v:>11}")
            });
        }
        table.push(line);
    }
    // G92 in force (shown, not set here: MDI G92 / G92.1 set it).
    let g92 = c.interp.g92;
    if g92 != [0.0; 3] {
        let mut line = format!("{:<6}", "G92");
        for v in g92 {
            line.push_str(&format!("{:>11}", format!("{v:.3}")));
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
    p.body
        .push(format!("{:<6}{:>11}{:>11}{:>11}", "", "X", "Y", "Z"));
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
        assert_eq!(
            axis_words(" X100 Y-20.5").unwrap(),
            [Some(100.0), Some(-20.5), None]
        );
        assert_eq!(axis_words("z 3").unwrap(), [None, None, Some(3.0)]);
        assert!(axis_words("X1 X2").unwrap_err().contains("twice"));
        assert!(axis_words("A1").unwrap_err().contains("not an axis"));
        assert!(axis_words("Xabc").is_err());
        assert!(axis_words("X1e9").is_err());
        assert!(axis_words("").is_err());
    }
}
