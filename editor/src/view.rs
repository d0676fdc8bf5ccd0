//! The display of a buffer around its pointer (SPEC §5: "the display shows the text around the
//! pointer, with the pointer marked"). Costs a few line look-ups, whatever the buffer size.

use crate::{Buffer, EOB};

/// What the display shows: lines around the pointer, EOB drawn as `*`.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct View {
    /// The rows to draw, each at most `cols` characters, starting at column `first_col`.
    pub lines: Vec<String>,
    /// Row (index into `lines`) of the pointer.
    pub pointer_row: usize,
    /// Column of the pointer within its row (0 = before the row's first shown character).
    pub pointer_col: usize,
    /// 0-based buffer line number of `lines[0]`.
    pub first_line: usize,
    /// Buffer column of the first character shown on every row (horizontal scroll).
    pub first_col: usize,
}

/// Builds the view of `buf` for `rows` × `cols`.
pub fn view(buf: &Buffer, rows: usize, cols: usize) -> View {
    let p = buf.pointer();
    let cur = buf.line_of(p);
    let last = buf.line_of(buf.len());
    let col = p - buf.line_start(cur);
    let first_col = if cols > 0 && col >= cols {
        col + 1 - cols
    } else {
        0
    };
    if rows == 0 {
        return View {
            first_line: cur,
            first_col,
            pointer_col: col - first_col,
            ..View::default()
        };
    }
    let mut first = cur.saturating_sub((rows - 1) / 2);
    first = first.min(last.saturating_sub(rows - 1));
    let mut lines = Vec::with_capacity(rows);
    let mut start = buf.line_start(first);
    for line in first..=last.min(first + rows - 1) {
        let next = buf.line_start(line + 1);
        let from = (start + first_col).min(next);
        let to = (from + cols).min(next);
        lines.push(buf.slice(from, to).replace(EOB, "*"));
        start = next;
    }
    View {
        lines,
        pointer_row: cur - first,
        pointer_col: col - first_col,
        first_line: first,
        first_col,
    }
}
