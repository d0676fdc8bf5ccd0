//! The egui window (`novanc --window`, cargo feature `window`): the same console drawn as a
//! desktop front panel — plasma display, selectors, relay panel, data keys, handwheel,
//! position readout — with a backplot. It is only a renderer and input source for the same
//! `Console` as the terminal; see docs/window.md. With `--machine` naming a lathe, the
//! lathe's console instead (`lathe`, docs/window.md "The lathe window"). One application
//! (`app`) for both: what differs is each machine's `app::Front` (`centre`, `lathe`).

pub(crate) mod app;
mod bench;
mod centre;
mod controls;
pub mod font;
pub mod image;
mod keys;
pub mod lathe;
mod pathdraw;
mod plasma;
pub mod plot;
mod shot;
mod tapestrip;
mod velocity;

use crate::console::Panel;
use crate::panel_model::PanelEvent;
use app::{App, Drive, Front};
use std::sync::atomic::{AtomicI32, Ordering};
use std::sync::Arc;
use std::time::Duration;

/// The window's `--help`.
pub const HELP: &str = "\
usage: novanc --window [console options] [--script FILE] [--screenshot OUT.ppm|OUT.png]
                       [--bench-frames N] [--size WxH]
       novanc --window --machine citizen [--state DIR] [--record OUT.mcap] [--script FILE]
                       [--screenshot OUT] [--size WxH]

The console in an egui window (see docs/window.md); with --machine naming a lathe, the lathe's
console: every channel side by side with its backplot (\"The lathe window\").
  --script FILE       play a panel script (docs/cli.md) into the console, then keep running
                      (a lathe script, docs/lathe.md, runs in virtual time)
  --screenshot OUT    after the script (and the benchmark), write a screenshot (PPM, or PNG
                      if OUT ends in .png)
                      and close; prints the plasma and backplot rectangles
  --bench-frames N    after the script, measure N frames, print frame time and pulse rate, close
  --size WxH          window size in points (default 1400x860)
Other options go to the console (e.g. --state DIR, --rows N, --cols N, --machine M, and
--mtconnect ADDR:PORT: the window streams to MTConnect agents once a frame, docs/mtconnect.md).
";

/// The window's own options, split from the console's.
#[derive(Debug, Default, PartialEq)]
pub struct WindowOptions {
    /// `--script FILE`.
    pub script: Option<String>,
    /// `--screenshot OUT`.
    pub screenshot: Option<String>,
    /// `--bench-frames N`.
    pub bench_frames: Option<u64>,
    /// `--size WxH`.
    pub size: Option<(f32, f32)>,
    /// `--help`.
    pub help: bool,
    /// Everything else, for the console (without `--window`).
    pub console_args: Vec<String>,
    /// `--mtconnect ADDR:PORT`, taken out of the console's arguments by the command line:
    /// the window streams to MTConnect agents once a frame (docs/mtconnect.md).
    pub mtc: crate::mtconnect::feed::MtcOpts,
}

/// Splits `argv` into the window's options and the console's.
pub fn parse_options(argv: &[String]) -> Result<WindowOptions, String> {
    let mut o = WindowOptions::default();
    let mut it = argv.iter();
    while let Some(a) = it.next() {
        let (name, inline) = match a.split_once('=') {
            Some((n, v)) if n.starts_with("--") => (n, Some(v.to_string())),
            _ => (a.as_str(), None),
        };
        let mut value = |inline: Option<String>| -> Result<String, String> {
            inline
                .or_else(|| it.next().cloned())
                .ok_or_else(|| format!("option '{name}' needs a value"))
        };
        match name {
            "--window" => {}
            "-h" | "--help" => o.help = true,
            "--script" => o.script = Some(value(inline)?),
            "--screenshot" => o.screenshot = Some(value(inline)?),
            "--bench-frames" => {
                let v = value(inline)?;
                let n: u64 = v
                    .parse()
                    .map_err(|_| format!("--bench-frames '{v}' is not a whole number"))?;
                if n == 0 {
                    return Err("--bench-frames needs at least 1 frame".into());
                }
                o.bench_frames = Some(n);
            }
            "--size" => {
                let v = value(inline)?;
                let bad = || format!("--size '{v}' is not WIDTHxHEIGHT (e.g. 1400x860)");
                let (w, h) = v.split_once(['x', 'X']).ok_or_else(bad)?;
                let w: f32 = w.parse().map_err(|_| bad())?;
                let h: f32 = h.parse().map_err(|_| bad())?;
                if !(320.0..=8192.0).contains(&w) || !(240.0..=8192.0).contains(&h) {
                    return Err(bad());
                }
                o.size = Some((w, h));
            }
            _ => o.console_args.push(a.clone()),
        }
    }
    Ok(o)
}

/// Prints a line on stdout (the script's `show`, the screenshot's layout, the benchmark's
/// figures). A stdout nobody reads any more (a closed pipe) is no reason to panic.
fn say(text: &str) {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    let _ = writeln!(out, "{text}");
    let _ = out.flush();
}

/// Whether a display server is named in the environment (X11 `DISPLAY` or `WAYLAND_DISPLAY`).
pub fn display_named() -> bool {
    ["DISPLAY", "WAYLAND_DISPLAY"]
        .iter()
        .any(|v| std::env::var_os(v).is_some_and(|s| !s.is_empty()))
}

const NO_WINDOW_HINT: &str =
    "run the terminal panel instead: novanc (without --window), or a headless panel session: novanc script FILE";

/// Before the window opens: with no display named, says why the window cannot open and
/// returns exit code 1; else the script (`--script`), if any, read with the machine's grammar
/// (`Panel::read_script`; a file that cannot be read, or a bad line, is said with its place,
/// exit 1).
fn before_opening(
    opts: &WindowOptions,
    lathe: Option<&crate::lathe::desc::LatheDesc>,
) -> Result<Drive<PanelEvent>, i32> {
    if !display_named() {
        eprintln!(
            "novanc: the window cannot open: no display (neither DISPLAY nor WAYLAND_DISPLAY is set).\n\
             novanc: {NO_WINDOW_HINT}"
        );
        return Err(1);
    }
    let mut drive = Drive {
        screenshot: opts.screenshot.as_ref().map(Into::into),
        bench_frames: opts.bench_frames,
        ..Drive::default()
    };
    let Some(path) = &opts.script else {
        return Ok(drive);
    };
    let text = std::fs::read_to_string(path).map_err(|e| {
        eprintln!("novanc: cannot read script {path}: {e}");
        1
    })?;
    let events = Panel::read_script(lathe, &text).map_err(|(line, e)| {
        eprintln!("novanc: {path}:{line}: {e}");
        1
    })?;
    drive.script = app::script_steps(events).into();
    drive.scripted = true;
    Ok(drive)
}

/// Schedules both windows' next frame: at once while a script, a screenshot or the benchmark
/// runs (`busy`: frames back to back); about 60 frames a second while the machine moves, no
/// more (the pulse core's CPU); idle, still a look at the console now and then (messages,
/// alarms).
fn schedule_repaint(ctx: &egui::Context, busy: bool, moving: bool) {
    if busy {
        ctx.request_repaint();
    } else if moving {
        ctx.request_repaint_after(Duration::from_millis(16));
    } else {
        ctx.request_repaint_after(Duration::from_millis(100));
    }
}

/// Opens the console of the machine (`lathe`: a lathe's description; `None`: the machining
/// centre of `cfg`) in a window (`novanc --window`), as the terminal opens it (`Panel::open`,
/// `Panel::start_feed`); returns the exit code when the window closes. A lathe's script plays
/// in virtual time; without one, and on the centre, the machine keeps the wall clock in its
/// own thread. A window that cannot open says why and suggests the terminal.
pub fn run(
    lathe: Option<crate::lathe::desc::LatheDesc>,
    mut cfg: crate::console::ConsoleConfig,
    opts: WindowOptions,
) -> i32 {
    let drive = match before_opening(&opts, lathe.as_ref()) {
        Ok(d) => d,
        Err(code) => return code,
    };
    if lathe.is_some() && drive.scripted {
        cfg.clock = crate::pulse_core::ClockMode::Virtual;
    }
    // SIGINT, SIGTERM and SIGHUP close the window (docs/window.md, "Closing").
    crate::signals::install();
    let (mut panel, warnings) = match Panel::open(lathe, cfg) {
        Ok(x) => x,
        Err(e) => {
            eprintln!("novanc: {e}");
            return 1;
        }
    };
    for w in warnings {
        eprintln!("novanc: warning at start: {w}");
    }
    let feed = match panel.start_feed(&opts.mtc, "novanc", drive.scripted) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("novanc: {e}");
            panel.close_saying(None);
            return 1;
        }
    };
    match panel {
        Panel::Centre(c) => open(
            &opts,
            drive,
            centre::Centre::new(*c),
            feed,
            "novanc — NC panel",
        ),
        Panel::Lathe(c) => {
            let title = format!("novanc — {} lathe", c.desc().name);
            open(&opts, drive, lathe::Lathe::new(*c), feed, &title)
        }
    }
}

/// Opens the window on `front`, played by `drive`; returns when it closes, with its exit code.
fn open<F: Front<Ev = PanelEvent>>(
    opts: &WindowOptions,
    drive: Drive<PanelEvent>,
    front: F,
    feed: Option<crate::mtconnect::feed::Feed>,
    title: &str,
) -> i32 {
    let (w, h) = opts.size.unwrap_or((1400.0, 860.0));
    let native = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title(title)
            .with_inner_size([w, h]),
        ..eframe::NativeOptions::default()
    };
    let exit = Arc::new(AtomicI32::new(0));
    let exit2 = exit.clone();
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        eframe::run_native(
            "novanc",
            native,
            Box::new(move |cc| {
                cc.egui_ctx.set_visuals(egui::Visuals::dark());
                Ok(Box::new(App::new(front, drive, exit2, feed)))
            }),
        )
    }));
    let code = match result {
        Ok(Ok(())) => exit.load(Ordering::SeqCst),
        Ok(Err(e)) => {
            eprintln!("novanc: the window cannot open: {e}\nnovanc: {NO_WINDOW_HINT}");
            1
        }
        Err(_) => {
            eprintln!("novanc: the window failed while opening.\nnovanc: {NO_WINDOW_HINT}");
            1
        }
    };
    crate::signals::exit_code(code)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(s: &[&str]) -> Vec<String> {
        s.iter().map(|x| x.to_string()).collect()
    }

    #[test]
    fn window_options_are_split_from_the_consoles() {
        let o = parse_options(&v(&[
            "--window",
            "--state",
            "d",
            "--script=s.txt",
            "--screenshot",
            "o.ppm",
            "--bench-frames",
            "10",
            "--size",
            "800x600",
        ]))
        .unwrap();
        assert_eq!(o.script.as_deref(), Some("s.txt"));
        assert_eq!(o.screenshot.as_deref(), Some("o.ppm"));
        assert_eq!(o.bench_frames, Some(10));
        assert_eq!(o.size, Some((800.0, 600.0)));
        assert_eq!(o.console_args, v(&["--state", "d"]));
        assert!(parse_options(&v(&["--bench-frames", "x"])).is_err());
        assert!(parse_options(&v(&["--bench-frames", "0"])).is_err());
        assert!(parse_options(&v(&["--size", "10x10"])).is_err());
        assert!(parse_options(&v(&["--script"]))
            .unwrap_err()
            .contains("needs a value"));
    }
}
