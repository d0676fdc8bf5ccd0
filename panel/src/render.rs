//! Diff rendering: only the cells that changed since the last frame are written, with the
//! fewest cursor moves and colour changes this simple scheme allows. An unchanged frame
//! writes nothing.

use crate::screen::{Color, Screen, Style};
use std::io::Write;

/// Turns successive screens into the bytes that update a terminal.
#[derive(Debug, Default)]
pub struct Renderer {
    prev: Option<Screen>,
    /// The terminal's current style (None: unknown).
    style: Option<Style>,
    /// The terminal's cursor position (None: unknown).
    cursor: Option<(usize, usize)>,
}

impl Renderer {
    /// A renderer whose first frame is drawn in full.
    pub fn new() -> Renderer {
        Renderer::default()
    }

    /// Forgets what the terminal shows: the next frame clears it and draws in full (after a
    /// resize, or when something else wrote to the terminal).
    pub fn invalidate(&mut self) {
        self.prev = None;
        self.style = None;
        self.cursor = None;
    }

    /// Appends to `out` the bytes that turn the last frame into `screen`.
    pub fn render(&mut self, screen: &Screen, out: &mut Vec<u8>) {
        let full = match &self.prev {
            Some(p) => p.width() != screen.width() || p.height() != screen.height(),
            None => true,
        };
        if full {
            out.extend_from_slice(b"\x1b[0m\x1b[H\x1b[2J");
            self.style = Some(Style::PLAIN);
            self.cursor = Some((0, 0));
        }
        let w = screen.width();
        for y in 0..screen.height() {
            for x in 0..w {
                let Some(cell) = screen.get(x, y) else {
                    continue;
                };
                let changed = match (&self.prev, full) {
                    (Some(p), false) => p.get(x, y) != Some(cell),
                    _ => *cell != crate::screen::Cell::BLANK,
                };
                if !changed {
                    continue;
                }
                if self.cursor != Some((x, y)) {
                    let _ = write!(out, "\x1b[{};{}H", y + 1, x + 1);
                }
                if self.style != Some(cell.style) {
                    sgr(cell.style, out);
                    self.style = Some(cell.style);
                }
                let mut buf = [0u8; 4];
                out.extend_from_slice(cell.ch.encode_utf8(&mut buf).as_bytes());
                // At the right edge the terminal's cursor is in its pending-wrap state.
                self.cursor = if x + 1 < w { Some((x + 1, y)) } else { None };
            }
        }
        match &mut self.prev {
            Some(p) if !full => p.clone_from(screen),
            _ => self.prev = Some(screen.clone()),
        }
    }
}

/// Select Graphic Rendition for a style, from a reset.
fn sgr(s: Style, out: &mut Vec<u8>) {
    out.extend_from_slice(b"\x1b[0");
    if s.bold {
        out.extend_from_slice(b";1");
    }
    if s.reverse {
        out.extend_from_slice(b";7");
    }
    colour(s.fg, 38, out);
    colour(s.bg, 48, out);
    out.push(b'm');
}

/// The SGR parameters of one colour (38 foreground, 48 background).
fn colour(c: Color, base: u8, out: &mut Vec<u8>) {
    match c {
        Color::Default => {}
        Color::Idx(n) => {
            let _ = write!(out, ";{base};5;{n}");
        }
        Color::Rgb(r, g, b) => {
            let _ = write!(out, ";{base};2;{r};{g};{b}");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_unchanged_frame_writes_nothing() {
        let mut s = Screen::new(20, 5);
        s.text(0, 0, "hello", Style::fg(Color::Idx(208)));
        let mut r = Renderer::new();
        let mut out = Vec::new();
        r.render(&s, &mut out);
        assert!(String::from_utf8_lossy(&out).contains("hello"));
        out.clear();
        r.render(&s, &mut out);
        assert!(out.is_empty());
    }

    #[test]
    fn one_changed_cell_costs_a_move_and_a_character() {
        let mut s = Screen::new(20, 5);
        s.text(0, 0, "X 12.345", Style::PLAIN);
        let mut r = Renderer::new();
        let mut out = Vec::new();
        r.render(&s, &mut out);
        s.put(7, 0, '6', Style::PLAIN);
        out.clear();
        r.render(&s, &mut out);
        assert_eq!(out, b"\x1b[1;8H6");
        // Adjacent changes need one move only; a new style costs one SGR.
        s.text(6, 0, "99", Style::fg(Color::Idx(208)));
        out.clear();
        r.render(&s, &mut out);
        assert_eq!(out, b"\x1b[1;7H\x1b[0;38;5;208m99");
    }

    #[test]
    fn a_resized_screen_is_drawn_in_full() {
        let mut r = Renderer::new();
        let mut out = Vec::new();
        r.render(&Screen::new(4, 2), &mut out);
        out.clear();
        let mut s = Screen::new(6, 2);
        s.text(0, 1, "ab", Style::PLAIN);
        r.render(&s, &mut out);
        let t = String::from_utf8_lossy(&out);
        assert!(t.starts_with("\x1b[0m\x1b[H\x1b[2J"), "{t:?}");
        assert!(t.ends_with("\x1b[2;1Hab"), "{t:?}");
    }
}
