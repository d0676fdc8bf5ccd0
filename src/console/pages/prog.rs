//! PROG: the directory of the programs in memory (name, language, size, last change; `>` on
//! the cursor, `*` on the current program; a G-code program's language is its dialect: ISO
//! LinuxCNC's, FAN Fanuc's, and the current one's is named in the header) and what can be done to them, with the machine stopped and no
//! run loaded, every change journaled:
//! - Enter with nothing typed: make the program under the cursor current;
//! - `C NAME` Enter: copy it as NAME (the copy becomes current);
//! - `R NAME` Enter: rename it;
//! - `D` Enter: delete it: the page asks, and `D` Enter again deletes it (anything else
//!   cancels). Program memory keeps at least one program.

use super::super::display::{message_lines, split_line, Page as Frame};
use super::Console;
use novanc_panel::Key;

/// The language of a program, by its first line: ISO G-code (`%` or `O<number>`) or the source
/// language (AP).
pub fn language(first_line: &str) -> &'static str {
    let l = first_line.trim();
    let o_number = l
        .strip_prefix(['O', 'o'])
        .is_some_and(|r| r.starts_with(|c: char| c.is_ascii_digit()));
    if l.starts_with('%') || o_number {
        "ISO"
    } else {
        "AP"
    }
}

/// Moves the cursor.
pub(super) fn arrow(c: &mut Console, k: Key) {
    let n = c.mem.program_names().len();
    let r = &mut c.pages.prog_row;
    match k {
        Key::Down | Key::PageDown => *r = (*r + 1).min(n.saturating_sub(1)),
        Key::Up | Key::PageUp => *r = r.saturating_sub(1),
        Key::Home => *r = 0,
        Key::End => *r = n.saturating_sub(1),
        _ => {}
    }
    c.pages.confirm_delete = None;
}

/// A PROG page command line.
pub(super) fn enter(c: &mut Console, line: &str) -> Result<String, String> {
    let names = c.mem.program_names();
    let Some(name) = names.get(c.pages.prog_row.min(names.len().saturating_sub(1))) else {
        return Err("PROG: memory holds no program".into());
    };
    let name = name.clone();
    if c.status.job.is_some() || c.running() {
        return Err("PROG refused: a run is loaded; RESET first".into());
    }
    let l = line.trim();
    let up = l.to_ascii_uppercase();
    let confirm = c.pages.confirm_delete.take();
    let r = if l.is_empty() {
        c.mem
            .select_program(&name)
            .map(|()| format!("program {name} is current"))
    } else if up == "D" {
        if confirm.as_deref() == Some(name.as_str()) {
            c.mem
                .delete_program(&name)
                .map(|()| format!("program {name} deleted"))
        } else {
            c.pages.confirm_delete = Some(name.clone());
            Ok(format!(
                "delete {name}? D Enter again deletes it, anything else keeps it"
            ))
        }
    } else if let Some(to) = up.strip_prefix("C ") {
        c.mem
            .copy_program(&name, to.trim())
            .map(|()| format!("{name} copied as {}", to.trim()))
    } else if let Some(to) = up.strip_prefix("R ") {
        c.mem
            .rename_program(&name, to.trim())
            .map(|()| format!("{name} renamed {}", to.trim()))
    } else {
        Err("PROG: Enter selects; C NAME copies, R NAME renames, D deletes (asked twice)".into())
    };
    if c.pages.confirm_delete.is_none() && c.search.is_some() {
        c.search = None;
    }
    let n = c.mem.program_names().len();
    c.pages.prog_row = c.pages.prog_row.min(n.saturating_sub(1));
    r.map_err(|e| format!("PROG refused: {e}"))
}

/// The PROG page. At 56 columns and more: name, language, lines, characters and the date and
/// time of the last change; narrower: a shorter name, no line count, and the change without
/// the year.
pub(super) fn compose(c: &Console, rows: usize, cols: usize) -> Vec<String> {
    let list = c.mem.program_list();
    let current = c.mem.program_name();
    let machine = c.cfg.settings.dialect;
    // The current G-code program and the dialect it is read in (docs/gcode.md "Fanuc dialect").
    let head = if c.mem.program_is_gcode() {
        let d = c.mem.program_dialect(&current, machine);
        format!("PROG  {current} {}", d.name().to_ascii_uppercase())
    } else {
        "PROG".to_string()
    };
    let mut p = Frame::new(
        rows,
        cols,
        split_line(&head, &format!("{} programs", list.len()), cols),
    );
    p.bottom = message_lines(c, cols, (rows / 4).max(1));
    p.bottom.push(format!("> {}_", c.shell.front.entry));
    let n = p.body_rows().saturating_sub(1);
    let wide = cols >= 56;
    let name_w = if wide { 16 } else { 12 };
    let changed = |t: Option<u64>| -> String {
        match t {
            Some(t) if wide => crate::store::stamps::format_local(t),
            Some(t) => crate::store::stamps::format_local(t)[5..].to_string(),
            None => "-".into(),
        }
    };
    p.body.push(if wide {
        format!(
            "  {:<16} {:<4} {:>7} {:>7} {}",
            "NAME", "LANG", "LINES", "CHARS", "CHANGED"
        )
    } else {
        format!("  {:<12} {:<3} {:>7} {}", "NAME", "LNG", "CHARS", "CHANGED")
    });
    let row = c.pages.prog_row.min(list.len().saturating_sub(1));
    let first = row.saturating_sub(n.saturating_sub(1));
    for (i, info) in list.iter().enumerate().skip(first).take(n) {
        let mark = if i == row { '>' } else { ' ' };
        let cur = if info.name == current { '*' } else { ' ' };
        let mut name: String = info.name.chars().take(name_w).collect();
        if info.name.chars().count() > name_w {
            name.pop();
            name.push('…');
        }
        let gcode = crate::gcode::is_gcode(&info.name, "") || language(&info.first_line) == "ISO";
        let lang = match (gcode, c.mem.program_dialect(&info.name, machine)) {
            (false, _) => "AP",
            (true, crate::settings::Dialect::LinuxCnc) => "ISO",
            (true, crate::settings::Dialect::Fanuc) => "FAN",
        };
        let when = changed(info.changed_s);
        p.body.push(if wide {
            format!(
                "{mark}{cur}{name:<16} {lang:<4} {:>7} {:>7} {when}",
                info.lines, info.chars
            )
        } else {
            format!("{mark}{cur}{name:<12} {lang:<3} {:>7} {when}", info.chars)
        });
    }
    p.lines()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_language_is_read_from_the_first_line() {
        assert_eq!(language("%"), "ISO");
        assert_eq!(language("O1234 (part)"), "ISO");
        assert_eq!(language("DA1 = (200, 0, -450)"), "AP");
        assert_eq!(language("OX"), "AP");
    }
}
