//! The cell buffer: a grid of characters with colours, drawn into by the layout and compared
//! frame to frame by the renderer.

/// A colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Color {
    /// The terminal's default.
    Default,
    /// One of the 256 indexed colours.
    Idx(u8),
    /// A 24-bit colour.
    Rgb(u8, u8, u8),
}

/// How a cell is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Style {
    /// Foreground.
    pub fg: Color,
    /// Background.
    pub bg: Color,
    /// Bold (bright).
    pub bold: bool,
    /// Reverse video.
    pub reverse: bool,
}

impl Style {
    /// The terminal's default style.
    pub const PLAIN: Style = Style {
        fg: Color::Default,
        bg: Color::Default,
        bold: false,
        reverse: false,
    };

    /// A foreground colour on the default background.
    pub const fn fg(c: Color) -> Style {
        Style {
            fg: c,
            bg: Color::Default,
            bold: false,
            reverse: false,
        }
    }

    /// Foreground on background.
    pub const fn on(fg: Color, bg: Color) -> Style {
        Style {
            fg,
            bg,
            bold: false,
            reverse: false,
        }
    }

    /// The same style, bold.
    pub const fn bold(mut self) -> Style {
        self.bold = true;
        self
    }

    /// The same style, reversed.
    pub const fn reversed(mut self) -> Style {
        self.reverse = true;
        self
    }
}

/// One character cell.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Cell {
    /// The character (a single-width one).
    pub ch: char,
    /// Its style.
    pub style: Style,
}

impl Cell {
    /// A blank cell.
    pub const BLANK: Cell = Cell {
        ch: ' ',
        style: Style::PLAIN,
    };
}

/// A grid of cells, `width` × `height`.
#[derive(Clone, Debug, PartialEq)]
pub struct Screen {
    width: usize,
    height: usize,
    cells: Vec<Cell>,
}

impl Screen {
    /// A blank screen.
    pub fn new(width: usize, height: usize) -> Screen {
        Screen {
            width,
            height,
            cells: vec![Cell::BLANK; width * height],
        }
    }

    /// Width in cells.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height in cells.
    pub fn height(&self) -> usize {
        self.height
    }

    /// Blanks every cell.
    pub fn clear(&mut self) {
        self.cells.fill(Cell::BLANK);
    }

    /// The cell at (x, y), if inside.
    pub fn get(&self, x: usize, y: usize) -> Option<&Cell> {
        if x < self.width && y < self.height {
            self.cells.get(y * self.width + x)
        } else {
            None
        }
    }

    /// Sets one cell; outside the screen it does nothing. Control characters become `?`.
    pub fn put(&mut self, x: usize, y: usize, ch: char, style: Style) {
        if x < self.width && y < self.height {
            let ch = if ch.is_control() { '?' } else { ch };
            self.cells[y * self.width + x] = Cell { ch, style };
        }
    }

    /// Writes text from (x, y) on one row, clipped at the right edge; returns the cells used.
    pub fn text(&mut self, x: usize, y: usize, s: &str, style: Style) -> usize {
        let mut n = 0;
        for (i, ch) in s.chars().enumerate() {
            if x + i >= self.width {
                break;
            }
            self.put(x + i, y, ch, style);
            n += 1;
        }
        n
    }

    /// Fills a rectangle with one character.
    pub fn fill(&mut self, x: usize, y: usize, w: usize, h: usize, ch: char, style: Style) {
        for yy in y..y + h {
            for xx in x..x + w {
                self.put(xx, yy, ch, style);
            }
        }
    }

    /// Draws a box border with a title in its top edge.
    pub fn frame(&mut self, x: usize, y: usize, w: usize, h: usize, title: &str, style: Style) {
        if w < 2 || h < 2 {
            return;
        }
        for xx in x + 1..x + w - 1 {
            self.put(xx, y, '─', style);
            self.put(xx, y + h - 1, '─', style);
        }
        for yy in y + 1..y + h - 1 {
            self.put(x, yy, '│', style);
            self.put(x + w - 1, yy, '│', style);
        }
        self.put(x, y, '╭', style);
        self.put(x + w - 1, y, '╮', style);
        self.put(x, y + h - 1, '╰', style);
        self.put(x + w - 1, y + h - 1, '╯', style);
        if !title.is_empty() && w > 4 {
            let t: String = title.chars().take(w - 4).collect();
            self.text(x + 2, y, &t, style.bold());
        }
    }

    /// The screen's text, one line per row, trailing blanks removed (for tests).
    pub fn to_text(&self) -> String {
        let mut out = String::new();
        for y in 0..self.height {
            let row: String = self.cells[y * self.width..(y + 1) * self.width]
                .iter()
                .map(|c| c.ch)
                .collect();
            out.push_str(row.trim_end());
            out.push('\n');
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_is_clipped_and_outside_puts_are_ignored() {
        let mut s = Screen::new(5, 2);
        assert_eq!(s.text(3, 0, "abcd", Style::PLAIN), 2);
        s.put(9, 9, 'x', Style::PLAIN);
        s.put(0, 1, '\x07', Style::PLAIN);
        assert_eq!(s.to_text(), "   ab\n?\n");
    }

    #[test]
    fn frame_draws_corners_and_title() {
        let mut s = Screen::new(8, 3);
        s.frame(0, 0, 8, 3, "AB", Style::PLAIN);
        assert_eq!(s.to_text(), "╭─AB───╮\n│      │\n╰──────╯\n");
    }
}
