//! The window under Xvfb (issue 6): `novanc --window` with Table B, driven by a panel script
//! through SINGLE BLOCK and 3 STARTs, takes a screenshot; the pixels must show the executing
//! block marker in the plasma display and the executed path in the backplot. Also: with no
//! display at all, `novanc --window` says so, suggests the terminal panel and exits non-zero.
//!
//! Needs Xvfb (Debian package `xvfb`, installed by `.ci/run`). Without it the Xvfb tests fail
//! when CI=true and are skipped loudly otherwise.
#![cfg(feature = "window")]

#[path = "common/xvfb.rs"]
mod xvfb;

use novanc::window::image::read_ppm;
use std::path::Path;
use std::process::Command;
use std::time::Duration;
use xvfb::{px, read_plasma, run_with_limit, scratch, window_command, xvfb_or_skip, R};

const BIN: &str = env!("CARGO_BIN_EXE_novanc");

/// The tests that render a run take turns: each software-rendered window with a real-time run
/// takes a core, and side by side on a 2-core machine the table B run's recorder fell behind.
static RENDERING: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn one_at_a_time() -> std::sync::MutexGuard<'static, ()> {
    RENDERING.lock().unwrap_or_else(|e| e.into_inner())
}

/// The executing-block marker the console's display program puts before the executing block.
const MARKER: char = '>';

/// The `screenshot PATH WxH plasma X Y W H pitch P plot X Y W H` line the window prints.
fn parse_layout(stdout: &str) -> (R, usize, R) {
    let line = stdout
        .lines()
        .find(|l| l.starts_with("screenshot "))
        .unwrap_or_else(|| panic!("no screenshot line in stdout:\n{stdout}"));
    let w: Vec<&str> = line.split_whitespace().collect();
    let num = |i: usize| -> usize { w[i].parse::<f64>().unwrap() as usize };
    let at = |k: &str| w.iter().position(|x| *x == k).unwrap();
    let p = at("plasma");
    let plasma = R {
        x: num(p + 1),
        y: num(p + 2),
        w: num(p + 3),
        h: num(p + 4),
    };
    let pitch = num(at("pitch") + 1);
    let q = at("plot");
    let plot = R {
        x: num(q + 1),
        y: num(q + 2),
        w: num(q + 3),
        h: num(q + 4),
    };
    (plasma, pitch, plot)
}

/// The executed path's colour (plot::EXECUTED = 0, 255, 140), allowing for anti-aliasing.
fn is_executed_path(p: [u8; 3]) -> bool {
    p[0] < 70 && p[1] > 200 && (100..=185).contains(&p[2])
}

#[test]
fn table_b_single_block_three_starts_shows_marker_and_executed_path() {
    let _turn = one_at_a_time();
    let Some(x) = xvfb_or_skip("window_xvfb table B") else {
        return;
    };
    let dir = scratch("tableb");
    let script = dir.join("single3.txt");
    std::fs::write(
        &script,
        "# SINGLE BLOCK, three STARTs, each waited for\nop SINGLE\nstart\nwait\nstart\nwait\nstart\nwait\nshow\n",
    )
    .unwrap();
    let shot = dir.join("shot.ppm");
    let mut cmd = window_command(&x, &[], &dir, &script, &shot);
    cmd.arg("--record").arg(dir.join("run.mcap"));
    let (code, out, err) = run_with_limit(cmd, Duration::from_secs(240));
    assert_eq!(
        code,
        Some(0),
        "novanc --window failed.\nstdout:\n{out}\nstderr:\n{err}"
    );
    // Closing the window finished the console: the recording is closed, with its summary. In
    // real time the recorder never holds the machine up, so on a loaded machine (llvmpipe
    // drawing beside the other tests on 2 cores) an event may be dropped and the summary says
    // RECORDING INCOMPLETE (docs/recording.md); the file is still closed with its footer.
    assert!(
        err.to_ascii_lowercase().contains("recording"),
        "no recording summary on stderr: {err}"
    );
    let mcap = std::fs::read(dir.join("run.mcap")).unwrap();
    assert!(mcap.starts_with(b"\x89MCAP0\r\n") && mcap.ends_with(b"\x89MCAP0\r\n"));
    let (plasma, pitch, plot) = parse_layout(&out);
    let bytes = std::fs::read(&shot).unwrap();
    let img = read_ppm(&bytes).expect("a P6 screenshot");
    assert!(plasma.x + plasma.w <= img.0 && plasma.y + plasma.h <= img.1);
    assert!(plot.x + plot.w <= img.0 && plot.y + plot.h <= img.1);

    // The plasma display: read back as text, it is the frame the console showed (`show`),
    // and it holds the executing-block marker, in orange.
    let seen = read_plasma(&img, plasma, pitch);
    let shown: Vec<&str> = out
        .lines()
        .skip_while(|l| *l != "--- display")
        .skip(1)
        .take_while(|l| *l != "---")
        .collect();
    assert!(
        !shown.is_empty(),
        "the script's `show` printed no frame:\n{out}"
    );
    let marker_line = seen
        .iter()
        .position(|l| l.contains(MARKER))
        .unwrap_or_else(|| {
            panic!(
                "no '{MARKER}' marker in the plasma display:\n{}",
                seen.join("\n")
            )
        });
    assert_eq!(
        seen.iter().map(|l| l.trim_end()).collect::<Vec<_>>(),
        shown.iter().map(|l| l.trim_end()).collect::<Vec<_>>(),
        "the window's plasma display differs from the console's frame"
    );
    assert!(shown[marker_line].contains(MARKER));

    // The backplot: the executed path's colour, which nothing else in the plot uses.
    let mut path_px = 0;
    for y in plot.y..plot.y + plot.h {
        for xx in plot.x..plot.x + plot.w {
            if is_executed_path(px(&img, xx, y)) {
                path_px += 1;
            }
        }
    }
    assert!(
        path_px >= 20,
        "the backplot shows no executed path ({path_px} pixels)"
    );
    // And nowhere outside the plot (it is the executed path's own colour).
    let outside = (0..img.1)
        .flat_map(|y| (0..plasma.x + plasma.w).map(move |xx| (xx, y)))
        .filter(|&(xx, y)| is_executed_path(px(&img, xx, y)))
        .count();
    assert_eq!(
        outside, 0,
        "the executed-path colour appears left of the plot"
    );
}

/// A punched hole in the tape strip: dark (the panel through the paper), or red for the frame
/// in error; the paper itself is light yellow.
fn is_hole(p: [u8; 3]) -> bool {
    let dark = p[0] < 80 && p[1] < 80 && p[2] < 80;
    let red = p[0] > 180 && p[1] < 90 && p[2] < 90;
    dark || red
}

#[test]
fn a_tape_read_draws_the_strip_of_frames_with_their_holes_and_the_sprocket() {
    let _turn = one_at_a_time();
    let Some(x) = xvfb_or_skip("window_xvfb tape strip") else {
        return;
    };
    let dir = scratch("tape");
    // The parity error stops the tape at frame 87, so the strip holds still for the screenshot.
    let tape = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden/frames/drill2_parity.tape");
    let image = std::fs::read(&tape).unwrap();
    let script = dir.join("tape.txt");
    std::fs::write(
        &script,
        format!(
            "op DATA\ndata READ\ntape {}\nstart\nwait\nshow\n",
            tape.display()
        ),
    )
    .unwrap();
    let shot = dir.join("shot.ppm");
    let cmd = window_command(&x, &[], &dir, &script, &shot);
    let (code, out, err) = run_with_limit(cmd, Duration::from_secs(240));
    assert_eq!(code, Some(0), "stdout:\n{out}\nstderr:\n{err}");
    let (plasma, pitch, _) = parse_layout(&out);
    let img = read_ppm(&std::fs::read(&shot).unwrap()).expect("a P6 screenshot");
    // The plasma display shows where the tape stopped, the frame in error marked `!`.
    let seen = read_plasma(&img, plasma, pitch);
    assert!(
        seen.iter().any(|l| l.contains("ISO frame 87/159 block 3")),
        "{}",
        seen.join("\n")
    );
    assert!(
        seen.iter().any(|l| l.starts_with("!●·●··•●·· ERR")),
        "{}",
        seen.join("\n")
    );
    // `tape X Y W H strip P first F count N`: frame F + i is column i, channel 8 on top, the
    // sprocket between channels 4 and 3.
    let line = out.lines().find(|l| l.starts_with("screenshot ")).unwrap();
    let w: Vec<&str> = line.split_whitespace().collect();
    let at = w.iter().position(|x| *x == "tape").unwrap();
    let n = |i: usize| -> usize { w[at + i].parse::<f64>().unwrap() as usize };
    let (x0, y0, step, first, count) = (n(1), n(2), n(6), n(8), n(10));
    assert_eq!(w[at + 5], "strip", "{line}");
    assert_eq!(
        first + count,
        87,
        "the last frame drawn is the one in error: {line}"
    );
    assert!(count >= 20, "{line}");
    let mut holes = 0;
    for i in 0..count {
        let f = image[first + i];
        let cx = x0 + i * step + step / 2;
        for ch in 1..=8u8 {
            let row = if ch >= 4 {
                8 - ch as usize
            } else {
                9 - ch as usize
            };
            let cy = y0 + row * step + step / 2;
            let want = f & (1 << (ch - 1)) != 0;
            assert_eq!(
                is_hole(px(&img, cx, cy)),
                want,
                "frame {} channel {ch} at ({cx}, {cy}): {:?}",
                first + i + 1,
                px(&img, cx, cy)
            );
            holes += usize::from(want);
        }
        let sy = y0 + 5 * step + step / 2;
        assert!(
            is_hole(px(&img, cx, sy)),
            "sprocket of frame {}",
            first + i + 1
        );
    }
    assert!(holes > count, "{holes} holes in {count} frames");
    // The frame in error is drawn red.
    let last = x0 + (count - 1) * step + step / 2;
    let bad = image[86];
    let ch = (1..=8u8).find(|c| bad & (1 << (c - 1)) != 0).unwrap();
    let row = if ch >= 4 {
        8 - ch as usize
    } else {
        9 - ch as usize
    };
    let p = px(&img, last, y0 + row * step + step / 2);
    assert!(p[0] > 180 && p[1] < 90, "the bad frame is red: {p:?}");
}

#[test]
fn without_a_display_the_window_says_so_and_suggests_the_terminal() {
    let dir = scratch("nodisplay");
    let mut cmd = Command::new(BIN);
    cmd.args(["--window", "--state"])
        .arg(dir.join("state"))
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY");
    let (code, out, err) = run_with_limit(cmd, Duration::from_secs(30));
    assert!(
        matches!(code, Some(c) if c != 0),
        "exit {code:?}; stdout {out}"
    );
    assert!(err.contains("no display"), "stderr: {err}");
    assert!(err.contains("terminal panel"), "stderr: {err}");
    assert!(!err.contains("panicked"), "stderr: {err}");
}

#[test]
fn a_display_that_does_not_answer_is_reported_not_a_panic() {
    let dir = scratch("deaddisplay");
    let mut cmd = Command::new(BIN);
    // A display number nobody serves (no socket), so the connection is refused.
    cmd.args(["--window", "--state"])
        .arg(dir.join("state"))
        .env("DISPLAY", ":4093")
        .env_remove("WAYLAND_DISPLAY");
    let (code, _out, err) = run_with_limit(cmd, Duration::from_secs(60));
    assert!(
        matches!(code, Some(c) if c != 0),
        "exit {code:?}; stderr {err}"
    );
    assert!(err.contains("cannot open"), "stderr: {err}");
    assert!(err.contains("terminal panel"), "stderr: {err}");
    assert!(!err.contains("panicked"), "stderr: {err}");
}

/// The velocity strip (issue 12): after Table B's first two blocks in SINGLE BLOCK with the
/// error-proportional interpolator, the strip in the lower left of the backplot shows the
/// rapid N2's X and Y velocities (docs/window.md, "The velocity strip").
#[test]
fn the_velocity_strip_shows_the_axes_of_the_block() {
    let _turn = one_at_a_time();
    let Some(x) = xvfb_or_skip("window_xvfb velocity strip") else {
        return;
    };
    let dir = scratch("velocity");
    let script = dir.join("two.txt");
    std::fs::write(&script, "op SINGLE\nstart\nwait\nstart\nwait\n").unwrap();
    let shot = dir.join("shot.ppm");
    let cmd = window_command(
        &x,
        &["--interpolator", "error-proportional"],
        &dir,
        &script,
        &shot,
    );
    let (code, out, err) = run_with_limit(cmd, Duration::from_secs(240));
    assert_eq!(code, Some(0), "stdout:\n{out}\nstderr:\n{err}");
    let (_, _, plot) = parse_layout(&out);
    let img = read_ppm(&std::fs::read(&shot).unwrap()).expect("a P6 screenshot");
    // The strip's rectangle, as the window reports it: its own place, under the plot.
    let line = out.lines().find(|l| l.starts_with("screenshot ")).unwrap();
    let f: Vec<usize> = line
        .split(" velocity ")
        .nth(1)
        .expect("the velocity strip's rectangle")
        .split_whitespace()
        .take(4)
        .map(|v| v.parse::<f64>().unwrap() as usize)
        .collect();
    let (x0, y0, w, h) = (f[0], f[1], f[2], f[3]);
    assert!(
        y0 >= plot.y + plot.h,
        "the strip ({y0}) lies under the backplot ({}..{}), not over it",
        plot.y,
        plot.y + plot.h
    );
    let near = |p: [u8; 3], c: [u8; 3]| (0..3).all(|i| (p[i] as i32 - c[i] as i32).abs() < 40);
    let count = |c: [u8; 3]| {
        (y0..y0 + h)
            .flat_map(|y| (x0..x0 + w).map(move |xx| (xx, y)))
            .filter(|&(xx, y)| near(px(&img, xx, y), c))
            .count()
    };
    let (xs, ys) = (count([255, 170, 60]), count([110, 170, 255]));
    assert!(
        xs >= 30 && ys >= 30,
        "X {xs} and Y {ys} pixels in the strip"
    );
}
