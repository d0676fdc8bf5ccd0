//! The keyboard map of the terminal panel (`docs/panel.md`), the help screen and the
//! "terminal too small" notice, as console state so that every front end and the panel script
//! (`key NAME`) press the same keys with the same effect.
//!
//! The relay panel always acts: STOP, RESET and E-STOP work on every screen (help, too small,
//! any mode). While the help screen is up any other key closes it and acts (F8 turns its page);
//! while the terminal is too small every other key is ignored and the notice says so. A key
//! that does nothing where it is pressed says so: no key is lost in silence.

use super::front::JogPress;
use super::pages::{self, Page};
use super::Console;
use crate::panel_model::{Axis, DataMode, OpMode, PanelEvent};
use crate::pulse_core::{ClockMode, Command};
use novanc_panel::Key;
use std::time::Instant;

pub use super::front::{JOG_RELEASE, REPEAT_GAP};
pub use super::run::JOG_DEADMAN;

/// What a key asks of the console.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    /// A panel event.
    Event(PanelEvent),
    /// A jog or handwheel key on an axis and direction (its meaning depends on the mode).
    Move(Axis, i8),
    /// Feed override up or down 10 %.
    Override(i32),
    /// Next handwheel scale (x1, x10, x100).
    WheelScale,
    /// Turn the handwheel one detent on its selected axis.
    Wheel(i32),
    /// The handwheel's axis selector turned to the machine's next axis (X Y Z, then the
    /// rotary axes it has): `wheel AXIS 0` (Alt+a).
    WheelAxis,
    /// The typed line names the tape to put in the reader.
    Tape,
    /// The punch: the typed line names the image to punch program memory to (PROGRAM READ).
    Punch,
    /// Show the help screen.
    Help,
    /// Turn the BLOCK DELETE switch over.
    BlockDelete,
    /// Turn the OPTIONAL STOP switch over.
    OptionalStop,
    /// Rapid override one step down: 100, 50, 25, F0, then back to 100.
    RapidOverride,
    /// Spindle override up or down 10 % (50–120).
    SpindleOverride(i32),
    /// Turn the DRY RUN switch over.
    DryRun,
    /// Turn the MACHINE LOCK switch over.
    MachineLock,
    /// Turn the Z NEGLECT switch over.
    ZNeglect,
    /// Acknowledge the messages that live until acknowledged.
    Acknowledge,
    /// A page key of the row beside the selectors: its page (docs/panel.md "Pages").
    Page(crate::panel_model::Page),
    /// The channel selector's next position, on a machine with several channels (Tab, Alt+c).
    NextChannel,
    /// FAULT of the selected channel with the typed reason, on a machine with several
    /// channels (Alt+x).
    Fault,
    /// The part target from the typed number, on a machine with several channels (Alt+n).
    Target,
    /// Nothing.
    None,
}

/// The keyboard map (`docs/panel.md`). Quit (Ctrl-C, Alt+q) and redraw (Ctrl-L) belong to the
/// terminal itself and are not here.
pub fn map_key(k: Key) -> Action {
    use Action as A;
    match k {
        Key::Char(c) => A::Event(PanelEvent::Key(c)),
        Key::Enter => A::Event(PanelEvent::Eob),
        Key::Backspace => A::Event(PanelEvent::Rubout),
        Key::F(n @ 1..=7) => A::Event(PanelEvent::Data(DataMode::ALL[n as usize - 1])),
        Key::Alt(c @ '1'..='7') => A::Event(PanelEvent::Op(OpMode::ALL[c as usize - '1' as usize])),
        Key::F(8) | Key::Alt('h') => A::Help,
        Key::F(9) | Key::Alt('s') => A::Event(PanelEvent::Start),
        Key::F(10) | Key::Alt('p') => A::Event(PanelEvent::Stop),
        Key::F(11) | Key::Alt('r') => A::Event(PanelEvent::Reset),
        Key::F(12) | Key::Alt('e') => A::Event(PanelEvent::EStop),
        Key::Alt('=') | Key::Alt('+') => A::Override(10),
        Key::Alt('-') => A::Override(-10),
        Key::Alt('w') => A::WheelScale,
        Key::Alt(',') => A::Wheel(-1),
        Key::Alt('.') => A::Wheel(1),
        Key::Alt('a') => A::WheelAxis,
        super::state::TAPE_KEY => A::Tape,
        super::state::PUNCH_KEY => A::Punch,
        Key::Alt('b') => A::BlockDelete,
        Key::Alt('o') => A::OptionalStop,
        Key::Alt('0') => A::Event(PanelEvent::Home),
        Key::Alt('f') => A::RapidOverride,
        Key::Alt(']') => A::SpindleOverride(10),
        Key::Alt('[') => A::SpindleOverride(-10),
        Key::Alt('d') => A::DryRun,
        Key::Alt('l') => A::MachineLock,
        Key::Alt('z') => A::ZNeglect,
        Key::Left => A::Move(Axis::X, -1),
        Key::Right => A::Move(Axis::X, 1),
        Key::Up => A::Move(Axis::Y, 1),
        Key::Down => A::Move(Axis::Y, -1),
        Key::PageUp => A::Move(Axis::Z, 1),
        Key::PageDown => A::Move(Axis::Z, -1),
        k if k == super::state::ACKNOWLEDGE => A::Acknowledge,
        // The keys of a machine with several channels (docs/lathe.md "Keys").
        Key::Tab | Key::Alt('c') => A::NextChannel,
        Key::Alt('x') => A::Fault,
        Key::Alt('n') => A::Target,
        k => match super::pages::page_of_key(k) {
            Some(p) => A::Page(p),
            None => A::None,
        },
    }
}

/// What a key that does nothing where it is pressed says, on every console: in selector
/// position `op`, on `page` when a page is up.
pub(crate) fn does_nothing(k: Key, op: OpMode, page: Option<&str>) -> String {
    let on = page
        .map(|p| format!(" on the {p} page"))
        .unwrap_or_default();
    format!(
        "key {} does nothing in {}{on} (F8 shows the keys)",
        key_name(k),
        op.name()
    )
}

/// Whether a key is one of a page's or the editor's cursor keys: the arrows, PgUp/PgDn,
/// Home/End.
pub fn is_cursor_key(k: Key) -> bool {
    matches!(
        k,
        Key::Up
            | Key::Down
            | Key::Left
            | Key::Right
            | Key::PageUp
            | Key::PageDown
            | Key::Home
            | Key::End
    )
}

/// Whether a key is on the relay panel's stop side (STOP, RESET, E-STOP): these always act.
pub fn is_relay_stop(k: Key) -> bool {
    matches!(
        map_key(k),
        Action::Event(PanelEvent::Stop | PanelEvent::Reset | PanelEvent::EStop)
    )
}

pub use super::script_line::key_name;

/// A key from its name (see [`key_name`]); names other than one character are matched without
/// regard to case.
pub fn parse_key(name: &str) -> Result<Key, String> {
    let mut chars = name.chars();
    if let (Some(c), None) = (chars.next(), chars.next()) {
        return Ok(Key::Char(c));
    }
    let low = name.to_ascii_lowercase();
    let named = match low.as_str() {
        "enter" => Some(Key::Enter),
        "backspace" => Some(Key::Backspace),
        "up" => Some(Key::Up),
        "down" => Some(Key::Down),
        "left" => Some(Key::Left),
        "right" => Some(Key::Right),
        "pgup" | "pageup" => Some(Key::PageUp),
        "pgdn" | "pagedown" => Some(Key::PageDown),
        "tab" => Some(Key::Tab),
        "esc" => Some(Key::Esc),
        "home" => Some(Key::Home),
        "end" => Some(Key::End),
        "insert" => Some(Key::Insert),
        "delete" => Some(Key::Delete),
        _ => None,
    };
    if let Some(k) = named {
        return Ok(k);
    }
    if let Some(n) = low.strip_prefix('f').and_then(|n| n.parse::<u8>().ok()) {
        if (1..=12).contains(&n) {
            return Ok(Key::F(n));
        }
    }
    if let Some(rest) = name.get(4..).filter(|_| low.starts_with("alt+")) {
        let mut cs = rest.chars();
        if let (Some(c), None) = (cs.next(), cs.next()) {
            return Ok(Key::Alt(c.to_ascii_lowercase()));
        }
    }
    if let Some(rest) = name.get(5..).filter(|_| low.starts_with("ctrl+")) {
        let mut cs = rest.chars();
        if let (Some(c @ ('a'..='z' | 'A'..='Z')), None) = (cs.next(), cs.next()) {
            return Ok(Key::Ctrl(c.to_ascii_lowercase()));
        }
    }
    Err(format!(
        "unknown key '{name}' (F1-F12, Alt+1-Alt+7 and the other Alt keys of docs/panel.md, Ctrl+P/D/O/E (the page keys), Up, Down, Left, Right, PgUp, PgDn, Home, End, Tab, Enter, Backspace, or one character)"
    ))
}

/// What a console gives the one key pipeline ([`press`]): the state of the keys every console
/// has (the help screen, the screen fit, the switches the toggle keys turn), and the keys it
/// has of its own. The centre's `Console` and a lathe's console answer it; the pipeline is
/// written once, so a key means the same on every machine (issue 22: the dispatch was written
/// twice before stop 40).
pub(crate) trait Keyed: super::side::Side {
    /// The help screen's pages (the help screen cycles through them, and closes after the last).
    const HELP_PAGES: u8;
    /// The machine's key map (a lathe's is an overlay on [`map_key`]).
    fn action(&self, k: Key) -> Action;
    /// Records the key on `/panel/event` (what a replay presses again).
    fn record_key(&mut self, k: Key) {
        self.record(&PanelEvent::Press(k));
    }
    /// The machine's pages' keys, taken before the key map (`takes_first`): a page key, and
    /// the keys of the page shown (its cursor, INPUT, +INPUT, its data keys). Whether `k` was
    /// one of them.
    fn page_keys(&mut self, k: Key, action: &Action) -> bool;
    /// A key of the machine's own (the centre's tape and punch, a lathe's channel, FAULT and
    /// TARGET): whether `action` was one it has.
    fn own_key(&mut self, k: Key, action: &Action) -> bool;
}

/// Presses a key on a console: the one key pipeline. The relay panel (STOP, RESET, E-STOP)
/// acts on every screen; with the help screen up any other key closes it and acts (the help
/// key turns its page, and closes it from the last); with the terminal too small any other key
/// is ignored, and the notice says so; a key that does nothing where it is pressed says so.
pub(crate) fn press<C: Keyed>(c: &mut C, k: Key) {
    let action = c.action(k);
    let stop = is_relay_stop(k);
    if stop {
        c.front().help = 0;
        if let Action::Event(e) = action {
            handle(c, e);
        }
        return;
    }
    if c.front().screen.fits() {
        c.front().new_action();
    }
    let was = c.front().help;
    if was > 0 {
        // Any other key closes the help and acts (it is not eaten).
        c.front().help = 0;
        if action == Action::Help {
            c.record_key(k);
            c.front().help = if was < C::HELP_PAGES { was + 1 } else { 0 };
            return c.refresh();
        }
    }
    if !c.front().screen.fits() {
        // Only the relay panel's stops (above) act while the panel does not fit.
        c.front().screen.refuse(&key_name(k));
        return;
    }
    if takes_first(c, k, &action) {
        return;
    }
    let machine = c.machine_switches();
    let f = c.front();
    let (sw, feed, wheel, op) = (f.switches, f.feed_override, f.wheel, f.op);
    let ev = match action {
        Action::Event(e) => e,
        Action::Move(axis, dir) => match op {
            OpMode::Handle => PanelEvent::Wheel(axis, i32::from(dir)),
            OpMode::Continuous => return hold(c, k, axis, dir),
            _ => PanelEvent::Jog(axis, dir),
        },
        Action::Override(d) => PanelEvent::Override((feed as i32 + d).clamp(0, 150) as u32),
        Action::WheelScale => PanelEvent::WheelScale(super::manual::next_scale(wheel.1)),
        // The handwheel's keys jog its selected axis in CONTINUOUS and STEP (a pendant's axis
        // selector and jog buttons): the rotary axes' jog keys, since stop 54.
        Action::Wheel(n) => match op {
            OpMode::Continuous => return hold(c, k, wheel.0, n.signum() as i8),
            OpMode::Step => PanelEvent::Jog(wheel.0, n.signum() as i8),
            _ => PanelEvent::Wheel(wheel.0, n),
        },
        Action::WheelAxis => {
            let s = c.axis_settings();
            let list: Vec<usize> = s.axis_list().collect();
            let at = list.iter().position(|&a| a == wheel.0.index());
            let next = at.map_or(0, |i| (i + 1) % list.len());
            PanelEvent::Wheel(Axis::ALL[list.get(next).copied().unwrap_or(0)], 0)
        }
        Action::BlockDelete => PanelEvent::BlockDelete(!sw.block_delete),
        Action::OptionalStop => PanelEvent::OptionalStop(!sw.optional_stop),
        Action::RapidOverride => {
            PanelEvent::RapidOverride(super::next_rapid(machine.rapid_override))
        }
        Action::SpindleOverride(d) => {
            PanelEvent::SpindleOverride(super::next_spindle(machine.spindle_override, d))
        }
        Action::DryRun => PanelEvent::DryRun(!machine.dry_run),
        Action::MachineLock => PanelEvent::MachineLock(!machine.machine_lock),
        Action::ZNeglect => PanelEvent::ZNeglect(!machine.z_neglect),
        Action::Help => {
            c.record_key(k);
            c.front().help = 1;
            return c.refresh();
        }
        Action::Acknowledge => {
            // Esc: the program messages waiting (MSG, NOT KEPT) are acknowledged, on every
            // console (before stop 46 each had its own copy of this).
            if !c.book().acknowledge() {
                c.front().message = format!("{}: no message to acknowledge", key_name(k));
            }
            c.record_key(k);
            return c.refresh();
        }
        a => {
            if !c.own_key(k, &a) {
                // Recorded: the key was pressed, and said so.
                c.record_key(k);
                let page = Some(c.page())
                    .filter(|p| *p != Page::Mode)
                    .map(|p| p.label());
                c.front().message = does_nothing(k, op, page);
                c.refresh();
            }
            return;
        }
    };
    handle(c, ev)
}

/// The keys taken before the key map, on every console: the pages' (`Keyed::page_keys`), the
/// editor's cursor keys in DATA (`entry::cursor_key`) and the MDI recall (`entry::recall_key`).
/// Each is recorded, as every key that acts is (a replay moves, types or recalls the same), and
/// the state after it shown. Whether `k` was one of them. Before stop 45 each console had its
/// own.
fn takes_first<C: Keyed>(c: &mut C, k: Key, action: &Action) -> bool {
    let taken = tab_adds(c, k)
        || c.page_keys(k, action)
        || super::entry::cursor_key(c, k)
        || super::entry::recall_key(c, k);
    if taken {
        c.record_key(k);
        c.refresh();
    }
    taken
}

/// The keyboard's Tab, one rule on every machine: with a page up and a value typed, +INPUT
/// (`entry::plus_input`, the keypad's key: the value added to the cell under the cursor, or
/// INPUT on a page without cells); otherwise the channel selector's next position, as Alt+c
/// (a machine with one channel says the key does nothing). Whether `k` was Tab taken as
/// +INPUT. Before stop 47 the centre took Tab as +INPUT on every page, typed or not, and a
/// lathe only on OFS and MACRO, turning the channel (and clearing the line) on its other pages.
fn tab_adds<C: Keyed>(c: &mut C, k: Key) -> bool {
    if k != Key::Tab || c.page() == Page::Mode || c.front().entry.trim().is_empty() {
        return false;
    }
    super::entry::plus_input(c);
    true
}

/// One event of the panel grammar on a console, every console's one dispatch (issue 22: each
/// console had its own before stop 44): a key goes through the key pipeline ([`press`], which
/// records it as what it did); any other event is recorded on `/panel/event`; a script's
/// waits run the machine (`wait::wait`) and `show` does nothing here (the front end prints
/// the display); an operator action ends the last one's message and goes to the machine side
/// (`Side::act`: its own gate, the rules written once and its own words). The machine's
/// state is then taken and shown.
pub(crate) fn handle<C: Keyed>(c: &mut C, ev: PanelEvent) {
    use super::wait::{wait, WaitFor};
    if let PanelEvent::Press(k) = ev {
        return press(c, k);
    }
    c.record(&ev);
    match ev {
        PanelEvent::Wait => wait(c, WaitFor::Idle),
        PanelEvent::WaitBlock(n) => wait(c, WaitFor::Block(n)),
        PanelEvent::WaitMs(t) => wait(c, WaitFor::Ms(t)),
        PanelEvent::Show => {}
        ev => {
            // A simulated machine input is not the operator's: the message lives on.
            if !matches!(ev, PanelEvent::Input { .. }) {
                c.front().new_action();
            }
            c.act(ev);
        }
    }
    c.refresh();
}

/// A CONTINUOUS jog key as a terminal reports it (`HeldJog`): a tap moves one increment (run
/// to rest in virtual time), a held key jogs until it stops repeating (`manual::keep` lets it
/// go).
fn hold<C: Keyed>(c: &mut C, k: Key, axis: Axis, dir: i8) {
    let virtual_time = c.clock() == ClockMode::Virtual;
    match c
        .front()
        .jog_key
        .press(axis, dir, Instant::now(), virtual_time)
    {
        JogPress::KeepAlive => {
            if let Some(ch) = c.front().jogging {
                c.tell(ch, Command::JogAlive(super::deadman_ms()));
            }
        }
        JogPress::Begin => {
            // The tap's increment may still be moving: the jog begins on a later repeat.
            c.refresh();
            let ch = c.selected();
            if !c.channels().get(ch).is_some_and(|s| s.moving) {
                handle(c, PanelEvent::Jog(axis, dir));
                let began = c.front().jogging.is_some();
                c.front().jog_key.began(began);
            }
        }
        JogPress::Tap { release } => {
            if release {
                super::manual::release(c, true);
            }
            // A tap is the key (a held key is `jog X+`).
            c.record(&PanelEvent::Press(k));
            super::manual::tap(c, axis, dir);
            c.refresh();
        }
    }
}

impl Keyed for Console {
    const HELP_PAGES: u8 = 2;
    fn action(&self, k: Key) -> Action {
        map_key(k)
    }
    fn page_keys(&mut self, k: Key, action: &Action) -> bool {
        if let Some(p) = pages::page_of_key(k) {
            pages::page_key(self, p);
            return true;
        }
        if matches!(
            action,
            Action::Event(PanelEvent::Op(_) | PanelEvent::Data(_))
        ) {
            self.shell.shown.page = Page::Mode;
        }
        // What a page takes (a data key, INPUT, a cursor key) is in the recording, as every
        // key that acts: a replay types the same revision.
        self.shell.shown.page != Page::Mode && pages::press(self, k)
    }
    fn own_key(&mut self, _k: Key, action: &Action) -> bool {
        match action {
            Action::Tape => self.tape_from_entry(),
            Action::Punch => self.punch_from_entry(),
            _ => return false,
        }
        true
    }
}

impl Console {
    /// Presses a key of the terminal's key map ([`press`], the one key pipeline).
    pub fn press(&mut self, k: Key) {
        press(self, k)
    }

    /// Tells the console whether the terminal is large enough for the panel (the terminal
    /// front end calls it every frame).
    pub fn set_screen_fits(&mut self, fits: bool) {
        self.shell.front.screen.set(fits)
    }

    /// Whether the help screen is up.
    pub fn help_shown(&self) -> bool {
        self.shell.front.help_shown()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_selector_position_and_button_has_a_key() {
        for (i, m) in OpMode::ALL.iter().enumerate() {
            let c = char::from(b'1' + i as u8);
            assert_eq!(map_key(Key::Alt(c)), Action::Event(PanelEvent::Op(*m)));
        }
        for (i, m) in DataMode::ALL.iter().enumerate() {
            assert_eq!(
                map_key(Key::F(i as u8 + 1)),
                Action::Event(PanelEvent::Data(*m))
            );
        }
        assert_eq!(map_key(Key::F(9)), Action::Event(PanelEvent::Start));
        assert_eq!(map_key(Key::F(10)), Action::Event(PanelEvent::Stop));
        assert_eq!(map_key(Key::F(11)), Action::Event(PanelEvent::Reset));
        assert_eq!(map_key(Key::F(12)), Action::Event(PanelEvent::EStop));
        assert_eq!(map_key(Key::Enter), Action::Event(PanelEvent::Eob));
        assert_eq!(map_key(Key::Char('*')), Action::Event(PanelEvent::Key('*')));
        assert_eq!(map_key(Key::PageDown), Action::Move(Axis::Z, -1));
        assert!(is_relay_stop(Key::F(12)) && is_relay_stop(Key::Alt('p')));
        assert!(!is_relay_stop(Key::F(9)));
    }

    #[test]
    fn key_names_round_trip() {
        for k in [
            Key::F(1),
            Key::F(12),
            Key::Alt('7'),
            Key::Alt('='),
            Key::Up,
            Key::PageDown,
            Key::Enter,
            Key::Backspace,
            Key::Char('x'),
            Key::Char('*'),
            Key::Ctrl('p'),
            Key::Tab,
            Key::Home,
        ] {
            assert_eq!(parse_key(&key_name(k)), Ok(k), "{k:?}");
        }
        assert_eq!(parse_key("pgup"), Ok(Key::PageUp));
        assert_eq!(parse_key("ALT+2"), Ok(Key::Alt('2')));
        assert_eq!(parse_key("CTRL+O"), Ok(Key::Ctrl('o')));
        assert!(parse_key("Ctrl+1").is_err());
        assert!(parse_key("F13").is_err());
        assert!(parse_key("Hyper").unwrap_err().contains("unknown key"));
    }
}
