//! The console of a machine as the front ends hold it (the terminal, `novanc script`): one type
//! with one set of verbs, whether the machine is the machining centre (its panel, `Console`) or
//! a lathe (its channel panel with the channel selector, `LatheConsole`). A front end opens it
//! from the machine and the configuration, gives it keys or panel events, ticks it, shows it,
//! publishes it to MTConnect and closes it, without asking which machine it is; only the
//! drawing of the two panels differs (docs/panel.md, docs/lathe.md "The panel").

use super::{Console, ConsoleConfig};
use crate::lathe::console::LatheConsole;
use crate::lathe::desc::LatheDesc;
use crate::mtconnect::feed::{Feed, MtcOpts};
use crate::panel_model::PanelEvent;
use novanc_panel::Key;

/// The console of the machine.
pub enum Panel {
    /// The machining centre's panel.
    Centre(Box<Console>),
    /// A lathe's panel: its channels, each with its program, MDI buffer and tools.
    Lathe(Box<LatheConsole>),
}

impl Panel {
    /// Opens the console of the machine (`lathe`: a lathe's description; None: the machining
    /// centre `cfg` describes) on `cfg`: its state directory, display size, recording, clock
    /// and the interrupt of a script's waits. The warnings of the opening come back with it.
    pub fn open(
        lathe: Option<LatheDesc>,
        cfg: ConsoleConfig,
    ) -> Result<(Panel, Vec<String>), String> {
        match lathe {
            None => Console::open(cfg).map(|(c, w)| (Panel::Centre(Box::new(c)), w)),
            Some(desc) => {
                let (c, w) = LatheConsole::open_config(desc, &cfg)?;
                Ok((Panel::Lathe(Box::new(c)), w))
            }
        }
    }

    /// Reads a whole panel script for the machine (`lathe`: a lathe's description; None: the
    /// machining centre) with the one grammar, checked whole before anything opens: a lathe
    /// refuses the centre's own words, and the centre a lathe's. A bad line gives its number
    /// (1-based) and why, and nothing is returned.
    pub fn read_script(
        lathe: Option<&LatheDesc>,
        text: &str,
    ) -> Result<Vec<PanelEvent>, (usize, String)> {
        match lathe {
            Some(d) => crate::lathe::console::events::parse_script(text, d.channels.len()),
            None => PanelEvent::parse_script(text).map_err(|e| (e.line as usize, e.message)),
        }
    }

    /// A key of the panel.
    pub fn press(&mut self, k: Key) {
        match self {
            Panel::Centre(c) => c.press(k),
            Panel::Lathe(c) => c.press(k),
        }
    }

    /// One event of the panel grammar (a wait runs the machine, in virtual time, until it
    /// ends or cannot: [`Panel::wait_error`]).
    pub fn handle(&mut self, ev: PanelEvent) {
        match self {
            Panel::Centre(c) => c.handle(ev),
            Panel::Lathe(c) => c.handle(ev),
        }
    }

    /// Once a frame, `ns` of wall time after the last: the console takes the machine's state
    /// (the centre's pulse core and a lathe's kernel keep their own clocks).
    pub fn tick(&mut self, ns: u64) {
        match self {
            Panel::Centre(c) => c.tick(),
            Panel::Lathe(c) => c.tick(ns),
        }
    }

    /// The operator's side of the console (`front.rs`): the screen fit and the key it last
    /// refused, why the last wait could not end, the message and the entry line.
    pub(crate) fn front(&self) -> &super::front::Front {
        &self.shell().front
    }

    /// What every console holds beside its machine (`shell.rs`).
    fn shell(&self) -> &super::shell::Shell {
        use super::side::Side;
        match self {
            Panel::Centre(c) => c.shell_ref(),
            Panel::Lathe(c) => c.shell_ref(),
        }
    }

    /// Tells the console whether the screen is large enough for the panel: while it is not,
    /// only STOP, RESET and E-STOP act, and another key is refused (`Front::ignored_key`).
    pub fn set_screen_fits(&mut self, fits: bool) {
        use super::side::Side;
        let front = match self {
            Panel::Centre(c) => c.front(),
            Panel::Lathe(c) => c.front(),
        };
        front.screen.set(fits)
    }

    /// The display as text, as a script's `show` prints it and the recording keeps it.
    pub fn frame_text(&mut self) -> String {
        match self {
            Panel::Centre(c) => {
                c.tick();
                c.frame_text()
            }
            Panel::Lathe(c) => c.frame_text(),
        }
    }

    /// The frame is on the screen (the centre stores what waited for it).
    pub fn frame_written(&mut self) {
        if let Panel::Centre(c) = self {
            c.frame_written();
        }
    }

    /// Starts the MTConnect adapter `mtc` asks for (None without `--mtconnect`) and publishes
    /// the state before anything happens. `headless` (a script): the feed waits for an agent
    /// if `--mtconnect-wait` asks, and, in virtual time, every change inside a wait is published
    /// with its machine time.
    pub fn start_feed(
        &mut self,
        mtc: &MtcOpts,
        who: &str,
        headless: bool,
    ) -> Result<Option<Feed>, String> {
        match self {
            Panel::Centre(c) => {
                let Some(mut f) = Feed::start(mtc, who, c.core())? else {
                    return Ok(None);
                };
                f.publish(c);
                if headless {
                    f.wait(mtc)?;
                }
                Ok(Some(f))
            }
            Panel::Lathe(c) => {
                let Some(mut f) = Feed::start_on(mtc, who, headless, c.machine_ns())? else {
                    return Ok(None);
                };
                f.publish_lathe(c);
                if headless {
                    f.wait(mtc)?;
                    // Every change of every channel inside a wait, as the kernel makes it
                    // (docs/mtconnect.md "The lathe").
                    c.set_watch(Some(f.lathe_watcher()));
                }
                Ok(Some(f))
            }
        }
    }

    /// Publishes the state to the MTConnect adapter.
    pub fn publish(&self, feed: &mut Feed) {
        match self {
            Panel::Centre(c) => feed.publish(c),
            Panel::Lathe(c) => feed.publish_lathe(c),
        }
    }

    /// Ends the session: the machine stopped (by E-STOP on every machine when a stop signal,
    /// `interrupted`, cut it short; else the centre is RESET; the centre's recording is marked
    /// by `signals::caught`), the stores and the recording closed. The recording's summary
    /// line, or why it could not be finished.
    pub fn close(self, interrupted: Option<&str>) -> Result<Option<String>, String> {
        match self {
            Panel::Centre(c) => (*c)
                .close(interrupted)
                .map_err(|e| format!("recording: {e}")),
            Panel::Lathe(c) => (*c).close(interrupted),
        }
    }

    /// [`Panel::close`], saying the recording's summary, or why it could not be finished, on
    /// stderr: how every front end (the terminal, the window, `novanc script`) ends.
    pub fn close_saying(self, interrupted: Option<&str>) {
        match self.close(interrupted) {
            Ok(Some(line)) | Err(line) => eprintln!("novanc: {line}"),
            Ok(None) => {}
        }
    }
}
