//! The data keys of the NC panel: alphabetic (15a), numeric with their shifted characters
//! (15b), SHIFT (15c), SPACE, RUBOUT and EOB, clickable; and the physical keyboard mapped onto
//! the same keys. Each key becomes a `PanelEvent`; the console decides what it means.

use super::controls::HandState;
use crate::panel_model::PanelEvent;
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
    });
}

/// The physical keyboard: letters (made upper case), digits and signs are data keys, Enter
/// is EOB, Backspace is RUBOUT.
pub fn keyboard(events: &[egui::Event], out: &mut Vec<PanelEvent>) {
    for e in events {
        match e {
            egui::Event::Text(t) => {
                for ch in t.chars().filter(|c| !c.is_control()) {
                    out.push(PanelEvent::Key(ch.to_ascii_uppercase()));
                }
            }
            egui::Event::Key {
                key: egui::Key::Enter,
                pressed: true,
                ..
            } => out.push(PanelEvent::Eob),
            egui::Event::Key {
                key: egui::Key::Backspace,
                pressed: true,
                ..
            } => out.push(PanelEvent::Rubout),
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keyboard_maps_letters_enter_and_backspace() {
        let evs = vec![
            egui::Event::Text("g1".into()),
            egui::Event::Key {
                key: egui::Key::Enter,
                physical_key: None,
                pressed: true,
                repeat: false,
                modifiers: Default::default(),
            },
            egui::Event::Key {
                key: egui::Key::Backspace,
                physical_key: None,
                pressed: true,
                repeat: false,
                modifiers: Default::default(),
            },
        ];
        let mut out = Vec::new();
        keyboard(&evs, &mut out);
        assert_eq!(
            out,
            vec![
                PanelEvent::Key('G'),
                PanelEvent::Key('1'),
                PanelEvent::Eob,
                PanelEvent::Rubout
            ]
        );
    }
}
