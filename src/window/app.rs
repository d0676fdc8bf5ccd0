//! The one eframe application of both machines (docs/window.md): each frame it gives the
//! machine its time, plays the panel script, lets the machine's part of the window (a
//! [`Front`]: the centre's panel and backplot, or the lathe's channels) draw and take the
//! operator's actions, takes the screenshot and measures frames when asked (headless runs
//! under Xvfb), streams to MTConnect and schedules the next frame. It is to the window what
//! `terminal::run` and its one loop are to the terminal. No NC logic lives here.

use super::bench::Bench;
use super::shot::Shot;
use crate::mtconnect::feed::Feed;
use std::collections::VecDeque;
use std::path::PathBuf;
use std::sync::atomic::{AtomicI32, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// The most wall time one frame hands a machine that keeps time by the window, ns (a window
/// held up does not make the machine jump).
const MAX_FRAME_NS: u64 = 250_000_000;
/// Wall time a frame may spend on a script's waits before it draws (a machine the script
/// runs in virtual time).
const SCRIPT_BUDGET: Duration = Duration::from_millis(25);

/// What a script wait waits for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wait {
    /// `wait`: the machine at rest (the centre idle; every lathe channel at rest).
    Rest,
    /// `wait block N`: block N executing, or the machine at rest.
    Block(u32),
    /// `wait ms T`, begun: machine time at or past this, ns.
    Until(u64),
}

/// One step of a panel script, as the window plays it: an event of the machine's own, or one
/// of the player's words.
#[derive(Clone, Debug, PartialEq)]
pub enum Step<E> {
    /// An operator action.
    Ev(E),
    /// `wait` / `wait block N` (`Wait::Until` is not read: `WaitMs` is).
    Wait(Wait),
    /// `wait ms T`: T milliseconds of machine time from the moment the wait begins.
    WaitMs(u64),
    /// `show`: print the display between `--- display` and `---`.
    Show,
}

/// A panel script of the one grammar as the window plays it: its waits and `show` are the
/// player's steps, every other line an event for the console.
pub fn script_steps(
    evs: Vec<crate::panel_model::PanelEvent>,
) -> Vec<Step<crate::panel_model::PanelEvent>> {
    use crate::panel_model::PanelEvent;
    evs.into_iter()
        .map(|ev| match ev {
            PanelEvent::Wait => Step::Wait(Wait::Rest),
            PanelEvent::WaitBlock(n) => Step::Wait(Wait::Block(n)),
            PanelEvent::WaitMs(t) => Step::WaitMs(t),
            PanelEvent::Show => Step::Show,
            ev => Step::Ev(ev),
        })
        .collect()
}

/// What differs between the machines in the window, behind the one application: the console
/// it drives, its panel and plots, its key map and its clock.
pub trait Front: 'static {
    /// A script's event (`PanelEvent` for both machines; the tests' fake has its own).
    type Ev;
    /// First in every frame: the console takes its machine's state. `wall_ns` is the wall time
    /// since the last frame when the machine keeps time by the window's frames; `None` while
    /// a script plays it (virtual time) or holds it still for the screenshot. A machine with a
    /// clock of its own (the centre's pulse core) ignores it.
    fn tick(&mut self, wall_ns: Option<u64>);
    /// A script's event.
    fn event(&mut self, ev: Self::Ev);
    /// Machine time, ns.
    fn machine_ns(&self) -> u64;
    /// A script wait for `w` begins.
    fn begin_wait(&mut self, w: Wait);
    /// Works towards `w` until `deadline` (a machine in virtual time is advanced; one with its
    /// own clock only looked at, once a frame); whether it is reached.
    fn pursue(&mut self, w: Wait, deadline: Instant) -> bool;
    /// The display as the script's `show` prints it.
    fn show(&self) -> String;
    /// Why a wait cannot end without the operator, if it cannot (the machine stands still at
    /// feed override 0): `novanc script`'s words.
    fn stuck(&self) -> Option<String> {
        None
    }
    /// The machine can move (the window then draws about 60 frames a second).
    fn moving(&self) -> bool;
    /// Work of the window's own under way that a screenshot waits for (the backplot's
    /// translation).
    fn settling(&self) -> bool {
        false
    }
    /// Draws the panel from the console's view and hands this frame's keys (`events`),
    /// clicks and drags to the console. Returns whether a quit key (the terminal's Ctrl-C or
    /// Alt+q) was pressed.
    fn draw(&mut self, ui: &mut egui::Ui, events: &[egui::Event]) -> bool;
    /// The screenshot line's rectangles after `WxH` (physical pixels, `ppp` pixels a point).
    fn layout(&self, ppp: f32) -> String;
    /// Pulses output so far, all axes together (`--bench-frames`).
    fn pulses(&self) -> u64;
    /// The state to the MTConnect adapter, once a frame.
    fn publish(&self, feed: &mut Feed);
    /// Ends the session (the machine stopped, the recording closed, its summary on stderr);
    /// `interrupted` names the stop signal that closed the window.
    fn close(self, interrupted: Option<&str>);
}

/// What a run asks of the window besides drawing (all optional).
#[derive(Debug)]
pub struct Drive<E> {
    /// The script's steps still to play (`--script FILE`).
    pub script: VecDeque<Step<E>>,
    /// A script was given: the script plays the machine in virtual time, and with a
    /// screenshot asked for, the machine holds still where the script left it.
    pub scripted: bool,
    /// Where to write a screenshot once the script has been played (`--screenshot OUT`).
    pub screenshot: Option<PathBuf>,
    /// Frames to measure, then print the figures and close (`--bench-frames N`).
    pub bench_frames: Option<u64>,
    /// Longest a script wait may take in wall time before the run is abandoned.
    pub wait_limit: Duration,
}

impl<E> Default for Drive<E> {
    fn default() -> Self {
        Drive {
            script: VecDeque::new(),
            scripted: false,
            screenshot: None,
            bench_frames: None,
            wait_limit: Duration::from_secs(300),
        }
    }
}

/// The window application around one machine's [`Front`].
pub struct App<F: Front> {
    front: Option<F>,
    drive: Drive<F::Ev>,
    waiting: Option<(Instant, Wait)>,
    shot: Shot,
    bench: Option<Bench>,
    last: Instant,
    exit: Arc<AtomicI32>,
    /// The stop signal that closed the window, as the recording says it.
    interrupted: Option<String>,
    /// The MTConnect adapter (`--mtconnect`): the state is published once a frame.
    feed: Option<Feed>,
}

impl<F: Front> App<F> {
    /// The application around an opened machine. `exit` receives the exit code.
    pub fn new(front: F, drive: Drive<F::Ev>, exit: Arc<AtomicI32>, feed: Option<Feed>) -> Self {
        App {
            front: Some(front),
            bench: drive.bench_frames.map(|_| Bench::default()),
            drive,
            waiting: None,
            shot: Shot::Idle,
            last: Instant::now(),
            exit,
            interrupted: None,
            feed,
        }
    }

    fn fail(&mut self, ctx: &egui::Context, msg: String) {
        eprintln!("novanc: {msg}");
        self.exit.store(1, Ordering::SeqCst);
        ctx.send_viewport_cmd(egui::ViewportCommand::Close);
    }

    /// The run is unattended: it ends by itself with a screenshot or a benchmark.
    fn unattended(&self) -> bool {
        self.drive.screenshot.is_some() || self.drive.bench_frames.is_some()
    }

    /// The script has been played to its end (or there is none).
    fn script_done(&self) -> bool {
        self.drive.script.is_empty() && self.waiting.is_none()
    }

    /// Plays script steps until a wait not yet reached, for at most `SCRIPT_BUDGET` of wall
    /// time on waits.
    fn play(&mut self, f: &mut F, ctx: &egui::Context) {
        let deadline = Instant::now() + SCRIPT_BUDGET;
        loop {
            if let Some((since, w)) = self.waiting {
                if f.pursue(w, deadline) {
                    self.waiting = None;
                } else if let Some(why) = f.stuck().filter(|_| self.unattended()) {
                    // Nobody is there to raise the override: the script stops, as
                    // `novanc script` does. An operator at the window raises it and the
                    // wait ends.
                    self.drive.script.clear();
                    self.waiting = None;
                    self.fail(ctx, format!("script wait: {why}"));
                    return;
                } else {
                    if since.elapsed() > self.drive.wait_limit {
                        self.drive.script.clear();
                        self.waiting = None;
                        let s = self.drive.wait_limit.as_secs();
                        self.fail(ctx, format!("script wait: not done after {s} s"));
                    }
                    return;
                }
            }
            let Some(step) = self.drive.script.pop_front() else {
                return;
            };
            let w = match step {
                Step::Ev(ev) => {
                    f.event(ev);
                    continue;
                }
                Step::Show => {
                    super::say(&format!("--- display\n{}\n---", f.show()));
                    continue;
                }
                Step::Wait(w) => w,
                Step::WaitMs(ms) => {
                    Wait::Until(f.machine_ns().saturating_add(ms.saturating_mul(1_000_000)))
                }
            };
            f.begin_wait(w);
            self.waiting = Some((Instant::now(), w));
        }
    }

    fn screenshot(&mut self, f: &F, ctx: &egui::Context) {
        let Some(path) = self.drive.screenshot.clone() else {
            return;
        };
        // After the benchmark, if both are asked for.
        let ready = self.script_done() && !f.settling() && self.drive.bench_frames.is_none();
        match self.shot.step(ctx, &path, ready) {
            None => {}
            Some(Err(e)) => self.fail(ctx, e),
            Some(Ok([w, h])) => {
                let layout = f.layout(ctx.pixels_per_point());
                super::say(&format!("screenshot {} {w}x{h} {layout}", path.display()));
                ctx.send_viewport_cmd(egui::ViewportCommand::Close);
            }
        }
    }

    fn measure(&mut self, f: &F, ctx: &egui::Context, frame: &eframe::Frame) {
        // After the script's last wait too: a script ending in `wait ms T` is measured from
        // the machine time it leaves (before stop 51 the frames of its wait were counted).
        if !self.script_done() {
            return;
        }
        let (Some(b), Some(n)) = (self.bench.as_mut(), self.drive.bench_frames) else {
            return;
        };
        let cpu = frame.info().cpu_usage;
        if let Some(report) = b.frame(n, f.machine_ns(), cpu, f.pulses()) {
            super::say(&report);
            self.drive.bench_frames = None;
            // With a screenshot asked for too, it is taken now, and that closes the window.
            if self.drive.screenshot.is_none() {
                ctx.send_viewport_cmd(egui::ViewportCommand::Close);
            }
        }
    }

    /// One frame: the machine's time, the script, the panel and the operator's actions, the
    /// screenshot, the benchmark, MTConnect, the next frame.
    fn frame(&mut self, f: &mut F, ui: &mut egui::Ui, frame: &eframe::Frame) {
        let ctx = ui.ctx().clone();
        // A stop signal closes the window as closing it does (`on_exit`: the machine stopped,
        // the recording closed and marked interrupted).
        if let Some(why) = crate::signals::caught_reason() {
            if self.interrupted.is_none() {
                self.interrupted = Some(why);
                ctx.send_viewport_cmd(egui::ViewportCommand::Close);
            }
            return;
        }
        let now = Instant::now();
        // Real time, unless a script plays the machine or holds it for the screenshot.
        let held = self.drive.scripted && self.drive.screenshot.is_some();
        let wall = (self.script_done() && !held)
            .then(|| (now.duration_since(self.last).as_nanos() as u64).min(MAX_FRAME_NS));
        self.last = now;
        f.tick(wall);
        if !self.script_done() {
            self.play(f, &ctx);
        }
        let events = ctx.input(|i| i.events.clone());
        if f.draw(ui, &events) {
            // The terminal's quit keys close the window as closing it does.
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        }
        self.screenshot(f, &ctx);
        self.measure(f, &ctx, frame);
        if let Some(feed) = self.feed.as_mut() {
            f.publish(feed);
        }
        let busy = !self.script_done()
            || f.settling()
            || self.bench.is_some()
            || self.drive.screenshot.is_some();
        super::schedule_repaint(&ctx, busy, f.moving());
    }
}

impl<F: Front> eframe::App for App<F> {
    fn ui(&mut self, ui: &mut egui::Ui, frame: &mut eframe::Frame) {
        // The machine is taken out for the frame (and put back), so that it can be closed
        // when the window closes.
        let Some(mut f) = self.front.take() else {
            return;
        };
        self.frame(&mut f, ui, frame);
        self.front = Some(f);
    }

    fn on_exit(&mut self, _gl: Option<&eframe::glow::Context>) {
        // Stop the machine and close the recording, as the terminal panel does on quitting.
        if let Some(f) = self.front.take() {
            f.close(self.interrupted.as_deref());
        }
    }

    fn clear_color(&self, _visuals: &egui::Visuals) -> [f32; 4] {
        super::controls::ENAMEL.to_normalized_gamma_f32()
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// Plays the whole script of `app` as frames would, each within its budget; the front
    /// comes back.
    pub(crate) fn play_all<F: Front>(app: &mut App<F>) -> F {
        let ctx = egui::Context::default();
        let mut f = app.front.take().expect("the front");
        let mut frames = 0;
        while !app.script_done() {
            f.tick(None);
            app.play(&mut f, &ctx);
            frames += 1;
            assert!(frames < 100_000, "the script does not end");
        }
        f
    }

    /// A machine of events numbered by the script, whose clock moves 1 ms each time a wait
    /// looks at it, and which comes to rest at the third look.
    #[derive(Default)]
    struct Fake {
        t: u64,
        evs: Vec<u32>,
        looks: u32,
        /// It stands still at feed override 0.
        stalled: bool,
    }

    impl Front for Fake {
        type Ev = u32;
        fn tick(&mut self, _wall_ns: Option<u64>) {}
        fn event(&mut self, ev: u32) {
            self.evs.push(ev);
        }
        fn machine_ns(&self) -> u64 {
            self.t
        }
        fn begin_wait(&mut self, _w: Wait) {
            self.looks = 0;
        }
        fn pursue(&mut self, w: Wait, _deadline: Instant) -> bool {
            self.looks += 1;
            self.t += 1_000_000;
            match w {
                Wait::Until(t) => self.t >= t,
                Wait::Rest => self.looks >= 3,
                Wait::Block(_) => false,
            }
        }
        fn show(&self) -> String {
            String::new()
        }
        fn stuck(&self) -> Option<String> {
            self.stalled.then(|| "it stands still".to_string())
        }
        fn moving(&self) -> bool {
            false
        }
        fn draw(&mut self, _ui: &mut egui::Ui, _events: &[egui::Event]) -> bool {
            false
        }
        fn layout(&self, _ppp: f32) -> String {
            String::new()
        }
        fn pulses(&self) -> u64 {
            0
        }
        fn publish(&self, _feed: &mut Feed) {}
        fn close(self, _interrupted: Option<&str>) {}
    }

    fn app(script: Vec<Step<u32>>) -> App<Fake> {
        let drive = Drive {
            script: script.into(),
            scripted: true,
            ..Drive::default()
        };
        App::new(Fake::default(), drive, Arc::new(AtomicI32::new(0)), None)
    }

    #[test]
    fn the_script_stops_at_each_wait_until_the_machine_reaches_it() {
        let mut a = app(vec![
            Step::Ev(1),
            Step::WaitMs(5),
            Step::Ev(2),
            Step::Wait(Wait::Rest),
            Step::Ev(3),
        ]);
        let ctx = egui::Context::default();
        let mut f = a.front.take().unwrap();
        a.play(&mut f, &ctx);
        assert_eq!(f.evs, [1], "the event after the wait waits");
        assert_eq!(a.waiting.map(|w| w.1), Some(Wait::Until(5_000_000)));
        a.front = Some(f);
        let f = play_all(&mut a);
        assert_eq!(f.evs, [1, 2, 3]);
        // `wait ms 5` from 0, then three looks for the rest.
        assert_eq!(f.t, 8_000_000);
    }

    #[test]
    fn a_wait_not_reached_in_time_ends_the_run_with_exit_1() {
        let mut a = app(vec![Step::Wait(Wait::Block(7)), Step::Ev(1)]);
        a.drive.wait_limit = Duration::ZERO;
        let f = play_all(&mut a);
        assert!(f.evs.is_empty(), "{:?}", f.evs);
        assert_eq!(a.exit.load(Ordering::SeqCst), 1);
    }

    /// A wait the machine cannot end by itself (feed override 0) ends an unattended run (a
    /// screenshot or a benchmark asked for) at once, with exit 1, as `novanc script` stops; an
    /// operator at the window can raise the override, so there the wait goes on.
    #[test]
    fn a_stuck_wait_ends_an_unattended_run_at_once() {
        for unattended in [true, false] {
            let mut a = app(vec![Step::Wait(Wait::Block(7)), Step::Ev(1)]);
            if unattended {
                a.drive.screenshot = Some(PathBuf::from("never.png"));
            }
            a.front.as_mut().unwrap().stalled = true;
            let ctx = egui::Context::default();
            let mut f = a.front.take().unwrap();
            a.play(&mut f, &ctx);
            assert!(f.evs.is_empty(), "{:?}", f.evs);
            assert_eq!(a.waiting.is_none(), unattended);
            assert_eq!(a.exit.load(Ordering::SeqCst), i32::from(unattended));
        }
    }
}
