//! The window streams to MTConnect agents (docs/mtconnect.md "The window"): `novanc --window
//! --mtconnect 127.0.0.1:0`, the mill's and the Citizen's, under Xvfb. The port is read from
//! stderr (`mtconnect: listening on`); an agent connects and reads the dump, then the mode
//! that the window's script turns, which only the window's frame loop publishes.
//!
//! Needs Xvfb (as tests/window_xvfb.rs): skipped loudly without it, a failure when CI=true.
#![cfg(feature = "window")]

#[path = "common/xvfb.rs"]
mod xvfb;

use std::io::{BufRead, BufReader};
use std::net::TcpStream;
use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};
use xvfb::{on_xvfb, scratch, xvfb_or_skip};

/// Opens the window with `args` and the panel `script` on Xvfb, with `--mtconnect
/// 127.0.0.1:0`; connects to the port it announces and reads until every text of `want` has
/// been seen in a line (60 s at most), then closes the window.
fn window_streams(name: &str, args: &[&str], script: &str, want: &[&str]) {
    let Some(x) = xvfb_or_skip(name) else {
        return;
    };
    let d = scratch(name);
    let script_path = d.join("s.script");
    std::fs::write(&script_path, script).unwrap();
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_novanc"));
    cmd.arg("--window")
        .args(args)
        .arg("--state")
        .arg(d.join("state"))
        .arg("--script")
        .arg(&script_path)
        .args(["--size", "1400x860", "--mtconnect", "127.0.0.1:0"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    on_xvfb(&mut cmd, &x);
    let mut child = cmd.spawn().unwrap();
    let (tx, rx) = mpsc::channel();
    let err = BufReader::new(child.stderr.take().unwrap());
    std::thread::spawn(move || {
        for l in err.lines().map_while(Result::ok) {
            let _ = tx.send(l);
        }
    });
    let end = Instant::now() + Duration::from_secs(60);
    let mut stderr = Vec::new();
    let addr = loop {
        let left = end.saturating_duration_since(Instant::now());
        match rx.recv_timeout(left) {
            Ok(l) => {
                if let Some(a) = l.split("mtconnect: listening on ").nth(1) {
                    break a.trim().to_string();
                }
                stderr.push(l);
            }
            Err(_) => {
                let _ = child.kill();
                let _ = child.wait();
                panic!("no `mtconnect: listening on` from the window: {stderr:?}");
            }
        }
    };
    let s = TcpStream::connect(&addr).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(60))).unwrap();
    let mut r = BufReader::new(s);
    let mut seen: Vec<String> = Vec::new();
    let mut line = String::new();
    let found = loop {
        if want.iter().all(|w| seen.iter().any(|l| l.contains(w))) {
            break true;
        }
        line.clear();
        match r.read_line(&mut line) {
            Ok(n) if n > 0 => seen.push(line.clone()),
            _ => break false,
        }
    };
    let _ = child.kill();
    let _ = child.wait();
    assert!(found, "{want:?} not all in {seen:?}");
}

#[test]
fn the_mill_window_streams_to_an_agent() {
    // The dump: DATA INPUT is EDIT; the script turns the selector to AUTO.
    window_streams(
        "mtc_mill",
        &[],
        "op AUTO\n",
        &[
            "|avail|AVAILABLE",
            "|exec|READY",
            "|mode|EDIT",
            "|mode|AUTOMATIC",
        ],
    );
}

#[test]
fn the_lathe_window_streams_its_paths_to_an_agent() {
    window_streams(
        "mtc_lathe",
        &["--machine", "citizen"],
        "op MDI\n",
        &[
            "|avail|AVAILABLE",
            "|p3_exec|READY",
            "|p1_mode|AUTOMATIC",
            "|p1_mode|MANUAL_DATA_INPUT",
        ],
    );
}
