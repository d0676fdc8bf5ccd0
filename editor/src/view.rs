//! The display of a buffer around its pointer (docs/editor.md: "the display shows the text around the
//! pointer, with the pointer marked"). Costs a few line look-ups, whatever the buffer size.

use crate::{Buffer, EOB};

/// Up to this many characters, the shown lines are fetched in one slice.
const QUICK: usize = 64 * 1024;

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
    view_with(buf, rows, cols, QUICK)
}

/// Builds the view, fetching the lines in one slice when they hold at most `quick` characters.
fn view_with(buf: &Buffer, rows: usize, cols: usize, quick: usize) -> View {
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
    let shown_last = last.min(first.saturating_add(rows - 1));
    let start = buf.line_start(first);
    let end = buf.line_start(shown_last + 1);
    let mut lines = Vec::with_capacity(shown_last - first + 1);
    if end - start <= quick {
        // One slice, cut into lines: a few chunk look-ups in all.
        let text = buf.slice(start, end);
        let mut rest = text.as_str();
        for _ in first..=shown_last {
            let (line, next) = match rest.find(EOB) {
                Some(i) => (&rest[..=i], &rest[i + 1..]),
                None => (rest, ""),
            };
            lines.push(
                line.chars()
                    .skip(first_col)
                    .take(cols)
                    .collect::<String>()
                    .replace(EOB, "*"),
            );
            rest = next;
        }
    } else {
        // Long lines: fetch only the visible columns of each.
        let mut start = start;
        for line in first..=shown_last {
            let next = buf.line_start(line + 1);
            let from = (start + first_col).min(next);
            let to = from.saturating_add(cols).min(next);
            lines.push(buf.slice(from, to).replace(EOB, "*"));
            start = next;
        }
    }
    View {
        lines,
        pointer_row: cur - first,
        pointer_col: col - first_col,
        first_line: first,
        first_col,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn huge_displays_do_not_overflow() {
        let mut b = Buffer::from_text("a\nbb\nccc");
        b.set_pointer(5);
        let v = b.view(usize::MAX, usize::MAX);
        assert_eq!(v.lines, vec!["a*", "bb*", "ccc"]);
        assert_eq!((v.pointer_row, v.pointer_col, v.first_line), (2, 0, 0));
    }

    #[test]
    fn the_quick_and_the_long_line_paths_agree() {
        let text = "N1 G00\n\nN2 X10 Y20 Z30 F100\nñé€\nN4\n\n\nN8 M30";
        let mut b = Buffer::from_text(text);
        for p in 0..=b.len() {
            b.set_pointer(p);
            for rows in 0..6 {
                for cols in 0..12 {
                    let quick = view_with(&b, rows, cols, usize::MAX);
                    assert_eq!(quick, view_with(&b, rows, cols, 0), "p {p} {rows}x{cols}");
                    if rows > 0 {
                        assert!(quick.lines.len() <= rows);
                        assert!(quick.lines.iter().all(|l| l.chars().count() <= cols));
                        assert!(cols == 0 || quick.pointer_col < cols);
                        assert_eq!(quick.first_line + quick.pointer_row, b.line_of(p));
                    }
                }
            }
        }
    }
}
