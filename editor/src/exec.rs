//! Running a command line (patent Fig. 21, routines (i)–(viii)) atomically, with an undo log of
//! the edits done so far in the line: on a failure they are undone in reverse order.

use crate::parse::parse_typed;
use crate::{Buffer, Command, EditError, ExecOptions, Outcome, EOB};

/// One edit done in the current line, enough to undo it.
enum Undo {
    /// `n` characters were inserted at `pos`.
    Inserted { pos: usize, n: usize },
    /// `text` was removed from `pos`.
    Removed { pos: usize, text: String },
}

/// Runs `line` on `buf`; on any failure restores the text and pointer and names the command.
pub fn execute(buf: &mut Buffer, line: &str, opts: &ExecOptions) -> Result<Outcome, EditError> {
    let commands = parse_typed(line)?;
    let saved_pointer = buf.pointer;
    let mut log = Vec::new();
    let mut out = Outcome::default();
    let mut last_edit = None;
    for (index, typed) in commands.iter().enumerate() {
        let before = log.len();
        if let Err(reason) = run(buf, &typed.command, opts, &mut log, &mut out.y_output) {
            rollback(buf, log, saved_pointer);
            return Err(EditError {
                index,
                command: typed.typed.clone(),
                reason,
            });
        }
        if log.len() > before {
            last_edit = Some(index);
        }
    }
    out.changed = !log.is_empty();
    if let (Some(index), Some(validator)) = (last_edit, opts.validator) {
        if let Err(reason) = validator(buf) {
            rollback(buf, log, saved_pointer);
            return Err(EditError {
                index,
                command: commands[index].typed.clone(),
                reason,
            });
        }
    }
    Ok(out)
}

/// Undoes the logged edits, newest first, and puts the pointer back.
fn rollback(buf: &mut Buffer, log: Vec<Undo>, pointer: usize) {
    for undo in log.into_iter().rev() {
        match undo {
            Undo::Inserted { pos, n } => {
                buf.text.remove(pos, pos + n);
            }
            Undo::Removed { pos, text } => {
                buf.text.insert(pos, &text);
            }
        }
    }
    buf.pointer = pointer;
}

/// A count's size as a usize (saturating).
fn size(n: i64) -> usize {
    usize::try_from(n.unsigned_abs()).unwrap_or(usize::MAX)
}

/// Removes `start..end` and logs it.
fn remove(buf: &mut Buffer, start: usize, end: usize, log: &mut Vec<Undo>) {
    if end > start {
        let text = buf.text.remove(start, end);
        log.push(Undo::Removed { pos: start, text });
    }
}

/// Inserts `s` at `pos`, logs it, and returns the number of characters inserted.
fn insert(buf: &mut Buffer, pos: usize, s: &str, log: &mut Vec<Undo>) -> usize {
    let n = buf.text.insert(pos, s);
    if n > 0 {
        log.push(Undo::Inserted { pos, n });
    }
    n
}

/// The text as an operator reads it: EOB shown as `*`.
fn shown(s: &str) -> String {
    s.replace(EOB, "*")
}

/// Runs one command; Err is the reason it failed.
fn run(
    buf: &mut Buffer,
    command: &Command,
    opts: &ExecOptions,
    log: &mut Vec<Undo>,
    y_output: &mut String,
) -> Result<(), String> {
    let p = buf.pointer;
    let len = buf.text.len();
    match command {
        Command::L(n) => {
            buf.pointer = if *n > 0 {
                buf.text.after_eobs(p, size(*n))
            } else {
                buf.text.lines_back(p, size(*n))
            };
        }
        Command::M(m) => {
            let target = p as i128 + *m as i128;
            if target < 0 || target > len as i128 {
                return Err(format!(
                    "pointer would leave the buffer (pointer {p}, length {len})"
                ));
            }
            buf.pointer = target as usize;
        }
        Command::K(n) => {
            if *n > 0 {
                let end = buf.text.after_eobs(p, size(*n));
                remove(buf, p, end, log);
            } else {
                let start = buf.text.lines_back(p, size(*n));
                remove(buf, start, p, log);
                buf.pointer = start;
            }
        }
        Command::D(n) => {
            let k = size(*n);
            if *n >= 0 {
                if k > len - p {
                    return Err(format!("only {} characters after the pointer", len - p));
                }
                remove(buf, p, p + k, log);
            } else {
                if k > p {
                    return Err(format!("only {p} characters before the pointer"));
                }
                remove(buf, p - k, p, log);
                buf.pointer = p - k;
            }
        }
        Command::I(text) => {
            buf.pointer = p + insert(buf, p, text, log);
        }
        Command::S(pat) => {
            let start = find(buf, p, pat)?;
            buf.pointer = start + pat.chars().count();
        }
        Command::C(old, new) => {
            let start = find(buf, p, old)?;
            remove(buf, start, start + old.chars().count(), log);
            buf.pointer = start + insert(buf, start, new, log);
        }
        Command::Y(n) => {
            let (start, mut end) = if *n > 0 {
                (p, buf.text.after_eobs(p, size(*n)))
            } else if *n == 0 {
                (buf.text.line_start_at(p), p)
            } else {
                (buf.text.lines_back(p, size(*n)), p)
            };
            if let Some(max) = opts.y_max_lines {
                end = if max == 0 {
                    start
                } else {
                    end.min(buf.text.after_eobs(start, max))
                };
            }
            let shown = buf.text.slice(start, end);
            y_output.push_str(&shown);
            if !shown.is_empty() && !shown.ends_with(EOB) {
                y_output.push(EOB);
            }
        }
    }
    Ok(())
}

/// Where `pat` next occurs at or after `from`, or the reason it does not.
fn find(buf: &Buffer, from: usize, pat: &str) -> Result<usize, String> {
    if pat.is_empty() {
        return Err("search text is empty".to_string());
    }
    buf.text
        .find(from, pat)
        .ok_or_else(|| format!("'{}' not found", crate::parse::cut(&shown(pat))))
}
