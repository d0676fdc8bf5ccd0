//! The data keys of the NC panel: alphabetic (15a), numeric with their shifted characters
//! (15b), SHIFT (15c), SPACE, RUBOUT, EOB, the tape reader and punch keys, clickable; and the physical
//! keyboard, with the terminal panel's key map. Each key becomes a `PanelEvent`; the console decides what it means.

use super::controls::HandState;
use crate::panel_model::{Axis, DataMode, OpMode, PanelEvent, PanelView};
use egui::{vec2, Ui};

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
/// SPACE, RUBOUT and EOB.
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
        if key(ui, "TAPE", 50.0, false) {
            hand.tape_requested = true;
        }
        if key(ui, "PUNCH", 56.0, false) {
            hand.punch_requested = true;
        }
    });
}

/// The physical keyboard, with the terminal panel's key map (docs/panel.md) so an operator
/// can go from one to the other:
/// - letters (made upper case), digits and signs are data keys; Enter is EOB, Backspace RUBOUT;
/// - F1–F7 turn the data-processing mode selector, Alt+1–Alt+7 the operation mode selector;
/// - F9 START, F10 STOP, F11 RESET, F12 E-STOP (also Alt+S, Alt+P, Alt+R, Alt+E);
/// - Alt+= / Alt+- feed override ±10 %; Alt+W the ×1/×10/×100 selector; Alt+, / Alt+. one
///   handwheel detent; Alt+T the tape reader (the typed line names the file); Alt+U the punch
///   (in PROGRAM READ the typed line names the image, `PATH` or `PATH EIA`);
/// - arrows (X, Y) and Page Up/Down (Z): in HANDLE one handwheel detent on that axis, in
///   CONTINUOUS jog while held, otherwise one jog press (STEP).
pub fn keyboard(
    events: &[egui::Event],
    view: &PanelView,
    hand: &mut HandState,
    out: &mut Vec<PanelEvent>,
) {
    use egui::Key as K;
    // Text typed with Alt held belongs to a shortcut, not to the data keys.
    let alt_combo = events
        .iter()
        .any(|e| matches!(e, egui::Event::Key { pressed: true, modifiers, .. } if modifiers.alt));
    for e in events {
        match e {
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
                        K::Equals | K::Plus if alt => {
                            out.push(PanelEvent::Override((view.feed_override + 10).min(150)))
                        }
                        K::Minus if alt => {
                            out.push(PanelEvent::Override(view.feed_override.saturating_sub(10)))
                        }
                        K::W if alt => out.push(PanelEvent::WheelScale(match view.wheel.1 {
                            1 => 10,
                            10 => 100,
                            _ => 1,
                        })),
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

/// An axis key: a handwheel detent in HANDLE, jog while held in CONTINUOUS, a jog press
/// otherwise (STEP; in other modes the console says why it refuses).
fn move_key(
    view: &PanelView,
    hand: &mut HandState,
    axis: Axis,
    dir: i8,
    pressed: bool,
    repeat: bool,
    out: &mut Vec<PanelEvent>,
) {
    match (view.op_mode, pressed) {
        (OpMode::Handle, true) => out.push(PanelEvent::Wheel(axis, dir as i32)),
        (OpMode::Continuous, true) if !repeat && hand.key_jog.is_none() => {
            hand.key_jog = Some((axis, dir));
            out.push(PanelEvent::Jog(axis, dir));
        }
        (OpMode::Continuous, false) if hand.key_jog == Some((axis, dir)) => {
            hand.key_jog = None;
            out.push(PanelEvent::JogRelease);
        }
        (OpMode::Continuous, _) | (OpMode::Handle, false) => {}
        (_, true) if !repeat => out.push(PanelEvent::Jog(axis, dir)),
        _ => {}
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
    fn axis_keys_turn_the_wheel_in_handle_and_jog_while_held_in_continuous() {
        let mut h = HandState::default();
        let up = key(egui::Key::PageUp, true, false, false);
        let out = run(
            &[up.clone(), up.clone()],
            &view(OpMode::Handle, 100),
            &mut h,
        );
        assert_eq!(
            out,
            [PanelEvent::Wheel(Axis::Z, 1), PanelEvent::Wheel(Axis::Z, 1)]
        );

        let cont = view(OpMode::Continuous, 100);
        let evs = [
            key(egui::Key::ArrowLeft, true, false, false),
            key(egui::Key::ArrowLeft, true, true, false), // key repeat: still the same jog
            key(egui::Key::ArrowLeft, false, false, false),
        ];
        let out = run(&evs, &cont, &mut h);
        assert_eq!(out, [PanelEvent::Jog(Axis::X, -1), PanelEvent::JogRelease]);
        assert_eq!(h.key_jog, None);

        let step = view(OpMode::Step, 100);
        let evs = [
            key(egui::Key::ArrowUp, true, false, false),
            key(egui::Key::ArrowUp, false, false, false),
        ];
        assert_eq!(run(&evs, &step, &mut h), [PanelEvent::Jog(Axis::Y, 1)]);
    }
}
