//! The data keys and the entry line: where a typed line goes (docs/panel.md, "Rules").
//!
//! - On an operator page (POS, PROG, OFS): to the page, in any mode (the line is handed back
//!   to the console, which gives it to the page shown: the model names nothing of the pages).
//! - In MDI (the operation selector), as on a Fanuc MDI page: the line becomes the MDI buffer,
//!   and START runs it; the last lines are kept for recall (Up and Down).
//! - In DATA INPUT with the machine stopped: to the editor on the buffer of the data mode, or
//!   to SEARCH, T-CODE SETTING.
//! - Anywhere else the data keys are refused with a message, and the line is not kept.

use super::{run, search, tcode, Console};
use crate::panel_model::{DataMode, OpMode, Page};
use crate::store::Target;

/// Where the data keys type now.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum To {
    Page,
    Mdi,
    Data,
}

/// Where the data keys go now, or why they are refused (said on the display).
fn target(c: &mut Console, what: &str) -> Option<To> {
    if c.pages.page != Page::Mode {
        return Some(To::Page);
    }
    if c.front.op == OpMode::Mdi {
        return Some(To::Mdi);
    }
    if c.front.op != OpMode::Data {
        c.front.message = format!(
            "{what} refused: data keys work in DATA INPUT, MDI or on a page (now {})",
            c.front.op.name()
        );
        return None;
    }
    if c.running() {
        c.front.message = format!("{what} refused: the machine is running");
        return None;
    }
    Some(To::Data)
}

/// The longest entry line, characters: every console's (the centre's and the lathe's).
pub const ENTRY_MAX: usize = 240;

/// One data key on an entry line, every console's rule: a full line refuses the key and says
/// so (no key is lost in silence).
pub(crate) fn push_key(entry: &mut String, ch: char) -> Result<(), String> {
    if entry.chars().count() >= ENTRY_MAX {
        return Err(format!("the command line is full ({ENTRY_MAX} characters)"));
    }
    entry.push(ch);
    Ok(())
}

/// One data key.
pub(super) fn key(c: &mut Console, ch: char) {
    if target(c, &format!("key '{ch}'")).is_some() {
        c.front.key(ch);
    }
}

/// The editor command an editor cursor key (arrows, PgUp/PgDn, Home/End) or Delete stands for
/// on buffer `b`, every console's (docs/editor.md, "Cursor keys"): `nM` to move the pointer,
/// `1D` for Delete; `page` lines for PgUp and PgDn. None: not such a key. Err: why the pointer
/// cannot move (said on the message line; nothing is run).
pub(crate) fn cursor_command(
    b: &novanc_editor::Buffer,
    k: novanc_panel::Key,
    page: usize,
) -> Option<(&'static str, Result<String, String>)> {
    use super::memory::Cursor as C;
    use novanc_panel::Key as K;
    let (cursor, name) = match k {
        K::Left => (Some(C::Left), "Left"),
        K::Right => (Some(C::Right), "Right"),
        K::Up => (Some(C::Up), "Up"),
        K::Down => (Some(C::Down), "Down"),
        K::PageUp => (Some(C::PageUp), "PgUp"),
        K::PageDown => (Some(C::PageDown), "PgDn"),
        K::Home => (Some(C::Home), "Home"),
        K::End => (Some(C::End), "End"),
        K::Delete => (None, "Delete"),
        _ => return None,
    };
    let Some(cur) = cursor else {
        return Some((name, Ok("1D".into())));
    };
    let r = match super::memory::cursor_target(b, cur, page) {
        Ok(to) if to == b.pointer() => Err(format!("{name}: the pointer is there already")),
        Ok(to) => Ok(format!("{}M", to as i64 - b.pointer() as i64)),
        Err(e) => Err(format!("{name}: {e}")),
    };
    Some((name, r))
}

/// The editor's cursor keys (arrows, PgUp/PgDn, Home/End) and Delete in DATA INPUT, on the
/// buffer the data-processing mode edits (PROGRAM REVISION, MDI, TOOL DATA REVISION), beside
/// the letter commands, as Fanuc's EDIT screen has them (docs/editor.md, "Cursor keys"). Each
/// is the editor command it stands for ([`cursor_command`]), journaled like a typed one; the
/// line being typed stays on the entry line. Returns false for a key that is not one of these
/// here (the key then does what it does elsewhere).
pub(super) fn cursor_key(c: &mut Console, k: novanc_panel::Key) -> bool {
    let t = match (c.front.op, c.data) {
        (OpMode::Data, DataMode::Revise) => Target::Program,
        (OpMode::Data, DataMode::Mdi) => Target::Mdi,
        (OpMode::Data, DataMode::ToolRevise) => Target::ToolFile,
        _ => return false,
    };
    let Some((name, command)) = cursor_command(c.mem.buffer(t), k, c.cfg.text_rows()) else {
        return false;
    };
    if c.running() {
        c.front.message = format!("{name} refused: the machine is running");
        return true;
    }
    let command = match command {
        Ok(cmd) => cmd,
        Err(e) => {
            c.front.message = e;
            return true;
        }
    };
    let rev = c.mem.rev();
    match c.mem.edit(t, &command, None) {
        Ok(_) => {
            c.front.message = String::new();
            if t == Target::Program && c.mem.rev() != rev && c.search.is_some() {
                c.search = None;
                c.front.message = "SEARCH point cleared (program changed)".into();
            }
            run::recheck_program_alarm(c);
        }
        Err(e) if command == "1D" => {
            c.front.message = format!("Delete: nothing after the pointer ({e})");
        }
        Err(e) => c.front.message = format!("{name}: {e}"),
    }
    true
}

/// RUBOUT.
pub(super) fn rubout(c: &mut Console) {
    if target(c, "RUBOUT").is_some() {
        c.front.entry.pop();
    }
}

/// EOB: the line typed is entered. Returns the line when it is for the page shown.
#[must_use]
pub(super) fn eob(c: &mut Console) -> Option<String> {
    let to = target(c, "EOB")?;
    let line = std::mem::take(&mut c.front.entry);
    enter(c, to, line)
}

/// A whole line typed, then EOB (`type TEXT`). Returns the line when it is for the page shown.
#[must_use]
pub(super) fn typed(c: &mut Console, text: String) -> Option<String> {
    let to = target(c, &format!("'{text}'"))?;
    c.front.entry.clear();
    enter(c, to, text)
}

/// Enters a line where it goes; a line for the page shown is returned.
fn enter(c: &mut Console, to: To, line: String) -> Option<String> {
    match to {
        To::Page => return Some(line),
        To::Mdi => mdi_line(c, line),
        To::Data => enter_line(c, line),
    }
    None
}

/// MDI at the keys: the line becomes the MDI buffer (START runs it).
fn mdi_line(c: &mut Console, line: String) {
    if line.trim().is_empty() {
        c.front.message = "MDI: type a statement or a G-code line, Enter, then START".into();
        return;
    }
    c.pages.recall.remember(&line);
    if c.status.job.is_some() {
        c.front.message = "MDI refused: a run is loaded; RESET first (Up recalls the line)".into();
        return;
    }
    match c.mem.set_mdi(&line) {
        Ok(()) => c.front.message = "MDI buffer set: START runs it".into(),
        Err(e) => c.front.message = format!("MDI refused: {e} (Up recalls the line)"),
    }
    run::recheck_program_alarm(c);
}

/// Up or Down in MDI: the previous or next line typed into the entry line.
pub(super) fn recall(c: &mut Console, back: bool) {
    match c.pages.recall.step(back) {
        Some(l) => c.front.entry = l,
        None => c.front.message = "MDI: no line to recall".into(),
    }
}

/// A command line ended with EOB, in DATA INPUT with RUN = 0.
fn enter_line(c: &mut Console, line: String) {
    c.last_line = line.clone();
    c.front.y_output = None;
    let target = match c.data {
        DataMode::Revise => Target::Program,
        DataMode::Mdi => Target::Mdi,
        DataMode::ToolRevise => Target::ToolFile,
        DataMode::TCode => return tcode::enter(c, &line),
        DataMode::Search => return search::enter(c, &line),
        DataMode::Read | DataMode::ToolRead => {
            c.front.message = "put the tape in the reader and press START to read it".into();
            return;
        }
    };
    let rows = c.cfg.text_rows();
    let rev = c.mem.rev();
    match c.mem.edit(target, &line, Some(rows)) {
        Ok(y) => {
            if !y.is_empty() {
                c.front.y_output = Some(y);
            }
            c.front.message = "ok".into();
            if target == Target::Program && c.mem.rev() != rev && c.search.is_some() {
                c.search = None;
                c.front.message = "ok; SEARCH point cleared (program changed)".into();
            }
            run::recheck_program_alarm(c);
        }
        Err(e) => c.front.message = e,
    }
}
