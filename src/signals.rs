//! Stop signals for the headless commands (docs/recording.md, "Interrupted runs"): SIGINT,
//! SIGTERM and SIGHUP no longer end `novanc run` or `novanc script` at once. The handler only
//! notes the signal; the command sees it at its next check (`caught`), stops the machine
//! (RESET), closes the recording with `complete: false`, and exits with 128 + the signal number
//! (`exit_code`), as a shell expects of a process a signal ended.
//!
//! The same holds for the consoles, in the terminal (`crate::terminal`: the panel's loop looks
//! at `pending` between frames) and in the window.
//!
//! A signal that was ignored when the process started (`nohup`, a background job of a shell
//! without job control) stays ignored. A second stop signal ends the process at once, as if no
//! handler were installed (the operator insists: a step that does not come back must not trap
//! them), after handing the terminal back if the panel holds it. The recording is then not
//! closed, but it stays readable: its file ends with a provisional end after every commit
//! (`crate::record::file`), which names the first signal once it was caught.

use std::sync::atomic::{AtomicBool, AtomicI32, Ordering};

/// The signals that stop a headless run properly.
pub const STOP_SIGNALS: [libc::c_int; 3] = [libc::SIGINT, libc::SIGTERM, libc::SIGHUP];

/// The first stop signal caught, 0 for none. Written by the handler (a lock-free atomic, so
/// async-signal-safe) and read by the command.
static CAUGHT: AtomicI32 = AtomicI32::new(0);

/// Whether `caught` has already told the operator and the recorder.
static REPORTED: AtomicBool = AtomicBool::new(false);

/// The handler: keeps the first signal; a second one gets its default action (the process
/// ends), after the terminal is handed back if the panel has it. Only async-signal-safe
/// calls: atomics, `write` and `tcsetattr` (`restore_now`), `signal` and `raise`.
extern "C" fn note(sig: libc::c_int) {
    if CAUGHT
        .compare_exchange(0, sig, Ordering::SeqCst, Ordering::SeqCst)
        .is_err()
    {
        novanc_panel::term::restore_now();
        // SAFETY: both are async-signal-safe; the raised signal stays blocked until this
        // handler returns, then takes its default action.
        unsafe {
            libc::signal(sig, libc::SIG_DFL);
            libc::raise(sig);
        }
    }
}

/// Installs the handler for SIGINT, SIGTERM and SIGHUP, except where a signal is ignored.
/// Returns the signals now handled. Safe to call more than once.
pub fn install() -> Vec<libc::c_int> {
    let mut handled = Vec::new();
    for sig in STOP_SIGNALS {
        // SAFETY: sigaction with a zeroed struct reads the current disposition, then installs
        // a handler that only touches an atomic (async-signal-safe). SA_RESTART keeps blocking
        // calls of the other threads going.
        unsafe {
            let mut old: libc::sigaction = std::mem::zeroed();
            if libc::sigaction(sig, std::ptr::null(), &mut old) != 0
                || old.sa_sigaction == libc::SIG_IGN
            {
                continue;
            }
            let mut act: libc::sigaction = std::mem::zeroed();
            act.sa_sigaction = note as extern "C" fn(libc::c_int) as libc::sighandler_t;
            act.sa_flags = libc::SA_RESTART;
            libc::sigemptyset(&mut act.sa_mask);
            if libc::sigaction(sig, &act, std::ptr::null_mut()) == 0 {
                handled.push(sig);
            }
        }
    }
    handled
}

/// The name of a stop signal (`SIGINT`), or its number.
pub fn name(sig: libc::c_int) -> String {
    match sig {
        libc::SIGINT => "SIGINT".into(),
        libc::SIGTERM => "SIGTERM".into(),
        libc::SIGHUP => "SIGHUP".into(),
        n => format!("signal {n}"),
    }
}

/// What a recording says of a stop signal: `interrupted by SIGINT`.
pub fn reason(sig: libc::c_int) -> String {
    format!("interrupted by {}", name(sig))
}

/// The first stop signal caught since `install`, if any. The first call that sees it says on
/// stderr that the run is being stopped and marks every recording of the process interrupted
/// (`complete: false`, `interrupted: interrupted by SIGINT`; a running recorder commits that
/// to its file at once: docs/recording.md).
pub fn caught() -> Option<libc::c_int> {
    let sig = CAUGHT.load(Ordering::SeqCst);
    if sig == 0 {
        return None;
    }
    if !REPORTED.swap(true, Ordering::SeqCst) {
        let why = reason(sig);
        crate::record::interrupt_all(&why);
        eprintln!("novanc: {why}: stopping the machine and closing the recording");
    }
    Some(sig)
}

/// `caught`, as the reason a recording gives (`interrupted by SIGTERM`).
pub fn caught_reason() -> Option<String> {
    caught().map(reason)
}

/// Whether a stop signal has been caught (no side effects: for a pulse core to poll).
pub fn pending() -> bool {
    CAUGHT.load(Ordering::SeqCst) != 0
}

/// Runs `stop` once, the first time it is called after a stop signal was caught.
pub fn on_signal(stop: impl FnOnce()) {
    static DONE: AtomicBool = AtomicBool::new(false);
    if caught().is_some() && !DONE.swap(true, Ordering::SeqCst) {
        stop();
    }
}

/// The exit code of a command: 128 + the signal number if the command acted on a stop signal
/// (it called `caught` and saw it), else `code`. A signal that arrives once the command has
/// stopped looking (its run over, the recording being closed) changes nothing.
pub fn exit_code(code: i32) -> i32 {
    match CAUGHT.load(Ordering::SeqCst) {
        sig if sig != 0 && REPORTED.load(Ordering::SeqCst) => 128 + sig,
        _ => code,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stop_signals_are_named_as_the_shell_names_them() {
        assert_eq!(name(libc::SIGINT), "SIGINT");
        assert_eq!(name(libc::SIGHUP), "SIGHUP");
        assert_eq!(name(libc::SIGTERM), "SIGTERM");
        assert_eq!(name(64), "signal 64");
    }
}
