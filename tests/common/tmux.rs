//! The tmux driver of the terminal tests (`tests/tmux_panel.rs`, `tests/record_signals.rs`):
//! a tmux server on its own socket running `novanc` in an 80×24 pane, keys by `send-keys`, the
//! screen by `capture-pane`. Included by `#[path]`, so each test binary has its own copy.
//! Without tmux a test fails when CI=true and is skipped (loudly) otherwise.
#![allow(dead_code)]

use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

/// One tmux server (its own socket) with one pane; killed when dropped.
pub struct Tmux {
    socket: String,
}

impl Tmux {
    /// Runs a tmux command on this server; its stdout.
    pub fn run(&self, args: &[&str]) -> String {
        let out = Command::new("tmux")
            .arg("-L")
            .arg(&self.socket)
            .args(args)
            .output()
            .expect("tmux runs");
        String::from_utf8_lossy(&out.stdout).into_owned()
    }

    /// Sends keys by tmux's names (`F9`, `M-1`, `C-c`, `Enter`).
    pub fn keys(&self, keys: &[&str]) {
        let mut a = vec!["send-keys", "-t", "0"];
        a.extend_from_slice(keys);
        self.run(&a);
    }

    /// Types literal text (no key-name lookup), then Enter.
    pub fn type_line(&self, text: &str) {
        self.run(&["send-keys", "-t", "0", "-l", text]);
        self.keys(&["Enter"]);
    }

    /// The pane's screen as text.
    pub fn screen(&self) -> String {
        self.run(&["capture-pane", "-p", "-t", "0"])
    }

    /// Waits until every `want` is on the screen; panics with the screen after `secs`.
    pub fn wait_for(&self, want: &[&str], secs: u64) -> String {
        let end = Instant::now() + Duration::from_secs(secs);
        loop {
            let s = self.screen();
            if want.iter().all(|w| s.contains(w)) {
                return s;
            }
            if Instant::now() > end {
                panic!("waited {secs} s for {want:?}; the screen is:\n{s}");
            }
            std::thread::sleep(Duration::from_millis(50));
        }
    }
}

impl Drop for Tmux {
    fn drop(&mut self) {
        self.run(&["kill-server"]);
    }
}

fn have_tmux() -> bool {
    Command::new("tmux")
        .arg("-V")
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false)
}

/// Whether tmux can run this test: in CI it must (a missing tmux fails the test); elsewhere a
/// missing tmux skips it, loudly.
pub fn tmux_or_skip(what: &str) -> bool {
    if have_tmux() {
        return true;
    }
    if std::env::var("CI").as_deref() == Ok("true") {
        panic!("tmux is required in CI (install it in .ci/run)");
    }
    eprintln!("SKIPPED: tmux is not installed; the {what} test did not run");
    false
}

/// Waits until the file `p` exists and is not empty; its text.
pub fn wait_file(p: &Path, secs: u64) -> String {
    let end = Instant::now() + Duration::from_secs(secs);
    loop {
        if let Ok(s) = std::fs::read_to_string(p) {
            if !s.is_empty() {
                return s;
            }
        }
        assert!(Instant::now() < end, "{} never appeared", p.display());
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// Starts an 80x24 pane on a tmux server of its own running `argv`.
fn start(name: &str, argv: &[&str]) -> Tmux {
    let t = Tmux {
        socket: format!("novanc-{name}-{}", std::process::id()),
    };
    let mut a = vec![
        "-f",
        "/dev/null",
        "new-session",
        "-d",
        "-x",
        "80",
        "-y",
        "24",
    ];
    a.extend_from_slice(argv);
    t.run(&a);
    t
}

/// Starts an 80x24 tmux session on its own socket running `run` (a shell command line that
/// starts novanc), with `stty -a` written to `before` and `after` it, and its exit status to
/// `exit`.
pub fn session(name: &str, d: &Path, run: &str) -> Tmux {
    let cmd = format!(
        "stty -a > '{d}/before'; {run}; echo \"exit=$?\" > '{d}/exit'; stty -a > '{d}/after'; sleep 60",
        d = d.display()
    );
    start(name, &["sh", "-c", &cmd])
}

/// Starts an 80x24 tmux session running an interactive shell with job control (`sh -i`: the
/// shell of a terminal, which stops and continues its jobs), no core files, and the prompt
/// `$ `. Type command lines into it with `type_line`.
pub fn shell(name: &str) -> Tmux {
    let t = start(name, &["env", "PS1=$ ", "ENV=", "sh", "-i"]);
    t.wait_for(&["$"], 10);
    t.type_line("ulimit -c 0");
    t
}

/// A shell command line that writes its process id to `pid` in `d`, then becomes `run` (so
/// that id is novanc's); for `kill` from the test.
pub fn with_pid(d: &Path, run: &str) -> String {
    format!("sh -c 'echo $$ > {d}/pid; exec {run}'", d = d.display())
}

/// The terminal settings after novanc exited are the ones before it started.
pub fn assert_stty_unchanged(d: &Path) {
    let after = wait_file(&d.join("after"), 10);
    let before = std::fs::read_to_string(d.join("before")).unwrap();
    assert_eq!(before, after, "stty -a changed");
}
