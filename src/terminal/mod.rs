//! The terminal front end: the thin loop between the terminal's devices (`novanc-panel`: raw
//! mode, keys, cells) and the `Console`. It reads stdin without blocking (poll, 20 ms), maps keys to panel
//! events, ticks the console (about 50 Hz) and draws the panel with diff rendering. The
//! terminal is handed back on exit, on panic, on SIGQUIT and on SIGTERM/SIGINT/SIGHUP; SIGTSTP
//! hands it back and stops, SIGCONT takes it again and draws the whole frame (docs/panel.md,
//! "Terminal"). A stop signal ends the session as it ends `novanc run` (`crate::cli::signals`):
//! the machine stopped, the recording closed `complete: false`, exit 128 + the signal.

pub mod lathe;
pub mod layout;

use crate::cli::signals;
use crate::console::{Console, ConsoleConfig};
use layout::{draw_help, draw_panel, draw_too_small, panel_size};
use novanc_panel::{Decoder, Key, Renderer, Screen, Terminal};
use std::time::Duration;

/// The terminal front end's `--help`.
pub const HELP: &str = "\
usage: novanc [--state DIR] [--rows N] [--cols N] [--record OUT.mcap] [--mtconnect ADDR:PORT|PORT]
The terminal front panel; F8 in the panel shows the keys.
";

/// Runs the terminal panel on a console opened with `cfg`; returns the exit code.
pub fn run(cfg: ConsoleConfig) -> i32 {
    run_with(cfg, &crate::cli::mtconnect::MtcOpts::default())
}

/// The terminal panel, streaming to MTConnect agents with `--mtconnect` (docs/mtconnect.md):
/// the state is published once a frame, after the console's tick.
pub fn run_with(cfg: ConsoleConfig, mtc: &crate::cli::mtconnect::MtcOpts) -> i32 {
    signals::install();
    let (console, warnings) = match Console::open(cfg) {
        Ok(x) => x,
        Err(e) => {
            eprintln!("novanc: {e}");
            return 1;
        }
    };
    let mut feed = match crate::cli::mtconnect::Feed::start(mtc, "novanc", console.core()) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("novanc: {e}");
            let _ = console.finish();
            return 1;
        }
    };
    let mut term = match Terminal::enter() {
        Ok(t) => t,
        Err(e) => {
            eprintln!("novanc: {e}");
            return 1;
        }
    };
    let (code, console) = run_loop(&mut term, console, &mut feed);
    term.restore();
    // A stop signal is said now that the terminal is back, and marks the recording
    // interrupted before `finish` (RESET, then the recording closed) closes it.
    let _ = signals::caught();
    for w in warnings {
        eprintln!("novanc: warning at start: {w}");
    }
    match console.finish() {
        Ok(Some(s)) => eprintln!("novanc: {s}"),
        Ok(None) => {}
        Err(e) => eprintln!("novanc: recording: {e}"),
    }
    signals::exit_code(code)
}

/// What the loops of both panels do first in each frame: end on a stop signal or on a panic in
/// another thread (`Some` exit code; a stop signal's, 128 + N, is the caller's
/// `signals::exit_code`), and take job control and resizes (`Terminal::take_redraw`: the
/// whole frame drawn again).
pub(crate) fn between_frames(term: &mut Terminal, renderer: &mut Renderer) -> Option<i32> {
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
fn run_loop(
    term: &mut Terminal,
    mut console: Console,
    feed: &mut Option<crate::cli::mtconnect::Feed>,
) -> (i32, Console) {
    let mut dec = Decoder::new();
    let mut renderer = Renderer::new();
    let mut screen = Screen::new(0, 0);
    let mut out = Vec::with_capacity(16 * 1024);
    let need = panel_size(console.config().rows, console.config().cols);
    console.set_saves_after_frame(true);
    // Test hook: proves that a panic hands the terminal back (tests/tmux_panel.rs).
    let panic_requested = std::env::var_os("NOVANC_TEST_PANIC").is_some();
    loop {
        if let Some(code) = between_frames(term, &mut renderer) {
            return (code, console);
        }
        let (w, h) = term.size();
        console.set_screen_fits(w >= need.0 && h >= need.1);
        let keys = match term.read_keys(Duration::from_millis(20), &mut dec) {
            Ok(k) => k,
            Err(_) => return (0, console),
        };
        for k in keys {
            match k {
                Key::Ctrl('c') | Key::Alt('q') => return (0, console),
                Key::Ctrl('l') => renderer.invalidate(),
                k => console.press(k),
            }
        }
        console.tick();
        if let Some(f) = feed.as_mut() {
            f.publish(&console);
        }
        if screen.width() != w || screen.height() != h {
            screen = Screen::new(w, h);
        }
        screen.clear();
        let view = console.view();
        if w < need.0 || h < need.1 {
            draw_too_small(&mut screen, need, view.ignored.as_deref());
        } else if view.help > 0 {
            draw_help(&mut screen, view.help);
        } else {
            draw_panel(&mut screen, &view);
        }
        out.clear();
        renderer.render(&screen, &mut out);
        if !out.is_empty() && term.write_all(&out).is_err() {
            return (1, console);
        }
        console.frame_written();
        if panic_requested && !out.is_empty() {
            panic!("NOVANC_TEST_PANIC: a panic after the first frame, as requested");
        }
    }
}
