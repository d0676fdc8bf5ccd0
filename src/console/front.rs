//! The operator's side of a console, on every machine (issue 22: each console held its own
//! copy of these before stop 41, and their rules had begun to differ): the operation
//! selector, the line typed on the data keys, the operator message and how long it lives,
//! the help page, whether the screen fits, the panel's switches, the feed override, the
//! handwheel, the CONTINUOUS key held, the type-out of the last editor command line, and why
//! the last script wait ended early. What the machine is doing is never kept here: each
//! console derives it from its machine's state when the frame is drawn. This is model state:
//! it names nothing of the display, the pages or the key map (`tests/console_rules.rs`).

use super::MsgLife;
use crate::panel_model::{Axis, OpMode, PanelEvent};
use std::time::{Duration, Instant};

/// A CONTINUOUS jog stops when its key has not repeated for this long (terminals report no
/// key release; auto-repeat keeps a held key coming).
pub const JOG_RELEASE: Duration = Duration::from_millis(150);

/// Two presses of one jog key closer than this are the terminal's auto-repeat (25 to 30 a
/// second), so the key is held; a person tapping twice is slower (docs/panel.md, "Jogging").
pub const REPEAT_GAP: Duration = Duration::from_millis(90);

/// The operator's side of a console (see the module's text).
#[derive(Clone, Debug)]
pub(crate) struct Front {
    /// The operation selector's position.
    pub op: OpMode,
    /// The line being typed on the data keys.
    pub entry: String,
    /// The operator message: the result, refusal or error of an action, or what the machine
    /// or a program said. It lives as [`Front::life`] says.
    pub message: String,
    /// How long [`Front::message`] lives.
    pub life: MsgLife,
    /// The machine time the message was said at, ns (a message said with START lives through
    /// the instant before the machine answers it).
    pub said_ns: u64,
    /// The help screen page up (0: none).
    pub help: u8,
    /// Whether the terminal is large enough for the panel, and the key last refused.
    pub screen: ScreenFit,
    /// The BLOCK DELETE and OPTIONAL STOP switches.
    pub switches: crate::gcode::Switches,
    /// The feed override, percent.
    pub feed_override: u32,
    /// The handwheel's axis and scale (the STEP increment), pulses a detent.
    pub wheel: (Axis, u32),
    /// The CONTINUOUS jog key last pressed: when, and whether it is held.
    pub jog_key: HeldJog,
    /// The channel a CONTINUOUS jog was begun on and not yet let go (`manual::release`).
    pub jogging: Option<usize>,
    /// The `Y` type-out of the last editor command line, shown in place of the text window
    /// until the next line, mode or channel.
    pub y_output: Option<String>,
    /// Why the last script `wait` ended before its condition, if it did.
    pub wait_error: Option<String>,
}

impl Front {
    /// A console's front at power-on: the selector at `op`, the handwheel at `scale`.
    pub fn new(op: OpMode, scale: u32) -> Front {
        Front {
            op,
            entry: String::new(),
            message: String::new(),
            life: MsgLife::NextKey,
            said_ns: 0,
            help: 0,
            screen: ScreenFit::default(),
            switches: Default::default(),
            feed_override: 100,
            wheel: (Axis::X, scale),
            jog_key: HeldJog::default(),
            jogging: None,
            y_output: None,
            wait_error: None,
        }
    }

    /// Says `text` on the message line, at machine time `now_ns`, for as long as `life`.
    pub fn say(&mut self, text: impl Into<String>, life: MsgLife, now_ns: u64) {
        self.message = text.into();
        self.life = life;
        self.said_ns = now_ns;
    }

    /// Whether the message still lives at machine time `now_ns` ([`MsgLife`]), every
    /// console's one rule: `runs`, the machine runs or moves (a lathe's: a channel runs, jogs,
    /// or waits on one that is not stopped); `block_over(done)`, the block executing when a
    /// `WhileBlock(done)` message was said has ended, or the run with it. A `WhileRunning`
    /// message said in this instant lives: the machine has not answered yet.
    pub fn message_lives(
        &self,
        now_ns: u64,
        runs: bool,
        block_over: impl FnOnce(u64) -> bool,
    ) -> bool {
        match self.life {
            MsgLife::NextKey => true,
            MsgLife::WhileBlock(done) => !block_over(done),
            MsgLife::WhileRunning => runs || self.said_ns == now_ns,
        }
    }

    /// A secondary failure (a store that could not keep the counters or the history) said
    /// after the message shown, never in its place, until the next key: every console's rule
    /// (`book::with_failure`).
    pub fn say_failure(&mut self, failure: &str, now_ns: u64) {
        let m = super::book::with_failure(&self.message, failure);
        self.say(m, MsgLife::NextKey, now_ns);
    }

    /// Forgets the CONTINUOUS key held and the jog begun (E-STOP and RESET have stopped the
    /// machine: nothing is left to let go).
    pub fn forget_jog(&mut self) {
        self.jog_key.clear();
        self.jogging = None;
    }

    /// An operator action begins: the message of the last one has lived its life.
    pub fn new_action(&mut self) {
        self.message.clear();
        self.life = MsgLife::NextKey;
    }

    /// One data key on the entry line: a full line refuses it, and says so (no key is lost
    /// in silence).
    pub fn key(&mut self, ch: char) {
        if let Err(e) = super::entry::push_key(&mut self.entry, ch) {
            self.message = e;
        }
    }

    /// The feed override switch turned to `p` percent, the same on every machine: 0 to 150 %
    /// in 10 % steps, the rotary's positions; another is refused, and said. Whether it was
    /// taken (the console then tells its machine).
    pub fn set_override(&mut self, p: u32) -> bool {
        if p <= 150 && p.is_multiple_of(10) {
            self.feed_override = p;
            return true;
        }
        self.message = format!("override {p} % is not 0 to 150 in 10 % steps");
        false
    }

    /// BLOCK DELETE or OPTIONAL STOP turned, the same on every machine: kept for the next
    /// run, and said. Whether `ev` was one of them.
    pub fn switch(&mut self, ev: &PanelEvent) -> bool {
        let (name, on) = match *ev {
            PanelEvent::BlockDelete(on) => {
                self.switches.block_delete = on;
                ("BLOCK DELETE", on)
            }
            PanelEvent::OptionalStop(on) => {
                self.switches.optional_stop = on;
                ("OPTIONAL STOP", on)
            }
            _ => return false,
        };
        self.message = super::switch_message(name, on);
        true
    }

    /// Whether the help screen is up.
    pub fn help_shown(&self) -> bool {
        self.help > 0
    }

    /// The last key ignored because the terminal is too small, for the notice.
    pub fn ignored_key(&self) -> Option<&str> {
        self.screen.ignored()
    }
}

/// The CONTINUOUS jog key last pressed.
#[derive(Clone, Copy, Debug)]
struct JogKey {
    axis: Axis,
    dir: i8,
    /// When it was last pressed (or repeated).
    at: Instant,
    /// Repeating: a continuous jog is running (else it was tapped: one increment).
    held: bool,
}

/// A CONTINUOUS jog key as a terminal reports it, every console's rule (the centre's and a
/// lathe's; docs/panel.md, "Jogging"): terminals report presses and auto-repeats, never a
/// release. A tap moves one increment, as STEP does; a key pressed again within
/// [`REPEAT_GAP`] is the auto-repeat of a held key, and then the axis jogs until the key stops
/// repeating for [`JOG_RELEASE`]. In virtual time every press is a tap. The console acts on
/// what [`HeldJog::press`] answers and tells it whether a jog began.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct HeldJog(Option<JogKey>);

/// What a CONTINUOUS jog key asks of the console ([`HeldJog::press`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum JogPress {
    /// A repeat of a held key: keep the running jog alive (`Command::JogAlive`).
    KeepAlive,
    /// A repeat of a tapped key: the key is held. Once the tap's increment is at rest, begin
    /// the continuous jog and say whether it began ([`HeldJog::began`]); while it still
    /// moves, nothing (a later repeat begins it).
    Begin,
    /// A new press: one increment (a tap), after releasing the jog of the key held until now
    /// when `release`.
    Tap {
        /// Another key's continuous jog runs: release it first.
        release: bool,
    },
}

impl HeldJog {
    /// A CONTINUOUS jog key `axis`, `dir` pressed at `now`.
    pub(crate) fn press(
        &mut self,
        axis: Axis,
        dir: i8,
        now: Instant,
        virtual_time: bool,
    ) -> JogPress {
        if let Some(k) = self.0.as_mut() {
            if k.axis == axis && k.dir == dir && !virtual_time {
                // A held key that has not repeated for the release time (the console was
                // not running: the core's deadman may have stopped the jog) is pressed anew.
                let gap = now.duration_since(k.at);
                if gap <= REPEAT_GAP || (k.held && gap <= JOG_RELEASE) {
                    k.at = now;
                    return if k.held {
                        JogPress::KeepAlive
                    } else {
                        JogPress::Begin
                    };
                }
            }
        }
        let release = self.0.is_some_and(|k| k.held);
        self.0 = (!virtual_time).then_some(JogKey {
            axis,
            dir,
            at: now,
            held: false,
        });
        JogPress::Tap { release }
    }

    /// After [`JogPress::Begin`]: whether the continuous jog began (the key is held from now
    /// on) or was refused (the key is forgotten).
    pub(crate) fn began(&mut self, ok: bool) {
        match self.0.as_mut() {
            Some(k) if ok => k.held = true,
            _ => self.0 = None,
        }
    }

    /// Called each display tick: whether a held key's jog is to be released now (it has not
    /// repeated for [`JOG_RELEASE`]); a tapped key is forgotten then.
    pub(crate) fn expired(&mut self, now: Instant) -> bool {
        match self.0 {
            Some(k) if now.duration_since(k.at) > JOG_RELEASE => {
                self.0 = None;
                k.held
            }
            _ => false,
        }
    }

    /// Forgets the key (RESET, E-STOP, a release, a mode turned).
    pub(crate) fn clear(&mut self) {
        self.0 = None;
    }

    /// No key is pressed (a jog that runs was begun by a front end's button).
    pub(crate) fn is_none(&self) -> bool {
        self.0.is_none()
    }
}

/// Whether the terminal is large enough for the panel, and the key last refused while it was
/// not: every console's rule (the centre's and the lathe's). While it is not, only the relay
/// panel's STOP, RESET and E-STOP act; another key is refused, and the notice names it.
#[derive(Clone, Debug)]
pub struct ScreenFit {
    fits: bool,
    ignored: Option<String>,
}

impl Default for ScreenFit {
    fn default() -> Self {
        ScreenFit {
            fits: true,
            ignored: None,
        }
    }
}

impl ScreenFit {
    /// The front end tells it every frame; a terminal grown large enough forgets the notice.
    pub fn set(&mut self, fits: bool) {
        if fits && !self.fits {
            self.ignored = None;
        }
        self.fits = fits;
    }

    /// Whether the panel fits.
    pub fn fits(&self) -> bool {
        self.fits
    }

    /// A key (named `key`) is refused because the panel does not fit: the notice names it.
    pub fn refuse(&mut self, key: &str) {
        self.ignored = Some(format!("key {key} ignored: the terminal is too small"));
    }

    /// The last key refused, for the notice.
    pub fn ignored(&self) -> Option<&str> {
        self.ignored.as_deref()
    }
}
