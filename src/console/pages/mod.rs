//! The operator pages (`docs/panel.md`, "Pages"): POS, PROG, OFS and MSG, on a row of page
//! keys beside the patent's two selectors, as Fanuc's function keys sit beside its MDI keys.
//!
//! A page key shows its page on the plasma display in any mode; the same key again, or turning
//! either selector, goes back to the mode's display program. While a page is shown the arrow
//! keys move its cursor, the data keys type into the entry line (in any mode: what the page
//! accepts is its own rule, each one below), Enter is INPUT and Tab is +INPUT.
//!
//! - POS (`pos.rs`): work, relative, machine positions and distance to go; feed, spindle, jog
//!   and tool change; the counters. `X` INPUT zeroes the relative X, `X12.5` presets it.
//! - PROG (`prog.rs`): the programs in memory; select, copy, rename, delete (confirmed).
//! - OFS (`ofs.rs`): the tool file as a table; a value INPUT sets a cell, +INPUT adds to it;
//!   also during a feed hold and between single blocks (a length applies from the next block).
//!   After the last T code, the work offsets G54 to G59 (`workofs.rs`).
//! - MODAL (`modal.rs`, Ctrl-G): the active G codes of every modal group, F S T H D, the
//!   offsets in force, the overrides and the switches; read only.
//! - MSG (`msg.rs`): the alarm and message history, newest first, full text, kept across
//!   restarts.
//! - I/O (`io.rs`, Ctrl-T): the outputs and the simulated inputs; `P3 ON`, `E2 4.5` INPUT
//!   sets an input.
//! - MACRO (`macros.rs`, Ctrl-U): the Fanuc dialect's variables #1–#33, #100–#199 and
//!   #500–#999; INPUT as on OFS (`#500=12.5`, or a value at the cursor).

mod io;
pub(crate) mod macros;
mod measure;
pub(crate) mod modal;
pub(crate) mod msg;
mod ofs;
pub(crate) mod pos;
mod prog;
pub(crate) mod workofs;

use super::Console;
pub use crate::panel_model::Page;
use novanc_panel::Key;
pub(super) use pos::length_in_force;
pub(crate) use pos::{rotary_work_offset, work_origin};

pub use super::shell::Shown;

/// The pages' cursor rule (`shell::Shown`'s state).
impl Shown {
    /// A cursor key on the MSG page (a history of `history` entries: it scrolls) or the
    /// MACRO page (`room` rows: the variable cursor moves); whether the page shown took it.
    pub fn cursor(&mut self, k: Key, history: usize, room: usize) -> bool {
        match self.page {
            Page::Msg => msg::scroll(&mut self.msg_first, history, k),
            Page::Macro => self.macro_var = macros::cursor_moved(self.macro_var, k, room),
            _ => return false,
        }
        true
    }
}

/// The pages' state.
#[derive(Debug)]
pub struct Pages {
    /// The relative position's origin, pulses (the POS page).
    pub rel_origin: crate::block::Axes,
    /// The PROG page's cursor row.
    pub prog_row: usize,
    /// A delete waiting for its confirmation: the program's name.
    pub confirm_delete: Option<String>,
    /// The OFS page's cursor: T code and column; past the last T code, the work offset rows
    /// G54.. G59.
    pub ofs: (u32, usize),
    /// The OFS page's axis on the work offset rows (0 = X).
    pub ofs_axis: usize,
    /// A tool length revised on OFS while a run is loaded, not yet in force (POS marks it).
    pub pending_len: Option<PendingLength>,
}

/// A length revised during a run that the machine does not use yet: a source-language run
/// takes it from the next block, a G-code run from the next run (its G43 read the old one).
#[derive(Clone, Debug, PartialEq)]
pub struct PendingLength {
    /// The tool revised (in the spindle).
    pub tool: u32,
    /// The length in force (set length plus wear), mm.
    pub in_force: f64,
    /// The revised length, mm.
    pub revised: f64,
    /// The run's blocks completed when it was revised.
    pub blocks_done: u64,
    /// The run is a G-code run (the length applies from the next run).
    pub gcode: bool,
}

impl Pages {
    /// The pages as a console opens: the mode's display shown.
    pub(in crate::console) fn new() -> Pages {
        Pages {
            rel_origin: Default::default(),
            prog_row: 0,
            confirm_delete: None,
            ofs: (1, ofs::LENGTH),
            ofs_axis: 0,
            pending_len: None,
        }
    }
}

pub use super::entry::{Recall, RECALL};

/// The page key's page, for the keys of the row of page keys.
pub fn page_of_key(k: Key) -> Option<Page> {
    match k {
        Key::Ctrl('p') => Some(Page::Pos),
        Key::Ctrl('d') => Some(Page::Prog),
        Key::Ctrl('o') => Some(Page::Ofs),
        Key::Ctrl('e') => Some(Page::Msg),
        Key::Ctrl('g') => Some(Page::Modal),
        Key::Ctrl('t') => Some(Page::Io),
        Key::Ctrl('u') => Some(Page::Macro),
        _ => None,
    }
}

/// A page key: its page, or back to the mode's display if it is shown already.
pub(super) fn page_key(c: &mut Console, p: Page) {
    c.shell.shown.key(p);
    c.pages.confirm_delete = None;
}

/// A key while a page is shown; whether the page took it.
pub(super) fn press(c: &mut Console, k: Key) -> bool {
    let page = c.shell.shown.page;
    let take = match k {
        k if super::keys::is_cursor_key(k) => {
            match page {
                Page::Prog => prog::arrow(c, k),
                Page::Ofs => ofs::arrow(c, k),
                Page::Msg | Page::Macro => {
                    let n = c.shell.book.log.history.entries().len();
                    let room = c.cfg.rows.saturating_sub(4);
                    c.shell.shown.cursor(k, n, room);
                }
                Page::Pos | Page::Modal | Page::Io | Page::Mode => return false,
            }
            true
        }
        Key::Enter => {
            // INPUT: the one entry rule; a refused value stays on the entry line. (Tab, +INPUT
            // with a value typed, is the key pipeline's: `keys::tab_adds`.)
            let line = std::mem::take(&mut c.shell.front.entry);
            super::entry::enter(c, super::entry::To::Page(page), line, false);
            true
        }
        Key::Char(ch) => {
            // A full line refuses the key and says so, as everywhere (before stop 41 a page
            // dropped the 241st key in silence).
            c.shell.front.key(ch);
            true
        }
        Key::Backspace => {
            c.shell.front.entry.pop();
            true
        }
        _ => false,
    };
    // The one pipeline records the key and shows the state after it (`keys::takes_first`).
    take
}

/// A line entered on the page shown: INPUT (or +INPUT with `add`). Ok: what it did; Err: why
/// it is refused, and the line stays on the entry line beside the reason (`entry::enter`), as
/// a Fanuc keeps its key-in buffer on a refused INPUT.
pub(super) fn enter(c: &mut Console, line: &str, add: bool) -> Result<String, String> {
    match c.shell.shown.page {
        Page::Pos => pos::enter(c, line),
        Page::Prog => prog::enter(c, line),
        Page::Ofs => ofs::enter(c, line, add),
        Page::Msg => Err("MSG: the history is read only; Up/Down scroll it".into()),
        Page::Modal => {
            Err("MODAL: the state is read only; MDI sets it (G55, G91, F300 ...)".into())
        }
        Page::Io => io::enter(c, line),
        Page::Macro => macros::enter(c, line, add),
        Page::Mode => Err("the mode display takes no line".into()),
    }
}

/// The page's display frame.
pub(super) fn compose(c: &Console, rows: usize, cols: usize) -> Vec<String> {
    match c.shell.shown.page {
        Page::Pos => pos::compose(c, rows, cols),
        Page::Prog => prog::compose(c, rows, cols),
        Page::Ofs => ofs::compose(c, rows, cols),
        Page::Modal => modal::compose(c, rows, cols),
        Page::Io => io::compose(c, rows, cols),
        Page::Macro => macros::compose(c, rows, cols),
        Page::Msg | Page::Mode => msg::compose(c, rows, cols),
    }
}
