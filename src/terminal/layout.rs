//! The terminal panel's layout: the plasma display (orange on black), both selectors as rotary
//! switches, the relay panel (buttons, feed override, handwheel), the position readout, the
//! lamps, the data keys and a key legend; the help screen; and the "enlarge" notice. The
//! lathe's panel (docs/lathe.md "The panel"): the title, one summary line per channel, the
//! selected channel's plasma display and the key legend beside it.
//!
//! For a display of R×C the panel needs (C + 39) × (max(R + 2, 14) + 10) cells: 79×24 for
//! the default 12×40.

use crate::console::help::{HELP, HELP_EDITOR, LATHE_HELP, LATHE_KEYS};
use crate::lathe::console::LatheView;
use crate::panel_model::{DataMode, OpMode, Page, PanelView};
use novanc_panel::draw::{button, gauge, lamp, rotary};
use novanc_panel::{Color, Screen, Style};

/// Plasma orange.
const ORANGE: Color = Color::Idx(208);
/// The display's black.
const BLACK: Color = Color::Idx(16);
/// The plasma display's style.
const PLASMA: Style = Style::on(ORANGE, BLACK);
/// Panel frames and labels.
const PANEL: Style = Style::fg(Color::Idx(250));
/// A selected or lit item.
const LIT: Style = Style::fg(Color::Idx(226)).bold();
/// The e-stop / alarm red.
const RED: Style = Style::fg(Color::Idx(196)).bold();
/// A lit green lamp (RUN).
const GREEN: Style = Style::fg(Color::Idx(46)).bold();

/// Width of one selector switch.
const SEL_W: usize = 18;

/// Operation mode selector labels, in position order.
fn op_labels() -> [&'static str; 7] {
    OpMode::ALL.map(|m| m.names().label)
}
/// Data-processing mode selector labels, in position order.
fn data_labels() -> [&'static str; 7] {
    DataMode::ALL.map(|m| m.names().label)
}

/// The key legend under the panel.
pub const LEGEND: &str =
    "F1-7 data  Alt+1-7 op  F9 START F10 STOP F11 RESET F12 E-STOP  F8 help ^C quit";

/// The cells the panel needs for a display of `rows` × `cols`: (width, height).
pub fn panel_size(rows: usize, cols: usize) -> (usize, usize) {
    (cols + 3 + 2 * SEL_W, (rows + 2).max(14) + 10)
}

/// Draws the whole panel for `v` (display of `v.display.len()` lines) at the top left.
pub fn draw_panel(s: &mut Screen, v: &PanelView) {
    let rows = v.display.len();
    let cols = v.display.first().map(|l| l.chars().count()).unwrap_or(40);
    let dw = cols + 2;
    let rx = dw + 1;
    let top = (rows + 2).max(14);
    // Plasma display 14.
    s.frame(0, 0, dw, rows + 2, "PLASMA DISPLAY 14", PANEL);
    for (i, line) in v.display.iter().enumerate() {
        s.text(1, 1 + i, line, PLASMA);
    }
    // Selectors 17 and 16.
    let op = OpMode::ALL
        .iter()
        .position(|m| *m == v.op_mode)
        .unwrap_or(0);
    let data = DataMode::ALL
        .iter()
        .position(|m| *m == v.data_mode)
        .unwrap_or(0);
    rotary(
        s,
        (rx, 0),
        SEL_W,
        "OPERATION 17",
        &op_labels(),
        op,
        (PANEL, LIT),
    );
    rotary(
        s,
        (rx + SEL_W, 0),
        SEL_W,
        "DATA MODE 16",
        &data_labels(),
        data,
        (PANEL, LIT),
    );
    // Relay panel 12: buttons, override, handwheel.
    let rw = 2 * SEL_W;
    s.frame(rx, 9, rw, 5, "RELAY PANEL 12", PANEL);
    let mut x = rx + 1;
    x += button(s, x, 10, "START", v.lamps.run, PANEL, GREEN) + 1;
    x += button(s, x, 10, "STOP", v.lamps.hold, PANEL, LIT) + 1;
    x += button(s, x, 10, "RESET", false, PANEL, LIT) + 1;
    button(s, x, 10, "E-STOP", v.lamps.estop, RED, RED.reversed());
    let o = format!("OVERRIDE {:>3}% ", v.feed_override);
    let n = s.text(rx + 1, 11, &o, PANEL);
    gauge(s, rx + 1 + n, 11, 15, v.feed_override, 150, LIT);
    s.text(
        rx + 1,
        12,
        &format!(
            "HANDWHEEL {} x{:<4} Alt+, Alt+.",
            v.wheel.0.letter(),
            v.wheel.1
        ),
        PANEL,
    );
    // Position readout.
    let title = if v.rotary_deg.is_empty() {
        "POSITION mm"
    } else {
        "POSITION mm, deg"
    };
    s.frame(0, top, dw, 5, title, PANEL);
    for (i, a) in ["X", "Y", "Z"].iter().enumerate() {
        // A rotary axis beside each row (A, B, C in the machine's order), degrees; the
        // readout of a 3-axis machine is as it was. With fewer rotary axes than rows, every
        // row keeps the rotary rows' columns.
        let line = match v.rotary_deg.get(i) {
            Some((r, deg)) => format!(
                "{a} {:>10.3} tip {a} {:>10.3} {r}{:>9}",
                v.axis_mm[i],
                v.tip_mm[i],
                degrees_in_9(*deg)
            ),
            None if !v.rotary_deg.is_empty() => {
                format!("{a} {:>10.3} tip {a} {:>10.3}", v.axis_mm[i], v.tip_mm[i])
            }
            None => format!("{a} {:>10.3}  tip {a} {:>10.3}", v.axis_mm[i], v.tip_mm[i]),
        };
        s.text(1, top + 1 + i, &line, PLASMA);
    }
    // Lamps and machine state.
    s.frame(rx, top, rw, 5, "LAMPS", PANEL);
    let mut x = rx + 1;
    x += lamp(s, x, top + 1, "RUN", v.lamps.run, PANEL, GREEN) + 1;
    x += lamp(s, x, top + 1, "HOLD", v.lamps.hold, PANEL, LIT) + 1;
    x += lamp(s, x, top + 1, "E-STOP", v.lamps.estop, PANEL, RED) + 1;
    lamp(s, x, top + 1, "ALARM", v.lamps.alarm, PANEL, RED);
    let tool = v
        .tool
        .map(|t| format!("T{t:02}"))
        .unwrap_or_else(|| "T--".into());
    s.text(
        rx + 1,
        top + 2,
        &format!("RUN {}  {tool}  S{}", v.run, v.spindle),
        PANEL,
    );
    let room = rw.saturating_sub(10);
    let e: Vec<char> = v.entry.chars().collect();
    let shown: String = e[e.len().saturating_sub(room)..].iter().collect();
    s.text(rx + 1, top + 3, "ENTRY > ", PANEL);
    s.text(rx + 9, top + 3, &shown, LIT);
    // Data keys 15.
    let kw = rx + rw;
    s.frame(
        0,
        top + 5,
        kw,
        4,
        "DATA KEYS 15 (type; Enter = EOB *)",
        PANEL,
    );
    s.text(
        1,
        top + 6,
        "A B C D E F G H I J K L M N O P Q R S T U V W X Y Z",
        PANEL,
    );
    s.text(
        1,
        top + 7,
        "1 2 3 4 5 6 7 8 9 0 . , / = ( ) - + $ *  SHIFT  EOB  RUBOUT",
        PANEL,
    );
    // The row of page keys (docs/panel.md, "Pages"), right of the letters, each key's control
    // letter on the frame above its button; the page shown is lit.
    let mut x = kw.saturating_sub(25);
    // (MODAL and I/O have no button in this row: MODAL's is below; I/O's key, Ctrl-T, is in
    // the help.)
    for (p, key) in Page::KEYS.iter().zip(["^P", "^D", "^O", "^E"]) {
        s.text(x + 1, top + 5, key, PANEL);
        x += button(s, x, top + 6, p.label(), v.page == *p, PANEL, LIT) + 1;
    }
    // MODAL, under them at the end of the digits' row, its letter beside it.
    let mx = kw.saturating_sub(12);
    s.text(mx, top + 7, "^G", PANEL);
    button(
        s,
        mx + 3,
        top + 7,
        Page::Modal.label(),
        v.page == Page::Modal,
        PANEL,
        LIT,
    );
    s.text(0, top + 9, LEGEND, PANEL);
}

/// Draws help page `page` (1: the panel keys, 2: the editor commands and pages).
pub fn draw_help(s: &mut Screen, page: u8) {
    let lines = if page == 2 { HELP_EDITOR } else { HELP };
    for (i, l) in lines.iter().enumerate() {
        s.text(1, i, l, if i == 0 { LIT } else { PANEL });
    }
}

/// Draws the notice for a terminal smaller than the panel, with the last key ignored.
pub fn draw_too_small(s: &mut Screen, need: (usize, usize), ignored: Option<&str>) {
    let (w, h) = (s.width(), s.height());
    // Most important first, each wrapped at word boundaries to the width, so that even a
    // 10-column terminal shows the size to enlarge to.
    let lines = [
        (format!("enlarge to {}x{}", need.0, need.1), LIT),
        (format!("(now {w}x{h})"), PANEL),
        ("terminal too small".to_string(), LIT),
        (
            "keys are ignored but STOP RESET E-STOP; Ctrl-C quits".to_string(),
            PANEL,
        ),
        (ignored.unwrap_or("").to_string(), RED),
    ];
    let mut row = 0;
    for (text, style) in &lines {
        for l in crate::console::display::wrap(text, w.max(1), usize::MAX) {
            if row >= h {
                return;
            }
            s.text(0, row, &l, *style);
            row += 1;
        }
    }
}

/// Width of the lathe's key legend column.
const LATHE_KEYS_W: usize = 25;

/// The cells the lathe panel needs for `channels` and a `rows`×`cols` display: (width, height).
pub fn lathe_size(channels: usize, rows: usize, cols: usize) -> (usize, usize) {
    (cols + 3 + LATHE_KEYS_W, 1 + channels + rows + 2)
}

/// Draws the lathe panel, or its help.
pub fn draw_lathe(s: &mut Screen, v: &LatheView) {
    if v.help {
        for (i, l) in LATHE_HELP.iter().enumerate() {
            s.text(0, i, l, if i == 0 { LIT } else { PANEL });
        }
        return;
    }
    let cols = v.display.first().map(|l| l.chars().count()).unwrap_or(40);
    s.text(0, 0, &v.title, LIT);
    for (i, l) in v.summary.iter().enumerate() {
        let c = &v.channels[i];
        let style = match c.state.as_str() {
            "FAULT" | "ALARM" | "ESTOP" => RED,
            _ if i == v.selected => LIT,
            _ => PANEL,
        };
        s.text(0, 1 + i, l, style);
    }
    let top = 1 + v.summary.len();
    s.frame(
        0,
        top,
        cols + 2,
        v.display.len() + 2,
        "PLASMA DISPLAY 14",
        PANEL,
    );
    for (i, l) in v.display.iter().enumerate() {
        s.text(1, top + 1 + i, l, PLASMA);
    }
    for (i, k) in LATHE_KEYS.iter().enumerate() {
        s.text(cols + 3, top + 1 + i, k, PANEL);
    }
}

/// A rotary axis's degrees in at most 9 characters (the POSITION box's room): three decimals,
/// fewer for a wrapped axis that has turned far (its counter runs on past 360), `>>>>>>>>>`
/// past any.
fn degrees_in_9(deg: f64) -> String {
    (0..=3)
        .rev()
        .map(|d| format!("{deg:.d$}"))
        .find(|t| t.len() <= 9)
        .unwrap_or_else(|| ">".repeat(9))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::panel_model::{Axis, Lamps};

    fn view() -> PanelView {
        PanelView {
            display: vec![format!("{:<40}", "HELLO"); 12],
            op_mode: OpMode::Data,
            data_mode: DataMode::Revise,
            run: 0,
            lamps: Lamps::default(),
            feed_override: 100,
            switches: Default::default(),
            program_switches: Default::default(),
            axis_mm: [1.0, 2.0, -3.5],
            rotary_deg: Vec::new(),
            tip_mm: [1.0, 2.0, -153.5],
            tool: Some(2),
            spindle: 1200,
            wheel: (Axis::Y, 10),
            entry: "2L".into(),
            machine_ns: 0,
            help: 0,
            page: crate::panel_model::Page::Mode,
            ignored: None,
        }
    }

    #[test]
    fn the_default_panel_fits_80_by_24_and_shows_every_device() {
        assert_eq!(panel_size(12, 40), (79, 24));
        let mut s = Screen::new(79, 24);
        draw_panel(&mut s, &view());
        let t = s.to_text();
        for want in [
            "HELLO",
            "◉━4 DATA INPUT",
            "◉━3 PROG REVISE",
            "[START]",
            "[E-STOP]",
            "OVERRIDE 100%",
            "HANDWHEEL Y x10",
            "Z     -3.500  tip Z   -153.500",
            "○ RUN",
            "T02  S1200",
            "F9 START",
            "ENTRY > 2L",
        ] {
            assert!(t.contains(want), "missing {want:?} in\n{t}");
        }
        assert!(LEGEND.chars().count() <= 79);
    }

    /// The rotary axes stand beside X Y Z in the POSITION box, inside its frame, so that a
    /// turning table is seen in every mode, not only on POS (stop 53).
    #[test]
    fn the_position_box_shows_the_rotary_axes_inside_its_frame() {
        // A, B and C; then a trunnion (B and C), whose Z row keeps the columns of the rows
        // above it.
        let abc = vec![('A', 0.0), ('B', -30.0), ('C', -10_080.5)];
        let trunnion = vec![('B', 5.0), ('C', 45.0)];
        for (rotary, rows) in [
            (
                abc,
                [
                    "│X      1.000 tip X      1.000 A    0.000│",
                    "│Y      2.000 tip Y      2.000 B  -30.000│",
                    "│Z     -3.500 tip Z   -153.500 C-10080.50│",
                ],
            ),
            (
                trunnion,
                [
                    "│X      1.000 tip X      1.000 B    5.000│",
                    "│Y      2.000 tip Y      2.000 C   45.000│",
                    "│Z     -3.500 tip Z   -153.500           │",
                ],
            ),
        ] {
            let mut v = view();
            v.rotary_deg = rotary;
            let mut s = Screen::new(79, 24);
            draw_panel(&mut s, &v);
            let t = s.to_text();
            for want in rows.iter().chain(&["POSITION mm, deg"]) {
                assert!(t.contains(want), "missing {want:?} in\n{t}");
            }
        }
    }

    #[test]
    fn the_small_notice_fits_20_by_5() {
        let mut s = Screen::new(20, 5);
        draw_too_small(&mut s, (79, 24), None);
        let t = s.to_text();
        assert!(t.contains("enlarge to 79x24"), "{t}");
        assert!(t.contains("(now 20x5)"), "{t}");
        assert!(t.contains("terminal too small"), "{t}");
    }

    #[test]
    fn the_small_notice_keeps_the_size_at_10_columns() {
        let mut s = Screen::new(10, 4);
        draw_too_small(&mut s, (79, 24), None);
        let t = s.to_text();
        let lines: Vec<&str> = t.lines().map(|l| l.trim_end()).collect();
        assert_eq!(&lines[..3], &["enlarge to", "79x24", "(now 10x4)"], "{t}");
        let mut s = Screen::new(3, 1);
        draw_too_small(&mut s, (79, 24), None);
        assert_eq!(s.to_text().trim_end(), "enl");
    }
}
