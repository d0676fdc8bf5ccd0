//! The lathe window under Xvfb (issue 13, docs/window.md "The lathe window"):
//! `novanc --window --machine citizen` plays a panel script that starts the cycle and lets 27 s
//! of machine time pass (virtual time), then takes a PNG screenshot. The pixels must show, in
//! each of the three channels' backplots, the path cut on the work in its spindle (drawn in
//! that work's colour), and the plasma display read back dot by dot must be the selected
//! channel's display as the script's `show` printed it.
//!
//! Needs Xvfb, as tests/window_xvfb.rs: without it the test fails when CI=true and is skipped
//! loudly otherwise.
#![cfg(feature = "window")]

#[path = "common/xvfb.rs"]
mod xvfb;

use novanc::window::image::read_png;
use novanc::window::lathe::plot::{ARC, FEED, WORK_COLOURS};
use std::process::Command;
use std::time::Duration;
use xvfb::{px, read_plasma, run_with_limit, scratch, window_command, xvfb_or_skip, R};

const BIN: &str = env!("CARGO_BIN_EXE_novanc");

/// The `screenshot PATH WxH plasma X Y W H pitch P plot1 X Y W H detail1 X Y W H ...` line.
struct Shot {
    size: (usize, usize),
    plasma: R,
    pitch: usize,
    plots: Vec<R>,
    details: Vec<R>,
    /// The operator's panel along the bottom.
    panel: R,
}

fn parse_layout(stdout: &str) -> Shot {
    let line = stdout
        .lines()
        .find(|l| l.starts_with("screenshot "))
        .unwrap_or_else(|| panic!("no screenshot line in stdout:\n{stdout}"));
    let w: Vec<&str> = line.split_whitespace().collect();
    let num = |i: usize| -> usize { w[i].parse::<f64>().unwrap() as usize };
    let at = |k: &str| {
        w.iter()
            .position(|x| *x == k)
            .unwrap_or_else(|| panic!("no '{k}' in {line}"))
    };
    let rect = |k: &str| {
        let i = at(k);
        R {
            x: num(i + 1),
            y: num(i + 2),
            w: num(i + 3),
            h: num(i + 4),
        }
    };
    let (sw, sh) = w[2].split_once('x').unwrap();
    Shot {
        size: (sw.parse().unwrap(), sh.parse().unwrap()),
        plasma: rect("plasma"),
        pitch: num(at("pitch") + 1),
        plots: (1..=3).map(|i| rect(&format!("plot{i}"))).collect(),
        details: (1..=3).map(|i| rect(&format!("detail{i}"))).collect(),
        panel: rect("panel"),
    }
}

/// A pixel of the path cut on a work: one of the works' colours (the work in the spindle is
/// drawn at full colour, two pixels wide).
fn is_work_path(p: [u8; 3]) -> bool {
    WORK_COLOURS.iter().any(|c| {
        let c = [c.r(), c.g(), c.b()];
        (0..3).all(|i| (p[i] as i32 - c[i] as i32).abs() <= 12)
    })
}

fn count(img: &Image, r: R, f: impl Fn([u8; 3]) -> bool) -> usize {
    (r.y..r.y + r.h)
        .flat_map(|y| (r.x..r.x + r.w).map(move |x| (x, y)))
        .filter(|&(x, y)| f(px(img, x, y)))
        .count()
}

/// The Citizen's window on Xvfb `x` playing `script` in a fresh folder `name`, recorded, its
/// screenshot taken: stdout, the layout line and the image. Closing the window closed the
/// recording.
fn citizen_shot(x: &xvfb::Xvfb, name: &str, script: &str) -> (String, Shot, Image) {
    let dir = scratch(name);
    let path = dir.join("script.txt");
    std::fs::write(&path, script).unwrap();
    let shot = dir.join("shot.png");
    let mut cmd = window_command(x, &["--machine", "citizen"], &dir, &path, &shot);
    cmd.arg("--record").arg(dir.join("run.mcap"));
    let (code, out, err) = run_with_limit(cmd, Duration::from_secs(240));
    assert_eq!(code, Some(0), "stdout:\n{out}\nstderr:\n{err}");
    assert!(err.contains("recording"), "no recording summary: {err}");
    let mcap = std::fs::read(dir.join("run.mcap")).unwrap();
    assert!(mcap.starts_with(b"\x89MCAP0\r\n") && mcap.ends_with(b"\x89MCAP0\r\n"));
    let s = parse_layout(&out);
    let img = read_png(&std::fs::read(&shot).unwrap()).expect("a PNG as the window writes it");
    (out, s, img)
}

/// A screenshot: width, height, RGB bytes.
type Image = (usize, usize, Vec<u8>);

#[test]
fn the_lathe_window_shows_every_channel_with_its_backplot() {
    let Some(x) = xvfb_or_skip("lathe_window_xvfb") else {
        return;
    };
    let (out, s, img) = citizen_shot(
        &x,
        "lathe",
        "# the cycle, 27 s of machine time: every channel has a work and cuts it\nstart\nwait ms 27000\nshow\n",
    );
    assert_eq!((img.0, img.1), s.size, "the PNG's size is the one printed");
    assert_eq!(s.size, (1400, 860));
    // Every control of the operator's panel is inside the default window, none behind its
    // right edge (stop 41: the Z+ jog button and the x1000 increment were cut off there).
    assert!(
        s.panel.x + s.panel.w <= s.size.0 && s.panel.w > 1000,
        "the panel runs past the window: {:?}",
        s.panel
    );

    // The three channels side by side: their boxes left to right, apart, inside the image.
    for w in s.plots.windows(2) {
        assert!(w[0].x + w[0].w < w[1].x, "plots overlap: {:?}", s.plots);
    }
    for r in s.plots.iter().chain(&s.details).chain([&s.plasma]) {
        assert!(r.x + r.w <= img.0 && r.y + r.h <= img.1, "{r:?} outside");
        assert!(r.w > 100 && r.h > 50, "{r:?} too small");
    }
    // Each backplot holds its work's path; the travel box (Z 120 mm by X 37 mm) at equal scale.
    for (i, (p, d)) in s.plots.iter().zip(&s.details).enumerate() {
        let ratio = p.w as f64 / p.h as f64;
        assert!(
            (ratio - 120.0 / 37.0).abs() < 0.1,
            "CH{} travel box {p:?}",
            i + 1
        );
        let (np, nd) = (count(&img, *p, is_work_path), count(&img, *d, is_work_path));
        assert!(
            np >= 20 && nd >= 40,
            "CH{}: {np} path pixels in the travel box, {nd} in the detail",
            i + 1
        );
    }
    // Nothing else in the window is drawn in the works' colours.
    let outside: usize = (0..img.1)
        .flat_map(|y| (0..img.0).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let inside = |r: &R| x >= r.x && x < r.x + r.w && y >= r.y && y < r.y + r.h;
            !s.plots.iter().chain(&s.details).any(inside)
        })
        .filter(|&(x, y)| is_work_path(px(&img, x, y)))
        .count();
    // The readouts name each channel's work in its colour (a few hundred pixels of text).
    assert!(
        outside < 2_000,
        "{outside} pixels of path colour outside the plots"
    );

    // The plasma display: the selected channel's display, as `show` printed it (the frame's
    // last lines; the title and summary lines come before).
    let seen = read_plasma(&img, s.plasma, s.pitch);
    let shown: Vec<&str> = out
        .lines()
        .skip_while(|l| *l != "--- display")
        .skip(1)
        .take_while(|l| *l != "---")
        .collect();
    assert!(shown.len() > seen.len(), "show printed:\n{out}");
    let display = &shown[shown.len() - seen.len()..];
    assert_eq!(
        seen.iter().map(|l| l.trim_end()).collect::<Vec<_>>(),
        display.iter().map(|l| l.trim_end()).collect::<Vec<_>>(),
        "the window's plasma display differs from the console's"
    );
    assert!(display[0].starts_with("CH1 SYSTEM-1"), "{display:?}");
    // 27 s in (the chucks wait for their spindles to stop since issue 22), every channel runs with a work (the summary lines, after the title).
    for (i, l) in shown[1..4].iter().enumerate() {
        assert!(l.contains(&format!("CH{} RUN", i + 1)), "{l}");
    }
}

/// Before START each channel's backplot shows its program as START would read it (stop 51;
/// before, a lathe's plots stayed empty until the machine moved, where the centre's shows its
/// programmed path): feed moves and arcs in the centre's backplot colours, in the travel box
/// and in the detail, which shows the program's cuts.
#[test]
fn before_start_the_lathe_window_shows_each_channels_programmed_path() {
    let Some(x) = xvfb_or_skip("lathe_window_xvfb") else {
        return;
    };
    let (_, s, img) = citizen_shot(
        &x,
        "lathe_programmed",
        "# nothing started: the programs as START would read them\nshow\n",
    );
    // One-point lines, antialiased on the dark plot: pixels of the path's blue and violet
    // hue (FEED, ARC), which nothing else of a plot has before START.
    assert!([FEED, ARC]
        .iter()
        .all(|c| c.b() > c.r() + 60 && c.b() > c.g() + 30));
    let programmed = |p: [u8; 3]| {
        let [r, g, b] = p.map(i32::from);
        b >= 90 && b - r >= 50 && b - g >= 30
    };
    for (i, (p, d)) in s.plots.iter().zip(&s.details).enumerate() {
        let (np, nd) = (count(&img, *p, programmed), count(&img, *d, programmed));
        assert!(
            np >= 10 && nd >= 100,
            "CH{}: {np} programmed-path pixels in the travel box, {nd} in the detail",
            i + 1
        );
        // Nothing is cut yet: no work's colour in the plots.
        assert_eq!(count(&img, *p, is_work_path), 0, "CH{}", i + 1);
    }
}

/// `--bench-frames` on the lathe window (stop 51; refused before): after the script's last
/// wait, N frames measured and printed as the centre's, the kernel's pulses counted over every
/// channel, the machine keeping the window's wall clock.
#[test]
fn the_lathe_window_measures_its_frames_after_the_script() {
    let Some(x) = xvfb_or_skip("lathe_window_xvfb") else {
        return;
    };
    let dir = scratch("lathe_bench");
    let script = dir.join("b.txt");
    std::fs::write(&script, "start\nwait ms 3000\n").unwrap();
    let mut cmd = Command::new(BIN);
    cmd.args(["--window", "--machine", "citizen", "--state"])
        .arg(dir.join("state"))
        .arg("--script")
        .arg(&script)
        .args(["--bench-frames", "30"]);
    xvfb::on_xvfb(&mut cmd, &x);
    let (code, out, err) = run_with_limit(cmd, Duration::from_secs(240));
    assert_eq!(code, Some(0), "stdout:\n{out}\nstderr:\n{err}");
    let line = out
        .lines()
        .find(|l| l.starts_with("bench-frames 30:"))
        .unwrap_or_else(|| panic!("no figures: {out}"));
    let field = |k: &str| -> f64 {
        let w: Vec<&str> = line.split_whitespace().collect();
        let i = w
            .iter()
            .position(|x| *x == k)
            .unwrap_or_else(|| panic!("{k}: {line}"));
        w[i + 1].trim_start_matches('(').parse().unwrap()
    };
    // The cycle runs: the three channels' axes move during the frames; the 3 s of the
    // script's wait are not counted in them (a wall of a few seconds at most).
    assert!(field("pulses") > 0.0, "{line}");
    let (machine, wall) = (field("machine"), field("wall"));
    assert!(machine > 0.0 && machine <= wall * 1.5 + 0.2, "{line}");
}

#[test]
fn without_a_display_the_lathe_window_says_so_and_suggests_the_terminal() {
    let dir = scratch("lathe_nodisplay");
    let mut cmd = Command::new(BIN);
    cmd.args(["--window", "--machine", "citizen", "--state"])
        .arg(dir.join("state"))
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY");
    let (code, _out, err) = run_with_limit(cmd, Duration::from_secs(30));
    assert!(matches!(code, Some(c) if c != 0), "exit {code:?}; {err}");
    assert!(err.contains("no display"), "stderr: {err}");
    assert!(err.contains("terminal panel"), "stderr: {err}");
    assert!(!err.contains("panicked"), "stderr: {err}");
}

#[test]
fn a_bad_lathe_script_is_refused_before_anything_opens() {
    let dir = scratch("lathe_badscript");
    let script = dir.join("bad.txt");
    std::fs::write(&script, "start\nfault 4 tool breakage\n").unwrap();
    let mut cmd = Command::new(BIN);
    // A display nobody serves: the script is read, and refused, before the window is tried.
    cmd.args(["--window", "--machine", "citizen", "--state"])
        .arg(dir.join("state"))
        .arg("--script")
        .arg(&script)
        .env("DISPLAY", ":4093")
        .env_remove("WAYLAND_DISPLAY");
    let (code, _out, err) = run_with_limit(cmd, Duration::from_secs(30));
    assert_eq!(code, Some(1), "stderr: {err}");
    assert!(err.contains("bad.txt:2:"), "stderr: {err}");
    assert!(err.contains("not a channel"), "stderr: {err}");
    assert!(!err.contains("cannot open"), "stderr: {err}");
    // Nothing was made: not even the state directory.
    assert!(!dir.join("state").exists());
}

/// A lathe window made small (1000 × 700, then one of 400 × 300) still draws every frame: the
/// readouts wrap in their columns, and the backplots take what room is left. Before stop 39 a
/// channel column shorter than 150 points panicked the window (an overview height clamped
/// between 60 points and less than 60).
#[test]
fn a_small_lathe_window_draws_and_says_where_everything_is() {
    let Some(x) = xvfb_or_skip("lathe_window_xvfb") else {
        return;
    };
    let dir = scratch("lathe_small");
    let script = dir.join("s.txt");
    std::fs::write(
        &script,
        "start\nwait ms 8000\nfault 2 chip jam\nwait ms 200\nkey Ctrl+E\nshow\n",
    )
    .unwrap();
    for (w, h) in [(1000, 700), (400, 300)] {
        let shot = dir.join(format!("shot{w}.png"));
        let mut cmd = Command::new(BIN);
        cmd.args(["--window", "--machine", "citizen", "--state"])
            .arg(dir.join(format!("state{w}")))
            .arg("--script")
            .arg(&script)
            .arg("--screenshot")
            .arg(&shot)
            .args(["--size", &format!("{w}x{h}")]);
        xvfb::on_xvfb(&mut cmd, &x);
        let (code, out, err) = run_with_limit(cmd, Duration::from_secs(240));
        assert_eq!(code, Some(0), "{w}x{h}: stdout:\n{out}\nstderr:\n{err}");
        let s = parse_layout(&out);
        assert_eq!(s.size, (w, h));
        // The MSG page is up, the fault in it.
        assert!(out.contains("ALARM CH2 FAULT: chip jam"), "{out}");
        for p in s.plots.windows(2) {
            assert!(p[0].x + p[0].w < p[1].x, "plots overlap: {:?}", s.plots);
        }
    }
}
