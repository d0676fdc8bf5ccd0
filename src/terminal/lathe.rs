//! The lathe console in the terminal (docs/lathe.md "The panel"): the title, one summary line
//! per channel, the selected channel's plasma display and the key legend beside it.

use crate::lathe::console::{LatheConsole, LatheView};
use novanc_panel::{Color, Decoder, Key, Renderer, Screen, Style, Terminal};
use std::time::{Duration, Instant};

const PLASMA: Style = Style::on(Color::Idx(208), Color::Idx(16));
const PANEL: Style = Style::fg(Color::Idx(250));
const LIT: Style = Style::fg(Color::Idx(226)).bold();
const RED: Style = Style::fg(Color::Idx(196)).bold();

/// The key legend beside the plasma display.
pub const KEYS: [&str; 11] = [
    "F9  START   F10 STOP",
    "F11 RESET   F12 E-STOP",
    "Tab CHANNEL",
    "Alt+2 AUTO  Alt+3 MDI",
    "Alt+4 DATA  Alt+5 OFS",
    "Alt+f FAULT the channel",
    "Alt+n TARGET (typed N)",
    "Alt+o M01   Alt+b /DEL",
    "Alt+= Alt+- OVERRIDE",
    "Enter EOB   F8 help",
    "Ctrl-C quit",
];

/// Width of the legend column.
const KEYS_W: usize = 25;

/// The help screen.
pub const HELP: [&str; 12] = [
    "LATHE CONSOLE  (F8 or Alt+h: back)",
    "Tab / Alt+c   channel selector: the display, data keys and editor act on it",
    "F9  / Alt+s   START: begin the cycle (AUTO) or the MDI lines; resume after a stop",
    "F10 / Alt+p   STOP: feed hold on every channel",
    "F11 / Alt+r   RESET the selected channel (a fault or alarm); after E-STOP, the machine",
    "F12 / Alt+e   E-STOP: everything stops at once",
    "Alt+f         FAULT: stop the selected channel with the typed reason (else 'operator')",
    "Alt+n         set the part target to the typed number",
    "Alt+2/3/4/5   AUTO / MDI (Enter adds a line) / DATA (an editor line) / OFS (T1 X.. Z.. R.. P..)",
    "Alt+o, Alt+b  OPTIONAL STOP (M01), BLOCK DELETE (/); Alt+= / Alt+- feed override ±10 %",
    "The summary line: channel, state, current block or whom it waits for, parts/target",
    "Ctrl-C or Alt+q quits; programs and the part counter are stored at every change",
];

/// The cells the lathe panel needs: (width, height).
pub fn size(channels: usize, rows: usize, cols: usize) -> (usize, usize) {
    (cols + 3 + KEYS_W, 1 + channels + rows + 2)
}

/// Draws the lathe panel.
pub fn draw(s: &mut Screen, v: &LatheView) {
    if v.help {
        for (i, l) in HELP.iter().enumerate() {
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
    for (i, k) in KEYS.iter().enumerate() {
        s.text(cols + 3, top + 1 + i, k, PANEL);
    }
}

/// Runs the lathe console in the terminal until Ctrl-C or a stop signal (the caller closes
/// the session with `LatheConsole::finish`), publishing to MTConnect agents once a frame
/// after the tick with `feed`; returns the exit code.
pub fn run(
    mut c: LatheConsole,
    rows: usize,
    cols: usize,
    feed: &mut Option<crate::cli::mtconnect::Feed>,
) -> (i32, LatheConsole) {
    let mut term = match Terminal::enter() {
        Ok(t) => t,
        Err(e) => {
            eprintln!("novanc: {e}");
            return (1, c);
        }
    };
    let need = size(c.desc().channels.len(), rows, cols);
    let mut dec = Decoder::new();
    let mut renderer = Renderer::new();
    let mut screen = Screen::new(0, 0);
    let mut out = Vec::with_capacity(16 * 1024);
    let mut last = Instant::now();
    let code = loop {
        if let Some(code) = super::between_frames(&mut term, &mut renderer) {
            break code;
        }
        let (w, h) = term.size();
        let fits = w >= need.0 && h >= need.1;
        let keys = match term.read_keys(Duration::from_millis(20), &mut dec) {
            Ok(k) => k,
            Err(_) => break 0,
        };
        let mut quit = false;
        for k in keys {
            match k {
                Key::Ctrl('c') | Key::Alt('q') => quit = true,
                Key::Ctrl('l') => renderer.invalidate(),
                // While the panel does not fit, only the relay panel's stops act.
                k if !fits && !matches!(k, Key::F(10..=12) | Key::Alt('p' | 'r' | 'e')) => {}
                k => c.press(k),
            }
        }
        if quit {
            break 0;
        }
        let now = Instant::now();
        let ns = now.duration_since(last).as_nanos().min(1_000_000_000) as u64;
        last = now;
        c.tick(ns);
        if let Some(f) = feed.as_mut() {
            f.publish_lathe(&c);
        }
        if screen.width() != w || screen.height() != h {
            screen = Screen::new(w, h);
        }
        screen.clear();
        if fits {
            draw(&mut screen, &c.view());
        } else {
            super::layout::draw_too_small(&mut screen, need, None);
        }
        out.clear();
        renderer.render(&screen, &mut out);
        if !out.is_empty() && term.write_all(&out).is_err() {
            break 1;
        }
    };
    term.restore();
    (code, c)
}
