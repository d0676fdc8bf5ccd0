//! What every console holds beside its machine: the operator's side of the panel (`Front`),
//! the log book, the recording, the page shown with its cursors and each channel's MDI recall.
//! The machining centre's `Console` and a lathe's `LatheConsole` each hold one `Shell`, and the
//! one console's rules (`side::Side`) reach it through `Side::shell`: before stop 59 each
//! console held the five beside its machine's fields, and `Side` asked for each of them.

use super::book::Book;
use super::entry::Recall;
use super::front::Front;
use super::recording::Recording;
use crate::panel_model::Page;

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
