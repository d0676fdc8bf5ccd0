//! What every console holds beside its machine: the operator's side of the panel (`Front`),
//! the log book, the recording, the page shown with its cursors and each channel's MDI recall.
//! The machining centre's `Console` and a lathe's `LatheConsole` each hold one `Shell`, and the
//! one console's rules (`side::Side`) reach it through `Side::shell`: before stop 59 each
//! console held the five beside its machine's fields, and `Side` asked for each of them.

use super::book::{At, Book};
use super::entry::Recall;
use super::front::Front;
use super::recording::Recording;
use crate::panel_model::Page;
use crate::pulse_core::Status;
use crate::record::foxglove::level;
use crate::store::history::Kind;

/// What every console holds beside its machine.
pub(crate) struct Shell {
    /// The operator's side: selector, entry line, message, help, switches, override, wheel.
    pub front: Front,
    /// The alarm and message history, the counters, the programs' messages.
    pub book: Book,
    /// The recording of the session (the one recording of every console).
    pub recorder: Recording,
    /// The page shown over the mode display, and the MSG and MACRO cursors.
    pub shown: Shown,
    /// Each channel's MDI lines last typed, for recall with Up and Down (the centre's one).
    pub recall: Vec<Recall>,
}

impl Shell {
    /// A console's shell as it opens, on a machine of `channels` channels: the mode's display
    /// shown, no MDI line to recall.
    pub fn new(front: Front, book: Book, recorder: Recording, channels: usize) -> Shell {
        Shell {
            front,
            book,
            recorder,
            shown: Shown::default(),
            recall: (0..channels.max(1)).map(|_| Recall::default()).collect(),
        }
    }

    /// Puts in the history each alarm slot's alarm now, when it comes (`book::Log::alarms`:
    /// the centre's one slot, a lathe's E-STOP and one a channel), then the message shown, if
    /// it is new, at its level (`book::message_level` over the machine's `channels`), said at
    /// `at`. A failure to keep either is said after the message, never in its place, until the
    /// next key, and is not logged again. Every console's rule, after each action and each
    /// look at the machine (before stop 46 each console had its copy).
    pub fn log(&mut self, alarms: &[Option<(String, At)>], at: At, channels: &[Status]) {
        let failed = self.book.log.alarms(&mut self.recorder, alarms).err();
        let front = &mut self.front;
        let lvl = super::book::message_level(&front.message, channels);
        let r = (self.book.log).message(&mut self.recorder, at, lvl, &front.message);
        if let Some(e) = failed.or(r.err()) {
            front.say_failure(&e, at.0);
            self.book.log.shown(&front.message);
        }
    }

    /// A program's message `line` of `kind` (`MSG: text`; a lathe's after its channel's name),
    /// every console's rule: in the history at `at` at once (each one, however many a step
    /// gives), then waiting for acknowledgement, for the kinds `state::until_acknowledged`
    /// names, or on the message line until the next key. Why the history could not keep it.
    pub fn program_message(&mut self, at: At, kind: &str, line: String) -> Result<(), String> {
        let r = (self.book.log).put(&mut self.recorder, at, Kind::Message, level::INFO, &line);
        if super::state::until_acknowledged(kind) {
            self.book.unacknowledged.push(line);
        } else {
            self.front.say(line, super::MsgLife::NextKey, at.0);
        }
        r
    }

    /// `PARTS n` (`parts`) or `TARGET n` on the POS page: the log book's part count or its
    /// target, saved in `dir` at once; a save that fails changes nothing.
    pub fn set_count(
        &mut self,
        parts: bool,
        n: u64,
        dir: &std::path::Path,
    ) -> Result<String, String> {
        let was = self.book.counters;
        if parts {
            self.book.counters.parts = n;
        } else {
            self.book.counters.target = n;
        }
        if let Err(e) = self.book.counters.save(dir) {
            self.book.counters = was;
            return Err(e);
        }
        Ok(format!("{} {n}", if parts { "parts" } else { "target" }))
    }
}

/// The page shown and the cursors of the pages every console has (MSG, MACRO), with their
/// one rule for a page key and a cursor key: the centre's and a lathe's (before stop 58 the
/// lathe kept the three beside each other and its own copy of the rules).
#[derive(Clone, Debug)]
pub struct Shown {
    /// The page shown (`Page::Mode`: the mode's display program).
    pub page: Page,
    /// The MSG page's first entry shown (0: the newest).
    pub msg_first: usize,
    /// The MACRO page's cursor: a variable number.
    pub macro_var: usize,
}

impl Default for Shown {
    fn default() -> Shown {
        Shown {
            page: Page::Mode,
            msg_first: 0,
            macro_var: 1,
        }
    }
}

impl Shown {
    /// A page key: its page, or back to the mode's display if it is shown already; the MSG
    /// page opens at the newest entry. The line being typed stays on the entry line: a page
    /// key shows a screen, it does not take back what the operator typed (before stop 41 the
    /// centre cleared it, the lathe kept it).
    pub fn key(&mut self, p: Page) {
        self.page = if self.page == p { Page::Mode } else { p };
        self.msg_first = 0;
    }
}
