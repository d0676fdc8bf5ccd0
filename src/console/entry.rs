//! The data keys and the entry line: where a typed line goes (docs/panel.md, "Rules"), one rule
//! over every machine's side (`Side`; issue 22: each console had its own before stop 45).
//!
//! - On an operator page (POS, PROG, OFS, MACRO ...): to the page, in any mode (INPUT, or
//!   +INPUT with Tab).
//! - In MDI (the operation selector): to the MDI buffer (the centre's one line, a lathe
//!   channel's lines), and START runs it; the last lines are kept for recall (Up and Down).
//! - In DATA INPUT: to the editor on the buffer of the data mode, or to the data mode's own use
//!   (SEARCH, T-CODE SETTING).
//! - In another position: to the machine's own use, where it has one (a lathe's TARGET and
//!   FAULT take the typed line).
//!
//! The machine may refuse the data keys where it has no use for them (the centre in AUTO, or
//! in DATA INPUT while it runs): each key is refused with the reason. A line the machine
//! refuses at EOB stays on the entry line beside the reason, to be entered again or corrected
//! with Backspace, on every machine and in every position (before stop 45 the centre dropped a
//! refused MDI or editor line, and only a page kept it).

use super::side::Side;
use super::{run, search, tcode, Console};
use crate::panel_model::{DataMode, OpMode, Page};
use crate::store::Target;

/// Where the data keys type now, on every console.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum To {
    /// The page up over the mode display.
    Page(Page),
    /// MDI: the selected channel's MDI buffer.
    Mdi,
    /// DATA INPUT: the editor or the data mode's own use.
    Data,
    /// Another position of the operation selector: the machine's own use, if any.
    Other,
}

/// Where the data keys go now, or, said on the display, why the machine refuses them.
fn target<C: Side>(c: &mut C, what: &str) -> Option<To> {
    let page = c.page();
    let to = if page != Page::Mode {
        To::Page(page)
    } else {
        match c.front().op {
            OpMode::Mdi => To::Mdi,
            OpMode::Data => To::Data,
            _ => To::Other,
        }
    };
    match c.takes_keys(to) {
        Ok(()) => Some(to),
        Err(e) => {
            c.front().message = format!("{what} refused: {e}");
            None
        }
    }
}

/// One data key.
pub(crate) fn key<C: Side>(c: &mut C, ch: char) {
    if target(c, &format!("key '{ch}'")).is_some() {
        c.front().key(ch);
    }
}

/// RUBOUT.
pub(crate) fn rubout<C: Side>(c: &mut C) {
    if target(c, "RUBOUT").is_some() {
        c.front().entry.pop();
    }
}

/// EOB (INPUT on a page): the line typed is entered where it goes.
pub(crate) fn eob<C: Side>(c: &mut C) {
    if let Some(to) = target(c, "EOB") {
        let line = std::mem::take(&mut c.front().entry);
        enter(c, to, line, false);
    }
}

/// +INPUT (`plusinput`, the keypad's key): on a page, the line typed is added to the cell
/// under its cursor (a page that has no cells takes it as INPUT); elsewhere it is refused, the
/// line kept, since only a page has a cell to add to. One key on every machine: on a lathe the
/// keyboard's Tab with nothing typed turns the channel selector, so the keypad's +INPUT is this
/// event, never Tab (before stop 46 the lathe's keypad had no +INPUT).
pub(crate) fn plus_input<C: Side>(c: &mut C) {
    let Some(to) = target(c, "+INPUT") else {
        return;
    };
    let line = std::mem::take(&mut c.front().entry);
    if let To::Page(_) = to {
        return enter(c, to, line, true);
    }
    let f = c.front();
    f.message = "+INPUT refused: it adds to the cell under a page's cursor (OFS, MACRO); EOB enters the line here".into();
    f.entry = line;
}

/// A whole line typed, then EOB (`type TEXT`).
pub(crate) fn typed<C: Side>(c: &mut C, text: &str) {
    if let Some(to) = target(c, &format!("'{text}'")) {
        // The line typed takes the entry line's place.
        c.front().entry.clear();
        let line = text.chars().filter(|c| !c.is_control()).collect();
        enter(c, to, line, false);
    }
}

/// Enters `line` at `to` (with `add`, +INPUT on a page): the machine's use of it. A line it
/// refuses stays on the entry line beside the reason: nothing typed is lost.
pub(crate) fn enter<C: Side>(c: &mut C, to: To, line: String, add: bool) {
    if to == To::Data {
        // A `Y` type-out shows until the next line (docs/editor.md).
        c.front().y_output = None;
    }
    if let Err(e) = c.enter_line(to, &line, add) {
        let f = c.front();
        f.message = e;
        f.entry = line;
    }
}

/// Up or Down in MDI, on the mode display or a page that has no use for them (the pages that
/// do take them first): the selected channel's previous or next line typed, on the entry line.
/// Whether `k` was one of them. One rule since stop 45 (a lathe's POS page took Up as a jog,
/// refused in MDI, where the centre's recalled).
pub(crate) fn recall_key<C: Side>(c: &mut C, k: novanc_panel::Key) -> bool {
    use novanc_panel::Key;
    if c.front().op != OpMode::Mdi || !matches!(k, Key::Up | Key::Down) {
        return false;
    }
    match c.recall().step(k == Key::Up) {
        Some(l) => c.front().entry = l,
        None => c.front().message = "MDI: no line to recall".into(),
    }
    true
}

/// The MDI lines kept for recall.
pub const RECALL: usize = 20;

/// The MDI lines last typed, for recall with Up and Down (every console's: the centre's MDI,
/// each channel's of a lathe): oldest first, and where the recall stands.
#[derive(Debug, Default)]
pub struct Recall {
    /// The lines, oldest first (the last [`RECALL`]).
    pub lines: Vec<String>,
    at: Option<usize>,
}

impl Recall {
    /// Keeps an MDI line for recall (the last [`RECALL`]).
    pub fn remember(&mut self, line: &str) {
        if line.trim().is_empty() || self.lines.last().is_some_and(|l| l == line) {
            self.at = None;
            return;
        }
        self.lines.push(line.to_string());
        if self.lines.len() > RECALL {
            self.lines.remove(0);
        }
        self.at = None;
    }

    /// The recalled line one step back (`back`) or forward, if any.
    pub fn step(&mut self, back: bool) -> Option<String> {
        if self.lines.is_empty() {
            return None;
        }
        let n = self.lines.len();
        let at = match (self.at, back) {
            (None, true) => n - 1,
            (None, false) => return None,
            (Some(i), true) => i.saturating_sub(1),
            (Some(i), false) if i + 1 < n => i + 1,
            (Some(_), false) => {
                self.at = None;
                return Some(String::new());
            }
        };
        self.at = Some(at);
        self.lines.get(at).cloned()
    }
}

/// The centre's refusal of the data keys at `to`: outside DATA INPUT, MDI and the pages, and in
/// DATA INPUT while the machine runs.
pub(super) fn centre_takes_keys(c: &Console, to: To) -> Result<(), String> {
    match to {
        To::Page(_) | To::Mdi => Ok(()),
        To::Data if c.running() => Err("the machine is running".into()),
        To::Data => Ok(()),
        To::Other => Err(format!(
            "data keys work in DATA INPUT, MDI or on a page (now {})",
            c.shell.front.op.name()
        )),
    }
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

/// The editor's cursor keys (arrows, PgUp/PgDn, Home/End) and Delete in DATA INPUT on the
/// mode display, on every machine: on the buffer the machine edits there (`Side::cursor_command`:
/// the centre's data mode's, PROGRAM REVISION, MDI, TOOL DATA REVISION; a lathe's selected
/// channel's program), beside the letter commands, as Fanuc's EDIT screen has them
/// (docs/editor.md, "Cursor keys"). Each is the editor command it stands for
/// ([`cursor_command`]), run and stored as a typed one is (`Side::edit`); the line being typed
/// stays on the entry line. Returns false for a key that is not one of these here (the key then
/// does what it does elsewhere). Before stop 45 each console had its own, and the centre's
/// moved the pointer under a page that hid it.
pub(crate) fn cursor_key<C: Side>(c: &mut C, k: novanc_panel::Key) -> bool {
    if c.page() != Page::Mode || c.front().op != OpMode::Data {
        return false;
    }
    let Some((name, command)) = c.cursor_command(k) else {
        return false;
    };
    if let Err(e) = c.takes_keys(To::Data) {
        c.front().message = format!("{name} refused: {e}");
        return true;
    }
    // A `Y` type-out gives way to the listing the pointer moves in (docs/editor.md).
    c.front().y_output = None;
    let said = match command {
        Err(e) => e,
        Ok(cmd) => match c.edit(&cmd) {
            Ok(note) => note,
            Err(e) if cmd == "1D" => format!("Delete: nothing after the pointer ({e})"),
            Err(e) if e.starts_with(name) => e,
            Err(e) => format!("{name}: {e}"),
        },
    };
    c.front().message = said;
    true
}

/// The command cursor key `k` stands for on the centre's buffer of the DATA editor now (a page
/// is the display's text rows); the buffer is read in place, not copied.
pub(super) fn centre_cursor_command(
    c: &Console,
    k: novanc_panel::Key,
) -> Option<(&'static str, Result<String, String>)> {
    let t = edited(c.data)?;
    cursor_command(c.mem.buffer(t), k, c.cfg.text_rows())
}

/// The buffer a data mode edits.
fn edited(d: DataMode) -> Option<Target> {
    match d {
        DataMode::Revise => Some(Target::Program),
        DataMode::Mdi => Some(Target::Mdi),
        DataMode::ToolRevise => Some(Target::ToolFile),
        _ => None,
    }
}

/// An editor command on the centre's buffer of the DATA editor (a cursor key's), journaled; a
/// note to say (the SEARCH point cleared by a program changed), or why it is refused.
pub(super) fn centre_edit(c: &mut Console, command: &str) -> Result<String, String> {
    let t = edited(c.data).ok_or("no buffer is edited in this data mode")?;
    let rev = c.mem.rev();
    c.mem.edit(t, command, None)?;
    let mut note = String::new();
    if t == Target::Program && c.mem.rev() != rev && c.search.is_some() {
        c.search = None;
        note = "SEARCH point cleared (program changed)".into();
    }
    run::recheck_program_alarm(c);
    Ok(note)
}

/// MDI at the keys: the line becomes the MDI buffer (START runs it).
pub(super) fn mdi_line(c: &mut Console, line: &str) -> Result<(), String> {
    if line.trim().is_empty() {
        return Err("MDI: type a statement or a G-code line, Enter, then START".into());
    }
    c.shell.recall[0].remember(line);
    if c.status.job.is_some() {
        return Err("MDI refused: a run is loaded; RESET first".into());
    }
    let set = c.mem.set_mdi(line);
    run::recheck_program_alarm(c);
    set.map_err(|e| format!("MDI refused: {e}"))?;
    c.shell.front.message = "MDI buffer set: START runs it".into();
    Ok(())
}

/// A command line ended with EOB, in DATA INPUT with RUN = 0.
pub(super) fn data_line(c: &mut Console, line: &str) -> Result<(), String> {
    c.last_line = line.to_string();
    let target = match c.data {
        DataMode::Revise => Target::Program,
        DataMode::Mdi => Target::Mdi,
        DataMode::ToolRevise => Target::ToolFile,
        DataMode::TCode => return tcode::enter(c, line),
        DataMode::Search => return search::enter(c, line),
        DataMode::Read | DataMode::ToolRead => {
            return Err("put the tape in the reader and press START to read it".into());
        }
    };
    let rows = c.cfg.text_rows();
    let rev = c.mem.rev();
    let y = c.mem.edit(target, line, Some(rows))?;
    if !y.is_empty() {
        c.shell.front.y_output = Some(y);
    }
    c.shell.front.message = "ok".into();
    if target == Target::Program && c.mem.rev() != rev && c.search.is_some() {
        c.search = None;
        c.shell.front.message = "ok; SEARCH point cleared (program changed)".into();
    }
    run::recheck_program_alarm(c);
    Ok(())
}
