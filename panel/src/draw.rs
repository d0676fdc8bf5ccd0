//! Drawing panel devices into a screen: rotary selector switches, push buttons, lamps and a
//! bar gauge. Plain shapes; the console decides what they mean.

use crate::screen::{Screen, Style};

/// Draws a rotary selector: a framed list of numbered positions with the knob's pointer
/// `◉━` on the selected one. `w` is the outer width; the height is `labels.len() + 2`.
/// `styles` are (frame and unselected positions, selected position).
pub fn rotary(
    s: &mut Screen,
    (x, y): (usize, usize),
    w: usize,
    title: &str,
    labels: &[&str],
    selected: usize,
    (frame, active): (Style, Style),
) {
    s.frame(x, y, w, labels.len() + 2, title, frame);
    for (i, l) in labels.iter().enumerate() {
        let row = y + 1 + i;
        let inner = w.saturating_sub(2);
        let text = if i == selected {
            format!("◉━{} {l}", i + 1)
        } else {
            format!(" ┆{} {l}", i + 1)
        };
        let t: String = text.chars().take(inner).collect();
        let st = if i == selected { active } else { frame };
        s.text(x + 1, row, &t, st);
    }
}

/// Draws a push button `[LABEL]` with its key below-right; lit buttons use `lit`.
pub fn button(
    s: &mut Screen,
    x: usize,
    y: usize,
    label: &str,
    lit: bool,
    off: Style,
    on: Style,
) -> usize {
    let st = if lit { on } else { off };
    s.text(x, y, &format!("[{label}]"), st)
}

/// Draws a lamp: `●` lit, `○` dark, then its name.
pub fn lamp(
    s: &mut Screen,
    x: usize,
    y: usize,
    name: &str,
    lit: bool,
    off: Style,
    on: Style,
) -> usize {
    let (ch, st) = if lit { ('●', on) } else { ('○', off) };
    s.put(x, y, ch, st);
    1 + s.text(x + 1, y, &format!(" {name}"), st)
}

/// Draws a bar gauge of `w` cells filled in proportion `value/max`.
pub fn gauge(s: &mut Screen, x: usize, y: usize, w: usize, value: u32, max: u32, st: Style) {
    let filled = if max == 0 {
        0
    } else {
        (value.min(max) as usize * w) / max as usize
    };
    for i in 0..w {
        s.put(x + i, y, if i < filled { '█' } else { '░' }, st);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotary_marks_the_selected_position() {
        let mut s = Screen::new(16, 5);
        rotary(
            &mut s,
            (0, 0),
            16,
            "MODE",
            &["AUTO", "MDI", "DATA"],
            1,
            (Style::PLAIN, Style::PLAIN),
        );
        let t = s.to_text();
        assert!(t.contains("◉━2 MDI"), "{t}");
        assert!(t.contains(" ┆1 AUTO"), "{t}");
    }

    #[test]
    fn gauge_fills_in_proportion() {
        let mut s = Screen::new(10, 1);
        gauge(&mut s, 0, 0, 10, 75, 150, Style::PLAIN);
        assert_eq!(s.to_text(), "█████░░░░░\n");
    }
}
