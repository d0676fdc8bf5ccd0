//! The data keys of the NC panel: alphabetic (15a), numeric with their shifted characters
//! (15b), SHIFT (15c), SPACE, RUBOUT, EOB, the tape reader and punch keys, clickable; and the physical
//! keyboard, with the terminal panel's key map. Each key becomes a `PanelEvent`; the console decides what it means.

use super::controls::HandState;
use crate::panel_model::{Axis, DataMode, OpMode, Page, PanelEvent, PanelView};
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
/// with `tape`, the machining centre's tape reader and punch keys. Before stop 46 the lathe's
/// keypad had no +INPUT, and the centre's sent Tab, which on a lathe with nothing typed turns
/// the channel selector.
pub fn data_keys(ui: &mut Ui, hand: &mut HandState, out: &mut Vec<PanelEvent>, tape: bool) {
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
        if tape && key(ui, "TAPE", 50.0, false) {
            hand.tape_requested = true;
        }
        if tape && key(ui, "PUNCH", 56.0, false) {
            hand.punch_requested = true;
        }
    });
}

/// The physical keyboard, with the terminal panel's key map (docs/panel.md) so an operator
/// can go from one to the other:
/// - letters (made upper case), digits and signs are data keys; Enter is EOB, Backspace RUBOUT;
/// - F1–F7 turn the data-processing mode selector, Alt+1–Alt+7 the operation mode selector;
/// - F9 START, F10 STOP, F11 RESET, F12 E-STOP (also Alt+S, Alt+P, Alt+R, Alt+E);
/// - Alt+= / Alt+- feed override ±10 %; Alt+W the ×1/×10/×100/×1000 increment; Alt+, / Alt+. one
///   handwheel detent; Alt+T the tape reader (the typed line names the file); Alt+U the punch
///   (in PROGRAM READ the typed line names the image, `PATH` or `PATH EIA`);
/// - Ctrl+P/D/O/E the page keys POS, PROG, OFS, MSG; Tab +INPUT;
/// - arrows (X, Y) and Page Up/Down (Z): the terminal's arrow keys (`move_key`).
pub fn keyboard(
    events: &[egui::Event],
    view: &PanelView,
    hand: &mut HandState,
    out: &mut Vec<PanelEvent>,
) {
    use egui::Key as K;
    // Text typed with Alt held belongs to a shortcut, not to the data keys.
    let alt_combo = events.iter().any(|e| {
        matches!(e, egui::Event::Key { pressed: true, modifiers, .. }
            if modifiers.alt || modifiers.ctrl)
    });
    for e in events {
        match e {
            // egui turns Ctrl-C into a copy: it is the terminal's quit key here.
            egui::Event::Copy => hand.quit_requested = true,
            egui::Event::Text(t) if !alt_combo => {
                for ch in t.chars().filter(|c| !c.is_control()) {
                    out.push(PanelEvent::Key(ch.to_ascii_uppercase()));
                }
            }
            egui::Event::Key {
                key,
                pressed,
                repeat,
                modifiers,
                ..
            } => {
                let axis_key = match key {
                    K::ArrowLeft => Some((Axis::X, -1i8)),
                    K::ArrowRight => Some((Axis::X, 1)),
                    K::ArrowUp => Some((Axis::Y, 1)),
                    K::ArrowDown => Some((Axis::Y, -1)),
                    K::PageUp => Some((Axis::Z, 1)),
                    K::PageDown => Some((Axis::Z, -1)),
                    _ => None,
                };
                if let Some((axis, dir)) = axis_key {
                    move_key(view, hand, axis, dir, *pressed, *repeat, out);
                    continue;
                }
                if !pressed {
                    continue;
                }
                let fkey = [K::F1, K::F2, K::F3, K::F4, K::F5, K::F6, K::F7];
                let digit = [
                    K::Num1,
                    K::Num2,
                    K::Num3,
                    K::Num4,
                    K::Num5,
                    K::Num6,
                    K::Num7,
                ];
                if let Some(i) = fkey.iter().position(|k| k == key) {
                    out.push(PanelEvent::Data(DataMode::ALL[i]));
                } else if let (true, Some(i)) = (modifiers.alt, digit.iter().position(|k| k == key))
                {
                    out.push(PanelEvent::Op(OpMode::ALL[i]));
                } else if *repeat {
                } else {
                    let alt = modifiers.alt;
                    let ctrl = modifiers.ctrl || modifiers.command;
                    match key {
                        K::Enter => out.push(PanelEvent::Eob),
                        K::Backspace => out.push(PanelEvent::Rubout),
                        K::F9 => out.push(PanelEvent::Start),
                        K::F10 => out.push(PanelEvent::Stop),
                        K::F11 => out.push(PanelEvent::Reset),
                        K::F12 => out.push(PanelEvent::EStop),
                        K::S if alt => out.push(PanelEvent::Start),
                        K::P if alt => out.push(PanelEvent::Stop),
                        K::R if alt => out.push(PanelEvent::Reset),
                        K::E if alt => out.push(PanelEvent::EStop),
                        K::T if alt => hand.tape_requested = true,
                        K::U if alt => hand.punch_requested = true,
                        K::B if alt => out.push(PanelEvent::Press(Key::Alt('b'))),
                        K::O if alt => out.push(PanelEvent::Press(Key::Alt('o'))),
                        K::F if alt => out.push(PanelEvent::Press(Key::Alt('f'))),
                        K::D if alt => out.push(PanelEvent::Press(Key::Alt('d'))),
                        K::L if alt => out.push(PanelEvent::Press(Key::Alt('l'))),
                        K::Z if alt => out.push(PanelEvent::Press(Key::Alt('z'))),
                        K::OpenBracket if alt => out.push(PanelEvent::Press(Key::Alt('['))),
                        K::CloseBracket if alt => out.push(PanelEvent::Press(Key::Alt(']'))),
                        K::Equals | K::Plus if alt => {
                            out.push(PanelEvent::Override((view.feed_override + 10).min(150)))
                        }
                        K::Minus if alt => {
                            out.push(PanelEvent::Override(view.feed_override.saturating_sub(10)))
                        }
                        K::W if alt => out.push(PanelEvent::WheelScale(match view.wheel.1 {
                            1 => 10,
                            10 => 100,
                            100 => 1000,
                            _ => 1,
                        })),
                        K::Q if alt => hand.quit_requested = true,
                        K::Num0 if alt => out.push(PanelEvent::Home),
                        K::C if ctrl => hand.quit_requested = true,
                        K::Tab => out.push(PanelEvent::Press(Key::Tab)),
                        K::Home => out.push(PanelEvent::Press(Key::Home)),
                        K::End => out.push(PanelEvent::Press(Key::End)),
                        K::Delete => out.push(PanelEvent::Press(Key::Delete)),
                        K::P if ctrl => out.push(PanelEvent::Press(Key::Ctrl('p'))),
                        K::D if ctrl => out.push(PanelEvent::Press(Key::Ctrl('d'))),
                        K::O if ctrl => out.push(PanelEvent::Press(Key::Ctrl('o'))),
                        K::E if ctrl => out.push(PanelEvent::Press(Key::Ctrl('e'))),
                        K::G if ctrl => out.push(PanelEvent::Press(Key::Ctrl('g'))),
                        K::T if ctrl => out.push(PanelEvent::Press(Key::Ctrl('t'))),
                        K::U if ctrl => out.push(PanelEvent::Press(Key::Ctrl('u'))),
                        K::Comma if alt => out.push(PanelEvent::Wheel(hand.wheel_axis, -1)),
                        K::Period if alt => out.push(PanelEvent::Wheel(hand.wheel_axis, 1)),
                        _ => {}
                    }
                }
            }
            _ => {}
        }
    }
}

/// The physical keyboard as the terminal's keys (`novanc_panel::Key`), for a console that
/// takes those (the lathe's `LatheConsole::press`, docs/lathe.md "Keys"): typed text is
/// `Char` (not with Alt or Ctrl held), Enter, Backspace, Tab, Esc, the arrows and pages, F1–F12,
/// Alt with a letter or digit, Ctrl with a letter.
pub fn terminal_keys(events: &[egui::Event]) -> Vec<Key> {
    use egui::Key as K;
    let alt_combo = events.iter().any(|e| {
        matches!(e, egui::Event::Key { pressed: true, modifiers, .. }
            if modifiers.alt || modifiers.ctrl)
    });
    let mut out = Vec::new();
    for e in events {
        match e {
            // egui turns Ctrl-C into a copy (with no key event): it is the terminal's Ctrl-C.
            egui::Event::Copy => out.push(Key::Ctrl('c')),
            egui::Event::Text(t) if !alt_combo => {
                out.extend(t.chars().filter(|c| !c.is_control()).map(Key::Char));
            }
            egui::Event::Key {
                key,
                pressed: true,
                modifiers,
                ..
            } => {
                let named = match key {
                    K::Enter => Some(Key::Enter),
                    K::Backspace => Some(Key::Backspace),
                    K::Tab => Some(Key::Tab),
                    K::Escape => Some(Key::Esc),
                    K::ArrowUp => Some(Key::Up),
                    K::ArrowDown => Some(Key::Down),
                    K::ArrowLeft => Some(Key::Left),
                    K::ArrowRight => Some(Key::Right),
                    K::PageUp => Some(Key::PageUp),
                    K::PageDown => Some(Key::PageDown),
                    _ => None,
                };
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
                // A letter or digit key's character (lower case), for Alt and Ctrl.
                let ch = key
                    .name()
                    .chars()
                    .next()
                    .filter(|c| key.name().len() == 1 && c.is_ascii_alphanumeric())
                    .map(|c| c.to_ascii_lowercase());
                if let Some(i) = fkeys.iter().position(|k| k == key) {
                    out.push(Key::F(i as u8 + 1));
                } else if let (true, Some(c)) = (modifiers.alt, ch) {
                    out.push(Key::Alt(c));
                } else if let (true, Some(c)) = (modifiers.ctrl || modifiers.command, ch) {
                    if c.is_ascii_alphabetic() {
                        out.push(Key::Ctrl(c));
                    }
                } else if let Some(k) = named {
                    out.push(k);
                }
            }
            _ => {}
        }
    }
    out
}

/// The terminal key of an axis direction: X on Left/Right, Y on Up/Down, Z on PgUp/PgDn.
pub fn arrow_key(axis: Axis, dir: i8) -> Key {
    match (axis, dir > 0) {
        (Axis::X, false) => Key::Left,
        (Axis::X, true) => Key::Right,
        (Axis::Y, true) => Key::Up,
        (Axis::Y, false) => Key::Down,
        (Axis::Z, true) => Key::PageUp,
        (Axis::Z, false) => Key::PageDown,
    }
}

/// An axis key, as the terminal's key map takes it (docs/panel.md, "Jogging"): each press and
/// each auto-repeat is the terminal's key, so a tap in CONTINUOUS is one increment and a held
/// key jogs; in HANDLE a detent, in STEP an increment, on a page its cursor, in MDI the recall.
/// The window also sees the release, so a held CONTINUOUS jog stops at once rather than
/// 150 ms later.
fn move_key(
    view: &PanelView,
    hand: &mut HandState,
    axis: Axis,
    dir: i8,
    pressed: bool,
    repeat: bool,
    out: &mut Vec<PanelEvent>,
) {
    if pressed {
        out.push(PanelEvent::Press(arrow_key(axis, dir)));
        let jogs = matches!(view.page, Page::Mode | Page::Pos);
        if repeat && jogs && view.op_mode == OpMode::Continuous {
            hand.key_jog = Some((axis, dir));
        }
    } else if hand.key_jog == Some((axis, dir)) {
        hand.key_jog = None;
        out.push(PanelEvent::JogRelease);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::panel_model::Lamps;

    fn view(op: OpMode, ovr: u32) -> PanelView {
        PanelView {
            display: vec![],
            op_mode: op,
            data_mode: DataMode::Revise,
            run: 0,
            lamps: Lamps::default(),
            feed_override: ovr,
            switches: Default::default(),
            axis_mm: [0.0; 3],
            tip_mm: [0.0; 3],
            tool: None,
            spindle: 0,
            wheel: (Axis::X, 10),
            entry: String::new(),
            machine_ns: 0,
            help: 0,
            page: crate::panel_model::Page::Mode,
            ignored: None,
        }
    }

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

    fn run(evs: &[egui::Event], v: &PanelView, hand: &mut HandState) -> Vec<PanelEvent> {
        let mut out = Vec::new();
        keyboard(evs, v, hand, &mut out);
        out
    }

    #[test]
    fn keyboard_maps_letters_enter_and_backspace() {
        let evs = vec![
            egui::Event::Text("g1".into()),
            key(egui::Key::Enter, true, false, false),
            key(egui::Key::Backspace, true, false, false),
        ];
        let out = run(&evs, &view(OpMode::Data, 100), &mut HandState::default());
        let want = [
            PanelEvent::Key('G'),
            PanelEvent::Key('1'),
            PanelEvent::Eob,
            PanelEvent::Rubout,
        ];
        assert_eq!(out, want);
    }

    #[test]
    fn function_and_alt_keys_are_the_terminal_panels() {
        let v = view(OpMode::Data, 150);
        let mut h = HandState::default();
        let evs = vec![
            key(egui::Key::F2, true, false, false),
            key(egui::Key::Num7, true, false, true),
            egui::Event::Text("7".into()), // the text of Alt+7 is not a data key
            key(egui::Key::F9, true, false, false),
            key(egui::Key::F12, true, false, false),
            key(egui::Key::Equals, true, false, true),
            key(egui::Key::T, true, false, true),
        ];
        let out = run(&evs, &v, &mut h);
        let want = [
            PanelEvent::Data(DataMode::Read),
            PanelEvent::Op(OpMode::Single),
            PanelEvent::Start,
            PanelEvent::EStop,
            PanelEvent::Override(150), // already at the top
        ];
        assert_eq!(out, want);
        assert!(h.tape_requested);
        let out = run(
            &[key(egui::Key::Minus, true, false, true)],
            &view(OpMode::Data, 0),
            &mut h,
        );
        assert_eq!(out, [PanelEvent::Override(0)]);
    }

    #[test]
    fn axis_keys_are_the_terminals_and_a_held_jog_stops_on_release() {
        let mut h = HandState::default();
        let up = key(egui::Key::PageUp, true, false, false);
        let out = run(&[up.clone(), up], &view(OpMode::Handle, 100), &mut h);
        assert_eq!(
            out,
            [
                PanelEvent::Press(Key::PageUp),
                PanelEvent::Press(Key::PageUp)
            ]
        );

        // A tap: the key alone (one increment); its release says nothing.
        let cont = view(OpMode::Continuous, 100);
        let tap = [
            key(egui::Key::ArrowLeft, true, false, false),
            key(egui::Key::ArrowLeft, false, false, false),
        ];
        assert_eq!(run(&tap, &cont, &mut h), [PanelEvent::Press(Key::Left)]);
        // Held: the repeats are the terminal's, and the release stops the jog at once.
        let evs = [
            key(egui::Key::ArrowLeft, true, false, false),
            key(egui::Key::ArrowLeft, true, true, false),
            key(egui::Key::ArrowLeft, false, false, false),
        ];
        let out = run(&evs, &cont, &mut h);
        assert_eq!(
            out,
            [
                PanelEvent::Press(Key::Left),
                PanelEvent::Press(Key::Left),
                PanelEvent::JogRelease
            ]
        );
        assert_eq!(h.key_jog, None);
    }

    #[test]
    fn terminal_keys_are_what_the_terminal_decoder_gives() {
        let mut ctrl = key(egui::Key::C, true, false, false);
        if let egui::Event::Key { modifiers, .. } = &mut ctrl {
            modifiers.ctrl = true;
        }
        let evs = [
            egui::Event::Text("g1".into()),
            key(egui::Key::Enter, true, false, false),
            key(egui::Key::F9, true, false, false),
            key(egui::Key::Tab, true, false, false),
            key(egui::Key::Tab, false, false, false),
        ];
        assert_eq!(
            terminal_keys(&evs),
            [
                Key::Char('g'),
                Key::Char('1'),
                Key::Enter,
                Key::F(9),
                Key::Tab
            ]
        );
        // With Alt or Ctrl held the text is the shortcut's, not a data key.
        let evs = [
            key(egui::Key::F, true, false, true),
            egui::Event::Text("f".into()),
            key(egui::Key::Num3, true, false, true),
            ctrl,
        ];
        assert_eq!(
            terminal_keys(&evs),
            [Key::Alt('f'), Key::Alt('3'), Key::Ctrl('c')]
        );
    }

    /// egui-winit sends Ctrl-C as `Event::Copy` alone: the lathe window did not close on it.
    #[test]
    fn egui_s_copy_is_the_terminal_s_ctrl_c() {
        assert_eq!(terminal_keys(&[egui::Event::Copy]), [Key::Ctrl('c')]);
    }

    #[test]
    fn ctrl_keys_are_the_page_keys_and_tab_is_plus_input() {
        let mut h = HandState::default();
        let mut ctrl = key(egui::Key::O, true, false, false);
        if let egui::Event::Key { modifiers, .. } = &mut ctrl {
            modifiers.ctrl = true;
        }
        let evs = [
            ctrl,
            egui::Event::Text("o".into()),
            key(egui::Key::Tab, true, false, false),
        ];
        let out = run(&evs, &view(OpMode::Auto, 100), &mut h);
        assert_eq!(
            out,
            [
                PanelEvent::Press(Key::Ctrl('o')),
                PanelEvent::Press(Key::Tab)
            ]
        );
    }

    #[test]
    fn the_terminals_quit_keys_close_the_window_and_editing_keys_pass() {
        for quit in [
            key(egui::Key::Q, true, false, true),
            {
                let mut c = key(egui::Key::C, true, false, false);
                if let egui::Event::Key { modifiers, .. } = &mut c {
                    modifiers.ctrl = true;
                }
                c
            },
            egui::Event::Copy,
        ] {
            let mut h = HandState::default();
            let out = run(
                std::slice::from_ref(&quit),
                &view(OpMode::Auto, 100),
                &mut h,
            );
            assert!(h.quit_requested, "{quit:?} closes the window");
            assert!(out.is_empty(), "{quit:?} is nothing else: {out:?}");
        }
        let mut h = HandState::default();
        let evs = [
            key(egui::Key::Home, true, false, false),
            key(egui::Key::End, true, false, false),
            key(egui::Key::Delete, true, false, false),
        ];
        let out = run(&evs, &view(OpMode::Data, 100), &mut h);
        assert_eq!(
            out,
            [
                PanelEvent::Press(Key::Home),
                PanelEvent::Press(Key::End),
                PanelEvent::Press(Key::Delete)
            ]
        );
        assert!(!h.quit_requested);
    }
}
