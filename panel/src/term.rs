//! The terminal: raw mode and the alternate screen through libc (termios, ioctl TIOCGWINSZ,
//! poll), handed back clean on exit, on panic (a panic hook), on SIGQUIT (its handler hands the
//! terminal back, then the signal takes its default action), and before a stop signal ends the
//! process: the stop signals (SIGTERM, SIGINT, SIGHUP) are the application's (novanc:
//! `src/cli/signals.rs`), whose loop ends and drops the `Terminal`, and whose handler calls
//! [`restore_now`] before a second signal ends the process at once.
//!
//! Job control (docs/panel.md, "Terminal"): SIGTSTP hands the terminal back (main screen,
//! cursor, the modes it had) and stops the process with SIGTSTP's default action; when it
//! continues (SIGCONT: `fg`), raw mode and the alternate screen are taken again and the loop
//! draws the whole frame (`take_redraw`). SIGWINCH raises a resize flag.
//!
//! Handlers only touch atomics or call async-signal-safe functions (`write`, `tcsetattr`,
//! `signal`, `raise`); the terminal's modes they restore are saved before any handler is
//! installed and never change while a `Terminal` is alive.

use crate::input::{Decoder, Key};
use std::cell::UnsafeCell;
use std::io;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Once;
use std::time::Duration;

/// The bytes that enter the panel's screen: alternate screen, cursor hidden, no autowrap.
const ENTER: &[u8] = b"\x1b[?1049h\x1b[?25l\x1b[?7l\x1b[H\x1b[2J";
/// The bytes that leave it: default colours, autowrap and cursor back, main screen.
const LEAVE: &[u8] = b"\x1b[0m\x1b[?7h\x1b[?25h\x1b[?1049l";

static RESIZED: AtomicBool = AtomicBool::new(false);
/// SIGTSTP arrived: the loop is to hand the terminal back and stop.
static SUSPEND: AtomicBool = AtomicBool::new(false);
/// SIGCONT arrived: the loop is to take the terminal again and draw the whole frame.
static CONTINUED: AtomicBool = AtomicBool::new(false);
/// A thread panicked (the panic hook has handed the terminal back).
static PANICKED: AtomicBool = AtomicBool::new(false);
/// A `Terminal` is alive: `MODES` holds its modes.
static ALIVE: AtomicBool = AtomicBool::new(false);
/// The terminal is in raw mode on the alternate screen now: a restore is owed.
static RAW: AtomicBool = AtomicBool::new(false);
static HOOK: Once = Once::new();

/// The terminal's modes before the panel (to restore) and the panel's raw modes.
#[derive(Clone, Copy)]
struct Modes {
    original: libc::termios,
    raw: libc::termios,
}

/// `Modes` where a signal handler can read them without a lock: written by `Terminal::enter`
/// only while `ALIVE` is false, read only while it is true.
struct SavedModes(UnsafeCell<Option<Modes>>);

// SAFETY: see `SavedModes`: the one writer (`enter`) and the readers (handlers, `restore_now`,
// `reenter`) are kept apart by `ALIVE` (release on the write side, acquire on the read side).
unsafe impl Sync for SavedModes {}

static MODES: SavedModes = SavedModes(UnsafeCell::new(None));

/// The saved modes, while a `Terminal` is alive.
fn modes() -> Option<Modes> {
    if !ALIVE.load(Ordering::Acquire) {
        return None;
    }
    // SAFETY: `ALIVE` is true, so `enter` is not writing (see `SavedModes`).
    unsafe { *MODES.0.get() }
}

extern "C" fn on_winch(_sig: libc::c_int) {
    RESIZED.store(true, Ordering::SeqCst);
}

extern "C" fn on_tstp(_sig: libc::c_int) {
    SUSPEND.store(true, Ordering::SeqCst);
}

extern "C" fn on_cont(_sig: libc::c_int) {
    CONTINUED.store(true, Ordering::SeqCst);
}

/// SIGQUIT: the terminal back now, then the default action (the process ends, with a core
/// file where they are enabled).
extern "C" fn on_quit(sig: libc::c_int) {
    restore_now();
    // SAFETY: async-signal-safe calls; the raised signal stays blocked until this handler
    // returns, then takes its default action.
    unsafe {
        libc::signal(sig, libc::SIG_DFL);
        libc::raise(sig);
    }
}

/// Installs `handler` for `sig` without SA_RESTART, so that a blocked poll wakes up; a
/// signal ignored when the process started (`nohup`) stays ignored. Returns the disposition
/// it replaced, if it installed the handler.
fn set_handler(sig: libc::c_int, handler: extern "C" fn(libc::c_int)) -> Option<libc::sigaction> {
    // SAFETY: sigaction with a zeroed struct reads the current disposition; a zeroed sigaction
    // is a valid "no flags, empty mask" value; the handlers only touch atomics or call
    // async-signal-safe functions.
    unsafe {
        let mut old: libc::sigaction = std::mem::zeroed();
        if libc::sigaction(sig, std::ptr::null(), &mut old) != 0
            || old.sa_sigaction == libc::SIG_IGN
        {
            return None;
        }
        let mut sa: libc::sigaction = std::mem::zeroed();
        sa.sa_sigaction = handler as usize;
        libc::sigemptyset(&mut sa.sa_mask);
        sa.sa_flags = 0;
        (libc::sigaction(sig, &sa, std::ptr::null_mut()) == 0).then_some(old)
    }
}

/// Writes all of `bytes` to stdout with `write` (async-signal-safe); gives up on an error.
fn write_raw(bytes: &[u8]) {
    let mut rest = bytes;
    while !rest.is_empty() {
        // SAFETY: writing from a live slice.
        let n = unsafe { libc::write(1, rest.as_ptr() as *const libc::c_void, rest.len()) };
        if n > 0 {
            rest = &rest[n as usize..];
        } else if n < 0 && io::Error::last_os_error().kind() == io::ErrorKind::Interrupted {
            continue;
        } else {
            return;
        }
    }
}

/// Applies terminal modes to stdin, again after a signal; false on an error.
fn set_modes(t: &libc::termios) -> bool {
    loop {
        // SAFETY: applying a termios we own to stdin.
        if unsafe { libc::tcsetattr(0, libc::TCSANOW, t) } == 0 {
            return true;
        }
        if io::Error::last_os_error().kind() != io::ErrorKind::Interrupted {
            return false;
        }
    }
}

/// Hands the terminal back now, if the panel has it: default colours, autowrap and cursor,
/// main screen, and the modes it had before the panel. Async-signal-safe (atomics, `write`,
/// `tcsetattr`), so a signal handler may call it; only the first call after the panel took
/// the terminal does anything.
pub fn restore_now() {
    if let Some(m) = modes() {
        if RAW.swap(false, Ordering::SeqCst) {
            write_raw(LEAVE);
            set_modes(&m.original);
        }
    }
}

/// Takes the terminal again after it was handed back while the panel is alive (after SIGCONT).
fn reenter() {
    if let Some(m) = modes() {
        if !RAW.swap(true, Ordering::SeqCst) {
            set_modes(&m.raw);
            write_raw(ENTER);
        }
    }
}

/// The panel's terminal, in raw mode on the alternate screen until dropped.
pub struct Terminal {
    active: bool,
    /// The dispositions the panel's handlers replaced, put back by `restore`.
    replaced: Vec<(libc::c_int, libc::sigaction)>,
}

impl Terminal {
    /// Switches stdin/stdout to raw mode and the alternate screen, and installs the panic hook
    /// and the handlers of SIGWINCH, SIGTSTP, SIGCONT and SIGQUIT. The stop signals are the
    /// application's (see the module's documentation).
    pub fn enter() -> io::Result<Terminal> {
        if ALIVE.load(Ordering::Acquire) {
            return Err(io::Error::other("the terminal panel is already open"));
        }
        // SAFETY: isatty and tcgetattr only read; `t` is fully written by tcgetattr on success.
        let original = unsafe {
            if libc::isatty(0) != 1 || libc::isatty(1) != 1 {
                return Err(io::Error::other(
                    "the terminal panel needs a terminal on stdin and stdout",
                ));
            }
            let mut t: libc::termios = std::mem::zeroed();
            if libc::tcgetattr(0, &mut t) != 0 {
                return Err(io::Error::last_os_error());
            }
            t
        };
        let mut raw = original;
        // SAFETY: cfmakeraw edits the struct we own.
        unsafe {
            libc::cfmakeraw(&mut raw);
        }
        raw.c_cc[libc::VMIN] = 1;
        raw.c_cc[libc::VTIME] = 0;
        if !set_modes(&raw) {
            return Err(io::Error::last_os_error());
        }
        // SAFETY: no `Terminal` is alive, so no handler or `restore_now` reads `MODES` now.
        unsafe {
            *MODES.0.get() = Some(Modes { original, raw });
        }
        RAW.store(true, Ordering::SeqCst);
        ALIVE.store(true, Ordering::Release);
        HOOK.call_once(|| {
            let prev = std::panic::take_hook();
            std::panic::set_hook(Box::new(move |info| {
                restore_now();
                // A panic in any thread ends the panel loop too (`panicked`).
                PANICKED.store(true, Ordering::SeqCst);
                prev(info);
            }));
        });
        SUSPEND.store(false, Ordering::SeqCst);
        CONTINUED.store(false, Ordering::SeqCst);
        let handlers: [(libc::c_int, extern "C" fn(libc::c_int)); 4] = [
            (libc::SIGWINCH, on_winch),
            (libc::SIGTSTP, on_tstp),
            (libc::SIGCONT, on_cont),
            (libc::SIGQUIT, on_quit),
        ];
        let replaced = handlers
            .into_iter()
            .filter_map(|(sig, h)| set_handler(sig, h).map(|old| (sig, old)))
            .collect();
        let mut t = Terminal {
            active: true,
            replaced,
        };
        t.write_all(ENTER)?;
        Ok(t)
    }

    /// The terminal size (columns, rows); (80, 24) if it cannot be asked.
    pub fn size(&self) -> (usize, usize) {
        // SAFETY: TIOCGWINSZ fills a winsize we own.
        unsafe {
            let mut ws: libc::winsize = std::mem::zeroed();
            if libc::ioctl(1, libc::TIOCGWINSZ, &mut ws) == 0 && ws.ws_col > 0 && ws.ws_row > 0 {
                (ws.ws_col as usize, ws.ws_row as usize)
            } else {
                (80, 24)
            }
        }
    }

    /// Writes all bytes to the terminal.
    pub fn write_all(&mut self, bytes: &[u8]) -> io::Result<()> {
        let mut rest = bytes;
        while !rest.is_empty() {
            // SAFETY: writing from a live slice.
            let n = unsafe { libc::write(1, rest.as_ptr() as *const libc::c_void, rest.len()) };
            if n < 0 {
                let e = io::Error::last_os_error();
                if e.kind() == io::ErrorKind::Interrupted {
                    continue;
                }
                return Err(e);
            }
            rest = &rest[n as usize..];
        }
        Ok(())
    }

    /// Waits up to `timeout` for input and decodes it. Returns no keys on a timeout or a
    /// signal; an error when stdin is closed.
    pub fn read_keys(&mut self, timeout: Duration, dec: &mut Decoder) -> io::Result<Vec<Key>> {
        let mut pfd = libc::pollfd {
            fd: 0,
            events: libc::POLLIN,
            revents: 0,
        };
        let ms = timeout.as_millis().min(i32::MAX as u128) as i32;
        // SAFETY: polling one pollfd we own.
        let r = unsafe { libc::poll(&mut pfd, 1, ms) };
        if r < 0 {
            let e = io::Error::last_os_error();
            return if e.kind() == io::ErrorKind::Interrupted {
                Ok(Vec::new())
            } else {
                Err(e)
            };
        }
        if r == 0 {
            return Ok(dec.flush());
        }
        let mut buf = [0u8; 4096];
        // SAFETY: reading into a buffer we own.
        let n = unsafe { libc::read(0, buf.as_mut_ptr() as *mut libc::c_void, buf.len()) };
        if n < 0 {
            let e = io::Error::last_os_error();
            return if e.kind() == io::ErrorKind::Interrupted {
                Ok(Vec::new())
            } else {
                Err(e)
            };
        }
        if n == 0 {
            return Err(io::Error::new(io::ErrorKind::UnexpectedEof, "stdin closed"));
        }
        Ok(dec.feed(&buf[..n as usize]))
    }

    /// Between frames: job control and resizes. After SIGTSTP the terminal is handed back
    /// and the process stops here (SIGTSTP's default action) until it is continued; after
    /// SIGCONT (`fg`, or after a SIGSTOP) raw mode and the alternate screen are taken again.
    /// True when the whole frame must be drawn again (continued, or resized).
    pub fn take_redraw(&mut self) -> bool {
        let mut redraw = RESIZED.swap(false, Ordering::SeqCst);
        if SUSPEND.swap(false, Ordering::SeqCst) {
            restore_now();
            // SAFETY: async-signal-safe calls; SIGTSTP with its default action stops every
            // thread of the process until SIGCONT, then `raise` returns.
            unsafe {
                libc::signal(libc::SIGTSTP, libc::SIG_DFL);
                libc::raise(libc::SIGTSTP);
            }
            let _ = set_handler(libc::SIGTSTP, on_tstp);
            CONTINUED.store(true, Ordering::SeqCst);
        }
        if CONTINUED.swap(false, Ordering::SeqCst) {
            reenter();
            redraw = true;
        }
        redraw
    }

    /// Whether a thread panicked (the panic hook has handed the terminal back): the loop is to
    /// end.
    pub fn panicked(&self) -> bool {
        PANICKED.load(Ordering::SeqCst)
    }

    /// Hands the terminal back: main screen, cursor, cooked mode; the signals the panel
    /// handled get their former dispositions again. Idempotent.
    pub fn restore(&mut self) {
        if self.active {
            self.active = false;
            restore_now();
            for (sig, old) in self.replaced.drain(..) {
                // SAFETY: putting back a disposition sigaction gave us.
                unsafe {
                    libc::sigaction(sig, &old, std::ptr::null_mut());
                }
            }
            ALIVE.store(false, Ordering::Release);
        }
    }
}

impl Drop for Terminal {
    fn drop(&mut self) {
        self.restore();
    }
}
