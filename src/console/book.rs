//! The console's log book: the alarm and message history (the MSG page shows it), the
//! counters (the POS page shows them), and a program's messages. Part of the console's model:
//! the pages draw it, it names nothing of them.

use super::Console;
use crate::record::foxglove::{alarm_line, level};
use crate::store::history::{Counters, Entry, History, Kind};

/// The history and the counters, kept in the stores across restarts.
#[derive(Debug)]
pub(super) struct Book {
    /// The alarm and message history.
    pub(super) history: History,
    /// The counters.
    pub(super) counters: Counters,
    /// The last message and alarm put in the history.
    logged: (String, String),
    /// The program's message taken since the last frame (a run's end says it too, so that the
    /// frame, and with it the recording, shows it).
    pub(super) program_msg: Option<String>,
    /// Program messages that live until acknowledged (`state::until_acknowledged`), oldest
    /// first: the message line shows the newest until Esc or RESET.
    pub(super) unacknowledged: Vec<String>,
}

impl Book {
    /// The book of a console whose state directory is `dir`, with the warnings of reading its
    /// history and counters.
    pub(super) fn open(dir: &std::path::Path) -> (Book, Vec<String>) {
        let (history, w1) = History::open(dir);
        let (counters, w2) = Counters::open(dir);
        (
            Book {
                history,
                counters,
                logged: (String::new(), String::new()),
                program_msg: None,
                unacknowledged: Vec::new(),
            },
            w1.into_iter().chain(w2).collect(),
        )
    }
}

/// Puts a new message and a new alarm in the history (not `ok`, not a repeat).
pub(super) fn log(c: &mut Console, alarm: Option<String>) {
    let t = c.status.machine_ns;
    let wall = Some(crate::store::stamps::now_s());
    let mut warn = None;
    if let Some(a) = alarm {
        if a != c.book.logged.1 {
            c.book.logged.1 = a.clone();
            let line = c
                .program_alarm
                .as_ref()
                .filter(|p| p.error.to_string() == a)
                .map_or_else(|| alarm_line(&a), |p| p.error.line);
            record_log(c, t, level::ERROR, &a, line);
            warn = c
                .book
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
        c.book.logged.1.clear();
    }
    let m = c.message.clone();
    if !m.is_empty() && m != "ok" && m != c.book.logged.0 {
        c.book.logged.0 = m.clone();
        // The pulse core's refusal of an operator action is a warning; the rest, information.
        let lvl = if c.status.notice.as_deref() == Some(m.as_str()) {
            level::WARNING
        } else {
            level::INFO
        };
        record_log(c, t, lvl, &m, 0);
        warn = warn.or(c
            .book
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
        c.book.logged.0 = c.message.clone();
    }
}

/// A message or an alarm as it goes into the history, on the recording's `/foxglove/log`:
/// the program in memory named as its file.
fn record_log(c: &mut Console, t_ns: u64, lvl: u8, text: &str, line: u32) {
    let file = c.mem.program_name();
    c.recorder.log(t_ns, lvl, text, &file, line);
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
/// display frame, and with it the recording, shows it: until acknowledged for the kinds
/// `state::until_acknowledged` names, else until the next key. A history that cannot be saved
/// is said after the message, never in its place.
pub(super) fn program_message(c: &mut Console, kind: &str, text: &str) {
    let line = format!("{kind}: {text}");
    // When the console shows it; the message does not say which line gave it.
    let t = c.status.machine_ns;
    record_log(c, t, level::INFO, &line, 0);
    let pushed = c.book.history.push(Entry {
        machine_ns: c.status.machine_ns,
        wall_s: Some(crate::store::stamps::now_s()),
        kind: Kind::Message,
        text: line.clone(),
    });
    c.book.logged.0 = line.clone();
    if super::state::until_acknowledged(kind) {
        c.book.unacknowledged.push(line);
    } else {
        c.book.program_msg = Some(line.clone());
        c.message = line;
    }
    if let Err(w) = pushed {
        also_say(c, &w);
        c.book.logged.0 = c.message.clone();
    }
}

/// A run of program memory reached its end: one more part, its cycle time; every run's time
/// counts in the run hours.
pub(super) fn count_run(c: &mut Console, auto: bool, done: bool, machine_ns: u64) {
    let k = &mut c.book.counters;
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
    if let Err(e) = c.book.counters.save(&c.cfg.state_dir) {
        also_say(c, &e);
    }
}

/// Why a new AUTO run may not begin: the part counter has reached its target, as a Fanuc's
/// part count signal stops the cycle (docs/panel.md, "Pages").
pub(super) fn target_refusal(c: &Console) -> Option<String> {
    let k = &c.book.counters;
    (k.target > 0 && k.parts >= k.target).then(|| {
        format!(
            "START refused: part count target reached ({}/{}); on the POS page type PARTS 0 or a new TARGET",
            k.parts, k.target
        )
    })
}

/// Acknowledges the program messages that live until acknowledged (Esc, RESET); whether there
/// was one.
pub(super) fn acknowledge(c: &mut Console) -> bool {
    let had = !c.book.unacknowledged.is_empty();
    c.book.unacknowledged.clear();
    had
}
