//! The console's log book: the alarm and message history (the MSG page shows it), the
//! counters (the POS page shows them), and a program's messages. Part of the console's model:
//! the pages draw it, it names nothing of them. [`Log`], the history as it is written, is every
//! console's: the centre's and a lathe's alike.

use super::recording::Recording;
use super::Console;
use crate::record::foxglove::{alarm_line, level};
use crate::store::history::{Counters, Entry, History, Kind};

/// The alarm and message history as every console writes it: each message and alarm when it
/// is first shown, in the history of the state directory (the MSG page) and on the recording's
/// `/foxglove/log`, the program it came from named as the file.
#[derive(Debug)]
pub(crate) struct Log {
    /// The history kept in the state directory.
    pub(crate) history: History,
    /// The last message put in the history (a message shown again is not logged again).
    last: String,
    /// The alarm last put in the history of each alarm slot ([`Log::alarms`]; empty: none
    /// stands).
    alarms: Vec<String>,
}

/// Where an entry of the history was said: machine time (ns), the program's name, its line
/// (0: none).
pub(crate) type At<'a> = (u64, &'a str, u32);

impl Log {
    /// The history kept in `dir`, and the warning of reading it.
    pub(crate) fn open(dir: &std::path::Path) -> (Log, Option<String>) {
        let (history, w) = History::open(dir);
        let last = String::new();
        let alarms = Vec::new();
        (
            Log {
                history,
                last,
                alarms,
            },
            w,
        )
    }

    /// Each alarm slot's alarm now (`now[i]`: slot i's, with where it was said), in the
    /// history as an alarm when it comes: not again while it stands, again once its slot has
    /// been clear. One rule for every console: the centre has one slot (the machine's, the
    /// program's or the tape's alarm); a lathe has one for the machine's E-STOP and one a
    /// channel (its FAULT or ALARM). Why the history could not keep one, if it could not.
    pub(crate) fn alarms(
        &mut self,
        rec: &mut Recording,
        now: &[Option<(String, At)>],
    ) -> Result<(), String> {
        if self.alarms.len() < now.len() {
            self.alarms.resize(now.len(), String::new());
        }
        let mut failed = Ok(());
        for (i, a) in now.iter().enumerate() {
            match a {
                None => self.alarms[i].clear(),
                Some((text, _)) if *text == self.alarms[i] => {}
                Some((text, at)) => {
                    self.alarms[i] = text.clone();
                    let r = self.put(rec, *at, Kind::Alarm, level::ERROR, text);
                    failed = failed.and(r);
                }
            }
        }
        failed
    }

    /// The alarms standing are new to the history: each is logged again if it still stands
    /// (a new cycle's faults are its own).
    pub(crate) fn forget_alarms(&mut self) {
        self.alarms.iter_mut().for_each(String::clear);
    }

    /// `text` in the history as `kind`, and in the recording at level `lvl`, whatever was
    /// logged before; why the history could not keep it, if it could not (said once of
    /// failures in a row).
    pub(crate) fn put(
        &mut self,
        rec: &mut Recording,
        (t_ns, file, line): At,
        kind: Kind,
        lvl: u8,
        text: &str,
    ) -> Result<(), String> {
        rec.log(t_ns, lvl, text, file, line);
        if kind == Kind::Message {
            self.last = text.to_string();
        }
        self.history.push(Entry {
            machine_ns: t_ns,
            wall_s: Some(crate::store::stamps::now_s()),
            kind,
            text: text.to_string(),
        })
    }

    /// The message shown, if it is new (not empty, not `ok`, not the last one logged), as
    /// [`Log::put`] puts it.
    pub(crate) fn message(
        &mut self,
        rec: &mut Recording,
        at: At,
        lvl: u8,
        text: &str,
    ) -> Result<(), String> {
        if text.is_empty() || text == "ok" || text == self.last {
            return Ok(());
        }
        self.put(rec, at, Kind::Message, lvl, text)
    }

    /// The message line as it stands with a failure of the history added to it: not logged
    /// again.
    pub(crate) fn shown(&mut self, text: &str) {
        self.last = text.to_string();
    }
}

/// The log book every console keeps (the centre's and a lathe's): the history and the
/// counters, kept in the stores across restarts, and the program messages waiting to be
/// acknowledged.
#[derive(Debug)]
pub(crate) struct Book {
    /// The alarm and message history.
    pub(crate) log: Log,
    /// The counters.
    pub(crate) counters: Counters,
    /// The program's message taken since the last frame (a run's end says it too, so that the
    /// frame, and with it the recording, shows it).
    pub(super) program_msg: Option<String>,
    /// Program messages that live until acknowledged (`state::until_acknowledged`), oldest
    /// first: the message line shows the newest until Esc or RESET.
    pub(crate) unacknowledged: Vec<String>,
}

impl Book {
    /// Acknowledges the program messages that live until acknowledged (Esc, RESET); whether
    /// there was one.
    pub(crate) fn acknowledge(&mut self) -> bool {
        let had = !self.unacknowledged.is_empty();
        self.unacknowledged.clear();
        had
    }

    /// The book of a console whose state directory is `dir`, with the warnings of reading its
    /// history and counters.
    pub(crate) fn open(dir: &std::path::Path) -> (Book, Vec<String>) {
        let (log, w1) = Log::open(dir);
        let (counters, w2) = Counters::open(dir);
        (
            Book {
                log,
                counters,
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
    let file = c.mem.program_name();
    let now = alarm.map(|a| {
        let line = c
            .program_alarm
            .as_ref()
            .filter(|p| p.error.to_string() == a)
            .map_or_else(|| alarm_line(&a), |p| p.error.line);
        (a, (t, file.as_str(), line))
    });
    let channels = std::slice::from_ref(&c.status);
    c.shell.log(&[now], (t, file.as_str(), 0), channels);
}

/// The level a message goes into the history and the recording at, on every console
/// (docs/recording.md "Levels"): a machine's refusal of an operator action (a channel's
/// notice, said as it is or after the channel's name: `CH1 X jog refused: ...`) is a warning;
/// every other message is information. Before stop 45 the lathe wrote every message as
/// information.
pub(crate) fn message_level(message: &str, channels: &[crate::pulse_core::Status]) -> u8 {
    let refusal = channels.iter().any(|s| {
        s.notice
            .as_deref()
            .is_some_and(|n| !n.is_empty() && message.ends_with(n))
    });
    if refusal {
        level::WARNING
    } else {
        level::INFO
    }
}

/// Adds a secondary failure (the history or the counters could not be saved) after the
/// message shown, never in its place: a refusal the operator must see stays first.
fn also_say(c: &mut Console, failure: &str) {
    c.shell.front.say_failure(failure, c.status.machine_ns);
}

/// The message line `message` with a secondary `failure` after it, on every console (a
/// message that says nothing, or `ok`, gives way to it).
pub(crate) fn with_failure(message: &str, failure: &str) -> String {
    match message {
        "" | "ok" => failure.to_string(),
        m => format!("{m}; {failure}"),
    }
}

/// A program's message (`(MSG,...)`, `(PRINT,...)`, `(DEBUG,...)`, `(LOG,...)`): in the
/// history at once (each one, however many a line gives) and on the message line, so the
/// display frame, and with it the recording, shows it: until acknowledged for the kinds
/// `state::until_acknowledged` names, else until the next key. A history that cannot be saved
/// is said after the message, never in its place.
pub(super) fn program_message(c: &mut Console, kind: &str, text: &str) {
    let line = format!("{kind}: {text}");
    if !super::state::until_acknowledged(kind) {
        c.shell.book.program_msg = Some(line.clone());
    }
    // When the console shows it; the message does not say which line gave it.
    let file = c.mem.program_name();
    let at = (c.status.machine_ns, file.as_str(), 0);
    let pushed = c.shell.program_message(at, kind, line);
    if let Err(w) = pushed {
        also_say(c, &w);
        c.shell.book.log.shown(&c.shell.front.message.clone());
    }
}

/// A run of program memory reached its end: one more part, its cycle time; every run's time
/// counts in the run hours.
pub(super) fn count_run(c: &mut Console, auto: bool, done: bool, machine_ns: u64) {
    let k = &mut c.shell.book.counters;
    k.ran(machine_ns);
    if auto && done {
        k.made(machine_ns);
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
    if let Err(e) = c.shell.book.counters.save(&c.cfg.state_dir) {
        also_say(c, &e);
    }
}

/// Why a new AUTO run may not begin: the part counter has reached its target, as a Fanuc's
/// part count signal stops the cycle (docs/panel.md, "Pages").
pub(super) fn target_refusal(c: &Console) -> Option<String> {
    let k = &c.shell.book.counters;
    (k.target > 0 && k.parts >= k.target).then(|| {
        format!(
            "START refused: part count target reached ({}/{}); on the POS page type PARTS 0 or a new TARGET",
            k.parts, k.target
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A failure of a store is said after the message shown, never in its place, and lives
    /// until the next key; a message that says nothing gives way to it.
    #[test]
    fn a_failure_is_said_after_the_message_until_the_next_key() {
        let mut f = super::super::front::Front::new(crate::panel_model::OpMode::Auto, 10);
        f.say("START refused: X", super::super::MsgLife::WhileRunning, 1);
        f.say_failure("the counters were not saved: disk full", 2);
        assert_eq!(
            f.message,
            "START refused: X; the counters were not saved: disk full"
        );
        assert_eq!(f.life, super::super::MsgLife::NextKey);
        f.say("ok", super::super::MsgLife::NextKey, 3);
        f.say_failure("the history was not kept", 4);
        assert_eq!(f.message, "the history was not kept");
    }

    /// Each slot's alarm goes into the history once while it stands, again once its slot has
    /// been clear; the slots are independent (a lathe's E-STOP and its channels).
    #[test]
    fn an_alarm_is_logged_when_it_comes_in_its_own_slot() {
        let dir = std::env::temp_dir().join(format!("novanc-book-alarms-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let (mut log, _) = Log::open(&dir);
        let info = crate::record::RecordingInfo::default();
        let settings = crate::settings::MachineSettings::default();
        let mut rec = Recording::start(None, None, &settings, &info).unwrap();
        let a = |text: &str, t: u64| Some((text.to_string(), (t, "P", 3)));
        let texts = |log: &Log| -> Vec<String> {
            log.history
                .entries()
                .iter()
                .map(|e| e.text.clone())
                .collect()
        };
        log.alarms(&mut rec, &[a("E", 1), None]).unwrap();
        log.alarms(&mut rec, &[a("E", 2), a("CH1 FAULT: x", 2)])
            .unwrap();
        // Standing: not again; another slot's alarm of the same text is its own.
        log.alarms(&mut rec, &[a("E", 3), a("CH1 FAULT: x", 3)])
            .unwrap();
        log.alarms(&mut rec, &[None, a("E", 4)]).unwrap();
        // Cleared, then back: logged again.
        log.alarms(&mut rec, &[a("E", 5), None]).unwrap();
        log.forget_alarms();
        log.alarms(&mut rec, &[a("E", 6), None]).unwrap();
        assert_eq!(texts(&log), ["E", "CH1 FAULT: x", "E", "E", "E"]);
        assert!(log.history.entries().iter().all(|e| e.kind == Kind::Alarm));
        let _ = std::fs::remove_dir_all(&dir);
    }
}
