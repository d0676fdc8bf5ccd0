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

mod measure;
mod modal;
mod msg;
mod ofs;
mod pos;
mod prog;
mod workofs;

use super::Console;
pub use crate::panel_model::Page;
use crate::store::history::{Counters, Entry, History, Kind};
use novanc_panel::Key;
pub(crate) use pos::work_origin;

/// The MDI lines kept for recall.
pub const RECALL: usize = 20;

/// The pages' state.
#[derive(Debug)]
pub struct Pages {
    /// The page shown (`Page::Mode`: the mode's display program).
    pub page: Page,
    /// The relative position's origin, pulses (the POS page).
    pub rel_origin: [i64; 3],
    /// The PROG page's cursor row.
    pub prog_row: usize,
    /// A delete waiting for its confirmation: the program's name.
    pub confirm_delete: Option<String>,
    /// The OFS page's cursor: T code and column; past the last T code, the work offset rows
    /// G54.. G59.
    pub ofs: (u32, usize),
    /// The OFS page's axis on the work offset rows (0 = X).
    pub ofs_axis: usize,
    /// The MSG page's first entry shown (0: the newest).
    pub msg_first: usize,
    /// The alarm and message history.
    pub history: History,
    /// The counters.
    pub counters: Counters,
    /// The last MDI lines typed, oldest first, and where the recall stands.
    pub recall: Vec<String>,
    recall_at: Option<usize>,
    /// The last message and alarm put in the history.
    logged: (String, String),
    /// The program's message taken since the last frame (a run's end says it too, so that the
    /// frame, and with it the recording, shows it).
    pub program_msg: Option<String>,
    /// A tool length revised on OFS while a run is loaded, not yet in force (POS marks it).
    pub pending_len: Option<PendingLength>,
    /// The jog feed chosen on POS (`JOG 500`), mm/min; None: the settings' jog feed.
    pub jog_feed: Option<f64>,
    /// Rapid jog (`JOG RAPID`): jogs at the rapid rate until `JOG` with a feed.
    pub rapid_jog: bool,
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
    /// The pages of a console whose state directory is `dir`, with the warnings of reading
    /// its history and counters.
    pub fn open(dir: &std::path::Path) -> (Pages, Vec<String>) {
        let (history, w1) = History::open(dir);
        let (counters, w2) = Counters::open(dir);
        (
            Pages {
                page: Page::Mode,
                rel_origin: [0; 3],
                prog_row: 0,
                confirm_delete: None,
                ofs: (1, ofs::LENGTH),
                ofs_axis: 0,
                msg_first: 0,
                history,
                counters,
                recall: Vec::new(),
                recall_at: None,
                logged: (String::new(), String::new()),
                program_msg: None,
                pending_len: None,
                jog_feed: None,
                rapid_jog: false,
            },
            w1.into_iter().chain(w2).collect(),
        )
    }

    /// Keeps an MDI line for recall (the last [`RECALL`]).
    pub fn remember(&mut self, line: &str) {
        if line.trim().is_empty() || self.recall.last().is_some_and(|l| l == line) {
            self.recall_at = None;
            return;
        }
        self.recall.push(line.to_string());
        if self.recall.len() > RECALL {
            self.recall.remove(0);
        }
        self.recall_at = None;
    }

    /// The recalled line one step back (`back`) or forward, if any.
    pub fn recall_step(&mut self, back: bool) -> Option<String> {
        if self.recall.is_empty() {
            return None;
        }
        let n = self.recall.len();
        let at = match (self.recall_at, back) {
            (None, true) => n - 1,
            (None, false) => return None,
            (Some(i), true) => i.saturating_sub(1),
            (Some(i), false) if i + 1 < n => i + 1,
            (Some(_), false) => {
                self.recall_at = None;
                return Some(String::new());
            }
        };
        self.recall_at = Some(at);
        self.recall.get(at).cloned()
    }
}

/// The page key's page, for the keys of the row of page keys.
pub fn page_of_key(k: Key) -> Option<Page> {
    match k {
        Key::Ctrl('p') => Some(Page::Pos),
        Key::Ctrl('d') => Some(Page::Prog),
        Key::Ctrl('o') => Some(Page::Ofs),
        Key::Ctrl('e') => Some(Page::Msg),
        Key::Ctrl('g') => Some(Page::Modal),
        _ => None,
    }
}

/// A page key: its page, or back to the mode's display if it is shown already.
pub(super) fn page_key(c: &mut Console, p: Page) {
    c.pages.page = if c.pages.page == p { Page::Mode } else { p };
    c.pages.confirm_delete = None;
    c.pages.msg_first = 0;
    c.entry.clear();
}

/// A key while a page is shown; whether the page took it.
pub(super) fn press(c: &mut Console, k: Key) -> bool {
    let page = c.pages.page;
    let take = match k {
        Key::Up
        | Key::Down
        | Key::Left
        | Key::Right
        | Key::PageUp
        | Key::PageDown
        | Key::Home
        | Key::End => {
            match page {
                Page::Prog => prog::arrow(c, k),
                Page::Ofs => ofs::arrow(c, k),
                Page::Msg => msg::arrow(c, k),
                Page::Pos | Page::Modal | Page::Mode => return false,
            }
            true
        }
        Key::Enter | Key::Tab => {
            let line = std::mem::take(&mut c.entry);
            enter(c, &line, k == Key::Tab);
            // A value that cannot be applied now stays on the entry line, beside the reason
            // (the operator INPUTs it again, or corrects it), as a Fanuc keeps its key-in
            // buffer on a refused INPUT.
            if c.entry.is_empty() && c.message.contains("refused") {
                c.entry = line;
            }
            true
        }
        Key::Char(ch) => {
            if c.entry.chars().count() < 240 {
                c.entry.push(ch);
            }
            true
        }
        Key::Backspace => {
            c.entry.pop();
            true
        }
        _ => false,
    };
    if take {
        c.refresh();
    }
    take
}

/// A line entered on the page shown: INPUT (or +INPUT with `add`).
pub(super) fn enter(c: &mut Console, line: &str, add: bool) {
    match c.pages.page {
        Page::Pos => pos::enter(c, line),
        Page::Prog => prog::enter(c, line),
        Page::Ofs => ofs::enter(c, line, add),
        Page::Msg => {
            c.message = "MSG: the history is read only; Up/Down scroll it".into();
        }
        Page::Modal => {
            c.message = "MODAL: the state is read only; MDI sets it (G55, G91, F300 ...)".into();
        }
        Page::Mode => {}
    }
}

/// The page's display frame.
pub(super) fn compose(c: &Console, rows: usize, cols: usize) -> Vec<String> {
    match c.pages.page {
        Page::Pos => pos::compose(c, rows, cols),
        Page::Prog => prog::compose(c, rows, cols),
        Page::Ofs => ofs::compose(c, rows, cols),
        Page::Modal => modal::compose(c, rows, cols),
        Page::Msg | Page::Mode => msg::compose(c, rows, cols),
    }
}

/// Puts a new message and a new alarm in the history (not `ok`, not a repeat).
pub(super) fn log(c: &mut Console, alarm: Option<String>) {
    let t = c.status.machine_ns;
    let wall = Some(crate::store::stamps::now_s());
    let mut warn = None;
    if let Some(a) = alarm {
        if a != c.pages.logged.1 {
            c.pages.logged.1 = a.clone();
            warn = c
                .pages
                .history
                .push(Entry {
                    machine_ns: t,
                    wall_s: wall,
                    kind: Kind::Alarm,
                    text: a,
                })
                .err();
        }
    } else {
        c.pages.logged.1.clear();
    }
    let m = c.message.clone();
    if !m.is_empty() && m != "ok" && m != c.pages.logged.0 {
        c.pages.logged.0 = m.clone();
        warn = warn.or(c
            .pages
            .history
            .push(Entry {
                machine_ns: t,
                wall_s: wall,
                kind: Kind::Message,
                text: m,
            })
            .err());
    }
    if let Some(w) = warn {
        also_say(c, &w);
        // The message with the failure added is not logged again.
        c.pages.logged.0 = c.message.clone();
    }
}

/// Adds a secondary failure (the history or the counters could not be saved) after the
/// message shown, never in its place: a refusal the operator must see stays first.
fn also_say(c: &mut Console, failure: &str) {
    c.message = if c.message.is_empty() || c.message == "ok" {
        failure.to_string()
    } else {
        format!("{}; {failure}", c.message)
    };
}

/// A program's message (`(MSG,...)`, `(PRINT,...)`, `(DEBUG,...)`, `(LOG,...)`): in the
/// history at once (each one, however many a line gives) and on the message line, so the
/// display frame, and with it the recording, shows it. A history that cannot be saved is said
/// after the message, never in its place.
pub(super) fn program_message(c: &mut Console, kind: &str, text: &str) {
    let line = format!("{kind}: {text}");
    let pushed = c.pages.history.push(Entry {
        machine_ns: c.status.machine_ns,
        wall_s: Some(crate::store::stamps::now_s()),
        kind: Kind::Message,
        text: line.clone(),
    });
    c.pages.logged.0 = line.clone();
    c.pages.program_msg = Some(line.clone());
    c.message = line;
    if let Err(w) = pushed {
        also_say(c, &w);
        c.pages.logged.0 = c.message.clone();
    }
}

/// A run of program memory reached its end: one more part, its cycle time; every run's time
/// counts in the run hours.
pub(super) fn count_run(c: &mut Console, auto: bool, done: bool, machine_ns: u64) {
    let k = &mut c.pages.counters;
    k.run_ns = k.run_ns.saturating_add(machine_ns);
    if auto && done {
        k.parts += 1;
        k.last_cycle_ns = machine_ns;
    }
    if c.saves_after_frame {
        // The terminal writes the frame first (the key's answer), then saves them.
        c.counters_unsaved = true;
        return;
    }
    save_counters(c);
}

/// Saves the counters; a failure is said after the message shown.
pub(super) fn save_counters(c: &mut Console) {
    c.counters_unsaved = false;
    if let Err(e) = c.pages.counters.save(&c.cfg.state_dir) {
        also_say(c, &e);
    }
}

/// Why a new AUTO run may not begin: the part counter has reached its target, as a Fanuc's
/// part count signal stops the cycle (docs/panel.md, "Pages").
pub(super) fn target_refusal(c: &Console) -> Option<String> {
    let k = &c.pages.counters;
    (k.target > 0 && k.parts >= k.target).then(|| {
        format!(
            "START refused: part count target reached ({}/{}); on the POS page type PARTS 0 or a new TARGET",
            k.parts, k.target
        )
    })
}
