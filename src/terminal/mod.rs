//! The terminal front end: the thin loop between the terminal's devices (`novanc-panel`: raw
//! mode, keys, cells) and the `Console`. It reads stdin without blocking (poll, 20 ms), maps keys to panel
//! events, ticks the console (about 50 Hz) and draws the panel with diff rendering. The
//! terminal is handed back on exit, on panic, on SIGQUIT and on SIGTERM/SIGINT/SIGHUP; SIGTSTP
//! hands it back and stops, SIGCONT takes it again and draws the whole frame (docs/panel.md,
//! "Terminal"). A stop signal ends the session as it ends `novanc run` (`crate::signals`):
//! the machine stopped, the recording closed `complete: false`, exit 128 + the signal.

pub mod layout;

use crate::console::{ConsoleConfig, Panel};
use crate::lathe::desc::LatheDesc;
use crate::mtconnect::feed::{Feed, MtcOpts};
use crate::signals;
use layout::{draw_help, draw_lathe, draw_panel, draw_too_small, lathe_size, panel_size};
use novanc_panel::{Decoder, Key, Renderer, Screen, Terminal};
use std::time::{Duration, Instant};

/// The terminal front end's `--help`.
pub const HELP: &str = "\
usage: novanc [--state DIR] [--rows N] [--cols N] [--record OUT.mcap] [--mtconnect ADDR:PORT|PORT]
The terminal front panel; F8 in the panel shows the keys.
";

/// The cells the panel of the console needs: (width, height).
fn need(p: &Panel) -> (usize, usize) {
    match p {
        Panel::Centre(c) => panel_size(c.config().rows, c.config().cols),
        Panel::Lathe(c) => {
            let (rows, cols) = c.display_size();
            lathe_size(c.desc().channels.len(), rows, cols)
        }
    }
}

/// Draws the panel (or its help) on a cleared screen at least [`need`] large.
fn draw(p: &Panel, s: &mut Screen) {
    match p {
        Panel::Centre(c) => {
            let view = c.view();
            if view.help > 0 {
                draw_help(s, view.help);
            } else {
                draw_panel(s, &view);
            }
        }
        Panel::Lathe(c) => draw_lathe(s, &c.view()),
    }
}

/// Opens the console of the machine (`lathe`: a lathe's description; `None`: the machining
/// centre of `cfg`) and runs the terminal panel on it, streaming to MTConnect agents with
/// `--mtconnect` (docs/mtconnect.md); returns the exit code. The machine keeps the wall clock
/// in its own thread (`cfg.clock`).
pub fn run_machine(lathe: Option<LatheDesc>, cfg: ConsoleConfig, mtc: &MtcOpts) -> i32 {
    signals::install();
    let (mut panel, warnings) = match Panel::open(lathe, cfg) {
        Ok(x) => x,
        Err(e) => {
            eprintln!("novanc: {e}");
            return 1;
        }
    };
    if let Panel::Centre(c) = &mut panel {
        c.set_saves_after_frame(true);
    }
    let feed = panel.start_feed(mtc, "novanc", false);
    run(panel, warnings, feed)
}

/// Runs the terminal panel on an opened console until Ctrl-C, Alt-q or a stop signal, then
/// closes it (the warnings of its opening said once the terminal is back); returns the exit
/// code (128 + N after a stop signal). `feed`: the MTConnect adapter as it started (an
/// adapter that could not start closes the console, exit 1).
pub fn run(front: Panel, warnings: Vec<String>, feed: Result<Option<Feed>, String>) -> i32 {
    let mut feed = match feed {
        Ok(f) => f,
        Err(e) => {
            eprintln!("novanc: {e}");
            front.close_saying(None);
            return 1;
        }
    };
    if let Some(f) = feed.as_mut() {
        front.publish(f);
    }
    let mut term = match Terminal::enter() {
        Ok(t) => t,
        Err(e) => {
            eprintln!("novanc: {e}");
            front.close_saying(None);
            return 1;
        }
    };
    let (code, front) = run_loop(&mut term, front, &mut feed);
    term.restore();
    // A stop signal is said now that the terminal is back, and marks the recording
    // interrupted before `close` (the machine stopped, the recording closed) closes it.
    let interrupted = signals::caught_reason();
    for w in warnings {
        eprintln!("novanc: warning at start: {w}");
    }
    front.close_saying(interrupted.as_deref());
    signals::exit_code(code)
}

/// What the loop does first in each frame: end on a stop signal or on a panic in
/// another thread (`Some` exit code; a stop signal's, 128 + N, is the caller's
/// `signals::exit_code`), and take job control and resizes (`Terminal::take_redraw`: the
/// whole frame drawn again).
fn between_frames(term: &mut Terminal, renderer: &mut Renderer) -> Option<i32> {
    if term.panicked() {
        return Some(128 + libc::SIGABRT);
    }
    if signals::pending() {
        return Some(1);
    }
    if term.take_redraw() {
        renderer.invalidate();
    }
    None
}

/// The input/draw loop; returns the exit code and the console.
fn run_loop(term: &mut Terminal, mut front: Panel, feed: &mut Option<Feed>) -> (i32, Panel) {
    let mut dec = Decoder::new();
    let mut renderer = Renderer::new();
    let mut screen = Screen::new(0, 0);
    let mut out = Vec::with_capacity(16 * 1024);
    let need = need(&front);
    let mut last = Instant::now();
    // Test hook: proves that a panic hands the terminal back (tests/tmux_panel.rs).
    let panic_requested = std::env::var_os("NOVANC_TEST_PANIC").is_some();
    loop {
        if let Some(code) = between_frames(term, &mut renderer) {
            return (code, front);
        }
        let (w, h) = term.size();
        let fits = w >= need.0 && h >= need.1;
        front.set_screen_fits(fits);
        let keys = match term.read_keys(Duration::from_millis(20), &mut dec) {
            Ok(k) => k,
            Err(_) => return (0, front),
        };
        for k in keys {
            match k {
                Key::Ctrl('c') | Key::Alt('q') => return (0, front),
                Key::Ctrl('l') => renderer.invalidate(),
                k => front.press(k),
            }
        }
        let now = Instant::now();
        let ns = now.duration_since(last).as_nanos().min(1_000_000_000) as u64;
        last = now;
        front.tick(ns);
        if let Some(f) = feed.as_mut() {
            front.publish(f);
        }
        if screen.width() != w || screen.height() != h {
            screen = Screen::new(w, h);
        }
        screen.clear();
        if fits {
            draw(&front, &mut screen);
        } else {
            draw_too_small(&mut screen, need, front.front().ignored_key());
        }
        out.clear();
        renderer.render(&screen, &mut out);
        if !out.is_empty() && term.write_all(&out).is_err() {
            return (1, front);
        }
        front.frame_written();
        if panic_requested && !out.is_empty() {
            panic!("NOVANC_TEST_PANIC: a panic after the first frame, as requested");
        }
    }
}
