//! The lathe console in the egui window (`novanc --window --machine citizen`, docs/window.md
//! "The lathe window"): every channel side by side with its readout and a backplot of its tool
//! tip in the Z–X plane, the selected channel's plasma display and the operator's panel. Like
//! the mill's window it is only a renderer and an input source for the same `LatheConsole` as
//! the terminal: each frame it ticks the console (by wall time, or by a script's waits in
//! virtual time), draws `LatheView`, and hands keys and clicks back as `LatheConsole::press` /
//! `LatheConsole::event`.

mod panel;
pub mod plot;

use super::controls::{self, HandState};
use super::plasma::Plasma;
use super::shot::{rect_px, Shot};
use super::WindowOptions;
use crate::console::ConsoleConfig;
use crate::lathe::console::events::{parse_script, ScriptStep};
use crate::lathe::console::{LatheConsole, LatheView};
use crate::lathe::desc::LatheDesc;
use egui::{Color32, Rect};
use panel::Act;
use plot::Trail;
use std::collections::VecDeque;
use std::path::PathBuf;
use std::sync::atomic::{AtomicI32, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Machine time of one step of the clock, ns: the backplot samples every tip after each.
pub const STEP_NS: u64 = 2_000_000;
/// The most wall time one frame makes up in real time, ns (a window held up does not make the
/// machine jump).
const MAX_FRAME_NS: u64 = 250_000_000;
/// Wall time a frame may spend on a script's waits before it draws.
const SCRIPT_BUDGET: Duration = Duration::from_millis(25);
/// The longest a script wait may take in wall time before the run is abandoned.
const WAIT_LIMIT: Duration = Duration::from_secs(300);

/// Opens the lathe `desc`'s console, configured by `cfg` (state directory, display size,
/// recording), in a window; returns the exit code.
pub fn run(desc: LatheDesc, cfg: ConsoleConfig, opts: WindowOptions) -> i32 {
    if opts.bench_frames.is_some() {
        eprintln!("novanc: --bench-frames: the lathe window has no benchmark (docs/window.md)");
        return 2;
    }
    let script = match super::before_opening(&opts) {
        Err(code) => return code,
        Ok(None) => None,
        Ok(Some((path, text))) => match parse_script(&text, desc.channels.len()) {
            Ok(s) => Some(s),
            Err((line, e)) => {
                eprintln!("novanc: {path}:{line}: {e}");
                return 1;
            }
        },
    };
    let (mut console, warnings) = match LatheConsole::open_config(desc, &cfg) {
        Ok(x) => x,
        Err(e) => {
            eprintln!("novanc: {e}");
            return 1;
        }
    };
    // Without a script the kernel keeps the wall clock in its own thread; a script plays in
    // virtual time.
    if script.is_none() {
        console.set_clock(crate::pulse_core::ClockMode::RealTime);
    }
    for w in warnings {
        eprintln!("novanc: warning at start: {w}");
    }
    let virt = script.is_some();
    let mut feed = match crate::cli::mtconnect::Feed::start_on(
        &opts.mtc,
        "novanc",
        virt,
        console.machine_ns(),
    ) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("novanc: {e}");
            let _ = console.finish(None);
            return 1;
        }
    };
    if let Some(f) = feed.as_mut() {
        f.publish_lathe(&console);
    }
    // A stop signal closes the window as closing it does, the recording marked interrupted.
    crate::cli::signals::install();
    let title = format!("novanc — {} lathe", console.desc().name);
    let size = opts.size.unwrap_or((1400.0, 860.0));
    let shot = opts.screenshot.map(PathBuf::from);
    let code = super::open_window(&title, size, move |exit| {
        Box::new(LatheApp::new(console, script, shot, exit).with_feed(feed))
    });
    crate::cli::signals::exit_code(code)
}

/// What a script wait waits for.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Wait {
    /// `wait`: every channel at rest.
    Rest,
    /// `wait ms T`: machine time at or past this, ns.
    Until(u64),
}

/// The rectangles a test needs to read a screenshot.
#[derive(Clone, Debug, Default)]
struct Layout {
    plasma: Option<Rect>,
    pitch: usize,
    /// Each channel's travel box and detail box.
    plots: Vec<(Rect, Rect)>,
}

/// The lathe window's application.
pub struct LatheApp {
    console: Option<LatheConsole>,
    view: LatheView,
    trails: Vec<Trail>,
    plasma: Plasma,
    hand: HandState,
    /// The script's steps still to play; `None` without `--script`.
    script: Option<VecDeque<ScriptStep>>,
    waiting: Option<(Instant, Wait)>,
    screenshot: Option<PathBuf>,
    shot: Shot,
    last: Instant,
    layout: Layout,
    exit: Arc<AtomicI32>,
    /// The stop signal that closed the window, as the recording says it.
    interrupted: Option<String>,
    /// The MTConnect adapter (`--mtconnect`): the state is published once a frame.
    feed: Option<crate::cli::mtconnect::Feed>,
}

impl LatheApp {
    /// The application around an opened console, with the script to play (virtual time) and
    /// the screenshot to take, if any. `exit` receives the exit code.
    pub fn new(
        console: LatheConsole,
        script: Option<Vec<ScriptStep>>,
        screenshot: Option<PathBuf>,
        exit: Arc<AtomicI32>,
    ) -> LatheApp {
        let step = console.desc().pulses(plot::TRAIL_STEP_MM).max(1);
        let trails = (0..console.desc().channels.len())
            .map(|_| Trail::new(step, plot::TRAIL_POINTS))
            .collect();
        let mut app = LatheApp {
            view: console.view(),
            console: None,
            trails,
            plasma: Plasma::new(),
            hand: HandState::default(),
            script: script.map(Into::into),
            waiting: None,
            screenshot,
            shot: Shot::Idle,
            last: Instant::now(),
            layout: Layout::default(),
            exit,
            interrupted: None,
            feed: None,
        };
        app.sample(&console);
        app.console = Some(console);
        app
    }

    /// Streams to MTConnect agents through `feed` (once a frame, after the machine's time).
    pub fn with_feed(mut self, feed: Option<crate::cli::mtconnect::Feed>) -> LatheApp {
        self.feed = feed;
        self
    }

    /// Takes every channel's tip into its trail.
    fn sample(&mut self, c: &LatheConsole) {
        for (t, (pos, work)) in self.trails.iter_mut().zip(c.tips()) {
            t.push(pos, work);
        }
    }

    /// Advances the machine `ns` in steps of `STEP_NS`, sampling after each.
    fn advance(&mut self, c: &mut LatheConsole, ns: u64) {
        if c.cycle().is_none() {
            c.tick(ns);
            return;
        }
        let mut left = ns;
        while left > 0 {
            let n = left.min(STEP_NS);
            c.tick(n);
            self.sample(c);
            left -= n;
        }
    }

    /// The script has been played to its end (or there is none).
    fn script_done(&self) -> bool {
        self.waiting.is_none() && self.script.as_ref().is_none_or(|s| s.is_empty())
    }

    fn fail(&mut self, ctx: &egui::Context, msg: String) {
        eprintln!("novanc: {msg}");
        self.exit.store(1, Ordering::SeqCst);
        ctx.send_viewport_cmd(egui::ViewportCommand::Close);
    }

    /// Plays the script in virtual time for at most `SCRIPT_BUDGET` of wall time: events at
    /// once, waits by steps of the machine.
    fn play(&mut self, c: &mut LatheConsole, ctx: &egui::Context) {
        let t0 = Instant::now();
        loop {
            if let Some((since, w)) = self.waiting {
                let done = match w {
                    Wait::Rest => c.at_rest(),
                    Wait::Until(t) => c.machine_ns() >= t,
                };
                if done {
                    self.waiting = None;
                    continue;
                }
                if since.elapsed() > WAIT_LIMIT {
                    self.waiting = None;
                    self.script = Some(VecDeque::new());
                    let s = WAIT_LIMIT.as_secs();
                    return self.fail(ctx, format!("script wait: not done after {s} s"));
                }
                if t0.elapsed() > SCRIPT_BUDGET {
                    return;
                }
                for _ in 0..16 {
                    let n = match w {
                        Wait::Until(t) => t.saturating_sub(c.machine_ns()).min(STEP_NS),
                        Wait::Rest => STEP_NS,
                    };
                    if n == 0 || (w == Wait::Rest && c.at_rest()) {
                        break;
                    }
                    self.advance(c, n);
                }
                continue;
            }
            let Some(step) = self.script.as_mut().and_then(|s| s.pop_front()) else {
                return;
            };
            match step {
                ScriptStep::Ev(ev) => {
                    c.event(ev);
                    self.sample(c);
                }
                ScriptStep::Wait => {
                    // The machine knows it is busy only once it has ticked (after a START, say),
                    // so a wait takes one step first, as `novanc script`'s does.
                    if c.cycle().is_some() {
                        self.advance(c, STEP_NS);
                    }
                    self.waiting = Some((Instant::now(), Wait::Rest));
                }
                ScriptStep::WaitMs(ms) => {
                    let at = c.machine_ns().saturating_add(ms.saturating_mul(1_000_000));
                    self.waiting = Some((Instant::now(), Wait::Until(at)));
                }
                ScriptStep::Show => {
                    let frame = c.frame_text();
                    super::say(&format!("--- display\n{frame}\n---"));
                }
            }
        }
    }

    /// One frame: run the clock, take the keyboard, draw, hand the actions over, and the
    /// screenshot.
    fn frame(&mut self, c: &mut LatheConsole, ui: &mut egui::Ui) {
        let ctx = ui.ctx().clone();
        if let Some(why) = crate::cli::signals::caught_reason() {
            if self.interrupted.is_none() {
                self.interrupted = Some(why);
                ctx.send_viewport_cmd(egui::ViewportCommand::Close);
            }
            return;
        }
        let now = Instant::now();
        if !self.script_done() {
            self.play(c, &ctx);
        } else if self.script.is_none() || self.screenshot.is_none() {
            // Real time (after a script too, unless the screenshot is to show its end).
            let ns = (now.duration_since(self.last).as_nanos() as u64).min(MAX_FRAME_NS);
            self.advance(c, ns);
        }
        self.last = now;
        self.view = c.view();
        let mut acts = Vec::new();
        let events = ctx.input(|i| i.events.clone());
        for k in super::keys::terminal_keys(&events) {
            // Ctrl+C and Alt+Q quit the terminal panel: here they close the window.
            if matches!(
                k,
                novanc_panel::Key::Alt('q') | novanc_panel::Key::Ctrl('c')
            ) {
                ctx.send_viewport_cmd(egui::ViewportCommand::Close);
            } else {
                acts.push(Act::Press(k));
            }
        }
        self.draw(ui, c, &mut acts);
        for a in acts {
            match a {
                Act::Ev(ev) => c.event(ev),
                Act::Press(k) => c.press(k),
                Act::ClearPaths => {
                    let step = c.desc().pulses(plot::TRAIL_STEP_MM).max(1);
                    self.trails
                        .iter_mut()
                        .for_each(|t| *t = Trail::new(step, plot::TRAIL_POINTS));
                }
            }
            self.sample(c);
        }
        self.screenshot(&ctx);
        let busy = !self.script_done() || self.shot.busy() || self.screenshot.is_some();
        super::schedule_repaint(&ctx, busy, !c.at_rest());
    }

    fn screenshot(&mut self, ctx: &egui::Context) {
        let Some(path) = self.screenshot.clone() else {
            return;
        };
        let ready = self.script_done();
        match self.shot.step(ctx, &path, ready) {
            None => {}
            Some(Err(e)) => self.fail(ctx, e),
            Some(Ok([w, h])) => {
                let ppp = ctx.pixels_per_point();
                let plots: Vec<String> = self
                    .layout
                    .plots
                    .iter()
                    .enumerate()
                    .map(|(i, (t, d))| {
                        format!(
                            "plot{} {} detail{} {}",
                            i + 1,
                            rect_px(Some(*t), ppp),
                            i + 1,
                            rect_px(Some(*d), ppp)
                        )
                    })
                    .collect();
                super::say(&format!(
                    "screenshot {} {w}x{h} plasma {} pitch {} {}",
                    path.display(),
                    rect_px(self.layout.plasma, ppp),
                    self.layout.pitch,
                    plots.join(" ")
                ));
                ctx.send_viewport_cmd(egui::ViewportCommand::Close);
            }
        }
    }

    fn draw(&mut self, ui: &mut egui::Ui, c: &LatheConsole, out: &mut Vec<Act>) {
        let v = self.view.clone();
        let frame = egui::Frame::new().fill(controls::ENAMEL).inner_margin(8.0);
        egui::Panel::top("lathe-summary")
            .frame(frame.fill(Color32::from_rgb(30, 32, 36)))
            .show(ui, |ui| panel::summary(ui, &v, out));
        egui::Panel::bottom("lathe-panel")
            .frame(frame.fill(Color32::from_rgb(48, 52, 56)))
            .show(ui, |ui| {
                ui.horizontal_top(|ui| {
                    ui.vertical(|ui| {
                        let max = egui::vec2(ui.available_width() * 0.4, 330.0);
                        let (r, pitch) = panel::plasma(ui, &mut self.plasma, &v.display, max);
                        self.layout.plasma = Some(r);
                        self.layout.pitch = pitch;
                    });
                    ui.add_space(8.0);
                    ui.vertical(|ui| panel::relay(ui, &v, c.mode(), c.switches(), out));
                    ui.add_space(8.0);
                    ui.vertical(|ui| panel::data_keys(ui, &mut self.hand, out));
                });
            });
        egui::CentralPanel::default().frame(frame).show(ui, |ui| {
            if v.help {
                panel::help(ui);
                self.layout.plots.clear();
            } else {
                let target = c.counter().target;
                self.layout.plots = panel::channels(ui, &v, c.desc(), &self.trails, target, out);
            }
        });
    }
}

impl eframe::App for LatheApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        // The console is taken out for the frame (and put back), so that it can be finished
        // when the window closes.
        let Some(mut c) = self.console.take() else {
            return;
        };
        self.frame(&mut c, ui);
        if let Some(f) = self.feed.as_mut() {
            f.publish_lathe(&c);
        }
        self.console = Some(c);
    }

    fn on_exit(&mut self, _gl: Option<&eframe::glow::Context>) {
        // Close the recording, as quitting the terminal panel does.
        if let Some(c) = self.console.take() {
            if let Some(Ok(line) | Err(line)) = c.finish(self.interrupted.as_deref()) {
                eprintln!("novanc: {line}");
            }
        }
    }

    fn clear_color(&self, _visuals: &egui::Visuals) -> [f32; 4] {
        controls::ENAMEL.to_normalized_gamma_f32()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lathe::console::events::LatheEv;

    fn app(name: &str, steps: Vec<ScriptStep>) -> (LatheApp, PathBuf) {
        let d =
            std::env::temp_dir().join(format!("novanc-lathe-window-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        let (c, _) = LatheConsole::open(LatheDesc::citizen(), &d, 12, 40, None).unwrap();
        let a = LatheApp::new(c, Some(steps), None, Arc::new(AtomicI32::new(0)));
        (a, d)
    }

    /// Plays the whole script as frames would, each within its budget.
    fn play_all(a: &mut LatheApp) -> LatheConsole {
        let ctx = egui::Context::default();
        let mut c = a.console.take().unwrap();
        let mut frames = 0;
        while !a.script_done() {
            a.play(&mut c, &ctx);
            frames += 1;
            assert!(frames < 100_000, "the script does not end");
        }
        c
    }

    #[test]
    fn a_script_wait_after_start_runs_the_cycle_to_rest_in_virtual_time() {
        let (mut a, d) = app(
            "wait",
            vec![ScriptStep::Ev(LatheEv::Start), ScriptStep::Wait],
        );
        let c = play_all(&mut a);
        assert!(c.at_rest());
        assert_eq!(
            c.counter().counts,
            vec![5, 5, 5],
            "the 5-part run, all of it"
        );
        assert!(c.machine_ns() > 60_000_000_000, "{} ns", c.machine_ns());
        // Every channel's trail holds its cuts, tagged with the works 1 to 5.
        for t in &a.trails {
            let works: std::collections::BTreeSet<u32> =
                t.points().filter_map(|p| p.work).collect();
            assert_eq!(works.into_iter().collect::<Vec<_>>(), vec![1, 2, 3, 4, 5]);
        }
        let _ = std::fs::remove_dir_all(d);
    }

    #[test]
    fn a_script_wait_ms_lets_exactly_that_machine_time_pass() {
        let (mut a, d) = app(
            "waitms",
            vec![ScriptStep::Ev(LatheEv::Start), ScriptStep::WaitMs(1_234)],
        );
        let c = play_all(&mut a);
        assert_eq!(c.machine_ns(), 1_234_000_000);
        assert!(!c.at_rest(), "the cycle runs on");
        let _ = std::fs::remove_dir_all(d);
    }
}
