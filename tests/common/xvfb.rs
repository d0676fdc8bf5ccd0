//! Helpers of the window tests under Xvfb (`tests/window_xvfb.rs`, `tests/lathe_window_xvfb.rs`):
//! a scratch directory, an Xvfb server on a display it picks itself, running `novanc` with a
//! time limit, and reading the plasma display back from a screenshot's pixels. Included by
//! `#[path]`, so each test binary has its own copy.
#![allow(dead_code)]

use novanc::window::font::{char_of, CELL_H, CELL_W};
use std::io::{BufRead, BufReader, Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// A scratch directory under the target directory, fresh for each test.
pub fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("window_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// `novanc --window ARGS --script SCRIPT --screenshot SHOT --size 1400x860` on Xvfb `x`, with
/// software GL and a scale factor of 1 (so pixels are the layout's), the state in `dir/state`.
pub fn window_command(x: &Xvfb, args: &[&str], dir: &Path, script: &Path, shot: &Path) -> Command {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_novanc"));
    cmd.arg("--window")
        .args(args)
        .arg("--state")
        .arg(dir.join("state"))
        .arg("--script")
        .arg(script)
        .arg("--screenshot")
        .arg(shot)
        .args(["--size", "1400x860"]);
    on_xvfb(&mut cmd, x);
    cmd
}

/// Points a `novanc --window` command at Xvfb `x`, with software GL and a scale factor of 1.
pub fn on_xvfb(cmd: &mut Command, x: &Xvfb) {
    cmd.env("DISPLAY", &x.display)
        .env_remove("WAYLAND_DISPLAY")
        .env("LIBGL_ALWAYS_SOFTWARE", "1")
        .env("WINIT_X11_SCALE_FACTOR", "1");
}

/// An Xvfb server on a display number it picked itself (`-displayfd`); killed on drop.
pub struct Xvfb {
    child: Child,
    /// The display, `:N`.
    pub display: String,
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

pub fn find_in_path(prog: &str) -> Option<PathBuf> {
    std::env::var_os("PATH").and_then(|p| {
        std::env::split_paths(&p)
            .map(|d| d.join(prog))
            .find(|f| f.is_file())
    })
}

/// Starts Xvfb, or says why not: `Err` means skip (or fail under CI).
pub fn start_xvfb() -> Result<Xvfb, String> {
    let Some(xvfb) = find_in_path("Xvfb") else {
        return Err("Xvfb is not installed (apt-get install xvfb)".into());
    };
    let mut child = Command::new(xvfb)
        .args([
            "-displayfd",
            "1",
            "-screen",
            "0",
            "1600x1000x24",
            "-nolisten",
            "tcp",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .map_err(|e| format!("cannot start Xvfb: {e}"))?;
    let mut line = String::new();
    let out = child.stdout.take().ok_or("no Xvfb stdout")?;
    BufReader::new(out)
        .read_line(&mut line)
        .map_err(|e| format!("Xvfb did not report its display: {e}"))?;
    let n: u32 = line
        .trim()
        .parse()
        .map_err(|_| format!("Xvfb reported '{}' as its display", line.trim()))?;
    Ok(Xvfb {
        child,
        display: format!(":{n}"),
    })
}

/// Starts Xvfb, or skips loudly (fails when CI=true).
pub fn xvfb_or_skip(test: &str) -> Option<Xvfb> {
    match start_xvfb() {
        Ok(x) => Some(x),
        Err(why) => {
            if std::env::var("CI").is_ok_and(|v| v == "true") {
                panic!("{test}: {why}, and CI=true requires it");
            }
            // Straight to the process's stderr, past the test harness's output capture.
            let _ = writeln!(std::io::stderr(), "\n*** SKIPPED {test}: {why} ***\n");
            None
        }
    }
}

/// Runs the command to its end within `limit`, returning (exit code, stdout, stderr).
pub fn run_with_limit(mut cmd: Command, limit: Duration) -> (Option<i32>, String, String) {
    let mut child = cmd
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn novanc");
    let mut so = child.stdout.take().unwrap();
    let mut se = child.stderr.take().unwrap();
    let t_out = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = so.read_to_string(&mut s);
        s
    });
    let t_err = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = se.read_to_string(&mut s);
        s
    });
    let start = Instant::now();
    let code = loop {
        if let Some(st) = child.try_wait().unwrap() {
            break st.code();
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            panic!(
                "novanc --window did not finish within {} s; stderr: {}",
                limit.as_secs(),
                t_err.join().unwrap_or_default()
            );
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    (code, t_out.join().unwrap(), t_err.join().unwrap())
}

/// A rectangle in screenshot pixels.
#[derive(Clone, Copy, Debug)]
pub struct R {
    pub x: usize,
    pub y: usize,
    pub w: usize,
    pub h: usize,
}

pub fn px(img: &(usize, usize, Vec<u8>), x: usize, y: usize) -> [u8; 3] {
    let i = (y * img.0 + x) * 3;
    [img.2[i], img.2[i + 1], img.2[i + 2]]
}

/// A lit plasma dot: orange (red high, green middling, blue low).
pub fn is_orange(p: [u8; 3]) -> bool {
    p[0] > 200 && (90..=190).contains(&p[1]) && p[2] < 90
}

/// Reads the plasma display back from the screenshot: each cell's 5×7 dots to a character.
pub fn read_plasma(img: &(usize, usize, Vec<u8>), r: R, pitch: usize) -> Vec<String> {
    let rows = (r.h - pitch) / (CELL_H * pitch);
    let cols = (r.w - pitch) / (CELL_W * pitch);
    (0..rows)
        .map(|row| {
            (0..cols)
                .map(|col| {
                    let mut g = [0u8; 7];
                    for (dy, bits) in g.iter_mut().enumerate() {
                        for dx in 0..5 {
                            let x = r.x + pitch + (col * CELL_W + dx) * pitch;
                            let y = r.y + pitch + (row * CELL_H + dy) * pitch;
                            if is_orange(px(img, x, y)) {
                                *bits |= 0x10 >> dx;
                            }
                        }
                    }
                    char_of(g).unwrap_or('\u{FFFD}')
                })
                .collect::<String>()
        })
        .collect()
}
