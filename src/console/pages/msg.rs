//! MSG: the alarm and message history with the time of day (and the date on a wide display), newest first, each in full (wrapped,
//! never cut), kept across restarts (`store::history`). Up and Down scroll it. Every console
//! shows its history so: the centre on this page, a lathe in its plasma display
//! ([`history_lines`], [`scroll`]).

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
    let n = p.body_rows();
    p.body = history_lines(all, c.shell.shown.msg_first, n, cols);
    if p.body.len() > n {
        // The rest is further down: said, not cut silently.
        p.body.truncate(n);
        if let Some(last) = p.body.last_mut() {
            let keep: String = last.chars().take(cols.saturating_sub(1)).collect();
            *last = format!("{keep}{}", super::super::display::CUT);
        }
    }
    p.lines()
}

/// The history `all` as lines of `cols` characters, newest first from the `first`-th newest,
/// each entry in full (wrapped, its continuation indented), at most `most` lines.
pub(crate) fn history_lines(all: &[Entry], first: usize, most: usize, cols: usize) -> Vec<String> {
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
