//! The egui window (`novanc --window`, cargo feature `window`): the same console drawn as a
//! desktop front panel — plasma display, selectors, relay panel, data keys, handwheel,
//! position readout — with a backplot. It is only a renderer and input source for the same
//! `Console` as the terminal; see docs/window.md. With `--machine` naming a lathe, the
//! lathe's console instead (`lathe`, docs/window.md "The lathe window").

mod app;
mod bench;
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

use crate::panel_model::{PanelEvent, PanelView};
use crate::settings::MachineSettings;
use crate::tooldata::Magazine;
use std::sync::atomic::{AtomicI32, Ordering};
use std::sync::Arc;
use std::time::Duration;

/// What the window needs from the console: feed it events, let it run, read its view.
pub trait Machine {
    /// One operator action.
    fn handle(&mut self, ev: PanelEvent);
    /// Lets the console look at the pulse core and the translator (once per frame).
    fn tick(&mut self);
    /// The panel to draw.
    fn view(&self) -> PanelView;
    /// The text START runs in the current operation mode (program memory, or the MDI buffer in
    /// MDI), for the backplot.
    fn program_text(&self) -> String;
    /// For a `program_text` in ISO G-code, where reading starts (the console's interpreter
    /// state, so that the plot reads G91, G92 and the tool length as START will); None for the
    /// source language.
    fn gcode_start(&self) -> Option<plot::GcodeStart>;
    /// The magazine in force (T codes and tool data, for the backplot's translation).
    fn magazine(&self) -> Magazine;
    /// The machine settings.
    fn settings(&self) -> MachineSettings;
    /// The settings START reads `program_text` with (the program's own dialect).
    fn run_settings(&self) -> MachineSettings {
        self.settings()
    }
    /// RUN = 0 and no motion.
    fn is_idle(&self) -> bool;
    /// The N number of the block executing now, if one is.
    fn block_executing(&self) -> Option<u32>;
    /// Machine time (ns), the axis counters (pulses) and whether the axes are moving (not in
    /// a hold, a dwell or an E-STOP), for the velocity strip.
    fn motion_sample(&self) -> (u64, [i64; 3], bool);
    /// Waits until every action so far has been taken up and the machine is idle.
    fn wait_idle(&mut self);
    /// Pulses output in this run, all axes together (the pulse counters).
    fn pulses(&self) -> u64;
    /// The tape reader key: the typed line names the tape to put in the reader.
    fn tape_from_entry(&mut self);
    /// The punch key: in PROGRAM READ the typed line names the image to punch program memory
    /// to (docs/tape.md).
    fn punch_from_entry(&mut self);
    /// The tape read in progress (or the one an error stopped), for the tape strip.
    fn tape(&self) -> Option<crate::console::tape::TapeView>;
    /// Ends the session: stops the machine, closes the recording; its summary, if any.
    fn finish(self: Box<Self>) -> Result<Option<String>, String>;
    /// Publishes the state to MTConnect agents (`--mtconnect`, once a frame).
    fn publish(&self, feed: &mut crate::cli::mtconnect::Feed);
}

impl Machine for crate::console::Console {
    fn handle(&mut self, ev: PanelEvent) {
        crate::console::Console::handle(self, ev)
    }
    fn tick(&mut self) {
        crate::console::Console::tick(self)
    }
    fn view(&self) -> PanelView {
        crate::console::Console::view(self)
    }
    fn program_text(&self) -> String {
        crate::console::Console::run_text(self)
    }
    fn gcode_start(&self) -> Option<plot::GcodeStart> {
        crate::console::Console::run_text_is_gcode(self).then(|| plot::GcodeStart::State {
            state: Box::new(self.interp_state().clone()),
            mdi: self.run_text_is_mdi(),
            subs: Some(Arc::new(self.subroutines())),
        })
    }
    fn magazine(&self) -> Magazine {
        crate::console::Console::magazine(self)
    }
    fn settings(&self) -> MachineSettings {
        crate::console::Console::settings(self).clone()
    }
    fn run_settings(&self) -> MachineSettings {
        self.run_settings_for(!self.run_text_is_mdi())
    }
    fn is_idle(&self) -> bool {
        crate::console::Console::is_idle(self)
    }
    fn block_executing(&self) -> Option<u32> {
        let st = self.status();
        st.executing
            .as_ref()
            .filter(|_| st.in_block)
            .and_then(|e| e.block())
            .map(|b| b.seq)
    }
    fn motion_sample(&self) -> (u64, [i64; 3], bool) {
        let st = self.status();
        (st.machine_ns, st.pos.xyz(), st.moving && !st.estop)
    }
    fn wait_idle(&mut self) {
        crate::console::Console::wait_idle(self)
    }
    fn pulses(&self) -> u64 {
        self.status().pulses.iter().sum()
    }
    fn tape_from_entry(&mut self) {
        crate::console::Console::tape_from_entry(self)
    }
    fn punch_from_entry(&mut self) {
        crate::console::Console::punch_from_entry(self)
    }
    fn tape(&self) -> Option<crate::console::tape::TapeView> {
        crate::console::Console::tape_view(self)
    }
    fn finish(self: Box<Self>) -> Result<Option<String>, String> {
        crate::console::Console::finish(*self)
    }
    fn publish(&self, feed: &mut crate::cli::mtconnect::Feed) {
        feed.publish(self)
    }
}

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
    pub mtc: crate::cli::mtconnect::MtcOpts,
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

/// Both windows before they open: with no display named, says why the window cannot open
/// and returns exit code 1; else the text of the `--script` file, if any (a file that cannot
/// be read is said, exit 1).
fn before_opening(opts: &WindowOptions) -> Result<Option<(String, String)>, i32> {
    if !display_named() {
        eprintln!(
            "novanc: the window cannot open: no display (neither DISPLAY nor WAYLAND_DISPLAY is set).\n\
             novanc: {NO_WINDOW_HINT}"
        );
        return Err(1);
    }
    let Some(path) = &opts.script else {
        return Ok(None);
    };
    match std::fs::read_to_string(path) {
        Ok(t) => Ok(Some((path.clone(), t))),
        Err(e) => {
            eprintln!("novanc: cannot read script {path}: {e}");
            Err(1)
        }
    }
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

/// Opens the console configured by `cfg` in a window (`novanc --window`); returns the exit
/// code.
pub fn run(cfg: crate::console::ConsoleConfig, opts: WindowOptions) -> i32 {
    let script = match before_opening(&opts) {
        Ok(s) => s,
        Err(code) => return code,
    };
    let mut drive = app::Drive {
        wait_limit: Duration::from_secs(300),
        ..app::Drive::default()
    };
    if let Some((path, text)) = script {
        match PanelEvent::parse_script(&text) {
            Ok(evs) => drive.script = evs.into(),
            Err(e) => {
                eprintln!("novanc: {path}:{}: {}", e.line, e.message);
                return 1;
            }
        }
    }
    drive.screenshot = opts.screenshot.as_ref().map(Into::into);
    drive.bench_frames = opts.bench_frames;
    // SIGINT, SIGTERM and SIGHUP close the window (docs/window.md, "Closing").
    crate::cli::signals::install();
    let (machine, feed) = match open_console(cfg, &opts.mtc) {
        Ok(m) => m,
        Err(e) => {
            eprintln!("novanc: {e}");
            return 1;
        }
    };
    let size = opts.size.unwrap_or((1400.0, 860.0));
    let code = open_window("novanc — NC panel", size, move |exit| {
        Box::new(app::App::new(machine, drive, exit).with_feed(feed))
    });
    crate::cli::signals::exit_code(code)
}

/// Opens an eframe window titled `title`, `size` points, with the app `make` builds (given
/// the cell its exit code goes in); runs it until it closes; returns the exit code. A window
/// that cannot open says why and suggests the terminal.
fn open_window(
    title: &str,
    size: (f32, f32),
    make: impl FnOnce(Arc<AtomicI32>) -> Box<dyn eframe::App> + 'static,
) -> i32 {
    let native = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title(title)
            .with_inner_size([size.0, size.1]),
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
                Ok(make(exit2))
            }),
        )
    }));
    match result {
        Ok(Ok(())) => exit.load(Ordering::SeqCst),
        Ok(Err(e)) => {
            eprintln!("novanc: the window cannot open: {e}\nnovanc: {NO_WINDOW_HINT}");
            1
        }
        Err(_) => {
            eprintln!("novanc: the window failed while opening.\nnovanc: {NO_WINDOW_HINT}");
            1
        }
    }
}

/// Opens the console the window drives.
/// Opens the console, and the MTConnect adapter if `mtc` asks (its state published once).
fn open_console(
    cfg: crate::console::ConsoleConfig,
    mtc: &crate::cli::mtconnect::MtcOpts,
) -> Result<(Box<dyn Machine>, Option<crate::cli::mtconnect::Feed>), String> {
    let (console, warnings) = crate::console::Console::open(cfg)?;
    for w in warnings {
        eprintln!("novanc: {w}");
    }
    let mut feed = match crate::cli::mtconnect::Feed::start(mtc, "novanc", console.core()) {
        Ok(f) => f,
        Err(e) => {
            let _ = console.finish();
            return Err(e);
        }
    };
    if let Some(f) = feed.as_mut() {
        f.publish(&console);
    }
    Ok((Box::new(console), feed))
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
