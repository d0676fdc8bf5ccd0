//! The data keys of the NC panel: alphabetic (15a), numeric with their shifted characters
//! (15b), SHIFT (15c), SPACE, RUBOUT, EOB, the tape reader and punch keys, clickable; and the physical
//! keyboard, with the terminal panel's key map. Each key becomes a `PanelEvent`; the console decides what it means.

use super::controls::HandState;
use crate::panel_model::{Axis, PanelEvent};
use egui::{vec2, Ui};
use novanc_panel::Key;

/// The numeric keys (15b) and what each gives with SHIFT (15c).
pub const NUMERIC_KEYS: [(char, char); 12] = [
    ('1', '='),
    ('2', ','),
    ('3', '/'),
    ('4', '('),
    ('5', ')'),
    ('6', '*'),
    ('7', '$'),
    ('8', ';'),
    ('9', '+'),
    ('0', '#'),
    ('.', ':'),
    ('-', '_'),
];

/// The data keys: alphabetic (15a), numeric with shifted characters (15b), SHIFT (15c),
/// SPACE, RUBOUT, EOB (INPUT on a page) and +INPUT (a page adds the typed value to the cell
/// under its cursor: `PanelEvent::PlusInput`, on every machine; the keyboard's Tab on a page);
/// the tape reader (PROGRAM READ) and punch keys, on every machine since stop 52 (a lathe's read
/// a file into, and punch, its selected channel's program). Before stop 46 the lathe's keypad
/// had no +INPUT, and the centre's sent Tab, which on a lathe with nothing typed turns the
/// channel selector.
pub fn data_keys(ui: &mut Ui, hand: &mut HandState, out: &mut Vec<PanelEvent>) {
    let key = |ui: &mut Ui, label: &str, w: f32, lit: bool| -> bool {
        let b = egui::Button::new(egui::RichText::new(label).monospace().size(13.0))
            .min_size(vec2(w, 26.0))
            .selected(lit);
        ui.add(b).clicked()
    };
    ui.spacing_mut().item_spacing = vec2(3.0, 3.0);
    ui.horizontal(|ui| {
        for (n, s) in NUMERIC_KEYS {
            let label = if hand.shift {
                format!("{s}")
            } else {
                format!("{n}")
            };
            if key(ui, &label, 26.0, false) {
                out.push(PanelEvent::Key(if hand.shift { s } else { n }));
                hand.shift = false;
            }
        }
    });
    for row in ["ABCDEFGHI", "JKLMNOPQR", "STUVWXYZ"] {
        ui.horizontal(|ui| {
            for ch in row.chars() {
                if key(ui, &ch.to_string(), 26.0, false) {
                    out.push(PanelEvent::Key(ch));
                    hand.shift = false;
                }
            }
            if row.len() == 8 && key(ui, "SP", 26.0, false) {
                out.push(PanelEvent::Key(' '));
            }
        });
    }
    ui.horizontal(|ui| {
        if key(ui, "SHIFT", 60.0, hand.shift) {
            hand.shift = !hand.shift;
        }
        if key(ui, "RUBOUT", 70.0, false) {
            out.push(PanelEvent::Rubout);
        }
        if key(ui, "EOB *", 70.0, false) {
            out.push(PanelEvent::Eob);
        }
        if key(ui, "+INPUT", 60.0, false) {
            out.push(PanelEvent::PlusInput);
        }
    });
    // The tape reader and punch keys (the terminal's Alt+t and Alt+u), a row of their own so
    // that a lathe's panel, with its channel keys, stays inside the window.
    ui.horizontal(|ui| {
        if key(ui, "TAPE", 50.0, false) {
            out.push(PanelEvent::Press(Key::Alt('t')));
        }
        if key(ui, "PUNCH", 56.0, false) {
            out.push(PanelEvent::Press(Key::Alt('u')));
        }
    });
}

/// The physical keyboard, on both machines' windows, as the terminal's keys: each key goes to
/// the console as `PanelEvent::Press`, through the one key map (`console::keys::map_key`,
/// docs/panel.md), so an operator can go from the terminal to the window and back. Typed text
/// is `Char` (not with Alt or Ctrl held); Enter, Backspace, Tab, Esc, Home, End, Delete, the
/// arrows and pages, F1–F12, Alt with a letter, a digit or `= + - , . [ ]`, Ctrl with a letter.
/// One thing the window knows better than a terminal: a held axis key in CONTINUOUS (`jogs`:
/// the selector there, no page but POS up) stops its jog when it is let go (`JogRelease`), not
/// 150 ms after its last repeat. Alt+, and Alt+. are the terminal's keys (before stop 54 the
/// window's own): the handwheel (HANDLE) or a jog (CONTINUOUS, STEP) of the axis the console's
/// selector (Alt+a, the window's selector) shows.
///
/// Returns the events and whether a quit key of the terminal (Ctrl-C, Alt+q) was pressed: it
/// closes the window. Before stop 49 the centre's window had a key map of its own, without
/// Esc, F8 or Tab's channel turn, and the lathe's took no Alt with a sign (its feed override,
/// handwheel and spindle override keys did nothing) and no Home, End or Delete.
pub fn keyboard(
    events: &[egui::Event],
    jogs: bool,
    hand: &mut HandState,
) -> (Vec<PanelEvent>, bool) {
    use egui::Key as K;
    // Text typed with Alt or Ctrl held belongs to a shortcut, not to the data keys.
    let alt_combo = events.iter().any(|e| {
        matches!(e, egui::Event::Key { pressed: true, modifiers, .. }
            if modifiers.alt || modifiers.ctrl)
    });
    let moves = [
        (K::ArrowLeft, Key::Left),
        (K::ArrowRight, Key::Right),
        (K::ArrowUp, Key::Up),
        (K::ArrowDown, Key::Down),
        (K::PageUp, Key::PageUp),
        (K::PageDown, Key::PageDown),
    ];
    let mut out = Vec::new();
    let mut quit = false;
    for e in events {
        let k = match e {
            // egui turns Ctrl-C into a copy (with no key event): it is the terminal's Ctrl-C.
            egui::Event::Copy => Some(Key::Ctrl('c')),
            egui::Event::Text(t) if !alt_combo => {
                let typed = t.chars().filter(|c| !c.is_control());
                out.extend(typed.map(|c| PanelEvent::Press(Key::Char(c))));
                None
            }
            egui::Event::Key {
                key,
                pressed,
                repeat,
                modifiers,
                ..
            } => match moves.iter().find(|m| m.0 == *key) {
                // Each press and auto-repeat is the terminal's key (a tap in CONTINUOUS is one
                // increment, a held key jogs); the release of a held one ends its jog.
                Some(&(_, k)) if *pressed => {
                    if *repeat && jogs {
                        hand.key_jog = Some(*key);
                    }
                    Some(k)
                }
                Some(_) => {
                    if hand.key_jog == Some(*key) {
                        hand.key_jog = None;
                        out.push(PanelEvent::JogRelease);
                    }
                    None
                }
                None if *pressed => terminal_key(*key, *modifiers),
                None => None,
            },
            _ => None,
        };
        match k {
            Some(Key::Alt('q') | Key::Ctrl('c')) => quit = true,
            Some(k) => out.push(PanelEvent::Press(k)),
            None => {}
        }
    }
    (out, quit)
}

/// Whether an axis key held may jog (the `jogs` of [`keyboard`]): the selector in CONTINUOUS,
/// no page up but POS.
pub fn holds_jog(op: crate::panel_model::OpMode, page: crate::panel_model::Page) -> bool {
    use crate::panel_model::{OpMode, Page};
    op == OpMode::Continuous && matches!(page, Page::Mode | Page::Pos)
}

/// The terminal's key of a pressed key that is not an axis key, if it has one.
fn terminal_key(key: egui::Key, m: egui::Modifiers) -> Option<Key> {
    use egui::Key as K;
    let fkeys = [
        K::F1,
        K::F2,
        K::F3,
        K::F4,
        K::F5,
        K::F6,
        K::F7,
        K::F8,
        K::F9,
        K::F10,
        K::F11,
        K::F12,
    ];
    if let Some(i) = fkeys.iter().position(|k| *k == key) {
        return Some(Key::F(i as u8 + 1));
    }
    let signs = [
        (K::Equals, '='),
        (K::Plus, '+'),
        (K::Minus, '-'),
        (K::Comma, ','),
        (K::Period, '.'),
        (K::OpenBracket, '['),
        (K::CloseBracket, ']'),
    ];
    // A letter or digit key's character (lower case), or a sign's, for Alt and Ctrl.
    let ch = (key.name().len() == 1)
        .then(|| key.name().chars().next())
        .flatten()
        .filter(|c| c.is_ascii_alphanumeric())
        .map(|c| c.to_ascii_lowercase())
        .or_else(|| signs.iter().find(|s| s.0 == key).map(|s| s.1));
    match ch {
        Some(c) if m.alt => Some(Key::Alt(c)),
        Some(c) if (m.ctrl || m.command) && c.is_ascii_alphabetic() => Some(Key::Ctrl(c)),
        _ => match key {
            K::Enter => Some(Key::Enter),
            K::Backspace => Some(Key::Backspace),
            K::Tab => Some(Key::Tab),
            K::Escape => Some(Key::Esc),
            K::Home => Some(Key::Home),
            K::End => Some(Key::End),
            K::Delete => Some(Key::Delete),
            _ => None,
        },
    }
}

/// The terminal key of an axis direction: X on Left/Right, Y on Up/Down, Z on PgUp/PgDn. The
/// rotary axes' are the handwheel's keys, Alt+. and Alt+, (the axis selected with Alt+a or the
/// window's selector): a detent in HANDLE, a jog in CONTINUOUS and STEP.
pub fn arrow_key(axis: Axis, dir: i8) -> Key {
    match (axis, dir > 0) {
        (Axis::X, false) => Key::Left,
        (Axis::X, true) => Key::Right,
        (Axis::Y, true) => Key::Up,
        (Axis::Y, false) => Key::Down,
        (Axis::Z, true) => Key::PageUp,
        (Axis::Z, false) => Key::PageDown,
        (_, true) => Key::Alt('.'),
        (_, false) => Key::Alt(','),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(k: egui::Key, pressed: bool, repeat: bool, alt: bool) -> egui::Event {
        egui::Event::Key {
            key: k,
            physical_key: None,
            pressed,
            repeat,
            modifiers: egui::Modifiers {
                alt,
                ..Default::default()
            },
        }
    }

    fn ctrl(k: egui::Key) -> egui::Event {
        let mut e = key(k, true, false, false);
        if let egui::Event::Key { modifiers, .. } = &mut e {
            modifiers.ctrl = true;
        }
        e
    }

    /// The keys pressed (`jogs`: a CONTINUOUS jog may be held), and whether one quits.
    fn run(evs: &[egui::Event], jogs: bool, hand: &mut HandState) -> (Vec<PanelEvent>, bool) {
        keyboard(evs, jogs, hand)
    }

    fn presses(keys: &[Key]) -> Vec<PanelEvent> {
        keys.iter().map(|k| PanelEvent::Press(*k)).collect()
    }

    #[test]
    fn typed_text_enter_and_backspace_are_the_terminal_s_keys() {
        let evs = [
            egui::Event::Text("g1".into()),
            key(egui::Key::Enter, true, false, false),
            key(egui::Key::Backspace, true, false, false),
            key(egui::Key::Tab, true, false, false),
            key(egui::Key::Tab, false, false, false),
            key(egui::Key::Escape, true, false, false),
        ];
        let (out, quit) = run(&evs, false, &mut HandState::default());
        use Key::*;
        let want = [Char('g'), Char('1'), Enter, Backspace, Tab, Esc];
        assert_eq!((out, quit), (presses(&want), false));
    }

    #[test]
    fn function_alt_and_ctrl_keys_are_the_terminal_s() {
        let mut h = HandState {
            wheel_axis: Axis::Z,
            ..HandState::default()
        };
        let evs = [
            key(egui::Key::F2, true, false, false),
            key(egui::Key::F8, true, false, false),
            key(egui::Key::Num7, true, false, true),
            egui::Event::Text("7".into()), // the text of Alt+7 is not a data key
            key(egui::Key::F9, true, false, false),
            key(egui::Key::Equals, true, false, true),
            key(egui::Key::Minus, true, false, true),
            key(egui::Key::CloseBracket, true, false, true),
            key(egui::Key::T, true, false, true),
            ctrl(egui::Key::O),
            key(egui::Key::Home, true, false, false),
            key(egui::Key::End, true, false, false),
            key(egui::Key::Delete, true, false, false),
        ];
        let (out, quit) = run(&evs, false, &mut h);
        use Key::*;
        let want = [
            F(2),
            F(8),
            Alt('7'),
            F(9),
            Alt('='),
            Alt('-'),
            Alt(']'),
            Alt('t'),
            Ctrl('o'),
            Home,
            End,
            Delete,
        ];
        assert_eq!((out, quit), (presses(&want), false));
        // Alt+, and Alt+. are the terminal's keys: the pipeline turns the handwheel on the
        // console's selected axis in HANDLE and jogs it in CONTINUOUS and STEP (the window's
        // selector sets the console's).
        let evs = [
            key(egui::Key::Comma, true, false, true),
            key(egui::Key::Period, true, false, true),
        ];
        let out = run(&evs, false, &mut h).0;
        assert_eq!(out, presses(&[Alt(','), Alt('.')]));
    }

    #[test]
    fn axis_keys_are_the_terminals_and_a_held_jog_stops_on_release() {
        let mut h = HandState::default();
        let up = key(egui::Key::PageUp, true, false, false);
        let (out, _) = run(&[up.clone(), up], false, &mut h);
        assert_eq!(out, presses(&[Key::PageUp, Key::PageUp]));

        // A tap: the key alone (one increment); its release says nothing.
        let tap = [
            key(egui::Key::ArrowLeft, true, false, false),
            key(egui::Key::ArrowLeft, false, false, false),
        ];
        assert_eq!(run(&tap, true, &mut h).0, presses(&[Key::Left]));
        // Held: the repeats are the terminal's, and the release stops the jog at once.
        let evs = [
            key(egui::Key::ArrowLeft, true, false, false),
            key(egui::Key::ArrowLeft, true, true, false),
            key(egui::Key::ArrowLeft, false, false, false),
        ];
        let mut want = presses(&[Key::Left, Key::Left]);
        want.push(PanelEvent::JogRelease);
        assert_eq!(run(&evs, true, &mut h).0, want);
        assert_eq!(h.key_jog, None);
        // Where no jog can be held (HANDLE, a page), a release is nothing.
        assert_eq!(run(&evs, false, &mut h).0, presses(&[Key::Left, Key::Left]));
    }

    #[test]
    fn the_terminals_quit_keys_close_the_window_and_nothing_else() {
        // egui-winit sends Ctrl-C as `Event::Copy` alone.
        for quit in [
            key(egui::Key::Q, true, false, true),
            ctrl(egui::Key::C),
            egui::Event::Copy,
        ] {
            let (out, q) = run(
                std::slice::from_ref(&quit),
                false,
                &mut HandState::default(),
            );
            assert!(q, "{quit:?} closes the window");
            assert!(out.is_empty(), "{quit:?} is nothing else: {out:?}");
        }
    }
}
