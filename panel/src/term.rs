//! The terminal: raw mode and the alternate screen through libc (termios, ioctl TIOCGWINSZ,
//! poll), handed back clean on exit, on panic (a panic hook) and on SIGTERM/SIGINT/SIGHUP
//! (the handlers only raise a flag; the input loop sees it, returns, and `Drop` restores).
//! SIGWINCH raises a resize flag.

use crate::input::{Decoder, Key};
use std::io;
use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};
use std::sync::{Mutex, Once};
use std::time::Duration;

/// The bytes that enter the panel's screen: alternate screen, cursor hidden, no autowrap.
const ENTER: &[u8] = b"\x1b[?1049h\x1b[?25l\x1b[?7l\x1b[H\x1b[2J";
/// The bytes that leave it: default colours, autowrap and cursor back, main screen.
const LEAVE: &[u8] = b"\x1b[0m\x1b[?7h\x1b[?25h\x1b[?1049l";

static RESIZED: AtomicBool = AtomicBool::new(false);
static TERMINATE: AtomicI32 = AtomicI32::new(0);
/// The terminal state to restore (also used by the panic hook).
static ORIGINAL: Mutex<Option<libc::termios>> = Mutex::new(None);
static HOOK: Once = Once::new();

extern "C" fn on_winch(_sig: libc::c_int) {
    RESIZED.store(true, Ordering::SeqCst);
}

extern "C" fn on_terminate(sig: libc::c_int) {
    TERMINATE.store(sig, Ordering::SeqCst);
}

/// Installs `handler` for `sig` without SA_RESTART, so that a blocked poll wakes up.
fn set_handler(sig: libc::c_int, handler: extern "C" fn(libc::c_int)) {
    // SAFETY: a zeroed sigaction is a valid "no flags, empty mask" value; the handler only
    // stores to an atomic, which is async-signal-safe.
    unsafe {
        let mut sa: libc::sigaction = std::mem::zeroed();
        sa.sa_sigaction = handler as usize;
        libc::sigemptyset(&mut sa.sa_mask);
        sa.sa_flags = 0;
        libc::sigaction(sig, &sa, std::ptr::null_mut());
    }
}

/// Restores the saved terminal state, if any; safe to call more than once.
pub fn restore_terminal() {
    let saved = match ORIGINAL.try_lock() {
        Ok(mut g) => g.take(),
        Err(std::sync::TryLockError::Poisoned(p)) => p.into_inner().take(),
        Err(_) => None,
    };
    if let Some(t) = saved {
        // SAFETY: writing a constant buffer and restoring a termios we read earlier.
        unsafe {
            libc::write(1, LEAVE.as_ptr() as *const libc::c_void, LEAVE.len());
            libc::tcsetattr(0, libc::TCSANOW, &t);
        }
    }
}

/// The panel's terminal, in raw mode on the alternate screen until dropped.
pub struct Terminal {
    active: bool,
}

impl Terminal {
    /// Switches stdin/stdout to raw mode and the alternate screen, and installs the signal
    /// handlers and the panic hook that hand the terminal back.
    pub fn enter() -> io::Result<Terminal> {
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
        // SAFETY: cfmakeraw edits the struct we own; tcsetattr applies it to stdin.
        unsafe {
            libc::cfmakeraw(&mut raw);
            raw.c_cc[libc::VMIN] = 1;
            raw.c_cc[libc::VTIME] = 0;
            if libc::tcsetattr(0, libc::TCSANOW, &raw) != 0 {
                return Err(io::Error::last_os_error());
            }
        }
        if let Ok(mut g) = ORIGINAL.lock() {
            *g = Some(original);
        }
        HOOK.call_once(|| {
            let prev = std::panic::take_hook();
            std::panic::set_hook(Box::new(move |info| {
                restore_terminal();
                // A panic in any thread ends the panel loop too (exit 128 + SIGABRT).
                TERMINATE.store(libc::SIGABRT, Ordering::SeqCst);
                prev(info);
            }));
        });
        set_handler(libc::SIGWINCH, on_winch);
        set_handler(libc::SIGTERM, on_terminate);
        set_handler(libc::SIGINT, on_terminate);
        set_handler(libc::SIGHUP, on_terminate);
        let mut t = Terminal { active: true };
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

    /// Whether the terminal was resized since the last call.
    pub fn take_resized(&self) -> bool {
        RESIZED.swap(false, Ordering::SeqCst)
    }

    /// The signal that asked the panel to end (SIGTERM, SIGINT, SIGHUP), if any.
    pub fn terminate_requested(&self) -> Option<i32> {
        match TERMINATE.load(Ordering::SeqCst) {
            0 => None,
            s => Some(s),
        }
    }

    /// Hands the terminal back: main screen, cursor, cooked mode. Idempotent.
    pub fn restore(&mut self) {
        if self.active {
            self.active = false;
            restore_terminal();
        }
    }
}

impl Drop for Terminal {
    fn drop(&mut self) {
        self.restore();
    }
}
