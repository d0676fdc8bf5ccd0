//! MSG: the alarm and message history with the time of day (and the date on a wide display), newest first, each in full (wrapped,
//! never cut), kept across restarts (`store::history`). Up and Down scroll it. Every console
//! shows its history so: the centre on this page, a lathe in its plasma display
//! ([`body`], [`scroll`]).

use super::super::display::{split_line, wrap, Page as Frame};
use super::Console;
use crate::store::history::{Entry, Kind};
use novanc_panel::Key;

/// A cursor key on a history of `n` entries whose first shown is `first` (0: the newest):
/// Down and PgDn show older ones, Up and PgUp newer ones, Home the newest, End the oldest.
pub(crate) fn scroll(first: &mut usize, n: usize, k: Key) {
    match k {
        Key::Down | Key::PageDown => *first = (*first + 1).min(n.saturating_sub(1)),
        Key::Up | Key::PageUp => *first = first.saturating_sub(1),
        Key::Home => *first = 0,
        Key::End => *first = n.saturating_sub(1),
        _ => {}
    }
}

/// The MSG page.
pub(super) fn compose(c: &Console, rows: usize, cols: usize) -> Vec<String> {
    let all = c.shell.book.log.history.entries();
    let mut p = Frame::new(
        rows,
        cols,
        split_line("MSG", &format!("{} entries", all.len()), cols),
    );
    p.body = body(all, c.shell.shown.msg_first, p.body_rows(), cols);
    p.lines()
}

/// The MSG page's body on every machine (the centre's page, a lathe's display under its
/// channel lines): [`history_lines`] in `rows` lines of `cols` characters, the last line
/// ending in `CUT` where an entry goes on below (said, not cut silently).
pub(crate) fn body(all: &[Entry], first: usize, rows: usize, cols: usize) -> Vec<String> {
    let mut body = history_lines(all, first, rows, cols);
    if body.len() > rows {
        body.truncate(rows);
        if let Some(last) = body.last_mut() {
            let keep: String = last.chars().take(cols.saturating_sub(1)).collect();
            *last = format!("{keep}{}", super::super::display::CUT);
        }
    }
    body
}

/// The history `all` as lines of `cols` characters, newest first from the `first`-th newest,
/// each entry in full (wrapped, its continuation indented), at most `most` lines.
fn history_lines(all: &[Entry], first: usize, most: usize, cols: usize) -> Vec<String> {
    let mut body = Vec::new();
    if all.is_empty() {
        body.push("(no alarm or message yet)".into());
    }
    for e in all.iter().rev().skip(first) {
        if body.len() >= most {
            break;
        }
        let kind = match e.kind {
            Kind::Alarm => "ALARM ",
            Kind::Message => "",
        };
        // The wall clock, as the operator's watch reads it: the time of day, and the date too
        // on a wide display; machine time for entries kept before the wall clock was.
        let when = match e.wall_s {
            Some(w) => {
                let full = crate::store::stamps::format_local_seconds(w);
                if cols >= 56 {
                    full
                } else {
                    full.get(11..).unwrap_or(&full).to_string()
                }
            }
            None => format!("{:.1} s", e.machine_ns as f64 / 1e9),
        };
        let text = format!("{when} {kind}{}", e.text);
        // Full text: wrapped on as many lines as it needs, the continuation indented.
        for (i, l) in wrap(&text, cols.saturating_sub(2), usize::MAX)
            .into_iter()
            .enumerate()
        {
            body.push(if i == 0 { l } else { format!("  {l}") });
        }
    }
    body
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_body_that_goes_on_below_ends_in_the_cut_mark_on_every_machine() {
        let e = |ns: u64, text: &str| Entry {
            machine_ns: ns,
            wall_s: None,
            kind: Kind::Message,
            text: text.into(),
        };
        let all = [
            e(1_000_000_000, &"word ".repeat(30)),
            e(2_000_000_000, "new"),
        ];
        // Newest first; the older entry wraps over the rows left, and its last shown line
        // says it goes on.
        let b = body(&all, 0, 3, 30);
        assert_eq!(b.len(), 3);
        assert!(b[0].ends_with("new"), "{b:?}");
        assert!(b[2].ends_with(crate::console::display::CUT), "{b:?}");
        assert!(b.iter().all(|l| l.chars().count() <= 30), "{b:?}");
        // Room for all: nothing marked.
        let b = body(&all, 0, 20, 30);
        assert!(!b.iter().any(|l| l.contains(crate::console::display::CUT)));
        assert_eq!(body(&[], 0, 3, 30), ["(no alarm or message yet)"]);
    }
}
