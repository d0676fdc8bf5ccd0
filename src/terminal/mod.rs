//! The terminal front end: the thin loop between the terminal's devices (`novanc-panel`: raw
//! mode, keys, cells) and the `Console`. It reads stdin without blocking (poll, 20 ms), maps keys to panel
//! events, ticks the console (about 50 Hz) and draws the panel with diff rendering. The
//! terminal is handed back on exit, on panic and on SIGTERM/SIGINT/SIGHUP.

pub mod layout;

use crate::console::{Console, ConsoleConfig};
use crate::panel_model::{Axis, DataMode, OpMode, PanelEvent};
use layout::{draw_help, draw_panel, draw_too_small, panel_size};
use novanc_panel::{Decoder, Key, Renderer, Screen, Terminal};
use std::time::{Duration, Instant};

/// A CONTINUOUS jog stops when its key has not repeated for this long (terminals report no
/// key release; auto-repeat keeps a held key coming).
const JOG_RELEASE: Duration = Duration::from_millis(150);

/// What a key asks of the loop.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    /// A panel event for the console.
    Event(PanelEvent),
    /// A jog or handwheel key on an axis and direction (its meaning depends on the mode).
    Move(Axis, i8),
    /// Feed override up or down 10 %.
    Override(i32),
    /// Next handwheel scale (x1, x10, x100).
    WheelScale,
    /// Turn the handwheel one detent on its selected axis.
    Wheel(i32),
    /// The typed line names the tape to put in the reader.
    Tape,
    /// Show the help screen.
    Help,
    /// Redraw the whole screen.
    Redraw,
    /// Leave the console.
    Quit,
    /// Nothing.
    None,
}

/// The keyboard map (see docs/panel.md).
pub fn map_key(k: Key) -> Action {
    use Action as A;
    match k {
        Key::Char(c) => A::Event(PanelEvent::Key(c)),
        Key::Enter => A::Event(PanelEvent::Eob),
        Key::Backspace => A::Event(PanelEvent::Rubout),
        Key::F(n @ 1..=7) => A::Event(PanelEvent::Data(DataMode::ALL[n as usize - 1])),
        Key::Alt(c @ '1'..='7') => A::Event(PanelEvent::Op(OpMode::ALL[c as usize - '1' as usize])),
        Key::F(8) | Key::Alt('h') => A::Help,
        Key::F(9) | Key::Alt('s') => A::Event(PanelEvent::Start),
        Key::F(10) | Key::Alt('p') => A::Event(PanelEvent::Stop),
        Key::F(11) | Key::Alt('r') => A::Event(PanelEvent::Reset),
        Key::F(12) | Key::Alt('e') => A::Event(PanelEvent::EStop),
        Key::Alt('=') | Key::Alt('+') => A::Override(10),
        Key::Alt('-') => A::Override(-10),
        Key::Alt('w') => A::WheelScale,
        Key::Alt(',') => A::Wheel(-1),
        Key::Alt('.') => A::Wheel(1),
        Key::Alt('t') => A::Tape,
        Key::Left => A::Move(Axis::X, -1),
        Key::Right => A::Move(Axis::X, 1),
        Key::Up => A::Move(Axis::Y, 1),
        Key::Down => A::Move(Axis::Y, -1),
        Key::PageUp => A::Move(Axis::Z, 1),
        Key::PageDown => A::Move(Axis::Z, -1),
        Key::Ctrl('l') => A::Redraw,
        Key::Ctrl('c') | Key::Alt('q') => A::Quit,
        _ => A::None,
    }
}

/// The terminal front end's `--help`.
pub const HELP: &str = "\
usage: novanc [--state DIR] [--rows N] [--cols N] [--record OUT.mcap]
The terminal front panel; F8 in the panel shows the keys.
";

/// Runs the terminal panel on a console opened with `cfg`; returns the exit code.
pub fn run(cfg: ConsoleConfig) -> i32 {
    let (console, warnings) = match Console::open(cfg) {
        Ok(x) => x,
        Err(e) => {
            eprintln!("novanc: {e}");
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
    let (code, console) = run_loop(&mut term, console);
    term.restore();
    for w in warnings {
        eprintln!("novanc: warning at start: {w}");
    }
    match console.finish() {
        Ok(Some(s)) => eprintln!("novanc: {s}"),
        Ok(None) => {}
        Err(e) => eprintln!("novanc: recording: {e}"),
    }
    code
}

/// The input/draw loop; returns the exit code and the console.
fn run_loop(term: &mut Terminal, mut console: Console) -> (i32, Console) {
    let mut dec = Decoder::new();
    let mut renderer = Renderer::new();
    let mut screen = Screen::new(0, 0);
    let mut out = Vec::with_capacity(16 * 1024);
    let mut help = false;
    let mut jog: Option<(Axis, i8, Instant)> = None;
    let need = panel_size(console.config().rows, console.config().cols);
    // Test hook: proves that a panic hands the terminal back (tests/tmux_panel.rs).
    let panic_requested = std::env::var_os("NOVANC_TEST_PANIC").is_some();
    loop {
        if let Some(sig) = term.terminate_requested() {
            return (128 + sig, console);
        }
        if term.take_resized() {
            renderer.invalidate();
        }
        let keys = match term.read_keys(Duration::from_millis(20), &mut dec) {
            Ok(k) => k,
            Err(_) => return (0, console),
        };
        for k in keys {
            if help {
                help = false;
                continue;
            }
            match map_key(k) {
                Action::Event(e) => console.handle(e),
                Action::Move(axis, dir) => {
                    let op = console.view().op_mode;
                    match op {
                        OpMode::Handle => console.handle(PanelEvent::Wheel(axis, dir as i32)),
                        OpMode::Continuous => {
                            let same = matches!(jog, Some((a, d, _)) if a == axis && d == dir);
                            if !same {
                                console.handle(PanelEvent::Jog(axis, dir));
                            }
                            jog = Some((axis, dir, Instant::now()));
                        }
                        _ => console.handle(PanelEvent::Jog(axis, dir)),
                    }
                }
                Action::Override(d) => {
                    let o = console.view().feed_override as i32 + d;
                    console.handle(PanelEvent::Override(o.clamp(0, 150) as u32));
                }
                Action::WheelScale => {
                    let s = match console.view().wheel.1 {
                        1 => 10,
                        10 => 100,
                        _ => 1,
                    };
                    console.handle(PanelEvent::WheelScale(s));
                }
                Action::Wheel(n) => {
                    let axis = console.view().wheel.0;
                    console.handle(PanelEvent::Wheel(axis, n));
                }
                Action::Tape => console.tape_from_entry(),
                Action::Help => help = true,
                Action::Redraw => renderer.invalidate(),
                Action::Quit => return (0, console),
                Action::None => {}
            }
        }
        if let Some((_, _, at)) = jog {
            if at.elapsed() > JOG_RELEASE {
                console.handle(PanelEvent::JogRelease);
                jog = None;
            }
        }
        console.tick();
        let (w, h) = term.size();
        if screen.width() != w || screen.height() != h {
            screen = Screen::new(w, h);
        }
        screen.clear();
        if help {
            draw_help(&mut screen);
        } else if w < need.0 || h < need.1 {
            draw_too_small(&mut screen, need);
        } else {
            draw_panel(&mut screen, &console.view());
        }
        out.clear();
        renderer.render(&screen, &mut out);
        if !out.is_empty() && term.write_all(&out).is_err() {
            return (1, console);
        }
        if panic_requested && !out.is_empty() {
            panic!("NOVANC_TEST_PANIC: a panic after the first frame, as requested");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_selector_position_and_button_has_a_key() {
        for (i, m) in OpMode::ALL.iter().enumerate() {
            let c = char::from(b'1' + i as u8);
            assert_eq!(map_key(Key::Alt(c)), Action::Event(PanelEvent::Op(*m)));
        }
        for (i, m) in DataMode::ALL.iter().enumerate() {
            assert_eq!(
                map_key(Key::F(i as u8 + 1)),
                Action::Event(PanelEvent::Data(*m))
            );
        }
        assert_eq!(map_key(Key::F(9)), Action::Event(PanelEvent::Start));
        assert_eq!(map_key(Key::F(10)), Action::Event(PanelEvent::Stop));
        assert_eq!(map_key(Key::F(11)), Action::Event(PanelEvent::Reset));
        assert_eq!(map_key(Key::F(12)), Action::Event(PanelEvent::EStop));
        assert_eq!(map_key(Key::Enter), Action::Event(PanelEvent::Eob));
        assert_eq!(map_key(Key::Char('*')), Action::Event(PanelEvent::Key('*')));
        assert_eq!(map_key(Key::PageDown), Action::Move(Axis::Z, -1));
        assert_eq!(map_key(Key::Ctrl('c')), Action::Quit);
    }
}
